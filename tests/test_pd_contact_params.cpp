// PeriDEM contact parameters (kernels/peridem/pd_contact_params.hpp): the stiffness of eq 36, the contact
// radius of eq 25 and the damping of eqs 26-30 against closed forms and the paper's decks; bad values.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "tests/pd_test_grains.hpp"

namespace debris {
namespace {

using namespace pd_test;

TEST(PdContactParams, StiffnessAndRadiusMatchEqs25And36AndThePaperDecks) {
  // two_particle_circ_example/input_0.yaml: K = 2.16e7 Pa, horizon 0.6 mm -> Kn: 1.591549e+24.
  const PdMaterial m1 = material_m1();
  const double h = 1.414e-4;
  const PdContactParams p = pd_contact_params(m1, m1, PdContactSettings{}, h);
  EXPECT_NEAR(p.k_n, 18.0 * 2.16e7 / (std::numbers::pi * std::pow(6e-4, 5)), 1e-14 * p.k_n);
  EXPECT_NEAR(p.k_n / 1.591549e24, 1.0, 1e-6);
  EXPECT_DOUBLE_EQ(p.kappa_eff, 2.16e7);
  EXPECT_DOUBLE_EQ(p.r_c, 0.95 * h);
  EXPECT_EQ(p.mu, 0.0);
  EXPECT_EQ(p.beta_coef, 0.0) << "e_n = 1: no damping";

  // compressive_small_set_ci: particles K = 5e3, walls K = 1e4, horizon 0.4 mm -> 2.797645e21, 3.730194e21.
  PdMaterial grain = m1, wall = m1;
  grain.bulk_modulus = 5e3;
  wall.bulk_modulus = 1e4;
  grain.horizon = wall.horizon = 4e-4;
  EXPECT_NEAR(pd_contact_params(grain, grain, PdContactSettings{}, h).k_n / 2.797645e21, 1.0, 1e-6);
  const PdContactParams gw = pd_contact_params(grain, wall, PdContactSettings{}, h);
  EXPECT_NEAR(gw.k_n / 3.730194e21, 1.0, 1e-6);
  EXPECT_NEAR(gw.kappa_eff, 2.0 * 5e3 * 1e4 / (5e3 + 1e4), 1e-12 * gw.kappa_eff);  // eq 25
  EXPECT_NEAR(gw.k_n, 18.0 * gw.kappa_eff / (std::numbers::pi * std::pow(4e-4, 5)), 1e-13 * gw.k_n);

  // Eq 23's factor, C = 100, e_n = 0.9; friction and Kn_Factor passed through.
  PdContactSettings s = settings(0.9, 0.5);
  s.stiffness_factor = 2.0;
  const PdContactParams q = pd_contact_params(m1, m1, s, h);
  const double l = std::log(0.9);
  EXPECT_NEAR(q.beta_coef, -2.0 * 100.0 * l / std::sqrt(std::numbers::pi * std::numbers::pi + l * l), 1e-13);
  EXPECT_NEAR(pd_damping_coefficient(q, 2e-6),
              -2.0 * 100.0 * l * std::sqrt(2.16e7 * 0.95 * h * 2e-6 / (std::numbers::pi * std::numbers::pi + l * l)),
              1e-12);
  EXPECT_EQ(q.mu, 0.5);
  EXPECT_NEAR(q.k_n, 2.0 * p.k_n, 1e-14 * q.k_n);

  // The table is symmetric bit for bit and its cutoff is the largest R_c.
  const PdContactTable t = pd_contact_table({grain, wall}, settings(0.8, 0.3), h);
  ASSERT_EQ(t.materials, 2);
  EXPECT_EQ(t.pair(0, 1).k_n, t.pair(1, 0).k_n);
  EXPECT_EQ(t.pair(0, 1).kappa_eff, t.pair(1, 0).kappa_eff);
  EXPECT_DOUBLE_EQ(t.max_contact_radius(), 0.95 * h);
}

TEST(PdContactParams, BadValuesThrowInputErrorNamingKeyAndValue) {
  const PdMaterial m = material_m1();
  auto with = [&](auto change) {
    PdContactSettings s;
    change(s);
    return [=] { pd_contact_params(m, m, s, 1e-4); };
  };
  expect_input_error(with([](PdContactSettings& s) { s.restitution = 0.0; }), "contact.restitution", "0");
  expect_input_error(with([](PdContactSettings& s) { s.restitution = 1.5; }), "contact.restitution", "1.5");
  expect_input_error(with([](PdContactSettings& s) { s.restitution = -0.2; }), "contact.restitution", "-0.2");
  expect_input_error(with([](PdContactSettings& s) { s.restitution = std::nan(""); }), "contact.restitution", "nan");
  expect_input_error(with([](PdContactSettings& s) { s.friction = -0.1; }), "contact.friction", "-0.1");
  expect_input_error(with([](PdContactSettings& s) { s.damping_factor = 0.0; }), "contact.damping_factor", "0");
  expect_input_error(with([](PdContactSettings& s) { s.contact_radius_factor = -0.95; }),
                     "contact.contact_radius_factor", "-0.95");
  expect_input_error(with([](PdContactSettings& s) { s.stiffness_factor = 0.0; }), "contact.stiffness_factor", "0");
  expect_input_error([&] { pd_contact_params(m, m, PdContactSettings{}, 0.0); }, "contact.h_min", "0");
  PdMaterial bad = m;
  bad.bulk_modulus = -3.0;
  expect_input_error([&] { pd_contact_params(m, bad, PdContactSettings{}, 1e-4); }, "contact.material_b.bulk_modulus",
                     "-3");
  bad = m;
  bad.horizon = 0.0;
  expect_input_error([&] { pd_contact_params(bad, m, PdContactSettings{}, 1e-4); }, "contact.material_a.horizon", "0");
  // Per-pair settings: the key names the pair; an asymmetric table is refused.
  std::vector<PdContactSettings> pairs(4);
  pairs[1].friction = pairs[2].friction = -1.0;
  expect_input_error([&] { pd_contact_table({m, m}, pairs, 1e-4); }, "contact.0_1.friction", "-1");
  pairs[1].friction = 0.2;
  pairs[2].friction = 0.3;
  expect_input_error([&] { pd_contact_table({m, m}, pairs, 1e-4); }, "contact.1_0", "differs");
}

}  // namespace
}  // namespace debris
