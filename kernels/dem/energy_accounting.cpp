#include "kernels/dem/energy_accounting.hpp"

#include "core/comm/communicator.hpp"
#include "core/particles.hpp"
#include "kernels/dem/integrate.hpp"

namespace debris {

void PairEnergyBuffers::resize(std::size_t n) { rows.resize(kPairEnergyColumns * n); }

PairEnergyOut PairEnergyBuffers::out() { return PairEnergyOut{rows.data()}; }

std::size_t PairEnergyBuffers::bytes() const { return sizeof(double) * rows.capacity(); }

void fold_energy(Particles& p, PairEnergyBuffers& pair, const Groups& groups, Groups::View view, double damping,
                 double dt) {
  const int n = static_cast<int>(p.size());
  const double *__restrict vx = p.vx.data(), *__restrict vy = p.vy.data(), *__restrict vz = p.vz.data();
  const double *__restrict wx = p.wx.data(), *__restrict wy = p.wy.data(), *__restrict wz = p.wz.data();
  const double *__restrict fx = p.fx.data(), *__restrict fy = p.fy.data(), *__restrict fz = p.fz.data();
  const double *__restrict tx = p.tx.data(), *__restrict ty = p.ty.data(), *__restrict tz = p.tz.data();
  const double *__restrict mass = p.mass.data(), *__restrict inertia = p.inertia.data();
  const int* __restrict group = p.group.data();
  const int* __restrict mode = view.mode;
  const double* __restrict e = pair.rows.data();
  double *__restrict pend_n = p.pending_normal.data(), *__restrict pend_t = p.pending_tangential.data();
  double *__restrict pend_g = p.pending_global.data(), *__restrict pend_w = p.pending_tangential_work.data();
  double *__restrict pend_d = p.pending_drive.data(), *__restrict sliding = p.dissipated_sliding.data();
  // The groups' next velocities, flat for the kernel (a few numbers, in a buffer kept between steps).
  exec::DeviceVector<double>& gv = pair.group_next;
  if (gv.size() != 3 * groups.size()) gv.resize(3 * groups.size());
  for (std::size_t g = 0; g < groups.size(); ++g) {
    // As kick_rigid_groups() will set them; frozen: at rest.
    const Group& grp = groups.list[g];
    Vec3 v = grp.velocity;
    if (grp.motion == GroupMotion::frozen) v = Vec3{};
    else if (grp.motion == GroupMotion::force && grp.mass > 0.0) v = kicked_velocity(grp, dt);
    gv[3 * g] = v.x, gv[3 * g + 1] = v.y, gv[3 * g + 2] = v.z;
  }
  const double* __restrict gnext = gv.data();
  const double c = damping;
  exec::to_device(gv);
  DEBRIS_RESIDENT(vx, vy, vz, wx, wy, wz, fx, fy, fz, tx, ty, tz, mass, inertia, group, mode, e, pend_n, pend_t, pend_g,
                  pend_w, pend_d, sliding, gnext);
  DEBRIS_KERNEL
  for (int i = 0; i < n; ++i) {
    const int g = group[i];
    const int m = g < 0 ? 0 : mode[g];
    const Vec3 v{vx[i], vy[i], vz[i]}, w{wx[i], wy[i], wz[i]};
    // The velocities the integration will give (integrate_semi_implicit_euler, kick_rigid_groups).
    Vec3 v1{}, w1{};
    if (m == 0) {
      const double im = dt / mass[i], ii = dt / inertia[i];
      v1 = Vec3{vx[i] + fx[i] * im, vy[i] + fy[i] * im, vz[i] + fz[i] * im};
      w1 = Vec3{wx[i] + tx[i] * ii, wy[i] + ty[i] * ii, wz[i] + tz[i] * ii};
    } else if (m != 1) {
      v1 = Vec3{gnext[3 * g], gnext[3 * g + 1], gnext[3 * g + 2]};
    }
    const Vec3 dv = 0.5 * (v1 - v), dw = 0.5 * (w1 - w);  // vb - v, wb - w
    // Half of each pair's dissipation, and this particle's own correction to the mean velocity.
    const double* ei = e + kPairEnergyColumns * i;
    const Vec3 damp_n{ei[kDampNx], ei[kDampNy], ei[kDampNz]}, damp_t{ei[kDampTx], ei[kDampTy], ei[kDampTz]};
    const Vec3 damp_q{ei[kDampTorqueX], ei[kDampTorqueY], ei[kDampTorqueZ]};
    pend_n[i] = 0.5 * ei[kPairDissNormal] - dot(damp_n, dv) * dt;
    pend_t[i] = 0.5 * ei[kPairDissTangential] - (dot(damp_t, dv) + dot(damp_q, dw)) * dt;
    pend_w[i] = 0.5 * ei[kPairTangentialWork];
    sliding[i] += 0.5 * ei[kPairDissSliding];
    const Vec3 vb = v + dv, wb = w + dw;
    // Global damping acts on free particles: F = -c v (global_damping_pass).
    pend_g[i] = m == 0 ? c * dot(v, vb) * dt : 0.0;
    // A member's velocity is set by its group: the drive did what the member's own forces did not.
    const double dke = 0.5 * mass[i] * (norm2(v1) - norm2(v)) + 0.5 * inertia[i] * (norm2(w1) - norm2(w));
    const Vec3 f{fx[i], fy[i], fz[i]}, t{tx[i], ty[i], tz[i]};
    pend_d[i] = m == 0 ? 0.0 : dke - (dot(f, vb) + dot(t, wb)) * dt;
  }
}

void commit_energy(Particles& p) {
  const int n = static_cast<int>(p.size());
  double *__restrict dn = p.dissipated_normal.data(), *__restrict dt = p.dissipated_tangential.data();
  double *__restrict dg = p.dissipated_global.data(), *__restrict tw = p.tangential_work.data();
  double *__restrict dw = p.drive_work.data();
  double *__restrict pn = p.pending_normal.data(), *__restrict pt = p.pending_tangential.data();
  double *__restrict pg = p.pending_global.data(), *__restrict pw = p.pending_tangential_work.data();
  double *__restrict pd = p.pending_drive.data();
  DEBRIS_RESIDENT(dn, dt, dg, tw, dw, pn, pt, pg, pw, pd);
  DEBRIS_KERNEL
  for (int i = 0; i < n; ++i) {
    dn[i] += pn[i];
    dt[i] += pt[i];
    dg[i] += pg[i];
    tw[i] += pw[i];
    dw[i] += pd[i];
    pn[i] = pt[i] = pg[i] = pw[i] = pd[i] = 0.0;
  }
}

EnergyTotals energy_totals(const Particles& p, int groups, SumScope scope) {
  const int n = static_cast<int>(p.size());
  const double *dn = p.dissipated_normal.data(), *dt = p.dissipated_tangential.data();
  const double *ds = p.dissipated_sliding.data(), *dg = p.dissipated_global.data();
  const double *tw = p.tangential_work.data(), *dw = p.drive_work.data();
  const int* group = p.group.data();
  const unsigned char* owned = scope.owned;
  const int K = 5 + groups;  // the mechanisms, then each group's drive work
  const int blocks = sum_blocks(n);
  ExactPartials partials;
  std::int64_t* part = partials.reserve(static_cast<std::size_t>(K) * static_cast<std::size_t>(blocks));
  DEBRIS_RESIDENT(part, dn, dt, ds, dg, tw, dw, group, owned);
  DEBRIS_KERNEL
  for (int b = 0; b < blocks; ++b) {
    std::int64_t* s = part + static_cast<std::size_t>(K) * comm::kExactWords * static_cast<std::size_t>(b);
    exact_zero(s, K);
    const BlockRange r = block_range(b, n);
    for (int i = r.begin; i < r.end; ++i) {
      if (owned && !owned[i]) continue;  // a ghost: its owner counts it
      comm::exact_add(s, dn[i]);
      comm::exact_add(s + comm::kExactWords, dt[i]);
      comm::exact_add(s + 2 * comm::kExactWords, ds[i]);
      comm::exact_add(s + 3 * comm::kExactWords, dg[i]);
      comm::exact_add(s + 4 * comm::kExactWords, tw[i]);
      if (group[i] >= 0) comm::exact_add(s + (5 + group[i]) * comm::kExactWords, dw[i]);
    }
  }
  partials.to_host(static_cast<std::size_t>(K) * static_cast<std::size_t>(blocks));
  std::vector<double> t(static_cast<std::size_t>(K));
  partials.add_up(blocks, K, t.data(), scope.across_ranks);
  EnergyTotals out;
  out.dissipated_normal = t[0];
  out.dissipated_tangential = t[1];
  out.dissipated_sliding = t[2];
  out.dissipated_global = t[3];
  out.tangential_work = t[4];
  out.drive_work.assign(t.begin() + 5, t.end());
  return out;
}

}  // namespace debris
