#pragma once
// Cohesive coarse-grained DEM (Pham-Ba & Molinari, shared/papers/cohesive-dem-adhesive-wear.md):
// target material properties (Table 3 + scaling s) and the per-pair force parameters computed from them
// by eqs 7-18, the critical time step (eq 6 / A.17) and the critical damping (eq 21 / A.19).
#include <cmath>

#include "core/exec.hpp"

namespace debris {

class Particles;

/// Table 3 of the paper plus the size-scaling exponent s of eq 10.
struct CohesiveMaterial {
  double youngs_modulus = 0;    // E
  double poisson_ratio = 0;     // nu, in (-1, 0.25]
  double tensile_strength = 0;  // sigma_{m,N}
  double shear_strength = 0;    // sigma_{m,T}
  double surface_energy = 0;    // gamma
  double restitution = 1;       // eta, in (0, 1]
  double density = 0;           // rho
  double scaling = 0;           // s >= 0 (0: constant strength, 0.5: constant surface energy)

  /// Throws InputError naming `prefix.key` for the first property out of its valid range.
  void validate(const char* prefix = "material") const;

  double critical_diameter() const;  // d_c, eq 18
  double minimum_diameter() const;   // d_min, eq 19
};

/// Table 4 of the paper: the material of the patch tests (no units; d_min = 30, d_c = 150).
CohesiveMaterial table4_material(double scaling = 0.0);
/// Table 5: amorphous silica, SI units (d_min = 0.375 nm, d_c = 1.71 nm), with s = 0.5 as in section 4.
CohesiveMaterial silica_material();

/// The seven force parameters of Table 2 for one pair.
struct CohesivePairParams {
  double k_n;      // normal stiffness, eq 7
  double k_t;      // tangential stiffness, eq 8
  double delta_e;  // elastic separation, eq 9
  double delta_f;  // fracture separation, eq 10
  double f_max_t;  // maximum tangential force, eq 11
  double c_n;      // normal damping, eq 12
  double c_t;      // tangential damping, eq 13
};

/// Material constants folded once on the host so that a kernel evaluates eqs 7-18 with a few multiplies.
struct CohesiveCoefficients {
  double E;
  double area_n;       // A_N / r_eff^2 = sqrt(2) / (1 - 2 nu), eq 15
  double area_t;       // A_T / r_eff^2 = sqrt(2) (1 - 4 nu) / ((1 - 2 nu)(1 + nu)), eq 16
  double strain_e;     // sigma_{m,N} / E, so that delta_e = (r_i + r_j) strain_e, eq 9
  double delta_f_min;  // 4 gamma / sigma_{m,N}, eq 10 for r_i + r_j <= d_c
  double d_c;          // eq 18
  double s;            // scaling exponent of eq 10
  double sigma_t;      // sigma_{m,T}, eq 11
  double damping;      // 2 (1 - eta) / pi, eqs 12-13
  double kt_over_kn;   // k_T / k_N = A_T / A_N, the same for every pair (eqs 7-8, 15-16)
  double ct_over_cn;   // c_T / c_N = sqrt(k_T / k_N) (eqs 12-13)

  static CohesiveCoefficients from(const CohesiveMaterial& m);
};

DEBRIS_DECLARE_TARGET

/// Fracture separation of eq 10 for a pair whose radii sum to `radsum`.
inline double cohesive_delta_f(const CohesiveCoefficients& c, double radsum) {
  if (radsum <= c.d_c) return c.delta_f_min;
  const double delta_e = radsum * c.strain_e;
  if (c.s == 0.0) return delta_e;
  return delta_e * std::pow(radsum / c.d_c, -c.s);
}

/// Eqs 7-17 for particles of radii r_i, r_j and masses m_i, m_j.
inline CohesivePairParams cohesive_pair_params(const CohesiveCoefficients& c, double ri, double rj, double mi,
                                               double mj) {
  const double radsum = ri + rj;
  const double r_eff = ri < rj ? ri : rj;        // eq 14
  const double a_n = c.area_n * r_eff * r_eff;    // eq 15
  const double a_t = c.area_t * r_eff * r_eff;    // eq 16
  const double m_eff = mi * mj / (mi + mj);       // eq 17
  CohesivePairParams p;
  p.k_n = a_n * c.E / radsum;                      // eq 7
  p.k_t = a_t * c.E / radsum;                      // eq 8
  p.delta_e = radsum * c.strain_e;                 // eq 9
  p.delta_f = cohesive_delta_f(c, radsum);         // eq 10
  p.f_max_t = a_t * c.sigma_t;                     // eq 11
  p.c_n = c.damping * std::sqrt(p.k_n * m_eff);    // eq 12
  p.c_t = c.damping * std::sqrt(p.k_t * m_eff);    // eq 13
  return p;
}

/// Interaction cutoff of a pair: centres closer than r_i + r_j + delta_f interact (never cut shorter).
struct CohesiveCutoff {
  CohesiveCoefficients c;
  double operator()(double ri, double rj) const { return ri + rj + cohesive_delta_f(c, ri + rj); }
};

DEBRIS_END_DECLARE_TARGET

/// Stability limit of the semi-implicit Euler scheme for one Hookean pair, eq A.17: 2 sqrt(m_eff / k_N).
double critical_time_step(double k_n, double m_eff);

/// Critical damping of one pair, eq A.19: 2 sqrt(k_N m_eff); equals eq 21, sqrt(2 k_N m), for equal masses.
double critical_damping(double k_n, double m_eff);

/// Eq 6 and eq 21 for the most restrictive particle of a system (the smallest, for one density): the
/// pair of two copies of that particle. Frozen and driven particles count too, since they still
/// interact with free ones.
struct StabilityLimits {
  double dt_c;     // critical time step, eq 6
  double c_c;      // critical damping, eq 21, for the same particle
  long particle;   // index of the particle that sets both
};
StabilityLimits stability_limits(const CohesiveCoefficients& c, const Particles& p);

}  // namespace debris
