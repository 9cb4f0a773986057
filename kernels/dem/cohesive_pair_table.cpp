#include "kernels/dem/cohesive_pair_table.hpp"


#include "core/exec.hpp"
#include "core/neighbor_list.hpp"
#include "core/particles.hpp"
#include "core/resize_for_overwrite.hpp"

namespace debris {

void CohesivePairTable::build(const CohesiveCoefficients& c, const Particles& p, const NeighborList& list) {
  resize_for_overwrite(delta_f, static_cast<std::size_t>(list.entries()));
  resize_for_overwrite(c_n, static_cast<std::size_t>(list.entries()));
  coefficients = c;
  const int n = list.rows();
  const int* offset = list.offset().data();
  const int* index = list.index().data();
  const double* radius = p.radius.data();
  const double* mass = p.mass.data();
  double* df = delta_f.data();
  double* cn = c_n.data();
  const CohesiveCoefficients coef = c;
  DEBRIS_RESIDENT(offset, index, radius, mass, df, cn);
  DEBRIS_KERNEL
  for (int i = 0; i < n; ++i)
    for (int k = offset[i]; k < offset[i + 1]; ++k) {
      const int j = index[k];
      const CohesivePairParams pp = cohesive_pair_params(coef, radius[i], radius[j], mass[i], mass[j]);
      df[k] = pp.delta_f;  // eq 10 (with its pow) once per pair
      cn[k] = pp.c_n;
    }
}

}  // namespace debris
