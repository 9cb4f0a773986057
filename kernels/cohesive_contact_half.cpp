#include "kernels/cohesive_contact_half.hpp"

#include <cmath>
#include <stdexcept>

#include "core/contact_history.hpp"
#include "core/exec.hpp"
#include "core/neighbor_list.hpp"
#include "core/particles.hpp"

namespace debris {

namespace {

// One row: the pairs (i, j > i) of particle i. The body is eqs 2-5 exactly as in cohesive_pair_force(), made
// branch-free (selects instead of early returns) so the loop over the row vectorises; j's reaction goes to
// the thread's own arrays. Templated on the switches so that disabled parts cost nothing.
template <int Adhesive, int Tangential, int Update>
inline void cohesive_row(int i, int begin, int end, const int* __restrict index, const BoxView& b,
                         const double* __restrict x, const double* __restrict y, const double* __restrict z,
                         const double* __restrict vx, const double* __restrict vy, const double* __restrict vz,
                         const double* __restrict wx, const double* __restrict wy, const double* __restrict wz,
                         const double* __restrict radius, const CohesivePairTable& t, double* __restrict hx,
                         double* __restrict hy, double* __restrict hz, double dt, double* __restrict fx,
                         double* __restrict fy, double* __restrict fz, double* __restrict tx, double* __restrict ty,
                         double* __restrict tz) {
  const double xi = x[i], yi = y[i], zi = z[i], ri = radius[i];
  const double vxi = vx[i], vyi = vy[i], vzi = vz[i], wxi = wx[i], wyi = wy[i], wzi = wz[i];
  const double* __restrict kn = t.k_n.data();
  const double* __restrict cn = t.c_n.data();
  const double* __restrict de = t.delta_e.data();
  const double* __restrict df = t.delta_f.data();
  const double* __restrict idf = t.inv_delta_f.data();
  const double* __restrict ks = t.k_soft.data();
  const double* __restrict fmt = t.f_max_t.data();
  const double* __restrict arm = t.arm_i.data();
  const double kt_over_kn = t.kt_over_kn, ct_over_cn = t.ct_over_cn;
  const double lx = b.len[0], ly = b.len[1], lz = b.len[2];
  const int px = b.periodic[0], py = b.periodic[1], pz = b.periodic[2];
  double sfx = 0, sfy = 0, sfz = 0, stx = 0, sty = 0, stz = 0;
  for (int k = begin; k < end; ++k) {
    const int j = index[k];
    const double dx = nearest_image(xi - x[j], lx, px);
    const double dy = nearest_image(yi - y[j], ly, py);
    const double dz = nearest_image(zi - z[j], lz, pz);
    const double d = std::sqrt(dx * dx + dy * dy + dz * dz);
    const double inv_d = 1.0 / d;
    const double nx = dx * inv_d, ny = dy * inv_d, nz = dz * inv_d;
    const double dn = d - ri - radius[j];
    const double reach = Adhesive ? df[k] : 0.0;
    const bool on = dn <= reach;

    // Eq 3 (positive in tension) and the normal part of eq 2.
    const double f_el = kn[k] * dn;
    const double f_n = (Adhesive && dn > de[k]) ? ks[k] * (df[k] - dn) : f_el;
    const double rvx = vxi - vx[j], rvy = vyi - vy[j], rvz = vzi - vz[j];
    const double v_n = rvx * nx + rvy * ny + rvz * nz;
    const double fnorm = on ? -(f_n + cn[k] * v_n) : 0.0;
    double Fx = fnorm * nx, Fy = fnorm * ny, Fz = fnorm * nz;

    if (Tangential) {
      // Contact point velocity (arms a_i + a_j = d), tangential part.
      const double a_i = d * arm[k], a_j = d - a_i;
      const double sx = a_i * wxi + a_j * wx[j], sy = a_i * wyi + a_j * wy[j], sz = a_i * wzi + a_j * wz[j];
      double vcx = rvx - (sy * nz - sz * ny);
      double vcy = rvy - (sz * nx - sx * nz);
      double vcz = rvz - (sx * ny - sy * nx);
      const double vcn = vcx * nx + vcy * ny + vcz * nz;
      const double vtx = vcx - vcn * nx, vty = vcy - vcn * ny, vtz = vcz - vcn * nz;

      // History: rotate into the tangent plane keeping its length, advance, cap by eqs 4-5.
      double h_x = hx[k], h_y = hy[k], h_z = hz[k];
      if (Update) {
        const double h2 = h_x * h_x + h_y * h_y + h_z * h_z;
        const double hn = h_x * nx + h_y * ny + h_z * nz;
        h_x -= hn * nx;
        h_y -= hn * ny;
        h_z -= hn * nz;
        const double hp2 = h_x * h_x + h_y * h_y + h_z * h_z;
        const double keep = hp2 > 0.0 ? std::sqrt(h2 / (hp2 > 0.0 ? hp2 : 1.0)) : 1.0;
        h_x = keep * h_x + dt * vtx;
        h_y = keep * h_y + dt * vty;
        h_z = keep * h_z + dt * vtz;
      }
      const double k_t = kt_over_kn * kn[k];
      const double share = (df[k] - dn) * idf[k];
      const double cap = (share < 1.0 ? share : 1.0) * fmt[k];
      const double spring = k_t * std::sqrt(h_x * h_x + h_y * h_y + h_z * h_z);
      const double slide = spring > cap ? cap / spring : 1.0;
      const double c_t = ct_over_cn * cn[k];
      const double kts = on ? -k_t * slide : 0.0, cts = on ? -c_t : 0.0;
      const double ftx = kts * h_x + cts * vtx, fty = kts * h_y + cts * vty, ftz = kts * h_z + cts * vtz;
      // Slid back to the cap when updating; gone when out of range (as in cohesive_pair_force()).
      const double keep = on ? (Update ? slide : 1.0) : 0.0;
      hx[k] = keep * h_x;
      hy[k] = keep * h_y;
      hz[k] = keep * h_z;
      Fx += ftx;
      Fy += fty;
      Fz += ftz;
      // Torques -a n x F_t on both particles (n points from j to i; j sees -n and -F_t).
      const double cx = ny * ftz - nz * fty, cy = nz * ftx - nx * ftz, cz = nx * fty - ny * ftx;
      stx -= a_i * cx;
      sty -= a_i * cy;
      stz -= a_i * cz;
      tx[j] -= a_j * cx;
      ty[j] -= a_j * cy;
      tz[j] -= a_j * cz;
    } else {
      hx[k] = hy[k] = hz[k] = 0.0;
    }
    sfx += Fx;
    sfy += Fy;
    sfz += Fz;
    fx[j] -= Fx;
    fy[j] -= Fy;
    fz[j] -= Fz;
  }
  fx[i] += sfx;
  fy[i] += sfy;
  fz[i] += sfz;
  tx[i] += stx;
  ty[i] += sty;
  tz[i] += stz;
}

template <int Adhesive, int Tangential, int Update>
void run_pass(const CohesivePairTable& t, const BoxView& box, Particles& p, const NeighborList& list,
              ContactHistory& h, double dt, ThreadForceBuffers& buf) {
  const int n = list.rows();
  const int* __restrict offset = list.offset().data();
  const int* __restrict index = list.index().data();
  const double *x = p.x.data(), *y = p.y.data(), *z = p.z.data();
  const double *vx = p.vx.data(), *vy = p.vy.data(), *vz = p.vz.data();
  const double *wx = p.wx.data(), *wy = p.wy.data(), *wz = p.wz.data();
  const double* radius = p.radius.data();
  double *hx = h.hx.data(), *hy = h.hy.data(), *hz = h.hz.data();
  double* own[6] = {p.fx.data(), p.fy.data(), p.fz.data(), p.tx.data(), p.ty.data(), p.tz.data()};
  double* extra = buf.data.data();
  const std::size_t stride = static_cast<std::size_t>(n);
  int team = 1;
  DEBRIS_HOST_PARALLEL
  {
    const int tid = exec::thread_id();
    if (tid == 0) team = exec::team_size();  // the region may get fewer threads than buffers
    double* out[6];
    for (int c = 0; c < 6; ++c) {
      out[c] = tid == 0 ? own[c] : extra + (static_cast<std::size_t>(tid - 1) * 6 + c) * stride;
      if (tid != 0)
        for (int i = 0; i < n; ++i) out[c][i] = 0.0;
    }
    DEBRIS_HOST_FOR
    for (int i = 0; i < n; ++i)
      cohesive_row<Adhesive, Tangential, Update>(i, offset[i], offset[i + 1], index, box, x, y, z, vx, vy, vz, wx,
                                                 wy, wz, radius, t, hx, hy, hz, dt, out[0], out[1], out[2], out[3],
                                                 out[4], out[5]);
  }
  // Fold the other threads' buffers in, in thread order.
  const int extra_threads = team - 1;
  if (extra_threads <= 0) return;
  DEBRIS_KERNEL
  for (int i = 0; i < n; ++i) {
    for (int e = 0; e < extra_threads; ++e)
      for (int c = 0; c < 6; ++c) own[c][i] += extra[(static_cast<std::size_t>(e) * 6 + c) * stride + i];
  }
}

}  // namespace

void cohesive_contact_pass_half(const CohesivePairTable& table, const CohesiveOptions& opt, const BoxView& box,
                                Particles& p, const NeighborList& list, ContactHistory& history, double dt,
                                int update_history, ThreadForceBuffers& buffers) {
  if (list.kind() != NeighborKind::half) throw std::logic_error("cohesive_contact_pass_half needs a half list");
  const int n = list.rows();
  buffers.threads = exec::threads();
  buffers.n = n;
  buffers.data.resize(static_cast<std::size_t>(buffers.threads - 1) * 6 * static_cast<std::size_t>(n));
  const int key = (opt.adhesive ? 4 : 0) + (opt.tangential ? 2 : 0) + (update_history ? 1 : 0);
  switch (key) {
    case 7: run_pass<1, 1, 1>(table, box, p, list, history, dt, buffers); break;
    case 6: run_pass<1, 1, 0>(table, box, p, list, history, dt, buffers); break;
    case 5: run_pass<1, 0, 1>(table, box, p, list, history, dt, buffers); break;
    case 4: run_pass<1, 0, 0>(table, box, p, list, history, dt, buffers); break;
    case 3: run_pass<0, 1, 1>(table, box, p, list, history, dt, buffers); break;
    case 2: run_pass<0, 1, 0>(table, box, p, list, history, dt, buffers); break;
    case 1: run_pass<0, 0, 1>(table, box, p, list, history, dt, buffers); break;
    default: run_pass<0, 0, 0>(table, box, p, list, history, dt, buffers); break;
  }
}

}  // namespace debris
