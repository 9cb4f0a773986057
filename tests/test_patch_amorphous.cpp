// Patch tests on amorphous samples (paper section 3.2) at small sizes: the elastic test runs end to end on
// a tiny relaxed sample and gives E and nu in a plausible range; the health check's overlap limit is a
// setting (automatic: the sample's own deepest overlap plus an allowance), because relaxed samples are
// pre-stressed with overlaps deeper than the engine's default of half a radius; debris_patch's `kind:
// amorphous` makes the sample, caches it, and ends bad input with messages naming the key and the value.
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>

#include "core/error.hpp"
#include "core/exec.hpp"
#include "scenarios/common/amorphous_sample.hpp"
#include "scenarios/common/patch_test.hpp"
#include "tests/cli_helpers.hpp"

namespace debris {
namespace {

namespace fs = std::filesystem;

// d0 = 0.6 d_c (delta_f = d0 / 3, the deepest relaxed overlaps of the sweep), s = 0, nu = 0.15: 8 x 8 x
// 3.6 d0 (W: the neighbour list's 3.32 d0 plus room for phase 2), 8 d0 tall so that an interior 1.5 d0 from
// both walls is left. About 300 particles, made once.
AmorphousSpec tiny_spec() {
  AmorphousSpec s;
  s.material = table4_material(0.0);
  s.material.poisson_ratio = 0.15;
  s.d0 = 0.6;
  s.length = 8;
  s.width = 3.6;
  s.seed = 1;
  return s;
}

// One thread: samples this small run fastest on one, and the shared test machine's cores are busy.
class OneThread {
 public:
  OneThread() : saved_(exec::threads()) { exec::set_threads(1); }
  ~OneThread() { exec::set_threads(saved_); }

 private:
  int saved_;
};

const AmorphousSample& tiny_sample() {
  static std::unique_ptr<AmorphousSample> s;
  if (!s) {
    OneThread one;
    s = std::make_unique<AmorphousSample>(make_amorphous_sample(tiny_spec()));
  }
  return *s;
}

PatchSample tiny_patch() {
  const AmorphousSample& a = tiny_sample();
  return make_walled_sample(a.box, a.particles, 1.5, tiny_spec().material, "sample", "tiny amorphous sample");
}

TEST(PatchOverlapLimit, AutomaticIsTheInitialOverlapPlusTheAllowance) {
  EXPECT_DOUBLE_EQ(patch_overlap_limit(0.0, 0.0, kOverlapAllowanceElastic), 0.5);  // a lattice: the old limits
  EXPECT_DOUBLE_EQ(patch_overlap_limit(0.0, 0.0, kOverlapAllowanceStrength), 1.0);
  EXPECT_DOUBLE_EQ(patch_overlap_limit(0.0, 0.65, kOverlapAllowanceElastic), 1.15);
  EXPECT_DOUBLE_EQ(patch_overlap_limit(2.0, 0.65, kOverlapAllowanceElastic), 2.0);  // a setting wins
  ElasticSettings es;
  es.overlap_limit = -1;
  try {
    validate(es);
    ADD_FAILURE() << "a negative overlap limit was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("'elastic.overlap_limit' = -1"), std::string::npos) << e.what();
  }
}

// E and nu of a ~300-particle sample with s = 0: the paper measures nu about 0.20 for a target of 0.15 and E
// following the volume fraction, which at d0 = 0.6 d_c (0.85 in debris's samples) is above the HCP
// lattice's 0.74, whose E is within 12% of the target (1.14 E measured on the 12 d0 sample of the sweep). A sample this
// small has only about 100 particles in its interior, so its moduli scatter by tens of percent from sample to sample
// (12 d0 samples of the d0 sweep: see scenarios/patch/RESULTS.md); the bounds take E within a factor of 2 of the target
// and nu between 0.05 and 0.35, which an unsubtracted pre-stress, a wrong volume or a broken sample would leave.
TEST(PatchAmorphous, ElasticTestOnATinySampleGivesPlausibleEAndNu) {
  const PatchSample s = tiny_patch();
  OneThread one;
  EXPECT_GT(s.volume_fraction, 0.8);
  const ElasticResult r = run_elastic_test(s, tiny_spec().material, ElasticSettings{});
  EXPECT_TRUE(std::isfinite(r.moduli.E) && std::isfinite(r.moduli.nu));
  EXPECT_GT(r.moduli.E, 0.5);
  EXPECT_LT(r.moduli.E, 2.0);
  EXPECT_GT(r.moduli.nu, 0.05);
  EXPECT_LT(r.moduli.nu, 0.35);
  EXPECT_LT(r.eps, 0.0);  // compressed
  // The bulk starts pre-stressed (its stress, not the box's, is far from the 1e-14 E the relaxation reached);
  // the moduli are taken from the stress change.
  EXPECT_GT(std::max({std::abs(r.sigma0.xx), std::abs(r.sigma0.yy), std::abs(r.sigma0.zz)}), 1e-5);
  EXPECT_NEAR(r.c11, (r.sigma.yy - r.sigma0.yy) / r.eps, 1e-12);
}

TEST(PatchAmorphous, OverlapLimitIsASettingAndAutomaticFitsRelaxedSamples) {
  const PatchSample s = tiny_patch();
  OneThread one;
  ElasticSettings es;
  es.max_steps = 600;  // enough for the first health checks (every 10 samples of 50 steps)
  es.window = 100000;  // no equilibrium within max_steps: only the health check can end it earlier
  // The engine's default limit, half the smallest radius, is below the relaxed sample's own overlaps.
  es.overlap_limit = 0.5;
  try {
    run_elastic_test(s, tiny_spec().material, es);
    ADD_FAILURE() << "a limit below the sample's own overlaps did not stop the run";
  } catch (const PatchRunError& e) {
    EXPECT_NE(std::string(e.what()).find("exploding overlap"), std::string::npos) << e.what();
  }
  // Automatic: it runs into the step limit instead, and the limit is the initial overlap + 0.5.
  es.overlap_limit = 0;
  try {
    run_elastic_test(s, tiny_spec().material, es);
    ADD_FAILURE() << "no step-limit error";
  } catch (const PatchRunError& e) {
    EXPECT_NE(std::string(e.what()).find("elastic.max_steps"), std::string::npos) << e.what();
  }
  const ElasticResult r = run_elastic_test(s, tiny_spec().material, ElasticSettings{});
  EXPECT_GT(r.initial_overlap, 0.5) << "the relaxed sample holds overlaps deeper than half the smallest radius";
  EXPECT_DOUBLE_EQ(r.overlap_limit, r.initial_overlap + kOverlapAllowanceElastic);
}

// ---------------------------------------------------------------------------------------------------------
// debris_patch with kind: amorphous.

using Result = debris::test::CommandResult;

Result run_input(const fs::path& dir, const std::string& yaml) {
  std::ofstream(dir / "in.yaml") << yaml;
  return debris::test::run_command(DEBRIS_PATCH_EXECUTABLE, "-i " + (dir / "in.yaml").string() + " -o " +
                                                                (dir / "out").string() + " --threads 1");
}

fs::path scratch(const std::string& name) { return debris::test::fresh_directory("debris_patch_amorphous_" + name); }

std::string small_input() {
  return R"(test: elastic
material:
  poisson_ratio: 0.15
sample:
  kind: amorphous
  d0: 0.6
  length: 8
  width: 3
output:
  plots: false
)";
}

std::string replace(std::string text, const std::string& from, const std::string& to) {
  const auto pos = text.find(from);
  EXPECT_NE(pos, std::string::npos) << from;
  if (pos != std::string::npos) text.replace(pos, from.size(), to);
  return text;
}

using debris::test::slurp;

TEST(PatchAmorphousCli, MakesTheSampleOnceAndReusesItFromTheCache) {
  const fs::path dir = scratch("good");
  const Result a = run_input(dir, small_input());
  ASSERT_EQ(a.exit_code, 0) << a.output;
  EXPECT_NE(a.output.find("making the amorphous sample"), std::string::npos) << a.output;
  EXPECT_NE(a.output.find("W raised from 3 to"), std::string::npos) << a.output;
  const std::string table = slurp(dir / "out" / "cases.csv");
  EXPECT_NE(table.find("\n1,elastic,amorphous,,0.59999999999999998,"), std::string::npos) << table;
  bool saved = false;
  for (const auto& e : fs::directory_iterator(dir / "out" / "samples")) saved = saved || e.path().extension() == ".h5";
  EXPECT_TRUE(saved);
  // The same recipe again: loaded, same result; another seed: made anew.
  const Result b = run_input(dir, small_input());
  ASSERT_EQ(b.exit_code, 0) << b.output;
  EXPECT_NE(b.output.find("amorphous sample loaded from"), std::string::npos) << b.output;
  EXPECT_EQ(slurp(dir / "out" / "cases.csv").substr(0, 400), table.substr(0, 400));
}

TEST(PatchAmorphousCli, BadInputsEndWithTheKeyAndValue) {
  const fs::path dir = scratch("bad");
  struct Bad {
    std::string from, to;
    std::vector<std::string> mention;
  };
  const Bad bad[] = {
      {"  d0: 0.6", "  d0: [0.6, 0.1]", {"sample.d0", "0.1", "d_min"}},
      {"  width: 3", "  width: 3\n  volume_fraction: 1.2", {"sample.volume_fraction", "1.2", "cannot be reached"}},
      {"output:", "elastic:\n  overlap_limit: -1\noutput:", {"elastic.overlap_limit", "-1"}},
      {"  width: 3", "  thickness: 3", {"relaxation", "unknown key"}},
  };
  for (const Bad& b : bad) {
    std::string yaml = replace(small_input(), b.from, b.to);
    if (b.to.find("thickness") != std::string::npos)  // a lattice has no relaxation section
      yaml = replace(replace(yaml, "kind: amorphous", "kind: hcp"),
                     "output:", "relaxation:\n  phase1: {steps: 10}\noutput:");
    const Result r = run_input(dir, yaml);
    EXPECT_EQ(r.exit_code, 2) << b.to << "\n" << r.output;
    for (const std::string& m : b.mention)
      EXPECT_NE(r.output.find(m), std::string::npos) << "no '" << m << "' in:\n" << r.output;
    EXPECT_FALSE(fs::exists(dir / "out" / "cases.csv")) << "bad input must not start writing results";
  }
}

TEST(PatchAmorphousCli, StressThresholdNeverMetEndsWithAMessageAndStatus3) {
  const fs::path dir = scratch("threshold");
  const Result r = run_input(dir, small_input() + "relaxation:\n  phase2: {max_steps: 100}\n");
  EXPECT_EQ(r.exit_code, 3) << r.output;
  EXPECT_NE(r.output.find("relaxation.phase2.max_steps"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("did not all fall below the threshold"), std::string::npos) << r.output;
  EXPECT_NE(slurp(dir / "out" / "cases.csv").find("failed: amorphous sample"), std::string::npos);
}

}  // namespace
}  // namespace debris
