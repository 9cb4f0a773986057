// The YAML input reader: typed getters with units, fallbacks, dotted key paths in every error, and
// detection of keys the run never read.
#include "core/io/input.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "core/error.hpp"
#include "tests/cli_helpers.hpp"

namespace debris {
namespace {

/// Runs f and returns the InputError message; fails the test if f does not throw one.
template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no InputError thrown";
  return "";
}

using test::contains;

const char* const material_yaml = R"(
material:
  youngs_modulus: 73 GPa
  poisson_ratio: 0.17
  density: 2.2 g/cm^3
  surface_energy: 1.5 J/m^2
run:
  steps: 1000
  dt: 20fs
  restart: yes
  integrator: velocity_verlet
  name: silica wear
  box: ["10 nm", "20 nm", "30 nm"]
  gravity: [0, 0, -9.81]
  radii: [1 nm, 2 nm, 1.5e-9]
groups:
  - name: top
    motion: fixed
  - name: bottom
    motion: free
    velocity: [1 m/s, 0, 0]
tags: [a, b]
)";

TEST(InputGetters, QuantitiesConvertToSi) {
  const InputNode root = InputNode::load_string(material_yaml);
  const InputNode m = root.child("material");
  EXPECT_EQ(m.path(), "material");
  EXPECT_TRUE(m.is_map());
  EXPECT_EQ(m.quantity("youngs_modulus", units::pressure), 7.3e10);
  EXPECT_EQ(m.quantity("poisson_ratio", units::dimensionless), 0.17);
  EXPECT_EQ(m.quantity("density", units::density), 2200.0);
  EXPECT_EQ(m.quantity("surface_energy", units::surface_energy), 1.5);
  EXPECT_EQ(m.quantity("restitution", units::dimensionless, 0.5), 0.5);  // absent: fallback
}

TEST(InputGetters, ScalarsOfEveryKind) {
  const InputNode run = InputNode::load_string(material_yaml).child("run");
  EXPECT_EQ(run.integer("steps"), 1000);
  EXPECT_EQ(run.integer("threads", 4), 4);
  EXPECT_EQ(run.quantity("dt", units::time), 2e-14);
  EXPECT_TRUE(run.boolean("restart"));
  EXPECT_FALSE(run.boolean("verbose", false));
  EXPECT_EQ(run.string("name"), "silica wear");
  EXPECT_EQ(run.string("output", "out"), "out");
  EXPECT_EQ(run.choice("integrator", {"euler", "velocity_verlet"}), "velocity_verlet");
  EXPECT_EQ(run.choice("neighbor", {"cells", "brute"}, "cells"), "cells");
  EXPECT_TRUE(run.has("steps"));
  EXPECT_FALSE(run.has("threads"));
}

TEST(InputGetters, Vec3WithAndWithoutUnits) {
  const InputNode run = InputNode::load_string(material_yaml).child("run");
  const Vec3 box = run.vec3("box", units::length);
  EXPECT_EQ(box.x, 1e-8);
  EXPECT_EQ(box.y, 2e-8);
  EXPECT_EQ(box.z, 3e-8);
  const Vec3 g = run.vec3("gravity", units::acceleration);
  EXPECT_EQ(g.x, 0.0);
  EXPECT_EQ(g.z, -9.81);
  const Vec3 f = run.vec3("shift", units::length, Vec3{1, 2, 3});
  EXPECT_EQ(f.y, 2.0);
}

TEST(InputGetters, NumbersAndLists) {
  const InputNode root = InputNode::load_string(material_yaml);
  const std::vector<double> radii = root.child("run").numbers("radii", units::length);
  ASSERT_EQ(radii.size(), 3u);
  EXPECT_EQ(radii[0], 1e-9);
  EXPECT_EQ(radii[1], 2e-9);
  EXPECT_EQ(radii[2], 1.5e-9);

  const std::vector<InputNode> groups = root.list("groups");
  ASSERT_EQ(groups.size(), 2u);
  EXPECT_EQ(groups[1].path(), "groups[1]");
  EXPECT_EQ(groups[0].string("name"), "top");
  EXPECT_EQ(groups[1].choice("motion", {"fixed", "free"}), "free");
  EXPECT_EQ(groups[1].vec3("velocity", units::velocity).x, 1.0);

  const std::vector<InputNode> tags = root.list("tags");
  ASSERT_EQ(tags.size(), 2u);
  EXPECT_TRUE(tags[0].is_scalar());
  EXPECT_EQ(tags[1].text(), "b");
  EXPECT_EQ(root.keys(), (std::vector<std::string>{"material", "run", "groups", "tags"}));
}

TEST(InputErrors, MissingKeyNamesDottedPath) {
  const InputNode root = InputNode::load_string("material:\n  density: 2200\n");
  const std::string msg = error_of([&] { root.child("material").quantity("youngs_modulus", units::pressure); });
  EXPECT_TRUE(contains(msg, "'material.youngs_modulus'")) << msg;
  EXPECT_TRUE(contains(msg, "missing key")) << msg;
  EXPECT_TRUE(contains(error_of([&] { root.child("run"); }), "'run'"));
  EXPECT_TRUE(contains(error_of([&] { root.list("groups"); }), "'groups'"));
}

TEST(InputErrors, BadValuesNameKeyAndValue) {
  const InputNode root = InputNode::load_string(R"(
a:
  steps: 1.5
  count: abc
  flag: maybe
  mode: fast
  E: 73 nm
  v: [1, 2]
  name: {x: 1}
  big: 99999999999999999999999
groups:
  - motion: {speed: 3 km}
)");
  const InputNode a = root.child("a");
  std::string msg = error_of([&] { a.integer("steps"); });
  EXPECT_TRUE(contains(msg, "'a.steps' = 1.5")) << msg;
  msg = error_of([&] { a.integer("count"); });
  EXPECT_TRUE(contains(msg, "'a.count' = abc")) << msg;
  msg = error_of([&] { a.integer("big"); });
  EXPECT_TRUE(contains(msg, "'a.big' = 99999999999999999999999")) << msg;
  // A plain number beside values with units is noted (it may be a forgotten unit); a file of plain
  // numbers alone (Table 4's reduced units) or of units alone has nothing to note.
  const InputNode mixed = InputNode::load_string("{E: 73 GPa, rho: 2200, nu: 0.17, v: [1 m/s, 2, 0]}", "m.yaml");
  mixed.quantity("E", units::pressure);
  mixed.quantity("rho", units::density);
  mixed.quantity("nu", units::dimensionless);
  mixed.vec3("v", units::velocity);
  EXPECT_EQ(mixed.plain_beside_units(), (std::vector<std::string>{"rho = 2200", "v[1] = 2"}));
  const InputNode plain = InputNode::load_string("{E: 1, rho: 1}", "p.yaml");
  plain.quantity("E", units::pressure);
  plain.quantity("rho", units::density);
  EXPECT_TRUE(plain.plain_beside_units().empty());
  // Exponent notation is a whole number when it is exact (1e9 steps); 1e-3 and 2.5e0 are not.
  const InputNode e = InputNode::load_string("{a: 1e9, b: 2.5e3, c: 1e-3, d: 2.5e0, f: 1e30}", "e.yaml");
  EXPECT_EQ(e.integer("a"), 1000000000);
  EXPECT_EQ(e.integer("b"), 2500);
  EXPECT_TRUE(contains(error_of([&] { e.integer("c"); }), "'c' = 1e-3")) << error_of([&] { e.integer("c"); });
  EXPECT_TRUE(contains(error_of([&] { e.integer("d"); }), "whole number"));
  EXPECT_TRUE(contains(error_of([&] { e.integer("f"); }), "out of the range"));
  msg = error_of([&] { a.boolean("flag"); });
  EXPECT_TRUE(contains(msg, "'a.flag' = maybe")) << msg;
  EXPECT_TRUE(contains(msg, "true or false")) << msg;
  msg = error_of([&] { a.choice("mode", {"slow", "exact"}); });
  EXPECT_TRUE(contains(msg, "'a.mode' = fast")) << msg;
  EXPECT_TRUE(contains(msg, "one of: slow, exact")) << msg;
  msg = error_of([&] { a.quantity("E", units::pressure); });
  EXPECT_TRUE(contains(msg, "'a.E'")) << msg;
  EXPECT_TRUE(contains(msg, "73 nm")) << msg;
  EXPECT_TRUE(contains(msg, "line 7")) << msg;  // where it is in the file
  msg = error_of([&] { a.vec3("v", units::length); });
  EXPECT_TRUE(contains(msg, "'a.v' = [1, 2]")) << msg;
  msg = error_of([&] { a.string("name"); });
  EXPECT_TRUE(contains(msg, "'a.name' = {x: 1}")) << msg;
  // Fallback getters still reject a value that is present but wrong.
  msg = error_of([&] { a.quantity("E", units::pressure, 1.0); });
  EXPECT_TRUE(contains(msg, "'a.E'")) << msg;
  msg = error_of([&] { root.list("groups")[0].child("motion").quantity("speed", units::time); });
  EXPECT_TRUE(contains(msg, "'groups[0].motion.speed'")) << msg;
  EXPECT_TRUE(contains(msg, "3 km")) << msg;
}

TEST(InputErrors, ElementErrorsNameTheIndex) {
  const InputNode root = InputNode::load_string("r: [1 nm, 2 s, 3 nm]\nb: [1 nm, x, 3 nm]\n");
  std::string msg = error_of([&] { root.numbers("r", units::length); });
  EXPECT_TRUE(contains(msg, "'r[1]' = '2 s'")) << msg;
  msg = error_of([&] { root.vec3("b", units::length); });
  EXPECT_TRUE(contains(msg, "'b[1]' = 'x'")) << msg;
}

TEST(InputUnknownKeys, TypoIsReportedWithKnownKeys) {
  const InputNode root = InputNode::load_string(R"(
material:
  youngs_modulu: 1
  poisson_ratio: 0.17
)");
  const InputNode m = root.child("material");
  EXPECT_EQ(m.quantity("youngs_modulus", units::pressure, 5.0), 5.0);
  EXPECT_EQ(m.quantity("poisson_ratio", units::dimensionless), 0.17);
  const std::string msg = error_of([&] { root.reject_unknown_keys(); });
  EXPECT_TRUE(contains(msg, "'material.youngs_modulu' = 1: unknown key")) << msg;
  EXPECT_TRUE(contains(msg, "did you mean 'youngs_modulus'")) << msg;
  EXPECT_TRUE(contains(msg, "known keys here: youngs_modulus, poisson_ratio")) << msg;
}

TEST(InputUnknownKeys, EverythingReadPasses) {
  const InputNode root = InputNode::load_string(material_yaml);
  const InputNode m = root.child("material");
  m.quantity("youngs_modulus", units::pressure);
  m.quantity("poisson_ratio", units::dimensionless);
  m.quantity("density", units::density);
  const InputNode copy = root;  // copies share what has been read
  const InputNode run = copy.child("run");
  run.integer("steps");
  run.quantity("dt", units::time);
  run.boolean("restart");
  run.choice("integrator", {"velocity_verlet"});
  run.string("name");
  run.vec3("box", units::length);
  run.vec3("gravity", units::acceleration);
  run.numbers("radii", units::length);
  for (const InputNode& g : root.list("groups")) {
    g.string("name");
    g.string("motion");
    g.vec3("velocity", units::velocity, Vec3{});
  }
  root.list("tags");
  // Only material.surface_energy is left.
  const std::string msg = error_of([&] { root.reject_unknown_keys(); });
  EXPECT_TRUE(contains(msg, "'material.surface_energy' = 1.5 J/m^2: unknown key")) << msg;
  m.quantity("surface_energy", units::surface_energy);
  EXPECT_NO_THROW(root.reject_unknown_keys());
}

TEST(InputUnknownKeys, NestedAndInsideLists) {
  const char* yaml = R"(
run:
  steps: 10
  output: {every: 5, fromat: csv}
groups:
  - name: top
  - name: bottom
    motoin: free
)";
  {
    const InputNode root = InputNode::load_string(yaml);
    const InputNode run = root.child("run");
    run.integer("steps");
    run.child("output").integer("every");
    run.child("output").string("format", "csv");
    for (const InputNode& g : root.list("groups")) {
      g.string("name");
      g.string("motion", "free");
    }
    const std::string msg = error_of([&] { root.reject_unknown_keys(); });
    EXPECT_TRUE(contains(msg, "'run.output.fromat' = csv: unknown key")) << msg;
    EXPECT_TRUE(contains(msg, "did you mean 'format'")) << msg;
    // The subtree that was never visited further down is checked on its own too.
    const std::string in_list = error_of([&] { root.list("groups")[1].reject_unknown_keys(); });
    EXPECT_TRUE(contains(in_list, "'groups[1].motoin' = free: unknown key")) << in_list;
    EXPECT_TRUE(contains(in_list, "known keys here: name, motion")) << in_list;
  }
  {
    // A section the run never opened is reported as a whole.
    const InputNode root = InputNode::load_string(yaml);
    root.child("run").integer("steps");
    root.child("run").child("output").integer("every");
    root.child("run").child("output").string("format", "csv");
    const std::string msg = error_of([&] { root.reject_unknown_keys(); });
    EXPECT_TRUE(contains(msg, "'run.output.fromat'")) << msg;
    root.child("run").child("output").string("fromat");
    const std::string next = error_of([&] { root.reject_unknown_keys(); });
    EXPECT_TRUE(contains(next, "'groups' = [{name: top}")) << next;
    EXPECT_TRUE(contains(next, "known keys here: run")) << next;
  }
}

TEST(InputUnknownKeys, AllReadMeansNoError) {
  const InputNode root = InputNode::load_string("a: 1\nb: {c: [1, 2, 3], d: [{e: x}]}\n");
  root.integer("a");
  const InputNode b = root.child("b");
  b.vec3("c", units::dimensionless);
  b.list("d")[0].string("e");
  EXPECT_NO_THROW(root.reject_unknown_keys());
}

TEST(InputLoad, SyntaxErrorReportsLine) {
  const std::string msg = error_of([] { InputNode::load_string("a: 1\nb: [1, 2\nc: 3\n", "bad.yaml"); });
  EXPECT_TRUE(contains(msg, "bad.yaml")) << msg;
  EXPECT_TRUE(contains(msg, "YAML syntax error at line")) << msg;
  const std::string indent = error_of([] { InputNode::load_string("a: 1\n b: 2\n", "indent.yaml"); });
  EXPECT_TRUE(contains(indent, "line 2")) << indent;
}

// yaml-cpp 0.7 loops for ever (allocating a null document per turn) on a document that starts with a ','
// (found by tests/fuzz in all five executables' inputs): the reader must call it a syntax error at once.
TEST(InputLoad, StrayCommaIsASyntaxErrorNotAHang) {
  for (const char* text : {",", ", x", "# comment\n, 38.4, 76.8]\n", "a: 1\n---\n,\n"}) {
    const std::string msg = error_of([&] { InputNode::load_string(text, "comma.yaml"); });
    EXPECT_TRUE(contains(msg, "comma.yaml")) << msg;
    EXPECT_TRUE(contains(msg, "YAML syntax error at line")) << msg;
  }
  const std::string two = error_of([] { InputNode::load_string("a: 1\n---\nb: 2\n", "two.yaml"); });
  EXPECT_TRUE(contains(two, "holds 2 YAML documents")) << two;
}

TEST(InputLoad, DuplicateKeyAndBadTopLevel) {
  std::string msg = error_of([] { InputNode::load_string("a: 1\nb: 2\na: 3\n"); });
  EXPECT_TRUE(contains(msg, "'a' = 3: key given twice")) << msg;
  msg = error_of([] { InputNode::load_string("- 1\n- 2\n"); });
  EXPECT_TRUE(contains(msg, "top level")) << msg;
  EXPECT_TRUE(InputNode::load_string("").keys().empty());  // an empty input: every key takes its default
}

TEST(InputLoad, FileRoundTripAndMissingFile) {
  const std::string dir = ::testing::TempDir() + "/debris_input_test";
  std::filesystem::create_directories(dir);
  const std::string path = dir + "/run.yaml";
  {
    std::ofstream(path) << "material:\n  density: 2200 kg/m^3\n";
  }
  const InputNode root = InputNode::load_file(path);
  EXPECT_EQ(root.child("material").quantity("density", units::density), 2200.0);
  const std::string unknown = error_of([&] { InputNode::load_file(path).reject_unknown_keys(); });
  EXPECT_TRUE(contains(unknown, path + " line 1")) << unknown;  // the file and line of the stray key

  const std::string missing = dir + "/no_such_file.yaml";
  const std::string msg = error_of([&] { InputNode::load_file(missing); });
  EXPECT_TRUE(contains(msg, missing)) << msg;
  EXPECT_TRUE(contains(msg, "no such file")) << msg;
  EXPECT_TRUE(contains(error_of([&] { InputNode::load_file(dir); }), "directory"));
}

// Nested YAML aliases ("billion laughs"): nine levels of ten copies each are a few lines of text but a tree of
// 10^9 nodes. The tree's size is counted with each alias counted once, and an input over the limit is refused
// naming the file; one just under it loads.
TEST(InputNode, NestedAliasesAreCountedAndRefusedOverTheLimit) {
  std::string yaml = "a0: &a0 [x, x, x, x, x, x, x, x, x, x]\n";
  for (int k = 1; k <= 9; ++k) {
    const std::string p = "*a" + std::to_string(k - 1);
    yaml += "a" + std::to_string(k) + ": &a" + std::to_string(k) + " [" + p;
    for (int c = 1; c < 10; ++c) yaml += ", " + p;
    yaml += "]\n";
  }
  const std::string msg = error_of([&] { InputNode::load_string(yaml, "laughs.yaml"); });
  EXPECT_TRUE(contains(msg, "'input file' = laughs.yaml")) << msg;
  EXPECT_TRUE(contains(msg, "aliases")) << msg;
  EXPECT_TRUE(contains(msg, std::to_string(kMaxInputNodes))) << msg;
  // a0 to a4: about 1.2e5 nodes, under the limit, load; with a5 (1.1e6 more) they do not.
  std::string five, six;
  for (std::size_t at = 0, line = 0; line < 6; ++line) {
    const std::size_t end = yaml.find('\n', at) + 1;
    if (line < 5) five += yaml.substr(at, end - at);
    six += yaml.substr(at, end - at);
    at = end;
  }
  EXPECT_NO_THROW(InputNode::load_string(five, "five.yaml"));
  EXPECT_THROW(InputNode::load_string(six, "six.yaml"), InputError);
}

}  // namespace
}  // namespace debris
