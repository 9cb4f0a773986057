#include "scenarios/common/peridem/shape_mesh.hpp"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <initializer_list>
#include <numbers>
#include <vector>

#include "core/error.hpp"
#include "core/io/text_format.hpp"
#include "scenarios/common/peridem/gmsh_api.hpp"

#if DEBRIS_HAVE_GMSH_API
#include <gmsh.h>
#endif

namespace debris {

const char* shape_name(Shape shape) {
  switch (shape) {
    case Shape::circle:
      return "circle";
    case Shape::hexagon:
      return "hexagon";
    case Shape::concave_polygon:
      return "concave_polygon";
    case Shape::rectangle:
      return "rectangle";
    case Shape::rectangle_minus_rectangle:
      return "rectangle_minus_rectangle";
    case Shape::sphere:
      return "sphere";
    case Shape::box:
      return "box";
  }
  return "unknown shape";
}

int shape_dimension(Shape shape) { return shape == Shape::sphere || shape == Shape::box ? 3 : 2; }

ShapeSpec ShapeSpec::make_circle(double R, double h, Vec3 centre) {
  ShapeSpec s;
  s.shape = Shape::circle;
  s.radius = R;
  s.mesh_size = h;
  s.centre = centre;
  return s;
}

ShapeSpec ShapeSpec::make_hexagon(double R, double h, Vec3 centre, Vec3 axis) {
  ShapeSpec s = make_circle(R, h, centre);
  s.shape = Shape::hexagon;
  s.axis = axis;
  return s;
}

ShapeSpec ShapeSpec::make_concave_polygon(double R, double w, double h, Vec3 centre, Vec3 axis) {
  ShapeSpec s = make_hexagon(R, h, centre, axis);
  s.shape = Shape::concave_polygon;
  s.neck_half_width = w;
  return s;
}

ShapeSpec ShapeSpec::make_rectangle(Vec3 lo, Vec3 hi, double h) {
  ShapeSpec s;
  s.shape = Shape::rectangle;
  s.lo = lo;
  s.hi = hi;
  s.mesh_size = h;
  return s;
}

ShapeSpec ShapeSpec::make_rectangle_minus_rectangle(Vec3 lo, Vec3 hi, Vec3 inner_lo, Vec3 inner_hi, double h) {
  ShapeSpec s = make_rectangle(lo, hi, h);
  s.shape = Shape::rectangle_minus_rectangle;
  s.inner_lo = inner_lo;
  s.inner_hi = inner_hi;
  return s;
}

ShapeSpec ShapeSpec::make_sphere(double R, double h, Vec3 centre) {
  ShapeSpec s = make_circle(R, h, centre);
  s.shape = Shape::sphere;
  return s;
}

ShapeSpec ShapeSpec::make_box(Vec3 lo, Vec3 hi, double h) {
  ShapeSpec s = make_rectangle(lo, hi, h);
  s.shape = Shape::box;
  return s;
}

namespace {

std::string vec_text(Vec3 v) {
  return "(" + format_value(v.x) + ", " + format_value(v.y) + ", " + format_value(v.z) + ")";
}

bool finite(Vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

std::string key(const ShapeSpec& s, const char* parameter) {
  return std::string(shape_name(s.shape)) + "." + parameter;
}

void require_positive(const ShapeSpec& s, const char* parameter, double v) {
  if (!(v > 0) || !std::isfinite(v))
    throw input_error(key(s, parameter), format_value(v), "must be a finite number > 0");
}

void require_finite(const ShapeSpec& s, const char* parameter, Vec3 v) {
  if (!finite(v)) throw input_error(key(s, parameter), vec_text(v), "must be finite");
}

/// A rectangle (2D: x and y extents, one plane z) or a box (3D) with lo < hi.
void require_extent(const ShapeSpec& s, const char* lo_name, Vec3 lo, const char* hi_name, Vec3 hi, int dim) {
  require_finite(s, lo_name, lo);
  require_finite(s, hi_name, hi);
  const double l[3] = {lo.x, lo.y, lo.z}, h[3] = {hi.x, hi.y, hi.z};
  for (int a = 0; a < dim; ++a)
    if (!(h[a] > l[a]))
      throw input_error(key(s, hi_name), vec_text(hi),
                        std::string("must exceed ") + lo_name + " = " + vec_text(lo) + " in " + char('x' + a));
  if (dim == 2 && hi.z != lo.z)
    throw input_error(
        key(s, hi_name), vec_text(hi),
        std::string("a 2D rectangle lies in one plane: z must equal ") + lo_name + ".z = " + format_value(lo.z));
}

/// The unit axis of a hexagon or concave polygon.
Vec3 unit_axis(const ShapeSpec& s) {
  require_finite(s, "axis", s.axis);
  if (s.axis.z != 0) throw input_error(key(s, "axis"), vec_text(s.axis), "must lie in the xy plane (z = 0)");
  const double n = std::hypot(s.axis.x, s.axis.y);
  if (!(n > 0)) throw input_error(key(s, "axis"), vec_text(s.axis), "must be a non-zero vector");
  return {s.axis.x / n, s.axis.y / n, 0.0};
}

/// rot(a, theta) about z.
Vec3 rotate_z(Vec3 a, double theta) {
  const double c = std::cos(theta), s = std::sin(theta);
  return {a.x * c - a.y * s, a.x * s + a.y * c, 0.0};
}

/// The polygon vertices of a hexagon or concave polygon, counter-clockwise, in PeriDEM's order.
[[maybe_unused]] std::vector<Vec3> polygon_vertices(const ShapeSpec& s) {
  const Vec3 a = unit_axis(s);
  const Vec3 c = s.centre;
  const double R = s.radius;
  std::vector<Vec3> v;
  if (s.shape == Shape::hexagon) {
    for (int k = 0; k < 6; ++k) v.push_back(c + R * rotate_z(a, k * std::numbers::pi / 3.0));
  } else {
    const double w = s.neck_half_width;
    const Vec3 v2 = c + R * rotate_z(a, std::numbers::pi / 3.0);
    const Vec3 v6 = c + R * rotate_z(a, -std::numbers::pi / 3.0);
    v = {c + w * a, v2, v2 - R * a, c - w * a, v6 - R * a, v6};
  }
  return v;
}

double overlap(double lo1, double hi1, double lo2, double hi2) {
  return std::max(0.0, std::min(hi1, hi2) - std::max(lo1, lo2));
}

[[maybe_unused]] std::vector<Vec3> rectangle_corners(Vec3 lo, Vec3 hi) {
  return {{lo.x, lo.y, lo.z}, {hi.x, lo.y, lo.z}, {hi.x, hi.y, lo.z}, {lo.x, hi.y, lo.z}};
}

}  // namespace

void validate_shape(const ShapeSpec& s) {
  require_positive(s, "mesh_size", s.mesh_size);
  switch (s.shape) {
    case Shape::circle:
    case Shape::sphere:
      require_positive(s, "radius", s.radius);
      require_finite(s, "centre", s.centre);
      break;
    case Shape::hexagon:
    case Shape::concave_polygon:
      require_positive(s, "radius", s.radius);
      require_finite(s, "centre", s.centre);
      unit_axis(s);
      if (s.shape == Shape::concave_polygon) {
        const double w = s.neck_half_width;
        if (!(w > 0 && w < 0.5 * s.radius))
          throw input_error(key(s, "neck_half_width"), format_value(w),
                            "must be in (0, R/2) = (0, " + format_value(0.5 * s.radius) +
                                ") for a concave polygon of radius R = " + format_value(s.radius) +
                                " (w = 0 closes the neck, w >= R/2 leaves no notch)");
      }
      break;
    case Shape::rectangle:
      require_extent(s, "lo", s.lo, "hi", s.hi, 2);
      break;
    case Shape::box:
      require_extent(s, "lo", s.lo, "hi", s.hi, 3);
      break;
    case Shape::rectangle_minus_rectangle: {
      require_extent(s, "lo", s.lo, "hi", s.hi, 2);
      require_extent(s, "inner_lo", s.inner_lo, "inner_hi", s.inner_hi, 2);
      if (s.inner_lo.z != s.lo.z)
        throw input_error(key(s, "inner_lo"), vec_text(s.inner_lo),
                          "must lie in the plane of lo, z = " + format_value(s.lo.z));
      const double cut =
          overlap(s.lo.x, s.hi.x, s.inner_lo.x, s.inner_hi.x) * overlap(s.lo.y, s.hi.y, s.inner_lo.y, s.inner_hi.y);
      if (!(cut > 0))
        throw input_error(
            key(s, "inner_lo"), vec_text(s.inner_lo),
            "the inner rectangle must overlap the outer one [" + vec_text(s.lo) + ", " + vec_text(s.hi) + "]");
      if (s.inner_lo.x <= s.lo.x && s.inner_lo.y <= s.lo.y && s.inner_hi.x >= s.hi.x && s.inner_hi.y >= s.hi.y)
        throw input_error(key(s, "inner_lo"), vec_text(s.inner_lo),
                          "the inner rectangle covers the outer one: nothing is left");
      break;
    }
  }
}

double shape_measure(const ShapeSpec& s) {
  validate_shape(s);
  const double R = s.radius;
  switch (s.shape) {
    case Shape::circle:
      return std::numbers::pi * R * R;
    case Shape::hexagon:
      return 1.5 * std::sqrt(3.0) * R * R;
    case Shape::concave_polygon:
      return std::sqrt(3.0) * R * (0.5 * R + s.neck_half_width);
    case Shape::rectangle:
      return (s.hi.x - s.lo.x) * (s.hi.y - s.lo.y);
    case Shape::rectangle_minus_rectangle:
      return (s.hi.x - s.lo.x) * (s.hi.y - s.lo.y) -
             overlap(s.lo.x, s.hi.x, s.inner_lo.x, s.inner_hi.x) * overlap(s.lo.y, s.hi.y, s.inner_lo.y, s.inner_hi.y);
    case Shape::sphere:
      return 4.0 / 3.0 * std::numbers::pi * R * R * R;
    case Shape::box:
      return (s.hi.x - s.lo.x) * (s.hi.y - s.lo.y) * (s.hi.z - s.lo.z);
  }
  return 0;
}

namespace {

#if DEBRIS_HAVE_GMSH_API
namespace geo = gmsh::model::geo;
namespace occ = gmsh::model::occ;

enum class Kernel { builtin, occ };

/// A closed polygon through points first..first+n-1 as lines first..first+n-1, its curve loop `loop`
/// (PeriDEM's wall scripts), in Gmsh's built-in kernel or OpenCASCADE's.
void add_polygon(Kernel kernel, const std::vector<Vec3>& v, int first, int loop, double h) {
  const int n = static_cast<int>(v.size());
  std::vector<int> lines;
  for (int k = 0; k < n; ++k) {
    const Vec3 p = v[static_cast<std::size_t>(k)];
    kernel == Kernel::occ ? occ::addPoint(p.x, p.y, p.z, h, first + k) : geo::addPoint(p.x, p.y, p.z, h, first + k);
  }
  for (int k = 0; k < n; ++k) {
    const int a = first + k, b = first + (k + 1) % n;
    kernel == Kernel::occ ? occ::addLine(a, b, a) : geo::addLine(a, b, a);
    lines.push_back(a);
  }
  kernel == Kernel::occ ? occ::addCurveLoop(lines, loop) : geo::addCurveLoop(lines, loop);
}

/// The shape as Gmsh geometry, in the current (empty) model, with physical group 1 holding what is meshed:
/// the same entities, tags and order as PeriDEM's .geo scripts (see the header), so that Gmsh meshes them
/// the same way.
void add_geometry(const ShapeSpec& s) {
  const double h = s.mesh_size;
  double max_size = 1e22;  // Gmsh's default: the point sizes alone set the mesh of the built-in shapes
  switch (s.shape) {
    case Shape::circle: {
      // PeriDEM's circle: centre, the four points on the axes, four quarter arcs, the centre embedded.
      const Vec3 c = s.centre;
      const double R = s.radius;
      geo::addPoint(c.x, c.y, c.z, h, 1);
      geo::addPoint(c.x + R, c.y, c.z, h, 2);
      geo::addPoint(c.x - R, c.y, c.z, h, 3);
      geo::addPoint(c.x, c.y + R, c.z, h, 4);
      geo::addPoint(c.x, c.y - R, c.z, h, 5);
      geo::addCircleArc(2, 1, 4, 1);
      geo::addCircleArc(4, 1, 3, 2);
      geo::addCircleArc(3, 1, 5, 3);
      geo::addCircleArc(5, 1, 2, 4);
      geo::addCurveLoop({2, 3, 4, 1}, 1);
      geo::addPlaneSurface({1}, 1);
      geo::synchronize();
      gmsh::model::mesh::embed(0, {1}, 2, 1);
      gmsh::model::addPhysicalGroup(2, {1}, 1);
      break;
    }
    case Shape::hexagon:
    case Shape::concave_polygon: {
      // PeriDEM's scripts: point 1 the centre, points 2..7 the vertices, lines 1..6 around them.
      geo::addPoint(s.centre.x, s.centre.y, s.centre.z, h, 1);
      const std::vector<Vec3> v = polygon_vertices(s);
      for (int k = 0; k < 6; ++k) {
        const Vec3 p = v[static_cast<std::size_t>(k)];
        geo::addPoint(p.x, p.y, p.z, h, k + 2);
      }
      for (int k = 0; k < 6; ++k) geo::addLine(k + 2, (k + 1) % 6 + 2, k + 1);
      geo::addCurveLoop({1, 2, 3, 4, 5, 6}, 1);
      geo::addPlaneSurface({1}, 1);
      geo::synchronize();
      gmsh::model::mesh::embed(0, {1}, 2, 1);
      gmsh::model::addPhysicalGroup(2, {1}, 1);
      break;
    }
    case Shape::rectangle:
      // PeriDEM's wall script: four corner points carrying h.
      add_polygon(Kernel::builtin, rectangle_corners(s.lo, s.hi), 1, 1, h);
      geo::addPlaneSurface({1}, 1);
      geo::synchronize();
      gmsh::model::addPhysicalGroup(2, {1}, 1);
      break;
    case Shape::rectangle_minus_rectangle: {
      add_polygon(Kernel::occ, rectangle_corners(s.lo, s.hi), 1, 1, h);
      occ::addPlaneSurface({1}, 1);
      add_polygon(Kernel::occ, rectangle_corners(s.inner_lo, s.inner_hi), 5, 2, h);
      occ::addPlaneSurface({2}, 2);
      // The difference may come in pieces (an inner rectangle across the outer one): keep them all.
      gmsh::vectorpair pieces;
      std::vector<gmsh::vectorpair> map;
      occ::cut({{2, 1}}, {{2, 2}}, pieces, map, -1, true, true);
      occ::synchronize();
      std::vector<int> surfaces;
      for (const auto& [dim, tag] : pieces) surfaces.push_back(tag);
      gmsh::model::addPhysicalGroup(2, surfaces, 1);
      max_size = h;
      break;
    }
    case Shape::sphere:
    case Shape::box:
      if (s.shape == Shape::sphere) {
        occ::addSphere(s.centre.x, s.centre.y, s.centre.z, s.radius, 1);
      } else {
        // OpenCASCADE's box is corner plus lengths: the far corner is lo + (hi - lo), exact to round-off.
        occ::addBox(s.lo.x, s.lo.y, s.lo.z, s.hi.x - s.lo.x, s.hi.y - s.lo.y, s.hi.z - s.lo.z, 1);
      }
      occ::synchronize();
      gmsh::model::addPhysicalGroup(3, {1}, 1);
      max_size = h;
      break;
  }
  gmsh::option::setNumber("Mesh.CharacteristicLengthMax", max_size);
}
#endif

/// Every number of the spec at 17 digits: what names the cached mesh file.
std::string spec_text(const ShapeSpec& s) {
  std::string t = shape_name(s.shape);
  for (const double x : {s.mesh_size, s.radius, s.neck_half_width, s.centre.x, s.centre.y, s.centre.z, s.axis.x,
                         s.axis.y, s.axis.z, s.lo.x, s.lo.y, s.lo.z, s.hi.x, s.hi.y, s.hi.z, s.inner_lo.x,
                         s.inner_lo.y, s.inner_lo.z, s.inner_hi.x, s.inner_hi.y, s.inner_hi.z}) {
    t += ' ';
    append_number(t, x);
  }
  return t;
}

/// FNV-1a: a stable hash (std::hash is not) that names the cached files.
std::uint64_t fnv1a(const std::string& text) {
  std::uint64_t hash = 14695981039346656037ull;
  for (const unsigned char c : text) {
    hash ^= c;
    hash *= 1099511628211ull;
  }
  return hash;
}

}  // namespace

SimplexMesh mesh_shape(const ShapeSpec& spec, const GmshRun& run) {
  namespace fs = std::filesystem;
  if (run.msh_version != 22 && run.msh_version != 41)
    throw input_error("gmsh.msh_version", std::to_string(run.msh_version), "must be 22 or 41 (MSH 2.2 or 4.1)");
  if (run.directory.empty()) throw input_error("gmsh.directory", "\"\"", "must name a directory for the mesh files");
  validate_shape(spec);
  const int dim = shape_dimension(spec.shape);

  std::error_code ec;
  fs::create_directories(run.directory, ec);
  if (ec) throw output_error(run.directory, "cannot create the mesh directory (gmsh.directory): " + ec.message());
  char hash[17];
  std::snprintf(hash, sizeof hash, "%016llx",
                static_cast<unsigned long long>(fnv1a(spec_text(spec) + " msh" + std::to_string(run.msh_version) +
                                                      " gmsh " + gmsh_version())));
  const fs::path base = fs::path(run.directory) / (std::string(shape_name(spec.shape)) + "-" + hash);
  const fs::path msh = base.string() + ".msh";
  if (run.reuse && fs::exists(msh)) return read_gmsh_msh(msh.string());

  // A private name while Gmsh writes, renamed into place when the mesh has been read back, so concurrent
  // runs never read half a file.
  const fs::path tmp = base.string() + ".tmp" + std::to_string(getpid()) + ".msh";
  const std::string what = std::string(shape_name(spec.shape)) + " mesh " + msh.string();
  with_gmsh("gmsh", what, [&] {
#if DEBRIS_HAVE_GMSH_API
    add_geometry(spec);
    gmsh::model::mesh::generate(dim);
    gmsh::option::setNumber("Mesh.MshFileVersion", run.msh_version == 22 ? 2.2 : 4.1);
    gmsh::write(tmp.string());
#endif
  });
  // The mesh is the file's, read back: a run that meshes the shape and one that reuses the file get the same
  // bits (Gmsh writes 16 significant digits, so a node read back may differ from Gmsh's own in the last bit).
  SimplexMesh mesh;
  try {
    mesh = read_gmsh_msh(tmp.string());
  } catch (const InputError& e) {
    throw input_error("gmsh", what, std::string("Gmsh wrote a mesh that cannot be used (") + e.what() + ")");
  }
  if (mesh.dimension != dim)
    throw input_error("gmsh", what,
                      "Gmsh made a mesh of dimension " + std::to_string(mesh.dimension) + ", not " + std::to_string(dim));
  fs::rename(tmp, msh, ec);
  if (ec) throw output_error(run.directory, "cannot rename " + tmp.string() + " there: " + ec.message());
  return mesh;
}

}  // namespace debris
