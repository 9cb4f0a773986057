// The PeriDEM two-particle drop (paper B, section 4.1) end to end: the engine's bonds, contact, centre
// damping and integrator together against the paper's Table 2.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "scenarios/common/peridem/grain_placement.hpp"
#include "scenarios/common/peridem/shape_mesh.hpp"
#include "scenarios/common/peridem/peridem_simulation.hpp"
#include "scenarios/restitution/two_particle_drop.hpp"

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

// The energy budget of one drop of run_two_particle_drop's set-up (the same meshes, placement, contact and
// start: scenarios/restitution/two_particle_drop.cpp), stepped here. The top grain is the only thing that moves
// (the bottom one is fixed), so its energy at the start, 1/2 M v^2 (M = rho sum V), goes into
//   kinetic + bond + contact energy + M g (y_c - y_c0)     what the system still holds
//   + the work of the centre damping                        eqs 26-28, computed here from the paper
//   + what the broken bonds took                            the rest, the fracture energy
// The damping's work is summed over the steps from eq 28 itself: while dist(top, bottom) < 1.01 R_c (the
// onset of table2_case) and the centres approach (rate = v_c . e < 0 for the fixed bottom grain), the
// dashpot beta-bar = -2 C log(eps) sqrt(kappa R_c M_eq / (pi^2 + log(eps)^2)), M_eq = 2 M M' / (M + M'),
// takes beta-bar rate^2 dt per step. R_c = 0.95 h with h of eq 35 from the nodes, kappa = K (one
// material). The energies at the end take v at the step (the mean of the velocities half a step before and
// after, eq 32 stores v half a step behind x).
struct EnergyAudit {
  long broken_bonds = 0;
  double e0 = 0;        // 1/2 M v^2 at the start (J/m)
  double held = 0;      // what the system holds at the end, over e0
  double damping = 0;   // the centre damping's work, over e0
  double fracture = 0;  // 1 - held - damping: the energy the broken bonds took, over e0
  double bonds_per_metre = 0;  // bonds of the top grain crossing its diameter, per metre of it
};

EnergyAudit audit_drop(const TwoParticleDrop& d) {
  GmshRun gmsh;
  gmsh.directory = d.mesh_directory;
  const ReferenceGrain bottom_ref =
      make_reference_grain(mesh_shape(ShapeSpec::make_circle(d.bottom_radius, d.mesh_size), gmsh), d.bottom_radius, 0,
                           "bottom grain");
  const ReferenceGrain top_ref = make_reference_grain(
      mesh_shape(ShapeSpec::make_circle(d.top_radius, d.mesh_size), gmsh), d.top_radius, 1, "top grain");
  const double gap0 = std::min(d.start_gap, d.drop_height);
  PdNodes nodes;
  PdGrains grains;
  const int gb = place_grain(bottom_ref, GrainRecord{0, 0.0, 0.0, 0.0, d.bottom_radius, 0.0}, nodes, grains);
  const int gt = place_grain(top_ref, GrainRecord{1, 0.0, d.bottom_radius + d.top_radius + gap0, 0.0, d.top_radius,
                                                  0.5 * 3.14159265358979323846},
                             nodes, grains);
  for (int i = grains.node_begin[gb]; i < grains.node_end[gb]; ++i) nodes.fixed[i] = 1 | 2 | 4;
  for (int i = grains.node_begin[gt]; i < grains.node_end[gt]; ++i) nodes.fixed[i] = 4;
  PdContactSettings contact;
  contact.contact_radius_factor = d.contact_radius_factor;
  contact.restitution = d.restitution;
  contact.damping_factor = d.damping_factor;
  contact.damping_onset_factor = d.damping_onset_factor;
  PeridemSettings settings;
  settings.time_step = d.time_step;
  settings.gravity = Vec3{0.0, -d.gravity, 0.0};
  settings.allow_unstable_time_step = d.allow_unstable_time_step;
  // The constants of eq 28 and the masses, from the input and the nodes (before the simulation owns them).
  double h = std::numeric_limits<double>::infinity();
  for (int g : {gb, gt})
    for (int i = grains.node_begin[g]; i < grains.node_end[g]; ++i)
      for (int j = i + 1; j < grains.node_end[g]; ++j) h = std::min(h, std::hypot(nodes.x[j] - nodes.x[i], nodes.y[j] - nodes.y[i]));
  const auto grain_mass = [&](int g, const PdMaterial& m) {
    double v = 0;
    for (int i = grains.node_begin[g]; i < grains.node_end[g]; ++i) v += nodes.volume[i];
    return m.density * v;
  };
  const double m_bottom = grain_mass(gb, d.bottom_material), m_top = grain_mass(gt, d.top_material);
  const double rc = d.contact_radius_factor * h, onset = d.damping_onset_factor * rc;
  const double kappa = 2 * d.bottom_material.bulk_modulus * d.top_material.bulk_modulus /
                       (d.bottom_material.bulk_modulus + d.top_material.bulk_modulus);  // eq 25
  const double l = std::log(d.restitution), m_eq = 2 * m_bottom * m_top / (m_bottom + m_top);  // eq 29
  const double beta = -2 * d.damping_factor * l * std::sqrt(kappa * rc * m_eq / (3.14159265358979323846 * 3.14159265358979323846 + l * l));

  // Bonds of the top grain across its horizontal diameter, per metre of it (eq 33's pairs, |xi| < horizon).
  long crossing = 0;
  const double yc_top = d.bottom_radius + d.top_radius + gap0;
  for (int i = grains.node_begin[gt]; i < grains.node_end[gt]; ++i)
    for (int j = i + 1; j < grains.node_end[gt]; ++j)
      if ((nodes.y[i] - yc_top) * (nodes.y[j] - yc_top) < 0 &&
          std::hypot(nodes.x[j] - nodes.x[i], nodes.y[j] - nodes.y[i]) < d.top_material.horizon)
        ++crossing;

  PeridemSimulation sim(nodes, grains, {d.bottom_material, d.top_material}, {contact}, settings);
  const double v0 = std::sqrt(d.initial_speed * d.initial_speed + 2.0 * d.gravity * (d.drop_height - gap0));
  sim.set_grain_velocity(gt, Vec3{0.0, -v0, 0.0});
  const PeridemSimulation& view = sim;
  sim.refresh_grain_centres();
  const double yc0 = view.grains().cy[gt];
  EnergyAudit a;
  a.e0 = 0.5 * m_top * v0 * v0;
  // The nodes of each grain that can meet the other (the half facing it), for dist(top, bottom).
  std::vector<int> near_bottom, near_top;
  for (int i = grains.node_begin[gb]; i < grains.node_end[gb]; ++i)
    if (nodes.y[i] > 0.5 * d.bottom_radius) near_bottom.push_back(i);
  for (int i = grains.node_begin[gt]; i < grains.node_end[gt]; ++i)
    if (nodes.y[i] < yc0 - 0.5 * d.top_radius) near_top.push_back(i);
  double work = 0;
  bool touched = false;
  long free_rising = 0;
  // Until the top grain has been free and rising for 100 steps, as run_two_particle_drop decides.
  for (long s = 0; s < d.max_steps && free_rising < 100; ++s) {
    sim.step();
    sim.refresh_grain_centres();
    const PdNodes& n = view.nodes();
    double dist2 = std::numeric_limits<double>::infinity();
    for (int i : near_top)
      for (int j : near_bottom) dist2 = std::min(dist2, (n.x[j] - n.x[i]) * (n.x[j] - n.x[i]) + (n.y[j] - n.y[i]) * (n.y[j] - n.y[i]));
    // This step's forces use these centres and velocities (x^n, v^{n-1/2}); the fixed grain does not move.
    const PdGrains& g = view.grains();
    const double ex = g.cx[gb] - g.cx[gt], ey = g.cy[gb] - g.cy[gt], len = std::hypot(ex, ey);
    const double rate = -(g.cvx[gt] * ex + g.cvy[gt] * ey) / len;  // eq 26 with v_c' = 0
    if (dist2 < onset * onset && rate < 0) work += beta * rate * rate * d.time_step;
    if (sim.touching_pairs() > 0) {
      touched = true;
      free_rising = 0;
    } else if (touched && g.cvy[gt] - 0.5 * d.time_step * d.gravity > 0) {
      ++free_rising;
    }
  }
  EXPECT_EQ(free_rising, 100) << "the top grain did not leave";
  const PeridemDiagnostics diag = sim.diagnostics();
  std::vector<double> vx(view.nodes().vx.begin(), view.nodes().vx.end()), vy(view.nodes().vy.begin(), view.nodes().vy.end());
  const double y_end = view.grains().cy[gt];
  sim.step();
  double ke = 0;
  for (std::size_t i = 0; i < view.nodes().size(); ++i) {
    const double ux = 0.5 * (vx[i] + view.nodes().vx[i]), uy = 0.5 * (vy[i] + view.nodes().vy[i]);
    ke += 0.5 * view.nodes().mass[i] * (ux * ux + uy * uy);
  }
  a.broken_bonds = diag.broken_bonds;
  a.held = (ke + diag.bond_energy + diag.contact_energy + m_top * d.gravity * (y_end - yc0)) / a.e0;
  a.damping = work / a.e0;
  a.fracture = 1.0 - a.held - a.damping;
  a.bonds_per_metre = static_cast<double>(crossing) / (2 * d.top_radius);
  return a;
}

// Section 4.1, "Fracture simulations": the top grain hits the fixed one at v0. With the paper's eq 11 (bonds
// break in tension only) not one bond breaks at these speeds, but the damage of eq 14 near the contact passes
// 1 (the fracture zone of eq 15) and grows with v0. With bonds that also break in compression (bond_breaking:
// tension_and_compression, the authors' code) a fracture zone forms at every speed, larger at higher speed, as
// in Figs 7-10. Measured (M1 on M1, scenarios/restitution/fracture.yaml): 16, 69, 92 bonds at v0 = 2, 4,
// 5 m/s. The bottom grain is rigid (Z = 0). One pair of runs per speed serves both checks.
//
// Checked independently by the energy budget of each run (audit_drop, the same runs stepped here: the same
// broken bonds). With no bond broken (eq 11) the impact's energy is what the grains hold after it plus the
// damping's work of eq 28, to 1% of E0, so nothing else takes energy; with broken bonds the rest, the
// fracture energy, is above that 1%, larger at 5 m/s than at 2 m/s, and per broken bond of the order
// G_c / n: eq 10 calibrates s_0 so that a straight crack costs G_c per unit length, and a unit length of
// crack cuts n bonds (n counted here across the top grain's diameter). Within a factor 2 of it, not closer:
// the zone is not a straight crack through the bulk but a patch at the contact, broken in compression too,
// and the LPS energy is not a sum over bonds.
// Measured (2026-12-03, 3.0 s for the test): no bond broken, held 0.9308 / 0.9377 E0 and damping 0.0697 /
// 0.0642 E0 at 2 / 5 m/s (E0 = 0.0075 / 0.0469 J/m; rest -0.0005 / -0.0019 E0); broken in compression too,
// 16 / 92 bonds took 0.486 / 0.483 E0 = 0.0037 / 0.0226 J/m, 2.3e-4 / 2.5e-4 J/m per bond against
// G_c / n = 50 / 1.365e5 = 3.7e-4 J/m.
TEST(PdRestitution, ImpactDamageAndFractureZoneGrowWithSpeed) {
  long previous_bonds = 0;
  double previous_damage = 0.0, previous_fracture = 0.0;
  for (double v0 : {2.0, 5.0}) {
    TwoParticleDrop d = table2_case(0.95);
    d.initial_speed = v0;
    const TwoParticleDropResult tension = run_two_particle_drop(d);
    EXPECT_EQ(tension.broken_bonds, 0) << "v0 = " << v0;
    EXPECT_GE(tension.top_max_damage, 1.0) << "v0 = " << v0;
    EXPECT_GT(tension.top_max_damage, previous_damage) << "v0 = " << v0;
    EXPECT_EQ(tension.bottom_max_damage, 0.0);
    previous_damage = tension.top_max_damage;
    const EnergyAudit ta = audit_drop(d);
    d.bottom_material.break_in_compression = d.top_material.break_in_compression = 1;
    const TwoParticleDropResult both = run_two_particle_drop(d);
    EXPECT_GT(both.broken_bonds, 5) << "v0 = " << v0;
    EXPECT_GT(both.broken_bonds, 2 * previous_bonds) << "v0 = " << v0;
    EXPECT_EQ(both.bottom_max_damage, 0.0);
    previous_bonds = both.broken_bonds;
    const EnergyAudit ba = audit_drop(d);
    for (const auto& [what, a] : {std::pair{"tension", ta}, std::pair{"both", ba}})
      std::printf("[ info ] v0 = %.0f m/s, %s: E0 = %.4g J/m, %ld broken; held %.5f E0, damping %.5f E0, rest %.5f E0"
                  " (%.3g J/m per broken bond; G_c / n = %.3g J/m, n = %.4g bonds/m)\n",
                  v0, what, a.e0, a.broken_bonds, a.held, a.damping, a.fracture,
                  a.broken_bonds ? a.fracture * a.e0 / static_cast<double>(a.broken_bonds) : 0.0,
                  d.top_material.fracture_energy / a.bonds_per_metre, a.bonds_per_metre);
    EXPECT_EQ(ta.broken_bonds, tension.broken_bonds) << "v0 = " << v0;  // the same runs as the helper's
    EXPECT_EQ(ba.broken_bonds, both.broken_bonds) << "v0 = " << v0;
    // No bond broken: the budget closes without a fracture term.
    EXPECT_NEAR(ta.fracture, 0.0, 0.01) << "v0 = " << v0;
    EXPECT_GT(ta.damping, 0.0) << "v0 = " << v0;
    // Bonds broken: they took energy, more at the higher speed, of the order G_c gives per bond.
    EXPECT_GT(ba.fracture, 0.01) << "v0 = " << v0;
    EXPECT_GT(ba.fracture * ba.e0, previous_fracture) << "v0 = " << v0;
    const double per_bond = ba.fracture * ba.e0 / static_cast<double>(ba.broken_bonds),
                 g_c_per_bond = d.top_material.fracture_energy / ba.bonds_per_metre;
    EXPECT_GT(per_bond, 0.5 * g_c_per_bond) << "v0 = " << v0;
    EXPECT_LT(per_bond, 2.0 * g_c_per_bond) << "v0 = " << v0;
    previous_fracture = ba.fracture * ba.e0;
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
