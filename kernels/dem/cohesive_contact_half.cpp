#include "kernels/dem/cohesive_contact_half.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "core/contact_history.hpp"
#include "core/exec.hpp"
#include "core/neighbor_list.hpp"
#include "core/particles.hpp"
#include "core/resize_for_overwrite.hpp"

namespace debris {

namespace {

struct PairInputs {
  const int *row, *col;
  CohesiveCoefficients c;
  const double *x, *y, *z, *r, *vx, *vy, *vz, *wx, *wy, *wz;
  const CohesivePairTable *t;
  double *hx, *hy, *hz;
  BoxView box;
  double dt;
  CohesiveOptions opt;
  int update;
};

// Phase 1 results of at most kChunkPairs pairs: small enough to stay in L1 between the vector loop that
// writes them and the scalar sweep that hands them out.
constexpr int kChunkPairs = 256;
struct ChunkBuffer {
  alignas(64) double fx[kChunkPairs], fy[kChunkPairs], fz[kChunkPairs];
  alignas(64) double tix[kChunkPairs], tiy[kChunkPairs], tiz[kChunkPairs];
  alignas(64) double tjx[kChunkPairs], tjy[kChunkPairs], tjz[kChunkPairs];
};

// Phase 1 for pairs [k0, k1): eqs 2-5 (cohesive_pair_force) for each pair, its force and both torques
// into the chunk buffer. The evaluator is branch-free, so this loop vectorises. Compiled three times
// (x86-64, AVX2, AVX-512); the loader picks the best the machine runs, so the default build still runs
// anywhere.
DEBRIS_HOST_ONLY_CLONES void pair_chunk(const PairInputs &a, int k0, int k1, ChunkBuffer &o) {
  const int *__restrict row = a.row;
  const int *__restrict col = a.col;
  const double *__restrict x = a.x, *__restrict y = a.y, *__restrict z = a.z, *__restrict r = a.r;
  const double *__restrict vx = a.vx, *__restrict vy = a.vy, *__restrict vz = a.vz;
  const double *__restrict wx = a.wx, *__restrict wy = a.wy, *__restrict wz = a.wz;
  const double *__restrict df = a.t->delta_f.data();
  const double *__restrict cn = a.t->c_n.data();
  double *__restrict hx = a.hx, *__restrict hy = a.hy, *__restrict hz = a.hz;
  // Chunk-local results, slot q = k - k0.
  double *__restrict fx = o.fx, *__restrict fy = o.fy, *__restrict fz = o.fz;
  double *__restrict tix = o.tix, *__restrict tiy = o.tiy, *__restrict tiz = o.tiz;
  double *__restrict tjx = o.tjx, *__restrict tjy = o.tjy, *__restrict tjz = o.tjz;
  const double lx = a.box.len[0], ly = a.box.len[1], lz = a.box.len[2];
  const int px = a.box.periodic[0], py = a.box.periodic[1], pz = a.box.periodic[2];
  const CohesiveCoefficients c = a.c;
  const CohesiveOptions opt = a.opt;
  const double dt = a.dt;
  const int update = a.update;
  DEBRIS_HOST_VECTOR_LOOP
  for (int q = 0; q < k1 - k0; ++q) {
    const int k = k0 + q;
    const int i = row[k], j = col[k];
    const Vec3 dx{nearest_image(x[i] - x[j], lx, px), nearest_image(y[i] - y[j], ly, py),
                  nearest_image(z[i] - z[j], lz, pz)};
    // A half list keeps a pair in row min(i, j): i is the first particle.
    const CohesivePair pair{dx,
                            r[i],
                            r[j],
                            df[k],
                            cn[k],
                            Vec3{vx[i] - vx[j], vy[i] - vy[j], vz[i] - vz[j]},
                            Vec3{wx[i], wy[i], wz[i]},
                            Vec3{wx[j], wy[j], wz[j]},
                            Vec3{hx[k], hy[k], hz[k]},
                            1};
    const CohesivePairResult out = cohesive_pair_force(c, opt, pair, dt, update);
    hx[k] = out.history.x;
    hy[k] = out.history.y;
    hz[k] = out.history.z;
    fx[q] = out.force.x;
    fy[q] = out.force.y;
    fz[q] = out.force.z;
    tix[q] = out.torque.x;
    tiy[q] = out.torque.y;
    tiz[q] = out.torque.z;
    tjx[q] = out.torque_j.x;
    tjy[q] = out.torque_j.y;
    tjz[q] = out.torque_j.z;
  }
}

// A row's own shares (force and torque on i), summed in increasing k.
struct RowSum {
  double fx = 0, fy = 0, fz = 0, tx = 0, ty = 0, tz = 0;
};

// Pairs [k_begin, k_end), whole rows, in chunks of kChunkPairs (pair_chunk is the vector loop): each row's
// own shares are summed in increasing k, carried across chunks, and handed to row_done(i, sum) when the row
// ends; each pair's partner share is handed to partner(k, q) while it is in the chunk buffer c (slot q).
// Both paths of the pass walk their pairs with it and differ only in what they do with the two shares.
template <class RowDone, class Partner>
inline void sweep_rows(const PairInputs &in, int k_begin, int k_end, ChunkBuffer &c, RowDone &&row_done,
                       Partner &&partner) {
  const int *__restrict row = in.row;
  int cur = -1;
  RowSum sum;
  for (int k0 = k_begin; k0 < k_end; k0 += kChunkPairs) {
    const int k1 = std::min(k_end, k0 + kChunkPairs);
    pair_chunk(in, k0, k1, c);
    for (int k = k0; k < k1; ++k) {
      const int q = k - k0, i = row[k];
      if (i != cur) {
        if (cur >= 0) row_done(cur, sum);
        cur = i;
        sum = RowSum{};
      }
      sum.fx += c.fx[q];
      sum.fy += c.fy[q];
      sum.fz += c.fz[q];
      sum.tx += c.tix[q];
      sum.ty += c.tiy[q];
      sum.tz += c.tiz[q];
      partner(k, q);
    }
  }
  if (cur >= 0) row_done(cur, sum);
}

}  // namespace

void HalfPassScratch::index(const NeighborList &list) {
  const int n = list.rows(), m = list.entries();
  const int *offset = list.offset().data();
  resize_for_overwrite(row_of, static_cast<std::size_t>(m));
  for (int i = 0; i < n; ++i)
    for (int k = offset[i]; k < offset[i + 1]; ++k) row_of[static_cast<std::size_t>(k)] = i;
  // Row blocks of about kBlockPairs pairs, whole rows each, so a row's own sum is made by one thread.
  block_row.assign(1, 0);
  for (int i = 0; i < n; ++i)
    if (offset[i + 1] - offset[block_row.back()] >= kBlockPairs) block_row.push_back(i + 1);
  if (block_row.back() != n) block_row.push_back(n);
  // The shares' index and buffer only where more than one thread sums: one thread adds each partner share
  // on the spot, and the buffer (6 doubles per pair, 315 of 904 B per particle at N = 32,000) would be
  // memory it never touches. A step on more threads builds them if the count rose since (index_shares).
  if (exec::threads() > 1) {
    index_shares(list);
  } else {
    for (std::vector<int> *v : {&in_offset, &in_entry}) std::vector<int>().swap(*v);
    std::vector<double>().swap(partner);
    shares_indexed = false;
  }
}

void HalfPassScratch::index_shares(const NeighborList &list) {
  const int n = list.rows(), m = list.entries();
  const int *col = list.index().data();
  // Counting sort of the pairs by partner; the pairs of one partner keep increasing k.
  in_offset.assign(static_cast<std::size_t>(n) + 1, 0);
  for (int k = 0; k < m; ++k) ++in_offset[static_cast<std::size_t>(col[k]) + 1];
  for (int j = 0; j < n; ++j) in_offset[static_cast<std::size_t>(j) + 1] += in_offset[static_cast<std::size_t>(j)];
  resize_for_overwrite(in_entry, static_cast<std::size_t>(m));
  std::vector<int> fill(in_offset.begin(), in_offset.end() - 1);
  for (int k = 0; k < m; ++k) in_entry[static_cast<std::size_t>(fill[static_cast<std::size_t>(col[k])]++)] = k;
  resize_for_overwrite(partner, static_cast<std::size_t>(kShareStride) * static_cast<std::size_t>(m));
  shares_indexed = true;
}

std::size_t HalfPassScratch::bytes() const {
  return sizeof(int) * (row_of.capacity() + in_offset.capacity() + in_entry.capacity() + block_row.capacity()) +
         sizeof(double) * partner.capacity();
}

void cohesive_contact_pass_half(const CohesivePairTable &table, const CohesiveOptions &opt, const BoxView &box,
                                Particles &p, const NeighborList &list, ContactHistory &history, double dt,
                                int update_history, HalfPassScratch &s) {
  if (list.kind() != NeighborKind::half) throw std::logic_error("cohesive_contact_pass_half needs a half list");
  if (s.row_of.size() != static_cast<std::size_t>(list.entries()))
    throw std::logic_error("cohesive_contact_pass_half: scratch not indexed for this list");
  const int n = list.rows();
  const PairInputs in{s.row_of.data(),
                      list.index().data(),
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
                      box,
                      dt,
                      opt,
                      update_history};

  constexpr int kShareStride = HalfPassScratch::kShareStride;
  const int blocks = static_cast<int>(s.block_row.size()) - 1;
  const int *__restrict block_row = s.block_row.data();
  const int *__restrict offset = list.offset().data();
  double *__restrict fx = p.fx.data(), *__restrict fy = p.fy.data(), *__restrict fz = p.fz.data();
  double *__restrict tx = p.tx.data(), *__restrict ty = p.ty.data(), *__restrict tz = p.tz.data();
  // Each particle's force (and torque) is R + P: R its row's own shares summed in increasing k, P the
  // shares of the pairs where it is the partner, summed from zero in increasing k (all of them come from
  // rows before its own: a half list keeps a pair in row min(i, j)). Both paths below make exactly these
  // sums, so 1 and 2 threads give the same bits.
  if (exec::threads() == 1) {
    // One thread: the rows in order, each pair's partner share added on the spot to f[j], which holds P_j
    // until row j adds R_j. No shares filed and read back: on a memory-bound machine that traffic (6
    // doubles written and read per pair, with the transposed index) was the largest part of the step's.
    std::fill(fx, fx + n, 0.0), std::fill(fy, fy + n, 0.0), std::fill(fz, fz + n, 0.0);
    std::fill(tx, tx + n, 0.0), std::fill(ty, ty + n, 0.0), std::fill(tz, tz + n, 0.0);
    const int *__restrict col = list.index().data();
    ChunkBuffer c;
    sweep_rows(
        in, 0, list.entries(), c,
        [&](int i, const RowSum &r) {  // the finished row: R + P
          fx[i] = r.fx + fx[i];
          fy[i] = r.fy + fy[i];
          fz[i] = r.fz + fz[i];
          tx[i] = r.tx + tx[i];
          ty[i] = r.ty + ty[i];
          tz[i] = r.tz + tz[i];
        },
        [&](int k, int q) {  // P_j, in increasing k
          const int j = col[k];
          fx[j] -= c.fx[q];
          fy[j] -= c.fy[q];
          fz[j] -= c.fz[q];
          tx[j] += c.tjx[q];
          ty[j] += c.tjy[q];
          tz[j] += c.tjz[q];
        });
    return;
  }

  // Two or more threads (host threads only: this is the host pass; offload builds use the full-list pass):
  // rows in blocks, one per thread at a time, partner shares filed at the pair's index and gathered per
  // particle afterwards; both phases in one parallel region, the loop barrier between them.
  if (!s.shares_indexed) s.index_shares(list);  // the thread count rose since the list was built
  const int *__restrict in_entry = s.in_entry.data();
  const int *__restrict in_offset = s.in_offset.data();
  double *__restrict partner = s.partner.data();
  DEBRIS_HOST_PARALLEL {
    ChunkBuffer c;  // per thread, on its stack
    // Phase 1: blocks of whole rows; each in chunks (the chunk loop is the vector loop), after which the
    // row's own share is summed on the spot (in increasing k, carried across chunks) and the partner's
    // share is filed at the pair's index.
    DEBRIS_HOST_FOR
    for (int b = 0; b < blocks; ++b) {
      // The block's rows start from zero here, not in a sweep of their own (this thread owns them; phase 2
      // reads them only after the loop barrier).
      for (int i = block_row[b]; i < block_row[b + 1]; ++i) fx[i] = fy[i] = fz[i] = tx[i] = ty[i] = tz[i] = 0.0;
      sweep_rows(
          in, offset[block_row[b]], offset[block_row[b + 1]], c,
          [&](int i, const RowSum &r) {  // the finished row's own share: R = 0 + the sum
            fx[i] += r.fx;
            fy[i] += r.fy;
            fz[i] += r.fz;
            tx[i] += r.tx;
            ty[i] += r.ty;
            tz[i] += r.tz;
          },
          [&](int k, int q) {  // filed at the pair's index for phase 2
            double *share_k = partner + static_cast<std::ptrdiff_t>(kShareStride) * k;
            share_k[0] = c.fx[q];
            share_k[1] = c.fy[q];
            share_k[2] = c.fz[q];
            share_k[3] = c.tjx[q];
            share_k[4] = c.tjy[q];
            share_k[5] = c.tjz[q];
          });
    }

    // Phase 2: each particle sums the shares filed for it (pairs where it is the partner, in increasing k,
    // from zero) and adds them to its own row's sum.
    DEBRIS_HOST_FOR
    for (int i = 0; i < n; ++i) {
      double sfx = 0, sfy = 0, sfz = 0, stx = 0, sty = 0, stz = 0;
      for (int e = in_offset[i]; e < in_offset[i + 1]; ++e) {
        const double *share_e = partner + static_cast<std::ptrdiff_t>(kShareStride) * in_entry[e];
        sfx -= share_e[0];
        sfy -= share_e[1];
        sfz -= share_e[2];
        stx += share_e[3];
        sty += share_e[4];
        stz += share_e[5];
      }
      fx[i] = fx[i] + sfx;
      fy[i] = fy[i] + sfy;
      fz[i] = fz[i] + sfz;
      tx[i] = tx[i] + stx;
      ty[i] = ty[i] + sty;
      tz[i] = tz[i] + stz;
    }
  }
}

}  // namespace debris
