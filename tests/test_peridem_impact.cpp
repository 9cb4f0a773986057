// Paper B, section 4.2 ("Two-particle with wall", Fig 13-17): a grain of R1 = 1 mm resting on a fixed wall
// is hit by a grain of R2 = 2 mm falling at v0 = 2, 4, 5 m/s. With material M1 everywhere both grains crack,
// more at higher speed; with the top grain and the wall of the stronger M2, only the bottom grain cracks.
//
// Reduced from scenarios/peridem/impact_wall_m1.yaml and impact_wall_m2_top.yaml (the files themselves are
// read, so the test follows them), to run in a fraction of a second per case: Gmsh size 0.3 mm instead of 0.2 mm
// (h = 0.179 mm, R_c = 0.170 mm; horizon, materials, dt and damping as in the files), the bottom grain
// 0.18 mm above the wall instead of 0.14 mm (just beyond the larger R_c), the top grain 0.2 mm above the
// bottom one instead of 1 mm (the fall in between is free), and 1500 steps (0.15 ms) instead of 1 ms. Broken
// bonds per grain are the measure of damage (nodes with Z >= 1 in tension, the paper's fracture zone).
// Measured with these reductions: M1 total broken bonds 5 / 45 / 90 at v0 = 2 / 4 / 5 m/s (top grain 0 / 6
// / 27); M2 top: bottom 5 / 19 / 70, top 0 at every speed. At full size (the scenario files as they are, 1 ms)
// the top M1 grain also cracks at v0 = 2 m/s, by a few bonds: measured bottom / top broken bonds 6 / 3,
// 118 / 59 and 292 / 224 at 2, 4, 5 m/s (M1), and 6 / 0, 153 / 0, 217 / 0 with the M2 top grain.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "scenarios/common/peridem/peridem_input.hpp"
#include "scenarios/common/peridem/peridem_simulation.hpp"
#include "tests/cli_helpers.hpp"

namespace debris {
namespace {

namespace fs = std::filesystem;

const std::string kScenarios = std::string(DEBRIS_SOURCE_DIR) + "/scenarios/peridem/";

using debris::test::slurp;

using debris::test::replace;

std::string replace_all(std::string text, const std::string& from, const std::string& to) {
  for (auto pos = text.find(from); pos != std::string::npos; pos = text.find(from, pos + to.size()))
    text.replace(pos, from.size(), to);
  return text;
}

struct Impact {
  long bottom_broken = 0, top_broken = 0;
  double top_max_damage = 0;  // largest Z of the top grain seen at any 100th step
};

Impact run_impact(const std::string& file, int v0) {
  std::string yaml = slurp(kScenarios + file);
  yaml = replace_all(yaml, "mesh_size: 0.2 mm", "mesh_size: 0.3 mm");
  yaml = replace(yaml, "centre: [0, 1.14 mm, 0]", "centre: [0, 1.18 mm, 0]");
  yaml = replace(yaml, "centre: [0, 5.14 mm, 0]", "centre: [0, 4.38 mm, 0]");
  yaml = replace(yaml, "velocity: [0, -5 m/s, 0]", "velocity: [0, -" + std::to_string(v0) + " m/s, 0]");
  yaml = replace(yaml, "final_time: 1 ms", "steps: 1500");
  PeridemInputOptions o;
  o.output_directory = (fs::path(::testing::TempDir()) / "debris_peridem_impact").string();
  PeridemRunConfig cfg = read_peridem_input_text(yaml, file, kScenarios, o);
  PeridemSimulation sim(std::move(cfg.nodes), std::move(cfg.grains), cfg.materials, cfg.contact, cfg.settings);
  sim.set_grain_names(cfg.grain_names);
  EXPECT_EQ(sim.grain_names(), (std::vector<std::string>{"bottom", "top", "wall"}));
  Impact r;
  const PdGrains& g = sim.grains();
  for (long s = 0; s < cfg.steps; s += 100) {
    sim.run(100);
    sim.refresh_damage();
    for (int i = g.node_begin[1]; i < g.node_end[1]; ++i)
      r.top_max_damage = std::max(r.top_max_damage, sim.nodes().damage[i]);
  }
  EXPECT_EQ(sim.health_check(), "");
  const BondList& b = sim.bonds();
  for (int grain = 0; grain < 2; ++grain) {
    long entries = 0;
    for (int i = g.node_begin[grain]; i < g.node_end[grain]; ++i)
      for (int k = b.offset[i]; k < b.offset[i + 1]; ++k) entries += b.broken[k];
    (grain == 0 ? r.bottom_broken : r.top_broken) = entries / 2;  // each bond is held from both ends
  }
  EXPECT_EQ(r.bottom_broken + r.top_broken, sim.broken_bonds());
  return r;
}

TEST(PeridemImpact, SameMaterialBothGrainsCrackMoreAtHigherSpeed) {
  const Impact v2 = run_impact("impact_wall_m1.yaml", 2);
  const Impact v4 = run_impact("impact_wall_m1.yaml", 4);
  const Impact v5 = run_impact("impact_wall_m1.yaml", 5);
  // The bottom grain, caught between the wall and the heavier top grain, cracks at every speed.
  EXPECT_GT(v2.bottom_broken, 0);
  // Both grains crack at 4 and 5 m/s (Fig 14-15).
  EXPECT_GT(v4.top_broken, 0);
  EXPECT_GT(v5.top_broken, 0);
  // The fracture zone grows with v0, in total and in each grain.
  EXPECT_LT(v2.bottom_broken + v2.top_broken, v4.bottom_broken + v4.top_broken);
  EXPECT_LT(v4.bottom_broken + v4.top_broken, v5.bottom_broken + v5.top_broken);
  EXPECT_LT(v2.bottom_broken, v4.bottom_broken);
  EXPECT_LT(v4.bottom_broken, v5.bottom_broken);
  EXPECT_LE(v2.top_broken, v4.top_broken);
  EXPECT_LT(v4.top_broken, v5.top_broken);
}

TEST(PeridemImpact, StrongerTopGrainStaysIntactWhileTheBottomOneCracks) {
  long previous = 0;
  for (int v0 : {2, 4, 5}) {
    SCOPED_TRACE("v0 = " + std::to_string(v0) + " m/s");
    const Impact r = run_impact("impact_wall_m2_top.yaml", v0);
    EXPECT_EQ(r.top_broken, 0);        // Fig 16-17: no node of the M2 grain has Z >= 1 ...
    EXPECT_LT(r.top_max_damage, 1.0);  // ... at any time (in tension or compression)
    EXPECT_GT(r.bottom_broken, previous);
    previous = r.bottom_broken;
  }
}

}  // namespace
}  // namespace debris
