// Calibration from target properties (scenarios/calibrate): Table 4's material on a small amorphous sample
// reaches E within 2%, nu within 0.01 and both strengths within 3% in at most 20 patch runs, checked by
// debris_patch on the inputs debris_calibrate prints (another reader and driver) and on a seed the
// calibration never saw, against the scatter it reports; targets no input can reach are named errors; an
// answer no run confirmed, or a sample that does not relax, is said to be so with exit status 3.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>
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

// A patch run of its own on inputs the calibration returned without running them (a step's inputs scaled
// onto the target's E): a sample relaxed afresh with them and the three tests.
std::array<double, 4> independent_errors(const CalibrationSpec& spec, const CohesiveMaterial& inputs) {
  const CalibrationMeasure check = measure_sample(spec, inputs);
  std::printf("[ info ] check: E %.4f nu %.4f tension %.4f shear %.4f\n", check.youngs_modulus, check.poisson_ratio,
              check.tensile_strength, check.shear_strength);
  return calibration_errors(spec.target, check);
}

void expect_within_the_tolerances(const std::array<double, 4>& e) {
  EXPECT_LE(std::abs(e[0]), 0.02) << "E";
  EXPECT_LE(std::abs(e[1]), 0.01) << "nu";
  EXPECT_LE(std::abs(e[2]), 0.03) << "tensile strength";
  EXPECT_LE(std::abs(e[3]), 0.03) << "shear strength";
}

namespace fs = std::filesystem;

// Table 4 (E 1, nu 0.15, s = 0) at d0 = 90 on an 8 x 8 x 5 d0 sample, table4.yaml's recipe, as a
// debris_calibrate input: `target` lines added to its target section, `calibration` lines as its
// calibration section.
std::string calibrate_input(const std::string& target, const std::string& calibration, const fs::path& out) {
  return "target:\n  preset: table4\n  poisson_ratio: 0.15\n  scaling: 0\n" + target +
         "sample:\n  d0: 90\n  length: 8\n  width: 5\n  seed: 1\ncalibration:\n" + calibration +
         "output:\n  directory: " + out.string() + "\nrun:\n  threads: 1\n";
}

// The `material:` block debris_calibrate prints, key by key, as printed.
std::map<std::string, std::string> printed_material(const std::string& output) {
  std::map<std::string, std::string> m;
  const auto at = output.find("\nmaterial:\n");
  if (at == std::string::npos) return m;
  std::istringstream in(output.substr(at + 11));
  std::string line;
  while (std::getline(in, line) && line.rfind("  ", 0) == 0) {
    const auto colon = line.find(": ");
    m[line.substr(2, colon - 2)] = line.substr(colon + 2);
  }
  return m;
}

struct Measured {
  double E = 0, nu = 0, tension = 0, shear = 0;
};

// debris_patch's elastic, tension and shear tests on an amorphous sample of the calibration's recipe (d0 = 90
// in the material's units, 8 x 8 x 5 d0, walls 1.5 d0) with the material as debris_calibrate printed it:
// another reader of the inputs and another driver of the tests. The elastic load is 1% of the inputs' E,
// as the calibration applies it.
Measured measure_with_debris_patch(const std::map<std::string, std::string>& material, long seed,
                                   const fs::path& dir) {
  std::ostringstream in;
  in.precision(17);
  in << "test: [elastic, tension, shear]\nmaterial:\n";
  for (const auto& [k, v] : material) in << "  " << k << ": " << v << "\n";
  const auto num = [&](const char* k) { return std::stod(material.at(k)); };
  const CohesiveMaterial m{num("youngs_modulus"), num("poisson_ratio"), num("tensile_strength"),
                           num("shear_strength"),  num("surface_energy"), num("restitution"),
                           num("density"),         num("scaling")};
  in << "sample:\n  kind: amorphous\n  d0: " << 90 / m.critical_diameter() << "\n  length: 8\n  width: 5\n  seed: "
     << seed << "\nelastic:\n  stress: " << 0.01 * m.youngs_modulus << "\noutput:\n  plots: false\n";
  const fs::path yaml = dir / ("patch_seed" + std::to_string(seed) + ".yaml"),
                 out = dir / ("patch_seed" + std::to_string(seed));
  std::ofstream(yaml) << in.str();
  const test::CommandResult r =
      test::run_command(DEBRIS_PATCH_EXECUTABLE, "-i " + yaml.string() + " -o " + out.string() + " --threads 1");
  EXPECT_EQ(r.exit_code, 0) << in.str() << r.output;
  EXPECT_EQ(r.output.find("W raised"), std::string::npos) << "the calibration's sample, not a wider one";
  Measured got;
  for (const auto& row : test::read_csv_rows(out / "cases.csv")) {
    const std::string t = row.at("test");
    if (t == "elastic") {
      got.E = test::csv_number(row, "E");
      got.nu = test::csv_number(row, "nu");
    } else {
      (t == "tension" ? got.tension : got.shear) = test::csv_number(row, "strength");
    }
  }
  std::printf("[ info ] debris_patch, seed %ld: E %.5f nu %.5f tension %.5f shear %.5f\n", seed, got.E, got.nu,
              got.tension, got.shear);
  return got;
}

std::array<double, 4> errors_of(const Measured& m, double E, double nu, double tension, double shear) {
  return {m.E / E - 1, m.nu - nu, m.tension / tension - 1, m.shear / shear - 1};
}

// debris_calibrate on `target` lines, then its printed inputs through debris_patch: on the calibration's own
// seed they meet every target within the tolerances (2%, 0.01, 3%), and on seed `other`, which it never
// ran, each property lies within twice the largest deviation from the target that spread.csv reports over
// its seeds (at least the tolerance). The calibration's own seed sits on the targets; of a normal scatter,
// the larger deviation of two other seeds is about 1.1 standard deviations, and a further seed passes
// twice that with a chance of about 2%.
void calibrate_and_check(const std::string& name, const std::string& target, double tension, double shear,
                         const std::string& spread, long other) {
  const fs::path dir = test::fresh_directory("debris_calibrate_" + name);
  const fs::path out = dir / "out";
  const std::string yaml =
      test::write_text_file(dir, "in.yaml", calibrate_input(target, "  spread_seeds: " + spread + "\n", out));
  const test::CommandResult r =
      test::run_command(DEBRIS_CALIBRATE_EXECUTABLE, "-i " + yaml + " -o " + out.string() + " --threads 1");
  std::printf("%s", r.output.c_str());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto steps = test::read_csv_rows(out / "calibration.csv");
  ASSERT_FALSE(steps.empty());
  EXPECT_LE(test::csv_number(steps.back(), "runs"), 20);
  const auto material = printed_material(r.output);
  ASSERT_EQ(material.size(), 8u) << r.output;

  const auto own = errors_of(measure_with_debris_patch(material, 1, dir), 1.0, 0.15, tension, shear);
  expect_within_the_tolerances(own);

  std::array<double, 4> scatter{0.02, 0.01, 0.03, 0.03};  // at least the tolerances
  const char* columns[] = {"error_E", "error_nu", "error_tensile", "error_shear"};
  const auto rows = test::read_csv_rows(out / "spread.csv");
  EXPECT_GE(rows.size(), 2u) << "the calibration's seed and at least one more";
  for (const auto& row : rows)
    for (std::size_t k = 0; k < 4; ++k) scatter[k] = std::max(scatter[k], std::abs(test::csv_number(row, columns[k])));
  const auto far = errors_of(measure_with_debris_patch(material, other, dir), 1.0, 0.15, tension, shear);
  for (std::size_t k = 0; k < 4; ++k)
    EXPECT_LE(std::abs(far[k]), 2 * scatter[k]) << columns[k] << " on seed " << other << ": reported scatter "
                                                << scatter[k];
}

// Table 4 (E 1, nu 0.15, tension 0.2, shear 0.1, s = 0) on a small sample: the targets' own inputs measure
// tension at 67% and shear at 78% of their targets (E at 1.157); the calibrated inputs meet all four within
// the tolerances through debris_patch, and on a fourth seed stay within the scatter of the three the
// calibration reports. (Table 4's tension is near the edge of what this recipe reaches: neighbouring inputs
// measure 0.18-0.21 E, scenarios/patch/RESULTS.md.)
TEST(Calibration, Table4MaterialOnASmallAmorphousSampleMeetsEveryTarget) {
  calibrate_and_check("table4", "", 0.2, 0.1, "[2, 3]", 4);
  const auto first =
      test::read_csv_rows(fs::path(::testing::TempDir()) / "debris_calibrate_table4" / "out" / "calibration.csv");
  ASSERT_FALSE(first.empty());
  EXPECT_LT(test::csv_number(first.front(), "error_tensile"), -0.2)
      << "the targets' own inputs measure a tension well short of it";
}

// A target inside the reachable set, from below (tension 0.16 with its own inputs measures 0.109 E).
TEST(Calibration, AReachableTargetIsMetWithinTwoPercentOnEAndThreeOnTheStrengths) {
  calibrate_and_check("reachable", "  tensile_strength: 0.16\n", 0.16, 0.1, "[2, 3]", 4);
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

// Targets E 1, nu 0.10, tension 0.17, shear 0.085, gamma 1.2 (s = 0, d0 = 90, 8 x 8 x 5 d0, seed 1) with a
// strength tolerance of 45% and 5 patch runs: the first step (3 runs) meets nu, tension / E and shear / E
// but measures E 6% high, and the 3 runs that would confirm the inputs rescaled onto E do not fit. The answer
// is printed as what those inputs should measure, not as a measurement; exit 3, and the reason names what
// misses (E, unconfirmed) and the max_runs that would confirm it. debris_patch on the printed inputs then
// measures E within 2% and the same nu: the rescale the reason describes does what it says.
TEST(CalibrateCli, AnAnswerNoRunConfirmedIsSaidToBeSoAndTheReasonNamesWhatMisses) {
  const fs::path dir = test::fresh_directory("debris_calibrate_unconfirmed");
  const fs::path out = dir / "out";
  const std::string yaml = test::write_text_file(
      dir, "in.yaml",
      "target:\n  preset: table4\n  youngs_modulus: 1\n  poisson_ratio: 0.10\n  tensile_strength: 0.17\n"
      "  shear_strength: 0.085\n  surface_energy: 1.2\n  scaling: 0\nsample:\n  d0: 90\n  length: 8\n  width: 5\n"
      "  seed: 1\ncalibration:\n  max_runs: 5\n  tolerance_strength: 0.45\n  spread_seeds: []\noutput:\n"
      "  directory: " + out.string() + "\n");
  const test::CommandResult r =
      test::run_command(DEBRIS_CALIBRATE_EXECUTABLE, "-i " + yaml + " -o " + out.string() + " --threads 1");
  std::printf("%s", r.output.c_str());
  EXPECT_EQ(r.exit_code, 3) << r.output;
  EXPECT_EQ(r.output.find("they measure:"), std::string::npos) << "inputs no run tried, printed as measured";
  const auto at = r.output.rfind("debris_calibrate: ");
  ASSERT_NE(at, std::string::npos) << r.output;
  const std::string why = r.output.substr(at);
  const auto colon = why.find(": ", 18);
  ASSERT_NE(colon, std::string::npos) << why;
  EXPECT_NE(why.find_first_not_of(" \n", colon + 1), std::string::npos) << "a reason after the colon: " << why;
  EXPECT_NE(why.find("youngs_modulus measured 1.06"), std::string::npos) << why;
  EXPECT_NE(why.find("calibration.max_runs to 6"), std::string::npos) << why;

  const auto material = printed_material(r.output);
  ASSERT_EQ(material.size(), 8u) << r.output;
  const Measured m = measure_with_debris_patch(material, 1, dir);
  EXPECT_NEAR(m.E, 1.0, 0.02);
  const auto rows = test::read_csv_rows(out / "calibration.csv");
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_NEAR(m.nu, test::csv_number(rows[0], "nu"), 0.01);
}

// A tensile strength target of 5e-4 E (surface energy 1e-3, s = 0, d0 = 90): its samples measure tension
// 7 to 12 times the target, the loop lowers the input, and at 2.2e-4 E phase 2 of the relaxation is still
// above 1e-14 E after its 200,000 steps. The calibration says the sample did not relax and that the target
// tensile_strength drives it, exit 3 with the two steps that ran kept in calibration.csv, not an input error
// naming relaxation.phase2.max_steps, a key the user did not give.
TEST(CalibrateCli, ASampleThatDoesNotRelaxIsNamedWithTheTargetThatDrivesIt) {
  const fs::path dir = test::fresh_directory("debris_calibrate_stall");
  const fs::path out = dir / "out";
  const std::string yaml = test::write_text_file(
      dir, "in.yaml",
      "target:\n  preset: table4\n  poisson_ratio: 0.10\n  tensile_strength: 0.0005\n  shear_strength: 0.085\n"
      "  surface_energy: 0.001\n  scaling: 0\nsample:\n  d0: 90\n  length: 8\n  width: 5\n  seed: 1\n"
      "calibration:\n  spread_seeds: []\noutput:\n  directory: " + out.string() + "\n");
  const test::CommandResult r =
      test::run_command(DEBRIS_CALIBRATE_EXECUTABLE, "-i " + yaml + " -o " + out.string() + " --threads 1");
  std::printf("%s", r.output.c_str());
  EXPECT_EQ(r.exit_code, 3) << r.output;
  EXPECT_EQ(r.output.find("input error: 'relaxation.phase2.max_steps'"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("the sample did not relax with these targets"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("the target that drives it is tensile_strength 0.0005"), std::string::npos) << r.output;
  EXPECT_EQ(test::read_csv_rows(out / "calibration.csv").size(), 2u) << "the steps that ran are kept";
}

}  // namespace
}  // namespace debris
