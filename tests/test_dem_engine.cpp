// The whole DEM engine (neighbours, history carry-over, contact pass, groups, semi-implicit Euler) against
// exact references: a pull-out driven by groups against eq 3, stability at the critical step of eq 6,
// conservation of energy, momentum and angular momentum, and invariance under storage order, thread count
// and neighbour rebuilds.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <numeric>
#include <random>

#include "core/comm/exact_sum.hpp"
#include "core/error.hpp"
#include "core/exec.hpp"
#include "core/lattice.hpp"
#include "kernels/dem/integrate.hpp"
#include "scenarios/common/dem/dem_simulation.hpp"
#include "tests/dem_sheared_sample.hpp"

namespace debris {
namespace {

using test::fcc_spec;
using test::run_sheared;
using test::shear_walls;
using test::Snapshot;
using test::table4;


std::size_t index_of(const Particles& p, std::int64_t id) {
  return static_cast<std::size_t>(std::find(p.id.begin(), p.id.end(), id) - p.id.begin());
}

// Two particles: j (id 0) frozen at the origin, i (id 1) driven along +x by a velocity group.
TEST(DemEngine, GroupDrivenPullOutFollowsEq3AndReactionBalances) {
  for (double eta : {1.0, 0.95}) {
    Particles p;
    p.add(0, 1, 0, 0, 0, 50);
    p.add(1, 1, 100 - 8, 0, 0, 50);  // starts 8 into compression
    Groups g;
    Group base{"base", GroupMotion::frozen};
    Group puller{"puller", GroupMotion::velocity};
    puller.velocity = {0.25, 0, 0};
    p.group[0] = g.add(base);
    p.group[1] = g.add(puller);
    DemSettings s;
    s.material = table4(eta);
    s.time_step = 1.0;
    DemSimulation sim(Box({-500, -500, -500}, {500, 500, 500}, {false, false, false}), p, g, s);
    const CohesivePairParams pp = cohesive_pair_params(sim.coefficients(), 50, 50, sim.particles().mass[0],
                                                       sim.particles().mass[1]);
    int regimes[4] = {0, 0, 0, 0};
    for (int step = 0; step < 240; ++step) {
      const Particles& q = sim.particles();
      const std::size_t i = index_of(q, 1), j = index_of(q, 0);
      const double dn = q.x[i] - q.x[j] - 100.0;
      double f_n = 0.0;  // eq 3 written out
      if (dn <= pp.delta_e) f_n = pp.k_n * dn;
      else if (dn <= pp.delta_f) f_n = -pp.k_n * pp.delta_e / (pp.delta_f - pp.delta_e) * (dn - pp.delta_f);
      const double v_n = q.vx[i];
      const double expected = dn <= pp.delta_f ? -(f_n + pp.c_n * v_n) : 0.0;
      ASSERT_NEAR(q.fx[i], expected, 1e-10) << "step " << step << " dN " << dn;
      EXPECT_EQ(q.fx[j], -q.fx[i]);
      // The frozen base reports the reaction, the driven group the opposite.
      EXPECT_EQ(sim.groups().list[0].reaction.x, q.fx[j]);
      EXPECT_EQ(sim.groups().list[1].reaction.x, q.fx[i]);
      regimes[dn < 0 ? 0 : dn <= pp.delta_e ? 1 : dn <= pp.delta_f ? 2 : 3]++;
      sim.step();
    }
    for (int r = 0; r < 4; ++r) EXPECT_GT(regimes[r], 0) << "regime " << r << " never visited";
    EXPECT_NEAR(sim.groups().list[1].displacement.x, 240 * 0.25, 1e-9);
    EXPECT_EQ(sim.groups().list[0].displacement.x, 0.0);
  }
}

// Eq 6: a Hookean pair is bounded just below the critical step and diverges just above it.
TEST(DemEngine, StabilityAtTheCriticalTimeStep) {
  auto amplitude_after = [](double fraction, bool insist) {
    Particles p;
    p.add(0, 1, 0, 0, 0, 50);
    p.add(1, 1, 100 - 0.01, 0, 0, 50);  // 1/2000 of delta_e into compression
    DemSettings s;
    s.material = table4(1.0);
    s.time_step_fraction = fraction;
    s.allow_unstable_time_step = insist;
    DemSimulation sim(Box({-500, -500, -500}, {500, 500, 500}, {false, false, false}), p, Groups{}, s);
    double worst = 0.0;
    for (int step = 0; step < 3000; ++step) {
      sim.step();
      const Particles& q = sim.particles();
      worst = std::max(worst, std::abs(std::abs(q.x[1] - q.x[0]) - 100.0));
      if (worst > 1.0) break;  // ran away (delta_e = 20; 100x the start)
    }
    return worst;
  };
  EXPECT_LT(amplitude_after(0.99, false), 0.1);  // bounded (the ellipse stretches near dt_c, < 10x)
  EXPECT_GT(amplitude_after(1.01, true), 1.0);   // grows by ~1.33 per step
  EXPECT_THROW(amplitude_after(1.01, false), InputError);
}

void random_velocities(Particles& p, double amplitude, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-amplitude, amplitude);
  for (std::size_t i = 0; i < p.size(); ++i) {
    p.vx[i] = u(rng);
    p.vy[i] = u(rng);
    p.vz[i] = u(rng);
    p.wx[i] = u(rng) / p.radius[i];
    p.wy[i] = u(rng) / p.radius[i];
    p.wz[i] = u(rng) / p.radius[i];
  }
}

// Energy without damping. A cohesive FCC cluster at rest in its equilibrium lattice (every nearest pair
// touching) is set vibrating with random velocities and spins: pairs go in and out of tension, tangential
// springs load and unload, nothing breaks or slides. The energy is measured with velocities synchronised to
// the positions (synchronized_kinetic_energy), the O(dt^2) energy of this trajectory.
struct EnergyTrace {
  double first, last, spread, ke0;
  long pairs, lattice_pairs;
};
EnergyTrace vibrate(int tangential, long steps) {
  Lattice lat = make_lattice(fcc_spec({3, 3, 3}));
  random_velocities(lat.particles, 2e-3, 11);
  DemSettings s;
  s.material = table4(1.0);
  s.options.tangential = tangential;
  s.time_step_fraction = 0.1;
  Box box({-1000, -1000, -1000}, {1500, 1500, 1500}, {false, false, false});
  DemSimulation sim(box, lat.particles, Groups{}, s);
  auto energy = [&] { return synchronized_kinetic_energy(sim.particles(), sim.dt()) + sim.diagnostics().elastic_energy; };
  EnergyTrace t{0, 0, 0, particle_totals(sim.particles()).kinetic_energy, 0, 0};
  const long window = steps / 10, every = 50;
  double lo = 1e300, hi = -1e300;
  for (long n = 0; n < steps; ++n) {
    sim.step();
    if (n % every) continue;
    const double e = energy();
    lo = std::min(lo, e);
    hi = std::max(hi, e);
    if (n < window) t.first += e / (window / every);
    if (n >= steps - window) t.last += e / (window / every);
  }
  t.spread = hi - lo;
  t.pairs = sim.diagnostics().interacting_pairs;
  const Particles& q = sim.particles();  // nearest lattice neighbours, by brute force
  for (std::size_t i = 0; i < q.size(); ++i)
    for (std::size_t j = i + 1; j < q.size(); ++j)
      t.lattice_pairs += norm(Vec3{q.x[i] - q.x[j], q.y[i] - q.y[j], q.z[i] - q.z[j]}) < 120.0;
  return t;
}

TEST(DemEngine, EnergyIsConservedWithoutDampingNormalLaw) {
  const EnergyTrace t = vibrate(0, 100000);
  EXPECT_LT(std::abs(t.last - t.first), 2e-3 * t.ke0) << "first " << t.first << " last " << t.last;
  EXPECT_LT(t.spread, 2e-2 * t.ke0);
  EXPECT_EQ(t.pairs, t.lattice_pairs);  // the 12-neighbour bonds, and only those, interact
}

// With the tangential history spring the scheme is no longer symplectic (the spring is an extra state
// updated once per step), so a slow O(dt^2) drift remains: about 1% of the kinetic energy per 1e5 steps at
// 0.1 dt_c, four times less at 0.05 dt_c. No slip and no breakage happen here.
TEST(DemEngine, EnergyIsConservedWithoutDampingFullLaw) {
  const EnergyTrace t = vibrate(1, 100000);
  EXPECT_LT(std::abs(t.last - t.first), 2e-2 * t.ke0) << "first " << t.first << " last " << t.last;
  EXPECT_LT(t.spread, 4e-2 * t.ke0);
  EXPECT_EQ(t.pairs, t.lattice_pairs);
}

// Pair forces (with damping) conserve momentum; their torques conserve angular momentum.
TEST(DemEngine, MomentumAndAngularMomentumAreConserved) {
  Lattice lat = make_lattice(fcc_spec({3, 3, 3}, 0.05, 2.0));
  random_velocities(lat.particles, 0.05, 5);  // strong enough to slide and break some pairs
  DemSettings s;
  s.material = table4(0.8);
  s.time_step_fraction = 0.1;
  Box box({-1000, -1000, -1000}, {1500, 1500, 1500}, {false, false, false});
  DemSimulation sim(box, lat.particles, Groups{}, s);
  const ParticleTotals t0 = particle_totals(sim.particles());
  sim.run(3000);
  const ParticleTotals t1 = particle_totals(sim.particles());
  double p_scale = 0, l_scale = 0;
  for (std::size_t i = 0; i < sim.particles().size(); ++i) {
    const Particles& q = sim.particles();
    const double v = std::sqrt(q.vx[i] * q.vx[i] + q.vy[i] * q.vy[i] + q.vz[i] * q.vz[i]);
    p_scale += q.mass[i] * v;
    l_scale += q.mass[i] * v * std::sqrt(q.x[i] * q.x[i] + q.y[i] * q.y[i] + q.z[i] * q.z[i]);
  }
  EXPECT_LT(norm(t1.momentum - t0.momentum), 1e-12 * p_scale);
  EXPECT_LT(norm(t1.angular_momentum - t0.angular_momentum), 1e-11 * l_scale);
  EXPECT_LT(t1.kinetic_energy, t0.kinetic_energy);  // damping and sliding dissipate
}

// Both contact passes sum each particle's pairs in one fixed order whatever the thread count (full list:
// its row; half list: its own pairs, then those where it is the partner): bit for bit on 1 and 2 threads.
TEST(DemEngine, SameResultsWithOneAndTwoThreads) {
  Lattice lat = make_lattice(fcc_spec({4, 3, 3}, 0.04, 1.0));
  Box box(lat.box.lo(), lat.box.hi(), {true, false, true});
  for (PairPass pass : {PairPass::full, PairPass::half}) {
    const Snapshot a = run_sheared(lat.particles, box, 400, 1, pass);
    const Snapshot b = run_sheared(lat.particles, box, 400, 2, pass);
    for (const auto& [id, va] : a.by_id)
      for (int k = 0; k < 9; ++k)
        ASSERT_EQ(va[k], b.by_id.at(id)[k]) << "id " << id << " component " << k << " pass " << int(pass);
  }
}

// The thread tuner changes the count between steps while a run goes on: the same bits as one thread.
TEST(DemEngine, ThreadCountChangedBetweenStepsGivesTheSameBits) {
  Lattice lat = make_lattice(fcc_spec({4, 3, 3}, 0.04, 1.0));
  Box box(lat.box.lo(), lat.box.hi(), {true, false, true});
  for (PairPass pass : {PairPass::full, PairPass::half}) {
    const Snapshot a = run_sheared(lat.particles, box, 400, 1, pass);
    const Snapshot b = run_sheared(lat.particles, box, 400, 0, pass);
    for (const auto& [id, va] : a.by_id)
      for (int k = 0; k < 9; ++k)
        ASSERT_EQ(va[k], b.by_id.at(id)[k]) << "id " << id << " component " << k << " pass " << int(pass);
  }
}

// The same bits whatever order the particles come in: storage is sorted by cell and then by id at every
// rebuild, and each row lists its neighbours in increasing index, so every per-particle sum has the same
// terms in the same order. This is the serial proxy for any rank count (shared/design/scale-mpi.md, section
// 4): a rank holds its particles in an order of its own. Both passes, 1 and 2 threads, 400 steps of shear
// with rebuilds.
TEST(DemEngine, SameBitsAfterPermutingStorageOrder) {
  Lattice lat = make_lattice(fcc_spec({4, 3, 3}, 0.04, 1.0));
  Box box(lat.box.lo(), lat.box.hi(), {true, false, true});
  Particles shuffled = lat.particles, reversed = lat.particles;
  std::vector<int> order(shuffled.size());
  std::iota(order.begin(), order.end(), 0);
  std::shuffle(order.begin(), order.end(), std::mt19937_64(99));
  shuffled.permute(order);
  std::reverse(order.begin(), order.end());
  std::sort(order.begin(), order.end(), std::greater<>());
  reversed.permute(order);
  for (PairPass pass : {PairPass::full, PairPass::half})
    for (int threads : {1, 2}) {
      const Snapshot a = run_sheared(lat.particles, box, 400, threads, pass);
      double fmax = 0;
      for (const auto& [id, va] : a.by_id) fmax = std::max({fmax, std::abs(va[0]), std::abs(va[1]), std::abs(va[2])});
      ASSERT_GT(fmax, 0.0);
      for (const Particles* q : {&shuffled, &reversed}) {
        const Snapshot b = run_sheared(*q, box, 400, threads, pass);
        for (const auto& [id, va] : a.by_id)
          for (int k = 0; k < 9; ++k)
            ASSERT_EQ(va[k], b.by_id.at(id)[k]) << "id " << id << " component " << k << ", pass " << int(pass)
                                                << ", " << threads << " threads";
      }
    }
}

// The sums the thermo table and the groups read are exact (core/block_sums' ExactPartials): the correctly
// rounded sum of the particles' terms, so the same bits in any storage order (a rank holds its particles in
// an order of its own). Checked on a sheared sample after 200 steps, shuffled three ways, against
// comm::ExactSum of the same terms added one by one on the host (itself checked against exact integer sums
// in tests/mpi/test_exact_sum.cpp).
TEST(DemEngine, ThermoTotalsAndGroupReactionsAreExactSumsInAnyOrder) {
  Lattice lat = make_lattice(fcc_spec({4, 3, 3}, 0.04, 1.0));
  Box box(lat.box.lo(), lat.box.hi(), {true, false, true});
  Particles p0 = lat.particles;
  const Groups g0 = shear_walls(p0, box, {0.02, 0, 0});
  DemSettings s;
  s.material = table4(0.9);
  s.time_step_fraction = 0.1;
  DemSimulation sim(box, p0, g0, s);
  sim.run(200);
  const Particles p = sim.particles();
  // References, term by term.
  comm::ExactSum ke, px, reaction_x[2];
  for (std::size_t i = 0; i < p.size(); ++i) {
    ke.add(0.5 * p.mass[i] * (p.vx[i] * p.vx[i] + p.vy[i] * p.vy[i] + p.vz[i] * p.vz[i]) +
           0.5 * p.inertia[i] * (p.wx[i] * p.wx[i] + p.wy[i] * p.wy[i] + p.wz[i] * p.wz[i]));
    px.add(p.mass[i] * p.vx[i]);
    if (p.group[i] >= 0) reaction_x[p.group[i]].add(p.fx[i]);
  }
  ASSERT_NE(reaction_x[0].value(), 0.0);
  std::vector<int> order(p.size());
  std::iota(order.begin(), order.end(), 0);
  for (int trial = 0; trial < 3; ++trial) {
    Particles q = p;
    if (trial == 1) std::reverse(order.begin(), order.end());
    if (trial == 2) std::shuffle(order.begin(), order.end(), std::mt19937_64(5));
    q.permute(order);
    to_device(q);  // offload builds: the kernels read the device copies
    const ParticleTotals t = particle_totals(q);
    EXPECT_EQ(t.kinetic_energy, ke.value()) << "order " << trial;
    EXPECT_EQ(t.momentum.x, px.value()) << "order " << trial;
    Groups g = sim.groups();
    g.measure_reactions(q);
    for (int k = 0; k < 2; ++k) EXPECT_EQ(g.list[static_cast<std::size_t>(k)].reaction.x, reaction_x[k].value()) << "group " << k;
  }
}

// The contact history of every pair, in tension or compression, survives a rebuild and a re-sort.
void expect_history_survives_rebuild_and_resort(PairPass pass) {
  Lattice lat = make_lattice(fcc_spec({4, 3, 3}, 0.04, 1.0));
  Box box(lat.box.lo(), lat.box.hi(), {true, false, true});
  Particles p = lat.particles;
  const Groups g = shear_walls(p, box, {0.05, 0.01, 0});  // shear and pull: pairs in tension too
  DemSettings s;
  s.material = table4(0.9);
  s.time_step_fraction = 0.1;
  s.pair_pass = pass;
  DemSimulation sim(box, p, g, s);
  ASSERT_EQ(sim.pair_pass(), pass);
  sim.run(300);
  auto collect = [&] {
    std::map<std::pair<std::int64_t, std::int64_t>, std::array<double, 3>> h;
    const Particles& q = sim.particles();
    const NeighborList& nl = sim.neighbors();
    for (int i = 0; i < nl.rows(); ++i)
      for (int k = nl.offset()[i]; k < nl.offset()[i + 1]; ++k) {
        const auto& H = sim.history();
        if (H.hx[k] != 0 || H.hy[k] != 0 || H.hz[k] != 0) {
          // A full list holds both ends (equal and opposite up to round-off): key by (row id, partner id).
          // A half list holds one end, which a re-sort may swap: key by (lower id, higher id), seen from
          // the lower id.
          const std::int64_t a = q.id[i], b = q.id[nl.index()[k]];
          const double sign = (pass == PairPass::full || a < b) ? 1.0 : -1.0;
          const auto key = pass == PairPass::full ? std::make_pair(a, b) : std::make_pair(std::min(a, b), std::max(a, b));
          h[key] = {sign * H.hx[k], sign * H.hy[k], sign * H.hz[k]};
        }
      }
    return h;
  };
  const auto before = collect();
  const auto forces_before = [&] {
    std::map<std::int64_t, std::array<double, 3>> f;
    const Particles& q = sim.particles();
    for (std::size_t i = 0; i < q.size(); ++i) f[q.id[i]] = {q.fx[i], q.fy[i], q.fz[i]};
    return f;
  }();
  // Count loaded pairs in tension: they must survive too.
  int tension = 0;
  {
    const Particles& q = sim.particles();
    for (const auto& [key, v] : before) {
      const std::size_t i = index_of(q, key.first), j = index_of(q, key.second);
      const Vec3 d = minimum_image(sim.box().view(), Vec3{q.x[i] - q.x[j], q.y[i] - q.y[j], q.z[i] - q.z[j]});
      tension += norm(d) > q.radius[i] + q.radius[j];
    }
  }
  ASSERT_GT(before.size(), 100u);
  ASSERT_GT(tension, 10);
  auto expect_same_forces = [&] {
    sim.recompute_forces();
    const Particles& q = sim.particles();
    for (std::size_t i = 0; i < q.size(); ++i) {
      const auto& f = forces_before.at(q.id[i]);
      EXPECT_NEAR(q.fx[i], f[0], 1e-12 * (1 + std::abs(f[0])));
      EXPECT_NEAR(q.fy[i], f[1], 1e-12 * (1 + std::abs(f[1])));
      EXPECT_NEAR(q.fz[i], f[2], 1e-12 * (1 + std::abs(f[2])));
    }
  };
  // Scramble the storage order: every index changes, every pair keeps its state.
  std::vector<int> order(sim.particles().size());
  std::iota(order.begin(), order.end(), 0);
  std::shuffle(order.begin(), order.end(), std::mt19937_64(5));
  const std::int64_t first_id = sim.particles().id[0];
  sim.reorder(order);
  ASSERT_NE(sim.particles().id[0], first_id);
  EXPECT_EQ(before, collect());
  expect_same_forces();
  // And back to cell order through an ordinary rebuild.
  sim.rebuild_neighbors();
  EXPECT_EQ(before, collect());
  expect_same_forces();
}

TEST(DemEngine, HistorySurvivesRebuildAndResortFullList) { expect_history_survives_rebuild_and_resort(PairPass::full); }
TEST(DemEngine, HistorySurvivesRebuildAndResortHalfList) { expect_history_survives_rebuild_and_resort(PairPass::half); }

}  // namespace
}  // namespace debris
