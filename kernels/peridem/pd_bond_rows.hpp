#pragma once
// What the bond passes' row sweeps share between the portable kernel (pd_bond_passes.cpp) and its AVX2
// variant (pd_bond_passes_avx2.cpp, compiled by x86-64 host builds only): the inputs of a sweep, the blocks
// rows are handed out in, the broken-bond check and the end of a dilatation row. Not part of the API.
#include <cstring>

#include "core/exec.hpp"
#include "kernels/peridem/lps_bond_force.hpp"
#include "kernels/peridem/pd_material.hpp"

namespace debris {

class BondList;

namespace pd_rows {

struct RowInputs {
  const int* offset;
  const int* partner;
  const double* length0;
  const double* weight;   // J V_j of each entry (BondList::weight)
  unsigned char* broken;  // written by the break step only
  const int* grain;
  const int* material;
  const PdLpsConstants* lps;
  const double *x, *y, *z, *volume, *m;
  double* theta;
  double* factors;  // P_i, Q_i (lps_node_factors), interleaved
  double *fx, *fy, *fz;
  int n, blocks, entries;
  int do_break, do_theta, do_factors;
  int planar;  // every node has the same z (nodes_in_one_plane): the sweeps skip z
};

DEBRIS_DECLARE_TARGET

// Bond entries of one row taken per round (staged in local arrays by the portable sweeps, summed in registers
// by the AVX2 ones).
constexpr int kStage = 64;

// First row of block b of `blocks` (block b is [block_row(b), block_row(b + 1))): the first row whose bond
// entries start at or after b / blocks of all entries. With blocks == n it is row b.
inline int block_row(const int* offset, int n, int blocks, int b) {
  if (b >= blocks) return n;
  if (blocks == n) return b;
  const long long target = static_cast<long long>(offset[n]) * b / blocks;
  int lo = 0, hi = n;
  while (lo < hi) {
    const int mid = lo + (hi - lo) / 2;
    if (offset[mid] < target)
      lo = mid + 1;
    else
      hi = mid;
  }
  return lo;
}

// Whether any of entries [k0, k0 + count) is broken (h = 0 in eqs 12-13), whole words of bytes at a time.
// Most rows have none: their sweeps then take every entry as intact.
inline bool any_broken(const unsigned char* broken, int k0, int count) {
  unsigned long long any = 0;
  int t = 0;
  for (; t + 8 <= count; t += 8) {
    unsigned long long word;
    std::memcpy(&word, broken + k0 + t, sizeof word);
    any |= word;
  }
  if (t < count && count >= 8) {  // the last 8 bytes, overlapping the words before: no byte loop
    unsigned long long word;
    std::memcpy(&word, broken + k0 + count - 8, sizeof word);
    any |= word;
  } else {
    for (; t < count; ++t) any |= broken[k0 + t];
  }
  return any != 0;
}

// The end of row i of a dilatation sweep, from its sum over the intact bonds: theta_i of eq 34 (do_theta) and
// the node factors P_i, Q_i (do_factors), which the force sweep reads. A row without bonds (walls) has none.
DEBRIS_ALWAYS_INLINE void finish_dilatation_row(const RowInputs& in, int i, const PdLpsConstants* c, double sum) {
  const double m_i = in.m[i];
  const double theta_i = c ? lps_dilatation(*c, sum, m_i) : 0.0;
  if (in.do_theta) in.theta[i] = theta_i;
  if (in.do_factors) {
    const LpsNodeFactors f = c ? lps_node_factors(*c, theta_i, m_i) : LpsNodeFactors{};
    in.factors[2 * i] = f.p;
    in.factors[2 * i + 1] = f.q;
  }
}

DEBRIS_END_DECLARE_TARGET

// Both sweeps of pd_bond_step (break + dilatation + node factors, then force) over all rows; returns the
// entries marked broken.
using BondStepSweeps = long (*)(const RowInputs& in, BondList& bonds);

// pd_bond_step's sweeps written with AVX2 intrinsics where this build has them (x86-64 host builds:
// pd_bond_passes_avx2.cpp) and the CPU runs them (AVX2 and FMA); null elsewhere (pd_bond_passes_no_avx2.cpp).
BondStepSweeps avx2_bond_step_sweeps();

}  // namespace pd_rows
}  // namespace debris
