// The reduced compression test (scenarios/peridem/compression_small.yaml, the shape of the paper's 502-grain
// compression, section 4.4, at five grains): read from the shipped file, run through debris_peridem with its
// stages (settle, then the lid placed and pressed down). What the paper's Fig 23 shows, in small: no lid
// force before the lid meets the grains, a reaction that then rises, and bonds that break late, under load.
// Measured (2026-12-01): lid_fy 0 through step 2000 (the settle) and until the lid reaches the top grains;
// mean lid_fy 79 N over steps 4000-8000 and 1,367 N over 12000-15000; broken bonds 0 at step 8000, 1,148
// at step 18000 (the pack crushes).
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "tests/cli_helpers.hpp"

namespace {

namespace fs = std::filesystem;
using debris::test::CommandResult;

TEST(PeridemCompression, LidForceStartsRisesAndTheGrainsBreak) {
  const fs::path out = debris::test::fresh_directory("debris_peridem_compression_small");
  const CommandResult r = debris::test::run_command(
      DEBRIS_PERIDEM_EXECUTABLE,
      "-i " + std::string(DEBRIS_SOURCE_DIR) + "/scenarios/peridem/compression_small.yaml -o " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("stage 1 'press' starts at step 2000"), std::string::npos) << r.output;
  const debris::test::NumberTable t = debris::test::read_number_table(out / "thermo.csv");
  ASSERT_EQ(t.rows.back()[0], 18000);
  const std::size_t lid = t.column("lid_fy"), broken = t.column("broken_bonds");
  // Onset: nothing on the lid while the grains settle and the lid approaches; then it meets them.
  double first_touch = -1;
  for (const auto& row : t.rows) {
    if (row[0] <= 2000) EXPECT_EQ(row[lid], 0.0) << "step " << row[0];
    if (first_touch < 0 && row[lid] > 0) first_touch = row[0];
  }
  EXPECT_GT(first_touch, 2000);
  EXPECT_LT(first_touch, 6000);
  // Rise: the reaction grows as the lid goes down (the pack is loaded, the lid pushes down: lid_fy > 0).
  const double early = t.mean("lid_fy", 4000, 8000), late = t.mean("lid_fy", 12000, 15000);
  EXPECT_GT(early, 0.0);
  EXPECT_GT(late, 4 * early);
  // Damage comes late, under load, and then fast.
  const auto at = [&](double step) {
    for (const auto& row : t.rows)
      if (row[0] == step) return row[broken];
    ADD_FAILURE() << "no row at step " << step;
    return 0.0;
  };
  EXPECT_LT(at(8000), 10);
  EXPECT_GT(t.rows.back()[static_cast<std::size_t>(broken)], 300);
}

}  // namespace
