// PeriDEM contact (paper B, eqs 16-30), its neighbour list and the time integration of eq 32, against
// closed forms, a brute-force pair search, conservation of momentum and Coulomb's sliding law.
// Grains are built directly in PdNodes / PdGrains on small regular grids (2D: z = 0, volumes are areas);
// bonds, where needed, are filled into BondList by hand.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <numbers>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "core/bond_list.hpp"
#include "core/error.hpp"
#include "core/exec.hpp"
#include "core/pd_contact_list.hpp"
#include "core/pd_nodes.hpp"
#include "kernels/peridem/pd_contact.hpp"
#include "kernels/peridem/pd_contact_force.hpp"
#include "kernels/peridem/pd_contact_params.hpp"
#include "kernels/peridem/pd_integrate.hpp"
#include "tests/pd_on_device.hpp"

namespace debris {
namespace {

// ---------------------------------------------------------------------------------------------------------
// Building blocks

struct PdSystem {
  PdNodes nodes;
  PdGrains grains;
  BondList bonds;  // empty: no bonds

  int begin_grain(PdGrainKind kind, int material = 0) {
    const int g = static_cast<int>(grains.size());
    grains.resize(static_cast<std::size_t>(g) + 1);
    grains.node_begin[g] = grains.node_end[g] = static_cast<int>(nodes.size());
    grains.kind[g] = static_cast<int>(kind);
    grains.material[g] = material;
    return g;
  }
  int add_node(Vec3 p, double volume, double density) {
    const int g = static_cast<int>(grains.size()) - 1;
    const int i = static_cast<int>(nodes.add(static_cast<std::int64_t>(nodes.size()), g, p.x, p.y, p.z, volume));
    nodes.mass[i] = density * volume;
    grains.node_end[g] = i + 1;
    grains.volume[g] += volume;
    return i;
  }
  // nx * ny nodes at spacing h from corner o, volume h^2 (2D).
  int add_block(PdGrainKind kind, Vec3 o, int nx, int ny, double h, double density, int material = 0) {
    const int g = begin_grain(kind, material);
    for (int b = 0; b < ny; ++b)
      for (int a = 0; a < nx; ++a) add_node(o + Vec3{a * h, b * h, 0.0}, h * h, density);
    return g;
  }
  // Lattice points of spacing h within radius r of c (2D).
  int add_disk(Vec3 c, double r, double h, double density, int material = 0) {
    const int g = begin_grain(PdGrainKind::particle, material);
    const int m = static_cast<int>(r / h);
    for (int b = -m; b <= m; ++b)
      for (int a = -m; a <= m; ++a)
        if (a * a + b * b <= m * m) add_node(c + Vec3{a * h, b * h, 0.0}, h * h, density);
    return g;
  }
  void set_velocity(int g, Vec3 v) {
    for (int i = grains.node_begin[g]; i < grains.node_end[g]; ++i) {
      nodes.vx[i] = v.x;
      nodes.vy[i] = v.y;
      nodes.vz[i] = v.z;
    }
  }
  Vec3 position(int i) const { return {nodes.x[i], nodes.y[i], nodes.z[i]}; }
  Vec3 velocity(int i) const { return {nodes.vx[i], nodes.vy[i], nodes.vz[i]}; }
  Vec3 force(int i) const { return {nodes.fx[i], nodes.fy[i], nodes.fz[i]}; }
  int nodes_of(int g) const { return grains.node_end[g] - grains.node_begin[g]; }
};

// Bonds by hand (BondList::build is written elsewhere): every pair of one particle grain closer than the
// horizon in the reference positions, rows ascending.
void bond_within(PdSystem& s, double horizon) {
  BondList& b = s.bonds;
  const int n = static_cast<int>(s.nodes.size());
  b.offset.assign(1, 0);
  b.partner.clear();
  b.length0.clear();
  b.broken.clear();
  for (int i = 0; i < n; ++i) {
    const int g = s.nodes.grain[i];
    if (s.grains.kind[g] == static_cast<int>(PdGrainKind::particle)) {
      for (int j = s.grains.node_begin[g]; j < s.grains.node_end[g]; ++j) {
        const double r =
            norm(Vec3{s.nodes.x0[j] - s.nodes.x0[i], s.nodes.y0[j] - s.nodes.y0[i], s.nodes.z0[j] - s.nodes.z0[i]});
        if (j != i && r < horizon) {
          b.partner.push_back(j);
          b.length0.push_back(r);
          b.broken.push_back(0);
        }
      }
    }
    b.offset.push_back(static_cast<int>(b.partner.size()));
  }
}

// Breaks the bond (i, j) at both ends.
void break_bond(BondList& b, int i, int j) {
  for (auto [a, c] : {std::pair{i, j}, std::pair{j, i}})
    for (int k = b.offset[a]; k < b.offset[a + 1]; ++k)
      if (b.partner[k] == c) b.broken[k] = 1;
}

// A linear spring along every intact bond: a stand-in for the peridynamic bond force (written elsewhere)
// that keeps the test grains together. Exactly antisymmetric, so it conserves momentum too.
void spring_pass(PdSystem& s, double k) {
  const BondList& b = s.bonds;
  for (int i = 0; i < static_cast<int>(s.nodes.size()); ++i) {
    Vec3 f{};
    for (int e = b.offset[i]; e < b.offset[i + 1]; ++e) {
      if (b.broken[e]) continue;
      const Vec3 d = s.position(b.partner[e]) - s.position(i);
      const double l = norm(d);
      f += (k * (l - b.length0[e]) / l) * d;
    }
    s.nodes.fx[i] += f.x;
    s.nodes.fy[i] += f.y;
    s.nodes.fz[i] += f.z;
  }
}

// A soft material in SI units for the dynamic tests: with h = 1 mm and V = 1 mm^2 per node, K_n V V is
// 18 K / (pi eps^5) 1e-12 N/m for horizon eps.
PdMaterial soft_material(double bulk_modulus, double horizon = 3e-3) {
  PdMaterial m;
  m.density = 1000;
  m.bulk_modulus = bulk_modulus;
  m.shear_modulus = 0.6 * bulk_modulus;
  m.fracture_energy = 1;
  m.horizon = horizon;
  m.dimension = 2;
  return m;
}

PdContactSettings settings(double restitution, double friction) {
  PdContactSettings s;
  s.restitution = restitution;
  s.friction = friction;
  return s;
}

// One force evaluation as a PeriDEM step makes it: rebuild if needed, weights, (springs), contact.
struct Stepper {
  PdContactTable table;
  PdDamping damping = PdDamping::grain_centres;
  double skin = 0.3e-3;
  double spring_k = 0.0;
  Vec3 gravity{};
  PdContactList list;
  PdContactWork work;
  int rebuilds = 0;

  void forces(PdSystem& s, double dt) {
    if (test::needs_rebuild(list, s.nodes)) {
      test::build_list(list, s.nodes, s.grains, s.bonds, table.max_contact_radius(), skin);
      ++rebuilds;
    }
    test::pd_weight_forces(s.nodes, s.grains, gravity);  // f = m g on particle nodes, 0 on walls
    if (spring_k > 0) spring_pass(s, spring_k);
    test::pd_contact_pass(table, damping, s.nodes, s.grains, list, work, dt);
  }
};

// Moves every particle grain as a rigid body (one velocity for all its nodes, kicked by the grain's total
// force), walls at their prescribed velocity: the test harness for rigid grains.
void rigid_update(PdSystem& s, double dt) {
  for (int g = 0; g < static_cast<int>(s.grains.size()); ++g) {
    const int b = s.grains.node_begin[g], e = s.grains.node_end[g];
    Vec3 v{s.grains.wall_vx[g], s.grains.wall_vy[g], s.grains.wall_vz[g]};
    if (s.grains.kind[g] == static_cast<int>(PdGrainKind::particle)) {
      Vec3 f{};
      double m = 0;
      for (int i = b; i < e; ++i) {
        f += s.force(i);
        m += s.nodes.mass[i];
      }
      v = s.velocity(b) + (dt / m) * f;
    }
    for (int i = b; i < e; ++i) {
      s.nodes.vx[i] = v.x;
      s.nodes.vy[i] = v.y;
      s.nodes.vz[i] = v.z;
      s.nodes.x[i] += dt * v.x;
      s.nodes.y[i] += dt * v.y;
      s.nodes.z[i] += dt * v.z;
    }
  }
}

Vec3 momentum(const PdSystem& s) {
  Vec3 p{};
  for (std::size_t i = 0; i < s.nodes.size(); ++i) p += s.nodes.mass[i] * s.velocity(static_cast<int>(i));
  return p;
}

Vec3 grain_force(const PdSystem& s, int g) {
  Vec3 f{};
  for (int i = s.grains.node_begin[g]; i < s.grains.node_end[g]; ++i) f += s.force(i);
  return f;
}

double grain_mass(const PdSystem& s, int g) {
  double m = 0;
  for (int i = s.grains.node_begin[g]; i < s.grains.node_end[g]; ++i) m += s.nodes.mass[i];
  return m;
}

bool same_bits(Vec3 a, Vec3 b) { return a.x == b.x && a.y == b.y && a.z == b.z; }

class ThreadGuard {
 public:
  ThreadGuard() : saved_(exec::threads()) {}
  ~ThreadGuard() { exec::set_threads(saved_); }

 private:
  int saved_;
};

// The paper's material M1 (Table 1) and its two-particle deck: horizon 0.6 mm.
PdMaterial material_m1() {
  PdMaterial m;
  m.density = 1200;
  m.bulk_modulus = 2.16e7;
  m.shear_modulus = 1.296e7;
  m.fracture_energy = 50;
  m.horizon = 6e-4;
  m.dimension = 2;
  return m;
}

// ---------------------------------------------------------------------------------------------------------
// Parameters

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

void expect_input_error(const std::function<void()>& f, const std::string& key, const std::string& value) {
  try {
    f();
    ADD_FAILURE() << "no InputError for " << key;
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("'" + key + "'"), std::string::npos) << what;
    EXPECT_NE(what.find(value), std::string::npos) << what;
  }
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

// ---------------------------------------------------------------------------------------------------------
// The pair functions

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

// ---------------------------------------------------------------------------------------------------------
// The contact list

using Pairs = std::vector<std::pair<int, int>>;

// Random 3D system: three particle grains with bonds (a third of them broken) and two walls.
PdSystem random_system(std::uint64_t seed, double horizon) {
  PdSystem s;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const int sizes[5] = {120, 90, 110, 60, 50};
  const PdGrainKind kinds[5] = {PdGrainKind::particle, PdGrainKind::particle, PdGrainKind::wall, PdGrainKind::particle,
                                PdGrainKind::wall};
  for (int g = 0; g < 5; ++g) {
    s.begin_grain(kinds[g], g % 2);
    for (int k = 0; k < sizes[g]; ++k)
      s.add_node(Vec3{0.1 * g + 0.5 * u(rng), 0.5 * u(rng), 0.5 * u(rng)}, 1e-3, 1000.0);
  }
  bond_within(s, horizon);
  for (int i = 0; i < static_cast<int>(s.nodes.size()); ++i)
    for (int e = s.bonds.offset[i]; e < s.bonds.offset[i + 1]; ++e)
      if (s.bonds.partner[e] > i && u(rng) < 0.33) break_bond(s.bonds, i, s.bonds.partner[e]);
  return s;
}

Pairs brute_force(const PdSystem& s, double reach) {
  Pairs out;
  const int n = static_cast<int>(s.nodes.size());
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      if (i == j || norm(s.position(i) - s.position(j)) >= reach) continue;
      const int gi = s.nodes.grain[i], gj = s.nodes.grain[j];
      const bool wi = s.grains.kind[gi] == 1, wj = s.grains.kind[gj] == 1;
      if (wi && wj) continue;                                                     // never wall-wall
      if (gi == gj && !s.bonds.offset.empty() && s.bonds.intact(i, j)) continue;  // bonded: not contact
      out.emplace_back(i, j);
    }
  }
  return out;
}

Pairs listed_pairs(const PdContactList& l) {
  Pairs out;
  for (int i = 0; i < l.rows(); ++i)
    for (int k = l.offset()[i]; k < l.offset()[i + 1]; ++k) out.emplace_back(i, l.index()[k]);
  return out;
}

TEST(PdContactList, MatchesBruteForceWithSelfContactAndWalls) {
  const double cutoff = 0.06, skin = 0.02;
  const PdSystem s = random_system(3, 0.12);
  ThreadGuard guard;
  exec::set_threads(1);
  PdContactList one;
  test::build_list(one, s.nodes, s.grains, s.bonds, cutoff, skin);
  exec::set_threads(2);
  PdContactList two;
  test::build_list(two, s.nodes, s.grains, s.bonds, cutoff, skin);
  EXPECT_EQ(one.offset(), two.offset());
  EXPECT_EQ(one.index(), two.index());

  const Pairs ref = brute_force(s, cutoff + skin);
  int self = 0, bonded_close = 0;
  for (const auto& [i, j] : ref) self += s.nodes.grain[i] == s.nodes.grain[j];
  for (int i = 0; i < static_cast<int>(s.nodes.size()); ++i)
    for (int e = s.bonds.offset[i]; e < s.bonds.offset[i + 1]; ++e)
      bonded_close += !s.bonds.broken[e] && norm(s.position(i) - s.position(s.bonds.partner[e])) < cutoff + skin;
  ASSERT_GT(ref.size(), 1000u) << "the test system should have contacts";
  ASSERT_GT(self, 50) << "and self-contacts across broken bonds";
  ASSERT_GT(bonded_close, 50) << "and bonded pairs in range, which must stay out";
  Pairs got = listed_pairs(one);
  std::sort(got.begin(), got.end());
  EXPECT_TRUE(std::adjacent_find(got.begin(), got.end()) == got.end()) << "a pair listed twice";
  EXPECT_EQ(got, ref);

  // Slots: one per (particle grain, partner grain or wall node), holding exactly that pair's list entries.
  std::map<std::pair<int, long>, Pairs> expect;
  const long ng = static_cast<long>(s.grains.size());
  for (const auto& [i, j] : ref) {
    const int p = s.nodes.grain[i], q = s.nodes.grain[j];
    if (p == q || s.grains.kind[p] == 1) continue;
    expect[{p, s.grains.kind[q] == 1 ? ng + j : q}].emplace_back(i, j);
  }
  std::map<std::pair<int, long>, Pairs> slots;
  for (int p = 0; p < static_cast<int>(ng); ++p) {
    for (int sl = one.grain_slot_offset()[p]; sl < one.grain_slot_offset()[p + 1]; ++sl) {
      ASSERT_EQ(one.slot_owner()[sl], p);
      const int jn = one.slot_partner_node()[sl];
      const int q = one.slot_partner_grain()[sl];
      if (jn >= 0) {
        EXPECT_EQ(s.nodes.grain[jn], q);
        EXPECT_EQ(s.grains.kind[q], 1) << "node partners are wall nodes";
      }
      Pairs& v = slots[{p, jn >= 0 ? ng + jn : q}];
      EXPECT_TRUE(v.empty()) << "two slots for one grain pair";
      for (int e = one.slot_pair_offset()[sl]; e < one.slot_pair_offset()[sl + 1]; ++e)
        v.emplace_back(one.slot_pair_i()[e], one.slot_pair_j()[e]);
    }
  }
  for (auto& [k, v] : slots) std::sort(v.begin(), v.end());
  EXPECT_EQ(slots, expect);
  // Every wall-node slot is listed under its wall node.
  int wall_slots = 0;
  for (int j = 0; j < one.rows(); ++j)
    for (int k = one.wall_slot_offset()[j]; k < one.wall_slot_offset()[j + 1]; ++k) {
      EXPECT_EQ(one.slot_partner_node()[one.wall_slot()[k]], j);
      ++wall_slots;
    }
  EXPECT_EQ(wall_slots, static_cast<int>(std::count_if(one.slot_partner_node().begin(), one.slot_partner_node().end(),
                                                       [](int jn) { return jn >= 0; })));
  EXPECT_GT(wall_slots, 20);

  // 2D (all z = 0) with no bonds at all: every same-grain pair in range is a (self-)contact candidate.
  PdSystem flat;
  flat.add_block(PdGrainKind::particle, {0, 0, 0}, 6, 5, 1.0, 1.0);
  flat.add_block(PdGrainKind::wall, {-2, -1.1, 0}, 12, 1, 1.0, 1.0);
  flat.add_block(PdGrainKind::wall, {-2, -2.1, 0}, 12, 1, 1.0, 1.0);
  PdContactList fl;
  test::build_list(fl, flat.nodes, flat.grains, flat.bonds, 1.1, 0.2);
  Pairs fg = listed_pairs(fl);
  std::sort(fg.begin(), fg.end());
  EXPECT_EQ(fg, brute_force(flat, 1.3));
}

TEST(PdContactList, RebuildAfterHalfSkinDriftOrABrokenBond) {
  PdSystem s = random_system(4, 0.12);
  const double skin = 0.02;
  PdContactList l;
  EXPECT_TRUE(test::needs_rebuild(l, s.nodes)) << "never built";
  test::build_list(l, s.nodes, s.grains, s.bonds, 0.06, skin);
  EXPECT_FALSE(test::needs_rebuild(l, s.nodes));
  s.nodes.y[17] += 0.49 * skin;
  EXPECT_FALSE(test::needs_rebuild(l, s.nodes));
  s.nodes.y[17] += 0.02 * skin;
  EXPECT_TRUE(test::needs_rebuild(l, s.nodes)) << "moved 0.51 skin";
  s.nodes.y[17] -= 0.51 * skin;
  EXPECT_FALSE(test::needs_rebuild(l, s.nodes));
  l.request_rebuild();  // a bond broke
  EXPECT_TRUE(test::needs_rebuild(l, s.nodes));
  test::build_list(l, s.nodes, s.grains, s.bonds, 0.06, skin);
  EXPECT_FALSE(test::needs_rebuild(l, s.nodes));
  expect_input_error([&] { test::build_list(l, s.nodes, s.grains, s.bonds, 0.0, skin); }, "pd_contact.cutoff", "0");
  expect_input_error([&] { test::build_list(l, s.nodes, s.grains, s.bonds, 0.06, -1.0); }, "pd_contact.skin", "-1");
}

// Bonds that break after a build enter the list in place: the list is then exactly the one a build at the
// same (build) positions with the current broken flags gives, rows, order and all, so the force sums and a
// restart (which rebuilds from the build positions) agree bit for bit.
TEST(PdContactList, BrokenBondsAddedInPlaceEqualAFullBuild) {
  PdSystem s = random_system(7, 0.12);
  const double cutoff = 0.05, skin = 0.02;
  const PdNodes at_build = s.nodes;
  PdContactList l;
  test::build_list(l, s.nodes, s.grains, s.bonds, cutoff, skin);
  const int slots = l.slots();
  // The nodes drift (less than skin/2), then bonds break in three waves, some of them twice over.
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-0.2 * skin, 0.2 * skin);
  for (std::size_t i = 0; i < s.nodes.size(); ++i) s.nodes.x[i] += u(rng);
  ASSERT_FALSE(test::needs_rebuild(l, s.nodes));
  long added_in_all = 0;
  for (int wave = 0; wave < 3; ++wave) {
    int broken = 0;
    for (int i = 0; i < static_cast<int>(s.nodes.size()) && broken < 25; i += 7)
      for (int k = s.bonds.offset[i]; k < s.bonds.offset[i + 1]; ++k)
        if ((k + wave) % 5 == 0) {
          break_bond(s.bonds, i, s.bonds.partner[k]);
          ++broken;
        }
    const long added = test::add_broken_bonds(l, s.bonds);
    added_in_all += added;
    EXPECT_EQ(test::add_broken_bonds(l, s.bonds), 0) << "nothing left to add";
    PdContactList fresh;
    test::build_list(fresh, at_build, s.grains, s.bonds, cutoff, skin);
    EXPECT_EQ(l.offset(), fresh.offset()) << "wave " << wave;
    EXPECT_EQ(l.index(), fresh.index()) << "wave " << wave;
    EXPECT_EQ(l.slots(), slots) << "self-contact pairs have no slots";
    EXPECT_EQ(l.slot_pair_i(), fresh.slot_pair_i());
  }
  EXPECT_GT(added_in_all, 20) << "the test needs broken bonds within reach";
  EXPECT_FALSE(test::needs_rebuild(l, s.nodes)) << "an in-place update is not a rebuild";

  // A build with bonds broken already starts from them: the next additions are the new bonds only.
  const PdNodes at_rebuild = s.nodes;
  test::build_list(l, s.nodes, s.grains, s.bonds, cutoff, skin);
  EXPECT_EQ(test::add_broken_bonds(l, s.bonds), 0) << "the build holds every bond broken before it";
  int broken = 0;
  for (int i = 3; i < static_cast<int>(s.nodes.size()) && broken < 25; i += 5)
    for (int k = s.bonds.offset[i]; k < s.bonds.offset[i + 1]; ++k)
      if (!s.bonds.broken[static_cast<std::size_t>(k)] && k % 3 == 0) {
        break_bond(s.bonds, i, s.bonds.partner[k]);
        ++broken;
      }
  EXPECT_GT(test::add_broken_bonds(l, s.bonds), 0);
  PdContactList fresh;
  test::build_list(fresh, at_rebuild, s.grains, s.bonds, cutoff, skin);
  EXPECT_EQ(l.offset(), fresh.offset());
  EXPECT_EQ(l.index(), fresh.index());
}

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
TEST(PdIntegrate, ViscousDampingFollowsItsRecurrenceToTheTerminalVelocity) {
  PdSystem s;
  s.begin_grain(PdGrainKind::particle);
  s.add_node({0.0, 0.0, 0.0}, 2e-9, 2500.0);
  s.begin_grain(PdGrainKind::wall);
  s.add_node({1.0, 0.0, 0.0}, 2e-9, 2500.0);
  s.grains.wall_vx[1] = 0.3;
  const double c = 50.0, dt = 1e-3, gy = -9.81, v0 = 2.0;
  s.nodes.vy[0] = v0;
  const double terminal = gy / c;
  const double half = v0 + 0.5 * dt * (gy - c * v0);  // the first step's half kick
  for (int n = 1; n <= 400; ++n) {
    test::pd_weight_forces(s.nodes, s.grains, {0.0, gy, 0.0});
    test::pd_viscous_damping(s.nodes, s.grains, c);
    ASSERT_EQ(s.nodes.fx[1], 0.0) << "a wall node is not damped";
    test::pd_integrate(s.nodes, s.grains, dt, n == 1);
    const double exact = terminal + std::pow(1.0 - c * dt, n - 1) * (half - terminal);
    ASSERT_NEAR(s.nodes.vy[0], exact, 1e-12) << "step " << n;
  }
  EXPECT_NEAR(s.nodes.vy[0], terminal, 1e-3 * std::fabs(terminal));  // (0.95)^399: at the terminal velocity
  EXPECT_EQ(s.nodes.vx[1], 0.3);
}

TEST(PdIntegrate, FreeNodeFollowsTheParabolaFixedComponentsStayWallsMoveAtTheirVelocity) {
  PdSystem s;
  s.begin_grain(PdGrainKind::particle);
  s.add_node({0.1, 0.2, 0.3}, 2e-9, 2500.0);  // free
  s.add_node({1.0, 2.0, 3.0}, 2e-9, 2500.0);  // x and z fixed
  s.nodes.fixed[1] = 1 | 4;
  s.begin_grain(PdGrainKind::wall);
  s.add_node({-1.0, 0.0, 0.5}, 2e-9, 2500.0);
  s.add_node({-1.5, 0.0, 0.5}, 2e-9, 2500.0);
  s.grains.wall_vx[1] = 0.3;
  s.grains.wall_vz[1] = -0.1;
  const Vec3 v0{1.5, 4.0, -0.5}, g{0.0, -9.81, 2.0};
  s.nodes.vx[0] = v0.x;
  s.nodes.vy[0] = v0.y;
  s.nodes.vz[0] = v0.z;
  s.nodes.vx[1] = v0.x;
  s.nodes.vy[1] = v0.y;
  s.nodes.vz[1] = v0.z;
  const double dt = 1e-3;
  for (int n = 1; n <= 2000; ++n) {
    test::pd_weight_forces(s.nodes, s.grains, g);
    s.nodes.fx[2] = 1e6;  // a wall ignores forces
    test::pd_integrate(s.nodes, s.grains, dt, n == 1);
    const double t = n * dt;
    const Vec3 exact = Vec3{0.1, 0.2, 0.3} + t * v0 + (0.5 * t * t) * g;  // eq 32 is exact for constant force
    ASSERT_NEAR(s.nodes.x[0], exact.x, 1e-12 * (1 + std::fabs(exact.x))) << "step " << n;
    ASSERT_NEAR(s.nodes.y[0], exact.y, 1e-12 * (1 + std::fabs(exact.y))) << "step " << n;
    ASSERT_NEAR(s.nodes.z[0], exact.z, 1e-12 * (1 + std::fabs(exact.z))) << "step " << n;
    // The stored velocity is the half-step one, v(t - dt/2).
    ASSERT_NEAR(s.nodes.vy[0], v0.y + g.y * (t - 0.5 * dt), 1e-12);
    ASSERT_EQ(s.nodes.x[1], 1.0);
    ASSERT_EQ(s.nodes.z[1], 3.0);
    ASSERT_EQ(s.nodes.vx[1], 0.0);
    ASSERT_NEAR(s.nodes.y[1], 2.0 + t * v0.y + 0.5 * t * t * g.y, 1e-11);
    ASSERT_NEAR(s.nodes.x[2], -1.0 + 0.3 * t, 1e-12);
    ASSERT_NEAR(s.nodes.x[3], -1.5 + 0.3 * t, 1e-12);
    ASSERT_NEAR(s.nodes.z[3], 0.5 - 0.1 * t, 1e-12);
    ASSERT_EQ(s.nodes.y[3], 0.0);
    ASSERT_EQ(s.nodes.vx[2], 0.3);
  }
  // The first sweep of a step: each particle node's weight, and zero on walls, whatever the forces held.
  for (std::size_t i = 0; i < s.nodes.size(); ++i) s.nodes.fx[i] = s.nodes.fy[i] = s.nodes.fz[i] = 7.0;
  test::pd_weight_forces(s.nodes, s.grains, g);
  for (const int wall_node : {2, 3}) {
    EXPECT_EQ(s.nodes.fx[wall_node], 0.0);
    EXPECT_EQ(s.nodes.fy[wall_node], 0.0);
    EXPECT_EQ(s.nodes.fz[wall_node], 0.0);
  }
  for (const int node : {0, 1}) {
    EXPECT_EQ(s.nodes.fx[node], 0.0);
    EXPECT_DOUBLE_EQ(s.nodes.fy[node], s.nodes.mass[node] * g.y);
    EXPECT_DOUBLE_EQ(s.nodes.fz[node], s.nodes.mass[node] * g.z);
  }
  EXPECT_FALSE(std::signbit(s.nodes.fx[0]));  // g.x = 0: +0.0, as 0.0 + m * 0.0 gives
}

}  // namespace
}  // namespace debris
