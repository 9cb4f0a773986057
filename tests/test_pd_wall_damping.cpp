// A rigid wall damps a grain like a body of infinite mass (paper B, eqs 21-30 with the wall's mass taken as
// infinite). The same disc is shot at 1 m/s, without gravity, at (a) a fixed wall and (b) a free grain of the
// same shape, mesh and elastic constants as the wall but 1e6 times denser: in the limit the two are the same
// obstacle, so the coefficients of restitution must agree, for both dampings (between node pairs and
// between grain centres). Before this was fixed, the wall used the mass of one wall node as the partner's
// mass, and a disc with restitution 0.5 rebounded from it with C_R = 0.95 (grain centres) and 0.995 (node
// pairs), against 0.68 from a grain.
//
// Measured (mesh 0.3 mm, dt 0.1 us, restitution 0.5): grain centres C_R 0.6281 (wall) and 0.6281 (heavy
// grain); node pairs 0.9878 and 0.9877 (eq 22 damps each node pair with the nodes' own small masses, so it
// hardly damps a disc whatever the partner); elastic (restitution 1) 0.9914 and 0.9913 for both, the
// set-up's own loss (waves left ringing in the disc). The elastic rebound's energy (kinetic + bond + contact,
// no gravity) stays within +2.7e-4 / -1.1e-4 of the impact's kinetic energy through the contact and ends
// 3.4e-5 (wall) and 1.8e-5 (heavy grain) above it; 98.3% of it is in the disc's translation at the end.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "scenarios/common/peridem/peridem_input.hpp"
#include "scenarios/common/peridem/peridem_simulation.hpp"
#include "tests/pd_on_device.hpp"

namespace debris {
namespace {

// The obstacle is a 6 x 0.6 mm block, as wall or as grain; the disc (R = 1 mm) starts 0.05 mm beyond the
// contact radius above its centre, moving down at 1 m/s.
std::string drop_input(bool wall, const std::string& damping, double restitution) {
  const std::string obstacle = wall ? "walls:\n  - {name: floor, shape: block, material: M1}\n" : "";
  const std::string heavy = wall ? "" : "  - {name: floor, shape: block, material: heavy, centre: [0, -0.3 mm, 0], radius: 3 mm}\n";
  return "dimension: 2\n"
         "materials:\n"
         "  M1: {density: 1200 kg/m^3, bulk_modulus: 0.0216 GPa, shear_modulus: 0.01296 GPa,\n"
         "       fracture_energy: 1e9 J/m^2, horizon: 0.9 mm}\n"
         "  heavy: {density: 1.2e9 kg/m^3, bulk_modulus: 0.0216 GPa, shear_modulus: 0.01296 GPa,\n"
         "          fracture_energy: 1e9 J/m^2, horizon: 0.9 mm}\n"
         "shapes:\n"
         "  disc: {type: circle, radius: 1 mm, mesh_size: 0.3 mm}\n" +
         std::string(wall ? "  block: {type: rectangle, lo: [-3 mm, -0.6 mm, 0], hi: [3 mm, 0, 0], mesh_size: 0.3 mm}\n"
                          : "  block: {type: rectangle, lo: [-3 mm, -0.3 mm, 0], hi: [3 mm, 0.3 mm, 0], mesh_size: 0.3 mm,\n           reference_radius: 3 mm}\n") +
         "grains:\n"
         "  - {name: disc, shape: disc, material: M1, centre: [0, 1.22 mm, 0], velocity: [0, -1 m/s, 0]}\n" + heavy +
         obstacle +
         "contact: {contact_radius_factor: 0.95, restitution: " + std::to_string(restitution) +
         ", damping_factor: 100, friction: 0, damping: " + damping +
         "}\n"
         "run: {time_step: 0.1 us, steps: 40000}\n"
         "output: {directory: unused}\n";
}

// What one rebound gives: C_R, and the energy budget sampled every 50 steps (and at the end): total energy
// E = kinetic + bond + contact (no gravity here, and the wall stores none), its largest excursion from the
// initial 1/2 M v_in^2 in either direction, and the disc's share of it in translation at the end.
struct Rebound {
  double restitution = 0;          // rebound speed over impact speed of the disc's centre
  double e0 = 0;                   // kinetic energy at the start (J/m), all of the energy there is
  double max_excess = 0;           // largest (E - E0) / E0 over the samples
  double max_deficit = 0;          // largest (E0 - E) / E0 over the samples
  double end_energy = 0;           // E / E0 when the disc has left
  double end_translational = 0;    // 1/2 M v_c^2 / E0 of the disc then (C_R^2 times the impact's)
};

// Rebound speed over impact speed of the disc's centre, once it has left the obstacle.
Rebound rebound_of(bool wall, const std::string& damping, double restitution) {
  PeridemInputOptions o;
  o.output_directory = ::testing::TempDir();
  PeridemRunConfig cfg = read_peridem_input_text(drop_input(wall, damping, restitution), "wall_damping", ".", o);
  PeridemSimulation sim(std::move(cfg.nodes), std::move(cfg.grains), cfg.materials, cfg.contact, cfg.settings);
  sim.refresh_grain_centres();
  const double v_in = -sim.grains().cvy[0], y0 = sim.grains().cy[0];
  EXPECT_GT(v_in, 0.99);
  Rebound out;
  out.e0 = sim.diagnostics().kinetic_energy;
  double disc_mass = 0;
  const PeridemSimulation& view = sim;  // reads, not edits
  for (int i = view.grains().node_begin[0]; i < view.grains().node_end[0]; ++i) disc_mass += view.nodes().mass[i];
  // E at step n: bond and contact energy at x^n, kinetic energy from v^n = (v^{n-1/2} + v^{n+1/2}) / 2 (eq 32
  // stores v half a step behind x; that lag alone moves 1/2 m v^2 by dt/2 times the power of the forces,
  // 0.4% of E0 at the height of this impact). Takes the step to n + 1.
  std::vector<double> vx0, vy0;
  const auto energy_step = [&] {
    const PeridemDiagnostics d = sim.diagnostics();
    vx0.assign(view.nodes().vx.begin(), view.nodes().vx.end());
    vy0.assign(view.nodes().vy.begin(), view.nodes().vy.end());
    sim.step();
    const PdNodes& n = view.nodes();
    double ke = 0;
    for (std::size_t i = 0; i < n.size(); ++i) {
      const double ux = 0.5 * (vx0[i] + n.vx[i]), uy = 0.5 * (vy0[i] + n.vy[i]);
      if (view.grains().kind[n.grain[i]] != static_cast<int>(PdGrainKind::wall)) ke += 0.5 * n.mass[i] * (ux * ux + uy * uy);
    }
    const double e = ke + d.bond_energy + d.contact_energy;
    out.max_excess = std::max(out.max_excess, (e - out.e0) / out.e0);
    out.max_deficit = std::max(out.max_deficit, (out.e0 - e) / out.e0);
    return e / out.e0;
  };
  bool touched = false;
  for (long s = 0; s < 40000; s += 50) {
    // Sampled every 10 steps from the first contact on (the contact lasts about 1,000 steps); before it,
    // free flight changes nothing.
    double e = 1.0;
    if (touched || sim.touching_pairs() > 0)
      for (int k = 0; k < 5; ++k) {
        sim.run(9);
        e = energy_step();
      }
    else
      sim.run(50);
    const long touching = sim.touching_pairs();
    touched = touched || touching > 0;
    sim.refresh_grain_centres();
    // Node pairs touch on and off during one impact (a discrete surface): the rebound is over when the
    // disc is back where it started, out of range.
    if (touched && touching == 0 && sim.grains().cy[0] >= y0) {
      EXPECT_EQ(sim.health_check(), "");
      const double vx = sim.grains().cvx[0], vy = sim.grains().cvy[0];
      out.restitution = vy / v_in;
      out.end_energy = e;
      out.end_translational = 0.5 * disc_mass * (vx * vx + vy * vy) / out.e0;
      return out;
    }
  }
  ADD_FAILURE() << "the disc did not leave the obstacle within 4 ms";
  return out;
}

double restitution_of(bool wall, const std::string& damping, double restitution) {
  return rebound_of(wall, damping, restitution).restitution;
}

TEST(PdWallDamping, WallDampsLikeAGrainOfInfiniteMass) {
  for (const std::string damping : {"grain_centres", "node_pairs"}) {
    const double wall = restitution_of(true, damping, 0.5);
    const double grain = restitution_of(false, damping, 0.5);
    SCOPED_TRACE(damping);
    EXPECT_NEAR(wall, grain, 0.005);
    if (damping == "grain_centres") {  // really damped (a wall node's own mass would give 0.95), still a rebound
      EXPECT_GT(wall, 0.5);
      EXPECT_LT(wall, 0.75);
    } else {  // damped, if little: below the elastic rebound
      EXPECT_LT(wall, 0.990);
    }
  }
}

TEST(PdWallDamping, ElasticReboundIsLossless) {
  for (const std::string damping : {"grain_centres", "node_pairs"})
    for (const bool wall : {true, false}) {
      SCOPED_TRACE(damping + (wall ? ", wall" : ", heavy grain"));
      const Rebound r = rebound_of(wall, damping, 1.0);
      std::printf("[ info ] %s, %s: C_R = %.5f; energy within +%.2g / -%.2g of E0, %.6f E0 at the end (%.4f E0 in "
                  "the disc's translation)\n", damping.c_str(), wall ? "wall" : "heavy grain", r.restitution,
                  r.max_excess, r.max_deficit, r.end_energy, r.end_translational);
      // The energy budget of the undamped rebound (restitution 1: beta = 0 in both dampings, and bonds that
      // cannot break): kinetic + bond + contact energy is E0 through the impact to 1e-3 (four times the
      // excursion measured, 2.7e-4: the central difference's error on the ringing disc) and after it to
      // 1e-4 (measured 3.4e-5 and 1.8e-5).
      EXPECT_LT(r.max_excess, 1e-3);
      EXPECT_LT(r.max_deficit, 1e-3);
      EXPECT_NEAR(r.end_energy, 1.0, 1e-4);
      // Hence the rebound from both sides. The disc's translation is part of that energy, so C_R^2 is at
      // most E / E0 (the rest rings in the disc: 1.7% of E0), and C_R <= sqrt(1 + 1e-4) < 1 + 1e-4: a
      // rebound that gains energy fails. Below, 0.99 (measured 0.9913-0.9914) bounds the ringing loss.
      EXPECT_LE(r.restitution * r.restitution, r.end_translational * (1 + 1e-12));
      EXPECT_LE(r.end_translational, r.end_energy);
      EXPECT_LE(r.restitution, 1.0 + 1e-4);
      EXPECT_GT(r.restitution, 0.99);
    }
}

// wall_reactions() adds every pair force and damping share the wall exerts, each exactly, from the particles'
// end (pd_wall_reaction_sums: the same bits on any rank count); the wall's own node forces, added in node order,
// are the same sum rounded along the way. Through an impact with friction (a sliding disc) and both dampings,
// the two agree to 1e-9 of the reaction's size, and the reaction pushes the floor down.
TEST(PdWallDamping, WallReactionIsTheSumOfTheWallsNodeForces) {
  for (const std::string damping : {"grain_centres", "node_pairs"}) {
    SCOPED_TRACE(damping);
    std::string text = drop_input(true, damping, 0.5);
    text.replace(text.find("friction: 0"), 11, "friction: 0.4");
    text.replace(text.find("velocity: [0, -1 m/s, 0]"), 24, "velocity: [0.5 m/s, -1 m/s, 0]");
    PeridemInputOptions o;
    o.output_directory = ::testing::TempDir();
    PeridemRunConfig cfg = read_peridem_input_text(text, "wall_reaction", ".", o);
    PeridemSimulation sim(std::move(cfg.nodes), std::move(cfg.grains), cfg.materials, cfg.contact, cfg.settings);
    const PeridemSimulation& view = sim;
    const int floor = 1;
    ASSERT_EQ(view.grains().kind[floor], static_cast<int>(PdGrainKind::wall));
    int compared = 0;
    for (int s = 0; s < 4000 && compared < 20; s += 20) {
      sim.run(20);
      if (sim.touching_pairs() == 0) continue;
      std::vector<Vec3> node_sums;
      test::pd_wall_reactions(view.nodes(), view.grains(), node_sums);
      const std::vector<Vec3> exact = sim.wall_reactions();
      ASSERT_EQ(exact.size(), view.grains().size());
      const double size = std::hypot(node_sums[floor].x, node_sums[floor].y);
      EXPECT_LT(node_sums[floor].y, 0) << "step " << sim.step_count();
      EXPECT_NEAR(exact[floor].x, node_sums[floor].x, 1e-9 * size) << "step " << sim.step_count();
      EXPECT_NEAR(exact[floor].y, node_sums[floor].y, 1e-9 * size) << "step " << sim.step_count();
      EXPECT_EQ(exact[0].x, 0.0);  // the disc is no wall
      ++compared;
    }
    EXPECT_EQ(compared, 20) << "the disc never reached the floor";
  }
}

}  // namespace
}  // namespace debris
