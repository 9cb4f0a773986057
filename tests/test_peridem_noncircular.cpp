// Paper B, section 4.3 (non-circular grains), Fig 19 shortened for CI: the shipped input
// scenarios/peridem/noncircular_concave.yaml (a concave grain, R = 1 mm, shot down at 8 m/s onto a fixed
// concave grain, R = 1.5 mm; h = 0.057 mm, horizon 0.3 mm, dt = 0.05 us) with the top grain started 0.075 mm
// above the first contact instead of 1.675 mm (its centre at y = 2.7 mm, not 4.3 mm) and 0.1 ms run instead
// of 1.2 ms; gravity changes the impact speed by 0.002 m/s over the skipped fall, so the impact is the same.
// Measured (2026-12-02, 1 thread, 2,000 steps, 3 s): top_vy -8 -> +2.44 m/s (the full run: +2.54 m/s), 429
// broken bonds, all in the top grain (the full run: 430 at T), none in the fixed bottom grain.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

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

TEST(PeridemNoncircular, ConcaveGrainReboundsFromAConcaveGrainWithBoundedDamage) {
  const fs::path out = debris::test::fresh_directory("debris_peridem_noncircular_concave");
  std::string yaml = debris::test::slurp(fs::path(DEBRIS_SOURCE_DIR) / "scenarios/peridem/noncircular_concave.yaml");
  yaml = replace_once(yaml, "centre: [2.366 mm, 4.3 mm, 0]", "centre: [2.366 mm, 2.7 mm, 0]");
  yaml = replace_once(yaml, "final_time: 1.2 ms", "final_time: 0.1 ms");
  yaml = replace_once(yaml, "trajectory_every: 200", "trajectory_every: 0");
  const std::string input = debris::test::write_text_file(out, "short.yaml", yaml);
  const CommandResult r =
      debris::test::run_command(DEBRIS_PERIDEM_EXECUTABLE, "-i " + input + " -o " + out.string() + " --threads 1");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("889 nodes in 2 grains"), std::string::npos) << r.output;

  const debris::test::NumberTable t = debris::test::read_number_table(out / "thermo.csv");
  ASSERT_GE(t.rows.size(), 2u);
  ASSERT_EQ(t.rows.back()[0], 2000);
  const std::size_t vy = t.column("top_vy"), top_broken = t.column("top_broken_bonds"),
                    bottom_broken = t.column("bottom_broken_bonds"), damage = t.column("max_damage");
  EXPECT_EQ(t.rows.front()[vy], -8.0);
  // The top grain's velocity reverses: it rebounds at a fraction of its impact speed (damping, eps = 0.95,
  // and the energy spent in fracture).
  const std::vector<double>& last = t.rows.back();
  EXPECT_GT(last[vy], 1.5);
  EXPECT_LT(last[vy], 8.0);
  // A fracture zone in the top grain where the bottom grain's corner entered its notch, bounded: a few
  // hundred of its ~6,000 bonds, not a shattered grain. The bottom grain is fixed (rigid), so never breaks.
  EXPECT_GT(last[top_broken], 100);
  EXPECT_LT(last[top_broken], 1500);
  for (const auto& row : t.rows) {
    EXPECT_EQ(row[bottom_broken], 0) << "step " << row[0];
    EXPECT_TRUE(std::isfinite(row[damage])) << "step " << row[0];
  }
}

}  // namespace
