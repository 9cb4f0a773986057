#include "kernels/dem/cohesive_contact.hpp"

#include <stdexcept>

#include "core/block_sums.hpp"
#include "core/comm/communicator.hpp"
#include "core/contact_history.hpp"
#include "core/exec.hpp"
#include "core/neighbor_list.hpp"
#include "core/particles.hpp"

namespace debris {

namespace {

// The full-list pass with the energy parts: each row's own sums, from its own evaluation of each pair (both
// ends evaluate every pair, so each particle gets each of its pairs' energies, as the half-list pass gives).
void cohesive_contact_pass_energy(const CohesiveCoefficients& c, const CohesiveOptions& opt, const BoxView& box,
                                  Particles& p, const NeighborList& list, ContactHistory& history, double dt,
                                  int update_history, const PairEnergyOut& energy) {
  const int n = list.rows();
  const int* __restrict offset = list.offset().data();
  const int* __restrict index = list.index().data();
  const double *__restrict x = p.x.data(), *__restrict y = p.y.data(), *__restrict z = p.z.data();
  const double *__restrict vx = p.vx.data(), *__restrict vy = p.vy.data(), *__restrict vz = p.vz.data();
  const double *__restrict wx = p.wx.data(), *__restrict wy = p.wy.data(), *__restrict wz = p.wz.data();
  const double *__restrict radius = p.radius.data(), *__restrict mass = p.mass.data();
  double *__restrict fx = p.fx.data(), *__restrict fy = p.fy.data(), *__restrict fz = p.fz.data();
  double *__restrict tx = p.tx.data(), *__restrict ty = p.ty.data(), *__restrict tz = p.tz.data();
  double *__restrict hx = history.hx.data(), *__restrict hy = history.hy.data(), *__restrict hz = history.hz.data();
  double* __restrict e = energy.rows;
  const CohesiveCoefficients coef = c;
  const CohesiveOptions o = opt;
  const BoxView b = box;
  DEBRIS_RESIDENT(offset, index, x, y, z, vx, vy, vz, wx, wy, wz, radius, mass, fx, fy, fz, tx, ty, tz, hx, hy, hz, e);
  DEBRIS_KERNEL
  for (int i = 0; i < n; ++i) {
    const Vec3 xi{x[i], y[i], z[i]}, vi{vx[i], vy[i], vz[i]}, wi{wx[i], wy[i], wz[i]};
    const double ri = radius[i], mi = mass[i];
    Vec3 f{}, t{}, dn{}, dtg{}, dtq{};
    double s_n = 0, s_t = 0, s_s = 0, s_w = 0;
    for (int k = offset[i]; k < offset[i + 1]; ++k) {
      const int j = index[k];
      const Vec3 dx = minimum_image(b, xi - Vec3{x[j], y[j], z[j]});
      const CohesivePairParams pp = cohesive_pair_params(coef, ri, radius[j], mi, mass[j]);
      const CohesivePair pair{dx, ri, radius[j], pp.delta_f, pp.c_n, vi - Vec3{vx[j], vy[j], vz[j]},
                              wi, Vec3{wx[j], wy[j], wz[j]}, Vec3{hx[k], hy[k], hz[k]}, i < j};
      const CohesivePairResult r = cohesive_pair_force(coef, o, pair, dt, update_history);
      hx[k] = r.history.x;
      hy[k] = r.history.y;
      hz[k] = r.history.z;
      f += r.force;
      t += r.torque;
      dn += r.damping_n;
      dtg += r.damping_t;
      dtq += r.damping_torque;
      s_n += r.dissipated_normal;
      s_t += r.dissipated_tangential;
      s_s += r.dissipated_sliding;
      s_w += r.tangential_work;
    }
    fx[i] += f.x;
    fy[i] += f.y;
    fz[i] += f.z;
    tx[i] += t.x;
    ty[i] += t.y;
    tz[i] += t.z;
    double* ei = e + kPairEnergyColumns * i;
    ei[kDampNx] = dn.x, ei[kDampNy] = dn.y, ei[kDampNz] = dn.z;
    ei[kDampTx] = dtg.x, ei[kDampTy] = dtg.y, ei[kDampTz] = dtg.z;
    ei[kDampTorqueX] = dtq.x, ei[kDampTorqueY] = dtq.y, ei[kDampTorqueZ] = dtq.z;
    ei[kPairDissNormal] = s_n, ei[kPairDissTangential] = s_t, ei[kPairDissSliding] = s_s, ei[kPairTangentialWork] = s_w;
  }
}

}  // namespace

void cohesive_contact_pass(const CohesiveCoefficients& c, const CohesiveOptions& opt, const BoxView& box,
                           Particles& p, const NeighborList& list, ContactHistory& history, double dt,
                           int update_history, const PairEnergyOut* energy) {
  if (list.kind() != NeighborKind::full) throw std::logic_error("cohesive_contact_pass needs a full list");
  const int n = list.rows();
  const int* __restrict offset = list.offset().data();
  const int* __restrict index = list.index().data();
  const double *__restrict x = p.x.data(), *__restrict y = p.y.data(), *__restrict z = p.z.data();
  const double *__restrict vx = p.vx.data(), *__restrict vy = p.vy.data(), *__restrict vz = p.vz.data();
  const double *__restrict wx = p.wx.data(), *__restrict wy = p.wy.data(), *__restrict wz = p.wz.data();
  const double *__restrict radius = p.radius.data(), *__restrict mass = p.mass.data();
  double *__restrict fx = p.fx.data(), *__restrict fy = p.fy.data(), *__restrict fz = p.fz.data();
  double *__restrict tx = p.tx.data(), *__restrict ty = p.ty.data(), *__restrict tz = p.tz.data();
  double *__restrict hx = history.hx.data(), *__restrict hy = history.hy.data(), *__restrict hz = history.hz.data();
  const CohesiveCoefficients coef = c;
  const CohesiveOptions o = opt;
  const BoxView b = box;
  if (energy) return cohesive_contact_pass_energy(c, opt, box, p, list, history, dt, update_history, *energy);
  DEBRIS_RESIDENT(offset, index, x, y, z, vx, vy, vz, wx, wy, wz, radius, mass, fx, fy, fz, tx, ty, tz, hx, hy, hz);
  DEBRIS_KERNEL
  for (int i = 0; i < n; ++i) {
    const Vec3 xi{x[i], y[i], z[i]}, vi{vx[i], vy[i], vz[i]}, wi{wx[i], wy[i], wz[i]};
    const double ri = radius[i], mi = mass[i];
    Vec3 f{}, t{};
    for (int k = offset[i]; k < offset[i + 1]; ++k) {
      const int j = index[k];
      const Vec3 dx = minimum_image(b, xi - Vec3{x[j], y[j], z[j]});
      // delta_f (eq 10) and c_N (eq 12) as CohesivePairTable makes them for the half-list pass.
      const CohesivePairParams pp = cohesive_pair_params(coef, ri, radius[j], mi, mass[j]);
      const CohesivePair pair{dx, ri, radius[j], pp.delta_f, pp.c_n, vi - Vec3{vx[j], vy[j], vz[j]},
                              wi, Vec3{wx[j], wy[j], wz[j]}, Vec3{hx[k], hy[k], hz[k]}, i < j};
      const CohesivePairResult r = cohesive_pair_force(coef, o, pair, dt, update_history);
      hx[k] = r.history.x;
      hy[k] = r.history.y;
      hz[k] = r.history.z;
      f += r.force;
      t += r.torque;
    }
    fx[i] += f.x;
    fy[i] += f.y;
    fz[i] += f.z;
    tx[i] += t.x;
    ty[i] += t.y;
    tz[i] += t.z;
  }
}

CohesiveDiagnostics cohesive_diagnostics(const CohesiveCoefficients& c, const CohesiveOptions& opt,
                                         const BoxView& box, const Particles& p, const NeighborList& list,
                                         const ContactHistory& history, SumScope scope) {
  const int n = list.rows();
  const unsigned char* owned = scope.owned;
  const std::int64_t* id = p.id.data();
  const int* offset = list.offset().data();
  const int* index = list.index().data();
  const double *x = p.x.data(), *y = p.y.data(), *z = p.z.data();
  const double *radius = p.radius.data(), *mass = p.mass.data();
  const double *hx = history.hx.data(), *hy = history.hy.data(), *hz = history.hz.data();
  const CohesiveCoefficients coef = c;
  const CohesiveOptions o = opt;
  const BoxView b = box;
  // A full list holds each pair twice: half of its energy per appearance.
  const double share = list.kind() == NeighborKind::full ? 0.5 : 1.0;
  // The energy in exact block sums of rows (core/block_sums.hpp): the same bits on any thread count, storage
  // order or rank count.
  const int blocks = sum_blocks(n);
  ExactPartials partials;
  std::int64_t* part = partials.reserve(2 * static_cast<std::size_t>(blocks));
  DEBRIS_RESIDENT(part, offset, index, x, y, z, radius, mass, hx, hy, hz, owned, id);
  DEBRIS_KERNEL
  for (int blk = 0; blk < blocks; ++blk) {
    std::int64_t* s = part + 2 * comm::kExactWords * static_cast<std::size_t>(blk);
    exact_zero(s, 2);
    const BlockRange r = block_range(blk, n);
    for (int i = r.begin; i < r.end; ++i) {
      for (int k = offset[i]; k < offset[i + 1]; ++k) {
        const int j = index[k];
        if (owned && !owned[id[i] < id[j] ? i : j]) continue;  // counted on the rank of its lower-id end
        const Vec3 dx = minimum_image(b, Vec3{x[i] - x[j], y[i] - y[j], z[i] - z[j]});
        const CohesivePairParams pp = cohesive_pair_params(coef, radius[i], radius[j], mass[i], mass[j]);
        const double dn = norm(dx) - radius[i] - radius[j];
        comm::exact_add(s, share * cohesive_pair_energy(pp, o, dn, Vec3{hx[k], hy[k], hz[k]}));
        if (dn <= (o.adhesive ? pp.delta_f : 0.0)) comm::exact_add(s + comm::kExactWords, share);
      }
    }
  }
  partials.to_host(2 * static_cast<std::size_t>(blocks));
  double sums[2];
  partials.add_up(blocks, 2, sums, scope.across_ranks);
  const double energy = sums[0], pairs = sums[1];
  double overlap = 0.0;
  DEBRIS_RESIDENT(offset, index, x, y, z, radius, owned);
  DEBRIS_KERNEL_MAX(overlap)
  for (int i = 0; i < n; ++i) {
    for (int k = offset[i]; k < offset[i + 1]; ++k) {
      const int j = index[k];
      if (owned && !owned[i] && !owned[j]) continue;  // two ghosts: not this rank's pair
      const Vec3 dx = minimum_image(b, Vec3{x[i] - x[j], y[i] - y[j], z[i] - z[j]});
      const double ov = radius[i] + radius[j] - norm(dx);
      overlap = ov > overlap ? ov : overlap;
    }
  }
  if (scope.across_ranks) comm::allreduce_max(&overlap, 1);
  CohesiveDiagnostics d;
  d.elastic_energy = energy;
  d.max_overlap = overlap;
  d.interacting_pairs = static_cast<long>(pairs + 0.5);
  return d;
}

}  // namespace debris
