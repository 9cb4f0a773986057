// The PeriDEM two-particle drop (paper B, section 4.1) end to end: the engine's bonds, contact, centre
// damping and integrator together against the paper's Table 2.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <string>

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

// Table 3, test 9 with eps = 0.95 (the one mixed row of that table in ctest; about as fast as a Table 2
// row): the top M1 grain dropped on a fixed M2 grain (Table 1: K = 2 GPa, G = 1.2 GPa, G_c = 500 J/m^2),
// both 1 mm, at the paper's 0.1 us. The paper's C_R is 0.925; measured 0.9230 (README.md), so the Table 2
// tolerance of 0.01 holds here too, and the elastic row gives 1 within its 0.3-0.5% ringing loss.
TEST(PdRestitution, Table3Test9MixedMaterialsRow) {
  for (double eps : {1.0, 0.95}) {
    TwoParticleDrop d = table2_case(eps);
    d.bottom_material.bulk_modulus = 2e9;
    d.bottom_material.shear_modulus = 1.2e9;
    d.bottom_material.fracture_energy = 500;
    d.time_step = 1e-7;
    const TwoParticleDropResult r = run_two_particle_drop(d);
    std::printf("[ info ] Table 3 test 9, eps = %.2f: C_R = %.4f (paper %.3f)\n", eps, r.restitution_coefficient,
                eps == 1.0 ? 1.0 : 0.925);
    EXPECT_NEAR(r.restitution_coefficient, eps == 1.0 ? 1.0 : 0.925, 0.01) << "eps " << eps;
    EXPECT_EQ(r.broken_bonds, 0);
  }
}

// Table 3, test 8 with eps = 0.95 (an M2 grain of R = 1 mm on a fixed M2 grain of R = 3 mm; paper 0.716),
// on the meshes the authors' code ran (PeriDEM 0.1.0's two-particle examples, scenarios/peridem/data/
// two_particle_diff_radius_v010). Their 3 mm circle has a smaller smallest node spacing (eq 35: 0.1210 mm,
// ours 0.1294 mm), so a smaller R_c = 0.95 h, a narrower damping band (1.01 R_c to R_c) and less damping:
// 0.7183 on theirs, 0.6936 on ours (scenarios/peridem/RESULTS.md, section 6). The run starts 0.15 mm above
// the bottom grain, above the 1.01 R_c where the centre damping starts: free fall before either start, so
// the same C_R to 1e-5 as the 0.2 mm of tables.yaml, in a third of the steps (about 5 s).
TEST(PdRestitution, Table3Test8OnTheAuthorsMeshes) {
  const std::string data = std::string(DEBRIS_SOURCE_DIR) + "/scenarios/peridem/data/two_particle_diff_radius_v010/";
  TwoParticleDrop d = table2_case(0.95);
  for (PdMaterial* m : {&d.bottom_material, &d.top_material}) {
    m->bulk_modulus = 2e9;
    m->shear_modulus = 1.2e9;
    m->fracture_energy = 500;
  }
  d.bottom_radius = 3e-3;
  d.time_step = 2e-8;
  d.start_gap = 0.15e-3;
  d.bottom_mesh_file = data + "mesh_cir_r3mm.msh";
  d.top_mesh_file = data + "mesh_cir_r1mm.msh";
  const TwoParticleDropResult r = run_two_particle_drop(d);
  std::printf("[ info ] Table 3 test 8 on the authors' meshes: h = %.4f mm, C_R = %.4f (paper 0.716)\n",
              r.mesh_h * 1e3, r.restitution_coefficient);
  EXPECT_EQ(r.nodes, 1015 + 125);
  EXPECT_NEAR(r.mesh_h, 0.1210e-3, 0.0005e-3);  // in the 3 mm circle
  EXPECT_NEAR(r.restitution_coefficient, 0.716, 0.01);
  EXPECT_EQ(r.broken_bonds, 0);
}

// The authors' code takes a grain's centre and velocity in eqs 26-29 from its centre node, debris from the
// mean of its nodes (damping_centre_node). The two agree while a grain moves rigidly, which is when the
// centre damping works in a drop: Table 2 test 5 differs by 3e-4 on our meshes (0.79265 against 0.79294),
// by 2e-4 or less on the authors' for the rows tried (RESULTS.md, section 6).
TEST(PdRestitution, CentreNodeDampingAgreesWithTheMeanInADrop) {
  TwoParticleDrop d = table2_case(0.8);
  const double mean = run_two_particle_drop(d).restitution_coefficient;
  d.damping_centre_node = true;
  const double node = run_two_particle_drop(d).restitution_coefficient;
  EXPECT_NEAR(node, mean, 1e-3);
  EXPECT_NE(node, mean);  // the option is in effect: the centre node rings during the contact
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

// Section 4.1, "Fracture simulations": the top grain hits the fixed one at v0. With the paper's eq 11 (bonds
// break in tension only) not one bond breaks at these speeds, but the damage of eq 14 near the contact passes
// 1 (the fracture zone of eq 15) and grows with v0. With bonds that also break in compression (bond_breaking:
// tension_and_compression, the authors' code) a fracture zone forms at every speed, larger at higher speed, as
// in Figs 7-10. Measured (M1 on M1, scenarios/restitution/fracture.yaml): 16, 69, 92 bonds at v0 = 2, 4,
// 5 m/s. The bottom grain is rigid (Z = 0). One pair of runs per speed serves both checks.
TEST(PdRestitution, ImpactDamageAndFractureZoneGrowWithSpeed) {
  long previous_bonds = 0;
  double previous_damage = 0.0;
  for (double v0 : {2.0, 5.0}) {
    TwoParticleDrop d = table2_case(0.95);
    d.initial_speed = v0;
    const TwoParticleDropResult tension = run_two_particle_drop(d);
    EXPECT_EQ(tension.broken_bonds, 0) << "v0 = " << v0;
    EXPECT_GE(tension.top_max_damage, 1.0) << "v0 = " << v0;
    EXPECT_GT(tension.top_max_damage, previous_damage) << "v0 = " << v0;
    EXPECT_EQ(tension.bottom_max_damage, 0.0);
    previous_damage = tension.top_max_damage;
    d.bottom_material.break_in_compression = d.top_material.break_in_compression = 1;
    const TwoParticleDropResult both = run_two_particle_drop(d);
    EXPECT_GT(both.broken_bonds, 5) << "v0 = " << v0;
    EXPECT_GT(both.broken_bonds, 2 * previous_bonds) << "v0 = " << v0;
    EXPECT_EQ(both.bottom_max_damage, 0.0);
    previous_bonds = both.broken_bonds;
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
