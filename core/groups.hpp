#pragma once
// Named particle groups and how they move. A particle belongs to at most one group (column
// Particles::group, -1 for none). A group is either free (integrated like any particle, but measured),
// frozen, moved rigidly at a prescribed velocity, or moved rigidly under a prescribed external force (a wall
// loaded by a stress). Every step the group's reaction, the sum of the interaction forces on its members,
// and its centre-of-mass displacement are measured.
#include <string>
#include <vector>

#include "core/vec3.hpp"

namespace debris {

class Particles;

enum class GroupMotion : int { free = 0, frozen = 1, velocity = 2, force = 3 };

struct Group {
  std::string name;
  GroupMotion motion = GroupMotion::free;
  Vec3 velocity{};        // velocity mode: prescribed; force mode: current rigid velocity
  Vec3 external_force{};  // force mode: the applied load (e.g. stress times wall area)

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

  /// Recounts members and their mass (after particles were assigned or masses changed).
  void refresh_members(const Particles& p);

  /// Kernel view: motion mode and rigid velocity per group, copied out of `list` before each pass.
  struct View {
    const int* mode;
    const double *vx, *vy, *vz;
  };
  View view();

  /// Force mode: v += (reaction + external) / M * dt, the semi-implicit Euler kick of a rigid body.
  void kick_rigid(double dt);

  /// Sums the current forces of each group's members into Group::reaction.
  void measure_reactions(const Particles& p);

  /// Adds each group's centre-of-mass velocity times dt to its displacement (call after the drift).
  void accumulate_displacements(const Particles& p, double dt);

 private:
  std::vector<int> mode_;
  std::vector<double> vx_, vy_, vz_;
};

}  // namespace debris
