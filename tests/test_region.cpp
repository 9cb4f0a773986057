// Regions (core/region.hpp): blocks, cylinders along each axis, unions and differences against brute-force
// inequalities written out per case, the input forms read_region accepts, and its errors.
#include "core/region.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "core/box.hpp"
#include "core/error.hpp"
#include "core/io/input.hpp"

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

Region from_yaml(const std::string& yaml, const Box* box = nullptr) {
  const InputNode n = InputNode::load_string(yaml, "test");
  Region r = read_region(n, box);
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

void expect_input_error(const std::string& yaml, const std::vector<std::string>& mention, const Box* box = nullptr) {
  try {
    from_yaml(yaml, box);
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
  expect_input_error("{sphere: {radius: 1}}", {"sphere", "block, cylinder, union, difference"});
  expect_input_error("{block: {x: [0, 1]}, cylinder: {axis: y, centre: [0, 0, 0], radius: 1}}",
                     {"block and cylinder", "one form"});
  expect_input_error("{union: []}", {"union", "at least one"});
  expect_input_error("{difference: [{block: {x: [0, 1]}}]}", {"difference", "cut"});
  expect_input_error("{block: {x: [0, 1], q: [0, 1]}}", {"block.q", "unknown key"});
}

}  // namespace
}  // namespace debris
