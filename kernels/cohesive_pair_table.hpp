#pragma once
// Per-pair data of the cohesive law kept with the neighbour list, for the host pass: delta_f of eq 10,
// which for d > d_c and s other than 0 needs a pow, computed once per rebuild. The other constants of
// eqs 7-17 are cheaper to recompute in the vectorised pair loop than to stream from memory (measured: the
// host pass went from 4.2 to 5.3 M particles/s at N = 256,000 when an 8-double table became this one).
// Recomputed whenever the list, the masses or the material change.
#include <vector>

#include "kernels/cohesive_material.hpp"

namespace debris {

class Particles;
class NeighborList;

struct CohesivePairTable {
  std::vector<double> delta_f;          // eq 10, per neighbour-list entry
  CohesiveCoefficients coefficients{};  // the material constants of eqs 7-18
  double kt_over_kn = 0;                // k_T / k_N = A_T / A_N, the same for every pair (eqs 7-8, 15-16)
  double ct_over_cn = 0;                // c_T / c_N = sqrt(k_T / k_N) (eqs 12-13)

  void build(const CohesiveCoefficients& c, const Particles& p, const NeighborList& list);
  std::size_t bytes() const { return sizeof(double) * delta_f.capacity(); }
};

}  // namespace debris
