#include "core/region.hpp"

#include <cmath>
#include <sstream>

#include "core/box.hpp"
#include "core/error.hpp"
#include "core/io/input.hpp"
#include "core/io/key_reference.hpp"

namespace debris {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

double comp(Vec3 v, int a) { return a == 0 ? v.x : (a == 1 ? v.y : v.z); }

// Appended piece by piece: GCC 12 warns falsely (-Wrestrict) on "[" + std::string at -O3.
std::string interval(double lo, double hi) {
  std::string s = "[";
  s += format_value(lo);
  s += ", ";
  s += format_value(hi);
  s += "]";
  return s;
}

// [lo, hi] from a two-element list of bounds; hi must exceed lo.
void read_interval(const InputNode& parent, const std::string& key, double& lo, double& hi) {
  const std::vector<InputNode> b = parent.list(key);
  const std::string path = parent.path().empty() ? key : parent.path() + "." + key;
  if (b.size() != 2) throw input_error(path, std::to_string(b.size()) + " values", "give [lo, hi]");
  lo = read_bound(b[0]);
  hi = read_bound(b[1]);
  if (!(hi > lo)) throw input_error(path, interval(lo, hi), "hi must exceed lo");
}

Region read_block(const InputNode& n) {
  Region r;
  for (int a = 0; a < 3; ++a) {
    const std::string ax(1, "xyz"[a]);
    if (n.has(ax)) read_interval(n, ax, r.lo[a], r.hi[a]);
  }
  return r;
}

Region read_cylinder(const InputNode& n, const Box* box) {
  const std::string ax = n.choice("axis", {"x", "y", "z"});
  const int axis = ax == "x" ? 0 : (ax == "y" ? 1 : 2);
  const Vec3 centre = n.vec3("centre", units::length);
  const double radius = n.quantity("radius", units::length);
  if (!(radius > 0.0) || !std::isfinite(radius))
    throw input_error(n.path() + ".radius", format_value(radius), "must be a length > 0");
  double lo = -kInf, hi = kInf;
  if (n.has("extent")) read_interval(n, "extent", lo, hi);
  if (box) {
    // Containment is tested on wrapped positions without images (region.hpp), so a cylinder wider than
    // the box along an axis across it cannot be meant: most likely a unit or a radius/diameter slip.
    for (int a = 0; a < 3; ++a) {
      if (a == axis || !(2.0 * radius > box->length(a))) continue;
      throw input_error(n.path() + ".radius", format_value(radius),
                        std::string("the cylinder is larger than the box: its diameter ") + format_value(2.0 * radius) +
                            " exceeds the box's " + "xyz"[a] + " length " + format_value(box->length(a)));
    }
  }
  return Region::cylinder(axis, centre, radius, lo, hi);
}

}  // namespace

Region::Region() {
  for (int a = 0; a < 3; ++a) lo[a] = -kInf, hi[a] = kInf;
}

Region Region::block(Vec3 l, Vec3 h) {
  Region r;
  for (int a = 0; a < 3; ++a) r.lo[a] = comp(l, a), r.hi[a] = comp(h, a);
  return r;
}

Region Region::cylinder(int axis, Vec3 centre, double radius, double lo, double hi) {
  Region r;
  r.kind = Kind::cylinder;
  r.axis = axis;
  r.centre = centre;
  r.radius = radius;
  r.lo[axis] = lo;
  r.hi[axis] = hi;
  return r;
}

Region Region::union_of(std::vector<Region> parts) {
  Region r;
  r.kind = Kind::union_of;
  r.parts = std::move(parts);
  return r;
}

Region Region::difference(std::vector<Region> parts) {
  Region r;
  r.kind = Kind::difference;
  r.parts = std::move(parts);
  return r;
}

bool Region::contains(Vec3 p) const {
  switch (kind) {
    case Kind::block:
      for (int a = 0; a < 3; ++a) {
        const double c = comp(p, a);
        if (!(c >= lo[a] && c < hi[a])) return false;
      }
      return true;
    case Kind::cylinder: {
      const double c = comp(p, axis);
      if (!(c >= lo[axis] && c < hi[axis])) return false;
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      const double du = comp(p, u) - comp(centre, u), dv = comp(p, v) - comp(centre, v);
      return du * du + dv * dv <= radius * radius;
    }
    case Kind::union_of:
      for (const Region& r : parts)
        if (r.contains(p)) return true;
      return false;
    case Kind::difference:
      if (parts.empty() || !parts[0].contains(p)) return false;
      for (std::size_t k = 1; k < parts.size(); ++k)
        if (parts[k].contains(p)) return false;
      return true;
  }
  return false;
}

std::string Region::describe() const {
  std::ostringstream os;
  switch (kind) {
    case Kind::block: {
      os << "block";
      bool any = false;
      for (int a = 0; a < 3; ++a) {
        if (lo[a] == -kInf && hi[a] == kInf) continue;
        os << " " << "xyz"[a] << " " << interval(lo[a], hi[a]);
        any = true;
      }
      if (!any) os << " (all space)";
      break;
    }
    case Kind::cylinder:
      os << "cylinder axis " << "xyz"[axis] << " centre [" << format_value(centre.x) << ", " << format_value(centre.y)
         << ", " << format_value(centre.z) << "] radius " << format_value(radius) << " extent "
         << interval(lo[axis], hi[axis]);
      break;
    case Kind::union_of:
    case Kind::difference:
      os << (kind == Kind::union_of ? "union of (" : "difference of (");
      for (std::size_t k = 0; k < parts.size(); ++k) os << (k ? "; " : "") << parts[k].describe();
      os << ")";
      break;
  }
  return os.str();
}

double read_bound(const InputNode& n) {
  const std::string t = n.text();
  if (t == "-inf" || t == "min") return -kInf;
  if (t == "inf" || t == "+inf" || t == "max") return kInf;
  return n.quantity(units::length);
}

Region read_region(const InputNode& node, const Box* box) {
  if (!node.is_map())
    throw input_error(node.path(), node.is_sequence() ? "a list" : node.text(),
                      "a region is a map: {block: {...}}, {cylinder: {...}}, {union: [...]} or {difference: [...]}");
  const char* forms[] = {"block", "cylinder", "union", "difference"};
  std::string form;
  for (const char* f : forms) {
    if (!node.has(f)) continue;
    if (!form.empty())
      throw input_error(node.path(), form + " and " + f, "give one form per region (combine them with union)");
    form = f;
  }
  if (form.empty()) {
    // The groups' older form: the block's axes directly.
    if (node.has("x") || node.has("y") || node.has("z") || node.keys().empty()) return read_block(node);
    throw input_error(node.path(), node.keys().front(),
                      "a region is one of block, cylinder, union, difference (or x/y/z bounds of a block)");
  }
  if (form == "block") return read_block(node.child("block"));
  if (form == "cylinder") return read_cylinder(node.child("cylinder"), box);
  std::vector<Region> parts;
  for (const InputNode& p : node.list(form)) parts.push_back(read_region(p, box));
  const std::string path = (node.path().empty() ? "" : node.path() + ".") + form;
  if (parts.empty()) throw input_error(path, "[]", "give at least one region");
  if (form == "difference" && parts.size() < 2)
    throw input_error(path, std::to_string(parts.size()) + " region",
                      "give the region to cut from, then one or more regions to cut out of it");
  return form == "union" ? Region::union_of(std::move(parts)) : Region::difference(std::move(parts));
}

void document_regions(KeyReference& ref) {
  const std::string t = "region";
  ref.describe_section("",
                       "A region is one of four forms, each a map with one key. Bounds are lengths; `-inf`/`min` "
                       "and `inf`/`max` leave a side open. Containment is tested on positions wrapped into the "
                       "box, without images; a block's `x`, `y`, `z` may also stand directly in the region's map.",
                       t);
  ref.key("block", t).is(KeyKind::section).fallback_is("one form per region")
      .means("an axis-aligned block: the points with lo <= x < hi on each axis given");
  for (const char* axis : {"x", "y", "z"})
    ref.key(std::string("block.") + axis, t).is(KeyKind::numbers).in(units::length).fallback_is("all of the axis")
        .allowed("[lo, hi], hi > lo").means(std::string("the block's bounds along ") + axis);
  for (const char* axis : {"x", "y", "z"})
    ref.key(axis, t).is(KeyKind::numbers).in(units::length).fallback_is("all of the axis")
        .allowed("[lo, hi], hi > lo").means(std::string("a block's bounds along ") + axis + ", given without `block:`");
  ref.key("cylinder", t).is(KeyKind::section).fallback_is("one form per region")
      .means("a circular cylinder: the points within `radius` of its axis line");
  ref.key("cylinder.axis", t).one_of({"x", "y", "z"}).means("the direction of the cylinder's axis");
  ref.key("cylinder.centre", t).is(KeyKind::vector).in(units::length).means("a point of the axis line");
  ref.key("cylinder.radius", t).is(KeyKind::quantity).in(units::length)
      .allowed("> 0, diameter at most the box across the axis").means("the cylinder's radius");
  ref.key("cylinder.extent", t).is(KeyKind::numbers).in(units::length).fallback_is("unbounded along the axis")
      .allowed("[lo, hi], hi > lo").means("the cylinder's bounds along its axis");
  ref.key("union", t).is(KeyKind::list).follows(t).fallback_is("one form per region")
      .allowed("at least one region").means("the points inside any of the listed regions");
  ref.key("difference", t).is(KeyKind::list).follows(t).fallback_is("one form per region")
      .allowed("two or more regions").means("the points of the first region that are in none of the others");
}

}  // namespace debris
