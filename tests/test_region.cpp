// Regions (core/region.hpp): blocks, cylinders along each axis, surfaces, unions and differences against
// brute-force inequalities written out per case, the input forms read_region accepts, and its errors.
#include "core/region.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "core/box.hpp"
#include "core/error.hpp"
#include "core/io/input.hpp"
#include "core/rough/height_field.hpp"

namespace debris {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// Random points in [-2, 12]^3 plus points on the faces that matter, so both sides of every bound are seen.
std::vector<Vec3> probe_points() {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-2.0, 12.0);
  std::vector<Vec3> pts;
  for (int i = 0; i < 20000; ++i) pts.push_back({u(rng), u(rng), u(rng)});
  for (double a : {0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 10.0})
    for (double b : {0.0, 2.0, 3.0, 5.0, 7.0, 8.0})
      for (double c : {0.0, 2.0, 4.0, 5.0, 6.0}) pts.push_back({a, b, c});
  return pts;
}

void expect_matches(const Region& r, const std::function<bool(double, double, double)>& want, const std::string& what) {
  long inside = 0, mismatches = 0;
  for (const Vec3& p : probe_points()) {
    const bool w = want(p.x, p.y, p.z);
    inside += w ? 1 : 0;
    if (r.contains(p) != w && ++mismatches <= 5)
      ADD_FAILURE() << what << ": point (" << p.x << ", " << p.y << ", " << p.z << ") contains " << r.contains(p)
                    << ", expected " << w;
  }
  EXPECT_EQ(mismatches, 0) << what;
  EXPECT_GT(inside, 100) << what << ": the probe points hardly test it";
}

Region from_yaml(const std::string& yaml, const Box* box = nullptr, const std::string& base_directory = "") {
  const InputNode n = InputNode::load_string(yaml, "test");
  Region r = read_region(n, box, base_directory);
  n.reject_unknown_keys();
  return r;
}

TEST(Region, BlockIsHalfOpenPerAxisWithOpenSides) {
  const Region b = Region::block({1, 2, -kInf}, {7, 5, 4});
  expect_matches(b, [](double x, double y, double z) { return x >= 1 && x < 7 && y >= 2 && y < 5 && z < 4; }, "block");
  EXPECT_TRUE(b.contains({1, 2, -1e300}));
  EXPECT_FALSE(b.contains({7, 2, 0}));
  EXPECT_TRUE(Region().contains({1e300, -1e300, 0}));  // the default region is all space
  expect_matches(from_yaml("{block: {x: [1, 7], y: [2, 5], z: [-inf, 4]}}"),
                 [](double x, double y, double z) { return x >= 1 && x < 7 && y >= 2 && y < 5 && z < 4; }, "yaml block");
  // The groups' older form is the same block.
  expect_matches(from_yaml("{x: [1, 7], y: [2, max], z: [min, 4]}"),
                 [](double x, double y, double z) { return x >= 1 && x < 7 && y >= 2 && z < 4; }, "bare block");
}

TEST(Region, CylinderAlongEachAxis) {
  // Centre (5, 3, 4), radius 2.5, extent [2, 8) along the axis; the axial component of the centre is unused.
  const double r2 = 2.5 * 2.5;
  auto in_x = [&](double x, double y, double z) {
    return x >= 2 && x < 8 && (y - 3) * (y - 3) + (z - 4) * (z - 4) <= r2;
  };
  auto in_y = [&](double x, double y, double z) {
    return y >= 2 && y < 8 && (x - 5) * (x - 5) + (z - 4) * (z - 4) <= r2;
  };
  auto in_z = [&](double x, double y, double z) {
    return z >= 2 && z < 8 && (x - 5) * (x - 5) + (y - 3) * (y - 3) <= r2;
  };
  expect_matches(Region::cylinder(0, {123, 3, 4}, 2.5, 2, 8), in_x, "cylinder x");
  expect_matches(Region::cylinder(1, {5, -99, 4}, 2.5, 2, 8), in_y, "cylinder y");
  expect_matches(Region::cylinder(2, {5, 3, 0}, 2.5, 2, 8), in_z, "cylinder z");
  expect_matches(from_yaml("{cylinder: {axis: x, centre: [0, 3, 4], radius: 2.5, extent: [2, 8]}}"), in_x, "yaml x");
  expect_matches(from_yaml("{cylinder: {axis: y, centre: [5, 0, 4], radius: 2.5, extent: [2, 8]}}"), in_y, "yaml y");
  expect_matches(from_yaml("{cylinder: {axis: z, centre: [5, 3, 0], radius: 2.5, extent: [2, 8]}}"), in_z, "yaml z");
  // The surface counts as inside; the extent is half-open; no extent means an infinite cylinder.
  EXPECT_TRUE(Region::cylinder(1, {5, 0, 4}, 2.5, 2, 8).contains({7.5, 2, 4}));
  EXPECT_FALSE(Region::cylinder(1, {5, 0, 4}, 2.5, 2, 8).contains({5, 8, 4}));
  expect_matches(from_yaml("{cylinder: {axis: y, centre: [5, 0, 4], radius: 2.5}}"),
                 [&](double x, double, double z) { return (x - 5) * (x - 5) + (z - 4) * (z - 4) <= r2; }, "open");
  // Units are read: 10 nm.
  const Region nm = from_yaml("{cylinder: {axis: y, centre: [30 nm, 0, 20 nm], radius: 10 nm, extent: [18 nm, 23 nm]}}");
  EXPECT_DOUBLE_EQ(nm.radius, 10e-9);
  EXPECT_TRUE(nm.contains({39e-9, 20e-9, 20e-9}));
  EXPECT_FALSE(nm.contains({41e-9, 20e-9, 20e-9}));
  EXPECT_FALSE(nm.contains({30e-9, 24e-9, 20e-9}));
}

TEST(Region, UnionAndDifference) {
  auto in_block = [](double x, double y, double) { return x >= 0 && x < 10 && y >= 2 && y < 5; };
  auto in_cyl = [](double x, double, double z) { return (x - 5) * (x - 5) + (z - 5) * (z - 5) <= 9.0; };
  auto in_ball_row = [](double x, double y, double z) { return x >= 8 && y >= 7 && z >= 6 && x < 10 && y < 9 && z < 8; };
  expect_matches(Region::union_of({Region::block({0, 2, -kInf}, {10, 5, kInf}), Region::cylinder(1, {5, 0, 5}, 3.0),
                                   Region::block({8, 7, 6}, {10, 9, 8})}),
                 [&](double x, double y, double z) { return in_block(x, y, z) || in_cyl(x, y, z) || in_ball_row(x, y, z); },
                 "union");
  // The junction's carving: a layer minus the cylinder that joins the two slabs.
  const std::string gap = R"({difference: [{block: {y: [2, 5]}}, {cylinder: {axis: y, centre: [5, 0, 5], radius: 3}}]})";
  expect_matches(from_yaml(gap), [&](double x, double y, double z) { return y >= 2 && y < 5 && !in_cyl(x, y, z); },
                 "difference");
  expect_matches(from_yaml("{union: [{block: {x: [0, 10], y: [2, 5]}}, " + gap.substr(0, gap.size()) + "]}"),
                 [&](double x, double y, double z) { return in_block(x, y, z) || (y >= 2 && y < 5 && !in_cyl(x, y, z)); },
                 "nested");
  EXPECT_NE(from_yaml(gap).describe().find("cylinder axis y"), std::string::npos) << from_yaml(gap).describe();
}

void expect_input_error(const std::string& yaml, const std::vector<std::string>& mention, const Box* box = nullptr,
                        const std::string& base_directory = "") {
  try {
    from_yaml(yaml, box, base_directory);
    ADD_FAILURE() << "accepted " << yaml;
  } catch (const InputError& e) {
    const std::string msg = e.what();
    for (const std::string& m : mention) EXPECT_NE(msg.find(m), std::string::npos) << "no '" << m << "' in " << msg;
  }
}

TEST(Region, BadInputNamesKeyAndValue) {
  const Box box({0, 0, 0}, {60, 40, 40}, {true, false, true});
  // Diameter 42 exceeds the z length 40 across a y cylinder; 19.5 fits.
  expect_input_error("{cylinder: {axis: y, centre: [30, 0, 20], radius: 21}}",
                     {"cylinder.radius", "21", "larger than the box", "z length 40"}, &box);
  EXPECT_NO_THROW(from_yaml("{cylinder: {axis: y, centre: [30, 0, 20], radius: 19.5}}", &box));
  expect_input_error("{cylinder: {axis: y, centre: [30, 0, 20], radius: 0}}", {"cylinder.radius", "0", "> 0"});
  expect_input_error("{cylinder: {axis: w, centre: [30, 0, 20], radius: 1}}", {"cylinder.axis", "w"});
  expect_input_error("{cylinder: {axis: y, centre: [30, 0, 20], radius: 1, extent: [5, 2]}}",
                     {"cylinder.extent", "hi must exceed lo"});
  expect_input_error("{block: {x: [1, 2, 3]}}", {"block.x", "3 values"});
  expect_input_error("{sphere: {radius: 1}}", {"sphere", "block, cylinder, surface, union, difference"});
  expect_input_error("{block: {x: [0, 1]}, cylinder: {axis: y, centre: [0, 0, 0], radius: 1}}",
                     {"block and cylinder", "one form"});
  expect_input_error("{union: []}", {"union", "at least one"});
  expect_input_error("{difference: [{block: {x: [0, 1]}}]}", {"difference", "cut"});
  expect_input_error("{block: {x: [0, 1], q: [0, 1]}}", {"block.q", "unknown key"});
}

// The hand-made surface of the surface tests: over the x-z plane of the box [0, 10) x [0, 6) x [0, 8) (normal
// y), h = 3 + 1.2 sin(2 pi x / 10) + 0.8 cos(2 pi 2 z / 8 + 0.5), periodic in x and z with the box.
constexpr double kPi = 3.14159265358979323846;
double sines(double x, double z) { return 3 + 1.2 * std::sin(2 * kPi * x / 10) + 0.8 * std::cos(2 * kPi * 2 * z / 8 + 0.5); }

// The field on a grid of spacing 10/200 x 8/160 = 0.05 (bilinear between points: at most ~3e-4 from sines()).
std::shared_ptr<const HeightField> sines_field() {
  HeightField f;
  f.normal_axis = 1;
  f.length_a = 10, f.length_b = 8;
  f.n_a = 200, f.n_b = 160;
  for (int i = 0; i < f.n_a; ++i)
    for (int j = 0; j < f.n_b; ++j) f.h.push_back(sines(i * 0.05, j * 0.05));
  return std::make_shared<const HeightField>(std::move(f));
}

TEST(Region, SurfaceBelowAndAboveAHandMadeField) {
  const Region below = Region::surface(sines_field(), true, "two sines");
  const Region above = Region::surface(sines_field(), false, "two sines");
  // Random points 1e-3 off the surface (more than the bilinear error), each side.
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> ux(0, 10), uz(0, 8);
  long checked = 0;
  for (int k = 0; k < 5000; ++k) {
    const double x = ux(rng), z = uz(rng), h = sines(x, z);
    for (double off : {-1e-3, 1e-3, -0.5, 0.7}) {
      const Vec3 p{x, h + off, z};
      ASSERT_EQ(below.contains(p), off < 0) << x << " " << z << " off " << off;
      ASSERT_EQ(above.contains(p), off > 0) << x << " " << z << " off " << off;
      ++checked;
    }
  }
  EXPECT_EQ(checked, 20000);
  // At grid points the field is the formula's value: 1e-9 off it is enough.
  for (double x : {0.0, 2.5, 5.05, 9.95})
    for (double z : {0.0, 1.0, 4.35, 7.95}) {
      EXPECT_TRUE(below.contains({x, sines(x, z) - 1e-9, z})) << x << " " << z;
      EXPECT_FALSE(below.contains({x, sines(x, z) + 1e-9, z})) << x << " " << z;
      EXPECT_TRUE(above.contains({x, sines(x, z), z})) << "the surface itself is above";
    }
  // Across the periodic seam: the last grid interval joins x = 9.95 to x = 0 (= 10), and z = 7.95 to z = 0;
  // points just outside [0, L) read the field of their image.
  for (double x : {9.975, 9.999, 1e-4, -0.02, 10.02})
    for (double z : {7.975, 7.999, 1e-4, -0.03, 8.03}) {
      const double h = sines(x, z);
      EXPECT_TRUE(below.contains({x, h - 1e-3, z})) << "seam " << x << " " << z;
      EXPECT_FALSE(below.contains({x, h + 1e-3, z})) << "seam " << x << " " << z;
      EXPECT_TRUE(above.contains({x, h + 1e-3, z})) << "seam " << x << " " << z;
    }
}

TEST(Region, SurfaceComposesWithBlocks) {
  const Region below = Region::surface(sines_field(), true, "two sines");
  const Region above = Region::surface(sines_field(), false, "two sines");
  const Region slab = Region::block({-kInf, 2.5, -kInf}, {kInf, 4, kInf});
  // Probe points away from the surface by more than the bilinear error.
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> ux(0, 10), uy(0, 6), uz(0, 8);
  long inside_union = 0, inside_difference = 0;
  for (int k = 0; k < 20000; ++k) {
    const Vec3 p{ux(rng), uy(rng), uz(rng)};
    const double h = sines(p.x, p.z);
    if (std::abs(p.y - h) < 1e-3) continue;
    const bool under = p.y < h, in_slab = p.y >= 2.5 && p.y < 4;
    // The slab with its rough top's valleys filled in: union; the slab minus what is below the surface: the
    // part of the slab above it.
    ASSERT_EQ(Region::union_of({below, slab}).contains(p), under || in_slab);
    ASSERT_EQ(Region::difference({slab, below}).contains(p), in_slab && !under);
    ASSERT_EQ(Region::difference({slab, above}).contains(p), in_slab && under);
    inside_union += under || in_slab;
    inside_difference += in_slab && !under;
  }
  EXPECT_GT(inside_difference, 500);
  EXPECT_GT(inside_union, 5000);
  EXPECT_EQ(Region::union_of({below, slab}).surfaces().size(), 1u);
  EXPECT_EQ(Region::difference({Region::union_of({slab, above}), below}).surfaces().size(), 2u);
  EXPECT_TRUE(slab.surfaces().empty());
}

TEST(Region, SurfaceDescribesItself) {
  const Region below = Region::surface(sines_field(), true, "two sines");
  const std::string d = below.describe();
  EXPECT_NE(d.find("surface normal y below at 3 "), std::string::npos) << d;
  // rms of 1.2 sin + 0.8 cos over whole periods: sqrt(1.2^2 / 2 + 0.8^2 / 2) = 1.019803902718557.
  EXPECT_NE(d.find("rms height 1.0198039027"), std::string::npos) << d;
  EXPECT_NE(d.find("two sines"), std::string::npos) << d;
  EXPECT_NE(Region::surface(sines_field(), false).describe().find("above"), std::string::npos);
  EXPECT_NE(Region::difference({Region(), below}).describe().find("surface normal y below"), std::string::npos);
}

// A box of 40 x 30 x 20 with the surfaces of read_region; periodic in x and z.
const Box kSurfaceBox({0, 0, 0}, {40, 30, 20}, {true, false, true});

TEST(Region, SurfaceFromSelfAffineInput) {
  const Region r = from_yaml("{surface: {normal: y, side: below, at: 12, self_affine: {hurst: 0.8, rms_height: 1, "
                             "cutoff_wavelength: 2, seed: 3}, grid_spacing: 0.5}}",
                             &kSurfaceBox);
  ASSERT_EQ(r.kind, Region::Kind::surface);
  ASSERT_TRUE(r.field);
  EXPECT_EQ(r.axis, 1);
  EXPECT_TRUE(r.below);
  // The field spans the box's x and z lengths at spacing 0.5, its mean at `at`, its rms as asked.
  EXPECT_EQ(r.field->n_a, 80);
  EXPECT_EQ(r.field->n_b, 40);
  EXPECT_DOUBLE_EQ(r.field->length_a, 40);
  EXPECT_DOUBLE_EQ(r.field->length_b, 20);
  EXPECT_NEAR(r.field->mean(), 12, 1e-12);
  EXPECT_NEAR(r.field->rms_height(), 1, 1e-12);
  EXPECT_DOUBLE_EQ(r.shortest_wavelength, 2);
  EXPECT_EQ(r.shortest_wavelength_key, "surface.self_affine.cutoff_wavelength");
  // Classification against the field's own grid values.
  for (int i = 0; i < r.field->n_a; i += 7)
    for (int j = 0; j < r.field->n_b; j += 3) {
      const double x = i * 0.5, z = j * 0.5, h = r.field->at(i, j);
      EXPECT_TRUE(r.contains({x, h - 1e-9, z}));
      EXPECT_FALSE(r.contains({x, h + 1e-9, z}));
    }
  const std::string d = r.describe();
  EXPECT_NE(d.find("surface normal y below at 12"), std::string::npos) << d;
  EXPECT_NE(d.find("H 0.8"), std::string::npos) << d;
  EXPECT_NE(d.find("rms height 1"), std::string::npos) << d;
  // Units, another normal, and the default grid (a quarter of the cut-off: 2 nm / 4 over 40 nm).
  const Box nm_box({0, 0, 0}, {40e-9, 30e-9, 20e-9}, {true, true, true});
  const Region x = from_yaml("{surface: {normal: x, side: above, at: 20 nm, self_affine: {hurst: 0.5, "
                             "rms_height: 1 nm, cutoff_wavelength: 2 nm}}}", &nm_box);
  EXPECT_EQ(x.field->normal_axis, 0);
  EXPECT_EQ(x.field->n_a, 60);  // y: 30 nm / 0.5 nm
  EXPECT_EQ(x.field->n_b, 40);  // z
  EXPECT_NEAR(x.field->mean(), 20e-9, 1e-20);
  EXPECT_FALSE(x.below);
}

TEST(Region, SurfaceFromHeightMapFileRelativeToTheInput) {
  const std::filesystem::path dir = std::filesystem::path(::testing::TempDir()) / "debris_region_height_map";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  // The sines on a 20 x 16 grid of spacing 0.5 (box 10 x 6 x 8), the heights written in centimetres of this
  // metre-unit box ("unit: cm").
  {
    std::ofstream map(dir / "afm.txt");
    map.precision(17);
    map << "# two sines\n";
    for (int i = 0; i < 20; ++i) {
      for (int j = 0; j < 16; ++j) map << (j ? " " : "") << 100 * sines(i * 0.5, j * 0.5);
      map << "\n";
    }
  }
  const Box box({0, 0, 0}, {10, 6, 8}, {true, false, true});
  const std::string yaml = "{surface: {normal: y, side: above, at: 4, height_map: {file: afm.txt, spacing: [0.5, 0.5], unit: cm}}}";
  const Region r = from_yaml(yaml, &box, dir.string());
  ASSERT_EQ(r.kind, Region::Kind::surface);
  EXPECT_EQ(r.field->n_a, 20);
  EXPECT_EQ(r.field->n_b, 16);
  // The sines' grid mean is 3 (whole periods): `at` 4 moves every height up by 1.
  for (int i = 0; i < 20; i += 3)
    for (int j = 0; j < 16; j += 5) {
      const double x = i * 0.5, z = j * 0.5, h = sines(x, z) + 1;
      EXPECT_TRUE(r.contains({x, h + 1e-6, z})) << x << " " << z;
      EXPECT_FALSE(r.contains({x, h - 1e-6, z})) << x << " " << z;
    }
  EXPECT_DOUBLE_EQ(r.shortest_wavelength, 1.0);
  EXPECT_EQ(r.shortest_wavelength_key, "surface.height_map.spacing");
  EXPECT_NE(r.describe().find("afm.txt"), std::string::npos) << r.describe();
  // Without the input's folder the relative path is not found, and the message says where it looked.
  expect_input_error(yaml, {"surface.height_map.file", "afm.txt", "no such file"}, &box);
  // The map must cover the box: 20 x 0.4 = 8 is not the box's x length 10.
  expect_input_error("{surface: {normal: y, side: above, at: 4, height_map: {file: afm.txt, spacing: [0.4, 0.5], unit: cm}}}",
                     {"surface.height_map.spacing", "[0.4, 0.5]", "cover 8 x 8", "x x z lengths 10 x 8"}, &box, dir.string());
}

TEST(Region, SurfaceBadInputNamesKeyAndValue) {
  const std::string good = "{surface: {normal: y, side: below, at: 12, self_affine: {hurst: 0.8, rms_height: 1, "
                           "cutoff_wavelength: 2, seed: 3}, grid_spacing: 0.5}}";
  EXPECT_NO_THROW(from_yaml(good, &kSurfaceBox));
  auto bad = [&](const std::string& from, const std::string& to) {
    std::string y = good;
    const auto at = y.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return y.replace(at, from.size(), to);
  };
  expect_input_error(good, {"surface", "needs the simulation box"});
  expect_input_error(bad("normal: y", "normal: w"), {"surface.normal", "w"}, &kSurfaceBox);
  expect_input_error(bad("side: below", "side: under"), {"surface.side", "under"}, &kSurfaceBox);
  // The box is 30 tall along y.
  expect_input_error(bad("rms_height: 1,", "rms_height: 31,"), {"surface.self_affine.rms_height", "31", "does not fit the box"},
                     &kSurfaceBox);
  // rms 1 fits, but not around 29.5 (or 0.5): the heights reach past the box's y extent [0, 30].
  expect_input_error(bad("at: 12", "at: 29.5"), {"surface.at", "29.5", "does not fit the box", "[0, 30]"}, &kSurfaceBox);
  expect_input_error(bad("at: 12", "at: 0.5"), {"surface.at", "0.5", "does not fit the box"}, &kSurfaceBox);
  expect_input_error(bad("grid_spacing: 0.5", "grid_spacing: 0"), {"surface.grid_spacing", "0", "> 0"}, &kSurfaceBox);
  expect_input_error(bad("grid_spacing: 0.5", "grid_spacing: -1"), {"surface.grid_spacing", "-1", "> 0"}, &kSurfaceBox);
  // The generator's refusals (std::invalid_argument) become input errors naming the region's key path.
  expect_input_error(bad("hurst: 0.8", "hurst: 1.5"), {"surface.self_affine", "hurst", "1.5"}, &kSurfaceBox);
  expect_input_error(bad("grid_spacing: 0.5", "grid_spacing: 1.5"), {"surface.self_affine", "cannot be generated"}, &kSurfaceBox);
  expect_input_error(bad("cutoff_wavelength: 2", "cutoff_wavelength: 0"), {"surface.self_affine.cutoff_wavelength", "0", "> 0"},
                     &kSurfaceBox);
  expect_input_error("{surface: {normal: y, side: below, at: 12}}", {"surface", "neither", "self_affine", "height_map"},
                     &kSurfaceBox);
  expect_input_error(bad("grid_spacing: 0.5", "grid_spacing: 0.5, height_map: {file: a.txt, spacing: [1, 1]}"),
                     {"surface", "self_affine and height_map", "exactly one"}, &kSurfaceBox);
  expect_input_error(bad("seed: 3", "seed: 3, colour: red"), {"surface.self_affine.colour", "unknown key"}, &kSurfaceBox);
  // Inside a composition the path says where.
  expect_input_error("{union: [{block: {y: [0, 1]}}, " + bad("at: 12", "at: 29.5") + "]}", {"union[1].surface.at", "29.5"},
                     &kSurfaceBox);
}

}  // namespace
}  // namespace debris
