#include "kernels/dem/cohesive_contact_half.hpp"

#include <algorithm>
#include <array>
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
  const int *offset, *col;
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
// writes them and the scalar sweep that hands them out. E: the energy parts each pair also gives (0, or
// kPairEnergyColumns with the accounting on, and the partner's in ej).
constexpr int kChunkPairs = 256;
constexpr int kRowRun = 8;
// With the energy parts a chunk holds 25 doubles per pair instead of 9: half as many pairs keep it in L1.
template <int E>
constexpr int chunk_pairs = E > 0 ? kChunkPairs / 2 : kChunkPairs;
constexpr int kE = kPairEnergyColumns;  // a particle's energy parts are contiguous: a partner's in one place
// A pair's energy parts, pair-major (one 128-byte record per pair), so the scalar sweep adds each record to a
// particle's contiguous parts in a few vector operations: i's kE parts, then the partner's own damping torque.
// The partner's other parts follow from i's: the damping forces negated, the same energies.
constexpr int kRecord = 16;
constexpr int kTorqueJ = kE;  // record slots kE .. kE + 2
static_assert(kE + 3 <= kRecord);
template <int E>
struct ChunkBuffer {
  static constexpr int P = chunk_pairs<E>;
  static constexpr int R = E > 0 ? P : 1;
  alignas(64) int row[P + kRowRun];  // i of each pair, from the list's offsets (no column kept)
  alignas(64) double fx[P], fy[P], fz[P];
  alignas(64) double tix[P], tiy[P], tiz[P];
  alignas(64) double tjx[P], tjy[P], tjz[P];
  alignas(64) double e[R][kRecord];
};

// The partner's parts of slot q's record: -damping forces, its damping torque, the same four energies.
template <int E>
inline void partner_parts(const ChunkBuffer<E> &c, int q, double *__restrict out) {
  const double *__restrict rec = c.e[q];
  for (int m = kDampNx; m <= kDampTz; ++m) out[m] = -rec[m];
  for (int m = 0; m < 3; ++m) out[kDampTorqueX + m] = rec[kTorqueJ + m];
  for (int m = kPairDissNormal; m < kE; ++m) out[m] = rec[m];
}
template <int E>
inline void add_partner_parts(const ChunkBuffer<E> &c, int q, double *__restrict dst) {
  const double *__restrict rec = c.e[q];
  for (int m = kDampNx; m <= kDampTz; ++m) dst[m] -= rec[m];
  for (int m = 0; m < 3; ++m) dst[kDampTorqueX + m] += rec[kTorqueJ + m];
  for (int m = kPairDissNormal; m < kE; ++m) dst[m] += rec[m];
}

// Phase 1 for pairs [k0, k1): eqs 2-5 (cohesive_pair_force) for each pair, its force and both torques
// into the chunk buffer. The evaluator is branch-free, so this loop vectorises. Compiled three times
// (x86-64, AVX2, AVX-512) in each of the two functions below; the loader picks the best the machine runs,
// so the default build still runs anywhere.
template <int E>
DEBRIS_ALWAYS_INLINE void pair_chunk_body(const PairInputs &a, int k0, int k1, ChunkBuffer<E> &o) {
  const int *__restrict row = o.row;
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
    const int i = row[q], j = col[k];
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
    if constexpr (E > 0) {
      double *__restrict rec = o.e[q];
      rec[kDampNx] = out.damping_n.x;
      rec[kDampNy] = out.damping_n.y;
      rec[kDampNz] = out.damping_n.z;
      rec[kDampTx] = out.damping_t.x;
      rec[kDampTy] = out.damping_t.y;
      rec[kDampTz] = out.damping_t.z;
      rec[kDampTorqueX] = out.damping_torque.x;
      rec[kDampTorqueY] = out.damping_torque.y;
      rec[kDampTorqueZ] = out.damping_torque.z;
      rec[kPairDissNormal] = out.dissipated_normal;
      rec[kPairDissTangential] = out.dissipated_tangential;
      rec[kPairDissSliding] = out.dissipated_sliding;
      rec[kPairTangentialWork] = out.tangential_work;
      rec[kTorqueJ] = out.damping_torque_j.x;
      rec[kTorqueJ + 1] = out.damping_torque_j.y;
      rec[kTorqueJ + 2] = out.damping_torque_j.z;
    }
  }
}

// The clones are of plain functions (clang multiversions no function template), one per E.
DEBRIS_HOST_ONLY_CLONES void pair_chunk_plain(const PairInputs &a, int k0, int k1, ChunkBuffer<0> &o) {
  pair_chunk_body<0>(a, k0, k1, o);
}
DEBRIS_HOST_ONLY_CLONES void pair_chunk_energy(const PairInputs &a, int k0, int k1, ChunkBuffer<kE> &o) {
  pair_chunk_body<kE>(a, k0, k1, o);
}
template <int E>
inline void pair_chunk(const PairInputs &a, int k0, int k1, ChunkBuffer<E> &o) {
  if constexpr (E > 0) pair_chunk_energy(a, k0, k1, o);
  else pair_chunk_plain(a, k0, k1, o);
}

// A row's own shares (force and torque on i), summed in increasing k.
template <int E>
struct RowSum {
  double fx = 0, fy = 0, fz = 0, tx = 0, ty = 0, tz = 0;
  std::array<double, E> e{};
};

// Rows [row_begin, row_end), their pairs in chunks of kChunkPairs (pair_chunk is the vector loop): each
// row's own shares are summed in increasing k, carried across chunks, and handed to row_done(i, sum) when the
// row ends; each pair's partner share is handed to partner(k, q) while it is in the chunk buffer c (slot q).
// Both paths of the pass walk their pairs with it and differ only in what they do with the two shares.
template <int E, class RowDone, class Partner>
inline void sweep_rows(const PairInputs &in, int row_begin, int row_end, ChunkBuffer<E> &c, RowDone &&row_done,
                       Partner &&partner) {
  const int *__restrict offset = in.offset;
  const int k_end = offset[row_end];
  int cur = -1, next_row = row_begin;
  RowSum<E> sum;
  for (int k0 = offset[row_begin]; k0 < k_end; k0 += chunk_pairs<E>) {
    const int k1 = std::min(k_end, k0 + chunk_pairs<E>);
    // The chunk's row indices (a row may span chunks): 4 bytes per pair in L1 instead of a column in memory.
    // Each row writes kRowRun slots at once (a later row overwrites the excess; the buffer has room past its
    // end), so rows of up to kRowRun pairs, nearly all of them, cost one store and no data-dependent loop.
    int i = next_row;
    while (offset[i + 1] <= k0) ++i;
    for (int k = k0; k < k1; ++i) {
      const int stop = std::min(offset[i + 1], k1);
      for (int at = k - k0; at < stop - k0; at += kRowRun)
        for (int v = 0; v < kRowRun; ++v) c.row[at + v] = i;
      k = stop;
    }
    next_row = i - 1;
    pair_chunk<E>(in, k0, k1, c);
    for (int k = k0; k < k1; ++k) {
      const int q = k - k0, i = c.row[q];
      if (i != cur) {
        if (cur >= 0) row_done(cur, sum);
        cur = i;
        sum = RowSum<E>{};
      }
      sum.fx += c.fx[q];
      sum.fy += c.fy[q];
      sum.fz += c.fz[q];
      sum.tx += c.tix[q];
      sum.ty += c.tiy[q];
      sum.tz += c.tiz[q];
      for (int m = 0; m < E; ++m) sum.e[static_cast<std::size_t>(m)] += c.e[q][m];
      partner(k, q);
    }
  }
  if (cur >= 0) row_done(cur, sum);
}

}  // namespace

void HalfPassScratch::index(const NeighborList &list) {
  entries = list.entries();
  partition(list, exec::threads());
}

void HalfPassScratch::partition(const NeighborList &list, int count) {
  const int n = list.rows();
  const int *offset = list.offset().data();
  const int *col = list.index().data();
  parts = std::max(1, count);
  // The rows of each part that hold a pair with a partner in a later part: particles are stored in cell
  // order, so these are a slab about one cutoff thick before the part's end, and, where the box is periodic
  // along the slowest axis of the order, the first layer (whose partners across the face are the last).
  std::vector<char> tail(static_cast<std::size_t>(n));
  auto find_tails = [&] {
    for (int t = 0; t < parts; ++t) {
      const int begin = part_row[static_cast<std::size_t>(t)], end = part_row[static_cast<std::size_t>(t) + 1];
      for (int i = begin; i < end; ++i) {
        char crosses = 0;
        for (int k = offset[i]; k < offset[i + 1]; ++k) crosses |= col[k] >= end ? 1 : 0;
        tail[static_cast<std::size_t>(i)] = crosses;
      }
    }
  };
  // Parts of contiguous rows of about equal work: first equal pairs; then a part's own sweep costs a pair for
  // each pair it sweeps on the spot and about a quarter of one for each tail pair whose kept shares it adds
  // (the tails themselves are swept before, shared equally among the threads). A part's tail is a thin slab
  // that moves with its end, so two more rounds settle the ends.
  part_row.assign(static_cast<std::size_t>(parts) + 1, n);
  part_row[0] = 0;
  std::vector<double> work(static_cast<std::size_t>(n) + 1, 0.0);
  for (int round = 0; round < (parts > 1 ? 3 : 1); ++round) {  // one part: nothing to move
    for (int i = 0; i < n; ++i) {
      const double pairs = offset[i + 1] - offset[i];
      const bool kept = round > 0 && tail[static_cast<std::size_t>(i)];
      work[static_cast<std::size_t>(i) + 1] = work[static_cast<std::size_t>(i)] + (kept ? 0.25 * pairs : pairs);
    }
    for (int t = 1; t < parts; ++t) {
      const double target = work[static_cast<std::size_t>(n)] * t / parts;
      const auto at = std::lower_bound(work.begin(), work.end(), target) - work.begin();
      part_row[static_cast<std::size_t>(t)] =
          std::max(part_row[static_cast<std::size_t>(t) - 1], static_cast<int>(std::min<std::ptrdiff_t>(at, n)));
    }
    find_tails();
  }
  // Runs of tail rows (gaps of a few rows closed: fewer, longer runs sweep faster, and a row kept that did
  // not need to be is only a row whose shares are added later, in the same order).
  constexpr int kGapRows = 8;
  run_begin.clear(), run_end.clear(), run_pair.assign(1, 0), run_sum.assign(1, 0);
  part_run.assign(1, 0);
  for (int t = 0; t < parts; ++t) {
    const int begin = part_row[static_cast<std::size_t>(t)], end = part_row[static_cast<std::size_t>(t) + 1];
    for (int i = begin; i < end; ++i) {
      if (!tail[static_cast<std::size_t>(i)]) continue;
      if (static_cast<int>(run_begin.size()) > part_run.back() && i - run_end.back() <= kGapRows) {
        run_end.back() = i + 1;
      } else {
        run_begin.push_back(i);
        run_end.push_back(i + 1);
      }
    }
    part_run.push_back(static_cast<int>(run_begin.size()));
  }
  for (std::size_t r = 0; r < run_begin.size(); ++r) {
    run_pair.push_back(run_pair.back() + offset[run_end[r]] - offset[run_begin[r]]);
    run_sum.push_back(run_sum.back() + run_end[r] - run_begin[r]);
  }
  // The tails' sweep, in units of whole rows and at most kUnitPairs pairs, shared equally among the threads.
  unit_run.clear(), unit_begin.clear(), unit_end.clear();
  thread_unit.assign(1, 0);  // thread t sweeps units thread_unit[t] .. thread_unit[t+1]
  for (std::size_t r = 0; r < run_begin.size(); ++r)
    for (int i = run_begin[r]; i < run_end[r];) {
      int e = i + 1;
      while (e < run_end[r] && offset[e + 1] - offset[i] <= kUnitPairs) ++e;
      const int before = run_pair[r] + offset[i] - offset[run_begin[r]];  // tail pairs in the units before
      while (static_cast<int>(thread_unit.size()) < parts &&
             before >= static_cast<long long>(run_pair.back()) * static_cast<long long>(thread_unit.size()) / parts)
        thread_unit.push_back(static_cast<int>(unit_run.size()));
      unit_run.push_back(static_cast<int>(r));
      unit_begin.push_back(i);
      unit_end.push_back(e);
      i = e;
    }
  while (static_cast<int>(thread_unit.size()) <= parts) thread_unit.push_back(static_cast<int>(unit_run.size()));
  // Where the tails hold many of the pairs (a small system, or one periodic along the order's slowest axis:
  // the first layer's partners across the face are in the last part), every share is filed instead.
  const double tail_fraction = offset[n] > 0 ? static_cast<double>(run_pair.back()) / offset[n] : 0.0;
  file_all =
      parts > 1 && (path == HalfPassPath::automatic ? tail_fraction > kMostTailPairs : path == HalfPassPath::filed);
  if (file_all) {
    index_filed(list);
    for (std::vector<int> *v : {&run_begin, &run_end, &run_pair, &run_sum, &unit_run, &unit_begin, &unit_end})
      v->assign(v == &run_pair || v == &run_sum ? 1 : 0, 0);
    std::fill(part_run.begin(), part_run.end(), 0);
    std::fill(thread_unit.begin(), thread_unit.end(), 0);
    std::vector<double>().swap(tail_share), std::vector<double>().swap(tail_sum);
    return;
  }
  for (std::vector<int> *v : {&in_offset, &in_entry, &block_row}) std::vector<int>().swap(*v);
  std::vector<double>().swap(filed);
  resize_for_overwrite(tail_share, static_cast<std::size_t>(stride()) * static_cast<std::size_t>(run_pair.back()));
  resize_for_overwrite(tail_sum, static_cast<std::size_t>(stride()) * static_cast<std::size_t>(run_sum.back()));
}

void HalfPassScratch::index_filed(const NeighborList &list) {
  const int n = list.rows(), m = list.entries();
  const int *offset = list.offset().data();
  const int *col = list.index().data();
  // Row blocks of about kBlockPairs pairs, whole rows each, so a row's own sum is made by one thread.
  block_row.assign(1, 0);
  for (int i = 0; i < n; ++i)
    if (offset[i + 1] - offset[block_row.back()] >= kBlockPairs) block_row.push_back(i + 1);
  if (block_row.back() != n) block_row.push_back(n);
  // Counting sort of the pairs by partner; the pairs of one partner keep increasing k.
  in_offset.assign(static_cast<std::size_t>(n) + 1, 0);
  for (int k = 0; k < m; ++k) ++in_offset[static_cast<std::size_t>(col[k]) + 1];
  for (int j = 0; j < n; ++j) in_offset[static_cast<std::size_t>(j) + 1] += in_offset[static_cast<std::size_t>(j)];
  resize_for_overwrite(in_entry, static_cast<std::size_t>(m));
  std::vector<int> fill(in_offset.begin(), in_offset.end() - 1);
  for (int k = 0; k < m; ++k) in_entry[static_cast<std::size_t>(fill[static_cast<std::size_t>(col[k])]++)] = k;
  resize_for_overwrite(filed, static_cast<std::size_t>(stride()) * static_cast<std::size_t>(m));
}

int HalfPassScratch::stride() const { return kShareStride + (energy ? kPairEnergyColumns : 0); }

std::size_t HalfPassScratch::bytes() const {
  std::size_t ints = part_row.capacity() + part_run.capacity() + thread_unit.capacity();
  for (const std::vector<int> *v : {&run_begin, &run_end, &run_pair, &run_sum, &unit_run, &unit_begin, &unit_end})
    ints += v->capacity();
  ints += block_row.capacity() + in_offset.capacity() + in_entry.capacity();
  return sizeof(int) * ints + sizeof(double) * (tail_share.capacity() + tail_sum.capacity() + filed.capacity());
}

namespace {

// Every partner share filed at its pair's index by the row's thread (blocks of whole rows), then gathered by
// each particle in increasing k: the same sums as the parts make, for lists whose tails would hold most pairs.
template <int E>
void filed_pass(const PairInputs &in, const NeighborList &list, Particles &p, HalfPassScratch &s,
                double *energy) {
  constexpr std::ptrdiff_t kStride = HalfPassScratch::kShareStride + E;
  const int n = list.rows();
  const int blocks = static_cast<int>(s.block_row.size()) - 1;
  const int *__restrict block_row = s.block_row.data();
  const int *__restrict in_entry = s.in_entry.data();
  const int *__restrict in_offset = s.in_offset.data();
  double *__restrict filed = s.filed.data();
  double *__restrict fx = p.fx.data(), *__restrict fy = p.fy.data(), *__restrict fz = p.fz.data();
  double *__restrict tx = p.tx.data(), *__restrict ty = p.ty.data(), *__restrict tz = p.tz.data();
  DEBRIS_HOST_PARALLEL {
    ChunkBuffer<E> c;  // per thread, on its stack
    DEBRIS_HOST_FOR
    for (int b = 0; b < blocks; ++b) {
      for (int i = block_row[b]; i < block_row[b + 1]; ++i) {
        fx[i] = fy[i] = fz[i] = tx[i] = ty[i] = tz[i] = 0.0;
        for (int m = 0; m < E; ++m) energy[kE * i + m] = 0.0;
      }
      sweep_rows<E>(
          in, block_row[b], block_row[b + 1], c,
          [&](int i, const RowSum<E> &r) {  // R, from zero
            fx[i] += r.fx;
            fy[i] += r.fy;
            fz[i] += r.fz;
            tx[i] += r.tx;
            ty[i] += r.ty;
            tz[i] += r.tz;
            for (int m = 0; m < E; ++m) energy[kE * i + m] += r.e[static_cast<std::size_t>(m)];
          },
          [&](int k, int q) {
            double *share_k = filed + kStride * k;
            share_k[0] = c.fx[q], share_k[1] = c.fy[q], share_k[2] = c.fz[q];
            share_k[3] = c.tjx[q], share_k[4] = c.tjy[q], share_k[5] = c.tjz[q];
            if constexpr (E > 0) partner_parts<E>(c, q, share_k + 6);
          });
    }
    DEBRIS_HOST_FOR
    for (int i = 0; i < n; ++i) {  // R + P, P from zero in increasing k
      double sfx = 0, sfy = 0, sfz = 0, stx = 0, sty = 0, stz = 0;
      std::array<double, E> se{};
      for (int e = in_offset[i]; e < in_offset[i + 1]; ++e) {
        const double *share_e = filed + kStride * in_entry[e];
        sfx -= share_e[0];
        sfy -= share_e[1];
        sfz -= share_e[2];
        stx += share_e[3];
        sty += share_e[4];
        stz += share_e[5];
        for (int m = 0; m < E; ++m) se[static_cast<std::size_t>(m)] += share_e[6 + m];
      }
      fx[i] = fx[i] + sfx;
      fy[i] = fy[i] + sfy;
      fz[i] = fz[i] + sfz;
      tx[i] = tx[i] + stx;
      ty[i] = ty[i] + sty;
      tz[i] = tz[i] + stz;
      for (int m = 0; m < E; ++m) energy[kE * i + m] = energy[kE * i + m] + se[static_cast<std::size_t>(m)];
    }
  }
}

}  // namespace

namespace {

template <int E>
void half_pass(const PairInputs &in, Particles &p, const NeighborList &list, HalfPassScratch &s,
               double *energy) {
  constexpr std::ptrdiff_t kStride = HalfPassScratch::kShareStride + E;
  const int parts = s.parts;
  const int *__restrict offset = list.offset().data();
  const int *__restrict col = list.index().data();
  const int *__restrict part_row = s.part_row.data();
  const int *__restrict part_run = s.part_run.data();
  const int *__restrict run_begin = s.run_begin.data();
  const int *__restrict run_end = s.run_end.data();
  const int *__restrict run_pair = s.run_pair.data();
  const int *__restrict run_sum = s.run_sum.data();
  double *__restrict tail_share = s.tail_share.data();
  double *__restrict tail_sum = s.tail_sum.data();
  double *__restrict fx = p.fx.data(), *__restrict fy = p.fy.data(), *__restrict fz = p.fz.data();
  double *__restrict tx = p.tx.data(), *__restrict ty = p.ty.data(), *__restrict tz = p.tz.data();

  // Each particle's force (and torque) is R + P: R its row's own shares summed in increasing k, P the
  // shares of the pairs where it is the partner, summed from zero in increasing k (all of them come from
  // rows before its own: a half list keeps a pair in row min(i, j)). One thread makes these sums in a single
  // sweep: the rows in order, each partner share added on the spot to f[j], which holds P_j until row j adds
  // R_j. More threads make the same sums: each owns a part (contiguous rows) and sweeps it the same way, but
  // the part's tail rows (those with a partner in a later part) are swept first, by all threads, their
  // shares kept; a part then starts its P sums from the kept shares it receives from earlier parts and adds
  // its own tail rows' shares where the sweep reaches them, in increasing k as one thread would. So any
  // thread count gives the same bits, and only the tails' shares are kept (a slab one cutoff thick per part,
  // against 6 doubles per pair everywhere when every share is filed: filed_pass).
  auto tail_unit = [&](int u, ChunkBuffer<E> &c) {  // tail rows [unit_begin, unit_end) of one run, kept
    const int r = s.unit_run[static_cast<std::size_t>(u)];
    const int row0 = run_begin[r], k0 = offset[row0];
    sweep_rows<E>(
        in, s.unit_begin[static_cast<std::size_t>(u)], s.unit_end[static_cast<std::size_t>(u)], c,
        [&](int i, const RowSum<E> &q) {
          double *sum_i = tail_sum + kStride * (run_sum[r] + i - row0);
          sum_i[0] = q.fx, sum_i[1] = q.fy, sum_i[2] = q.fz, sum_i[3] = q.tx, sum_i[4] = q.ty, sum_i[5] = q.tz;
          for (int m = 0; m < E; ++m) sum_i[6 + m] = q.e[static_cast<std::size_t>(m)];
        },
        [&](int k, int q) {
          double *share_k = tail_share + kStride * (run_pair[r] + k - k0);
          share_k[0] = c.fx[q], share_k[1] = c.fy[q], share_k[2] = c.fz[q];
          share_k[3] = c.tjx[q], share_k[4] = c.tjy[q], share_k[5] = c.tjz[q];
          if constexpr (E > 0) partner_parts<E>(c, q, share_k + 6);
        });
  };
  auto add_partner_share = [&](int j, const double *share) {
    fx[j] -= share[0], fy[j] -= share[1], fz[j] -= share[2];
    tx[j] += share[3], ty[j] += share[4], tz[j] += share[5];
    for (int m = 0; m < E; ++m) energy[kE * j + m] += share[6 + m];
  };
  auto sweep = [&](int row0, int row1, ChunkBuffer<E> &c) {  // rows swept on the spot: R + P, P_j in increasing k
    sweep_rows<E>(
        in, row0, row1, c,
        [&](int i, const RowSum<E> &q) {
          fx[i] = q.fx + fx[i];
          fy[i] = q.fy + fy[i];
          fz[i] = q.fz + fz[i];
          tx[i] = q.tx + tx[i];
          ty[i] = q.ty + ty[i];
          tz[i] = q.tz + tz[i];
          for (int m = 0; m < E; ++m) energy[kE * i + m] = q.e[static_cast<std::size_t>(m)] + energy[kE * i + m];
        },
        [&](int k, int q) {
          const int j = col[k];
          fx[j] -= c.fx[q];
          fy[j] -= c.fy[q];
          fz[j] -= c.fz[q];
          tx[j] += c.tjx[q];
          ty[j] += c.tjy[q];
          tz[j] += c.tjz[q];
          if constexpr (E > 0) add_partner_parts<E>(c, q, energy + kE * j);
        });
  };
  auto part_sweep = [&](int u, ChunkBuffer<E> &c) {  // part u's forces, once every tail is swept
    const int begin = part_row[u], end = part_row[u + 1];
    std::fill(fx + begin, fx + end, 0.0), std::fill(fy + begin, fy + end, 0.0), std::fill(fz + begin, fz + end, 0.0);
    std::fill(tx + begin, tx + end, 0.0), std::fill(ty + begin, ty + end, 0.0), std::fill(tz + begin, tz + end, 0.0);
    if constexpr (E > 0)
      std::fill(energy + static_cast<std::ptrdiff_t>(kPairEnergyColumns) * begin,
                energy + static_cast<std::ptrdiff_t>(kPairEnergyColumns) * end, 0.0);
    // The shares earlier parts' tails hold for this part's particles come first in k.
    for (int r = 0; r < part_run[u]; ++r) {
      const int k0 = offset[run_begin[r]], k1 = offset[run_end[r]];
      for (int k = k0; k < k1; ++k)
        if (col[k] >= begin && col[k] < end) add_partner_share(col[k], tail_share + kStride * (run_pair[r] + k - k0));
    }
    // The rows in order: swept on the spot between this part's tail runs, the runs from their kept shares.
    int row = begin;
    for (int r = part_run[u]; r < part_run[u + 1]; ++r) {
      sweep(row, run_begin[r], c);
      const int k0 = offset[run_begin[r]];
      for (int i = run_begin[r]; i < run_end[r]; ++i) {
        if (offset[i + 1] == offset[i]) continue;  // no row sum: f[i] is P_i, as in the sweep
        const double *sum_i = tail_sum + kStride * (run_sum[r] + i - run_begin[r]);
        fx[i] = sum_i[0] + fx[i];
        fy[i] = sum_i[1] + fy[i];
        fz[i] = sum_i[2] + fz[i];
        tx[i] = sum_i[3] + tx[i];
        ty[i] = sum_i[4] + ty[i];
        tz[i] = sum_i[5] + tz[i];
        for (int m = 0; m < E; ++m) energy[kE * i + m] = sum_i[6 + m] + energy[kE * i + m];
        for (int k = offset[i]; k < offset[i + 1]; ++k)
          if (col[k] < end) add_partner_share(col[k], tail_share + kStride * (run_pair[r] + k - k0));
      }
      row = run_end[r];
    }
    sweep(row, end, c);
  };

  if (parts == 1) {  // no tail, no parallel region
    ChunkBuffer<E> c;
    part_sweep(0, c);
    return;
  }
  if (s.file_all) return filed_pass<E>(in, list, p, s, energy);
  // Host threads only: this is the host pass (offload builds use the full-list pass). The tails first, shared
  // among the threads; the loop barrier; then one part per thread.
  const int *__restrict thread_unit = s.thread_unit.data();
  DEBRIS_HOST_PARALLEL {
    ChunkBuffer<E> c;  // per thread, on its stack
    // Static loops: with one thread per part, thread t sweeps its share of the tails, then part t.
    DEBRIS_HOST_FOR
    for (int t = 0; t < parts; ++t) {
      for (int u = thread_unit[t]; u < thread_unit[t + 1]; ++u) tail_unit(u, c);
    }
    DEBRIS_HOST_FOR
    for (int u = 0; u < parts; ++u) part_sweep(u, c);
  }
}

}  // namespace

void cohesive_contact_pass_half(const CohesivePairTable &table, const CohesiveOptions &opt, const BoxView &box,
                                Particles &p, const NeighborList &list, ContactHistory &history, double dt,
                                int update_history, HalfPassScratch &s, const PairEnergyOut *energy) {
  if (list.kind() != NeighborKind::half) throw std::logic_error("cohesive_contact_pass_half needs a half list");
  if (energy && !s.energy) throw std::logic_error("cohesive_contact_pass_half: scratch not indexed for energy");
  if (s.entries != list.entries())
    throw std::logic_error("cohesive_contact_pass_half: scratch not indexed for this list");
  // The thread count may have changed since the list was built (the thread tuner): part the rows anew.
  if (s.parts != exec::threads()) s.partition(list, exec::threads());
  const PairInputs in{list.offset().data(),
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
  if (energy) return half_pass<kPairEnergyColumns>(in, p, list, s, energy->rows);
  half_pass<0>(in, p, list, s, nullptr);
}

}  // namespace debris
