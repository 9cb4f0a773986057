// Calibration from target properties (scenarios/calibrate, issue 29): Table 4's material on a small amorphous
// sample reaches E within 2%, nu within 0.01 and both strengths within 3% in at most 20 patch runs, checked by
// a patch run of its own on the inputs it returns; targets no input can reach are named errors.
#include <gtest/gtest.h>

#include <cmath>
#include <array>
#include <cstdio>
#include <string>

#include <filesystem>
#include <fstream>

#include "core/error.hpp"
#include "core/exec.hpp"
#include "scenarios/calibrate/calibration.hpp"
#include "tests/cli_helpers.hpp"

namespace debris {
namespace {

// Table 4 (s = 0, nu = 0.15) on a sample of about 300 particles: d0 = 0.6 d_c of the targets (90 length
// units), 8 x 8 x 5 d0.
CalibrationSpec table4_spec() {
  CalibrationSpec spec;
  spec.target = table4_material(0.0);
  spec.target.poisson_ratio = 0.15;
  spec.d0 = 0.6 * spec.target.critical_diameter();
  spec.sample.length = 8;
  spec.sample.width = 5;  // room for the cutoff of the inputs the calibration tries (3.6 is too thin for some)
  spec.sample.seed = 1;
  return spec;
}

std::string error_of(const CalibrationSpec& spec) {
  try {
    spec.validate();
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(Calibration, TargetsNoInputReachesAreNamedErrors) {
  CalibrationSpec spec = table4_spec();
  spec.target.poisson_ratio = 0.4;
  const std::string nu = error_of(spec);
  EXPECT_NE(nu.find("target.poisson_ratio"), std::string::npos) << nu;
  EXPECT_NE(nu.find("0.4"), std::string::npos) << nu;
  EXPECT_NE(nu.find("0.25"), std::string::npos) << nu;
  spec = table4_spec();
  spec.target.tensile_strength = -0.2;
  EXPECT_NE(error_of(spec).find("target.tensile_strength"), std::string::npos) << error_of(spec);
  spec = table4_spec();
  spec.d0 = 0;
  EXPECT_NE(error_of(spec).find("sample.d0"), std::string::npos) << error_of(spec);
  spec = table4_spec();
  spec.max_runs = 2;
  EXPECT_NE(error_of(spec).find("calibration.max_runs"), std::string::npos) << error_of(spec);
  EXPECT_EQ(error_of(table4_spec()), "no error");
}

void print_step(const CalibrationStep& s) {
  std::printf("[ info ] %2d runs: inputs E %.4f nu %.4f sN %.4f sT %.4f gamma %.4f -> E %.4f nu %.4f tension %.4f "
              "shear %.4f (%ld particles, %.1f s)%s\n",
              s.runs, s.inputs.youngs_modulus, s.inputs.poisson_ratio, s.inputs.tensile_strength,
              s.inputs.shear_strength, s.inputs.surface_energy, s.measured.youngs_modulus, s.measured.poisson_ratio,
              s.measured.tensile_strength, s.measured.shear_strength, s.measured.particles, s.measured.seconds,
              s.collapsed ? " collapsed" : "");
}

// A patch run of its own on the inputs returned: a sample relaxed afresh with them (at the calibrated E, not
// at the target E the loop ran at) and the three tests.
std::array<double, 4> independent_errors(const CalibrationSpec& spec, const CohesiveMaterial& inputs) {
  const CalibrationMeasure check = measure_sample(spec, inputs);
  std::printf("[ info ] check: E %.4f nu %.4f tension %.4f shear %.4f\n", check.youngs_modulus, check.poisson_ratio,
              check.tensile_strength, check.shear_strength);
  return calibration_errors(spec.target, check);
}

void expect_within_the_issue_accuracy(const std::array<double, 4>& e) {
  EXPECT_LE(std::abs(e[0]), 0.02) << "E";
  EXPECT_LE(std::abs(e[1]), 0.01) << "nu";
  EXPECT_LE(std::abs(e[2]), 0.03) << "tensile strength";
  EXPECT_LE(std::abs(e[3]), 0.03) << "shear strength";
}

// Table 4 (E 1, nu 0.15, tension 0.2, shear 0.1, s = 0) on a small sample: the targets' own inputs measure
// tension at 67% and shear at 78% of their targets (E at 1.157); the calibrated inputs meet all four within
// the issue's accuracy, by a patch run the calibration did not make. (Table 4's tension is near the edge of
// what this recipe reaches: neighbouring inputs measure 0.18-0.21 E, scenarios/patch/RESULTS.md.)
TEST(Calibration, Table4MaterialOnASmallAmorphousSampleMeetsEveryTarget) {
  const int saved = exec::threads();
  exec::set_threads(1);  // samples this small run fastest on one thread
  const CalibrationSpec spec = table4_spec();
  const CalibrationResult r = calibrate(spec, print_step);
  EXPECT_TRUE(r.converged) << r.why;
  EXPECT_LE(r.runs, 20);
  ASSERT_FALSE(r.steps.empty());
  const auto first = calibration_errors(spec.target, r.steps.front().measured);
  EXPECT_LT(first[2], -0.2) << "the targets' own inputs measure a tension well short of it";
  expect_within_the_issue_accuracy(independent_errors(spec, r.inputs));
  exec::set_threads(saved);
}

// A target inside the reachable set, from below (tension 0.16 with its own inputs measures 0.109 E).
TEST(Calibration, AReachableTargetIsMetWithinTwoPercentOnEAndThreeOnTheStrengths) {
  const int saved = exec::threads();
  exec::set_threads(1);
  CalibrationSpec spec = table4_spec();
  spec.target.tensile_strength = 0.16;
  const CalibrationResult r = calibrate(spec, print_step);
  EXPECT_TRUE(r.converged) << r.why;
  EXPECT_LE(r.runs, 20);
  expect_within_the_issue_accuracy(independent_errors(spec, r.inputs));
  exec::set_threads(saved);
}

// A tension past the collapse edge (0.3 E; samples of this recipe measure at most about 0.2 E, and at
// sigma_N / E ~ 0.31 the packing pulls itself in): the answer names the target, the most a sample reached
// and the input that limits it, and the inputs it returns still meet E, nu and the shear strength, with
// the tension it reports, by an independent run.
TEST(Calibration, ATensionPastTheCollapseEdgeIsAnsweredWithTheClosestReachable) {
  const int saved = exec::threads();
  exec::set_threads(1);
  CalibrationSpec spec = table4_spec();
  spec.target.tensile_strength = 0.3;
  const CalibrationResult r = calibrate(spec, print_step);
  EXPECT_FALSE(r.converged);
  EXPECT_LE(r.runs, 20);
  EXPECT_NE(r.why.find("target tensile_strength 0.3 is out of reach"), std::string::npos) << r.why;
  EXPECT_NE(r.why.find("the input that limits it is tensile_strength"), std::string::npos) << r.why;
  bool collapsed = false;
  for (const auto& s : r.steps) collapsed = collapsed || s.collapsed;
  EXPECT_TRUE(collapsed) << "the edge was found by a sample that collapsed";
  const auto e = independent_errors(spec, r.inputs);
  EXPECT_LE(std::abs(e[0]), 0.02) << "E";
  EXPECT_LE(std::abs(e[1]), 0.01) << "nu";
  EXPECT_LE(std::abs(e[3]), 0.03) << "shear strength";
  EXPECT_NEAR(e[2] + 1, r.expected.tensile_strength / spec.target.tensile_strength, 0.03) << "tension as reported";
  EXPECT_LT(r.expected.tensile_strength, 0.23) << "the closest reachable";
  exec::set_threads(saved);
}

// debris_calibrate's bad input: a target nu of 0.4, a negative strength, an unknown key: exit 2 with the
// key and the value, before anything is written.
TEST(CalibrateCli, BadTargetsAreNamedErrorsAndWriteNothing) {
  namespace fs = std::filesystem;
  const fs::path dir = test::fresh_directory("debris_calibrate_cli");
  const std::string base = std::string(DEBRIS_SOURCE_DIR) + "/scenarios/calibrate/table4.yaml";
  std::ifstream in(base);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const struct {
    std::string from, to, key, value;
  } cases[] = {{"  scaling: 0", "  scaling: 0\n  poisson_ratio: 0.4", "target.poisson_ratio", "0.4"},
               {"  scaling: 0", "  scaling: 0\n  tensile_strength: -0.2", "tensile_strength", "-0.2"},
               {"  seed: 1", "  seed: 1\n  colour: red", "colour", ""}};
  for (const auto& c : cases) {
    SCOPED_TRACE(c.key);
    std::string t = text;
    t.replace(t.find(c.from), c.from.size(), c.to);
    const fs::path input = dir / "input.yaml", out = dir / "out";
    std::ofstream(input) << t;
    const test::CommandResult r =
        test::run_command(DEBRIS_CALIBRATE_EXECUTABLE, "-i " + input.string() + " -o " + out.string());
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find(c.key), std::string::npos) << r.output;
    EXPECT_NE(r.output.find(c.value), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(out)) << "nothing written";
  }
}

}  // namespace
}  // namespace debris
