// pd_bond_step's two sweeps (kernels/peridem/pd_bond_passes.cpp) written with AVX2 intrinsics, for x86-64 CPUs
// with AVX2 and FMA. Only x86-64 host builds compile this file (kernels/peridem/CMakeLists.txt), and
// pd_bond_step chooses it in one place (avx2_bond_step_sweeps); the portable sweeps stay the reference, and
// tests/test_pd_bond_passes_fast.cpp holds both to the same bits.
//
// Four entries an iteration: the partners' columns fetched by broadcast loads and blends (the compiler's vector
// loops of the portable sweeps insert them lane by lane on the shuffle port), every term kept in registers and
// summed in 4 lanes (sum4's order) instead of staged in arrays and read back, and |y| handed from the
// dilatation sweep to the force sweep (BondList::bond_length), so the force sweep takes no square root. Each
// operation is the one the portable bodies write, in their order (both files are built without contraction
// into FMA, so the compiler keeps theirs as written too): the same bits as the portable sweeps.
#include <immintrin.h>

#include <cstring>

#include "core/bond_list.hpp"
#include "core/exec.hpp"
#include "kernels/peridem/lps_bond_force.hpp"
#include "kernels/peridem/pd_bond_rows.hpp"

// The kernels below, and the helpers and loop bodies (lambdas) inlined into them, built for AVX2 + FMA. Only
// these functions are: the rest of the program, the inline functions of the headers included, runs on any
// x86-64 CPU.
#define DEBRIS_AVX2 __attribute__((target("arch=x86-64-v3")))
#define DEBRIS_AVX2_INLINE __attribute__((target("arch=x86-64-v3"), always_inline))

namespace debris::pd_rows {
namespace {


// Lane l of an iteration over entries [k, k + 4) belongs to the row while l < count - t (lane_index < rest).
DEBRIS_AVX2_INLINE inline __m256d lanes_below(int rest) {
  const __m256i lane_index = _mm256_setr_epi64x(0, 1, 2, 3);
  return _mm256_castsi256_pd(_mm256_cmpgt_epi64(_mm256_set1_epi64x(rest), lane_index));
}

// Four partners' values of one column: four broadcast loads and three blends (no shuffle port).
DEBRIS_AVX2_INLINE inline __m256d gather4(const double* a, const long* j) {
  const __m256d lo = _mm256_blend_pd(_mm256_broadcast_sd(a + j[0]), _mm256_broadcast_sd(a + j[1]), 0b1010);
  const __m256d hi = _mm256_blend_pd(_mm256_broadcast_sd(a + j[2]), _mm256_broadcast_sd(a + j[3]), 0b1010);
  return _mm256_blend_pd(lo, hi, 0b1100);
}

// Entries [k, k + 4) of one iteration: partners and reference lengths. kGuarded: lanes at or past `stop` (the
// end of the list, or of the rows this thread writes) take entry k's values instead: valid, and never summed
// or stored.
struct FourEntries {
  long j[4];
  __m256d x0;
};
template <bool kGuarded>
DEBRIS_AVX2_INLINE inline FourEntries four_entries(const int* partner, const double* length0, int k, int stop) {
  FourEntries f;
  if (!kGuarded || k + 4 <= stop) {
    for (int l = 0; l < 4; ++l) f.j[l] = partner[k + l];
    f.x0 = _mm256_loadu_pd(length0 + k);
  } else {
    alignas(32) double x0[4];
    for (int l = 0; l < 4; ++l) {
      const int kk = k + l < stop ? k + l : k;
      f.j[l] = partner[kk];
      x0[l] = length0[kk];
    }
    f.x0 = _mm256_load_pd(x0);
  }
  return f;
}

// Entries [k, k + 4) of a column of doubles. kGuarded: lanes at or past `stop` read as 0 (nothing is read
// there), or are not written.
template <bool kGuarded>
DEBRIS_AVX2_INLINE inline __m256d load_four(const double* a, int k, int stop) {
  if (!kGuarded || k + 4 <= stop) return _mm256_loadu_pd(a + k);
  return _mm256_maskload_pd(a + k, _mm256_castpd_si256(lanes_below(stop - k)));
}
template <bool kGuarded>
DEBRIS_AVX2_INLINE inline void store_four(double* a, int k, int stop, __m256d v) {
  if (!kGuarded || k + 4 <= stop)
    _mm256_storeu_pd(a + k, v);
  else
    _mm256_maskstore_pd(a + k, _mm256_castpd_si256(lanes_below(stop - k)), v);
}

// All ones in the lanes of entries [k, k + min(rest, 4)) that are not broken (rest > 0).
DEBRIS_AVX2_INLINE inline __m256d intact_lanes(const unsigned char* broken, int k, int rest) {
  int word = 0;
  if (rest >= 4)
    std::memcpy(&word, broken + k, sizeof word);
  else
    for (int l = 0; l < rest; ++l) word |= broken[k + l] << (8 * l);
  const __m256i flags = _mm256_cvtepu8_epi64(_mm_cvtsi32_si128(word));
  return _mm256_castsi256_pd(_mm256_cmpeq_epi64(flags, _mm256_setzero_si256()));
}

// (v0 + v1) + (v2 + v3): sum4's last step.
DEBRIS_AVX2_INLINE inline double add_lanes(__m256d v) {
  alignas(32) double l[4];
  _mm256_store_pd(l, v);
  return (l[0] + l[1]) + (l[2] + l[3]);
}

// A stage's iterations over its `count` entries from k0, iteration.template operator()<kMasked, kGuarded>(t)
// for t = 0, 4, ...: most stages have no broken entry and all their lanes before `stop`, so only their last
// iteration is masked and none guarded; the others take the general iteration throughout.
template <class Iteration>
DEBRIS_AVX2_INLINE inline void run_stage(Iteration& iteration, int k0, int count, bool any, int stop) {
  const int full = count & ~3;
  if (!any && k0 + full + 4 <= stop) {
    for (int t = 0; t < full; t += 4) iteration.template operator()<false, false>(t);
    if (full < count) iteration.template operator()<true, false>(full);
  } else {
    for (int t = 0; t < count; t += 4) iteration.template operator()<true, true>(t);
  }
}

// The portable break_and_dilate_body, with |y| of every entry stored in lengths_out. A row's last iteration
// stores the |y| its spare lanes compute for the next row's entries, which that row stores again after it; the
// lanes stop at the end of the block (offset[r1]), where another thread's rows begin.
template <bool kPlanar>
DEBRIS_AVX2_INLINE inline long break_and_dilate_body_avx2(const RowInputs& in, double* lengths_out, int r0, int r1) {
  const int* __restrict offset = in.offset;
  const int* __restrict partner = in.partner;
  const double* __restrict length0 = in.length0;
  const double* __restrict weight = in.weight;
  unsigned char* __restrict broken = in.broken;
  const double* __restrict x = in.x, * __restrict y = in.y, * __restrict z = in.z;
  double* __restrict lengths = lengths_out;
  const int may_break = in.do_break;
  const int stop = offset[r1];
  const __m256d zero = _mm256_setzero_pd();
  const __m256d magnitude = _mm256_castsi256_pd(_mm256_set1_epi64x(0x7fffffffffffffffLL));
  const __m256d all_lanes = _mm256_castsi256_pd(_mm256_set1_epi64x(-1));
  long marked = 0;
  for (int i = r0; i < r1; ++i) {
    const int begin = offset[i], end = offset[i + 1];
    if (begin == end) {
      finish_dilatation_row(in, i, nullptr, 0.0);
      continue;
    }
    const PdLpsConstants c = in.lps[in.material[in.grain[i]]];
    const __m256d xi = _mm256_set1_pd(x[i]), yi = _mm256_set1_pd(y[i]), zi = _mm256_set1_pd(z[i]);
    const double s0 = c.critical_stretch;
    const __m256d near_s0 = _mm256_set1_pd(0.999 * s0);
    const int in_compression = c.break_in_compression > 0.0;  // the same in every iteration of the row
    double sum = 0.0;
    for (int k0 = begin; k0 < end; k0 += kStage) {
      const int count = end - k0 < kStage ? end - k0 : kStage;
      const bool any = any_broken(broken, k0, count);
      __m256d acc = zero;
      // Entries [k0 + t, k0 + t + 4). kMasked: lanes past the row's count, or broken ones, add nothing;
      // kGuarded: lanes at or past `stop` are neither read nor written.
      auto iteration = [&]<bool kMasked, bool kGuarded>(int t) DEBRIS_AVX2_INLINE {
        const int k = k0 + t;
        const FourEntries f = four_entries<kGuarded>(partner, length0, k, stop);
        const __m256d dx = _mm256_sub_pd(gather4(x, f.j), xi), dy = _mm256_sub_pd(gather4(y, f.j), yi);
        __m256d r2 = _mm256_add_pd(_mm256_mul_pd(dx, dx), _mm256_mul_pd(dy, dy));
        if constexpr (!kPlanar) {
          const __m256d dz = _mm256_sub_pd(gather4(z, f.j), zi);
          r2 = _mm256_add_pd(r2, _mm256_mul_pd(dz, dz));
        }
        const __m256d length = _mm256_sqrt_pd(r2);
        store_four<kGuarded>(lengths, k, stop, length);
        const __m256d e = _mm256_sub_pd(length, f.x0);
        // break_and_dilate_body's e + both (|e| - e) is exactly |e| for both = 1 (e + 2|e| for e < 0), e for both = 0.
        const __m256d probe = in_compression ? _mm256_and_pd(e, magnitude) : e;
        const __m256d slack = _mm256_sub_pd(probe, _mm256_mul_pd(near_s0, f.x0));
        __m256d term = _mm256_mul_pd(_mm256_mul_pd(load_four<kGuarded>(weight, k, stop), f.x0), e);
        __m256d keep = all_lanes;
        if constexpr (kMasked) {
          keep = lanes_below(count - t);
          if (any) keep = _mm256_and_pd(keep, intact_lanes(broken, k, count - t));
        }
        if (may_break) {
          __m256d is_near = _mm256_cmp_pd(slack, zero, _CMP_GT_OQ);
          if constexpr (kMasked) is_near = _mm256_and_pd(is_near, keep);
          const int near = _mm256_movemask_pd(is_near);
          if (near) {  // eq 11 exactly for the entries near s_0, as break_and_dilate_body tests them
            alignas(32) double extension[4];
            alignas(32) long long kept[4];
            _mm256_store_pd(extension, e);
            _mm256_store_si256(reinterpret_cast<__m256i*>(kept), _mm256_castpd_si256(keep));
            for (int l = 0; l < 4; ++l)
              if ((near >> l & 1) && lps_bond_breaks(extension[l] / length0[k + l], s0, in_compression)) {
                broken[k + l] = 1;
                kept[l] = 0;
                ++marked;
              }
            term = _mm256_and_pd(term, _mm256_castsi256_pd(_mm256_load_si256(reinterpret_cast<const __m256i*>(kept))));
          }
        }
        if constexpr (kMasked) term = _mm256_and_pd(term, keep);
        acc = _mm256_add_pd(acc, term);
      };
      run_stage(iteration, k0, count, any, stop);
      sum += add_lanes(acc);
    }
    finish_dilatation_row(in, i, &c, sum);
  }
  return marked;
}

DEBRIS_AVX2 long break_and_dilate_rows_avx2(const RowInputs& in, double* lengths, int r0, int r1) {
  return in.planar ? break_and_dilate_body_avx2<true>(in, lengths, r0, r1)
                   : break_and_dilate_body_avx2<false>(in, lengths, r0, r1);
}

// The portable bond_force_body, with |y| read from lengths_in (this step's dilatation sweep).
template <bool kPlanar>
DEBRIS_AVX2_INLINE inline void bond_force_body_avx2(const RowInputs& in, const double* lengths_in, int r0, int r1) {
  const int* __restrict offset = in.offset;
  const int* __restrict partner = in.partner;
  const double* __restrict length0 = in.length0;
  const double* __restrict weight = in.weight;
  const unsigned char* __restrict broken = in.broken;
  const double* __restrict x = in.x, * __restrict y = in.y, * __restrict z = in.z;
  const double* __restrict volume = in.volume;
  const double* __restrict factors = in.factors;
  const double* __restrict lengths = lengths_in;
  double* __restrict fx = in.fx, * __restrict fy = in.fy, * __restrict fz = in.fz;
  const int stop = in.entries;
  const __m256d zero = _mm256_setzero_pd(), one = _mm256_set1_pd(1.0);
  for (int i = r0; i < r1; ++i) {
    const int begin = offset[i], end = offset[i + 1];
    if (begin == end) continue;
    const __m256d xi = _mm256_set1_pd(x[i]), yi = _mm256_set1_pd(y[i]), zi = _mm256_set1_pd(z[i]);
    const __m256d p_i = _mm256_set1_pd(factors[2 * i]), q_i = _mm256_set1_pd(factors[2 * i + 1]);
    double Fx = 0.0, Fy = 0.0, Fz = 0.0;
    for (int k0 = begin; k0 < end; k0 += kStage) {
      const int count = end - k0 < kStage ? end - k0 : kStage;
      const bool any = any_broken(broken, k0, count);
      __m256d ax = zero, ay = zero, az = zero;
      // Entries [k0 + t, k0 + t + 4); kMasked, kGuarded as in break_and_dilate_body_avx2.
      auto iteration = [&]<bool kMasked, bool kGuarded>(int t) DEBRIS_AVX2_INLINE {
        const int k = k0 + t;
        const FourEntries f = four_entries<kGuarded>(partner, length0, k, stop);
        // Every partner column first, while the partner indices are in registers.
        const __m256d x_j = gather4(x, f.j), y_j = gather4(y, f.j);
        const __m256d z_j = kPlanar ? zero : gather4(z, f.j);
        // P, Q of two partners per 128-bit load, then one unpack each for the P and the Q of four.
        const __m256d pq02 = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(factors + 2 * f.j[0])),
                                                  _mm_loadu_pd(factors + 2 * f.j[2]), 1);
        const __m256d pq13 = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(factors + 2 * f.j[1])),
                                                  _mm_loadu_pd(factors + 2 * f.j[3]), 1);
        const __m256d p_sum = _mm256_add_pd(p_i, _mm256_unpacklo_pd(pq02, pq13));
        const __m256d q_sum = _mm256_add_pd(q_i, _mm256_unpackhi_pd(pq02, pq13));
        const __m256d length = load_four<kGuarded>(lengths, k, stop);
        // bond_force_scale: eq 12's (J V_j (P x0 + Q e)) / |y|; 1 / |y| is bond_force_scale's for |y| > 0
        // (1 / (|y| + 0)), and a lane with |y| = 0 (no direction) is masked to s = 0 below, as its 1 / |y| = 0 does.
        const __m256d inv_length = _mm256_div_pd(one, length);
        const __m256d e = _mm256_sub_pd(length, f.x0);
        const __m256d bracket = _mm256_add_pd(_mm256_mul_pd(p_sum, f.x0), _mm256_mul_pd(q_sum, e));
        __m256d s = _mm256_mul_pd(_mm256_mul_pd(load_four<kGuarded>(weight, k, stop), bracket), inv_length);
        // Spare and broken lanes add s 0 = 0 (dx is finite: a position), as zero_broken's zeros do.
        __m256d keep = _mm256_cmp_pd(length, zero, _CMP_GT_OQ);
        if constexpr (kMasked) {
          keep = _mm256_and_pd(keep, lanes_below(count - t));
          if (any) keep = _mm256_and_pd(keep, intact_lanes(broken, k, count - t));
        }
        s = _mm256_and_pd(s, keep);
        ax = _mm256_add_pd(ax, _mm256_mul_pd(s, _mm256_sub_pd(x_j, xi)));
        ay = _mm256_add_pd(ay, _mm256_mul_pd(s, _mm256_sub_pd(y_j, yi)));
        if constexpr (!kPlanar) az = _mm256_add_pd(az, _mm256_mul_pd(s, _mm256_sub_pd(z_j, zi)));
      };
      run_stage(iteration, k0, count, any, stop);
      Fx += add_lanes(ax);
      Fy += add_lanes(ay);
      if constexpr (!kPlanar) Fz += add_lanes(az);
    }
    // Eq 33 is a force density; the node carries V_i of it.
    fx[i] += volume[i] * Fx;
    fy[i] += volume[i] * Fy;
    if constexpr (!kPlanar) fz[i] += volume[i] * Fz;
  }
}

DEBRIS_AVX2 void bond_force_rows_avx2(const RowInputs& in, const double* lengths, int r0, int r1) {
  if (in.planar)
    bond_force_body_avx2<true>(in, lengths, r0, r1);
  else
    bond_force_body_avx2<false>(in, lengths, r0, r1);
}

// Both sweeps over the blocks of rows the portable sweeps use: the dilatation sweep stores |y| of every entry
// in bonds.bond_length, the force sweep reads it there.
long bond_step_avx2(const RowInputs& in, BondList& bonds) {
  bonds.bond_length.resize(bonds.entries());
  double* lengths = bonds.bond_length.data();
  const int* offset = in.offset;
  const int n = in.n, blocks = in.blocks;
  long marked = 0;
  DEBRIS_KERNEL_SUM(marked)
  for (int b = 0; b < blocks; ++b)
    marked +=
        break_and_dilate_rows_avx2(in, lengths, block_row(offset, n, blocks, b), block_row(offset, n, blocks, b + 1));
  DEBRIS_KERNEL
  for (int b = 0; b < blocks; ++b)
    bond_force_rows_avx2(in, lengths, block_row(offset, n, blocks, b), block_row(offset, n, blocks, b + 1));
  return marked;
}

}  // namespace

BondStepSweeps avx2_bond_step_sweeps() {
  return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") ? bond_step_avx2 : nullptr;
}

}  // namespace debris::pd_rows
