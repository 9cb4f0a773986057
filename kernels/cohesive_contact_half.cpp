#include "kernels/cohesive_contact_half.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "core/contact_history.hpp"
#include "core/exec.hpp"
#include "core/neighbor_list.hpp"
#include "core/particles.hpp"

namespace debris {

namespace {

struct PairInputs {
  const int *row, *col;
  const double *mass;
  CohesiveCoefficients c;
  const double *x, *y, *z, *r, *vx, *vy, *vz, *wx, *wy, *wz;
  const CohesivePairTable *t;
  double *hx, *hy, *hz;
  HalfPassScratch *out;
  BoxView box;
  double dt;
  int adhesive, tangential, update;
};

// Phase 1 for pairs [k0, k1): eqs 2-5 exactly as in cohesive_pair_force(), made
// branch-free (selects instead of early returns) so that the loop vectorises.
// Compiled three times (x86-64, AVX2, AVX-512); the loader picks the best the
// machine runs, so the default build still runs anywhere.
__attribute__((target_clones("default", "arch=x86-64-v3", "arch=x86-64-v4"))) void pair_chunk(const PairInputs &a,
                                                                                              int k0, int k1) {
  const int *__restrict row = a.row;
  const int *__restrict col = a.col;
  const double *__restrict x = a.x, *__restrict y = a.y, *__restrict z = a.z, *__restrict r = a.r;
  const double *__restrict vx = a.vx, *__restrict vy = a.vy, *__restrict vz = a.vz;
  const double *__restrict wx = a.wx, *__restrict wy = a.wy, *__restrict wz = a.wz;
  const CohesivePairTable &t = *a.t;
  const double *__restrict df = t.delta_f.data();
  const double *__restrict mass = a.mass;
  const double E_an = a.c.E * a.c.area_n, area_t = a.c.area_t, strain_e = a.c.strain_e;
  const double sigma_t = a.c.sigma_t, damping = a.c.damping;
  double *__restrict hx = a.hx, *__restrict hy = a.hy, *__restrict hz = a.hz;
  HalfPassScratch &o = *a.out;
  double *__restrict fx = o.fx.data(), *__restrict fy = o.fy.data(), *__restrict fz = o.fz.data();
  double *__restrict tix = o.tix.data(), *__restrict tiy = o.tiy.data(), *__restrict tiz = o.tiz.data();
  double *__restrict tjx = o.tjx.data(), *__restrict tjy = o.tjy.data(), *__restrict tjz = o.tjz.data();
  const double lx = a.box.len[0], ly = a.box.len[1], lz = a.box.len[2];
  const int px = a.box.periodic[0], py = a.box.periodic[1], pz = a.box.periodic[2];
  const double dt = a.dt, kt_over_kn = t.kt_over_kn, ct_over_cn = t.ct_over_cn;
  const int adhesive = a.adhesive, update = a.update;
  const double tangential = a.tangential ? 1.0 : 0.0;
  DEBRIS_SIMD
  for (int k = k0; k < k1; ++k) {
    const int i = row[k], j = col[k];
    const double dx = nearest_image(x[i] - x[j], lx, px);
    const double dy = nearest_image(y[i] - y[j], ly, py);
    const double dz = nearest_image(z[i] - z[j], lz, pz);
    const double d = std::sqrt(dx * dx + dy * dy + dz * dz);
    const double inv_d = 1.0 / d;
    const double nx = dx * inv_d, ny = dy * inv_d, nz = dz * inv_d;
    const double ri = r[i], rj = r[j], radsum = ri + rj, inv_rs = 1.0 / radsum;
    const double dn = d - radsum;
    // Eqs 7-17 for this pair (only delta_f, which may need pow, comes from the table).
    const double r_eff = ri < rj ? ri : rj, r2 = r_eff * r_eff;
    const double kn_k = E_an * r2 * inv_rs;
    const double de_k = radsum * strain_e;
    const double df_k = df[k];
    const double ks_k = df_k > de_k ? kn_k * de_k / (df_k - de_k) : 0.0;
    const double fmt_k = area_t * r2 * sigma_t;
    const double mi = mass[i], mj = mass[j];
    const double cn_k = damping * std::sqrt(kn_k * (mi * mj / (mi + mj)));
    const bool on = dn <= (adhesive ? df_k : 0.0);

    // Eq 3 (positive in tension) and the normal part of eq 2.
    const double f_n = (adhesive && dn > de_k) ? ks_k * (df_k - dn) : kn_k * dn;
    const double rvx = vx[i] - vx[j], rvy = vy[i] - vy[j], rvz = vz[i] - vz[j];
    const double v_n = rvx * nx + rvy * ny + rvz * nz;
    const double fnorm = on ? -(f_n + cn_k * v_n) : 0.0;

    // Contact point velocity (arms a_i + a_j = d), tangential part.
    const double a_i = d * ri * inv_rs, a_j = d - a_i;
    const double sx = a_i * wx[i] + a_j * wx[j], sy = a_i * wy[i] + a_j * wy[j], sz = a_i * wz[i] + a_j * wz[j];
    const double vcx = rvx - (sy * nz - sz * ny), vcy = rvy - (sz * nx - sx * nz), vcz = rvz - (sx * ny - sy * nx);
    const double vcn = vcx * nx + vcy * ny + vcz * nz;
    const double vtx = vcx - vcn * nx, vty = vcy - vcn * ny, vtz = vcz - vcn * nz;

    // History: rotated into the tangent plane keeping its length, advanced
    // (when updating), capped (eqs 4-5).
    const double h0x = hx[k], h0y = hy[k], h0z = hz[k];
    const double h2 = h0x * h0x + h0y * h0y + h0z * h0z, hn = h0x * nx + h0y * ny + h0z * nz;
    const double hpx = h0x - hn * nx, hpy = h0y - hn * ny, hpz = h0z - hn * nz;
    const double hp2 = hpx * hpx + hpy * hpy + hpz * hpz;
    const double keep = hp2 > 0.0 ? std::sqrt(h2 / (hp2 > 0.0 ? hp2 : 1.0)) : 1.0;
    const double h_x = update ? keep * hpx + dt * vtx : h0x;
    const double h_y = update ? keep * hpy + dt * vty : h0y;
    const double h_z = update ? keep * hpz + dt * vtz : h0z;
    const double k_t = kt_over_kn * kn_k;
    const double share = (df_k - dn) / df_k;
    const double cap = (share < 1.0 ? share : 1.0) * fmt_k;
    const double spring = k_t * std::sqrt(h_x * h_x + h_y * h_y + h_z * h_z);
    const double slide = spring > cap ? cap / (spring > 0.0 ? spring : 1.0) : 1.0;
    const double live = on ? tangential : 0.0;
    const double kts = -live * k_t * slide, cts = -live * ct_over_cn * cn_k;
    const double ftx = kts * h_x + cts * vtx, fty = kts * h_y + cts * vty, ftz = kts * h_z + cts * vtz;
    // Slid back to the cap when updating; gone when out of range or without
    // tangential force.
    const double stays = live * (update ? slide : 1.0);
    hx[k] = stays * h_x;
    hy[k] = stays * h_y;
    hz[k] = stays * h_z;

    fx[k] = fnorm * nx + ftx;
    fy[k] = fnorm * ny + fty;
    fz[k] = fnorm * nz + ftz;
    // Torques -a n x F_t on both particles (n points from j to i; j sees -n and
    // -F_t).
    const double cx = ny * ftz - nz * fty, cy = nz * ftx - nx * ftz, cz = nx * fty - ny * ftx;
    tix[k] = -a_i * cx;
    tiy[k] = -a_i * cy;
    tiz[k] = -a_i * cz;
    tjx[k] = -a_j * cx;
    tjy[k] = -a_j * cy;
    tjz[k] = -a_j * cz;
  }
}

}  // namespace

void HalfPassScratch::index(const NeighborList &list) {
  const int n = list.rows(), m = list.entries();
  const int *offset = list.offset().data();
  const int *col = list.index().data();
  row_of.resize(static_cast<std::size_t>(m));
  for (int i = 0; i < n; ++i)
    for (int k = offset[i]; k < offset[i + 1]; ++k) row_of[static_cast<std::size_t>(k)] = i;
  // Counting sort of the pairs by partner; pairs of one partner stay in
  // increasing k.
  in_offset.assign(static_cast<std::size_t>(n) + 1, 0);
  for (int k = 0; k < m; ++k) ++in_offset[static_cast<std::size_t>(col[k]) + 1];
  for (int j = 0; j < n; ++j) in_offset[static_cast<std::size_t>(j) + 1] += in_offset[static_cast<std::size_t>(j)];
  in_entry.resize(static_cast<std::size_t>(m));
  std::vector<int> fill(in_offset.begin(), in_offset.end() - 1);
  for (int k = 0; k < m; ++k) in_entry[static_cast<std::size_t>(fill[static_cast<std::size_t>(col[k])]++)] = k;
  for (auto *v : {&fx, &fy, &fz, &tix, &tiy, &tiz, &tjx, &tjy, &tjz}) v->resize(static_cast<std::size_t>(m));
}

std::size_t HalfPassScratch::bytes() const {
  return sizeof(int) * (row_of.capacity() + in_offset.capacity() + in_entry.capacity()) +
         9 * sizeof(double) * fx.capacity();
}

void cohesive_contact_pass_half(const CohesivePairTable &table, const CohesiveOptions &opt, const BoxView &box,
                                Particles &p, const NeighborList &list, ContactHistory &history, double dt,
                                int update_history, HalfPassScratch &s) {
  if (list.kind() != NeighborKind::half) throw std::logic_error("cohesive_contact_pass_half needs a half list");
  if (s.row_of.size() != static_cast<std::size_t>(list.entries()))
    throw std::logic_error("cohesive_contact_pass_half: scratch not indexed for this list");
  const int n = list.rows(), m = list.entries();
  const PairInputs in{s.row_of.data(),
                      list.index().data(),
                      p.mass.data(),
                      table.coefficients,
                      p.x.data(),
                      p.y.data(),
                      p.z.data(),
                      p.radius.data(),
                      p.vx.data(),
                      p.vy.data(),
                      p.vz.data(),
                      p.wx.data(),
                      p.wy.data(),
                      p.wz.data(),
                      &table,
                      history.hx.data(),
                      history.hy.data(),
                      history.hz.data(),
                      &s,
                      box,
                      dt,
                      opt.adhesive,
                      opt.tangential,
                      update_history};

  constexpr int chunk = 512;
  const int chunks = (m + chunk - 1) / chunk;
  const int *__restrict offset = list.offset().data();
  const int *__restrict in_offset = s.in_offset.data();
  const int *__restrict in_entry = s.in_entry.data();
  const double *__restrict Fx = s.fx.data(), *__restrict Fy = s.fy.data(), *__restrict Fz = s.fz.data();
  const double *__restrict Tix = s.tix.data(), *__restrict Tiy = s.tiy.data(), *__restrict Tiz = s.tiz.data();
  const double *__restrict Tjx = s.tjx.data(), *__restrict Tjy = s.tjy.data(), *__restrict Tjz = s.tjz.data();
  double *__restrict fx = p.fx.data(), *__restrict fy = p.fy.data(), *__restrict fz = p.fz.data();
  double *__restrict tx = p.tx.data(), *__restrict ty = p.ty.data(), *__restrict tz = p.tz.data();
  // Host threads only (this is the host pass; offload builds use the full-list
  // pass): both phases in one parallel region, the loop barrier between them.
  DEBRIS_HOST_PARALLEL {
    // Phase 1: pairs in chunks (one call per chunk; the chunk loop is the
    // vector loop).
    DEBRIS_HOST_FOR
    for (int c = 0; c < chunks; ++c) pair_chunk(in, c * chunk, std::min(m, (c + 1) * chunk));

    // Phase 2: each particle gathers its pairs, own first, then as a partner,
    // in increasing pair order.
    DEBRIS_HOST_FOR
    for (int i = 0; i < n; ++i) {
      double sfx = 0, sfy = 0, sfz = 0, stx = 0, sty = 0, stz = 0;
      for (int k = offset[i]; k < offset[i + 1]; ++k) {
        sfx += Fx[k];
        sfy += Fy[k];
        sfz += Fz[k];
        stx += Tix[k];
        sty += Tiy[k];
        stz += Tiz[k];
      }
      for (int e = in_offset[i]; e < in_offset[i + 1]; ++e) {
        const int k = in_entry[e];
        sfx -= Fx[k];
        sfy -= Fy[k];
        sfz -= Fz[k];
        stx += Tjx[k];
        sty += Tjy[k];
        stz += Tjz[k];
      }
      fx[i] += sfx;
      fy[i] += sfy;
      fz[i] += sfz;
      tx[i] += stx;
      ty[i] += sty;
      tz[i] += stz;
    }
  }
}

}  // namespace debris
