#pragma once
// PeriDEM storage (paper B, section 3.1): every grain and every wall is a set of meshless nodes, each a
// mesh vertex with the nodal volume of eq 31. Structure of arrays like Particles: one column per field,
// declared once in the lists below. The nodes of one grain are contiguous ([node_begin, node_end) of the
// grain), so per-grain reductions are plain loops; a node's index never changes during a run (bonds are
// built once on indices), but its permanent `id` is what output and tests follow.
//
// Units are SI. Forces are stored as forces on the node (newtons): the force density of eq 33 times the
// node's volume, so the acceleration is f / mass with mass = rho V.
//
// Columns are exec::DeviceVector, as Particles': in offload builds each lives on the device for as long as
// its buffer; the host copy is current only after to_host(nodes), and a host-side change reaches kernels
// after to_device(nodes). A copy of a PdNodes copies the host columns only (to_device it before a kernel).
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/exec.hpp"

namespace debris {

// clang-format off
#define DEBRIS_PD_NODE_DOUBLE_FIELDS(X) \
  X(x0) X(y0) X(z0)    /* reference position (the placed, undeformed mesh vertex) */   \
  X(x) X(y) X(z)       /* current position */                                         \
  X(vx) X(vy) X(vz)    /* velocity */                                                 \
  X(fx) X(fy) X(fz)    /* force on the node this step (N) */                          \
  X(volume)            /* nodal volume V_i, eq 31 (area in 2D) */                     \
  X(mass)              /* rho V_i */                                                  \
  X(weighted_volume)   /* m_i of eq 7/34, computed once in the reference state */     \
  X(theta)             /* dilatation theta_i of eq 8/34, this step */                 \
  X(damage)            /* damage Z_i of eq 14 */
#define DEBRIS_PD_NODE_INT_FIELDS(X) \
  X(grain)             /* index of the grain or wall the node belongs to */           \
  X(fixed)             /* bit mask of fixed displacement components: 1 x, 2 y, 4 z */
#define DEBRIS_PD_NODE_ID_FIELDS(X) X(id)
// clang-format on

class PdNodes {
 public:
#define DEBRIS_DECLARE_COLUMN(name) exec::DeviceVector<double> name;
  DEBRIS_PD_NODE_DOUBLE_FIELDS(DEBRIS_DECLARE_COLUMN)
#undef DEBRIS_DECLARE_COLUMN
#define DEBRIS_DECLARE_COLUMN(name) exec::DeviceVector<int> name;
  DEBRIS_PD_NODE_INT_FIELDS(DEBRIS_DECLARE_COLUMN)
#undef DEBRIS_DECLARE_COLUMN
#define DEBRIS_DECLARE_COLUMN(name) exec::DeviceVector<std::int64_t> name;
  DEBRIS_PD_NODE_ID_FIELDS(DEBRIS_DECLARE_COLUMN)
#undef DEBRIS_DECLARE_COLUMN

  std::size_t size() const { return id.size(); }

  void resize(std::size_t n) {
    for_each_column([n](const char*, auto& column) { column.resize(n); });
  }

  /// Appends a node at rest at reference = current position; returns its index.
  std::size_t add(std::int64_t node_id, int grain_index, double px, double py, double pz, double node_volume) {
    const std::size_t i = size();
    resize(i + 1);
    id[i] = node_id;
    grain[i] = grain_index;
    x0[i] = x[i] = px;
    y0[i] = y[i] = py;
    z0[i] = z[i] = pz;
    volume[i] = node_volume;
    return i;
  }

  /// Calls f(name, column) for every column (resize, checkpoints, device residency).
  template <class F>
  void for_each_column(F&& f) {
#define DEBRIS_VISIT(name) f(#name, name);
    DEBRIS_PD_NODE_DOUBLE_FIELDS(DEBRIS_VISIT)
    DEBRIS_PD_NODE_INT_FIELDS(DEBRIS_VISIT)
    DEBRIS_PD_NODE_ID_FIELDS(DEBRIS_VISIT)
#undef DEBRIS_VISIT
  }
  template <class F>
  void for_each_column(F&& f) const {
#define DEBRIS_VISIT(name) f(#name, name);
    DEBRIS_PD_NODE_DOUBLE_FIELDS(DEBRIS_VISIT)
    DEBRIS_PD_NODE_INT_FIELDS(DEBRIS_VISIT)
    DEBRIS_PD_NODE_ID_FIELDS(DEBRIS_VISIT)
#undef DEBRIS_VISIT
  }
};

/// Transfer points for every column (no-ops in host builds): device -> host before the host reads the
/// nodes (output, checkpoints, checks), host -> device after it changed them.
inline void to_host(const PdNodes& nodes) {
  nodes.for_each_column([](const char*, const auto& column) { exec::to_host(column); });
}
inline void to_device(const PdNodes& nodes) {
  nodes.for_each_column([](const char*, const auto& column) { exec::to_device(column); });
}

/// What a grain is: a deformable peridynamic particle, or a rigid wall (meshed like a grain, moved as a
/// whole: fixed, or at a prescribed velocity; its nodes carry no bonds).
enum class PdGrainKind : int { particle = 0, wall = 1 };

/// Per-grain data. Grain g owns nodes [node_begin[g], node_end[g]). Device-resident like the nodes.
struct PdGrains {
  exec::DeviceVector<int> node_begin, node_end;
  exec::DeviceVector<int> kind;       // PdGrainKind
  exec::DeviceVector<int> material;   // index into the scenario's PdMaterial table
  exec::DeviceVector<double> volume;  // |Omega_p|: the sum of the nodal volumes
  // Centre and mean velocity of the grain (volume-weighted means of its nodes), refreshed each step by a
  // per-grain reduction: the damping between grain centres of eqs 26-30 uses them.
  exec::DeviceVector<double> cx, cy, cz, cvx, cvy, cvz;
  // Prescribed wall velocity (used for kind == wall; zero = fixed wall).
  exec::DeviceVector<double> wall_vx, wall_vy, wall_vz;
  // The grain's index in the whole system (one process's grain index; set by PeridemSimulation). A rank of a
  // run cut among processes holds some grains, or pieces of a wall, and knows them by it.
  exec::DeviceVector<int> id;

  std::size_t size() const { return node_begin.size(); }
  void resize(std::size_t n) {
    for (auto* v : {&node_begin, &node_end, &kind, &material, &id}) v->resize(n);
    for (auto* v : {&volume, &cx, &cy, &cz, &cvx, &cvy, &cvz, &wall_vx, &wall_vy, &wall_vz}) v->resize(n);
  }
  /// The grain columns (integers first, then doubles), for transfers.
  template <class F>
  void for_each_column(F&& f) const {
    for (auto* v : {&node_begin, &node_end, &kind, &material, &id}) f(*v);
    for (auto* v : {&volume, &cx, &cy, &cz, &cvx, &cvy, &cvz, &wall_vx, &wall_vy, &wall_vz}) f(*v);
  }
};

/// Transfer points for every grain column (no-ops in host builds).
inline void to_host(const PdGrains& grains) {
  grains.for_each_column([](const auto& column) { exec::to_host(column); });
}
inline void to_device(const PdGrains& grains) {
  grains.for_each_column([](const auto& column) { exec::to_device(column); });
}

}  // namespace debris
