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
// set-up's own loss (waves left ringing in the disc).
#include <gtest/gtest.h>

#include <string>

#include "scenarios/common/peridem_input.hpp"
#include "scenarios/common/peridem_simulation.hpp"

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

// Rebound speed over impact speed of the disc's centre, once it has left the obstacle.
double restitution_of(bool wall, const std::string& damping, double restitution) {
  PeridemInputOptions o;
  o.output_directory = ::testing::TempDir();
  PeridemRunConfig cfg = read_peridem_input_text(drop_input(wall, damping, restitution), "wall_damping", ".", o);
  PeridemSimulation sim(std::move(cfg.nodes), std::move(cfg.grains), cfg.materials, cfg.contact, cfg.settings);
  sim.refresh_grain_centres();
  const double v_in = -sim.grains().cvy[0], y0 = sim.grains().cy[0];
  EXPECT_GT(v_in, 0.99);
  bool touched = false;
  for (long s = 0; s < 40000; s += 50) {
    sim.run(50);
    const long touching = sim.touching_pairs();
    touched = touched || touching > 0;
    sim.refresh_grain_centres();
    // Node pairs touch on and off during one impact (a discrete surface): the rebound is over when the
    // disc is back where it started, out of range.
    if (touched && touching == 0 && sim.grains().cy[0] >= y0) {
      EXPECT_EQ(sim.health_check(), "");
      return sim.grains().cvy[0] / v_in;
    }
  }
  ADD_FAILURE() << "the disc did not leave the obstacle within 4 ms";
  return 0;
}

TEST(PdWallDamping, WallDampsLikeAGrainOfInfiniteMass) {
  for (const std::string damping : {"grain_centres", "node_pairs"}) {
    const double wall = restitution_of(true, damping, 0.5);
    const double grain = restitution_of(false, damping, 0.5);
    SCOPED_TRACE(damping);
    EXPECT_NEAR(wall, grain, 0.005);
    if (damping == "grain_centres") {  // really damped (it was 0.95 against a wall), and still a rebound
      EXPECT_GT(wall, 0.5);
      EXPECT_LT(wall, 0.75);
    } else {  // damped, if little: below the elastic rebound
      EXPECT_LT(wall, 0.990);
    }
  }
}

TEST(PdWallDamping, ElasticReboundIsLossless) {
  for (const std::string damping : {"grain_centres", "node_pairs"}) {
    SCOPED_TRACE(damping);
    EXPECT_GT(restitution_of(true, damping, 1.0), 0.99);
    EXPECT_GT(restitution_of(false, damping, 1.0), 0.99);
  }
}

}  // namespace
}  // namespace debris
