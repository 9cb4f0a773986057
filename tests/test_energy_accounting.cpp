// The energy accounting (kernels/dem/energy_accounting.hpp) against what is known without it: the kinetic
// energy a collision loses, computed here from the velocities before and after; the restitution of a linear
// spring-dashpot in closed form; the cap force of eq 4 times the slip a prescribed motion makes, from the
// geometry; a conservative run, where nothing may be dissipated; and the balance on a loaded, sheared block.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include "tests/dem_samples.hpp"

namespace debris {
namespace {

constexpr double kPi = std::numbers::pi;

struct Threads {
  int saved;
  explicit Threads(int n) : saved(exec::threads()) { exec::set_threads(n); }
  ~Threads() { exec::set_threads(saved); }
};

double kinetic(const Particles& p) {
  double e = 0;
  for (std::size_t i = 0; i < p.size(); ++i)
    e += 0.5 * p.mass[i] * (p.vx[i] * p.vx[i] + p.vy[i] * p.vy[i] + p.vz[i] * p.vz[i]) +
         0.5 * p.inertia[i] * (p.wx[i] * p.wx[i] + p.wy[i] * p.wy[i] + p.wz[i] * p.wz[i]);
  return e;
}

// Two equal spheres (Table 4, r = 50) meet head on at v0 and part; the run goes on until they are out of
// each other's range (forces zero, so no elastic energy is left); they start out of range too. The time step
// is small (2e-4 dt_c): what is left between the two is the integrator's error, O(dt^2) between force-free
// states (EnergyAccounting.ConservativeRunClosesToTheIntegratorsError), 1e-4 of the loss at 2.5e-3 dt_c.
struct Collision {
  double ke_before = 0, ke_after = 0;
  EnergyBalance balance;
};
Collision collide(double eta, bool adhesive, double dt_fraction, double v0, double gap = 2.0) {
  const double r = 50;
  Particles p;
  p.add(0, 1, 0, 0, 0, r);
  p.add(1, 1, 2 * r + gap, 0, 0, r);
  p.vx[0] = 0.5 * v0;
  p.vx[1] = -0.5 * v0;
  DemSettings s;
  s.energy_accounting = true;
  s.material = table4_material(0.0);
  s.material.restitution = eta;
  s.options.adhesive = adhesive ? 1 : 0;
  s.time_step_fraction = dt_fraction;
  DemSimulation sim(Box({-500, -500, -500}, {500, 500, 500}, {false, false, false}), p, Groups{}, s);
  Collision c;
  c.ke_before = kinetic(sim.particles());
  bool touched = false;
  for (long n = 0; n < 2000000; ++n) {
    sim.step();
    const Particles& q = sim.particles();
    touched = touched || q.fx[0] != 0.0;
    if (touched && q.fx[0] == 0.0 && q.vx[1] > q.vx[0]) {  // parted: out of range, moving apart
      c.ke_after = kinetic(q);
      c.balance = sim.energy_balance(sim.diagnostics());
      return c;
    }
  }
  ADD_FAILURE() << "the spheres never parted";
  return c;
}

// The normal damping of eq 2 is the only loss of a head-on collision: what it dissipated is what the two
// spheres lost, their kinetic energy before minus after (both computed here from the velocities; apart,
// the pair holds no elastic energy). With the cohesive tail of eq 3 and without it.
TEST(EnergyAccounting, HeadOnCollisionDissipatesWhatTheSpheresLose) {
  for (bool adhesive : {false, true}) {
    // Fast enough to leave the cohesive well (depth k_N delta_e delta_f / 2 at contact) with room to spare.
    const CohesiveMaterial m = table4_material(0.0);
    const double r = 50, mass = 4.0 / 3.0 * kPi * r * r * r;
    const CohesivePairParams pp = cohesive_pair_params(CohesiveCoefficients::from(m), r, r, mass, mass);
    const double depth = 0.5 * pp.k_n * std::min(pp.delta_e, pp.delta_f) * pp.delta_f;
    const double v0 = adhesive ? std::sqrt(8.0 * depth / (0.5 * mass)) : 0.01;
    const Collision c = collide(0.8, adhesive, 0.0002, v0, 1.5 * pp.delta_f);
    const double lost = c.ke_before - c.ke_after;
    std::printf("[ info ] adhesive %d: lost %.10g, normal damping %.10g (%.2e relative), tangential %.3g, sliding %.3g\n",
                adhesive, lost, c.balance.totals.dissipated_normal, c.balance.totals.dissipated_normal / lost - 1,
                c.balance.totals.dissipated_tangential, c.balance.totals.dissipated_sliding);
    ASSERT_GT(lost, 0.01 * c.ke_before);
    EXPECT_NEAR(c.balance.totals.dissipated_normal / lost, 1.0, 1e-6) << "adhesive " << adhesive;
    EXPECT_EQ(c.balance.totals.dissipated_sliding, 0.0);
    EXPECT_EQ(c.balance.totals.dissipated_global, 0.0);
    EXPECT_EQ(c.balance.work_in(), 0.0);  // no drive, no stage
    EXPECT_NEAR(c.balance.elastic, 0.0, 0.0);
  }
}

// A linear spring-dashpot (cohesion off) keeps e^2 of the kinetic energy, e = exp(-pi zeta / sqrt(1 -
// zeta^2)) with zeta = c_N / (2 sqrt(k_N m_eff)) = (1 - eta) / pi for eq 12's c_N (tests/test_dem_damping.cpp
// measures the restitution itself): the accounting's kinetic energy after over before, and 1 minus the
// dissipated fraction, both equal e^2.
TEST(EnergyAccounting, SpringDashpotKeepsTheSquareOfItsRestitution) {
  for (double eta : {0.95, 0.8}) {
    const double zeta = (1.0 - eta) / kPi;
    const double e = std::exp(-kPi * zeta / std::sqrt(1.0 - zeta * zeta));
    const Collision c = collide(eta, false, 0.005, 0.01);
    const double kept = c.balance.kinetic / c.balance.kinetic0;
    std::printf("[ info ] eta = %.2f: kinetic energy kept %.6f, e^2 = %.6f; 1 - dissipated / before %.6f\n", eta, kept,
                e * e, 1 - c.balance.totals.dissipated() / c.ke_before);
    EXPECT_NEAR(kept / (e * e), 1.0, 2e-3);
    EXPECT_NEAR((1 - c.balance.totals.dissipated() / c.ke_before) / (e * e), 1.0, 2e-3);
  }
}

// One sphere slides over another with the tangential spring at its cap: the bottom one frozen, the top one
// moved at a prescribed velocity along x at a fixed height that keeps the pair in compression (dN < 0, so
// the cap of eq 5 is F_mT itself). The contact point's tangential speed is v h / d (h the height, d the
// distance): the spring takes sum |v_T| dt of path, keeps F_mT / k_T of it, and slips the rest. The sliding
// dissipation is F_mT times that slip.
TEST(EnergyAccounting, SlidingDissipatesTheCapForceTimesTheSlip) {
  const double r = 50, h = 96.0, v = 1e-3, x0 = -25.0;
  Particles p;
  p.add(0, 1, 0, 0, 0, r);
  p.add(1, 1, x0, h, 0, r);
  Groups g;
  Group bottom{"bottom", GroupMotion::frozen};
  Group top{"top", GroupMotion::velocity};
  top.velocity = {v, 0, 0};
  p.group[0] = g.add(bottom);
  p.group[1] = g.add(top);
  DemSettings s;
  s.energy_accounting = true;
  s.material = table4_material(0.0);
  s.material.restitution = 0.9;
  s.time_step_fraction = 0.05;
  DemSimulation sim(Box({-500, -500, -500}, {500, 500, 500}, {false, false, false}), p, g, s);
  const double dt = sim.dt();
  const CohesiveCoefficients& c = sim.coefficients();
  const double f_max_t = c.area_t * r * r * c.sigma_t;  // eqs 11, 16 for r_eff = r
  // eq 7 with eq 15: k_N = E A r^2 / (r_i + r_j); eq 8: k_T = (k_T / k_N) k_N
  const double k_t = c.kt_over_kn * c.E * c.area_n * r * r / (2 * r);
  const long steps = static_cast<long>(50.0 / (v * dt));
  double path = 0;
  for (long n = 1; n <= steps; ++n) {
    sim.step();
    const double x = sim.particles().x[1] - sim.particles().x[0];
    path += v * h / std::sqrt(h * h + x * x) * dt;  // this step's tangential increment, at x_n
    ASSERT_LT(std::sqrt(h * h + x * x), 2 * r) << "the pair must stay in compression";
  }
  const double slip = path - f_max_t / k_t;
  ASSERT_GT(slip, 0.5 * path) << "most of the path must be slip";
  const EnergyBalance b = sim.energy_balance(sim.diagnostics());
  std::printf("[ info ] F_mT %.6g, path %.6g, slip %.6g: expected %.10g, sliding dissipation %.10g\n", f_max_t, path,
              slip, f_max_t * slip, b.totals.dissipated_sliding);
  EXPECT_NEAR(b.totals.dissipated_sliding / (f_max_t * slip), 1.0, 1e-6);
  // The drive did the work: its share, what the pair took and stored, close within the integrator's error.
  EXPECT_GT(b.totals.drive_work[1], 0.0);
  EXPECT_EQ(b.totals.drive_work[0], 0.0);  // a frozen body does no work
  EXPECT_LT(std::abs(b.residual()), 1e-3 * b.work_in());
}

// Without damping (eta = 1: c_N = c_T = 0) and without sliding (a head-on collision), nothing is dissipated,
// and the balance closes to the integrator's error: the residual's largest value over the collision (the
// mid-contact, where eq 1's velocity lags the force by half a step) halves with the time step, first order,
// and once the spheres have parted it shrinks faster, second order (README: energy balance).
TEST(EnergyAccounting, ConservativeRunClosesToTheIntegratorsError) {
  double prev_max = 0, prev_end = 0;
  for (double fraction : {0.04, 0.02, 0.01}) {
    const double r = 50, v0 = 0.01;
    Particles p;
    p.add(0, 1, 0, 0, 0, r);
    p.add(1, 1, 2 * r + 2.0, 0, 0, r);
    p.vx[0] = 0.5 * v0;
    p.vx[1] = -0.5 * v0;
    DemSettings s;
    s.energy_accounting = true;
  s.energy_accounting = true;
    s.material = table4_material(0.0);
    s.material.restitution = 1.0;
    s.options.adhesive = 0;  // parts where it met: force-free before and after
    s.time_step_fraction = fraction;
    DemSimulation sim(Box({-500, -500, -500}, {500, 500, 500}, {false, false, false}), p, Groups{}, s);
    const double ke0 = kinetic(sim.particles());
    double worst = 0;
    bool touched = false;
    EnergyBalance b;
    for (long n = 0; n < 1000000; ++n) {
      sim.step();
      b = sim.energy_balance(sim.diagnostics());
      worst = std::max(worst, std::abs(b.residual()));
      touched = touched || sim.particles().fx[0] != 0.0;
      if (touched && sim.particles().fx[0] == 0.0) break;
    }
    EXPECT_EQ(b.totals.dissipated_normal, 0.0);
    EXPECT_EQ(b.totals.dissipated_tangential, 0.0);
    EXPECT_EQ(b.totals.dissipated_global, 0.0);
    // A head-on pair's tangential spring holds only round-off (1e-32 here), let go as it parts.
    EXPECT_LT(b.totals.dissipated_sliding, 1e-12 * ke0);
    EXPECT_EQ(b.work_in(), 0.0);
    const double end = std::abs(b.residual());
    std::printf("[ info ] dt = %.2f dt_c: largest residual %.3e of the kinetic energy, at parting %.3e\n", fraction,
                worst / ke0, end / ke0);
    EXPECT_LT(worst, 0.05 * ke0);
    if (prev_max > 0) {
      EXPECT_NEAR(prev_max / worst, 2.0, 0.3) << "first order during contact";
      // O(dt^2) with a coefficient that depends on where in a step contact begins and ends (measured 3.2 and
      // 14 for these halvings): faster than first order.
      EXPECT_GT(prev_end / end, 2.5) << "second order between force-free states";
    }
    prev_max = worst, prev_end = end;
  }
}

// A loaded, sheared block (tests/dem_samples.hpp: a force-driven top under a load, a frozen base, global
// damping, contacts re-forming, many rebuilds; it starts displaced from its lattice, so most of what it
// dissipates is the elastic energy it starts with): the balance closes within 1% of what went through it, on
// 1 and on 2 threads with the same bits, and the half-list and full-list passes agree.
TEST(EnergyAccounting, ShearedBlockBalancesOnAnyThreadCountAndPass) {
  auto run = [](PairPass pass, int threads) {
    const Threads t(threads);
    DemSimulation sim = test::sheared_dem_system(pass);
    sim.run(1500);
    return sim.energy_balance(sim.diagnostics());
  };
  const EnergyBalance one = run(PairPass::half, 1), two = run(PairPass::half, 2), full = run(PairPass::full, 2);
  std::printf("[ info ] work in %.6g: dKE %.4g, dPE %.4g, normal %.4g, tangential %.4g, sliding %.4g, global %.4g, "
              "residual %.3g\n",
              one.work_in(), one.kinetic - one.kinetic0, one.elastic - one.elastic0, one.totals.dissipated_normal,
              one.totals.dissipated_tangential, one.totals.dissipated_sliding, one.totals.dissipated_global,
              one.residual());
  ASSERT_GT(one.work_in(), 0.0);
  EXPECT_GT(one.totals.dissipated_global, 0.0);
  EXPECT_LT(std::abs(one.residual()), 0.01 * one.totals.dissipated());
  for (const EnergyBalance* b : {&two}) {
    EXPECT_EQ(b->totals.dissipated_normal, one.totals.dissipated_normal);
    EXPECT_EQ(b->totals.dissipated_tangential, one.totals.dissipated_tangential);
    EXPECT_EQ(b->totals.dissipated_sliding, one.totals.dissipated_sliding);
    EXPECT_EQ(b->totals.dissipated_global, one.totals.dissipated_global);
    EXPECT_EQ(b->totals.tangential_work, one.totals.tangential_work);
    EXPECT_EQ(b->totals.drive_work, one.totals.drive_work);
  }
  // The full-list pass sums in another order: the same to round-off, amplified by the run's chaos.
  EXPECT_NEAR(full.totals.dissipated() / one.totals.dissipated(), 1.0, 1e-3);
  EXPECT_LT(std::abs(full.residual()), 0.01 * full.totals.dissipated());
}

// The accounting does not change the dynamics: with it off, the same run agrees to round-off (the pair
// loop with the accounting rounds the forces differently in the last bit), and its columns stay zero.
TEST(EnergyAccounting, OffLeavesTheDynamicsAlone) {
  DemSimulation on = test::sheared_dem_system(), off = test::sheared_dem_system(PairPass::automatic, false, false);
  on.run(300);
  off.run(300);
  const Particles &a = on.particles(), &b = off.particles();
  double worst = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    worst = std::max({worst, std::abs(a.x[i] - b.x[i]), std::abs(a.y[i] - b.y[i]), std::abs(a.z[i] - b.z[i])});
    ASSERT_EQ(b.dissipated_normal[i], 0.0);
    ASSERT_EQ(b.drive_work[i], 0.0);
  }
  EXPECT_LT(worst, 1e-9 * 100);  // particles of diameter 100
  EXPECT_GT(on.energy_balance(on.diagnostics()).totals.dissipated(), 0.0);
}

}  // namespace
}  // namespace debris
