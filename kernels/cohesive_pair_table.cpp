#include "kernels/cohesive_pair_table.hpp"

#include <cmath>

#include "core/exec.hpp"
#include "core/neighbor_list.hpp"
#include "core/particles.hpp"

namespace debris {

void CohesivePairTable::build(const CohesiveCoefficients& c, const Particles& p, const NeighborList& list) {
  delta_f.resize(static_cast<std::size_t>(list.entries()));
  coefficients = c;
  kt_over_kn = c.area_t / c.area_n;
  ct_over_cn = std::sqrt(kt_over_kn);
  const int n = list.rows();
  const int* offset = list.offset().data();
  const int* index = list.index().data();
  const double* radius = p.radius.data();
  double* df = delta_f.data();
  const CohesiveCoefficients coef = c;
  DEBRIS_KERNEL
  for (int i = 0; i < n; ++i)
    for (int k = offset[i]; k < offset[i + 1]; ++k) df[k] = cohesive_delta_f(coef, radius[i] + radius[index[k]]);
}

}  // namespace debris
