// PeriDEM (paper B) against independent references: the stable step of eq 32 that PeridemSimulation
// estimates (power iteration on the bond forces plus a contact spring) against a full eigenvalue solve of
// the assembled stiffness (Eigen), and two grains colliding without damping or friction conserving the total
// energy (kinetic + LPS bond + contact).
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "kernels/peridem/pd_bond_passes.hpp"
#include "kernels/peridem/pd_integrate.hpp"
#include "scenarios/common/peridem/peridem_input.hpp"
#include "scenarios/common/peridem/peridem_simulation.hpp"
#include "tests/pd_on_device.hpp"

namespace debris {
namespace {

const char* kMaterial =
    "materials:\n"
    "  M1: {density: 1200 kg/m^3, bulk_modulus: 0.0216 GPa, shear_modulus: 0.01296 GPa,\n"
    "       fracture_energy: 1e9 J/m^2, horizon: 0.9 mm}\n";

PeridemSimulation make(const std::string& yaml) {
  PeridemInputOptions o;
  o.output_directory = ::testing::TempDir();
  PeridemRunConfig cfg = read_peridem_input_text(yaml, "stable_step", ".", o);
  return PeridemSimulation(std::move(cfg.nodes), std::move(cfg.grains), cfg.materials, cfg.contact, cfg.settings);
}

// omega_max^2 of the linearised bond forces of a grain at rest: K assembled column by column from central
// differences of the bond force passes (amplitude 1e-7 h; the force is smooth there), then the largest
// eigenvalue of M^-1/2 K M^-1/2 by a dense symmetric solve.
double exact_bond_lambda_max(const PeridemSimulation& sim, int dimension) {
  const PdNodes& ref = sim.nodes();
  const std::size_t n = ref.size();
  PdLpsTable lps;
  for (const PdMaterial& m : sim.materials()) lps.push_back(PdLpsConstants::from(m));
  const int dofs = static_cast<int>(n) * dimension;
  Eigen::MatrixXd K(dofs, dofs);
  PdNodes work = ref;
  const double a = 1e-7 * sim.mesh_size();
  auto forces = [&](int k, double shift, Eigen::VectorXd& f) {
    for (std::size_t i = 0; i < n; ++i) {
      work.x[i] = ref.x0[i];
      work.y[i] = ref.y0[i];
      work.z[i] = ref.z0[i];
    }
    const std::size_t node = static_cast<std::size_t>(k / dimension);
    (k % dimension == 0 ? work.x : k % dimension == 1 ? work.y : work.z)[node] += shift;
    test::pd_zero_forces(work);
    test::pd_dilatation_pass(lps, sim.grains(), sim.bonds(), work);
    test::pd_bond_force_pass(lps, sim.grains(), sim.bonds(), work);
    for (std::size_t i = 0; i < n; ++i) {
      const double fi[3] = {work.fx[i], work.fy[i], work.fz[i]};
      for (int c = 0; c < dimension; ++c) f[static_cast<int>(i) * dimension + c] = fi[c];
    }
  };
  Eigen::VectorXd fp(dofs), fm(dofs);
  for (int k = 0; k < dofs; ++k) {
    forces(k, a, fp);
    forces(k, -a, fm);
    K.col(k) = -(fp - fm) / (2 * a);
  }
  // K is the Hessian of the bond energy (tests/test_pd_bonds.cpp: force = -gradient): symmetric up to the
  // differences' round-off.
  EXPECT_LT((K - K.transpose()).norm(), 1e-6 * K.norm());
  Eigen::VectorXd inv_sqrt_m(dofs);
  for (int k = 0; k < dofs; ++k) inv_sqrt_m[k] = 1.0 / std::sqrt(ref.mass[static_cast<std::size_t>(k / dimension)]);
  const Eigen::MatrixXd A = inv_sqrt_m.asDiagonal() * (0.5 * (K + K.transpose())) * inv_sqrt_m.asDiagonal();
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> solver(A, Eigen::EigenvaluesOnly);
  return solver.eigenvalues().maxCoeff();
}

// The estimate is 2 / sqrt(1.10 lambda_power + lambda_contact) with lambda_contact = K_n 2 V_max / rho for
// two particle nodes (PeridemSimulation's constructor). On a free grain the contact spring dominates (the
// bonds alone allow a step ~7 times longer), so the bond part is taken out of the estimate,
// lambda_power = (4 / dt^2 - lambda_contact) / 1.10, and compared with the exact eigenvalue: the Rayleigh
// quotient of the power iteration lies below it, and the 10% margin must bring it back above (a step the
// estimate allows is stable). The finest mesh (about 450 nodes) has the most crowded spectrum, where power
// iteration converges slowest.
TEST(PdStableStep, EstimateAgreesWithAnEigenvalueSolveOfTheAssembledStiffness) {
  for (const char* mesh : {"0.3 mm", "0.15 mm", "0.1 mm"}) {
    const std::string yaml = std::string("dimension: 2\n") + kMaterial +
                             "shapes:\n  disc: {type: circle, radius: 1 mm, mesh_size: " + mesh +
                             "}\n"
                             "grains:\n  - {name: disc, shape: disc, material: M1, centre: [0, 0, 0]}\n"
                             "contact: {contact_radius_factor: 0.95, restitution: 1, damping_factor: 100, friction: 0}\n"
                             "run: {time_step: 1 ns, steps: 1}\n"
                             "output: {directory: unused}\n";
    PeridemSimulation sim = make(yaml);
    const double lambda = exact_bond_lambda_max(sim, 2);
    double vmax = 0;
    for (double v : sim.nodes().volume) vmax = std::max(vmax, v);
    const double lambda_contact = sim.contact_table().pair(0, 0).k_n * 2 * vmax / sim.materials()[0].density;
    const double dt = sim.stable_time_step();
    const double lambda_power = (4.0 / (dt * dt) - lambda_contact) / 1.10;
    const double reference = 2.0 / std::sqrt(lambda + lambda_contact);
    std::printf("[ info ] mesh %s, %zu nodes: bonds' omega_max^2 %.6g (power iteration %.6g, ratio %.4f); stable step "
                "%.6g s against %.6g s with the exact eigenvalue\n",
                mesh, sim.nodes().size(), lambda, lambda_power, lambda_power / lambda, dt, reference);
    EXPECT_LE(lambda_power, lambda * (1 + 1e-6)) << mesh << ": a Rayleigh quotient above the largest eigenvalue";
    EXPECT_GE(lambda_power, 0.95 * lambda) << mesh << ": power iteration far from converged";
    EXPECT_GE(1.10 * lambda_power, lambda) << mesh << ": the margin does not cover the power iteration's shortfall";
    EXPECT_LE(dt, reference * (1 + 1e-9)) << mesh;
  }
}

// Two equal discs (R = 1 mm) approach at 2 x 0.5 m/s and bounce, with contact damping and friction off
// (restitution 1, friction 0) and bonds too strong to break: eq 32 is symplectic, so kinetic + bond +
// contact energy is conserved to O(dt^2) over the collision. The kinetic energy uses velocities half a step
// behind the positions (PeridemDiagnostics), an O(dt) bias on a fluctuating part; at dt = 0.1 us (about
// 1/3 of the stable step) the total came back to within 0.02% of its start after the collision, which at
// its height holds nearly all of it in the springs, and stayed within 0.7% throughout.
TEST(PdEnergy, TwoGrainsCollidingWithoutDampingConserveTotalEnergy) {
  const std::string yaml = std::string("dimension: 2\n") + kMaterial +
                           "shapes:\n  disc: {type: circle, radius: 1 mm, mesh_size: 0.3 mm}\n"
                           "grains:\n"
                           "  - {name: a, shape: disc, material: M1, centre: [0, 1.2 mm, 0], velocity: [0, -0.5 m/s, 0]}\n"
                           "  - {name: b, shape: disc, material: M1, centre: [0, -1.2 mm, 0], velocity: [0, 0.5 m/s, 0]}\n"
                           "contact: {contact_radius_factor: 0.95, restitution: 1, damping_factor: 100, friction: 0}\n"
                           "run: {time_step: 0.1 us, steps: 1}\n"
                           "output: {directory: unused}\n";
  PeridemSimulation sim = make(yaml);
  auto total = [&sim] {
    const PeridemDiagnostics d = sim.diagnostics();
    return d.kinetic_energy + d.bond_energy + d.contact_energy;
  };
  sim.run(1);  // the first step kicks by dt/2: from here on the stored velocity is the half-step one
  const double e0 = total();
  double lo = e0, hi = e0, most_in_springs = 0;
  bool touched = false, left = false;
  for (long s = 0; s < 60000 && !left; s += 20) {
    sim.run(20);
    const PeridemDiagnostics d = sim.diagnostics();
    const double e = d.kinetic_energy + d.bond_energy + d.contact_energy;
    lo = std::min(lo, e);
    hi = std::max(hi, e);
    most_in_springs = std::max(most_in_springs, (d.bond_energy + d.contact_energy) / e0);
    touched = touched || d.contact_pairs > 0;
    sim.refresh_grain_centres();
    left = touched && d.contact_pairs == 0 && sim.grains().cvy[0] > 0;
    if (left) sim.run(2000);  // and a while after, the discs ringing
  }
  const double e1 = total();
  std::printf("[ info ] undamped collision: energy %.6g J at start, %.6g J after (%.3f%%), range %.3f%%, up to "
              "%.1f%% held in the springs\n",
              e0, e1, 100 * (e1 / e0 - 1), 100 * (hi - lo) / e0, 100 * most_in_springs);
  ASSERT_TRUE(touched) << "the discs never met";
  ASSERT_TRUE(left) << "the discs never separated";
  EXPECT_EQ(sim.broken_bonds(), 0);
  EXPECT_NEAR(e1 / e0, 1.0, 1e-3);
  EXPECT_LT((hi - lo) / e0, 1e-2);
}

}  // namespace
}  // namespace debris
