#include "core/region.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>
#include <stdexcept>

#include "core/box.hpp"
#include "core/error.hpp"
#include "core/io/input.hpp"
#include "core/io/key_reference.hpp"
#include "core/memory_budget.hpp"
#include "core/rough/height_field.hpp"
#include "core/rough/height_map_file.hpp"
#include "core/rough/self_affine_input.hpp"
#include "core/rough/self_affine_surface.hpp"

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

std::string join_key(const std::string& path, const std::string& key) { return path.empty() ? key : path + "." + key; }

// Grid points along one in-plane axis: the fewest whose spacing is at most `spacing`.
int grid_points(double length, double spacing) {
  return std::max(1, static_cast<int>(std::ceil(length / spacing * (1 - 1e-12))));
}

// `path` = the surface's map ("remove[0].surface"); the field of a self-affine spec over the box.
HeightField self_affine_field(const InputNode& n, const std::string& path, const Box& box, int normal,
                              std::string& made_by, double& shortest, std::string& shortest_key) {
  const InputNode sa = n.child("self_affine");
  const SelfAffineSpec spec = read_self_affine_spec(sa);
  const std::string sa_path = join_key(path, "self_affine");
  // Checked before any grid is made: a field taller than the box cannot be carved in it, whatever its shape.
  if (spec.rms_height > box.length(normal))
    throw input_error(join_key(sa_path, "rms_height"), format_value(spec.rms_height),
                      std::string("a surface that does not fit the box: the rms height exceeds the box's ") +
                          "xyz"[normal] + " length " + format_value(box.length(normal)));
  const double grid_spacing = n.quantity("grid_spacing", units::length, spec.cutoff_wavelength / 4);
  if (!(grid_spacing > 0.0) || !std::isfinite(grid_spacing))
    throw input_error(join_key(path, "grid_spacing"), format_value(grid_spacing), "must be a length > 0");
  HeightField axes;
  axes.normal_axis = normal;
  const int a = axes.axis_a(), b = axes.axis_b();
  const double na = std::ceil(box.length(a) / grid_spacing), nb = std::ceil(box.length(b) / grid_spacing);
  const std::string shown = format_value(grid_spacing) + " (" + format_value(na) + " x " + format_value(nb) + " points)";
  if (na * nb > 1e9)
    throw input_error(join_key(path, "grid_spacing"), shown, "makes more grid points than debris generates");
  // The field, its spectrum and the random numbers: about 40 bytes a point.
  check_memory(join_key(path, "grid_spacing"), shown, na * nb, 40.0, "grid point");
  const int n_a = grid_points(box.length(a), grid_spacing), n_b = grid_points(box.length(b), grid_spacing);
  HeightField f;
  try {
    f = generate_self_affine(spec, normal, comp(box.lo(), a), comp(box.lo(), b), box.length(a), box.length(b), n_a, n_b);
  } catch (const std::invalid_argument& e) {
    throw input_error(sa_path, "{hurst: " + format_value(spec.hurst) + ", rms_height: " + format_value(spec.rms_height) +
                                   ", cutoff_wavelength: " + format_value(spec.cutoff_wavelength) + "}",
                      std::string("the surface cannot be generated: ") + e.what());
  }
  std::ostringstream os;
  os << "self-affine H " << format_value(spec.hurst) << ", cutoff wavelength " << format_value(spec.cutoff_wavelength)
     << ", seed " << spec.seed << ", grid " << n_a << " x " << n_b;
  made_by = os.str();
  shortest = spec.cutoff_wavelength;
  shortest_key = join_key(sa_path, "cutoff_wavelength");
  return f;
}

// The field of a measured map, which must cover the box's in-plane lengths at its spacing.
HeightField height_map_field(const InputNode& n, const std::string& path, const Box& box, int normal,
                             const std::string& base_directory, std::string& made_by, double& shortest,
                             std::string& shortest_key) {
  const InputNode m = n.child("height_map");
  const std::string m_path = join_key(path, "height_map");
  const std::string given = m.string("file");
  std::filesystem::path file = given;
  if (file.is_relative() && !base_directory.empty()) file = std::filesystem::path(base_directory) / file;
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec))
    throw input_error(join_key(m_path, "file"), given,
                      std::string(std::filesystem::exists(file, ec) ? "is not a file" : "no such file") + " (looked for at " +
                          file.lexically_normal().string() +
                          (std::filesystem::path(given).is_relative() && !base_directory.empty()
                               ? "; a relative path is taken from the input file's folder"
                               : "") +
                          ")");
  const std::vector<double> spacing = m.numbers("spacing", units::length);
  const std::string spacing_key = join_key(m_path, "spacing");
  if (spacing.empty() || spacing.size() > 2)
    throw input_error(spacing_key, std::to_string(spacing.size()) + " values", "give [along a, along b] or one spacing for both");
  for (double s : spacing)
    if (!(s > 0.0) || !std::isfinite(s)) throw input_error(spacing_key, format_value(s), "must be lengths > 0");
  const double sa = spacing[0], sb = spacing.back();
  double unit = 1;
  if (m.has("unit")) {
    const std::string u = m.string("unit");
    unit = units::parse("1 " + u, units::length, join_key(m_path, "unit"));
  }
  HeightField f = read_height_map(file.string(), normal, sa, sb, unit);
  const int a = f.axis_a(), b = f.axis_b();
  // The map must tile the box: its extent is the box's in-plane lengths (a profile's only along a).
  const double cover_a = f.n_a * sa, cover_b = f.n_b * sb;
  const bool fits_a = std::abs(cover_a - box.length(a)) <= 1e-6 * box.length(a);
  const bool fits_b = f.n_b == 1 || std::abs(cover_b - box.length(b)) <= 1e-6 * box.length(b);
  if (!fits_a || !fits_b)
    throw input_error(spacing_key, "[" + format_value(sa) + ", " + format_value(sb) + "]",
                      "the map's " + std::to_string(f.n_a) + " x " + std::to_string(f.n_b) + " points cover " +
                          format_value(cover_a) + " x " + (f.n_b == 1 ? std::string("(a profile)") : format_value(cover_b)) +
                          ", but a surface spans the box's " + "xyz"[a] + " x " + "xyz"[b] + " lengths " +
                          format_value(box.length(a)) + " x " + format_value(box.length(b)));
  f.normal_axis = normal;
  f.origin_a = comp(box.lo(), a);
  f.origin_b = comp(box.lo(), b);
  f.length_a = box.length(a);
  f.length_b = box.length(b);
  if (f.rms_height() > box.length(normal))
    throw input_error(join_key(m_path, "file"), given,
                      "a surface that does not fit the box: its rms height " + format_value(f.rms_height()) +
                          " exceeds the box's " + "xyz"[normal] + " length " + format_value(box.length(normal)));
  made_by = "height map " + given + ", " + std::to_string(f.n_a) + " x " + std::to_string(f.n_b) + " points";
  shortest = 2 * (f.n_b == 1 ? sa : std::max(sa, sb));
  shortest_key = spacing_key;
  return f;
}

Region read_surface(const InputNode& n, const std::string& path, const Box* box, const std::string& base_directory) {
  if (!box)
    throw input_error(path, "a surface",
                      "a surface region needs the simulation box (its field spans the box's in-plane lengths), and "
                      "none is known where this region is read");
  const std::string nm = n.choice("normal", {"x", "y", "z"});
  const int normal = nm == "x" ? 0 : (nm == "y" ? 1 : 2);
  const bool below = n.choice("side", {"below", "above"}) == "below";
  const double at = n.quantity("at", units::length);
  if (!std::isfinite(at)) throw input_error(join_key(path, "at"), format_value(at), "must be a finite length");
  const bool sa = n.has("self_affine"), hm = n.has("height_map");
  if (sa == hm)
    throw input_error(path, sa ? "self_affine and height_map" : "neither self_affine nor height_map",
                      "give exactly one of 'self_affine' (a generated surface) or 'height_map' (a measured one)");
  std::string made_by, shortest_key;
  double shortest = 0;
  HeightField f = sa ? self_affine_field(n, path, *box, normal, made_by, shortest, shortest_key)
                     : height_map_field(n, path, *box, normal, base_directory, made_by, shortest, shortest_key);
  // `at` is where the mean height sits.
  const double shift = at - f.mean();
  for (double& v : f.h) v += shift;
  const auto [lo, hi] = std::minmax_element(f.h.begin(), f.h.end());
  const double box_lo = comp(box->lo(), normal), box_hi = comp(box->hi(), normal);
  if (*lo < box_lo || *hi > box_hi)
    throw input_error(join_key(path, "at"), format_value(at),
                      std::string("a surface that does not fit the box: its heights span ") + interval(*lo, *hi) +
                          ", outside the box's " + "xyz"[normal] + " extent " + interval(box_lo, box_hi));
  return Region::surface(std::make_shared<const HeightField>(std::move(f)), below, made_by, shortest, shortest_key);
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

Region Region::surface(std::shared_ptr<const HeightField> field, bool below, std::string made_by,
                       double shortest_wavelength, std::string shortest_wavelength_key) {
  Region r;
  r.kind = Kind::surface;
  r.axis = field->normal_axis;
  r.field = std::move(field);
  r.below = below;
  r.made_by = std::move(made_by);
  r.shortest_wavelength = shortest_wavelength;
  r.shortest_wavelength_key = std::move(shortest_wavelength_key);
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
    case Kind::surface: {
      const double h = field->height_under(p);
      return below ? comp(p, axis) < h : comp(p, axis) >= h;
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

std::vector<const Region*> Region::surfaces() const {
  std::vector<const Region*> out;
  if (kind == Kind::surface) out.push_back(this);
  for (const Region& r : parts) {
    const std::vector<const Region*> inner = r.surfaces();
    out.insert(out.end(), inner.begin(), inner.end());
  }
  return out;
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
    case Kind::surface:
      os << "surface normal " << "xyz"[axis] << " " << (below ? "below" : "above") << " at "
         << format_value(field->mean()) << " (rms height " << format_value(field->rms_height());
      if (!made_by.empty()) os << ", " << made_by;
      os << ")";
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

void check_surface_resolution(const Region& region, double largest_diameter) {
  for (const Region* s : region.surfaces()) {
    if (!(s->shortest_wavelength < 2 * largest_diameter)) continue;
    const bool map = s->shortest_wavelength_key.ends_with(".spacing");
    throw input_error(s->shortest_wavelength_key,
                      map ? format_value(s->shortest_wavelength / 2) + " (a shortest wavelength of twice that, " +
                                format_value(s->shortest_wavelength) + ")"
                          : format_value(s->shortest_wavelength),
                      "a rough surface whose shortest wavelength " + format_value(s->shortest_wavelength) +
                          " is below two particle diameters (2 x " + format_value(largest_diameter) + " = " +
                          format_value(2 * largest_diameter) +
                          ", the largest particles) cannot be carved by spheres: particle centres would cut its "
                          "bumps into steps one particle wide. Use a longer wavelength or smaller particles");
  }
}

double read_bound(const InputNode& n) {
  const std::string t = n.text();
  if (t == "-inf" || t == "min") return -kInf;
  if (t == "inf" || t == "+inf" || t == "max") return kInf;
  return n.quantity(units::length);
}

Region read_region(const InputNode& node, const Box* box, const std::string& base_directory) {
  if (!node.is_map())
    throw input_error(node.path(), node.is_sequence() ? "a list" : node.text(),
                      "a region is a map: {block: {...}}, {cylinder: {...}}, {surface: {...}}, {union: [...]} or "
                      "{difference: [...]}");
  const char* forms[] = {"block", "cylinder", "surface", "union", "difference"};
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
                      "a region is one of block, cylinder, surface, union, difference (or x/y/z bounds of a block)");
  }
  if (form == "block") return read_block(node.child("block"));
  if (form == "cylinder") return read_cylinder(node.child("cylinder"), box);
  if (form == "surface") return read_surface(node.child("surface"), join_key(node.path(), "surface"), box, base_directory);
  std::vector<Region> parts;
  for (const InputNode& p : node.list(form)) parts.push_back(read_region(p, box, base_directory));
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
                       "A region is one of five forms, each a map with one key. Bounds are lengths; `-inf`/`min` "
                       "and `inf`/`max` leave a side open. Containment is tested on positions wrapped into the "
                       "box, without images (a surface's heights are periodic with the box's in-plane lengths, so "
                       "it continues across the periodic faces); a block's `x`, `y`, `z` may also stand directly in "
                       "the region's map.",
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
  ref.key("surface", t).is(KeyKind::section).fallback_is("one form per region")
      .means("the space below (or above) a rough surface along its normal axis: a generated self-affine "
             "surface or a measured height map, spanning the box's two in-plane lengths and periodic with them. "
             "Carving particles (remove, labels, groups) needs its shortest wavelength to be at least two "
             "particle diameters");
  ref.key("surface.normal", t).one_of({"x", "y", "z"}).means("the surface's normal axis: heights are along it");
  ref.key("surface.side", t).one_of({"below", "above"})
      .means("which side is inside: below, the points under the surface; above, the points on or over it");
  ref.key("surface.at", t).is(KeyKind::quantity).in(units::length)
      .allowed("the surface's lowest and highest points inside the box")
      .means("where the surface's mean height sits along the normal");
  ref.key("surface.grid_spacing", t).is(KeyKind::quantity).in(units::length)
      .fallback_is("a quarter of self_affine.cutoff_wavelength").allowed("> 0, at most half the cutoff wavelength")
      .means("the generated surface's grid spacing (the grid spans the box; heights are bilinear between points)");
  ref.key("surface.self_affine", t).is(KeyKind::section).follows("self_affine")
      .fallback_is("one of self_affine or height_map")
      .means("a self-affine random surface over the box's in-plane lengths, its keys in the table self_affine");
  ref.key("surface.height_map", t).is(KeyKind::section).fallback_is("one of self_affine or height_map")
      .means("a measured height map: a text grid of heights, one row per line along the first in-plane axis, "
             "covering the box's in-plane lengths at its spacing");
  ref.key("surface.height_map.file", t).is(KeyKind::text)
      .means("the map's file; a relative path is taken from the input file's folder");
  ref.key("surface.height_map.spacing", t).is(KeyKind::numbers).in(units::length)
      .allowed("[along a, along b] or one value, > 0; points x spacing = the box's in-plane lengths")
      .means("the map's grid spacing along the two in-plane axes (a, b: the other two axes in increasing order)");
  ref.key("surface.height_map.unit", t).is(KeyKind::text).fallback_is("none: the heights are taken as given")
      .allowed("a length unit: m, um, nm, ...").means("the unit of the heights in the file");
  ref.key("union", t).is(KeyKind::list).follows(t).fallback_is("one form per region")
      .allowed("at least one region").means("the points inside any of the listed regions");
  ref.key("difference", t).is(KeyKind::list).follows(t).fallback_is("one form per region")
      .allowed("two or more regions").means("the points of the first region that are in none of the others");
  document_self_affine(ref, "self_affine");
}

}  // namespace debris
