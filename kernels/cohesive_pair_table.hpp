#pragma once
// Per-pair constants of the cohesive law (eqs 7-17), one row per neighbour-list entry, computed when the
// list is rebuilt instead of at every step: the force pass then needs no division by r_i + r_j, no m_eff,
// no sqrt for the damping and no pow for eq 10. Recomputed whenever the list, the masses or the material
// change.
#include <vector>

#include "kernels/cohesive_material.hpp"

namespace debris {

class Particles;
class NeighborList;

struct CohesivePairTable {
  std::vector<double> k_n;          // eq 7
  std::vector<double> c_n;          // eq 12
  std::vector<double> delta_e;      // eq 9
  std::vector<double> delta_f;      // eq 10
  std::vector<double> inv_delta_f;  // 1 / delta_f, for eq 5
  std::vector<double> k_soft;       // k_N delta_e / (delta_f - delta_e): slope of the softening branch of eq 3 (0 if none)
  std::vector<double> f_max_t;      // eq 11
  std::vector<double> arm_i;        // r_i / (r_i + r_j): share of the centre distance on i's side
  double kt_over_kn = 0;            // k_T / k_N = A_T / A_N, the same for every pair (eqs 7-8, 15-16)
  double ct_over_cn = 0;            // c_T / c_N = sqrt(k_T / k_N) (eqs 12-13)

  void build(const CohesiveCoefficients& c, const Particles& p, const NeighborList& list);
  std::size_t bytes() const { return 8 * sizeof(double) * k_n.capacity(); }
};

}  // namespace debris
