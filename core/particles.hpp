#pragma once
// Structure-of-arrays particle storage. Every per-particle field is one contiguous column, declared once
// in the field lists below; permute() and resize() walk those lists, so adding a field is one line.
// A particle's index changes when we sort by cell; its permanent `id` never does, so anything that must
// follow a particle (contact history, groups, output) goes through the id.
// Columns are exec::DeviceVector: in offload builds each lives on the device for as long as its buffer;
// the host copy is current only after to_host(p), and a host-side change reaches kernels after to_device(p).
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "core/exec.hpp"

namespace debris {

// clang-format off
#define DEBRIS_PARTICLE_DOUBLE_FIELDS(X) \
  X(x) X(y) X(z)       /* position (wrapped into the box on periodic axes) */      \
  X(vx) X(vy) X(vz)    /* velocity */                                               \
  X(wx) X(wy) X(wz)    /* angular velocity */                                       \
  X(fx) X(fy) X(fz)    /* force of the current step */                              \
  X(tx) X(ty) X(tz)    /* torque of the current step */                             \
  X(radius) X(mass) X(inertia)                                                     \
  /* energy taken out by each mechanism since the start, and the work the drives did (kernels/dem/    */ \
  /* energy_accounting.hpp), cumulative                                                              */ \
  X(dissipated_normal) X(dissipated_tangential) X(dissipated_sliding) X(dissipated_global)          \
  X(tangential_work) X(drive_work)                                                                   \
  /* ... their shares of the integration to come, added to the above when it runs                    */ \
  X(pending_normal) X(pending_tangential) X(pending_global) X(pending_tangential_work) X(pending_drive)
#define DEBRIS_PARTICLE_INT_FIELDS(X) \
  X(type)              /* material / output type, >= 1 as in LAMMPS */              \
  X(group)             /* index of the motion group, -1 for a free particle */      \
  X(ix) X(iy) X(iz)    /* periodic image counts, for unwrapped positions */      \
  X(label)             /* body the particle started in: 0 = none, k = label_names[k-1] */
#define DEBRIS_PARTICLE_ID_FIELDS(X) X(id)
// clang-format on

class Particles {
 public:
#define DEBRIS_DECLARE_COLUMN(name) exec::DeviceVector<double> name;
  DEBRIS_PARTICLE_DOUBLE_FIELDS(DEBRIS_DECLARE_COLUMN)
#undef DEBRIS_DECLARE_COLUMN
#define DEBRIS_DECLARE_COLUMN(name) exec::DeviceVector<int> name;
  DEBRIS_PARTICLE_INT_FIELDS(DEBRIS_DECLARE_COLUMN)
#undef DEBRIS_DECLARE_COLUMN
#define DEBRIS_DECLARE_COLUMN(name) exec::DeviceVector<std::int64_t> name;
  DEBRIS_PARTICLE_ID_FIELDS(DEBRIS_DECLARE_COLUMN)
#undef DEBRIS_DECLARE_COLUMN

  /// What the label column means: label k >= 1 is label_names[k - 1]; 0 is an unlabelled particle. Not a
  /// column (one entry per label, not per particle), but it travels with the particles it describes, so
  /// every copy, writer and checkpoint that has the column has its legend too.
  std::vector<std::string> label_names;

  std::size_t size() const { return id.size(); }
  void resize(std::size_t n);
  void clear() { resize(0); }

  /// Appends one particle at rest; returns its index. mass/inertia are set later by the material.
  std::size_t add(std::int64_t id, int type, double x, double y, double z, double radius);

  /// Reorders every column (host copies): new index i holds the particle that was at order[i].
  void permute(const std::vector<int>& order);
  /// The same on the device copies (offload builds: a gather kernel per column, order copied there; the
  /// host copies are left meaningless until to_host). In host builds this is permute().
  void permute_resident(const std::vector<int>& order);
#if defined(DEBRIS_OFFLOAD_TARGET)
  /// The same with the order already on the device (host builds: DeviceVector is std::vector, the above).
  void permute_resident(const exec::DeviceVector<int>& order);
#endif

  /// Deletes every particle i with remove[i] != 0, keeping the others in their order (all columns).
  /// Returns the number removed.
  std::size_t remove_if(const std::vector<char>& remove);

  /// Largest permanent id (or -1 when empty).
  std::int64_t max_id() const;

  /// The values a system's particles must hold in column `name`, checked at set-up on what the input gave
  /// and again on what a host-side edit wrote (the Python module's): `id` >= 0 and unique; `radius`, `mass`
  /// and `inertia` finite and > 0; every other floating column finite; `type` >= 1 (LAMMPS); `group` >= -1
  /// (its upper end is the Groups'); `label` within label_names. InputError naming `key`, the value and the
  /// particle (its id and index).
  void check_column(const std::string& name, const std::string& key) const;

  /// Sets mass = density * 4/3 pi r^3 and inertia = 2/5 m r^2 (solid spheres).
  void set_mass_from_density(double density);

  /// Bytes held per particle by the columns (for memory reports).
  static constexpr std::size_t bytes_per_particle() {
    std::size_t b = 0;
#define DEBRIS_COUNT(name) b += sizeof(double);
    DEBRIS_PARTICLE_DOUBLE_FIELDS(DEBRIS_COUNT)
#undef DEBRIS_COUNT
#define DEBRIS_COUNT(name) b += sizeof(int);
    DEBRIS_PARTICLE_INT_FIELDS(DEBRIS_COUNT)
#undef DEBRIS_COUNT
#define DEBRIS_COUNT(name) b += sizeof(std::int64_t);
    DEBRIS_PARTICLE_ID_FIELDS(DEBRIS_COUNT)
#undef DEBRIS_COUNT
    return b;
  }

  /// Calls f(column) for every column; used for permutation, residency and checkpoints.
  template <class F>
  void for_each_column(F&& f) {
#define DEBRIS_VISIT(name) f(#name, name);
    DEBRIS_PARTICLE_DOUBLE_FIELDS(DEBRIS_VISIT)
    DEBRIS_PARTICLE_INT_FIELDS(DEBRIS_VISIT)
    DEBRIS_PARTICLE_ID_FIELDS(DEBRIS_VISIT)
#undef DEBRIS_VISIT
  }
  template <class F>
  void for_each_column(F&& f) const {
#define DEBRIS_VISIT(name) f(#name, name);
    DEBRIS_PARTICLE_DOUBLE_FIELDS(DEBRIS_VISIT)
    DEBRIS_PARTICLE_INT_FIELDS(DEBRIS_VISIT)
    DEBRIS_PARTICLE_ID_FIELDS(DEBRIS_VISIT)
#undef DEBRIS_VISIT
  }
};

/// Everything dissipated at particle i so far (the dump's and trajectory's `dissipated`).
inline double particle_dissipated(const Particles& p, std::size_t i) {
  return p.dissipated_normal[i] + p.dissipated_tangential[i] + p.dissipated_sliding[i] + p.dissipated_global[i];
}

/// Transfer points for every column (no-ops in host builds): device -> host before the host reads the
/// particles (output, checkpoints, analysis), host -> device after it changed them.
void to_host(const Particles& p);
void to_device(const Particles& p);

}  // namespace debris
