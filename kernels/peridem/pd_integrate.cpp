#include "kernels/peridem/pd_integrate.hpp"

#include "core/exec.hpp"
#include "core/pd_nodes.hpp"

namespace debris {

void pd_zero_forces(PdNodes& nodes) {
  const int n = static_cast<int>(nodes.size());
  double* __restrict fx = nodes.fx.data(), *__restrict fy = nodes.fy.data(), *__restrict fz = nodes.fz.data();
  DEBRIS_RESIDENT(fx, fy, fz);
  DEBRIS_KERNEL
  for (int i = 0; i < n; ++i) fx[i] = fy[i] = fz[i] = 0.0;
}

void pd_weight_forces(PdNodes& nodes, const PdGrains& grains, Vec3 g) {
  const int n = static_cast<int>(nodes.size());
  const double* __restrict mass = nodes.mass.data();
  const int* __restrict grain = nodes.grain.data();
  const int* __restrict kind = grains.kind.data();
  double* __restrict fx = nodes.fx.data(), *__restrict fy = nodes.fy.data(), *__restrict fz = nodes.fz.data();
  const double gx = g.x, gy = g.y, gz = g.z;
  const int wall = static_cast<int>(PdGrainKind::wall);
  DEBRIS_RESIDENT(mass, grain, kind, fx, fy, fz);
  DEBRIS_KERNEL
  for (int i = 0; i < n; ++i) {
    const bool weighs = kind[grain[i]] != wall;
    // 0.0 + m g: a -0.0 weight component becomes +0.0, as zeroing then adding would give.
    fx[i] = weighs ? 0.0 + mass[i] * gx : 0.0;
    fy[i] = weighs ? 0.0 + mass[i] * gy : 0.0;
    fz[i] = weighs ? 0.0 + mass[i] * gz : 0.0;
  }
}

void pd_viscous_damping(PdNodes& nodes, const PdGrains& grains, double c) {
  const int n = static_cast<int>(nodes.size());
  const double* __restrict mass = nodes.mass.data();
  const int* __restrict grain = nodes.grain.data();
  const int* __restrict kind = grains.kind.data();
  const double* __restrict vx = nodes.vx.data(), *__restrict vy = nodes.vy.data(), *__restrict vz = nodes.vz.data();
  double* __restrict fx = nodes.fx.data(), *__restrict fy = nodes.fy.data(), *__restrict fz = nodes.fz.data();
  const int wall = static_cast<int>(PdGrainKind::wall);
  DEBRIS_RESIDENT(mass, grain, kind, vx, vy, vz, fx, fy, fz);
  DEBRIS_KERNEL
  for (int i = 0; i < n; ++i) {
    if (kind[grain[i]] == wall) continue;  // walls move as prescribed
    const double cm = c * mass[i];
    fx[i] -= cm * vx[i];
    fy[i] -= cm * vy[i];
    fz[i] -= cm * vz[i];
  }
}

void pd_integrate(PdNodes& nodes, const PdGrains& grains, double dt, bool first_step) {
  const int n = static_cast<int>(nodes.size());
  double* __restrict x = nodes.x.data(), *__restrict y = nodes.y.data(), *__restrict z = nodes.z.data();
  double* __restrict vx = nodes.vx.data(), *__restrict vy = nodes.vy.data(), *__restrict vz = nodes.vz.data();
  const double* __restrict fx = nodes.fx.data(), *__restrict fy = nodes.fy.data(), *__restrict fz = nodes.fz.data();
  const double* __restrict mass = nodes.mass.data();
  const int* __restrict grain = nodes.grain.data(), *__restrict fixed = nodes.fixed.data();
  const int* __restrict kind = grains.kind.data();
  const double *__restrict wvx = grains.wall_vx.data(), *__restrict wvy = grains.wall_vy.data(),
                           *__restrict wvz = grains.wall_vz.data();
  const double kick = first_step ? 0.5 * dt : dt;
  const int wall = static_cast<int>(PdGrainKind::wall);
  DEBRIS_RESIDENT(x, y, z, vx, vy, vz, fx, fy, fz, mass, grain, fixed, kind, wvx, wvy, wvz);
  DEBRIS_KERNEL
  for (int i = 0; i < n; ++i) {
    const int g = grain[i];
    if (kind[g] == wall) {  // rigid, prescribed
      vx[i] = wvx[g];
      vy[i] = wvy[g];
      vz[i] = wvz[g];
      x[i] += dt * vx[i];
      y[i] += dt * vy[i];
      z[i] += dt * vz[i];
      continue;
    }
    const double h = kick / mass[i];
    const int fix = fixed[i];
    if (fix & 1) {
      vx[i] = 0.0;
    } else {
      vx[i] += h * fx[i];
      x[i] += dt * vx[i];
    }
    if (fix & 2) {
      vy[i] = 0.0;
    } else {
      vy[i] += h * fy[i];
      y[i] += dt * vy[i];
    }
    if (fix & 4) {
      vz[i] = 0.0;
    } else {
      vz[i] += h * fz[i];
      z[i] += dt * vz[i];
    }
  }
}

}  // namespace debris
