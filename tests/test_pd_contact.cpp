// The PeriDEM contact pass (kernels/peridem/pd_contact.hpp, paper B eqs 16-30): self-contact, thread-count
// determinism, damping between grain centres, momentum conservation, restitution and Coulomb's sliding law.
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

TEST(PdContact, SelfContactOnlyAcrossABrokenBond) {
  // One grain of two nodes 0.5 R_c apart, bonded: no contact. Bond broken: they repel with eq 17.
  const PdMaterial m = material_m1();
  const PdContactTable t = pd_contact_table({m}, PdContactSettings{}, 1e-4);
  PdSystem s;
  s.begin_grain(PdGrainKind::particle);
  s.add_node({0, 0, 0}, 1e-8, m.density);
  s.add_node({0.5 * t.pair(0, 0).r_c, 0, 0}, 1e-8, m.density);
  bond_within(s, m.horizon);
  ASSERT_TRUE(s.bonds.intact(0, 1));
  PdContactList l;
  PdContactWork w;
  test::build_list(l, s.nodes, s.grains, s.bonds, t.max_contact_radius(), 0.0);
  EXPECT_EQ(l.entries(), 0);
  break_bond(s.bonds, 0, 1);
  EXPECT_EQ(test::add_broken_bonds(l, s.bonds), 2);
  EXPECT_EQ(l.entries(), 2);
  test::pd_zero_forces(s.nodes);
  test::pd_contact_pass(t, PdDamping::grain_centres, s.nodes, s.grains, l, w, 1e-7);
  const double f = t.pair(0, 0).k_n * 0.5 * t.pair(0, 0).r_c * 1e-16;
  EXPECT_NEAR(s.nodes.fx[0], -f, 1e-13 * f);
  EXPECT_EQ(s.nodes.fx[1], -s.nodes.fx[0]);
  // The spring's energy, 1/2 K_n delta^2 V V', counted once for the pair.
  const double u = 0.5 * t.pair(0, 0).k_n * std::pow(0.5 * t.pair(0, 0).r_c, 2) * 1e-16;
  EXPECT_NEAR(test::pd_contact_elastic_energy(t, s.nodes, s.grains, l), u, 1e-13 * u);
}

// ---------------------------------------------------------------------------------------------------------
// The contact pass

// Two overlapping blocks, a disk and two walls (one moving), random velocities: every kind of pair.
PdSystem crowded_system(std::uint64_t seed) {
  PdSystem s;
  const double h = 1e-3;
  s.add_block(PdGrainKind::particle, {0, 0, 0}, 6, 5, h, 1000.0);
  s.add_block(PdGrainKind::particle, {5.3e-3, 0.4e-3, 0}, 5, 5, h, 1000.0, 1);
  s.add_disk({2.5e-3, 5.6e-3, 0}, 2e-3, h, 1000.0);
  s.add_block(PdGrainKind::wall, {-3e-3, -0.75e-3, 0}, 16, 1, 0.8 * h, 1000.0);
  s.add_block(PdGrainKind::wall, {10.0e-3, -1e-3, 0}, 1, 12, 0.8 * h, 1000.0, 1);
  s.grains.wall_vy[3] = 0.2;
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, 0.3);
  for (std::size_t i = 0; i < s.nodes.size(); ++i) {
    const int k = s.nodes.grain[i];
    if (s.grains.kind[k] == static_cast<int>(PdGrainKind::wall)) {
      s.nodes.vx[i] = s.grains.wall_vx[k];
      s.nodes.vy[i] = s.grains.wall_vy[k];
      continue;
    }
    s.nodes.x[i] += 0.1 * h * g(rng);
    s.nodes.y[i] += 0.1 * h * g(rng);
    s.nodes.vx[i] = g(rng);
    s.nodes.vy[i] = g(rng);
  }
  return s;
}

TEST(PdContact, ForcesAreTheSameBitsWithOneAndTwoThreads) {
  const PdContactTable t = pd_contact_table({soft_material(400), soft_material(900)}, settings(0.6, 0.4), 1e-3);
  for (PdDamping d : {PdDamping::node_pairs, PdDamping::grain_centres}) {
    std::vector<double> f[2];
    ThreadGuard guard;
    for (int threads = 1; threads <= 2; ++threads) {
      exec::set_threads(threads);
      PdSystem s = crowded_system(8);
      PdContactList l;
      PdContactWork w;
      test::build_list(l, s.nodes, s.grains, s.bonds, t.max_contact_radius(), 0.2e-3);
      test::pd_zero_forces(s.nodes);
      test::pd_contact_pass(t, d, s.nodes, s.grains, l, w, 1e-5);
      f[threads - 1].assign(s.nodes.fx.begin(), s.nodes.fx.end());
      f[threads - 1].insert(f[threads - 1].end(), s.nodes.fy.begin(), s.nodes.fy.end());
      if (threads == 1) {
        int nonzero = 0;
        for (double v : f[0]) nonzero += v != 0.0;
        EXPECT_GT(nonzero, 40) << "the configuration should be in contact";
        // The contact forces of a step sum to zero: walls take the reactions, damping included.
        Vec3 total{};
        double scale = 0;
        for (std::size_t i = 0; i < s.nodes.size(); ++i) {
          total += s.force(static_cast<int>(i));
          scale += norm(s.force(static_cast<int>(i)));
        }
        EXPECT_LT(norm(total), 1e-14 * scale);
        std::vector<Vec3> reaction;
        test::pd_wall_reactions(s.nodes, s.grains, reaction);
        Vec3 on_particles{};
        for (int g = 0; g < 3; ++g) on_particles += grain_force(s, g);
        EXPECT_LT(norm(reaction[3] + reaction[4] + on_particles), 1e-14 * scale);
        EXPECT_EQ(norm(reaction[0]), 0.0) << "particles have no reaction entry";
        EXPECT_TRUE(same_bits(reaction[3], grain_force(s, 3)));
        EXPECT_GT(norm(reaction[3]), 0.0);
        EXPECT_GT(norm(reaction[4]), 0.0);
      }
    }
    ASSERT_EQ(f[0].size(), f[1].size());
    for (std::size_t i = 0; i < f[0].size(); ++i) ASSERT_EQ(f[0][i], f[1][i]) << "entry " << i;
  }
}

TEST(PdContact, CentreDampingIsOneForcePerGrainPairSpreadByVolume) {
  // Two rigid blocks touching along a face (5 node pairs within R_c), approaching: the damping they get is
  // eqs 26-29 once, whatever the number of touching pairs; each node gets V_i / |Omega_p| of it (eq 30).
  const double h = 1e-3, e_n = 0.6;
  const PdContactTable damped = pd_contact_table({soft_material(400)}, settings(e_n, 0.0), h);
  const PdContactTable elastic = pd_contact_table({soft_material(400)}, settings(1.0, 0.0), h);
  PdSystem s;
  s.add_block(PdGrainKind::particle, {0, 0, 0}, 4, 5, h, 1000.0);
  s.add_block(PdGrainKind::particle, {3.8e-3, 0.3e-3, 0}, 3, 5, h, 2000.0);  // offset: centre line tilted
  s.nodes.volume[7] *= 1.5;                                                  // uneven volumes
  s.nodes.mass[7] *= 1.5;
  s.set_velocity(0, {0.3, 0.05, 0});
  s.set_velocity(1, {-0.2, 0.0, 0});
  const double skin = 0.1e-3;
  PdContactList l;
  test::build_list(l, s.nodes, s.grains, s.bonds, h, skin);
  PdContactWork w;
  auto forces = [&](const PdContactTable& t) {
    test::pd_zero_forces(s.nodes);
    test::pd_contact_pass(t, PdDamping::grain_centres, s.nodes, s.grains, l, w, 1e-5);
  };
  forces(elastic);
  std::vector<Vec3> f0;
  for (std::size_t i = 0; i < s.nodes.size(); ++i) f0.push_back(s.force(static_cast<int>(i)));
  forces(damped);
  // Closed form from the grains' own centres and volumes.
  Vec3 c[2], v[2];
  double vol[2] = {0, 0}, mass[2] = {0, 0};
  for (int g = 0; g < 2; ++g) {
    for (int i = s.grains.node_begin[g]; i < s.grains.node_end[g]; ++i) {
      vol[g] += s.nodes.volume[i];
      mass[g] += s.nodes.mass[i];
      c[g] += s.nodes.volume[i] * s.position(i);
      v[g] += s.nodes.volume[i] * s.velocity(i);
    }
    c[g] = (1.0 / vol[g]) * c[g];
    v[g] = (1.0 / vol[g]) * v[g];
    EXPECT_NEAR(s.grains.cx[g], c[g].x, 1e-15);
    EXPECT_NEAR(s.grains.cvy[g], v[g].y, 1e-15);
  }
  const Vec3 e = (1.0 / norm(c[1] - c[0])) * (c[1] - c[0]);
  const double rate = dot(v[1] - v[0], e);  // eq 26
  ASSERT_LT(rate, 0.0);
  const double l_e = std::log(e_n), m_eq = 2 * mass[0] * mass[1] / (mass[0] + mass[1]);
  const double beta =
      -2 * 100 * l_e * std::sqrt(400.0 * 0.95 * h * m_eq / (std::numbers::pi * std::numbers::pi + l_e * l_e));
  const Vec3 expected = (beta * rate) * e;  // on grain 0, eq 27 times |Omega_0|
  Vec3 total[2];
  for (int g = 0; g < 2; ++g) {
    for (int i = s.grains.node_begin[g]; i < s.grains.node_end[g]; ++i) {
      const Vec3 d = s.force(i) - f0[static_cast<std::size_t>(i)];
      const Vec3 share = (s.nodes.volume[i] / vol[g]) * (g == 0 ? expected : -expected);
      EXPECT_NEAR(d.x, share.x, 1e-12 * norm(expected));
      EXPECT_NEAR(d.y, share.y, 1e-12 * norm(expected));
      total[g] += d;
    }
  }
  EXPECT_NEAR(norm(total[0] - expected), 0.0, 1e-12 * norm(expected));
  EXPECT_NEAR(norm(total[0] + total[1]), 0.0, 1e-14 * norm(expected));
  int touching = 0;
  for (int i = 0; i < s.nodes_of(0); ++i)
    for (int k = l.offset()[i]; k < l.offset()[i + 1]; ++k)
      touching += norm(s.position(l.index()[k]) - s.position(i)) < 0.95 * h;
  EXPECT_GE(touching, 3) << "several node pairs touch, one damping force";

  // Separating grains: no damping.
  s.set_velocity(0, {-0.3, 0, 0});
  s.set_velocity(1, {0.2, 0, 0});
  forces(elastic);
  f0.clear();
  for (std::size_t i = 0; i < s.nodes.size(); ++i) f0.push_back(s.force(static_cast<int>(i)));
  forces(damped);
  for (std::size_t i = 0; i < s.nodes.size(); ++i) EXPECT_TRUE(same_bits(s.force(static_cast<int>(i)), f0[i]));
}

TEST(PdContact, CentreDampingAgainstAWallIsOneBodyOfInfiniteMass) {
  // A block pressed onto a fixed wall: the wall is one partner of infinite mass (eq 29: m_eq = 2 m_p), met
  // at each of the k wall nodes the block touches; each carries 1/k of eqs 26-28's force toward its node,
  // and takes the opposite.
  const double h = 1e-3, e_n = 0.5;
  const PdContactTable damped = pd_contact_table({soft_material(400)}, settings(e_n, 0.0), h);
  const PdContactTable elastic = pd_contact_table({soft_material(400)}, settings(1.0, 0.0), h);
  PdSystem s;
  s.add_block(PdGrainKind::particle, {0, 0, 0}, 3, 3, h, 1000.0);
  s.add_block(PdGrainKind::wall, {-2.2e-3, -0.8e-3, 0}, 9, 1, 0.7 * h, 3000.0);
  s.set_velocity(0, {0.1, -0.4, 0});
  PdContactList l;
  test::build_list(l, s.nodes, s.grains, s.bonds, h, 0.0);
  PdContactWork w;
  std::vector<Vec3> f0;
  test::pd_zero_forces(s.nodes);
  test::pd_contact_pass(elastic, PdDamping::grain_centres, s.nodes, s.grains, l, w, 1e-5);
  for (std::size_t i = 0; i < s.nodes.size(); ++i) f0.push_back(s.force(static_cast<int>(i)));
  test::pd_zero_forces(s.nodes);
  test::pd_contact_pass(damped, PdDamping::grain_centres, s.nodes, s.grains, l, w, 1e-5);

  const double mass = grain_mass(s, 0), l_e = std::log(e_n);
  const double beta =
      -2 * 100 * l_e * std::sqrt(400.0 * 0.95 * h * (2 * mass) / (std::numbers::pi * std::numbers::pi + l_e * l_e));
  Vec3 c{};
  for (int i = 0; i < 9; ++i) c += (1.0 / 9) * s.position(i);
  std::vector<int> partners;
  for (int j = 9; j < static_cast<int>(s.nodes.size()); ++j) {
    bool touches = false;
    for (int i = 0; i < 9; ++i) touches = touches || norm(s.position(j) - s.position(i)) < 0.95 * h;
    if (touches) partners.push_back(j);
  }
  ASSERT_GE(partners.size(), 2u);
  const double share = 1.0 / static_cast<double>(partners.size());
  Vec3 expected{};
  for (int j : partners) {
    const Vec3 e = (1.0 / norm(s.position(j) - c)) * (s.position(j) - c);
    const double rate = dot(s.velocity(j) - Vec3{0.1, -0.4, 0}, e);
    const Vec3 f = rate < 0 ? share * ((beta * rate) * e) : Vec3{};
    expected += f;
    const Vec3 dj = s.force(j) - f0[static_cast<std::size_t>(j)];
    EXPECT_NEAR(norm(dj + f), 0.0, 1e-12 * beta) << "wall node " << j << " takes the reaction";
  }
  Vec3 total{};
  for (int i = 0; i < 9; ++i) total += s.force(i) - f0[static_cast<std::size_t>(i)];
  EXPECT_NEAR(norm(total - expected), 0.0, 1e-12 * norm(expected));
  EXPECT_GT(norm(expected), 0.0);
}

// ---------------------------------------------------------------------------------------------------------
// Dynamics

// Two disks of 49 nodes (R = 4 h) held together by test springs along their bonds, colliding off centre.
struct Collision {
  PdSystem s;
  int a = 0, b = 1;
  explicit Collision(double offset_y = 0.5e-3) {
    const double h = 1e-3;
    a = s.add_disk({-4.5e-3, 0, 0}, 4 * h, h, 1000.0);
    b = s.add_disk({4.5e-3, offset_y, 0}, 4 * h, h, 1000.0);
    s.set_velocity(a, {0.05, 0.0, 0});
    s.set_velocity(b, {-0.05, 0.01, 0});
  }
};

TEST(PdContact, MomentumIsConservedInACollisionWithEitherDamping) {
  ThreadGuard guard;
  exec::set_threads(1);  // 98 nodes, 800 steps: one thread (the thread-count test is above)
  for (PdDamping d : {PdDamping::node_pairs, PdDamping::grain_centres}) {
    Collision c;
    bond_within(c.s, 2.1e-3);
    std::mt19937_64 rng(9);
    std::normal_distribution<double> g(0.0, 1e-3);
    for (std::size_t i = 0; i < c.s.nodes.size(); ++i) c.s.nodes.vx[i] += g(rng);  // some internal motion
    Stepper st;
    st.table = pd_contact_table({soft_material(400)}, settings(0.5, 0.3), 1e-3);
    st.damping = d;
    st.spring_k = 2e4;
    const double dt = 1e-5;
    const Vec3 p0 = momentum(c.s);
    double scale = 0, drift = 0, min_va = 1.0;
    for (std::size_t i = 0; i < c.s.nodes.size(); ++i)
      scale += c.s.nodes.mass[i] * norm(c.s.velocity(static_cast<int>(i)));
    PdContactWork w;
    for (int n = 0; n < 800; ++n) {
      st.forces(c.s, dt);
      test::pd_integrate(c.s.nodes, c.s.grains, dt, n == 0);
      drift = std::max(drift, norm(momentum(c.s) - p0));
      test::pd_grain_centres(c.s.nodes, c.s.grains, w);
      min_va = std::min(min_va, c.s.grains.cvx[c.a]);
    }
    EXPECT_LT(drift, 1e-14 * scale) << "damping " << static_cast<int>(d);
    EXPECT_LT(min_va, 0.5 * 0.05) << "the grains collided";
    EXPECT_GT(st.rebuilds, 1);
    std::printf("[ measured ] momentum drift / sum m|v| = %.2e (damping %d)\n", drift / scale, static_cast<int>(d));
  }
}

// Relative rebound speed / impact speed of two rigid disks colliding head on.
double rebound_ratio(PdDamping damping, double e_n, double* max_overlap = nullptr, double dt = 1e-5) {
  Collision c(0.0);
  c.s.set_velocity(c.b, {-0.05, 0, 0});
  Stepper st;
  st.table = pd_contact_table({soft_material(400)}, settings(e_n, 0.0), 1e-3);
  st.damping = damping;
  const double before = 0.05 - (-0.05);
  double overlap = 0;
  for (int n = 0; n < static_cast<int>(1.5e-2 / dt); ++n) {
    st.forces(c.s, dt);
    rigid_update(c.s, dt);
    double closest = 1.0;
    for (int i = c.s.grains.node_begin[c.a]; i < c.s.grains.node_end[c.a]; ++i)
      for (int j = c.s.grains.node_begin[c.b]; j < c.s.grains.node_end[c.b]; ++j)
        closest = std::min(closest, norm(c.s.position(j) - c.s.position(i)));
    overlap = std::max(overlap, 0.95e-3 - closest);
  }
  if (max_overlap) *max_overlap = overlap;
  const double after = c.s.velocity(c.s.grains.node_begin[c.b]).x - c.s.velocity(0).x;
  EXPECT_EQ(norm(grain_force(c.s, c.a)), 0.0) << "separated at the end";
  return after / before;
}

TEST(PdContact, CentreDampingLowersTheReboundMonotonicallyAndVanishesAtRestitutionOne) {
  ThreadGuard guard;
  exec::set_threads(1);
  const double e[] = {1.0, 0.95, 0.9, 0.8, 0.6, 0.4, 0.2};
  double previous = 2.0;
  std::printf("[ measured ] rebound / impact speed, centre damping:");
  for (double e_n : e) {
    double overlap = 0;
    const double r = rebound_ratio(PdDamping::grain_centres, e_n, &overlap);
    if (e_n == 1.0) {
      EXPECT_NEAR(r, 1.0, 1e-4) << "elastic: the rebound speed is the impact speed";
      EXPECT_GT(overlap, 0.05e-3) << "the springs were compressed";
      EXPECT_LT(overlap, 0.5e-3);
    }
    EXPECT_GT(r, 0.0);
    EXPECT_LT(r, previous) << "e_n = " << e_n;
    previous = r;
    std::printf(" e_n %.2f: %.6f;", e_n, r);
  }
  // The damping between nodes (eqs 21-25) lowers the rebound too.
  const double node_half = rebound_ratio(PdDamping::node_pairs, 0.5);
  std::printf(" node damping e_n 0.5: %.4f\n", node_half);
  EXPECT_LT(node_half, rebound_ratio(PdDamping::node_pairs, 1.0) - 0.01);
  EXPECT_NEAR(rebound_ratio(PdDamping::node_pairs, 1.0), rebound_ratio(PdDamping::grain_centres, 1.0), 1e-15);
}

// A rigid 10 x 2 block (a grain without bonds whose nodes the test moves together) on a fixed wall of
// nodes spaced h / 3.1, under gravity. Node-to-node contact makes the wall a corrugated surface; with the
// block's bottom nodes at ten equally spaced phases of the wall's period, the corrugation's tangential
// pull cancels to its 10th harmonic. The block settles without friction first, then is launched along the
// wall at v0 with friction mu. Returns the block's velocity along the wall at every step, and the wall
// reaction once settled.
struct Slide {
  std::vector<double> v;
  Vec3 reaction_at_rest;
  double weight;
};

Slide slide(double mu, double v0, int steps, double dt = 1e-5) {
  const double h = 1e-3, g = 10.0;
  PdSystem s;
  s.add_block(PdGrainKind::particle, {0, 0.78e-3, 0}, 10, 2, h, 1000.0);
  s.begin_grain(PdGrainKind::wall);
  for (int k = 0; k < 50; ++k) s.add_node({-3e-3 + k * h / 3.1, 0, 0}, h * h, 1000.0);
  Stepper st;
  st.table = pd_contact_table({soft_material(2.0)}, settings(1.0, 0.0), h);  // K_n V V = 47 N/m
  st.gravity = {0, -g, 0};
  Slide out{};
  out.weight = grain_mass(s, 0) * g;
  for (int n = 0; n < static_cast<int>(0.04 / dt); ++n) {  // settle: the harness damps the block's velocity
    st.forces(s, dt);
    rigid_update(s, dt);
    s.set_velocity(0, (1.0 - 500.0 * dt) * s.velocity(0));
  }
  st.forces(s, dt);
  std::vector<Vec3> reaction;
  test::pd_wall_reactions(s.nodes, s.grains, reaction);
  out.reaction_at_rest = reaction[1];
  st.table = pd_contact_table({soft_material(2.0)}, settings(1.0, mu), h);
  s.set_velocity(0, {v0, 0, 0});
  for (int n = 0; n < steps; ++n) {
    st.forces(s, dt);
    rigid_update(s, dt);
    out.v.push_back(s.nodes.vx[0]);
  }
  return out;
}

// Friction without tangential memory (the paper's law) cannot hold a static tangential load exactly: once
// stopped, the block creeps under the wall lattice's residual tangential pull at a speed proportional to dt
// (the stick cap removes one step's worth of relative velocity per step). The test measures that speed.
double creep_speed(const Slide& r, int from) {
  double v = 0;
  for (std::size_t n = static_cast<std::size_t>(from); n < r.v.size(); ++n) v = std::max(v, std::fabs(r.v[n]));
  return v;
}

TEST(PdFriction, BlockSlidingOnAWallDeceleratesAtMuGStopsAndDoesNotReverse) {
  ThreadGuard guard;
  exec::set_threads(1);  // 70 nodes: one thread; the thread-count tests are above
  const double mu = 0.3, g = 10.0, v0 = 0.05, dt = 1e-5;
  const Slide r = slide(mu, v0, 2600);
  EXPECT_NEAR(r.reaction_at_rest.y, -r.weight, 1e-4 * r.weight) << "the wall carries the block's weight";
  EXPECT_NEAR(r.reaction_at_rest.x, 0.0, 1e-4 * r.weight);
  // Deceleration: least-squares slope of v(t) over 10% .. 80% of the stopping time v0 / (mu g).
  const int stop = static_cast<int>(v0 / (mu * g) / dt);
  double st = 0, sv = 0, stt = 0, stv = 0;
  int m = 0;
  for (int n = stop / 10; n < 8 * stop / 10; ++n, ++m) {
    const double t = n * dt;
    st += t;
    sv += r.v[n];
    stt += t * t;
    stv += t * r.v[n];
  }
  const double slope = (m * stv - st * sv) / (m * stt - st * st);
  EXPECT_NEAR(-slope / (mu * g), 1.0, 0.02) << "measured deceleration " << -slope;
  // It slows down at every step until it stops, close to the predicted time, without chattering.
  int stopped_at = -1;
  for (int n = 1; n < static_cast<int>(r.v.size()) && stopped_at < 0; ++n) {
    ASSERT_LE(r.v[n], r.v[n - 1]) << "friction pushed the block forward at step " << n;
    ASSERT_GE(r.v[n], 0.0) << "friction reversed the sliding at step " << n;
    if (r.v[n] < 1e-5 * v0) stopped_at = n;
  }
  ASSERT_GT(stopped_at, 0) << "never stopped";
  EXPECT_NEAR(stopped_at, stop, 0.03 * stop);
  // Then it stays stopped, up to the O(dt) creep: its speed halves with the time step.
  const double creep = creep_speed(r, stopped_at + 200);
  EXPECT_LT(creep, 1e-5 * v0);
  const Slide fine = slide(mu, v0, 2 * 2600, 0.5 * dt);
  const double creep_fine = creep_speed(fine, 2 * (stopped_at + 200));
  EXPECT_NEAR(creep_fine / creep, 0.5, 0.1);

  // Without friction it keeps its speed.
  const Slide free = slide(0.0, v0, 2600);
  const auto [lo, hi] = std::minmax_element(free.v.begin(), free.v.end());
  EXPECT_NEAR(*lo, v0, 0.01 * v0);
  EXPECT_NEAR(*hi, v0, 0.01 * v0);
  std::printf(
      "[ measured ] deceleration / (mu g) = %.4f, stop at step %d (predicted %d), creep after the stop "
      "%.2e v0 (dt/2: %.2e v0), frictionless speed in [%.6f, %.6f] v0, wall reaction / weight = %.7f\n",
      -slope / (mu * g), stopped_at, stop, creep / v0, creep_fine / v0, *lo / v0, *hi / v0,
      -r.reaction_at_rest.y / r.weight);
}

// Global viscous damping (a settle stage): with f = m g - c m v^{n-1/2}, eq 32's kick gives the recurrence
// v^{n+1/2} = (1 - c dt) v^{n-1/2} + g dt, whose solution approaches the terminal velocity g / c as
// (1 - c dt)^n; walls are not damped.

}  // namespace
}  // namespace debris
