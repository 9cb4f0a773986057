// Rough surfaces (core/rough): the self-affine generator, its input keys, the measured-map reader and the
// spectra, each held to something the code does not compute: rms values of sums of sines in closed form,
// Parseval, the Hurst exponent the surface was made with, the bits a seed gives, and the errors' words.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <numbers>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "core/error.hpp"
#include "core/io/input.hpp"
#include "core/io/key_reference.hpp"
#include "core/rough/height_map_file.hpp"
#include "core/rough/self_affine_input.hpp"
#include "core/rough/self_affine_surface.hpp"
#include "core/rough/surface_spectrum.hpp"

namespace debris {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

constexpr double kPi = std::numbers::pi;
constexpr double nm = 1e-9;

// The two surfaces the exponent tests use, both with the roll-off at k = 4 and the cut-off at four grid
// spacings: a 256 x 256 field over 256 nm, and a profile of 4096 points over 4096 nm.
SelfAffineSpec spec_of(double hurst, double rolloff, std::uint64_t seed) {
  SelfAffineSpec s;
  s.hurst = hurst;
  s.rms_height = 1 * nm;
  s.rolloff_wavelength = rolloff;
  s.cutoff_wavelength = 4 * nm;
  s.seed = seed;
  return s;
}

HeightField surface_2d(double hurst, std::uint64_t seed) {
  return generate_self_affine(spec_of(hurst, 64 * nm, seed), 1, -100 * nm, 30 * nm, 256 * nm, 256 * nm, 256, 256);
}

HeightField profile(double hurst, std::uint64_t seed) {
  return generate_self_affine(spec_of(hurst, 1024 * nm, seed), 1, 0, 0, 4096 * nm, 5 * nm, 4096, 1);
}

bool all_finite(const std::vector<double>& v) {
  for (double x : v)
    if (!std::isfinite(x)) return false;
  return true;
}

template <class F>
std::string message_of(F&& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "(nothing thrown)";
}

// ---- the generator ----------------------------------------------------------------------------------------

TEST(RoughSurface, RmsHeightIsExactAndMeanZero) {
  for (const HeightField& f : {surface_2d(0.8, 3), profile(0.8, 3)}) {
    EXPECT_NEAR(f.rms_height(), 1 * nm, 1e-12 * nm);
    EXPECT_NEAR(f.mean(), 0, 1e-12 * nm);
    EXPECT_EQ(f.h.size(), static_cast<std::size_t>(f.n_a) * f.n_b);
  }
}

TEST(RoughSurface, RmsSlopeGivenIsReachedExactly) {
  SelfAffineSpec s = spec_of(0.5, 64 * nm, 9);
  s.rms_height = 0;
  s.rms_slope = 0.2;
  const HeightField f = generate_self_affine(s, 1, 0, 0, 256 * nm, 128 * nm, 256, 128);
  EXPECT_NEAR(spectral_rms_slope(f), 0.2, 1e-12 * 0.2);
  // The central differences see the same slope, less the short waves' part (sin(k d) / (k d) < 1).
  EXPECT_LT(f.rms_slope(), 0.2);
  EXPECT_GT(f.rms_slope(), 0.1);
}

// The field tiles the box: read across the seam, the bilinear height at a = origin + length is the one at
// the origin, and the step between the last and the first grid row is like any step between neighbours (a
// field that were not periodic would jump there by about its rms height).
TEST(RoughSurface, EdgesMeetAcrossThePeriodicSeam) {
  for (const HeightField& f : {surface_2d(0.3, 5), profile(0.3, 5)}) {
    for (double b : {0.0, 0.37, 0.5, 0.81}) {
      const double bb = f.origin_b + b * f.length_b;
      EXPECT_NEAR(f.height(f.origin_a, bb), f.height(f.origin_a + f.length_a, bb), 1e-12 * nm);
      EXPECT_NEAR(f.height(f.origin_a - 0.25 * f.spacing_a(), bb),
                  f.height(f.origin_a + f.length_a - 0.25 * f.spacing_a(), bb), 1e-12 * nm);
    }
    double seam = 0, inside = 0;
    for (int j = 0; j < f.n_b; ++j) {
      seam += std::pow(f.at(0, j) - f.at(f.n_a - 1, j), 2);
      for (int i = 0; i + 1 < f.n_a; ++i) inside += std::pow(f.at(i + 1, j) - f.at(i, j), 2);
    }
    const double ratio = std::sqrt(seam / f.n_b) / std::sqrt(inside / (f.n_b * (f.n_a - 1.0)));
    std::printf("[ measured ] seam step / neighbour step (rms) = %.3f (n_b = %d)\n", ratio, f.n_b);
    if (f.n_b > 1) {  // 256 steps across the seam: their rms within 25% of the neighbours'
      EXPECT_GT(ratio, 0.75);
      EXPECT_LT(ratio, 1.25);
    } else {  // one step: within a few neighbour steps (a jump of the rms height would be about 20 of them)
      EXPECT_LT(ratio, 4.0);
    }
    if (f.n_b > 1)  // and along b likewise
      for (double a : {0.0, 0.44}) {
        const double aa = f.origin_a + a * f.length_a;
        EXPECT_NEAR(f.height(aa, f.origin_b), f.height(aa, f.origin_b + f.length_b), 1e-12 * nm);
      }
  }
}

TEST(RoughSurface, SameSeedSameBitsOtherSeedOtherField) {
  const HeightField a = surface_2d(0.8, 11), b = surface_2d(0.8, 11), c = surface_2d(0.8, 12);
  EXPECT_EQ(a.h, b.h);  // bit for bit
  double dot = 0;
  for (std::size_t k = 0; k < a.h.size(); ++k) dot += a.h[k] * c.h[k];
  const double correlation = dot / a.h.size() / (1 * nm * 1 * nm);
  std::printf("[ measured ] correlation of seeds 11 and 12: %.3f\n", correlation);
  EXPECT_NE(a.h, c.h);
  EXPECT_LT(std::abs(correlation), 0.5);
  EXPECT_EQ(profile(0.5, 4).h, profile(0.5, 4).h);
  EXPECT_NE(profile(0.5, 4).h, profile(0.5, 5).h);
}

// FFTW's planner is not thread-safe: fields made at once on several threads are the ones made one by one.
TEST(RoughSurface, SeveralThreadsGetTheSameFields) {
  std::vector<HeightField> serial, parallel(4);
  for (int t = 0; t < 4; ++t) serial.push_back(t % 2 ? profile(0.5, 20 + t) : surface_2d(0.5, 20 + t));
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t)
    threads.emplace_back([&, t] { parallel[t] = t % 2 ? profile(0.5, 20 + t) : surface_2d(0.5, 20 + t); });
  for (std::thread& th : threads) th.join();
  for (int t = 0; t < 4; ++t) EXPECT_EQ(serial[t].h, parallel[t].h) << "thread " << t;
}

// The exponent the surface was made with, fitted between q_r and q_s, mean over seeds: 2D (slope -2(1 + H))
// and profile (slope -(1 + 2H)), so a mix-up of the two exponents fails by 0.5 in H.
TEST(RoughSurface, HurstRecoveredFromThePsd2D) {
  for (double hurst : {0.3, 0.5, 0.8}) {
    double sum = 0, error = 0;
    const int seeds = 4;
    for (int seed = 1; seed <= seeds; ++seed) {
      const HurstFit fit = fit_hurst_from_psd(power_spectrum(surface_2d(hurst, seed)), 2 * kPi / (64 * nm),
                                              2 * kPi / (4 * nm));
      ASSERT_TRUE(fit.defined);
      EXPECT_EQ(fit.points, 61);  // the integer |k| bins 4 ... 64
      sum += fit.hurst;
      error += fit.error;
    }
    std::printf("[ measured ] 2D 256^2, H = %.1f: fitted %.4f (fit error %.4f, %d seeds)\n", hurst, sum / seeds,
                error / seeds, seeds);
    EXPECT_NEAR(sum / seeds, hurst, 0.05);
  }
}

TEST(RoughSurface, HurstRecoveredFromThePsdProfile) {
  for (double hurst : {0.3, 0.5, 0.8}) {
    double sum = 0, error = 0;
    const int seeds = 8;
    for (int seed = 1; seed <= seeds; ++seed) {
      const HurstFit fit = fit_hurst_from_psd(power_spectrum(profile(hurst, seed)), 2 * kPi / (1024 * nm),
                                              2 * kPi / (4 * nm));
      ASSERT_TRUE(fit.defined);
      EXPECT_EQ(fit.points, 1021);  // k = 4 ... 1024
      sum += fit.hurst;
      error += fit.error;
    }
    std::printf("[ measured ] profile 4096, H = %.1f: fitted %.4f (fit error %.4f, %d seeds)\n", hurst,
                sum / seeds, error / seeds, seeds);
    EXPECT_NEAR(sum / seeds, hurst, 0.05);
  }
}

TEST(RoughSurface, BadParametersThrowNamingThemselves) {
  const auto gen = [](SelfAffineSpec s, int n_a = 256, int n_b = 256) {
    return message_of([&] { generate_self_affine(s, 1, 0, 0, 256 * nm, 256 * nm, n_a, n_b); });
  };
  SelfAffineSpec s = spec_of(1.2, 64 * nm, 1);
  EXPECT_THAT(gen(s), AllOf(HasSubstr("hurst = 1.2"), HasSubstr("(0, 1)")));
  s.hurst = 0;
  EXPECT_THAT(gen(s), HasSubstr("hurst = 0:"));
  s = spec_of(0.5, 64 * nm, 1);
  s.rms_height = -1 * nm;
  EXPECT_THAT(gen(s), AllOf(HasSubstr("rms_height = -1e-09"), HasSubstr("> 0")));
  s.rms_height = 0;
  EXPECT_THAT(gen(s), AllOf(HasSubstr("rms_height = 0"), HasSubstr("rms_slope = 0")));
  s.rms_height = 1 * nm;
  s.rms_slope = 0.1;
  EXPECT_THAT(gen(s), AllOf(HasSubstr("rms_height = 1e-09"), HasSubstr("not both"), HasSubstr("rms_slope = 0.1")));
  s = spec_of(0.5, 64 * nm, 1);
  s.cutoff_wavelength = 64 * nm;  // q_s = q_r
  EXPECT_THAT(gen(s), AllOf(HasSubstr("cutoff_wavelength = 6.4e-08"), HasSubstr("q_s > q_r")));
  s.cutoff_wavelength = 300 * nm;
  s.rolloff_wavelength = 0;  // the box's 256 nm
  EXPECT_THAT(gen(s), AllOf(HasSubstr("cutoff_wavelength = 3e-07"), HasSubstr("2.56e-07")));
  s = spec_of(0.5, 64 * nm, 1);
  s.cutoff_wavelength = 3 * nm;  // spacing 2 nm > 1.5 nm
  EXPECT_THAT(gen(s, 128, 256), AllOf(HasSubstr("grid spacing along a = 2e-09"), HasSubstr("1.5e-09")));
  EXPECT_THAT(gen(s, 256, 128), AllOf(HasSubstr("grid spacing along b = 2e-09"), HasSubstr("n_b >= 171")));
  s.cutoff_wavelength = 4 * nm;
  s.largest_wavelength = 32 * nm;
  EXPECT_THAT(gen(s), AllOf(HasSubstr("largest_wavelength = 3.2e-08"), HasSubstr("6.4e-08")));
  EXPECT_EQ(gen(spec_of(0.5, 64 * nm, 1)), "(nothing thrown)");
  EXPECT_THROW(generate_self_affine(spec_of(2, 64 * nm, 1), 1, 0, 0, 1, 1, 8, 8), std::invalid_argument);
}

// ---- its input keys ---------------------------------------------------------------------------------------

KeyReference surface_reference() {
  KeyReference r("test");
  r.key("surface").is(KeyKind::section).follows("self_affine").means("a rough face");
  document_self_affine(r, "self_affine");
  return r;
}

TEST(RoughSurface, InputKeysReadWithUnitsAndMatchTheirDescription) {
  const InputNode root = InputNode::load_string(
      "surface: {hurst: 0.3, rms_height: 2 nm, rolloff_wavelength: 64 nm, cutoff_wavelength: 4 nm,\n"
      "          largest_wavelength: 0.128 um, seed: 7}\n");
  const SelfAffineSpec s = read_self_affine_spec(root.child("surface"));
  EXPECT_DOUBLE_EQ(s.hurst, 0.3);
  EXPECT_DOUBLE_EQ(s.rms_height, 2e-9);
  EXPECT_EQ(s.rms_slope, 0);
  EXPECT_DOUBLE_EQ(s.rolloff_wavelength, 64e-9);
  EXPECT_DOUBLE_EQ(s.cutoff_wavelength, 4e-9);
  EXPECT_DOUBLE_EQ(s.largest_wavelength, 128e-9);
  EXPECT_EQ(s.seed, 7u);
  EXPECT_NO_THROW(root.reject_unknown_keys());
  EXPECT_TRUE(key_audit_findings(root, surface_reference()).empty());

  const InputNode slope = InputNode::load_string("surface: {rms_slope: 0.1, cutoff_wavelength: 4 nm}\n");
  const SelfAffineSpec d = read_self_affine_spec(slope.child("surface"));
  EXPECT_EQ(d.hurst, 0.8);  // the defaults
  EXPECT_EQ(d.rms_slope, 0.1);
  EXPECT_EQ(d.rolloff_wavelength, 0);
  EXPECT_EQ(d.largest_wavelength, 0);
  EXPECT_EQ(d.seed, 1u);
  const std::vector<std::string> findings = key_audit_findings(slope, surface_reference());
  EXPECT_TRUE(findings.empty()) << (findings.empty() ? "" : findings.front());
}

TEST(RoughSurface, InputErrorsNameTheKeyAndValue) {
  const auto read = [](const std::string& yaml) {
    return message_of([&] {
      const InputNode root = InputNode::load_string(yaml);
      (void)read_self_affine_spec(root.child("surface"));
      root.reject_unknown_keys();
    });
  };
  EXPECT_THAT(read("surface: {hurst: 1.5, rms_height: 1 nm, cutoff_wavelength: 4 nm}"),
              AllOf(HasSubstr("input error"), HasSubstr("'surface.hurst' = 1.5"), HasSubstr("(0, 1)")));
  EXPECT_THAT(read("surface: {hurst: 0, rms_height: 1 nm, cutoff_wavelength: 4 nm}"),
              HasSubstr("'surface.hurst' = 0"));
  EXPECT_THAT(read("surface: {rms_height: -2 nm, cutoff_wavelength: 4 nm}"),
              AllOf(HasSubstr("'surface.rms_height' = -2e-09 m"), HasSubstr("> 0")));
  EXPECT_THAT(read("surface: {rms_height: 2 GPa, cutoff_wavelength: 4 nm}"),
              AllOf(HasSubstr("surface.rms_height"), HasSubstr("2 GPa")));
  EXPECT_THAT(read("surface: {rms_height: 1 nm, rms_slope: 0.1, cutoff_wavelength: 4 nm}"),
              AllOf(HasSubstr("'surface.rms_height'"), HasSubstr("rms_slope"), HasSubstr("not both")));
  EXPECT_THAT(read("surface: {cutoff_wavelength: 4 nm}"),
              AllOf(HasSubstr("'surface.rms_height' = missing"), HasSubstr("rms_slope")));
  EXPECT_THAT(read("surface: {rms_slope: 0, cutoff_wavelength: 4 nm}"), HasSubstr("'surface.rms_slope' = 0"));
  EXPECT_THAT(read("surface: {rms_height: 1 nm}"), AllOf(HasSubstr("surface"), HasSubstr("cutoff_wavelength")));
  EXPECT_THAT(read("surface: {rms_height: 1 nm, cutoff_wavelength: 64 nm, rolloff_wavelength: 32 nm}"),
              AllOf(HasSubstr("'surface.cutoff_wavelength' = 6.4e-08 m"), HasSubstr("rolloff_wavelength = 3.2e-08 m")));
  EXPECT_THAT(read("surface: {rms_height: 1 nm, cutoff_wavelength: -4 nm}"),
              HasSubstr("'surface.cutoff_wavelength' = -4e-09 m"));
  EXPECT_THAT(read("surface: {rms_height: 1 nm, cutoff_wavelength: 4 nm, rolloff_wavelength: 64 nm, "
                   "largest_wavelength: 32 nm}"),
              AllOf(HasSubstr("'surface.largest_wavelength' = 3.2e-08 m"), HasSubstr("rolloff_wavelength")));
  EXPECT_THAT(read("surface: {rms_height: 1 nm, cutoff_wavelength: 4 nm, seed: -3}"),
              HasSubstr("'surface.seed' = -3"));
  EXPECT_THAT(read("surface: {rms_height: 1 nm, cutoff_wavelength: 4 nm, seed: 1.5}"), HasSubstr("surface.seed"));
  EXPECT_THAT(read("surface: {rms_height: 1 nm, cutoff_wavelength: 4 nm, hurst_exponent: 0.5}"),
              AllOf(HasSubstr("surface.hurst_exponent"), HasSubstr("unknown key")));
  EXPECT_THAT(read("surface: [1, 2]"), AllOf(HasSubstr("'surface'"), HasSubstr("a map")));
  EXPECT_THROW((void)read_self_affine_spec(InputNode::load_string("surface: {hurst: 2}").child("surface")),
               InputError);
}

// ---- the measured-map reader ------------------------------------------------------------------------------

std::string write_file(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + "/debris_height_map_" + name;
  std::ofstream(path) << text;
  return path;
}

TEST(HeightMap, GoodFileRoundTripsWithSpacing) {
  // Comments, blank lines, tabs, commas, a '+', a carriage return: an AFM export's habits.
  const std::string path = write_file("good.txt",
                                      "# exported heights in nm\n"
                                      "1.5 -2\t0.25, 4\n"
                                      "\n"
                                      "  0 +3e-1 -1.25e1 7   # row 2\r\n"
                                      "2,2,2,2\n");
  const HeightField f = read_height_map(path, 2, 2 * nm, 3 * nm, nm);
  EXPECT_EQ(f.normal_axis, 2);
  EXPECT_EQ(f.n_a, 3);
  EXPECT_EQ(f.n_b, 4);
  EXPECT_DOUBLE_EQ(f.length_a, 6 * nm);
  EXPECT_DOUBLE_EQ(f.length_b, 12 * nm);
  EXPECT_DOUBLE_EQ(f.spacing_a(), 2 * nm);
  EXPECT_DOUBLE_EQ(f.spacing_b(), 3 * nm);
  const std::vector<double> want{1.5, -2, 0.25, 4, 0, 0.3, -12.5, 7, 2, 2, 2, 2};
  ASSERT_EQ(f.h.size(), want.size());
  for (std::size_t k = 0; k < want.size(); ++k) EXPECT_DOUBLE_EQ(f.h[k], want[k] * nm) << k;
  EXPECT_DOUBLE_EQ(f.at(1, 2), -12.5 * nm);
  EXPECT_DOUBLE_EQ(f.height(f.length_a, 0), 1.5 * nm);  // periodic
  // A generated field written out at full precision reads back with its spectrum.
  const HeightField g = surface_2d(0.5, 2);
  std::string text;
  char buf[40];
  for (int i = 0; i < g.n_a; ++i) {
    for (int j = 0; j < g.n_b; ++j) {
      std::snprintf(buf, sizeof buf, "%.17g ", g.at(i, j) / nm);
      text += buf;
    }
    text += "\n";
  }
  const HeightField r = read_height_map(write_file("generated.txt", text), 1, g.spacing_a(), g.spacing_b(), nm);
  EXPECT_EQ(r.n_a, g.n_a);
  EXPECT_EQ(r.n_b, g.n_b);
  EXPECT_NEAR(r.rms_height(), g.rms_height(), 1e-12 * nm);
  EXPECT_NEAR(spectral_rms_slope(r), spectral_rms_slope(g), 1e-12 * spectral_rms_slope(g));
  // One column: a profile along a.
  const HeightField p = read_height_map(write_file("profile.txt", "1\n2\n3\n4\n"), 1, 0.5e-6, 0, 1e-6);
  EXPECT_EQ(p.n_a, 4);
  EXPECT_EQ(p.n_b, 1);
  EXPECT_DOUBLE_EQ(p.length_a, 2e-6);
  EXPECT_DOUBLE_EQ(p.height(0.25e-6, 0), 1.5e-6);
}

TEST(HeightMap, BadValuesNameTheFileLineAndValue) {
  const auto read = [](const std::string& name, const std::string& text) {
    const std::string path = write_file(name, text);
    return message_of([&] { read_height_map(path, 1, nm, nm, nm); });
  };
  EXPECT_THAT(read("ragged.txt", "1 2 3\n4 5 6\n# fine\n7 8\n"),
              AllOf(HasSubstr("debris_height_map_ragged.txt"), HasSubstr("line 4"), HasSubstr("2 values"),
                    HasSubstr("line 1) has 3")));
  EXPECT_THAT(read("abc.txt", "1 2\nabc 3\n"),
              AllOf(HasSubstr("debris_height_map_abc.txt"), HasSubstr("line 2"), HasSubstr("'abc'")));
  EXPECT_THAT(read("nan.txt", "1 2\n3 4\n5 nan\n"), AllOf(HasSubstr("line 3"), HasSubstr("'nan'")));
  EXPECT_THAT(read("inf.txt", "-inf 2\n"), AllOf(HasSubstr("line 1"), HasSubstr("'-inf'")));
  EXPECT_THAT(read("glued.txt", "1 2\n3 4e\n"), AllOf(HasSubstr("line 2"), HasSubstr("'4e'")));
  EXPECT_THAT(read("empty.txt", ""), AllOf(HasSubstr("debris_height_map_empty.txt"), HasSubstr("no heights")));
  EXPECT_THAT(read("comments.txt", "# only a comment\n\n"), HasSubstr("no heights"));
  const std::string missing = ::testing::TempDir() + "/debris_height_map_missing.txt";
  std::remove(missing.c_str());
  EXPECT_THAT(message_of([&] { read_height_map(missing, 1, nm, nm, nm); }),
              AllOf(HasSubstr("debris_height_map_missing.txt"), HasSubstr("cannot be opened")));
  EXPECT_THROW(read_height_map(missing, 1, nm, nm, nm), InputError);
  EXPECT_THAT(message_of([&] { read_height_map(::testing::TempDir(), 1, nm, nm, nm); }), HasSubstr("directory"));
}

// ---- the spectra --------------------------------------------------------------------------------------------

// A sum of sines, each a whole number of periods over the box: its rms height is sqrt(sum A^2 / 2), its rms
// slope sqrt(sum (A |k|)^2 / 2), its PSD holds A^2 / 2 times the area in the bin of each |k| (Parseval), and
// the central differences see each sine's gradient reduced to sin(k d) / d.
struct Sine {
  int n_a, n_b;  // periods over the box along a and b
  double amplitude, phase;
};

HeightField sines(const std::vector<Sine>& waves, int n_a, int n_b, double length_a, double length_b) {
  HeightField f;
  f.n_a = n_a;
  f.n_b = n_b;
  f.length_a = length_a;
  f.length_b = length_b;
  f.origin_a = 0.3;
  for (int i = 0; i < n_a; ++i)
    for (int j = 0; j < n_b; ++j) {
      double h = 0.125;  // an offset: the mean is not part of the roughness
      for (const Sine& w : waves)
        h += w.amplitude * std::sin(2 * kPi * (w.n_a * i / double(n_a) + w.n_b * j / double(n_b)) + w.phase);
      f.h.push_back(h);
    }
  return f;
}

void expect_sines(const std::vector<Sine>& waves, const HeightField& f) {
  double h2 = 0, s2 = 0, cd2 = 0;
  const double da = f.spacing_a(), db = f.n_b > 1 ? f.spacing_b() : 1;
  for (const Sine& w : waves) {
    const double ka = 2 * kPi * w.n_a / f.length_a, kb = f.n_b > 1 ? 2 * kPi * w.n_b / f.length_b : 0;
    h2 += w.amplitude * w.amplitude / 2;
    s2 += w.amplitude * w.amplitude * (ka * ka + kb * kb) / 2;
    cd2 += w.amplitude * w.amplitude / 2 * (std::pow(std::sin(ka * da) / da, 2) + std::pow(std::sin(kb * db) / db, 2));
  }
  EXPECT_NEAR(f.rms_height(), std::sqrt(h2), 1e-12 * std::sqrt(h2));
  EXPECT_NEAR(spectral_rms_slope(f), std::sqrt(s2), 1e-12 * std::sqrt(s2));
  EXPECT_NEAR(f.rms_slope(), std::sqrt(cd2), 1e-12 * std::sqrt(cd2));  // central differences
  const SurfaceSpectrum s = power_spectrum(f);
  const double area = f.n_b > 1 ? f.length_a * f.length_b : f.length_a;
  EXPECT_DOUBLE_EQ(s.area, area);
  double total = 0;
  long modes = 0;
  for (std::size_t k = 0; k < s.q.size(); ++k) total += s.modes[k] * s.c[k], modes += s.modes[k];
  EXPECT_NEAR(total, area * h2, 1e-12 * area * h2);  // Parseval
  EXPECT_EQ(modes, static_cast<long>(f.n_a) * f.n_b - 1);  // every k but 0, once
  // Each sine's power in the bin of its |k| (the sines are chosen with their |k| in different bins).
  const double dq = 2 * kPi / std::max(f.length_a, f.n_b > 1 ? f.length_b : 0.0);
  for (const Sine& w : waves) {
    const double q = std::hypot(2 * kPi * w.n_a / f.length_a, f.n_b > 1 ? 2 * kPi * w.n_b / f.length_b : 0);
    bool found = false;
    for (std::size_t k = 0; k < s.q.size(); ++k)
      if (std::lround(s.q[k] / dq) == std::lround(q / dq)) {
        found = true;
        EXPECT_NEAR(s.modes[k] * s.c[k], area * w.amplitude * w.amplitude / 2, 1e-12 * area * h2);
      }
    EXPECT_TRUE(found) << "no bin at q = " << q;
  }
}

TEST(SurfaceSpectrum, SinesHaveExactRmsHeightSlopeAndParseval) {
  // 2D over a box that is not square (64 x 48 points, 3.2 x 2.4): |k| / dq of the sines 1, 4.0, 7.3, 9.3.
  const std::vector<Sine> waves{{1, 0, 0.7, 0.1}, {3, 2, 0.2, 1.0}, {5, -4, 0.05, 2.0}, {0, 7, 0.1, -0.5}};
  expect_sines(waves, sines(waves, 64, 48, 3.2, 2.4));
  // A profile: one point per wave number.
  const std::vector<Sine> line{{1, 0, 1.0, 0.3}, {7, 0, 0.3, 0.0}, {30, 0, 0.02, 1.2}};
  expect_sines(line, sines(line, 200, 1, 10.0, 0.0));
  // Logarithmic bins keep Parseval too.
  const HeightField f = sines(waves, 64, 48, 3.2, 2.4);
  const SurfaceSpectrum s = power_spectrum(f, SpectrumBins::logarithmic, 5);
  double total = 0;
  for (std::size_t k = 0; k < s.q.size(); ++k) total += s.modes[k] * s.c[k];
  EXPECT_NEAR(total / s.area, f.rms_height() * f.rms_height(), 1e-12 * f.rms_height() * f.rms_height());
  EXPECT_LT(s.q.size(), 15u);
}

TEST(SurfaceSpectrum, ParsevalHoldsForAGeneratedField) {
  for (const HeightField& f : {surface_2d(0.5, 7), profile(0.5, 7)}) {
    const SurfaceSpectrum s = power_spectrum(f);
    double total = 0;
    for (std::size_t k = 0; k < s.q.size(); ++k) total += s.modes[k] * s.c[k];
    EXPECT_NEAR(total, s.area * 1 * nm * 1 * nm, 1e-12 * s.area * nm * nm);
  }
}

TEST(SurfaceSpectrum, FlatFieldHasNoExponentAndNoNaN) {
  for (const auto& [n_a, n_b] : {std::pair{32, 16}, std::pair{64, 1}}) {
    HeightField f;
    f.n_a = n_a;
    f.n_b = n_b;
    f.length_a = 1;
    f.length_b = n_b > 1 ? 0.5 : 0.0;
    f.h.assign(static_cast<std::size_t>(n_a) * n_b, 3.0);
    EXPECT_EQ(f.rms_height(), 0);
    EXPECT_EQ(f.rms_slope(), 0);
    EXPECT_EQ(spectral_rms_slope(f), 0);
    const SurfaceSpectrum s = power_spectrum(f);
    EXPECT_EQ(s.variance, 0);
    EXPECT_TRUE(all_finite(s.q) && all_finite(s.c));
    for (double c : s.c) EXPECT_EQ(c, 0);
    const HurstFit psd = fit_hurst_from_psd(s, 0, 1e9);
    EXPECT_FALSE(psd.defined);
    EXPECT_EQ(psd.hurst, 0);
    EXPECT_EQ(psd.error, 0);
    const HeightCorrelation c = height_height_correlation(f);
    EXPECT_TRUE(all_finite(c.value));
    const HurstFit hh = fit_hurst_from_hhcf(c, 0, 1e9);
    EXPECT_FALSE(hh.defined);
    EXPECT_TRUE(std::isfinite(hh.hurst) && std::isfinite(hh.error));
  }
  // One sine has power in one bin only: fewer than 3 points, no exponent.
  const HeightField one = sines({{2, 1, 1.0, 0.0}}, 32, 32, 1, 1);
  const HurstFit fit = fit_hurst_from_psd(power_spectrum(one), 0, 1e9);
  EXPECT_FALSE(fit.defined);
  EXPECT_EQ(fit.points, 1);
}

// The height-height correlation grows as r^2H between the cut-off and the roll-off wavelengths; the band's
// limits bend it (as r^2 below the cut-off, flat towards the roll-off), and for H near 1 the roll-off's pull
// fades only as (r / lambda_r)^(2 - 2H), so the fit sits below H there. Surfaces with the widest band their
// grid allows (roll-off at the box, cut-off at two spacings), fitted over r = 2 to 16-32 cut-offs: 8
// profiles of 4096 points (r = 4 ... 64 nm) and 4 fields of 512^2 along a and b (r = 4 ... 32 nm).
// Tolerance 0.1 in H (measured 2026-12: profile 0.318 / 0.499 / 0.762, 2D 0.332 / 0.492 / 0.723).
TEST(SurfaceSpectrum, HhcfSlopeRecoversTwiceHurst) {
  for (double hurst : {0.3, 0.5, 0.8}) {
    SelfAffineSpec s = spec_of(hurst, 0, 1);
    s.cutoff_wavelength = 2 * nm;
    double sum = 0;
    for (int seed = 1; seed <= 8; ++seed) {
      s.seed = seed;
      const HeightField f = generate_self_affine(s, 1, 0, 0, 4096 * nm, 0, 4096, 1);
      const HurstFit fit = fit_hurst_from_hhcf(height_height_correlation(f, 0, 1.0 / 64), 4 * nm, 64 * nm);
      ASSERT_TRUE(fit.defined);
      EXPECT_EQ(fit.points, 61);
      sum += fit.hurst;
    }
    double sum2d = 0;
    for (int seed = 1; seed <= 4; ++seed) {
      s.seed = seed;
      const HeightField f = generate_self_affine(s, 1, 0, 0, 512 * nm, 512 * nm, 512, 512);
      for (int along : {0, 1}) {
        const HurstFit fit = fit_hurst_from_hhcf(height_height_correlation(f, along, 1.0 / 16), 4 * nm, 32 * nm);
        ASSERT_TRUE(fit.defined);
        sum2d += fit.hurst;
      }
    }
    std::printf("[ measured ] HHCF, H = %.1f: profile %.4f, 2D %.4f\n", hurst, sum / 8, sum2d / 8);
    EXPECT_NEAR(sum / 8, hurst, 0.1);
    EXPECT_NEAR(sum2d / 8, hurst, 0.1);
  }
}

}  // namespace
}  // namespace debris
