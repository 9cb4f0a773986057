#include "kernels/dem/integrate.hpp"

#include <cmath>

#include "core/block_sums.hpp"
#include "core/exec.hpp"
#include "core/particles.hpp"

namespace debris {

void integrate_semi_implicit_euler(Particles& p, Groups::View groups, double dt) {
  const int n = static_cast<int>(p.size());
  double *__restrict x = p.x.data(), *__restrict y = p.y.data(), *__restrict z = p.z.data();
  double *__restrict vx = p.vx.data(), *__restrict vy = p.vy.data(), *__restrict vz = p.vz.data();
  double *__restrict wx = p.wx.data(), *__restrict wy = p.wy.data(), *__restrict wz = p.wz.data();
  const double *__restrict fx = p.fx.data(), *__restrict fy = p.fy.data(), *__restrict fz = p.fz.data();
  const double *__restrict tx = p.tx.data(), *__restrict ty = p.ty.data(), *__restrict tz = p.tz.data();
  const double *__restrict mass = p.mass.data(), *__restrict inertia = p.inertia.data();
  const int* __restrict group = p.group.data();
  const int* __restrict mode = groups.mode;
  const double *__restrict gvx = groups.vx, *__restrict gvy = groups.vy, *__restrict gvz = groups.vz;
  DEBRIS_RESIDENT(x, y, z, vx, vy, vz, wx, wy, wz, fx, fy, fz, tx, ty, tz, mass, inertia, group, mode, gvx, gvy, gvz);
  DEBRIS_KERNEL
  for (int i = 0; i < n; ++i) {
    const int g = group[i];
    const int m = g < 0 ? 0 : mode[g];
    if (m == 0) {  // free: eq 1a, 1b, 1c
      const double im = dt / mass[i], ii = dt / inertia[i];
      vx[i] += fx[i] * im;
      vy[i] += fy[i] * im;
      vz[i] += fz[i] * im;
      wx[i] += tx[i] * ii;
      wy[i] += ty[i] * ii;
      wz[i] += tz[i] * ii;
    } else if (m == 1) {  // frozen
      vx[i] = vy[i] = vz[i] = 0.0;
      wx[i] = wy[i] = wz[i] = 0.0;
    } else {  // rigid translation at the group's velocity
      vx[i] = gvx[g];
      vy[i] = gvy[g];
      vz[i] = gvz[g];
      wx[i] = wy[i] = wz[i] = 0.0;
    }
    x[i] += vx[i] * dt;
    y[i] += vy[i] * dt;
    z[i] += vz[i] * dt;
  }
}

void zero_forces(Particles& p) {
  const int n = static_cast<int>(p.size());
  double *fx = p.fx.data(), *fy = p.fy.data(), *fz = p.fz.data();
  double *tx = p.tx.data(), *ty = p.ty.data(), *tz = p.tz.data();
  DEBRIS_RESIDENT(fx, fy, fz, tx, ty, tz);
  DEBRIS_KERNEL
  for (int i = 0; i < n; ++i) {
    fx[i] = fy[i] = fz[i] = 0.0;
    tx[i] = ty[i] = tz[i] = 0.0;
  }
}

Vec3 kicked_velocity(const Group& g, double dt) {
  const Vec3 dv = (dt / g.mass) * (g.reaction + g.external_force);
  Vec3 v = g.velocity;
  if (!g.prescribed[0]) v.x += dv.x;
  if (!g.prescribed[1]) v.y += dv.y;
  if (!g.prescribed[2]) v.z += dv.z;
  return v;
}

void kick_rigid_groups(Groups& groups, double dt) {
  for (Group& g : groups.list) {
    if (g.motion != GroupMotion::force || !(g.mass > 0.0)) continue;
    g.velocity = kicked_velocity(g, dt);
  }
}

void global_damping_pass(Particles& p, Groups::View groups, double c) {
  if (c == 0.0) return;
  const int n = static_cast<int>(p.size());
  const double *vx = p.vx.data(), *vy = p.vy.data(), *vz = p.vz.data();
  double *fx = p.fx.data(), *fy = p.fy.data(), *fz = p.fz.data();
  const int* group = p.group.data();
  const int* mode = groups.mode;
  DEBRIS_RESIDENT(vx, vy, vz, fx, fy, fz, group, mode);
  DEBRIS_KERNEL
  for (int i = 0; i < n; ++i) {
    const int g = group[i];
    if (g >= 0 && mode[g] != 0) continue;
    fx[i] -= c * vx[i];
    fy[i] -= c * vy[i];
    fz[i] -= c * vz[i];
  }
}

ParticleTotals particle_totals(const Particles& p, SumScope scope) {
  const int n = static_cast<int>(p.size());
  const double *x = p.x.data(), *y = p.y.data(), *z = p.z.data();
  const double *vx = p.vx.data(), *vy = p.vy.data(), *vz = p.vz.data();
  const double *wx = p.wx.data(), *wy = p.wy.data(), *wz = p.wz.data();
  const double *mass = p.mass.data(), *inertia = p.inertia.data();
  const unsigned char* owned = scope.owned;
  // Exact block sums (core/block_sums.hpp): the thermo table has the same bits on any thread count, storage
  // order or rank count.
  constexpr int K = 7;  // kinetic energy, momentum, angular momentum
  const int blocks = sum_blocks(n);
  ExactPartials partials;
  std::int64_t* part = partials.reserve(static_cast<std::size_t>(K) * static_cast<std::size_t>(blocks));
  DEBRIS_RESIDENT(part, x, y, z, vx, vy, vz, wx, wy, wz, mass, inertia, owned);
  DEBRIS_KERNEL
  for (int b = 0; b < blocks; ++b) {
    std::int64_t* s = part + static_cast<std::size_t>(K) * comm::kExactWords * static_cast<std::size_t>(b);
    exact_zero(s, K);
    const BlockRange r = block_range(b, n);
    for (int i = r.begin; i < r.end; ++i) {
      if (owned && !owned[i]) continue;  // a ghost: its owner counts it
      const double ke = 0.5 * mass[i] * (vx[i] * vx[i] + vy[i] * vy[i] + vz[i] * vz[i]) +
                        0.5 * inertia[i] * (wx[i] * wx[i] + wy[i] * wy[i] + wz[i] * wz[i]);
      const Vec3 l = mass[i] * cross(Vec3{x[i], y[i], z[i]}, Vec3{vx[i], vy[i], vz[i]});
      const double term[K] = {ke,
                              mass[i] * vx[i],
                              mass[i] * vy[i],
                              mass[i] * vz[i],
                              l.x + inertia[i] * wx[i],
                              l.y + inertia[i] * wy[i],
                              l.z + inertia[i] * wz[i]};
      for (int q = 0; q < K; ++q) comm::exact_add(s + q * comm::kExactWords, term[q]);
    }
  }
  partials.to_host(static_cast<std::size_t>(K) * static_cast<std::size_t>(blocks));
  double t[K];
  partials.add_up(blocks, K, t, scope.across_ranks);
  return {t[0], {t[1], t[2], t[3]}, {t[4], t[5], t[6]}};
}

double synchronized_kinetic_energy(const Particles& p, double dt) {
  const int n = static_cast<int>(p.size());
  const double *vx = p.vx.data(), *vy = p.vy.data(), *vz = p.vz.data();
  const double *wx = p.wx.data(), *wy = p.wy.data(), *wz = p.wz.data();
  const double *fx = p.fx.data(), *fy = p.fy.data(), *fz = p.fz.data();
  const double *tx = p.tx.data(), *ty = p.ty.data(), *tz = p.tz.data();
  const double *mass = p.mass.data(), *inertia = p.inertia.data();
  const double h = 0.5 * dt;
  double ke = 0.0;
  DEBRIS_RESIDENT(vx, vy, vz, wx, wy, wz, fx, fy, fz, tx, ty, tz, mass, inertia);
  DEBRIS_KERNEL_SUM(ke)
  for (int i = 0; i < n; ++i) {
    const Vec3 v{vx[i] + h * fx[i] / mass[i], vy[i] + h * fy[i] / mass[i], vz[i] + h * fz[i] / mass[i]};
    const Vec3 w{wx[i] + h * tx[i] / inertia[i], wy[i] + h * ty[i] / inertia[i], wz[i] + h * tz[i] / inertia[i]};
    ke += 0.5 * mass[i] * norm2(v) + 0.5 * inertia[i] * norm2(w);
  }
  return ke;
}

long first_non_finite(const Particles& p) {
  const int n = static_cast<int>(p.size());
  const double *x = p.x.data(), *y = p.y.data(), *z = p.z.data();
  const double *vx = p.vx.data(), *vy = p.vy.data(), *vz = p.vz.data();
  const double *fx = p.fx.data(), *fy = p.fy.data(), *fz = p.fz.data();
  // Smallest bad index through a min reduction; a NaN anywhere makes the sum NaN, which isfinite catches.
  int first = n;
  DEBRIS_RESIDENT(x, y, z, vx, vy, vz, fx, fy, fz);
  DEBRIS_KERNEL_MIN(first)
  for (int i = 0; i < n; ++i) {
    const double s = x[i] + y[i] + z[i] + vx[i] + vy[i] + vz[i] + fx[i] + fy[i] + fz[i];
    if (!std::isfinite(s) && i < first) first = i;
  }
  return first < n ? first : -1;
}

}  // namespace debris
