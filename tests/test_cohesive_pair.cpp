// The cohesive pair law (eqs 2-5) against its closed forms, for a two-particle pull-out and shear cycles
// driven by prescribed motion, in every regime: d below and above d_c, s = 0 and 0.5, unequal sizes, with
// and without damping. The closed forms below are written out from the paper independently of the kernel.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <string>

#include "kernels/dem/cohesive_pair_force.hpp"

namespace debris {
namespace {

struct Regime {
  std::string name;
  double ri, rj, s, eta;
};

CohesiveCoefficients coefficients(const Regime& r) {
  CohesiveMaterial m = table4_material(r.s);  // d_min = 30, d_c = 150
  m.restitution = r.eta;
  return CohesiveCoefficients::from(m);
}

double mass_of(double r) { return 4.0 / 3.0 * std::numbers::pi * r * r * r; }

// Eq 3, written out.
double eq3(double kn, double de, double df, double dn) {
  if (dn > df) return 0.0;  // also when eq 10 makes delta_f < delta_e (d > d_c, s > 0): a cliff at delta_f
  if (dn <= de) return kn * dn;
  if (dn <= df) return -kn * de / (df - de) * (dn - df);
  return 0.0;
}
// Eq 5, written out.
double eq5(double fmt, double df, double dn) { return std::min((df - dn) / df, 1.0) * fmt; }

void expect_close(double actual, double expected, double scale, const std::string& what) {
  EXPECT_NEAR(actual, expected, 1e-12 * scale) << what;
}

// One end of a pair handed to the evaluator as the passes hand it: delta_f and c_N from the pair's
// parameters, i first unless told otherwise.
CohesivePairResult pair_force(const CohesiveCoefficients& c, const CohesivePairParams& p, const CohesiveOptions& opt,
                              Vec3 dx, double ri, double rj, Vec3 vi, Vec3 vj, Vec3 wi, Vec3 wj, Vec3& h, double dt,
                              int update, int i_first = 1) {
  const CohesivePairResult out =
      cohesive_pair_force(c, opt, CohesivePair{dx, ri, rj, p.delta_f, p.c_n, vi - vj, wi, wj, h, i_first}, dt, update);
  h = out.history;
  return out;
}

// F_N of eq 3 as the evaluator gives it: a pair at rest along x with no history (F_x = -F_N).
double normal_force(const CohesiveCoefficients& c, const CohesivePairParams& p, double ri, double rj, double dn) {
  Vec3 h{};
  return -pair_force(c, p, CohesiveOptions{}, Vec3{ri + rj + dn, 0, 0}, ri, rj, Vec3{}, Vec3{}, Vec3{}, Vec3{}, h, 0.0,
                     0)
              .force.x;
}

class CohesivePairLaw : public ::testing::TestWithParam<Regime> {
 protected:
  void SetUp() override {
    const Regime& r = GetParam();
    c = coefficients(r);
    p = cohesive_pair_params(c, r.ri, r.rj, mass_of(r.ri), mass_of(r.rj));
    // A force scale for tolerances: the elastic limit force.
    scale = p.k_n * p.delta_e + p.f_max_t;
  }
  CohesiveCoefficients c{};
  CohesivePairParams p{};
  double scale = 1;
};

// Pull-out along x at speed v, from compression through the elastic and softening ranges to beyond
// delta_f, then back again: the force follows eq 3 plus c_N v_N both ways (reversible), zero beyond delta_f.
TEST_P(CohesivePairLaw, PullOutAndReturnFollowsEq3) {
  const Regime& r = GetParam();
  const double start = -0.4 * p.delta_e, end = 1.25 * p.delta_f, steps = 400;
  const double dt = 1.0, v = (end - start) / steps;
  Vec3 h{};
  int seen_soft = 0, seen_free = 0, seen_tension = 0, seen_compression = 0;
  for (int pass = 0; pass < 2; ++pass) {
    const double vel = pass == 0 ? v : -v;
    for (int s = 0; s <= steps; ++s) {
      const double dn = pass == 0 ? start + s * v : end - s * v;
      const Vec3 dx{r.ri + r.rj + dn, 0, 0};
      const CohesivePairResult out =
          pair_force(c, p, CohesiveOptions{}, dx, r.ri, r.rj, Vec3{vel, 0, 0}, Vec3{}, Vec3{}, Vec3{}, h, dt, 1);
      const double expected = dn <= p.delta_f ? -(eq3(p.k_n, p.delta_e, p.delta_f, dn) + p.c_n * vel) : 0.0;
      expect_close(out.force.x, expected, scale, "dN = " + std::to_string(dn));
      EXPECT_EQ(out.force.y, 0.0);
      EXPECT_EQ(out.force.z, 0.0);
      EXPECT_EQ(norm(out.torque), 0.0);
      EXPECT_NEAR(out.delta_n, dn, 1e-12 * (r.ri + r.rj));
      EXPECT_EQ(out.interacting, dn <= p.delta_f ? 1 : 0);
      seen_compression += dn < 0;
      seen_tension += dn > 0 && dn <= p.delta_e;
      seen_soft += dn > p.delta_e && dn <= p.delta_f;
      seen_free += dn > p.delta_f;
    }
  }
  EXPECT_GT(seen_compression, 0);
  EXPECT_GT(seen_tension, 0);
  EXPECT_GT(seen_free, 0);
  if (p.delta_f > p.delta_e) EXPECT_GT(seen_soft, 0);
  if (r.eta == 1.0) EXPECT_EQ(p.c_n, 0.0);
}

// The peak force is the matched tensile strength of eq 20 times A_N (eqs 3, 9, 10, 15): sigma below d_c,
// sigma (d/d_c)^-s above it, reached at min(delta_e, delta_f).
TEST_P(CohesivePairLaw, PeakForceIsMatchedStrengthTimesArea) {
  const Regime& r = GetParam();
  const double r_eff = std::min(r.ri, r.rj), d = r.ri + r.rj;
  const double a_n = std::numbers::sqrt2 * r_eff * r_eff / (1 - 2 * 0.15);
  const double sigma = 0.2 * (d > 150.0 ? std::pow(d / 150.0, -r.s) : 1.0);
  // Just inside the peak: the evaluator recovers dN from the centres' distance (to an ulp of r_i + r_j + dN),
  // and where delta_f < delta_e the peak sits on the cliff at delta_f.
  const double peak_at = std::min(p.delta_e, p.delta_f) * (1 - 1e-13);
  EXPECT_NEAR(normal_force(c, p, r.ri, r.rj, peak_at), sigma * a_n, 1e-12 * sigma * a_n);
  EXPECT_EQ(normal_force(c, p, r.ri, r.rj, p.delta_f * (1 + 1e-12)), 0.0);
  // The work to separate a touching pair is 2 A_N gamma (eq A.33) for s = 0.5 or below d_c.
  if (d <= 150.0 || r.s == 0.5)
    EXPECT_NEAR(-cohesive_normal_energy(p, 0.0), 2 * a_n * 1.5, 1e-12 * 2 * a_n * 1.5);
}

// Shear cycle driven by a prescribed spin of i at fixed separation (the relative position, hence n, never
// changes): the contact point slides at a_i w, the history grows linearly, is capped at F'_mT / k_T (eq 4
// with eq 5), reverses, and is capped at the opposite bound. Forces and torques against the closed form.
TEST_P(CohesivePairLaw, SpinDrivenShearCycleFollowsEqs4And5) {
  const Regime& r = GetParam();
  std::vector<double> separations{-0.3 * p.delta_e, 0.5 * p.delta_e};
  if (p.delta_f > p.delta_e) separations.push_back(0.5 * (p.delta_e + p.delta_f));
  for (double dn : separations) {
    const double d = r.ri + r.rj + dn;
    const double a_i = d * r.ri / (r.ri + r.rj);
    const double cap = eq5(p.f_max_t, p.delta_f, dn);
    const double dt = 0.5, w = cap / p.k_t / 20.0 / (a_i * dt);  // 20 steps from zero to the cap
    const Vec3 dx{0, d, 0};                                      // n = +y
    Vec3 h{};
    double h_expected = 0.0;
    const int phases[4] = {30, -60, 60, -10};
    int slipped = 0;
    for (int ph : phases) {
      const double wz = ph > 0 ? w : -w;
      for (int s = 0; s < std::abs(ph); ++s) {
        const CohesivePairResult out = pair_force(c, p, CohesiveOptions{}, dx, r.ri, r.rj, Vec3{}, Vec3{},
                                                           Vec3{0, 0, wz}, Vec3{}, h, dt, 1);
        const double slide = a_i * wz;  // tangential velocity of the contact point, along +x
        h_expected += slide * dt;
        if (std::abs(p.k_t * h_expected) > cap) h_expected = std::copysign(cap / p.k_t, h_expected), ++slipped;
        const double f_t = -p.k_t * h_expected - p.c_t * slide;
        const std::string where = r.name + " dN = " + std::to_string(dn) + " step " + std::to_string(s);
        expect_close(h.x, h_expected, scale / p.k_t, where);
        expect_close(out.force.x, f_t, scale, where);
        expect_close(out.force.y, -eq3(p.k_n, p.delta_e, p.delta_f, dn), scale, where);
        EXPECT_EQ(out.force.z, 0.0);
        // Torque on i: (-a_i n) x F = a_i f_t z for n = y, F_t along x.
        expect_close(out.torque.z, a_i * f_t, scale * d, where);
        EXPECT_EQ(out.torque.x, 0.0);
        EXPECT_EQ(out.torque.y, 0.0);
      }
    }
    EXPECT_GT(slipped, 20) << "the cycle must reach the cap in both directions";
  }
}

// Pulling a sheared pair apart: the cap of eq 5 shrinks linearly to zero at delta_f, and the stored spring
// is rescaled with it; past delta_f the history is gone, and a pair that comes back starts from zero.
TEST_P(CohesivePairLaw, PullingAShearedPairRescalesTheSpringByEq5) {
  const Regime& r = GetParam();
  const double dt = 1.0, d0 = r.ri + r.rj;
  const double a_i_of = r.ri / (r.ri + r.rj);
  Vec3 h{};
  double h_expected = 0.0;
  const int steps = 300;
  const double v = 1.2 * p.delta_f / (steps + 1);  // no sample on delta_f itself, where s > 0 has a cliff
  const double w = 3.0 * p.f_max_t / p.k_t / steps / (0.5 * d0 * dt);
  for (int s = 0; s <= steps; ++s) {
    const double dn = s * v;
    const double d = d0 + dn, a_i = d * a_i_of;
    const CohesivePairResult out = pair_force(c, p, CohesiveOptions{}, Vec3{0, d, 0}, r.ri, r.rj, Vec3{0, v, 0},
                                                       Vec3{}, Vec3{0, 0, w}, Vec3{}, h, dt, 1);
    if (dn > p.delta_f) {
      h_expected = 0.0;
      EXPECT_EQ(norm(out.force), 0.0);
    } else {
      h_expected += a_i * w * dt;
      const double cap = eq5(p.f_max_t, p.delta_f, dn);
      if (p.k_t * h_expected > cap) h_expected = cap / p.k_t;
      expect_close(out.force.x, -p.k_t * h_expected - p.c_t * a_i * w, scale, "dN = " + std::to_string(dn));
      expect_close(out.force.y, -(eq3(p.k_n, p.delta_e, p.delta_f, dn) + p.c_n * v), scale, "normal");
    }
    expect_close(h.x, h_expected, scale / p.k_t, "history at dN = " + std::to_string(dn));
  }
  // Come back into range: fresh history, pure normal force.
  const CohesivePairResult back = pair_force(c, p, CohesiveOptions{}, Vec3{0, d0 + 0.5 * p.delta_e, 0}, r.ri,
                                                      r.rj, Vec3{}, Vec3{}, Vec3{}, Vec3{}, h, dt, 1);
  EXPECT_EQ(norm(h), 0.0);
  expect_close(back.force.y, -eq3(p.k_n, p.delta_e, p.delta_f, 0.5 * p.delta_e), scale, "re-bonded");
}

// Both ends of a pair, evaluated separately as a full neighbour list does, stay exact opposites over many
// random steps (bit for bit), as do the torque on j from either end, and the torques conserve angular momentum: x_i x F + t_i + x_j x (-F) + t_j = 0.
TEST_P(CohesivePairLaw, BothEndsStayExactOpposites) {
  const Regime& r = GetParam();
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double vs = 0.01 * p.delta_e;
  Vec3 hij{}, hji{};
  Vec3 xi{0, 0, 0}, xj{r.ri + r.rj, 0, 0};
  for (int s = 0; s < 200; ++s) {
    const Vec3 vi{vs * u(rng), vs * u(rng), vs * u(rng)}, vj{vs * u(rng), vs * u(rng), vs * u(rng)};
    const Vec3 wi{vs / r.ri * u(rng), vs / r.ri * u(rng), vs / r.ri * u(rng)};
    const Vec3 wj{vs / r.rj * u(rng), vs / r.rj * u(rng), vs / r.rj * u(rng)};
    xi += vi;
    xj += vj;
    const auto a = pair_force(c, p, CohesiveOptions{}, xi - xj, r.ri, r.rj, vi, vj, wi, wj, hij, 1.0, 1);
    const auto b = pair_force(c, p, CohesiveOptions{}, xj - xi, r.rj, r.ri, vj, vi, wj, wi, hji, 1.0, 1, 0);
    ASSERT_EQ(a.force.x, -b.force.x);
    ASSERT_EQ(a.force.y, -b.force.y);
    ASSERT_EQ(a.force.z, -b.force.z);
    ASSERT_EQ(hij.x, -hji.x);
    ASSERT_EQ(hij.y, -hji.y);
    ASSERT_EQ(hij.z, -hji.z);
    // The torque on j from i's end (the half-list pass's one evaluation) is the one j's end computes.
    ASSERT_EQ(a.torque_j.x, b.torque.x);
    ASSERT_EQ(a.torque_j.y, b.torque.y);
    ASSERT_EQ(a.torque_j.z, b.torque.z);
    const Vec3 l = cross(xi, a.force) + a.torque + cross(xj, b.force) + b.torque;
    EXPECT_NEAR(norm(l), 0.0, 1e-9 * scale * (r.ri + r.rj));
  }
}

// The potential of eq 3 is the integral of the force: F_N = dU/d(dN) by central differences.
TEST_P(CohesivePairLaw, NormalEnergyIsTheIntegralOfEq3) {
  const Regime& r = GetParam();
  for (double dn : {-0.5 * p.delta_e, 0.3 * p.delta_e, 0.5 * (p.delta_e + p.delta_f), 1.1 * p.delta_f}) {
    if (std::abs(dn - p.delta_e) < 1e-9) continue;
    const double e = 1e-6 * p.delta_e;
    const double fd = (cohesive_normal_energy(p, dn + e) - cohesive_normal_energy(p, dn - e)) / (2 * e);
    EXPECT_NEAR(fd, normal_force(c, p, r.ri, r.rj, dn), 1e-6 * scale) << "dN = " << dn;
  }
  EXPECT_EQ(cohesive_normal_energy(p, p.delta_f), 0.0);
  // Work of separation from dN = 0 to delta_f: the area under Fig 2 (eq A.31), or the triangle up to the
  // cliff at delta_f when delta_f < delta_e.
  const double peak = std::min(p.delta_e, p.delta_f);
  EXPECT_NEAR(-cohesive_normal_energy(p, 0.0), 0.5 * p.k_n * peak * p.delta_f, 1e-12 * scale * p.delta_f);
}

INSTANTIATE_TEST_SUITE_P(Regimes, CohesivePairLaw,
                         ::testing::Values(Regime{"below_dc_damped", 50, 50, 0.0, 0.95},
                                           Regime{"below_dc_undamped", 50, 50, 0.0, 1.0},
                                           Regime{"above_dc_s0", 150, 150, 0.0, 0.95},
                                           Regime{"above_dc_s05", 150, 150, 0.5, 0.95},
                                           Regime{"above_dc_s05_undamped", 150, 150, 0.5, 1.0},
                                           Regime{"unequal_below_dc", 40, 70, 0.0, 0.95},
                                           Regime{"unequal_above_dc_s05", 100, 160, 0.5, 0.95},
                                           Regime{"unequal_above_dc_s0", 100, 160, 0.0, 1.0}),
                         [](const auto& info) { return info.param.name; });

TEST(CohesivePairOptions, RepulsionOnlyAndNoTangential) {
  const Regime r{"x", 50, 50, 0.0, 0.95};
  const auto c = coefficients(r);
  const auto p = cohesive_pair_params(c, 50, 50, mass_of(50), mass_of(50));
  Vec3 h{};
  CohesiveOptions repulsive{0, 1};
  auto out = pair_force(c, p, repulsive, Vec3{100 + 0.5 * p.delta_e, 0, 0}, 50, 50, Vec3{}, Vec3{}, Vec3{},
                                 Vec3{}, h, 1.0, 1);
  EXPECT_EQ(out.interacting, 0);
  EXPECT_EQ(norm(out.force), 0.0);
  out = pair_force(c, p, repulsive, Vec3{100 - 0.5 * p.delta_e, 0, 0}, 50, 50, Vec3{}, Vec3{}, Vec3{}, Vec3{},
                            h, 1.0, 1);
  EXPECT_NEAR(out.force.x, 0.5 * p.k_n * p.delta_e, 1e-12 * p.k_n * p.delta_e);
  CohesiveOptions normal_only{1, 0};
  out = pair_force(c, p, normal_only, Vec3{0, 100, 0}, 50, 50, Vec3{1, 0, 0}, Vec3{}, Vec3{}, Vec3{}, h, 1.0, 1);
  EXPECT_EQ(out.force.x, 0.0);
  EXPECT_EQ(norm(h), 0.0);
}

}  // namespace
}  // namespace debris
