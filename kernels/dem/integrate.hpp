#pragma once
// Time integration and the per-particle passes around it.
#include "core/groups.hpp"

namespace debris {

class Particles;

/// Semi-implicit (symplectic) Euler, eq 1:  v += F/m dt ;  x += v dt ;  w += T/I dt.
/// Frozen members stay at rest; rigid members (velocity or force groups) take their group's velocity and
/// do not spin.
void integrate_semi_implicit_euler(Particles& p, Groups::View groups, double dt);

/// The rigid groups' Newton update, eq 1 for a body: v += (reaction + external) / M dt on the axes a force
/// group does not prescribe (semi-implicit Euler, before the drift). Host side: a few numbers per group.
void kick_rigid_groups(Groups& groups, double dt);
/// A force group's velocity after that kick (the energy accounting predicts it with the same arithmetic).
Vec3 kicked_velocity(const Group& g, double dt);

/// Zeroes forces and torques before the force passes.
void zero_forces(Particles& p);

/// Global viscous damping F -= c v on free particles (fix viscous in LAMMPS); section 3 uses c as a
/// fraction of the critical damping c_c of eq 21.
void global_damping_pass(Particles& p, Groups::View groups, double c);

/// Totals for conservation checks and thermo output.
struct ParticleTotals {
  double kinetic_energy;  // translational + rotational
  Vec3 momentum;
  Vec3 angular_momentum;  // about the origin, from unwrapped-free positions (use without periodic axes)
};
/// `scope`: the particles counted, and whether every rank's are added (core/block_sums.hpp).
ParticleTotals particle_totals(const Particles& p, SumScope scope = {});

/// Kinetic energy with velocities synchronised to the positions, v + F dt / 2m (and w + T dt / 2I). The
/// stored v of semi-implicit Euler lags x by half a step; this is the energy that velocity Verlet, the
/// same trajectory, would report, and it is conserved to O(dt^2) instead of O(dt).
double synchronized_kinetic_energy(const Particles& p, double dt);

/// Index of the first particle with a non-finite position, velocity or force, or -1.
long first_non_finite(const Particles& p);

}  // namespace debris
