#include "kernels/peridem/pd_bond_passes.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "core/block_sums.hpp"
#include "core/bond_list.hpp"
#include "core/error.hpp"
#include "core/exec.hpp"
#include "core/pd_nodes.hpp"
#include "core/vec3.hpp"
#include "kernels/peridem/lps_bond_force.hpp"
#include "kernels/peridem/pd_bond_rows.hpp"

namespace debris {

namespace {

// Host-side check before a kernel indexes `lps` through grains.material: every particle grain that owns
// nodes must name a material of the table (walls own no bonds and are never looked up).
void check_tables(const PdLpsTable& lps, const PdGrains& grains, const BondList& bonds,
                  const PdNodes& nodes) {
  if (bonds.nodes() != nodes.size())
    throw input_error("bond list", std::to_string(bonds.nodes()) + " rows",
                      "must have one row per node (" + std::to_string(nodes.size()) + " nodes): rebuild it");
  for (std::size_t g = 0; g < grains.size(); ++g) {
    if (grains.kind[g] != static_cast<int>(PdGrainKind::particle)) continue;
    if (grains.node_begin[g] == grains.node_end[g]) continue;
    const int mat = grains.material[g];
    if (mat < 0 || static_cast<std::size_t>(mat) >= lps.size())
      throw input_error("grain " + std::to_string(g) + " material", std::to_string(mat),
                        "must index the material table (" + std::to_string(lps.size()) + " materials)");
  }
}

// Raw pointers of everything the kernels read, copied into locals before each loop.
struct BondView {
  int n;
  const int* offset;
  const int* partner;
  const double* length0;
  const int* grain;
  const int* material;
  const PdLpsConstants* lps;
};

BondView view(const PdLpsTable& lps, const PdGrains& grains, const BondList& bonds,
              const PdNodes& nodes) {
  check_tables(lps, grains, bonds, nodes);
  return BondView{static_cast<int>(nodes.size()),
                  bonds.offset.data(),
                  bonds.partner.data(),
                  bonds.length0.data(),
                  nodes.grain.data(),
                  grains.material.data(),
                  lps.data()};
}

}  // namespace

void pd_weighted_volume_pass(const PdLpsTable& lps, const PdGrains& grains, BondList& bonds, PdNodes& nodes) {
  const BondView b = view(lps, grains, bonds, nodes);
  bonds.weight.resize(bonds.entries());
  const int n = b.n;
  const int* __restrict offset = b.offset, * __restrict partner = b.partner;
  const int* __restrict grain = b.grain, * __restrict material = b.material;
  const double* __restrict length0 = b.length0;
  const PdLpsConstants* __restrict table = b.lps;
  const double* __restrict volume = nodes.volume.data();
  double* __restrict m = nodes.weighted_volume.data();
  double* __restrict weight = bonds.weight.data();
  DEBRIS_RESIDENT(offset, partner, grain, material, length0, table, volume, m, weight);
  DEBRIS_KERNEL
  for (int i = 0; i < n; ++i) {
    double sum = 0.0;
    if (offset[i] < offset[i + 1]) {
      const double horizon = table[material[grain[i]]].horizon;
      for (int k = offset[i]; k < offset[i + 1]; ++k) {
        const double x = length0[k], J = lps_influence(x / horizon), v_j = volume[partner[k]];
        sum += lps_weighted_volume_term(J, x, v_j);
        weight[k] = lps_bond_weight(J, v_j);
      }
    }
    m[i] = sum;
  }
}

namespace {

using pd_rows::any_broken;
using pd_rows::block_row;
using pd_rows::finish_dilatation_row;
using pd_rows::kStage;
using pd_rows::RowInputs;

// Host builds compile the row kernels twice (x86-64 and x86-64-v3: AVX2; DEBRIS_CLONES) and the loader picks
// the one the machine runs, as kernels/dem/cohesive_contact_half.cpp does (no FMA in this file: both give the
// same bits). An AVX-512 clone was
// no faster on the compressive test: its loops take 16 entries per vector, more than half of a typical row
// (27 entries).
#define DEBRIS_PD_ROW_CLONES DEBRIS_CLONES

// Host builds hand rows to the kernels in blocks of about equal bond entries (one dispatched call per block,
// and two threads get equal work although the wall nodes, which have no bonds, all sit at the end). Offload
// builds use one row per iteration (exec::row_blocks).
constexpr int kEntriesPerBlock = 4096;
int row_blocks(int n, int entries) { return exec::row_blocks(n, entries, kEntriesPerBlock); }

DEBRIS_DECLARE_TARGET

// The sweeps take a row kStage bond entries a round (pd_bond_rows.hpp), staged: a vector loop computes every
// entry's term into local arrays, then a scalar loop sums them in entry order into 4 partial sums (fixed, so
// the sums do not depend on the thread count; there is no reduction inside the vector loop).

// The sum of v[0, count) in 4 running sums, entry t into sum t mod 4, then (s0 + s1) + (s2 + s3): the order
// of a 4-lane vector accumulator, so the AVX2 sweeps (pd_bond_passes_avx2.cpp: sums in registers) give the
// same bits.
inline double sum4(const double* v, int count) {
  double s0 = 0.0, s1 = 0.0, s2 = 0.0, s3 = 0.0;
  int t = 0;
  for (; t + 4 <= count; t += 4) {
    s0 += v[t];
    s1 += v[t + 1];
    s2 += v[t + 2];
    s3 += v[t + 3];
  }
  if (t < count) s0 += v[t];
  if (t + 1 < count) s1 += v[t + 1];
  if (t + 2 < count) s2 += v[t + 2];
  return (s0 + s1) + (s2 + s3);
}

// The largest of v[0, count) by 4 running maxima (a comparison per entry, no rounding); NaNs are passed over,
// -infinity for none.
inline double max4(const double* v, int count) {
  constexpr double kNone = -std::numeric_limits<double>::infinity();
  double m0 = kNone, m1 = kNone, m2 = kNone, m3 = kNone;
  int t = 0;
  for (; t + 4 <= count; t += 4) {
    m0 = v[t] > m0 ? v[t] : m0;
    m1 = v[t + 1] > m1 ? v[t + 1] : m1;
    m2 = v[t + 2] > m2 ? v[t + 2] : m2;
    m3 = v[t + 3] > m3 ? v[t + 3] : m3;
  }
  for (; t < count; ++t) m0 = v[t] > m0 ? v[t] : m0;
  m0 = m1 > m0 ? m1 : m0;
  m2 = m3 > m2 ? m3 : m2;
  return m2 > m0 ? m2 : m0;
}

// The vector loops below run over a row's entries padded to a multiple of kLanes while the padding stays
// inside the bond arrays: the extra lanes compute terms of the next row's entries (valid indices, finite
// values) that are never summed, and the loop needs no scalar remainder. kLanes is the widest vector the
// clones use for these loops (8 ints of 32 bytes).
constexpr int kLanes = 8;
inline int padded_count(int k0, int count, int entries) {
  const int padded = (count + kLanes - 1) / kLanes * kLanes;
  return k0 + padded <= entries ? padded : count;
}

// h = 0 of eqs 12-13 applied after a stage's vector loop computed every entry as intact: the staged values
// of the broken entries among [k0, k0 + count) are set to 0 in the three arrays a, b, c, after a check of the
// broken bytes a word at a time, which is all a stage without a broken entry costs. (Not a factor inside
// the vector loop: filling and reading a factor per entry cost the sweeps 8-10% on rows that, almost always,
// have no broken bond. Zeroing also keeps a non-finite term of a broken bond out of the sums.)
inline void zero_broken(const unsigned char* broken, int k0, int count, double* a, double* b, double* c) {
  if (!any_broken(broken, k0, count)) return;
  for (int t = 0; t < count; ++t)
    if (broken[k0 + t]) a[t] = b[t] = c[t] = 0.0;
}

// Rows [r0, r1): eq 11 (do_break: mark the intact bonds whose stretch reached s_0; returns the entries
// marked), then theta_i of eq 34 over the bonds intact after that (do_theta), and the node factors of
// lps_node_factors (do_factors). One bond length per entry serves both. kPlanar: every node has the same z,
// so dz = 0 exactly and |y| is computed from dx, dy alone: the same bits (the 3D sum adds dz dz = 0 last).
template <bool kPlanar>
DEBRIS_ALWAYS_INLINE long break_and_dilate_body(const RowInputs& in, int r0, int r1) {
  const int* __restrict offset = in.offset;
  const int* __restrict partner = in.partner;
  const double* __restrict length0 = in.length0;
  const double* __restrict weight = in.weight;
  unsigned char* __restrict broken = in.broken;
  const double* __restrict x = in.x, * __restrict y = in.y, * __restrict z = in.z;
  const int may_break = in.do_break;
  long marked = 0;
  double term[kStage], slack[kStage], extension[kStage];
  for (int i = r0; i < r1; ++i) {
    const int begin = offset[i], end = offset[i + 1];
    if (begin == end) {
      finish_dilatation_row(in, i, nullptr, 0.0);
      continue;
    }
    const PdLpsConstants c = in.lps[in.material[in.grain[i]]];
    const double xi = x[i], yi = y[i], zi = z[i];
    // A bond is near s_0 within 0.1 per cent of it: far above the roundings of e, s_0 x0 and e / x0, so every
    // bond that eq 11 breaks is near, and few others go through the scalar test below.
    const double s0 = c.critical_stretch, near_s0 = 0.999 * s0;
    const double both = c.break_in_compression;  // 1: |e| is tested, not e (a factor, not a branch)
    const int in_compression = both > 0.0;
    double sum = 0.0;
    for (int k0 = begin; k0 < end; k0 += kStage) {
      const int count = end - k0 < kStage ? end - k0 : kStage;
      const int lanes = padded_count(k0, count, in.entries);
      // Every entry's theta term (as if intact: h is applied after the loop) and its slack to breaking, in a
      // vector loop: all loads unconditional, no byte column (it would make the vector 32 entries wide, longer
      // than most rows), and no selects between computed values (with trapping floating-point math the compiler
      // may move such a value under a branch, and then it does not vectorise the loop). Since s_0 > 0 (G_c > 0,
      // pd_material.cpp), every bond that eq 11 breaks has a slack above 0.
      DEBRIS_SIMD
      for (int t = 0; t < lanes; ++t) {
        const int k = k0 + t, j = partner[k];
        const double dx = x[j] - xi, dy = y[j] - yi;
        const double x0 = length0[k];
        double r2 = dx * dx + dy * dy;
        if constexpr (!kPlanar) {
          const double dz = z[j] - zi;
          r2 += dz * dz;
        }
        const double length = std::sqrt(r2);
        const double e = length - x0;
        // Near s_0 when e > 0.999 s_0 x0, that is when this slack is above 0 (a multiplication, not the division
        // of the stretch; rounded, e at or below it still means e / x0 < s_0 for certain).
        const double probe = e + both * (std::fabs(e) - e);  // e, or |e| when compression breaks bonds too
        slack[t] = probe - near_s0 * x0;
        extension[t] = e;
        term[t] = lps_dilatation_term(weight[k], x0, e);
      }
      // A bond broken before this step adds nothing to theta and is not broken again.
      // (Its slack becomes 0: not near.)
      zero_broken(broken, k0, count, term, slack, extension);
      if (may_break && max4(slack, count) > 0.0) {
        // Eq 11 exactly, lps_bond_breaks(lps_stretch(|y|, x0), s0): e / x0 is the stretch, the same bits
        // from either end of the bond, so both ends decide alike. Broken now: h = 0 in this step's theta.
        for (int t = 0; t < count; ++t)
          if (slack[t] > 0.0 && lps_bond_breaks(extension[t] / length0[k0 + t], s0, in_compression)) {
            broken[k0 + t] = 1;
            term[t] = 0.0;
            ++marked;
          }
      }
      sum += sum4(term, count);
    }
    finish_dilatation_row(in, i, &c, sum);
  }
  return marked;
}

// Eq 33's bond term of one entry as the scalar s of lps_bond_force_scale (the term is s y), from |y|, the
// reference length x0, the weight J V_j and the sums P_i + P_j, Q_i + Q_j, with the sweeps' branch-free 1 / |y|.
DEBRIS_ALWAYS_INLINE double bond_force_scale(double length, double x0, double weight, double p_sum, double q_sum) {
  // 1 / |y|, or 0 when |y| is 0 (no direction), as arithmetic: a division under a branch may trap.
  const double has_length = static_cast<double>(length > 0.0);
  const double inv_length = has_length / (length + (1.0 - has_length));
  return lps_bond_force_scale(weight, x0, length - x0, p_sum, q_sum, inv_length);  // eq 12
}

// Rows [r0, r1): f_i += V_i F_i, F_i of eq 33 over the intact bonds, from the node factors. kPlanar: as in
// break_and_dilate_body; no z component then (it would be s 0 = 0 for every entry).
template <bool kPlanar>
DEBRIS_ALWAYS_INLINE void bond_force_body(const RowInputs& in, int r0, int r1) {
  const int* __restrict offset = in.offset;
  const int* __restrict partner = in.partner;
  const double* __restrict length0 = in.length0;
  const double* __restrict weight = in.weight;
  const unsigned char* __restrict broken = in.broken;
  const double* __restrict x = in.x, * __restrict y = in.y, * __restrict z = in.z;
  const double* __restrict volume = in.volume;
  const double* __restrict factors = in.factors;
  double* __restrict fx = in.fx, * __restrict fy = in.fy, * __restrict fz = in.fz;
  const int entries = in.entries;
  double ux[kStage], uy[kStage], uz[kStage];
  for (int i = r0; i < r1; ++i) {
    const int begin = offset[i], end = offset[i + 1];
    if (begin == end) continue;
    const double xi = x[i], yi = y[i], zi = z[i];
    const double p_i = factors[2 * i], q_i = factors[2 * i + 1];
    double Fx = 0.0, Fy = 0.0, Fz = 0.0;
    for (int k0 = begin; k0 < end; k0 += kStage) {
      const int count = end - k0 < kStage ? end - k0 : kStage;
      const int lanes = padded_count(k0, count, entries);
      // As in break_and_dilate_rows: every entry as if intact, the broken ones zeroed after the loop.
      DEBRIS_SIMD
      for (int t = 0; t < lanes; ++t) {
        const int k = k0 + t, j = partner[k];
        const double dx = x[j] - xi, dy = y[j] - yi;
        double r2 = dx * dx + dy * dy, dz = 0.0;
        if constexpr (!kPlanar) {
          dz = z[j] - zi;
          r2 += dz * dz;
        }
        const double s =
            bond_force_scale(std::sqrt(r2), length0[k], weight[k], p_i + factors[2 * j], q_i + factors[2 * j + 1]);
        ux[t] = s * dx;
        uy[t] = s * dy;
        if constexpr (!kPlanar) uz[t] = s * dz;
      }
      zero_broken(broken, k0, count, ux, uy, uz);
      Fx += sum4(ux, count);
      Fy += sum4(uy, count);
      if constexpr (!kPlanar) Fz += sum4(uz, count);
    }
    // Eq 33 is a force density; the node carries V_i of it.
    fx[i] += volume[i] * Fx;
    fy[i] += volume[i] * Fy;
    if constexpr (!kPlanar) fz[i] += volume[i] * Fz;
  }
}

DEBRIS_PD_ROW_CLONES long break_and_dilate_rows(const RowInputs& in, int r0, int r1) {
  return in.planar ? break_and_dilate_body<true>(in, r0, r1) : break_and_dilate_body<false>(in, r0, r1);
}

DEBRIS_PD_ROW_CLONES void bond_force_rows(const RowInputs& in, int r0, int r1) {
  if (in.planar)
    bond_force_body<true>(in, r0, r1);
  else
    bond_force_body<false>(in, r0, r1);
}

DEBRIS_END_DECLARE_TARGET

// Whether every node has the same finite z: a 2D deck, whose nodes lie in a plane z = const (the input files
// have z = 0); the sweeps then skip z (pd_bond_passes.hpp). One vector pass counting the nodes with
// z - z[0] != 0: a different z (no two doubles differ by 0 without gradual underflow's help), a NaN, or an
// infinite z[0] (inf - inf is NaN), so a blown-up state takes the 3D sweeps. (A minimum and then a count,
// two passes, took 2% of the bond passes.)
bool nodes_in_one_plane(int n, const double* z) {
  if (n == 0) return true;
  int off_plane = 0;
  DEBRIS_RESIDENT(z);
  DEBRIS_KERNEL_SUM(off_plane)
  for (int i = 0; i < n; ++i) {
    const double z0 = z[0];  // read on the device in offload builds, like z[i]
    off_plane += static_cast<int>(z[i] - z0 != 0.0);
  }
  return off_plane == 0;
}

// Everything the row kernels read; the outputs (theta, force) only from a mutable PdNodes (with_outputs).
RowInputs row_inputs(const PdLpsTable& lps, const PdGrains& grains, const BondList& bonds,
                     const PdNodes& nodes) {
  const BondView b = view(lps, grains, bonds, nodes);
  if (bonds.weight.size() != bonds.entries())
    throw std::logic_error("bond passes: the bond list has " + std::to_string(bonds.weight.size()) + " weights for " +
                           std::to_string(bonds.entries()) + " entries: run pd_weighted_volume_pass after building it");
  bonds.node_factors.resize(2 * nodes.size());
  RowInputs in{};
  in.offset = b.offset;
  in.partner = b.partner;
  in.length0 = b.length0;
  in.weight = bonds.weight.data();
  in.grain = b.grain;
  in.material = b.material;
  in.lps = b.lps;
  in.x = nodes.x.data();
  in.y = nodes.y.data();
  in.z = nodes.z.data();
  in.volume = nodes.volume.data();
  in.m = nodes.weighted_volume.data();
  in.factors = bonds.node_factors.data();
  in.n = b.n;
  in.entries = static_cast<int>(bonds.entries());
  in.blocks = row_blocks(b.n, in.entries);
  in.planar = nodes_in_one_plane(b.n, in.z);
  return in;
}

RowInputs row_inputs_with_outputs(const PdLpsTable& lps, const PdGrains& grains, const BondList& bonds,
                                  PdNodes& nodes) {
  RowInputs in = row_inputs(lps, grains, bonds, nodes);
  in.theta = nodes.theta.data();
  in.fx = nodes.fx.data();
  in.fy = nodes.fy.data();
  in.fz = nodes.fz.data();
  return in;
}

// The kernels' loops over row blocks. Every pointer is copied into a local and RowInputs is rebuilt inside
// the loop: an offload build maps each local pointer to its device copy, which it does not do for pointers
// inside a struct.
#define DEBRIS_PD_ROW_LOCALS(h)                                                                            \
  const int *offset = h.offset, *partner = h.partner, *grain = h.grain, *material = h.material;            \
  const double *length0 = h.length0, *weight = h.weight, *x = h.x, *y = h.y, *z = h.z, *volume = h.volume, *m = h.m;           \
  const PdLpsConstants* lps = h.lps;                                                                       \
  unsigned char* broken = h.broken;                                                                        \
  double *theta = h.theta, *factors = h.factors, *fx = h.fx, *fy = h.fy, *fz = h.fz; \
  const int n = h.n, blocks = h.blocks, entries = h.entries;                                               \
  const int do_break = h.do_break, do_theta = h.do_theta, do_factors = h.do_factors, planar = h.planar

#define DEBRIS_PD_ROW_INPUTS                                                                                         \
  RowInputs {                                                                                                        \
    offset, partner, length0, weight, broken, grain, material, lps, x, y, z, volume, m, theta, factors, fx, fy, fz, \
        n, blocks, entries, do_break, do_theta, do_factors, planar                                                   \
  }

long run_break_and_dilate(const RowInputs& host) {
  DEBRIS_PD_ROW_LOCALS(host);
  DEBRIS_RESIDENT(offset, partner, grain, material, length0, weight, x, y, z, volume, m, lps, broken, theta, factors);
  long marked = 0;
  DEBRIS_KERNEL_SUM(marked)
  for (int b = 0; b < blocks; ++b) {
    const RowInputs in = DEBRIS_PD_ROW_INPUTS;
    marked += break_and_dilate_rows(in, block_row(offset, n, blocks, b), block_row(offset, n, blocks, b + 1));
  }
  return marked;
}

void run_bond_force(const RowInputs& host) {
  DEBRIS_PD_ROW_LOCALS(host);
  DEBRIS_RESIDENT(offset, partner, grain, material, length0, weight, x, y, z, volume, lps, broken, factors, fx, fy, fz);
  DEBRIS_KERNEL
  for (int b = 0; b < blocks; ++b) {
    const RowInputs in = DEBRIS_PD_ROW_INPUTS;
    bond_force_rows(in, block_row(offset, n, blocks, b), block_row(offset, n, blocks, b + 1));
  }
}

#undef DEBRIS_PD_ROW_LOCALS
#undef DEBRIS_PD_ROW_INPUTS

// pd_bond_step's calls by the sweeps they ran (pd_bond_step_counts).
std::atomic<long long> portable_steps{0}, avx2_steps{0};

}  // namespace

bool pd_nodes_in_one_plane(const PdNodes& nodes) {
  return nodes_in_one_plane(static_cast<int>(nodes.size()), nodes.z.data());
}

void pd_dilatation_pass(const PdLpsTable& lps, const PdGrains& grains, const BondList& bonds,
                        PdNodes& nodes) {
  RowInputs in = row_inputs_with_outputs(lps, grains, bonds, nodes);
  in.broken = const_cast<unsigned char*>(bonds.broken.data());  // read only: do_break = 0
  in.do_theta = 1;
  run_break_and_dilate(in);
}

void pd_bond_force_pass(const PdLpsTable& lps, const PdGrains& grains, const BondList& bonds,
                        PdNodes& nodes) {
  RowInputs in = row_inputs_with_outputs(lps, grains, bonds, nodes);
  in.broken = const_cast<unsigned char*>(bonds.broken.data());  // read only
  // The node factors from the theta column (whoever computed it).
  const int n = in.n;
  const int* __restrict offset = in.offset;
  const int* __restrict grain = in.grain, * __restrict material = in.material;
  const PdLpsConstants* __restrict table = in.lps;
  const double* __restrict theta = in.theta, * __restrict m = in.m;
  double* __restrict factors = in.factors;
  DEBRIS_RESIDENT(offset, grain, material, table, theta, m, factors);
  DEBRIS_KERNEL
  for (int i = 0; i < n; ++i) {
    const LpsNodeFactors f =
        offset[i] == offset[i + 1] ? LpsNodeFactors{} : lps_node_factors(table[material[grain[i]]], theta[i], m[i]);
    factors[2 * i] = f.p;
    factors[2 * i + 1] = f.q;
  }
  run_bond_force(in);
}

long pd_bond_step(const PdLpsTable& lps, const PdGrains& grains, BondList& bonds, PdNodes& nodes) {
  // Break, dilatation and node factors in one pass over the bonds (row i breaks its own entries before it
  // sums them, which is what the separate passes do), then the force.
  RowInputs in = row_inputs_with_outputs(lps, grains, bonds, nodes);
  in.broken = bonds.broken.data();
  in.do_break = in.do_theta = in.do_factors = 1;
  // The one choice of back end: the same sweeps written with AVX2 intrinsics where the build has them and the
  // CPU runs them (pd_bond_passes_avx2.cpp), the same bits faster.
  static const pd_rows::BondStepSweeps avx2 = pd_rows::avx2_bond_step_sweeps();
  if (avx2) {
    avx2_steps.fetch_add(1, std::memory_order_relaxed);
    return avx2(in, bonds) / 2;
  }
  portable_steps.fetch_add(1, std::memory_order_relaxed);
  const long broke = run_break_and_dilate(in) / 2;
  run_bond_force(in);
  return broke;
}

PdBondStepCounts pd_bond_step_counts() {
  return {portable_steps.load(std::memory_order_relaxed), avx2_steps.load(std::memory_order_relaxed)};
}

void pd_damage_pass(const PdLpsTable& lps, const PdGrains& grains, const BondList& bonds,
                    PdNodes& nodes, double* broken_fraction) {
  const BondView b = view(lps, grains, bonds, nodes);
  const int n = b.n;
  const int* __restrict offset = b.offset, * __restrict partner = b.partner;
  const int* __restrict grain = b.grain, * __restrict material = b.material;
  const double* __restrict length0 = b.length0;
  const PdLpsConstants* __restrict table = b.lps;
  const unsigned char* __restrict broken = bonds.broken.data();
  const double* __restrict x = nodes.x.data(), * __restrict y = nodes.y.data(), * __restrict z = nodes.z.data();
  double* __restrict damage = nodes.damage.data();
  double* __restrict fraction = broken_fraction;
  DEBRIS_RESIDENT(offset, partner, grain, material, length0, table, broken, x, y, z, damage, fraction);
  DEBRIS_KERNEL
  for (int i = 0; i < n; ++i) {
    double z_max = 0.0;
    int n_broken = 0;
    if (offset[i] < offset[i + 1]) {
      const double s0 = table[material[grain[i]]].critical_stretch;
      const Vec3 yi{x[i], y[i], z[i]};
      for (int k = offset[i]; k < offset[i + 1]; ++k) {
        const int j = partner[k];
        const double s = std::fabs(lps_stretch(norm(Vec3{x[j], y[j], z[j]} - yi), length0[k]));
        z_max = s > z_max ? s : z_max;
        n_broken += broken[k];
      }
      z_max /= s0;  // 0 when s_0 is infinite
    }
    damage[i] = z_max;
    if (fraction) {
      const int count = offset[i + 1] - offset[i];
      fraction[i] = count > 0 ? static_cast<double>(n_broken) / count : 0.0;
    }
  }
}

namespace {

DEBRIS_DECLARE_TARGET
// W_i of the LPS (pd_material.hpp), from the theta column.
inline double node_energy_density(int i, const int* offset, const int* partner, const double* length0,
                                  const unsigned char* broken, const PdLpsConstants& c, const double* x,
                                  const double* y, const double* z, const double* volume, const double* m,
                                  const double* theta) {
  const Vec3 yi{x[i], y[i], z[i]};
  const double theta_i = theta[i];
  double w = lps_dilatation_energy(c, theta_i), m_intact = 0.0;
  for (int k = offset[i]; k < offset[i + 1]; ++k) {
    if (broken[k]) continue;
    const int j = partner[k];
    const double x0 = length0[k], J = lps_influence(x0 / c.horizon);
    const double e = norm(Vec3{x[j], y[j], z[j]} - yi) - x0;
    w += lps_deviatoric_energy_term(c, J, x0, e, theta_i, m[i], volume[j]);
    m_intact += lps_weighted_volume_term(J, x0, volume[j]);
  }
  return w + lps_broken_bond_energy(c, theta_i, m[i], m_intact);
}
DEBRIS_END_DECLARE_TARGET

}  // namespace

void pd_energy_density_pass(const PdLpsTable& lps, const PdGrains& grains, const BondList& bonds,
                            const PdNodes& nodes, double* energy_density) {
  const BondView b = view(lps, grains, bonds, nodes);
  const int n = b.n;
  const int *offset = b.offset, *partner = b.partner, *grain = b.grain, *material = b.material;
  const double* length0 = b.length0;
  const PdLpsConstants* table = b.lps;
  const unsigned char* broken = bonds.broken.data();
  const double *x = nodes.x.data(), *y = nodes.y.data(), *z = nodes.z.data();
  const double *volume = nodes.volume.data(), *m = nodes.weighted_volume.data(), *theta = nodes.theta.data();
  double* __restrict out = energy_density;
  DEBRIS_RESIDENT(offset, partner, grain, material, length0, table, broken, x, y, z, volume, m, theta, out);
  DEBRIS_KERNEL
  for (int i = 0; i < n; ++i) {
    out[i] = offset[i] == offset[i + 1] ? 0.0
                                        : node_energy_density(i, offset, partner, length0, broken,
                                                              table[material[grain[i]]], x, y, z, volume, m, theta);
  }
}

double pd_elastic_energy(const PdLpsTable& lps, const PdGrains& grains, const BondList& bonds,
                         const PdNodes& nodes) {
  const int n = static_cast<int>(nodes.size());
  exec::DeviceVector<double> density(static_cast<std::size_t>(n));  // W_i; 0 for nodes without bonds
  pd_energy_density_pass(lps, grains, bonds, nodes, density.data());
  const double* volume = nodes.volume.data();
  const double* w = density.data();
  // Fixed-order blocks of nodes (core/block_sums.hpp): the same bits on any thread count.
  const int blocks = sum_blocks(n);
  BlockPartials partials;
  double* part = partials.reserve(static_cast<std::size_t>(blocks));
  DEBRIS_RESIDENT(volume, w, part);
  DEBRIS_KERNEL
  for (int b = 0; b < blocks; ++b) {
    double energy = 0.0;
    const BlockRange r = block_range(b, n);
    for (int i = r.begin; i < r.end; ++i) energy += volume[i] * w[i];
    part[b] = energy;
  }
  partials.to_host(static_cast<std::size_t>(blocks));
  return partials.add_up<1>(blocks)[0];
}

}  // namespace debris
