#include "kernels/cohesive_pair_table.hpp"

#include <cmath>

#include "core/exec.hpp"
#include "core/neighbor_list.hpp"
#include "core/particles.hpp"

namespace debris {

void CohesivePairTable::build(const CohesiveCoefficients& c, const Particles& p, const NeighborList& list) {
  const std::size_t m = static_cast<std::size_t>(list.entries());
  for (auto* v : {&k_n, &c_n, &delta_e, &delta_f, &inv_delta_f, &k_soft, &f_max_t, &arm_i}) v->resize(m);
  kt_over_kn = c.area_t / c.area_n;
  ct_over_cn = std::sqrt(kt_over_kn);
  const int n = list.rows();
  const int* offset = list.offset().data();
  const int* index = list.index().data();
  const double *radius = p.radius.data(), *mass = p.mass.data();
  double *kn = k_n.data(), *cn = c_n.data(), *de = delta_e.data(), *df = delta_f.data(), *idf = inv_delta_f.data();
  double *ks = k_soft.data(), *fmt = f_max_t.data(), *arm = arm_i.data();
  const CohesiveCoefficients coef = c;
  DEBRIS_KERNEL
  for (int i = 0; i < n; ++i) {
    for (int k = offset[i]; k < offset[i + 1]; ++k) {
      const int j = index[k];
      const CohesivePairParams pp = cohesive_pair_params(coef, radius[i], radius[j], mass[i], mass[j]);
      kn[k] = pp.k_n;
      cn[k] = pp.c_n;
      de[k] = pp.delta_e;
      df[k] = pp.delta_f;
      idf[k] = 1.0 / pp.delta_f;
      ks[k] = pp.delta_f > pp.delta_e ? pp.k_n * pp.delta_e / (pp.delta_f - pp.delta_e) : 0.0;
      fmt[k] = pp.f_max_t;
      arm[k] = radius[i] / (radius[i] + radius[j]);
    }
  }
}

}  // namespace debris
