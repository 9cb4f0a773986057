// A worn face's statistics (surface_roughness) on fields whose answers are known, and the height maps' file
// (height_map_output): samples appended, and a continued run keeping what its checkpoint had.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>

#include "cli_helpers.hpp"
#include "core/io/hdf5_file.hpp"
#include "core/rough/self_affine_surface.hpp"
#include "scenarios/common/dem/height_map_output.hpp"
#include "scenarios/common/dem/surface_roughness.hpp"

namespace debris {
namespace {

HeightField generated(double hurst, std::uint64_t seed) {
  SelfAffineSpec s;
  s.hurst = hurst;
  s.rms_height = 2e-9;
  s.rolloff_wavelength = 64e-9;
  s.cutoff_wavelength = 4e-9;
  s.seed = seed;
  return generate_self_affine(s, 1, 0, 0, 256e-9, 256e-9, 256, 256);
}

TEST(SurfaceRoughness, AGeneratedFaceMeasuresItsRmsAndHurstExponent) {
  for (double hurst : {0.5, 0.8}) {
    const FaceRoughness r = measure_face(generated(hurst, 5), 4e-9, 64e-9);
    EXPECT_NEAR(r.rms_height, 2e-9, 2e-9 * 1e-12);
    EXPECT_NEAR(r.mean_height, 0.0, 1e-20);
    ASSERT_TRUE(r.psd.defined);
    EXPECT_NEAR(r.psd.hurst, hurst, 0.05) << "+- " << r.psd.error;
    EXPECT_GT(r.rms_slope, 0.0);
    ASSERT_TRUE(r.hhcf.defined);
  }
}

// Two sines: the exact rms height and slope; a flat face: zeros and no exponent (NaN in the CSV, not a crash).
TEST(SurfaceRoughness, SinesAndAFlatFace) {
  HeightField f;
  f.length_a = f.length_b = 1.0;
  f.n_a = f.n_b = 64;
  f.h.resize(64 * 64);
  const double k1 = 2 * std::numbers::pi * 3, k2 = 2 * std::numbers::pi * 5;
  for (int i = 0; i < 64; ++i)
    for (int j = 0; j < 64; ++j)
      f.h[i * 64 + j] = 0.1 * std::sin(k1 * i / 64.0) + 0.05 * std::cos(k2 * j / 64.0) + 7.0;
  const FaceRoughness r = measure_face(f, 0.1, 0.5);
  EXPECT_NEAR(r.mean_height, 7.0, 1e-12);
  EXPECT_NEAR(r.rms_height, std::sqrt(0.1 * 0.1 / 2 + 0.05 * 0.05 / 2), 1e-12);
  EXPECT_NEAR(r.rms_slope, std::sqrt(std::pow(0.1 * k1, 2) / 2 + std::pow(0.05 * k2, 2) / 2), 1e-10);

  std::fill(f.h.begin(), f.h.end(), 3.0);
  const FaceRoughness flat = measure_face(f, 0.1, 0.5);
  EXPECT_EQ(flat.rms_height, 0.0);
  EXPECT_EQ(flat.rms_slope, 0.0);
  EXPECT_FALSE(flat.psd.defined);
  const std::vector<double> v = face_values(flat);
  ASSERT_EQ(v.size(), face_columns("bottom").size());
  EXPECT_TRUE(std::isnan(v[3]));
  EXPECT_EQ(face_columns("top")[3], "top_hurst");
}

TEST(HeightMapOutput, AContinuedRunKeepsItsCheckpointsSamples) {
  const std::string path = (test::fresh_directory("height_maps") / "surfaces_heights.h5").string();
  const HeightField a = generated(0.5, 1), b = generated(0.8, 2), c = generated(0.3, 3);
  {
    HeightMapWriter w(path);
    w.append(10, 1.0, 0.1, a, b);
    w.append(20, 2.0, 0.2, b, c);
    w.append(30, 3.0, 0.3, c, a);  // past the checkpoint: dropped on continuing
  }
  HeightMapWriter w(path, 2);
  EXPECT_EQ(w.samples(), 2);
  w.append(30, 3.5, 0.35, a, a);
  h5::File f(path, h5::File::Mode::read_only);
  EXPECT_EQ(f.attribute<std::int32_t>("normal_axis"), 1);
  EXPECT_EQ(f.attribute_array<double>("spacing"), (std::vector<double>{1e-9, 1e-9}));
  h5::Group s = f.open_group("samples");
  EXPECT_EQ(s.children().size(), 3u);
  EXPECT_EQ(s.open_group("0").attribute<std::int64_t>("step"), 10);
  EXPECT_EQ(s.open_group("1").read<double>("top").values, c.h);
  EXPECT_EQ(s.open_group("2").attribute<double>("time"), 3.5);
  const h5::Array<double> top = s.open_group("2").read<double>("top");
  EXPECT_EQ(top.shape, (h5::Shape{256, 256}));
  EXPECT_EQ(top.values, a.h);
  EXPECT_THROW(HeightMapWriter(path, 5), std::runtime_error);
}

}  // namespace
}  // namespace debris
