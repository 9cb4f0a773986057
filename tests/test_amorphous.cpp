// Amorphous samples (Pham-Ba & Molinari section 3.2): the truncated log-normal sampler of the diameters
// against its closed forms, random insertion to the volume fraction, the two relaxation phases on a small
// sample (about 200 particles, under a second), the mass rescaling to the target density, the saved files
// read back, and the errors for inputs that cannot work.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <numbers>
#include <string>

#include "core/error.hpp"
#include "core/exec.hpp"
#include "core/io/lammps_data.hpp"
#include "scenarios/common/dem/truncated_lognormal.hpp"
#include "scenarios/common/dem/amorphous_sample.hpp"
#include "scenarios/common/dem/dem_simulation.hpp"

namespace debris {
namespace {

// ---------------------------------------------------------------------------------------------------------
// The sampler.

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no InputError)";
}

TEST(LogNormalSampler, ParametersGiveTheRequestedModeAndSd) {
  // The paper's distribution (d0 = 1, [0.75, 1.25], sd 0.1), the A.4 one (d_l = 5 d0, sd 0.85) and a mode
  // on a bound: the untruncated log-normal has exactly the mode and sd asked for.
  struct Case {
    double mode, sd, lo, hi;
  };
  for (const Case c : {Case{1.0, 0.1, 0.75, 1.25}, Case{90.0, 0.85 * 90.0, 67.5, 450.0}, Case{2.0, 0.3, 2.0, 3.0}}) {
    const auto d = TruncatedLogNormal::from_mode_and_sd(c.mode, c.sd, c.lo, c.hi);
    EXPECT_NEAR(d.mode(), c.mode, 1e-13 * c.mode);
    EXPECT_NEAR(d.untruncated_sd(), c.sd, 1e-12 * c.sd);
  }
}

TEST(LogNormalSampler, NormalQuantileInvertsTheCdf) {
  EXPECT_EQ(normal_quantile(0.5), 0.0);
  EXPECT_NEAR(normal_quantile(0.975), 1.959963984540054, 1e-14);
  for (double p : {1e-300, 1e-100, 1e-20, 1e-8, 1e-3, 0.02425, 0.1, 0.3, 0.7, 0.9, 0.999}) {
    const double z = normal_quantile(p);
    EXPECT_NEAR(normal_cdf(z) / p, 1.0, 1e-13) << "p = " << p;
    EXPECT_NEAR(normal_ccdf(-z) / p, 1.0, 1e-13) << "p = " << p;
  }
}

TEST(LogNormalSampler, DrawsStayInsideTheBoundsAndMatchTheTruncatedMoments) {
  const auto d = TruncatedLogNormal::from_mode_and_sd(1.0, 0.1, 0.75, 1.25);
  const std::size_t n = 400000;
  const auto x = d.sample(n, 7);
  double sum = 0.0, sum2 = 0.0;
  for (double v : x) {
    ASSERT_GE(v, 0.75);
    ASSERT_LE(v, 1.25);
    sum += v;
    sum2 += v * v;
  }
  const double mean = sum / n, sd = std::sqrt(sum2 / n - mean * mean);
  // The bounds are reached: the tails are 2.5 sd away, so about 1% of draws fall within 0.01 of each.
  EXPECT_LT(*std::min_element(x.begin(), x.end()), 0.751);
  EXPECT_GT(*std::max_element(x.begin(), x.end()), 1.249);
  // Closed-form truncated moments; the sample mean is within 5 standard errors of it.
  const double se = d.truncated_sd() / std::sqrt(static_cast<double>(n));
  EXPECT_NEAR(mean, d.mean(), 5.0 * se);
  EXPECT_NEAR(sd, d.truncated_sd(), 0.01 * d.truncated_sd());
  // Truncation at 2.5 sd narrows the spread a little, below the untruncated 0.1.
  EXPECT_LT(d.truncated_sd(), 0.1);
  EXPECT_GT(d.truncated_sd(), 0.09);
}

// Mode from a fit: ln(count) of equal-width bins in d is, for a log-normal, exactly quadratic in ln d
// (ln f = const + (mu / sigma^2 - 1) ln d - (ln d)^2 / (2 sigma^2)), so a least-squares fit of
// c0 + c1 ln d + c2 (ln d)^2, weighted by the counts (Var ln n_k ~ 1 / n_k for Poisson counts), gives the
// mode at ln d = -c1 / (2 c2) and, from the fit's covariance, its standard error.
struct ModeFit {
  double mode, se;  // se: standard error of ln(mode), i.e. relative
};

ModeFit fit_mode(const std::vector<double>& x, double lo, double hi, int bins) {
  std::vector<double> count(static_cast<std::size_t>(bins), 0.0);
  const double h = (hi - lo) / bins;
  for (double v : x) count[static_cast<std::size_t>(std::min(bins - 1, static_cast<int>((v - lo) / h)))] += 1.0;
  Eigen::Matrix3d a = Eigen::Matrix3d::Zero();
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  for (int k = 0; k < bins; ++k) {
    const double n = count[static_cast<std::size_t>(k)];
    if (n < 20) continue;  // too few for the Poisson-to-log variance approximation
    const double y = std::log(lo + (k + 0.5) * h);
    const Eigen::Vector3d row(1.0, y, y * y);
    a += n * row * row.transpose();
    b += n * std::log(n) * row;
  }
  const Eigen::Vector3d c = a.ldlt().solve(b);
  const Eigen::Matrix3d cov = a.inverse();
  const Eigen::Vector3d g(0.0, -1.0 / (2.0 * c(2)), c(1) / (2.0 * c(2) * c(2)));  // d ln(mode) / dc
  return {std::exp(-c(1) / (2.0 * c(2))), std::sqrt(g.dot(cov * g))};
}

TEST(LogNormalSampler, HistogramFitFindsTheMode) {
  // The paper's distribution: mode d0 = 90, sigma = 0.098; its truncated mean is 1.1% above the mode, so
  // the fit's standard error (about 1e-4 relative with 1e6 draws in 60 bins) must be far below that for the
  // test to tell the mode from the mean. 4 standard errors: a correct sampler fails 1 run in 16,000.
  {
    const auto d = TruncatedLogNormal::from_mode_and_sd(90.0, 0.2 * 45.0, 67.5, 112.5);
    const ModeFit f = fit_mode(d.sample(1000000, 3), 67.5, 112.5, 60);
    EXPECT_LT(f.se, 0.001);
    EXPECT_NEAR(std::log(f.mode / 90.0), 0.0, 4.0 * f.se) << "fitted mode " << f.mode;
    EXPECT_GT(std::log(d.mean() / 90.0), 5.0 * f.se);  // the mean is distinguishable from the mode
  }
  // A.4's wide distribution (d_s = 0.75 d0, d_l = 5 d0): the mode stays d0 while the mean is far above it.
  {
    const auto d = TruncatedLogNormal::from_mode_and_sd(1.0, 0.2 * 4.25, 0.75, 5.0);
    const ModeFit f = fit_mode(d.sample(1000000, 4), 0.75, 5.0, 100);
    EXPECT_LT(f.se, 0.005);
    EXPECT_NEAR(std::log(f.mode), 0.0, 4.0 * f.se) << "fitted mode " << f.mode;
    EXPECT_GT(d.mean(), 1.3);
  }
}

TEST(LogNormalSampler, ReproducibleForASeed) {
  const auto d = TruncatedLogNormal::from_mode_and_sd(1.0, 0.1, 0.75, 1.25);
  EXPECT_EQ(d.sample(1000, 42), d.sample(1000, 42));
  EXPECT_NE(d.sample(1000, 42), d.sample(1000, 43));
}

TEST(LogNormalSampler, RejectsBoundsThatCannotHoldTheMode) {
  auto make = [](double mode, double sd, double lo, double hi) {
    return [=] { TruncatedLogNormal::from_mode_and_sd(mode, sd, lo, hi, "sample"); };
  };
  EXPECT_NE(error_of(make(1.0, 0.1, 1.25, 1.25)).find("'sample.d_l' = 1.25"), std::string::npos);
  EXPECT_NE(error_of(make(1.0, 0.1, 1.2, 0.8)).find("'sample.d_l' = 0.8"), std::string::npos);
  EXPECT_NE(error_of(make(1.5, 0.1, 0.75, 1.25)).find("'sample.d0' = 1.5"), std::string::npos);
  EXPECT_NE(error_of(make(1.0, 0.1, 0.0, 1.25)).find("'sample.d_s' = 0"), std::string::npos);
  EXPECT_NE(error_of(make(1.0, -0.1, 0.75, 1.25)).find("'sample.sd' = -0.1"), std::string::npos);
  EXPECT_NE(error_of(make(1.0, NAN, 0.75, 1.25)).find("'sample.sd'"), std::string::npos);
}

// ---------------------------------------------------------------------------------------------------------
// Insertion and input checks.

// About 120 particles: d0 = 1.2 d_c (so s matters for the larger pairs), 5 x 5 x 3.5 d0.
AmorphousSpec small_spec() {
  AmorphousSpec s;
  s.d0 = 1.2;
  s.length = 5;
  s.width = 3.5;
  s.seed = 11;
  return s;
}

// The small sample, made once per process on one thread: at 120 particles the OpenMP barriers of a step
// cost more than its work, and on a loaded 2-core machine two threads made it 5 times slower.
struct MadeSample {
  AmorphousSpec spec = small_spec();
  AmorphousSample sample;
  long reports[3] = {0, 0, 0};  // progress reports per phase
};

const MadeSample& small_sample() {
  static const MadeSample made = [] {
    MadeSample m;
    const int before = exec::threads();
    exec::set_threads(1);
    m.sample = make_amorphous_sample(
        m.spec, [&](const AmorphousProgress& p) { ++m.reports[p.phase]; }, 1000);
    exec::set_threads(before);
    return m;
  }();
  return made;
}

TEST(AmorphousInsertion, ReachesTheVolumeFractionWithinHalfAParticle) {
  const AmorphousSpec spec = small_spec();
  const InsertedSpheres a = insert_random_spheres(spec);
  const Particles& p = a.particles;
  ASSERT_GT(p.size(), 100u);
  double volume = 0.0;
  const Vec3 len = spec.box_length();
  for (std::size_t i = 0; i < p.size(); ++i) {
    EXPECT_EQ(p.id[i], static_cast<std::int64_t>(i + 1));
    EXPECT_GE(2 * p.radius[i], spec.d_s_absolute());
    EXPECT_LE(2 * p.radius[i], spec.d_l_absolute());
    EXPECT_TRUE(p.x[i] >= 0 && p.x[i] < len.x && p.y[i] >= 0 && p.y[i] < len.y && p.z[i] >= 0 && p.z[i] < len.z);
    volume += 4.0 / 3.0 * std::numbers::pi * std::pow(p.radius[i], 3);
  }
  const double box = len.x * len.y * len.z;
  EXPECT_NEAR(a.volume_fraction, volume / box, 1e-14);
  const double half_largest = 0.5 * std::numbers::pi / 6.0 * std::pow(spec.d_l_absolute(), 3) / box;
  EXPECT_LE(std::abs(a.volume_fraction - 0.75), half_largest);
  // The same seed gives the same spheres; another seed other ones.
  const InsertedSpheres b = insert_random_spheres(spec);
  EXPECT_EQ(a.particles.x, b.particles.x);
  EXPECT_EQ(a.particles.radius, b.particles.radius);
  AmorphousSpec other = spec;
  other.seed = 12;
  EXPECT_NE(insert_random_spheres(other).particles.x, a.particles.x);
}

TEST(AmorphousSpec, BadInputsNameTheKeyAndTheValue) {
  auto check = [](const std::function<void(AmorphousSpec&)>& edit, const std::string& expected) {
    AmorphousSpec s = small_spec();
    edit(s);
    const std::string msg = error_of([&] { insert_random_spheres(s); });
    EXPECT_NE(msg.find(expected), std::string::npos) << msg;
  };
  // A volume fraction that cannot be reached.
  check([](AmorphousSpec& s) { s.volume_fraction = 1.2; }, "'sample.volume_fraction' = 1.2: cannot be reached");
  check([](AmorphousSpec& s) { s.volume_fraction = 1.0; }, "'sample.volume_fraction' = 1: cannot be reached");
  check([](AmorphousSpec& s) { s.volume_fraction = 0.0; }, "'sample.volume_fraction' = 0: cannot be reached");
  // A box too small: for the engine's neighbour list (2 (cutoff + skin) = 3.15 d0 here), let alone a particle.
  check([](AmorphousSpec& s) { s.width = 3.0; }, "'sample.width' = 3: the box is too small");
  check([](AmorphousSpec& s) { s.length = 0.5; }, "'sample.length' = 0.5: the box is too small");
  // d0 below d_min = 30 = 0.2 d_c (eq 19), and a smallest diameter below it.
  check([](AmorphousSpec& s) { s.d0 = 0.1; }, "'sample.d0' = 0.1: d0 = 15 is below d_min");
  check([](AmorphousSpec& s) { s.d0 = 0.25; }, "'sample.d_s' = 0.75: the smallest diameter");
  // Bounds that do not hold the mode.
  check([](AmorphousSpec& s) { s.d_l = 0.9; }, "'sample.d_l' = 0.9");
  check([](AmorphousSpec& s) { s.d_s = 1.1; }, "'sample.d_s' = 1.1");
  check([](AmorphousSpec& s) { s.d_l_fixed = 1.0; }, "'sample.d_l_fixed' = 1");
  check([](AmorphousSpec& s) { s.phase2_damping = 0.0; }, "'relaxation.phase2.damping' = 0");
  check([](AmorphousSpec& s) { s.stress_threshold = -1.0; }, "'relaxation.phase2.stress_threshold' = -1");
}

// ---------------------------------------------------------------------------------------------------------
// The relaxation.

TEST(AmorphousRelaxation, Phase2EndsBelowTheThresholdWithTheBoxMoved) {
  const MadeSample& made = small_sample();
  const AmorphousSpec& spec = made.spec;
  const AmorphousSample& s = made.sample;
  const long* reports = made.reports;
  EXPECT_EQ(s.phase1_steps, 3000);
  EXPECT_GT(reports[1], 2);
  EXPECT_GT(reports[2], 2);
  EXPECT_GT(s.phase2_steps, 0);
  EXPECT_LT(s.phase2_steps, spec.phase2_max_steps);
  const double E = spec.material.youngs_modulus;
  for (double v : {s.final_stress.xx, s.final_stress.yy, s.final_stress.zz}) EXPECT_LT(std::abs(v), 1e-14 * E);
  EXPECT_LT(s.final_max_stress, 1e-14);
  // Phase 1 removed the deep overlaps of the insertion (deeper than d_s there; below d_s / 2 after it).
  EXPECT_LT(s.phase1_max_overlap, 0.5);
  // The box moved: adhesion pulls the inserted packing together, here by about 1% on every axis.
  for (double r : {s.final_box_length.x / s.initial_box_length.x, s.final_box_length.y / s.initial_box_length.y,
                   s.final_box_length.z / s.initial_box_length.z})
    EXPECT_GT(std::abs(r - 1.0), 1e-3);
  EXPECT_NEAR(s.relaxed_fraction * s.box.volume(),
              s.inserted_fraction * s.initial_box_length.x * s.initial_box_length.y * s.initial_box_length.z,
              1e-9 * s.box.volume());

  // Independently of the relaxation's own bookkeeping: the saved state (at rest, phase 2's force law) has
  // every normal stress below the threshold.
  DemSettings set;
  set.material = spec.material;
  set.options = CohesiveOptions{1, 0};
  set.masses_from_density = false;
  DemSimulation sim(s.box, s.particles, Groups{}, set);
  const StressTensor t = sim.virial_stress(nullptr, s.box.volume());
  for (double v : {t.xx, t.yy, t.zz}) EXPECT_LT(std::abs(v), 1e-14 * E);
}

TEST(AmorphousRelaxation, MassesGiveTheTargetDensity) {
  const AmorphousSample& s = small_sample().sample;
  // The sample's own masses: rho = 1 (Table 4) over the whole box, one density rho / (volume fraction)
  // for every particle, solid-sphere inertia.
  auto check = [&](const Particles& p, double rho) {
    double mass = 0.0;
    for (std::size_t i = 0; i < p.size(); ++i) {
      mass += p.mass[i];
      const double v = 4.0 / 3.0 * std::numbers::pi * std::pow(p.radius[i], 3);
      EXPECT_NEAR(p.mass[i] / v, rho / s.relaxed_fraction, 1e-12 * rho / s.relaxed_fraction);
      EXPECT_NEAR(p.inertia[i], 0.4 * p.mass[i] * p.radius[i] * p.radius[i], 1e-12 * p.inertia[i]);
    }
    EXPECT_NEAR(mass / s.box.volume(), rho, 1e-12 * rho);
  };
  check(s.particles, 1.0);
  EXPECT_NEAR(s.mass_scale, 1.0 / s.relaxed_fraction, 1e-12);
  // Another target density, on a copy.
  Particles p = s.particles;
  EXPECT_NEAR(rescale_masses_to_density(p, s.box, 2.5), 2.5, 1e-12);
  check(p, 2.5);
}

TEST(AmorphousRelaxation, SavedSampleReadsBack) {
  const AmorphousSpec& spec = small_sample().spec;
  const AmorphousSample& s = small_sample().sample;
  const std::string dir = ::testing::TempDir() + "/debris_amorphous_test";
  std::filesystem::create_directories(dir);
  const std::string stem = dir + "/sample";
  write_amorphous_sample(stem, s, spec, "sample: {d0: 1.2}\n");

  const LammpsData data = read_lammps_data(stem + ".data", {true, true, true});
  const Particles& a = s.particles;
  const Particles& b = data.particles;
  ASSERT_EQ(b.size(), a.size());
  EXPECT_EQ(data.box.lo().x, s.box.lo().x);
  EXPECT_EQ(data.box.hi().x, s.box.hi().x);
  EXPECT_EQ(data.box.hi().y, s.box.hi().y);
  EXPECT_EQ(data.box.hi().z, s.box.hi().z);
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(b.id[i], a.id[i]);
    EXPECT_EQ(b.x[i], a.x[i]);
    EXPECT_EQ(b.y[i], a.y[i]);
    EXPECT_EQ(b.z[i], a.z[i]);
    EXPECT_EQ(b.radius[i], a.radius[i]);
    EXPECT_NEAR(b.mass[i], a.mass[i], 1e-15 * a.mass[i]);  // via density = m / volume in the file
  }

  const AmorphousSampleFile f = read_amorphous_sample(stem + ".h5");
  ASSERT_EQ(f.particles.size(), a.size());
  EXPECT_EQ(f.particles.x, a.x);
  EXPECT_EQ(f.particles.z, a.z);
  EXPECT_EQ(f.particles.radius, a.radius);
  EXPECT_EQ(f.particles.mass, a.mass);
  EXPECT_EQ(f.particles.id, a.id);
  EXPECT_EQ(f.box.hi().y, s.box.hi().y);
  EXPECT_EQ(f.relaxed_fraction, s.relaxed_fraction);
  EXPECT_EQ(f.d0, spec.d0_absolute());
  EXPECT_EQ(f.input_echo, "sample: {d0: 1.2}\n");
}

TEST(AmorphousRelaxation, ThresholdNotMetWithinTheLimitIsAClearError) {
  AmorphousSpec spec = small_spec();
  spec.phase1_steps = 300;
  spec.phase2_max_steps = 400;  // the small sample needs over 10,000
  const std::string msg = error_of([&] { make_amorphous_sample(spec); });
  EXPECT_NE(msg.find("'relaxation.phase2.max_steps' = 400"), std::string::npos) << msg;
  EXPECT_NE(msg.find("did not all fall below the threshold 1e-14 E within 400 steps"), std::string::npos) << msg;
  EXPECT_NE(msg.find("largest component counted was"), std::string::npos) << msg;
}

}  // namespace
}  // namespace debris
