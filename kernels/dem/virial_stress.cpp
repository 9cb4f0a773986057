#include "kernels/dem/virial_stress.hpp"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>
#include <stdexcept>

#include "core/block_sums.hpp"
#include "core/contact_history.hpp"
#include "core/exec.hpp"
#include "core/neighbor_list.hpp"
#include "core/particles.hpp"

namespace debris {

namespace {

DEBRIS_DECLARE_TARGET

// W_ab -= term: six exact accumulators, xx yy zz xy xz yz. (A function, not a lambda: clang's offload
// compiler refuses a lambda that captures the accumulator width in a declare-target region.)
inline void add_negated(std::int64_t* s, double xx, double yy, double zz, double xy, double xz, double yz) {
  const double term[6] = {xx, yy, zz, xy, xz, yz};
  for (int q = 0; q < 6; ++q) comm::exact_add(s + q * comm::kExactWords, -term[q]);
}

// Adds the share of row i to the exact accumulators s (six, xx yy zz xy xz yz): the pair forces of the row
// from copies of their histories (never advanced), plus m v v when i is selected. A full list meets each
// pair from both ends, and half of r_ij (x) F_ij goes to each selected end; a half list meets it once and
// credits the halves of both ends from here (r_ji (x) F_ji = r_ij (x) F_ij). Every pair term is added
// exactly on its own (not summed per particle first), so the total does not depend on which rows hold a
// pair: a run cut among ranks, where the two halves of a pair may be credited on two ranks, gets the same
// bits (0.5 r F, rounded, is half of r F, rounded). Takes the raw columns one by one (not in a struct) so
// that an offload build translates each pointer.
inline void add_particle_virial(std::int64_t* s, int i, int half, const int* sel, const int* offset, const int* index,
                                const double* x, const double* y, const double* z, const double* vx,
                                const double* vy, const double* vz, const double* wx, const double* wy,
                                const double* wz, const double* radius, const double* mass, const double* hx,
                                const double* hy, const double* hz, const CohesiveCoefficients& coef,
                                const CohesiveOptions& opt, const BoxView& b, int kinetic) {
  const Vec3 xi{x[i], y[i], z[i]}, vi{vx[i], vy[i], vz[i]}, wi{wx[i], wy[i], wz[i]};
  const double ri = radius[i], mi = mass[i];
  const double own = (sel == nullptr || sel[i]) ? 0.5 : 0.0;
  if (!half && own == 0.0) return;
  for (int k = offset[i]; k < offset[i + 1]; ++k) {
    const int j = index[k];
    const double share = half ? own + ((sel == nullptr || sel[j]) ? 0.5 : 0.0) : own;
    if (share == 0.0) continue;
    const Vec3 dx = minimum_image(b, xi - Vec3{x[j], y[j], z[j]});
    const CohesivePairParams pp = cohesive_pair_params(coef, ri, radius[j], mi, mass[j]);
    const CohesivePair pair{dx, ri, radius[j], pp.delta_f, pp.c_n, vi - Vec3{vx[j], vy[j], vz[j]}, wi,
                            Vec3{wx[j], wy[j], wz[j]}, Vec3{hx[k], hy[k], hz[k]}, i < j};
    const Vec3 f = cohesive_pair_force(coef, opt, pair, 0.0, 0).force;  // the history is not advanced
    add_negated(s, share * dx.x * f.x, share * dx.y * f.y, share * dx.z * f.z, share * dx.x * f.y, share * dx.x * f.z,
        share * dx.y * f.z);
  }
  if (kinetic && own > 0)
    add_negated(s, mi * vi.x * vi.x, mi * vi.y * vi.y, mi * vi.z * vi.z, mi * vi.x * vi.y, mi * vi.x * vi.z, mi * vi.y * vi.z);
}

DEBRIS_END_DECLARE_TARGET

}  // namespace

StressTensor virial_stress(const CohesiveCoefficients& c, const CohesiveOptions& opt, const BoxView& box,
                           const Particles& p, const NeighborList& list, const ContactHistory& history,
                           const int* select, double volume, bool kinetic, bool across_ranks) {
  if (static_cast<std::size_t>(list.rows()) != p.size() ||
      history.hx.size() != static_cast<std::size_t>(list.entries()))
    throw std::logic_error("virial_stress: the list and the history do not belong to these particles");
  if (!(volume > 0)) throw std::invalid_argument("virial_stress: the sample volume must be > 0");
  const int n = list.rows();
  const int* offset = list.offset().data();
  const int* index = list.index().data();
  const double *x = p.x.data(), *y = p.y.data(), *z = p.z.data();
  const double *vx = p.vx.data(), *vy = p.vy.data(), *vz = p.vz.data();
  const double *wx = p.wx.data(), *wy = p.wy.data(), *wz = p.wz.data();
  const double *radius = p.radius.data(), *mass = p.mass.data();
  const double *hx = history.hx.data(), *hy = history.hy.data(), *hz = history.hz.data();
  const int* sel = select;
  const CohesiveCoefficients coef = c;
  const CohesiveOptions o = opt;
  const BoxView b = box;
  const int kin = kinetic ? 1 : 0;
  const int half = list.kind() == NeighborKind::half ? 1 : 0;
  const double inv = 1.0 / volume;
  // Exact block sums (core/block_sums): the same bits for any thread count, device, storage order or rank
  // count (the amorphous relaxation feeds the stress back into the box).
  constexpr int K = 6;  // xx, yy, zz, xy, xz, yz
  const int blocks = sum_blocks(n);
  ExactPartials partials;
  std::int64_t* __restrict part = partials.reserve(static_cast<std::size_t>(K) * static_cast<std::size_t>(blocks));
  // The caller's mask is a host array: a copy on the device for this call (offload builds).
  exec::DeviceVector<int> select_copy;
  sel = exec::on_device(sel, static_cast<std::size_t>(n), select_copy);
  DEBRIS_RESIDENT(part, sel, offset, index, x, y, z, vx, vy, vz, wx, wy, wz, radius, mass, hx, hy, hz);
  DEBRIS_KERNEL
  for (int blk = 0; blk < blocks; ++blk) {
    std::int64_t* s = part + static_cast<std::size_t>(K) * comm::kExactWords * static_cast<std::size_t>(blk);
    exact_zero(s, K);
    const BlockRange r = block_range(blk, n);
    for (int i = r.begin; i < r.end; ++i)
      add_particle_virial(s, i, half, sel, offset, index, x, y, z, vx, vy, vz, wx, wy, wz, radius, mass, hx, hy, hz,
                          coef, o, b, kin);
  }
  partials.to_host(static_cast<std::size_t>(K) * static_cast<std::size_t>(blocks));
  double s[K];
  partials.add_up(blocks, K, s, across_ranks);
  return StressTensor{s[0] * inv, s[1] * inv, s[2] * inv, s[3] * inv, s[4] * inv, s[5] * inv};
}

}  // namespace debris
