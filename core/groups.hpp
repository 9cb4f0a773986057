#pragma once
// Named particle groups and how they move. A particle belongs to at most one group (column
// Particles::group, -1 for none). A group is either free (integrated like any particle, but measured),
// frozen, moved rigidly at a prescribed velocity, or moved rigidly under a prescribed external force (a wall
// loaded by a stress). Every step the group's reaction, the sum of the interaction forces on its members,
// and its centre-of-mass displacement are measured.
//
// A force group may also prescribe its velocity on some axes and take the load on the others (`prescribed`):
// the adhesive-wear junction's top wall slides at 10 m/s along x, stays put along z and is free along y
// under a normal load. In the input:
//
//   - name: top
//     region: {y: [12 nm, inf]}
//     motion: force
//     velocity: [10 m/s, free, 0]   # x and z prescribed, y free
//     stress: [0, -100 MPa, 0]      # the load, on free axes only (times the x-z area of the box)
//
// Only the free axes are kicked by (reaction + external force) / M dt; a prescribed axis keeps
// Group::velocity exactly, and its reaction is still measured (the friction force of the junction). Rigid
// groups translate only: their members never spin.
//
// The reactions (and free groups' momenta) are exact sums (core/block_sums' ExactPartials: each term on
// a fixed grid, added as integers, rounded once): the same bits on any thread count, storage order or rank
// count, so a force group moves the same way on 1 or 16 threads (or ranks) and a checkpoint continues bit
// for bit with another --threads.
#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include "core/block_sums.hpp"
#include "core/exec.hpp"
#include "core/vec3.hpp"

namespace debris {

class Particles;

enum class GroupMotion : int { free = 0, frozen = 1, velocity = 2, force = 3 };
/// The input's word for a motion: "free", "frozen", "velocity", "force".
const char* motion_name(GroupMotion m);

struct Group {
  std::string name;
  GroupMotion motion = GroupMotion::free;
  Vec3 velocity{};        // velocity mode: prescribed; force mode: current rigid velocity
  Vec3 external_force{};  // force mode: the applied load (e.g. stress times wall area)
  // Force mode: axes whose velocity stays at `velocity` (no kick; their load must be 0). All false: the
  // whole velocity follows the load.
  std::array<bool, 3> prescribed{false, false, false};

  // Measured.
  long count = 0;
  double mass = 0;
  Vec3 reaction{};      // sum of interaction forces on the members at the last force evaluation
  Vec3 displacement{};  // centre-of-mass displacement since the start of the run
};

class Groups {
 public:
  std::vector<Group> list;

  /// Adds a group; InputError if the name is empty or taken. Returns its index.
  int add(Group g);
  /// Index of the named group or -1.
  int find(const std::string& name) const;
  std::size_t size() const { return list.size(); }

  /// Recounts members and their mass (after particles were assigned or masses changed; a run cut among ranks
  /// counts them before it keeps its own particles).
  void refresh_members(const Particles& p);

  /// Kernel view: motion mode and rigid velocity per group, copied out of `list` before each pass.
  struct View {
    const int* mode;
    const double *vx, *vy, *vz;
  };
  View view();

  /// Sums the current forces of each group's members into Group::reaction (fixed-order blocks). `scope`:
  /// the particles counted and whether every rank's are added (core/block_sums.hpp); the same below.
  void measure_reactions(const Particles& p, SumScope scope = {});

  /// Adds each group's centre-of-mass velocity times dt to its displacement (call after the drift).
  void accumulate_displacements(const Particles& p, double dt, SumScope scope = {});

 private:
  /// Sums w[i] a[i] (b[i], c[i]) of each group's members into out[g], exactly; one pass for all groups.
  void sum_by_group(const Particles& p, const double* a, const double* b, const double* c, const double* w,
                    std::vector<Vec3>& out, SumScope scope);

  // The kernel view (copied to the device by view(): a few numbers per group) and the per-block partial
  // sums, [block][group][xyz] (core/block_sums: computed on the device, copied back by sum_by_group).
  exec::DeviceVector<int> mode_;
  exec::DeviceVector<double> vx_, vy_, vz_;
  ExactPartials partials_;
  std::vector<Vec3> sums_;
  std::vector<double> sums_flat_;  // sum_by_group's block sums added up, [group][xyz]
};

}  // namespace debris
