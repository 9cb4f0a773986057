// Patch tests on amorphous samples (paper section 3.2) at small sizes: the elastic test runs end to end on
// a tiny relaxed sample and gives C11 and E just below the affine estimate of the sample's own pair network
// and nu between the target and the paper's measured 0.20; the health check's overlap limit is a
// setting (automatic: the sample's own deepest overlap plus an allowance), because relaxed samples are
// pre-stressed with overlaps deeper than the engine's default of half a radius; debris_patch's `kind:
// amorphous` makes the sample, caches it, and ends bad input with messages naming the key and the value.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>

#include "core/error.hpp"
#include "core/exec.hpp"
#include "scenarios/common/dem/amorphous_sample.hpp"
#include "scenarios/patch/patch_test.hpp"
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
  EXPECT_DOUBLE_EQ(patch_overlap_limit(0.0, 0.0, kOverlapAllowanceElastic), 0.5);  // a lattice: 0.5 and 1.0
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

// The affine (Voigt) estimate of the confined moduli along y of a relaxed packing, by brute force over its
// pairs: a uniform strain eps_yy moves a pair l n apart by eps l n_y y, which loads its normal spring (eq 7)
// by eps l n_y^2 and its tangential one (eq 8) by the rest, so
//   C11 = sum l^2 (k_N n_y^4 + k_T n_y^2 (1 - n_y^2)) / V,   C12 = sum l^2 (k_N - k_T) n_x^2 n_y^2 / V
// over the pairs on the Hookean branch of eq 3 (dN <= delta_e; those past it soften and are left out, as
// they would only lower the estimate). Relaxation of the particles away from the affine positions can only
// lower the stiffness of a harmonic network, so the measured C11 lies below this.
struct AffineModuli {
  double c11, c12;
  long pairs;
};
AffineModuli affine_confined_moduli(const Box& box, const Particles& p, const CohesiveMaterial& m) {
  const double nu = m.poisson_ratio, E = m.youngs_modulus;
  const Vec3 len = box.length();
  double c11 = 0, c12 = 0;
  long pairs = 0;
  for (std::size_t i = 0; i < p.size(); ++i)
    for (std::size_t j = i + 1; j < p.size(); ++j) {
      double d[3] = {p.x[i] - p.x[j], p.y[i] - p.y[j], p.z[i] - p.z[j]};
      const double l3[3] = {len.x, len.y, len.z};
      for (int a = 0; a < 3; ++a) d[a] -= l3[a] * std::round(d[a] / l3[a]);  // minimum image, periodic box
      const double l = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
      const double ri = p.radius[i], rj = p.radius[j], r_eff = std::min(ri, rj);
      if (l - ri - rj > (ri + rj) * m.tensile_strength / E) continue;  // beyond delta_e (eq 9)
      const double an = std::sqrt(2.0) * r_eff * r_eff / (1 - 2 * nu);                           // eq 15
      const double at = std::sqrt(2.0) * r_eff * r_eff * (1 - 4 * nu) / ((1 - 2 * nu) * (1 + nu));  // eq 16
      const double kn = an * E / (ri + rj), kt = at * E / (ri + rj);                                 // eqs 7-8
      const double nx = d[0] / l, ny = d[1] / l;
      c11 += l * l * (kn * ny * ny * ny * ny + kt * ny * ny * (1 - ny * ny));
      c12 += l * l * (kn - kt) * nx * nx * ny * ny;
      ++pairs;
    }
  const double volume = len.x * len.y * len.z;
  return {c11 / volume, c12 / volume, pairs};
}

// E and nu of a ~300-particle sample with s = 0, nu = 0.15. The paper gives no number for E (Fig 8 only)
// but explains it: E follows the packing's contacts. So C11 is compared with the affine estimate of this
// very sample's pair network (affine_confined_moduli), an upper bound that non-affine relaxation lowers; the
// sample is well connected (about 14 Hookean pairs per particle, far above the 6 of a rigid packing), so it
// lowers it little: measured C11 = 1.201 against 1.247 (0.963), E = 1.129 against 1.181. The bound is taken
// 2% loose because the estimate covers the whole periodic sample and the measure its interior. nu: eqs
// 15-16 make the affine nu exactly the target 0.15 (1.500 here), and relaxation raises it: the paper
// measures about 0.20 on its 100 d0 samples, debris 0.155-0.173 on 12 d0 ones (scenarios/patch/RESULTS.md);
// this one gives 0.1586. The window is the target less 0.02 up to the paper's value plus 0.03 for the
// scatter of so small a sample.
TEST(PatchAmorphous, ElasticTestOnATinySampleGivesPlausibleEAndNu) {
  const PatchSample s = tiny_patch();
  OneThread one;
  EXPECT_GT(s.volume_fraction, 0.8);
  const ElasticResult r = run_elastic_test(s, tiny_spec().material, ElasticSettings{});
  EXPECT_LT(r.eps, 0.0);  // compressed
  // The bulk starts pre-stressed (its stress, not the box's, is far from the 1e-14 E the relaxation reached);
  // the moduli are taken from the stress change.
  EXPECT_GT(std::max({std::abs(r.sigma0.xx), std::abs(r.sigma0.yy), std::abs(r.sigma0.zz)}), 1e-5);
  const AmorphousSample& a = tiny_sample();
  const AffineModuli aff = affine_confined_moduli(a.box, a.particles, tiny_spec().material);
  const IsotropicModuli affine = isotropic_from_stiffness(aff.c11, aff.c12);
  std::printf("[ info ] tiny amorphous sample: C11 = %.4f (affine %.4f, ratio %.3f), C12 = %.4f (affine %.4f), E = %.4f "
              "(affine %.4f), nu = %.4f (affine %.4f, paper ~0.20), %ld Hookean pairs for %zu particles\n",
              r.c11, aff.c11, r.c11 / aff.c11, r.c12, aff.c12, r.moduli.E, affine.E, r.moduli.nu, affine.nu, aff.pairs,
              a.particles.size());
  EXPECT_NEAR(affine.nu, 0.15, 0.01) << "eqs 15-16: the affine network has the target nu";
  EXPECT_GT(aff.pairs, 10 * static_cast<long>(a.particles.size()) / 2) << "a well-connected packing";
  EXPECT_LT(r.c11, 1.02 * aff.c11);
  EXPECT_GT(r.c11, 0.85 * aff.c11);
  EXPECT_LT(r.moduli.E, 1.02 * affine.E);
  EXPECT_GT(r.moduli.E, 0.85 * affine.E);
  EXPECT_GT(r.moduli.nu, 0.15 - 0.02);
  EXPECT_LT(r.moduli.nu, 0.20 + 0.03);
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

using debris::test::replace;

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
