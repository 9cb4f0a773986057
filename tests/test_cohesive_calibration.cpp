// Force parameters of eqs 7-19 for the two materials of the paper (Table 4 and Table 5), against values
// computed independently from the printed equations (literals below), and the material checks.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "core/error.hpp"
#include "core/particles.hpp"
#include "kernels/dem/cohesive_material.hpp"

namespace debris {
namespace {

CohesiveMaterial table4(double s = 0.0) { return table4_material(s); }

CohesiveMaterial silica() { return silica_material(); }

double sphere_mass(double rho, double r) { return rho * 4.0 / 3.0 * std::numbers::pi * r * r * r; }

void expect_rel(double actual, double expected, double tol = 1e-13) {
  EXPECT_NEAR(actual, expected, tol * std::abs(expected)) << "expected " << expected;
}

TEST(CohesiveCalibration, Table4CriticalAndMinimumDiameters) {
  // Section 3: "we compute the minimum allowed particle size d_min = 30 (19) and d_c = 150 (18)".
  expect_rel(table4().minimum_diameter(), 30.0);
  expect_rel(table4().critical_diameter(), 150.0);
}

TEST(CohesiveCalibration, SilicaCriticalAndMinimumDiameters) {
  // Section 4: "d_min = 0.37 nm (19) and d_c = 1.7 nm (18)".
  expect_rel(silica().minimum_diameter(), 3.75e-10);
  expect_rel(silica().critical_diameter(), 1.7109375e-9);
  EXPECT_NEAR(silica().minimum_diameter(), 0.37e-9, 0.01e-9);
  EXPECT_NEAR(silica().critical_diameter(), 1.7e-9, 0.05e-9);
}

TEST(CohesiveCalibration, Table4BelowCriticalDiameter) {
  const auto c = CohesiveCoefficients::from(table4());
  const double m = sphere_mass(1.0, 50.0);
  const CohesivePairParams p = cohesive_pair_params(c, 50.0, 50.0, m, m);  // d = 100 < d_c
  expect_rel(p.k_n, 50.5076272276105);
  expect_rel(p.k_t, 17.5678703400385);
  expect_rel(p.delta_e, 20.0);
  expect_rel(p.delta_f, 30.0);  // 4 gamma / sigma: the whole range of eq 10's first branch
  expect_rel(p.f_max_t, 175.678703400385);
  expect_rel(p.c_n, 115.74784761942);
  expect_rel(p.c_t, 68.2643562949048);
  expect_rel(critical_time_step(p.k_n, 0.5 * m), 143.991158448725);
  expect_rel(critical_time_step(p.k_n, 0.5 * m), std::sqrt(2 * m / p.k_n));  // eq 6 == A.17 for equal masses
  expect_rel(critical_damping(p.k_n, 0.5 * m), std::sqrt(2 * p.k_n * m));    // eq 21 == A.19
}

TEST(CohesiveCalibration, Table4AboveCriticalDiameterBothScalings) {
  const double m = sphere_mass(1.0, 150.0);
  // d = 300 = 2 d_c. s = 0.5: delta_f = delta_e (2)^-1/2; s = 0: delta_f = delta_e (constant strength).
  const CohesivePairParams half = cohesive_pair_params(CohesiveCoefficients::from(table4(0.5)), 150, 150, m, m);
  expect_rel(half.k_n, 151.522881682832);
  expect_rel(half.k_t, 52.7036110201154);
  expect_rel(half.delta_e, 60.0);
  expect_rel(half.delta_f, 42.4264068711928);
  expect_rel(half.f_max_t, 1581.10833060346);
  expect_rel(half.c_n, 1041.73062857478);
  expect_rel(half.c_t, 614.379206654143);
  const CohesivePairParams zero = cohesive_pair_params(CohesiveCoefficients::from(table4(0.0)), 150, 150, m, m);
  expect_rel(zero.delta_f, 60.0);
  expect_rel(zero.delta_e, 60.0);
  // Eq 20: the matched strength k_N delta_e / A_N stays sigma for s = 0, the surface energy for s = 0.5.
  const double a_n = std::numbers::sqrt2 * 150.0 * 150.0 / (1 - 2 * 0.15);
  expect_rel(zero.k_n * zero.delta_e / a_n, 0.2);
  // s = 0.5 makes delta_f < delta_e: the force is Hookean up to delta_f, then zero (Fig A.2). The work of
  // separation (1/2) k_N delta_f^2 over the two new surfaces 2 A_N is gamma again (eqs A.31-A.33).
  expect_rel(0.5 * half.k_n * half.delta_f * half.delta_f / (2 * a_n), 1.5);
  expect_rel(half.k_n * half.delta_f / a_n, 0.2 * std::pow(2.0, -0.5));  // eq 20: sigma (d/d_c)^-s
}

TEST(CohesiveCalibration, Table4UnequalSizesUseSmallerRadius) {
  const auto c = CohesiveCoefficients::from(table4());
  const CohesivePairParams p = cohesive_pair_params(c, 40, 70, sphere_mass(1, 40), sphere_mass(1, 70));
  expect_rel(p.k_n, 29.3862558415189);
  expect_rel(p.k_t, 10.2213063796587);
  expect_rel(p.delta_e, 22.0);
  expect_rel(p.delta_f, 30.0);
  expect_rel(p.f_max_t, 112.434370176246);
  expect_rel(p.c_n, 82.0174763410768);
  expect_rel(p.c_t, 48.3712686024655);
  // The pair is symmetric in (i, j).
  const CohesivePairParams q = cohesive_pair_params(c, 70, 40, sphere_mass(1, 70), sphere_mass(1, 40));
  EXPECT_EQ(p.k_n, q.k_n);
  EXPECT_EQ(p.c_t, q.c_t);
}

TEST(CohesiveCalibration, SilicaPairs) {
  const auto c = CohesiveCoefficients::from(silica());
  const double r = 0.75e-9, m = sphere_mass(2200, r);
  const CohesivePairParams p = cohesive_pair_params(c, r, r, m, m);  // d0 = 1.5 nm < d_c
  expect_rel(p.k_n, 58.6577216211568, 1e-12);
  expect_rel(p.k_t, 16.0431375374104, 1e-12);
  expect_rel(p.delta_e, 3.28767123287671e-10, 1e-12);
  expect_rel(p.delta_f, 3.75e-10, 1e-12);
  expect_rel(p.f_max_t, 2.96688159938412e-09, 1e-12);
  expect_rel(p.c_n, 6.79790764980309e-13, 1e-12);
  expect_rel(p.c_t, 3.55514500081514e-13, 1e-12);
  expect_rel(critical_time_step(p.k_n, 0.5 * m), 3.64082615931343e-13, 1e-12);
  // 3 nm + 6 nm diameters: above d_c, s = 0.5.
  const CohesivePairParams q =
      cohesive_pair_params(c, 1.5e-9, 3e-9, sphere_mass(2200, 1.5e-9), sphere_mass(2200, 3e-9));
  expect_rel(q.k_n, 78.2102954948757, 1e-12);
  expect_rel(q.delta_e, 9.86301369863014e-10, 1e-12);
  expect_rel(q.delta_f, 6.08163640559537e-10, 1e-12);
  expect_rel(q.f_max_t, 1.18675263975365e-08, 1e-12);
  expect_rel(q.c_n, 2.96024978854755e-12, 1e-12);
  expect_rel(q.c_t, 1.54814066019619e-12, 1e-12);
}

TEST(CohesiveCalibration, PoissonRatioLimits) {
  CohesiveMaterial m = table4();
  m.poisson_ratio = 0.25;  // k_T = 0 at the upper limit, still valid
  EXPECT_EQ(CohesiveCoefficients::from(m).area_t, 0.0);
  m.poisson_ratio = 0.26;
  try {
    CohesiveCoefficients::from(m);
    FAIL() << "nu = 0.26 accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("material.poisson_ratio"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("0.26"), std::string::npos) << e.what();
  }
  m.poisson_ratio = -1.0;
  EXPECT_THROW(CohesiveCoefficients::from(m), InputError);
  m = table4();
  m.youngs_modulus = -1;
  EXPECT_THROW(CohesiveCoefficients::from(m), InputError);
  m = table4();
  m.restitution = 1.5;
  EXPECT_THROW(CohesiveCoefficients::from(m), InputError);
}

TEST(CohesiveCalibration, StabilityLimitsPickTheSmallestParticle) {
  Particles p;
  p.add(0, 1, 0, 0, 0, 60.0);
  p.add(1, 1, 200, 0, 0, 45.0);
  p.add(2, 1, 400, 0, 0, 50.0);
  p.set_mass_from_density(1.0);
  const auto c = CohesiveCoefficients::from(table4());
  const StabilityLimits s = stability_limits(c, p);
  EXPECT_EQ(s.particle, 1);
  const CohesivePairParams pp = cohesive_pair_params(c, 45, 45, p.mass[1], p.mass[1]);
  expect_rel(s.dt_c, std::sqrt(2 * p.mass[1] / pp.k_n));
  expect_rel(s.c_c, std::sqrt(2 * pp.k_n * p.mass[1]));
}

}  // namespace
}  // namespace debris
