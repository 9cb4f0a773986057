// Paper B, section 4.3 (non-circular grains), Fig 19 shortened for CI: the shipped input
// scenarios/peridem/noncircular_concave.yaml (a concave grain, R = 1 mm, shot down at 8 m/s onto a fixed
// concave grain, R = 1.5 mm; h = 0.057 mm, horizon 0.3 mm, dt = 0.05 us) with the top grain started 0.075 mm
// above the first contact instead of 1.675 mm (its centre at y = 2.7 mm, not 4.3 mm) and 0.1 ms run instead
// of 1.2 ms; gravity changes the impact speed by 0.002 m/s over the skipped fall, so the impact is the same.
// Thermo rows every 10 steps (the shipped file: 200), for the energy check.
//
// Independent checks (derived, not measured):
//  - energy: the contact is dissipative (damping, eps = 0.95) or at most elastic, and broken bonds only
//    remove energy, so the mechanical energy KE + bond + contact + potential never exceeds its initial
//    value, 1/2 M v0^2 with M = rho sum V from the system's nodes; the only slack allowed is the error of
//    the kinetic energy taken from velocities half a step behind the positions (eq 32), about dt/2 times
//    the rate at which kinetic and elastic energy are exchanged, well under 1e-3 of E0.
//  - the rebound: the top grain's centre-of-mass kinetic energy is part of its kinetic energy, so
//    C_R = |v_c| / v0 <= sqrt(1 + 2 g (y0 - y) / v0^2), the bound energy conservation gives.
//  - with the bottom grain freed and gravity off (the second test), the two grains' total momentum is
//    conserved to round-off through the impact (no wall, no external force), their kinetic energy of
//    relative motion cannot grow (restitution of the relative velocity e <= 1), and the centre-of-mass
//    kinetic energy P^2 / 2 M_total, which no internal force can change, is a lower bound of what is left.
// The input's restitution (0.95) is not a bound on C_R here: eq 28's dashpot gives C_R = eps only for a
// linear spring of stiffness kappa_eff R_c between two rigid bodies, and this contact is neither (many node
// springs of eq 17 on deforming, breaking grains). Nor is a contact time estimated: with eq 17's node
// springs far stiffer than the grains (K_n V V' against the grains' K), the contact time is the grains'
// elastic response, with no closed form for these concave shapes.
// Regression values (measured 2026-12-02 and 2026-12-03, 1 thread, 2,000 steps, about 1 s each), pinned
// only beside the checks above: top_vy -8 -> +2.442 m/s (the full run: +2.54 m/s), 429 broken bonds, all in
// the top grain (the full run: 430 at T), none in the fixed bottom grain; mechanical energy left at T 0.248
// of E0 (measured maximum over the rows: E0 itself, at step 0). Freed bottom grain: momentum conserved to
// 2e-15 relative, e = 0.125, 168 broken bonds (76 top, 92 bottom).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "scenarios/common/peridem/peridem_input.hpp"
#include "tests/cli_helpers.hpp"

namespace {

namespace fs = std::filesystem;
using debris::test::CommandResult;

// Replaces the one occurrence of `from` (the test fails if the shipped input no longer has it).
std::string replace_once(std::string text, const std::string& from, const std::string& to) {
  const std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << "the shipped input has no '" << from << "'";
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

// The shipped input shortened as described above, with `edit` applied.
std::string short_input(std::string (*edit)(std::string)) {
  std::string yaml = debris::test::slurp(fs::path(DEBRIS_SOURCE_DIR) / "scenarios/peridem/noncircular_concave.yaml");
  yaml = replace_once(yaml, "centre: [2.366 mm, 4.3 mm, 0]", "centre: [2.366 mm, 2.7 mm, 0]");
  yaml = replace_once(yaml, "final_time: 1.2 ms", "final_time: 0.1 ms");
  yaml = replace_once(yaml, "trajectory_every: 200", "trajectory_every: 0");
  yaml = replace_once(yaml, "thermo_every: 200", "thermo_every: 10");
  return edit ? edit(yaml) : yaml;
}

// Masses of the grains "bottom" and "top" (rho sum V over their nodes), from the same input read here.
struct Masses {
  double bottom = 0, top = 0;
};
Masses grain_masses(const std::string& yaml, const fs::path& dir) {
  debris::PeridemInputOptions o;
  o.output_directory = (dir / "setup").string();
  const debris::PeridemRunConfig cfg = debris::read_peridem_input_text(yaml, "short.yaml", dir.string(), o);
  Masses m;
  for (std::size_t k = 0; k < cfg.grains.size(); ++k) {
    double v = 0;
    for (int i = cfg.grains.node_begin[k]; i < cfg.grains.node_end[k]; ++i) v += cfg.nodes.volume[i];
    const double mass = cfg.materials[static_cast<std::size_t>(cfg.grains.material[k])].density * v;
    if (cfg.grain_names[k] == "bottom") m.bottom = mass;
    if (cfg.grain_names[k] == "top") m.top = mass;
  }
  EXPECT_GT(m.bottom, 0.0);
  EXPECT_GT(m.top, 0.0);
  return m;
}

debris::test::NumberTable run_short(const std::string& name, const std::string& yaml, const fs::path& out) {
  const std::string input = debris::test::write_text_file(out, name + ".yaml", yaml);
  const CommandResult r =
      debris::test::run_command(DEBRIS_PERIDEM_EXECUTABLE, "-i " + input + " -o " + out.string() + " --threads 1");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("889 nodes in 2 grains"), std::string::npos) << r.output;
  return debris::test::read_number_table(out / "thermo.csv");
}

TEST(PeridemNoncircular, ConcaveGrainReboundsFromAConcaveGrainWithBoundedDamage) {
  const fs::path out = debris::test::fresh_directory("debris_peridem_noncircular_concave");
  const std::string yaml = short_input(nullptr);
  const debris::test::NumberTable t = run_short("short", yaml, out);
  const Masses m = grain_masses(yaml, out);
  ASSERT_EQ(t.rows.size(), 201u);
  ASSERT_EQ(t.rows.back()[0], 2000);
  const std::size_t vx = t.column("top_vx"), vy = t.column("top_vy"), y = t.column("top_y"),
                    top_broken = t.column("top_broken_bonds"), bottom_broken = t.column("bottom_broken_bonds"),
                    damage = t.column("max_damage"), ke = t.column("kinetic_energy"), bond = t.column("bond_energy"),
                    contact = t.column("contact_energy");
  const double v0 = 8.0, g = 10.0;
  EXPECT_EQ(t.rows.front()[vy], -v0);

  // Energy: never more than at the start (the impact only dissipates).
  const double e0 = 0.5 * m.top * v0 * v0, y0 = t.rows.front()[y];
  EXPECT_NEAR(t.rows.front()[ke], e0, 1e-12 * e0);  // the run's own mass: the same nodes
  double e_max = 0, e_end = 0;
  for (const auto& row : t.rows) {
    const double e = row[ke] + row[bond] + row[contact] + m.top * g * (row[y] - y0);
    EXPECT_LE(e, e0 * (1 + 1e-3)) << "step " << row[0];
    e_max = std::max(e_max, e);
    e_end = e;
  }
  std::printf("[ info ] E0 = %.6g J/m; largest mechanical energy %.6g E0, at T %.4f E0\n", e0, e_max / e0, e_end / e0);
  EXPECT_LT(e_end, e0);  // damped and broken: energy is gone

  // The top grain's velocity reverses: it rebounds at a fraction of its impact speed (damping, eps = 0.95,
  // and the energy spent in fracture), and rises through the whole second half of the run. (Not "no contact
  // pair at the end": contact_pairs also counts the pairs between the top grain's own pieces where its bonds
  // broke, which flicker between 0 and 3 over steps 1,100-2,000 in runs that differ only in round-off: one
  // was 0 at step 2,000, another 1.)
  const std::vector<double>& last = t.rows.back();
  EXPECT_GT(last[vy], 0.0);
  for (std::size_t r = t.rows.size() / 2; r < t.rows.size(); ++r) {
    EXPECT_GT(t.rows[r][vy], 0.0) << "step " << t.rows[r][0];
    EXPECT_GT(t.rows[r][y], t.rows[r - 1][y]) << "step " << t.rows[r][0];
  }
  const double c_r = std::hypot(last[vx], last[vy]) / v0;
  EXPECT_LE(c_r, std::sqrt(1 + 2 * g * (y0 - last[y]) / (v0 * v0)));  // energy bound (replaces vy < 8)
  EXPECT_LE(0.5 * m.top * (last[vx] * last[vx] + last[vy] * last[vy]), last[ke] * (1 + 1e-12));
  // Regression (replaces 1.5 < vy < 8): 15% of the measured +2.442 m/s. Runs that differ only in round-off
  // (the bond force's V_i multiplied before or after its sum, and the normal stiffness's products grouped
  // otherwise) gave 2.29-2.44 m/s: the fracture is chaotic, so 3% passed or failed by the last bits. A force
  // sweep taking each bond once gave 2.431 m/s with V_i times eq 33's term and 2.134 m/s with V_i V_j
  // multiplied first (409 and 423 broken bonds): 10% too passed or failed by the last bits.
  EXPECT_NEAR(last[vy], 2.442, 0.15 * 2.442);
  // A fracture zone in the top grain where the bottom grain's corner entered its notch, bounded: a few
  // hundred of its ~6,000 bonds, not a shattered grain. Regression (replaces 100 < broken < 1500): the
  // round-off variants so far broke 401-429 (the bond sums' order and their products grouped otherwise, no
  // FMA, each bond's J V_j kept from the reference state: 401), so 7.5% about the middle of that range, 415.
  // The bottom grain is fixed (rigid), so never breaks.
  EXPECT_NEAR(last[top_broken], 415, 0.075 * 415);
  for (const auto& row : t.rows) {
    EXPECT_EQ(row[bottom_broken], 0) << "step " << row[0];
    EXPECT_TRUE(std::isfinite(row[damage])) << "step " << row[0];
  }
}

// The same impact with the bottom grain free and no gravity: a two-body collision with nothing outside.
TEST(PeridemNoncircular, FreeConcaveGrainsConserveMomentumAndLoseEnergy) {
  const fs::path out = debris::test::fresh_directory("debris_peridem_noncircular_concave_free");
  const std::string yaml = short_input([](std::string s) {
    s = replace_once(s, "centre: [1.5 mm, 1.5 mm, 0], fixed: true}", "centre: [1.5 mm, 1.5 mm, 0]}");
    return replace_once(s, "gravity: [0, -10 m/s^2, 0]", "gravity: [0, 0, 0]");
  });
  const debris::test::NumberTable t = run_short("free", yaml, out);
  const Masses m = grain_masses(yaml, out);
  ASSERT_EQ(t.rows.size(), 201u);
  const std::size_t tvx = t.column("top_vx"), tvy = t.column("top_vy"), bvx = t.column("bottom_vx"),
                    bvy = t.column("bottom_vy"), ke = t.column("kinetic_energy"), bond = t.column("bond_energy"),
                    contact = t.column("contact_energy"), broken = t.column("broken_bonds"),
                    ty = t.column("top_y"), by = t.column("bottom_y");
  const double v0 = 8.0, p0 = -m.top * v0, e0 = 0.5 * m.top * v0 * v0;
  const double e_com = 0.5 * p0 * p0 / (m.top + m.bottom);  // no internal force changes it
  double worst = 0;  // largest momentum residual over |P0|
  for (const auto& row : t.rows) {
    SCOPED_TRACE("step " + std::to_string(static_cast<long>(row[0])));
    worst = std::max({worst, std::abs(m.top * row[tvy] + m.bottom * row[bvy] - p0) / std::abs(p0),
                      std::abs(m.top * row[tvx] + m.bottom * row[bvx]) / std::abs(p0)});
    EXPECT_NEAR(m.top * row[tvy] + m.bottom * row[bvy], p0, 1e-12 * std::abs(p0));
    EXPECT_NEAR(m.top * row[tvx] + m.bottom * row[bvx], 0.0, 1e-12 * std::abs(p0));
    const double e = row[ke] + row[bond] + row[contact];
    EXPECT_LE(e, e0 * (1 + 1e-3));
    EXPECT_GE(row[ke], e_com * (1 - 1e-3));
  }
  const std::vector<double>& last = t.rows.back();
  // Separated: over the last 40% of the run the grains' centres move apart at every row. (Not "no contact
  // pair at the end": the pairs between the top grain's own broken pieces flicker between 0 and 2 there,
  // and round-off alone decides whether step 2,000 has one.)
  for (std::size_t r = t.rows.size() * 3 / 5; r < t.rows.size(); ++r) {
    const auto &a = t.rows[r - 1], &b = t.rows[r];
    EXPECT_GT(b[ty] - b[by], a[ty] - a[by]) << "step " << b[0];
  }
  EXPECT_GT(last[broken], 0);
  // Restitution of the relative velocity, e = |v_top - v_bottom| after / v0 before: in [0, 1], and its
  // translational energy 1/2 mu (e v0)^2 fits in what is left above the centre-of-mass energy.
  const double rvx = last[tvx] - last[bvx], rvy = last[tvy] - last[bvy];
  EXPECT_GT(rvy, 0.0);  // separating
  const double e_rel = std::hypot(rvx, rvy) / v0, mu = m.top * m.bottom / (m.top + m.bottom);
  std::printf("[ info ] free bottom grain: momentum residual %.2g |P0|, e = %.4f, energy left %.4f E0 (centre of mass "
              "%.4f E0), %.0f broken bonds\n", worst, e_rel, (last[ke] + last[bond]) / e0, e_com / e0, last[broken]);
  EXPECT_LE(e_rel, 1.0);
  EXPECT_LE(0.5 * mu * (e_rel * v0) * (e_rel * v0), last[ke] + last[bond] + last[contact] - e_com + 1e-12 * e0);
}

}  // namespace
