// The key reference (core/io/key_reference.hpp): lookup of a reader's key paths, the audit that holds a
// reader to its descriptions, and output headers built from column descriptions.
#include <gtest/gtest.h>

#include <sstream>

#include "core/io/input.hpp"
#include "core/io/key_reference.hpp"

namespace debris {
namespace {

KeyReference small_reference() {
  KeyReference r("demo");
  r.key("material").is(KeyKind::section).means("the material");
  r.key("material.density").is(KeyKind::quantity).in(units::density).allowed("> 0").means("density");
  r.key("material.scaling").is(KeyKind::quantity).fallback("0.5").means("s");
  r.key("groups").is(KeyKind::list).means("groups");
  r.key("groups.name").is(KeyKind::text).means("name");
  r.key("groups.motion").one_of({"free", "frozen"}).fallback("free").means("motion");
  r.key("groups.region").is(KeyKind::section).follows("region").means("where");
  r.key("shapes").is(KeyKind::section).means("shapes by name");
  r.key("shapes.<name>").is(KeyKind::section).means("one shape");
  r.key("shapes.<name>.mesh_size").is(KeyKind::quantity).in(units::length).fallback("1 mm").means("h");
  r.key("box", "region").is(KeyKind::section).means("a box");
  r.key("box.x", "region").is(KeyKind::numbers).in(units::length).means("bounds");
  r.key("union", "region").is(KeyKind::list).follows("region").means("any of");
  return r;
}

TEST(KeyReference, FindsPathsThroughListsWildcardsAndSharedTables) {
  const KeyReference r = small_reference();
  ASSERT_NE(r.find("groups[3].motion"), nullptr);
  EXPECT_EQ(r.find("groups[3].motion")->path, "groups.motion");
  ASSERT_NE(r.find("shapes.disc.mesh_size"), nullptr);
  EXPECT_EQ(r.find("shapes.disc.mesh_size")->path, "shapes.<name>.mesh_size");
  ASSERT_NE(r.find("groups[0].region.box.x"), nullptr);
  EXPECT_EQ(r.find("groups[0].region.box.x")->path, "box.x");
  // A region inside a union inside a group's region: the shared table refers to itself.
  ASSERT_NE(r.find("groups[1].region.union[2].box.x"), nullptr);
  EXPECT_EQ(r.find("groups[1].region.union[2].box.x")->path, "box.x");
  EXPECT_EQ(r.find("groups[0].velocity"), nullptr);
  EXPECT_EQ(r.find("material.densty"), nullptr);
  EXPECT_EQ(r.find("shapes.disc.size"), nullptr);
}

TEST(KeyReference, DescribingAKeyTwiceIsAProgrammingError) {
  KeyReference r("demo");
  r.key("a");
  EXPECT_THROW(r.key("a"), std::logic_error);
}

TEST(KeyAudit, AReaderThatMatchesItsDescriptionsHasNoFindings) {
  const InputNode root = InputNode::load_string(
      "material: {density: 2.2 g/cm^3}\ngroups: [{name: a, region: {box: {x: [0, 1]}}}]\n"
      "shapes: {disc: {}}\n");
  (void)root.child("material").quantity("density", units::density);
  (void)root.child("material").quantity("scaling", units::dimensionless, 0.5);
  for (const InputNode& g : root.list("groups")) {
    (void)g.string("name");
    (void)g.choice("motion", {"frozen", "free"}, "free");
    (void)g.child("region").child("box").list("x");
  }
  (void)root.child("shapes").child("disc").quantity("mesh_size", units::length, 1e-3);
  EXPECT_TRUE(key_audit_findings(root, small_reference()).empty());
}

TEST(KeyAudit, NamesAnUndescribedKeyAndEachDisagreement) {
  const InputNode root = InputNode::load_string("material: {density: 1}\ngroups: [{name: 7}]\n");
  const InputNode m = root.child("material");
  (void)m.quantity("density", units::pressure);          // another dimension
  (void)m.quantity("scaling", units::dimensionless, 0.25);  // another default
  (void)m.quantity("youngs_modulus", units::pressure, 1.0);  // not described
  for (const InputNode& g : root.list("groups")) {
    (void)g.integer("name");                                    // another kind
    (void)g.choice("motion", {"free", "frozen", "rigid"}, "free");  // more choices
  }
  const std::vector<std::string> f = key_audit_findings(root, small_reference());
  const auto has = [&](const std::string& text) {
    for (const std::string& s : f)
      if (s.find(text) != std::string::npos) return true;
    return false;
  };
  EXPECT_EQ(f.size(), 5u);
  EXPECT_TRUE(has("'material.density' is read in Pa but described in kg/m^3"));
  EXPECT_TRUE(has("'material.scaling' defaults to 0.25 but is described with the default '0.5'"));
  EXPECT_TRUE(has("'material.youngs_modulus' is read but not described"));
  EXPECT_TRUE(has("'groups.name' is read as integer but described as text"));
  EXPECT_TRUE(has("'groups.motion' accepts other choices"));
}

TEST(KeyAudit, ADefaultGivenWithAUnitIsComparedInSi) {
  const InputNode root = InputNode::load_string("shapes: {disc: {}}\n");
  (void)root.child("shapes").child("disc").quantity("mesh_size", units::length, 1e-3);
  EXPECT_TRUE(key_audit_findings(root, small_reference()).empty());
  const InputNode other = InputNode::load_string("shapes: {disc: {}}\n");
  (void)other.child("shapes").child("disc").quantity("mesh_size", units::length, 1e-2);
  EXPECT_EQ(key_audit_findings(other, small_reference()).size(), 1u);
}

// A key that takes one value or a list of them (a sweep: debris_patch's poisson_ratio) is described as a
// quantity that may be a list, and read as one quantity or as the list; a vector stays read element by
// element only.
TEST(KeyAudit, AListOfQuantitiesMayBeReadAsOneValue) {
  KeyReference r("demo");
  r.key("nu").is(KeyKind::quantity).or_a_list().means("one value or a sweep");
  r.key("at").is(KeyKind::vector).in(units::length).means("a point");
  const InputNode one = InputNode::load_string("nu: 0.1\nat: 1\n");
  (void)one.quantity("nu", units::dimensionless);
  EXPECT_TRUE(key_audit_findings(one, r).empty());
  const InputNode list = InputNode::load_string("nu: [0.1, 0.2]\n");
  (void)list.numbers("nu", units::dimensionless);
  EXPECT_TRUE(key_audit_findings(list, r).empty());
  (void)one.quantity("at", units::length);
  EXPECT_EQ(key_audit_findings(one, r).size(), 1u);
}

TEST(KeyAudit, AKeyThatTakesOneValueOrAListMayBeReadAsEither) {
  KeyReference r("demo");
  r.key("fixed").is(KeyKind::boolean).or_a_list().fallback("false").means("fixed axes");
  r.key("free").is(KeyKind::boolean).fallback("false").means("one value only");
  const InputNode root = InputNode::load_string("fixed: [x, y]\nfree: [x]\n");
  (void)root.list("fixed");
  (void)root.list("free");
  const std::vector<std::string> f = key_audit_findings(root, r);
  ASSERT_EQ(f.size(), 1u);
  EXPECT_NE(f[0].find("'free' is read as list but described as true/false"), std::string::npos);
}

TEST(KeyReference, MarkdownHasOneTablePerSectionAndTheSharedTables) {
  std::ostringstream out;
  small_reference().print_markdown(out);
  const std::string md = out.str();
  EXPECT_NE(md.find("### `material`"), std::string::npos);
  EXPECT_NE(md.find("| `material.density` | quantity | kg/m^3 | required | > 0 | density |  |"), std::string::npos);
  EXPECT_NE(md.find("| `material.scaling` | quantity | - | `0.5` |"), std::string::npos);
  EXPECT_NE(md.find("| `groups.motion` | choice |  | `free` | `free`, `frozen` |"), std::string::npos);
  EXPECT_NE(md.find("### Shared: region"), std::string::npos);
}

TEST(ColumnTable, HeaderExpandsPatternsEntryByEntryAndHonoursConditions) {
  const ColumnTable t{"t.csv", "", {{"step", "-", "", ""},
                                    {"<g>_fx", "N", "", ""},
                                    {"<g>_fz", "N", "", "3D"},
                                    {"<w>_d", "m", "", ""}}};
  EXPECT_EQ(t.header({{"g", {"top", "bottom"}}, {"w", {"left"}}}, {"3D"}),
            (std::vector<std::string>{"step", "top_fx", "top_fz", "bottom_fx", "bottom_fz", "left_d"}));
  EXPECT_EQ(t.header({{"g", {"top"}}, {"w", {}}}),
            (std::vector<std::string>{"step", "top_fx"}));
  EXPECT_THROW(t.header(), std::logic_error);
}

}  // namespace
}  // namespace debris
