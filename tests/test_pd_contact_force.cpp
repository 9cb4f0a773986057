// The PeriDEM pair functions (kernels/peridem/pd_contact_force.hpp): the node-to-node contact force of
// eqs 16-20, Coulomb friction and node damping, against closed forms.
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

TEST(PdContactForce, ZeroBeyondContactRadiusClosedFormInsideAndExactlyOpposite) {
  PdMaterial m = material_m1();
  const PdContactParams p = pd_contact_params(m, m, settings(0.7, 0.4), 1.4e-4);
  const double rc = p.r_c, vi = 2.1e-8, vj = 1.7e-8, mi = 1200 * vi, mj = 1200 * vj, dt = 1e-7;
  std::mt19937_64 rng(5);
  std::normal_distribution<double> g(0.0, 1.0);
  for (int trial = 0; trial < 200; ++trial) {
    Vec3 e{g(rng), g(rng), g(rng)};
    e = (1.0 / norm(e)) * e;
    const Vec3 dv{g(rng), g(rng), g(rng)};  // v_j - v_i, m/s
    const double frac = trial < 100 ? 0.02 + 0.98 * (trial / 100.0) : 1.0 + 0.05 * (trial - 100) / 100.0;
    const Vec3 dz = (frac * rc) * e;  // z_j - z_i
    for (int node_damping = 0; node_damping <= 1; ++node_damping) {
      const PdContactPairResult ij = pd_contact_pair_force(p, dz, dv, vi, vj, pd_equivalent_mass(mi, mj), 1e-9, dt, 0, node_damping);
      const PdContactPairResult ji = pd_contact_pair_force(p, -dz, -dv, vj, vi, pd_equivalent_mass(mj, mi), 1e-9, dt, 0, node_damping);
      // Equal and opposite, bit for bit, friction and damping included.
      EXPECT_EQ(ij.force.x, -ji.force.x);
      EXPECT_EQ(ij.force.y, -ji.force.y);
      EXPECT_EQ(ij.force.z, -ji.force.z);
      const double d = norm(dz);
      if (d >= rc) {
        EXPECT_TRUE(same_bits(ij.force, Vec3{})) << "force beyond R_c at d / R_c = " << d / rc;
        EXPECT_EQ(ij.in_contact, 0);
        continue;
      }
      EXPECT_EQ(ij.in_contact, 1);
      // Without friction and damping: eq 17 times V_i, K_n (R_c - d) V_i V_j, pointing from j to i.
      const PdContactPairResult bare = pd_contact_pair_force(p, dz, Vec3{}, vi, vj, pd_equivalent_mass(mi, mj), 1e-9, dt, 0, 0);
      const double closed = p.k_n * (rc - d) * vi * vj;
      EXPECT_NEAR(norm(bare.force), closed, 1e-13 * closed);
      EXPECT_NEAR(dot(bare.force, e), -closed, 1e-13 * closed);
      EXPECT_DOUBLE_EQ(bare.delta, d - rc);
      // Self-contact (one grain, bond broken): the normal force only.
      const PdContactPairResult self = pd_contact_pair_force(p, dz, dv, vi, vj, pd_equivalent_mass(mi, mj), 1e-9, dt, 1, node_damping);
      EXPECT_TRUE(same_bits(self.force, bare.force));
    }
  }
}

TEST(PdFriction, OpposesSlidingCappedByMuFnAndByTheStoppingForce) {
  const PdMaterial m = material_m1();
  const PdContactParams p = pd_contact_params(m, m, settings(1.0, 0.3), 1.4e-4);
  const double vol = 2e-8, mass = 1200 * vol, dt = 1e-7;
  const Vec3 dz{0.0, 0.8 * p.r_c, 0.0};               // j above i
  const double fn = p.k_n * 0.2 * p.r_c * vol * vol;  // |F_n|
  // i slides along +x under j: v_j - v_i = (-2, 0.1, 0) m/s (j also approaches i: normal part ignored).
  const Vec3 dv{-2.0, -0.1, 0.0};
  const double stick_big = 1.0;  // a large stopping mass: sliding regime
  const PdContactPairResult r = pd_contact_pair_force(p, dz, dv, vol, vol, pd_equivalent_mass(mass, mass), stick_big, dt, 0, 0);
  const Vec3 friction = r.force - Vec3{0.0, -fn, 0.0};
  EXPECT_NEAR(friction.x, -0.3 * fn, 1e-12 * fn) << "against the sliding of i, magnitude mu |F_n|";
  EXPECT_NEAR(friction.y, 0.0, 1e-12 * fn);
  EXPECT_NEAR(friction.z, 0.0, 1e-12 * fn);
  // Slow sliding: capped by the force that stops the relative tangential velocity within one step.
  const double stick = 1e-12;
  const PdContactPairResult slow = pd_contact_pair_force(p, dz, dv, vol, vol, pd_equivalent_mass(mass, mass), stick, dt, 0, 0);
  EXPECT_NEAR(slow.force.x, -stick * 2.0 / dt, 1e-12 * stick * 2.0 / dt);
  ASSERT_LT(stick * 2.0 / dt, 0.3 * fn);
  // No sliding, no friction; no friction coefficient, no friction.
  EXPECT_EQ(pd_contact_pair_force(p, dz, Vec3{0, -0.1, 0}, vol, vol, pd_equivalent_mass(mass, mass), stick_big, dt, 0, 0).force.x, 0.0);
  const PdContactParams smooth = pd_contact_params(m, m, PdContactSettings{}, 1.4e-4);
  EXPECT_EQ(pd_contact_pair_force(smooth, dz, dv, vol, vol, pd_equivalent_mass(mass, mass), stick_big, dt, 0, 0).force.x, 0.0);
  // The stopping mass: reduced mass of the shares, a wall node (rigid) counts as infinitely heavy.
  EXPECT_DOUBLE_EQ(pd_stick_mass(2.0, 0, 3.0, 0), 1.2);
  EXPECT_EQ(pd_stick_mass(2.0, 0, 3.0, 1), 2.0);
  EXPECT_EQ(pd_stick_mass(2.0, 1, 3.0, 0), 3.0);
}

TEST(PdContactForce, NodeDampingActsOnlyWhileApproachingInContact) {
  const PdMaterial m = material_m1();
  const PdContactParams p = pd_contact_params(m, m, settings(0.5, 0.0), 1.4e-4);
  const double vol = 2e-8, mi = 1200 * vol, mj = 3 * mi, dt = 1e-7;
  const Vec3 dz{0.9 * p.r_c, 0.0, 0.0};
  const double fn = p.k_n * 0.1 * p.r_c * vol * vol;
  // Approaching at 0.4 m/s: eq 22 times V, beta_n (eq 23, m_eq of eq 24) delta_dot e_n.
  const PdContactPairResult in = pd_contact_pair_force(p, dz, Vec3{-0.4, 0, 0}, vol, vol, pd_equivalent_mass(mi, mj), 1.0, dt, 0, 1);
  const double l = std::log(0.5), m_eq = 2 * mi * mj / (mi + mj);
  const double beta =
      -2 * 100 * l * std::sqrt(m.bulk_modulus * p.r_c * m_eq / (std::numbers::pi * std::numbers::pi + l * l));
  EXPECT_NEAR(in.force.x, -fn - 0.4 * beta, 1e-12 * (fn + 0.4 * beta));
  // Separating: no damping.
  const PdContactPairResult out = pd_contact_pair_force(p, dz, Vec3{0.4, 0, 0}, vol, vol, pd_equivalent_mass(mi, mj), 1.0, dt, 0, 1);
  EXPECT_NEAR(out.force.x, -fn, 1e-12 * fn);
  // e_n = 1: eq 23 gives beta = 0.
  const PdContactParams elastic = pd_contact_params(m, m, settings(1.0, 0.0), 1.4e-4);
  EXPECT_EQ(pd_contact_pair_force(elastic, dz, Vec3{-0.4, 0, 0}, vol, vol, pd_equivalent_mass(mi, mj), 1.0, dt, 0, 1).force.x,
            pd_contact_pair_force(elastic, dz, Vec3{}, vol, vol, pd_equivalent_mass(mi, mj), 1.0, dt, 0, 1).force.x);
}

}  // namespace
}  // namespace debris
