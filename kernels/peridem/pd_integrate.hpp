#pragma once
// Time integration of PeriDEM nodes (paper B, eq 32) and the small per-node passes around it.
//
// Eq 32 is the central difference rho (u^{n+1} - 2 u^n + u^{n-1}) / dt^2 = F^n. With the half-step velocity
// v^{n+1/2} = (u^{n+1} - u^n) / dt it reads (v^{n+1/2} - v^{n-1/2}) / dt = F^n / rho, that is
//   v^{n+1/2} = v^{n-1/2} + dt f^n / m,     x^{n+1} = x^n + dt v^{n+1/2}
// (f = F V in newtons, m = rho V): the same positions, step for step, with one stored velocity instead of
// two stored displacements (it is also velocity Verlet with the two half kicks merged). Started from
// v^0 with a half kick, v^{1/2} = v^0 + dt/2 f^0 / m, the scheme is exact for a constant force:
// x^n = x^0 + v^0 t_n + a t_n^2 / 2. (PeriDEM's integrateCD starts with a full kick, which shifts every later
// position by a dt t_n / 2.) The stored velocity is half a step behind the positions.
#include "core/vec3.hpp"

namespace debris {

class PdNodes;
struct PdGrains;

/// Sets every node force to zero.
void pd_zero_forces(PdNodes& nodes);

/// The first force of a step: the body force rho g V = m g on the nodes of particle grains, zero on walls
/// (walls move as prescribed; keeping gravity off their nodes keeps their force the pure contact reaction).
void pd_weight_forces(PdNodes& nodes, const PdGrains& grains, Vec3 g);

/// Global viscous damping: f -= c m v on particle nodes, with the stored v (half a step behind), so a free
/// node's velocity shrinks by (1 - c dt) per step: v^{n+1/2} = (1 - c dt) v^{n-1/2} + dt f / m. Not part of
/// paper B's model: it brings a pack to rest before it is loaded (a settle stage). c >= 0, c dt < 1.
void pd_viscous_damping(PdNodes& nodes, const PdGrains& grains, double c);

/// One step of eq 32 in velocity form. first_step: the stored velocity is the initial v^0 and the kick is
/// dt/2 (see above); every later step kicks by dt. Particle nodes: components whose bit is set in
/// PdNodes::fixed (1 x, 2 y, 4 z) keep their position and have zero velocity; the others move with f / m
/// (m > 0 required). Wall nodes move rigidly at their grain's prescribed velocity (PdGrains::wall_vx ..;
/// zero is a fixed wall), whatever their force.
void pd_integrate(PdNodes& nodes, const PdGrains& grains, double dt, bool first_step = false);

}  // namespace debris
