// Damping of the cohesive DEM against closed forms written out here from the paper, not from the code:
// the pair damping c_N of eq 12 in a head-on collision of two spheres (linear spring-dashpot, whose
// restitution is exp(-pi zeta / sqrt(1 - zeta^2))), and the global damping c = f c_c of eq 21 on free
// bodies (exponential decay of the velocity).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include "scenarios/common/dem/dem_simulation.hpp"

namespace debris {
namespace {

constexpr double kPi = std::numbers::pi;

// Table 4 (E = 1, nu = 0.15, rho = 1) with the given restitution.
CohesiveMaterial table4(double eta) {
  CohesiveMaterial m = table4_material(0.0);
  m.restitution = eta;
  return m;
}

double sphere_mass(double r, double rho) { return rho * 4.0 / 3.0 * kPi * r * r * r; }

// Eqs 7 and 15 for two spheres of radius r: k_N = sqrt(2) r^2 / (1 - 2 nu) E / (2 r).
double eq7_k_n(const CohesiveMaterial& m, double r) {
  return std::sqrt(2.0) * r * r / (1.0 - 2.0 * m.poisson_ratio) * m.youngs_modulus / (2.0 * r);
}

// Head-on collision of two equal spheres (r = 50), adhesion and tangential forces off, so that the pair is
// the linear spring-dashpot m_eff x'' + c_N x' + k_N x = 0 of eq A.2 while x < 0. Returns the measured
// restitution (separation speed / approach speed).
double measured_restitution(double eta, double dt_fraction) {
  const double r = 50, v0 = 0.01;  // max overlap ~ v0 / omega ~ 0.2: deep in the Hookean range
  Particles p;
  p.add(0, 1, 0, 0, 0, r);
  p.add(1, 1, 2 * r + 1e-3, 0, 0, r);
  p.vx[0] = 0.5 * v0;
  p.vx[1] = -0.5 * v0;
  DemSettings s;
  s.material = table4(eta);
  s.options.adhesive = 0;  // eq 3 only where dN <= 0: no cohesive tail to cross on the way out
  s.options.tangential = 0;
  s.time_step_fraction = dt_fraction;
  DemSimulation sim(Box({-500, -500, -500}, {500, 500, 500}, {false, false, false}), p, Groups{}, s);
  bool touched = false;
  for (long n = 0; n < 200000; ++n) {
    sim.step();
    const Particles& q = sim.particles();
    const double gap = std::abs(q.x[1] - q.x[0]) - 2 * r;
    if (gap < 0) touched = true;
    if (touched && gap > 0 && q.fx[0] == 0.0) {
      // Order-independent: the separation speed is |v_1 - v_0| along the line of centres.
      return std::abs(q.vx[1] - q.vx[0]) / v0;
    }
  }
  ADD_FAILURE() << "the spheres never separated";
  return 0;
}

// Eq 12, c_N = 2 (1 - eta) / pi sqrt(k_N m_eff), is a damping ratio zeta = c_N / (2 sqrt(k_N m_eff)) =
// (1 - eta) / pi. A linear spring-dashpot in contact while x < 0 leaves after half a damped period with
// e = exp(-pi zeta / sqrt(1 - zeta^2)) (the paper linearises this in A.43-A.44, so eta is matched to
// O((1 - eta) zeta^2): 0.13% at eta = 0.95, 20% at eta = 0.5). The scheme's error is O(zeta omega dt)
// (the damping force uses v_n, half a step behind) plus the step on which the contact ends: at
// dt = 0.01 dt_c (omega dt = 0.02, ~160 steps per contact) it measured 0.005%, 0.07% and 0.47% at eta =
// 0.95, 0.8, 0.5; at the 0.005 dt_c used here 0.006%, 0.08% and 0.05%.
TEST(DemDamping, TwoBodyCollisionRestitutionMatchesTheSpringDashpotClosedFormOfEq12) {
  for (double eta : {0.95, 0.8, 0.5}) {
    const double zeta = (1.0 - eta) / kPi;
    const double closed_form = std::exp(-kPi * zeta / std::sqrt(1.0 - zeta * zeta));
    const double e = measured_restitution(eta, 0.005);
    std::printf("[ info ] eta = %.2f: measured restitution %.6f, spring-dashpot closed form %.6f (%.3f%%)\n", eta, e,
                closed_form, 100 * (e / closed_form - 1));
    EXPECT_NEAR(e / closed_form, 1.0, 2e-3) << "eta " << eta;
    if (eta == 0.95) EXPECT_NEAR(e, eta, 0.01 * eta) << "eq 12 targets eta within its linearisation";
  }
  // Without damping (eta = 1) the Hookean collision is elastic: symplectic Euler returns the speed to O(dt^2).
  EXPECT_NEAR(measured_restitution(1.0, 0.01), 1.0, 1e-3);
}

// Global damping F = -c v on free particles, c = f c_c with c_c = sqrt(2 k_N m) of eq 21 for the smallest
// particle (section 3). Two free spheres of different sizes, far apart (no pair force): with forces taken
// at v_n (eq 1), each speed decays exactly as (1 - c dt / m)^n, which approaches exp(-c t / m) as dt -> 0
// (relative gap n (c dt / m)^2 / 2: 0.2% here for the small sphere).
TEST(DemDamping, GlobalDampingDecaysAFreeBodyAtTheRateOfEq21) {
  const CohesiveMaterial mat = table4(0.95);
  const double r_small = 50, r_large = 100, fraction = 0.2;
  Particles p;
  p.add(0, 1, -300, 0, 0, r_small);
  p.add(1, 1, 300, 0, 0, r_large);
  p.vx[0] = 0.01;
  p.vy[0] = -0.02;
  p.vz[1] = 0.03;
  DemSettings s;
  s.material = mat;
  s.time_step_fraction = 0.005;
  s.global_damping = fraction;
  DemSimulation sim(Box({-1000, -1000, -1000}, {1000, 1000, 1000}, {false, false, false}), p, Groups{}, s);

  const double m_small = sphere_mass(r_small, mat.density), m_large = sphere_mass(r_large, mat.density);
  const double c_c = std::sqrt(2.0 * eq7_k_n(mat, r_small) * m_small);  // eq 21, smallest particle
  const double dt_c = std::sqrt(2.0 * m_small / eq7_k_n(mat, r_small));  // eq 6
  const double c = fraction * c_c, dt = 0.005 * dt_c;
  EXPECT_NEAR(sim.damping_coefficient(), c, 1e-12 * c);
  EXPECT_NEAR(sim.dt(), dt, 1e-12 * dt);

  const long steps = 1000;  // c t / m_small = 0.2 * 0.005 * 2 * 1000 = 2
  sim.run(steps);
  const double t = steps * dt;
  const Particles& q = sim.particles();
  for (std::size_t i = 0; i < q.size(); ++i) {
    const bool small = q.id[i] == 0;
    const double m = small ? m_small : m_large;
    const double vx0 = small ? 0.01 : 0.0, vy0 = small ? -0.02 : 0.0, vz0 = small ? 0.0 : 0.03;
    const double discrete = std::pow(1.0 - c * dt / m, static_cast<double>(steps));
    const double continuous = std::exp(-c * t / m);
    const double speed0 = std::sqrt(vx0 * vx0 + vy0 * vy0 + vz0 * vz0);
    const double speed = std::sqrt(q.vx[i] * q.vx[i] + q.vy[i] * q.vy[i] + q.vz[i] * q.vz[i]);
    std::printf("[ info ] r = %g: v/v0 = %.6f, (1 - c dt/m)^n = %.6f, exp(-c t/m) = %.6f\n", q.radius[i],
                speed / speed0, discrete, continuous);
    EXPECT_NEAR(speed / speed0, discrete, 1e-10) << "r " << q.radius[i];
    EXPECT_NEAR(speed / speed0 / continuous, 1.0, 5e-3) << "r " << q.radius[i];
    // The direction is kept: damping is along -v.
    EXPECT_NEAR(q.vx[i], vx0 * discrete, 1e-12);
    EXPECT_NEAR(q.vy[i], vy0 * discrete, 1e-12);
    EXPECT_NEAR(q.vz[i], vz0 * discrete, 1e-12);
  }
}

}  // namespace
}  // namespace debris
