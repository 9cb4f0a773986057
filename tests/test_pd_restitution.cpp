// The PeriDEM two-particle drop (paper B, section 4.1) end to end: the engine's bonds, contact, centre
// damping and integrator together against the paper's Table 2.
#include <gtest/gtest.h>

#include <filesystem>

#include "core/error.hpp"
#include "scenarios/common/two_particle_drop.hpp"

namespace debris {
namespace {

TwoParticleDrop table2_case(double restitution) {
  TwoParticleDrop d;
  d.bottom_material = d.top_material = peridem_material_m1(2);
  // As the authors' code that made Table 2: 3D constants on the 2D grains, centre damping from 1.01 R_c.
  d.bottom_material.dimension = d.top_material.dimension = 3;
  d.restitution = restitution;
  d.time_step = 2e-7;
  d.allow_unstable_time_step = true;  // the paper's 0.2 us; see tables.yaml
  d.damping_onset_factor = 1.01;
  d.mesh_directory = (std::filesystem::temp_directory_path() / "debris_test_pd_meshes").string();
  return d;
}

// Table 2, tests 1 and 2: elastic contact returns the drop height, and epsilon = 0.95 gives the paper's
// C_R within the 0.01.
TEST(PdRestitution, Table2ElasticAndDampedRows) {
  const TwoParticleDropResult elastic = run_two_particle_drop(table2_case(1.0));
  EXPECT_NEAR(elastic.restitution_coefficient, 1.0, 0.01);
  EXPECT_GT(elastic.contact_time, 0.0);
  const TwoParticleDropResult damped = run_two_particle_drop(table2_case(0.95));
  EXPECT_NEAR(damped.restitution_coefficient, 0.946, 0.01);
  EXPECT_LT(damped.restitution_coefficient, elastic.restitution_coefficient);
  EXPECT_EQ(damped.broken_bonds, 0);  // a 0.14 m/s drop is elastic inside the grains
  EXPECT_NEAR(run_two_particle_drop(table2_case(0.8)).restitution_coefficient, 0.796, 0.01);
}

// The shortened start (free fall skipped, rebound extrapolated ballistically) measures what the whole fall
// and rise measure. A strong gravity keeps the full run short; the contact is then at 1.4 m/s.
TEST(PdRestitution, ShortcutEqualsFullDropAndRise) {
  TwoParticleDrop d = table2_case(0.9);
  d.gravity = 1000.0;
  const TwoParticleDropResult shortcut = run_two_particle_drop(d);
  d.full_drop = true;
  const TwoParticleDropResult full = run_two_particle_drop(d);
  EXPECT_NEAR(shortcut.restitution_coefficient, full.restitution_coefficient, 2e-3);
  EXPECT_GT(full.steps, 5 * shortcut.steps);
}

// Section 4.1, "Fracture simulations": the top grain hits the fixed one at v0; the damage of eq 14 near the
// contact passes 1 (the fracture zone of eq 15) and grows with v0. The bottom grain is rigid (Z = 0).
TEST(PdRestitution, ImpactDamageGrowsWithSpeed) {
  double previous = 0.0;
  for (double v0 : {2.0, 5.0}) {
    TwoParticleDrop d = table2_case(0.95);
    d.initial_speed = v0;
    const TwoParticleDropResult r = run_two_particle_drop(d);
    EXPECT_GE(r.top_max_damage, 1.0) << "v0 = " << v0;
    EXPECT_GT(r.top_max_damage, previous) << "v0 = " << v0;
    EXPECT_EQ(r.bottom_max_damage, 0.0);
    previous = r.top_max_damage;
  }
}

// Table 4, row 2 of the mesh study (scenarios/restitution/mesh_study.yaml): the mesh, horizon and time step
// refined together (Gmsh size 0.1138 mm, h = 0.08 mm; horizon 0.375 mm; 0.1 us) give the paper's C_R 0.962
// within 0.01 (measured 0.9618), above row 1's 0.946 (C_R rises as h falls).
TEST(PdRestitution, Table4MeshStudyRow2) {
  TwoParticleDrop d = table2_case(0.95);
  d.mesh_size = 0.1138e-3;
  d.bottom_material.horizon = d.top_material.horizon = 0.375e-3;
  d.time_step = 1e-7;
  const TwoParticleDropResult r = run_two_particle_drop(d);
  EXPECT_NEAR(r.mesh_h, 0.0805e-3, 0.004e-3);
  EXPECT_NEAR(r.restitution_coefficient, 0.962, 0.01);
  EXPECT_GT(r.restitution_coefficient, 0.946);
}

// The same impacts with bonds that also break in compression (bond_breaking: tension_and_compression, the
// authors' code): a fracture zone at every speed, larger at higher speed, as in Figs 7-10; with the paper's
// eq 11 (tension only) not one bond breaks at these speeds. Measured (M1 on M1, scenarios/restitution/
// fracture.yaml): 16, 69, 92 bonds at v0 = 2, 4, 5 m/s; 0 in tension only.
TEST(PdRestitution, CompressionBreakingGivesAFractureZoneGrowingWithSpeed) {
  long previous = 0;
  for (double v0 : {2.0, 5.0}) {
    TwoParticleDrop d = table2_case(0.95);
    d.initial_speed = v0;
    const TwoParticleDropResult tension = run_two_particle_drop(d);
    EXPECT_EQ(tension.broken_bonds, 0) << "v0 = " << v0;
    d.bottom_material.break_in_compression = d.top_material.break_in_compression = 1;
    const TwoParticleDropResult both = run_two_particle_drop(d);
    EXPECT_GT(both.broken_bonds, 5) << "v0 = " << v0;
    EXPECT_GT(both.broken_bonds, 2 * previous) << "v0 = " << v0;
    EXPECT_EQ(both.bottom_max_damage, 0.0);
    previous = both.broken_bonds;
  }
}

TEST(PdRestitution, BadInputNamesTheKey) {
  TwoParticleDrop d = table2_case(0.95);
  d.top_radius = -1e-3;
  try {
    run_two_particle_drop(d);
    FAIL() << "a negative radius was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("top_radius"), std::string::npos) << e.what();
  }
  d = table2_case(0.95);
  d.max_steps = 10;
  EXPECT_THROW(run_two_particle_drop(d), InputError);
}

}  // namespace
}  // namespace debris
