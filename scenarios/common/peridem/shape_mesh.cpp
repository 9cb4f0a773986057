#include "scenarios/common/peridem/shape_mesh.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <numbers>
#include <sstream>
#include <vector>

#include "core/error.hpp"
#include "core/io/text_format.hpp"

extern char** environ;

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
std::vector<Vec3> polygon_vertices(const ShapeSpec& s) {
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

void append_point(std::string& geo, int tag, Vec3 p, double h) {
  geo += "Point(" + std::to_string(tag) + ") = {";
  append_number(geo, p.x);
  geo += ", ";
  append_number(geo, p.y);
  geo += ", ";
  append_number(geo, p.z);
  geo += ", ";
  append_number(geo, h);
  geo += "};\n";
}

/// A closed polygon through points first..first+n-1 as lines first..first+n-1, its curve loop `loop`.
void append_polygon(std::string& geo, const std::vector<Vec3>& v, int first, int loop, double h) {
  const int n = static_cast<int>(v.size());
  for (int k = 0; k < n; ++k) append_point(geo, first + k, v[static_cast<std::size_t>(k)], h);
  std::string lines;
  for (int k = 0; k < n; ++k) {
    geo += "Line(" + std::to_string(first + k) + ") = {" + std::to_string(first + k) + ", " +
           std::to_string(first + (k + 1) % n) + "};\n";
    lines += (k ? ", " : "") + std::to_string(first + k);
  }
  geo += "Curve Loop(" + std::to_string(loop) + ") = {" + lines + "};\n";
}

void append_list(std::string& geo, const char* head, std::initializer_list<double> values) {
  geo += head;
  bool first = true;
  for (const double x : values) {
    if (!first) geo += ", ";
    append_number(geo, x);
    first = false;
  }
  geo += "};\n";
}

std::vector<Vec3> rectangle_corners(Vec3 lo, Vec3 hi) {
  return {{lo.x, lo.y, lo.z}, {hi.x, lo.y, lo.z}, {hi.x, hi.y, lo.z}, {lo.x, hi.y, lo.z}};
}

std::string header(const ShapeSpec& s) {
  std::string geo = "// debris reference mesh: ";
  geo += shape_name(s.shape);
  geo += ", mesh size ";
  append_number(geo, s.mesh_size);
  geo += "\n";
  return geo;
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

std::string shape_geo(const ShapeSpec& s) {
  validate_shape(s);
  const double h = s.mesh_size;
  std::string geo = header(s);
  switch (s.shape) {
    case Shape::circle: {
      // PeriDEM's circle: centre, the four points on the axes, four quarter arcs, the centre embedded.
      const Vec3 c = s.centre;
      const double R = s.radius;
      append_point(geo, 1, c, h);
      append_point(geo, 2, c + Vec3{R, 0, 0}, h);
      append_point(geo, 3, c + Vec3{-R, 0, 0}, h);
      append_point(geo, 4, c + Vec3{0, R, 0}, h);
      append_point(geo, 5, c + Vec3{0, -R, 0}, h);
      geo += "Circle(1) = {2, 1, 4};\nCircle(2) = {4, 1, 3};\nCircle(3) = {3, 1, 5};\nCircle(4) = {5, 1, 2};\n";
      geo += "Curve Loop(1) = {2, 3, 4, 1};\nPlane Surface(1) = {1};\nPoint{1} In Surface {1};\n";
      geo += "Physical Surface(1) = {1};\n";
      break;
    }
    case Shape::hexagon:
    case Shape::concave_polygon: {
      // PeriDEM's scripts: point 1 the centre, points 2..7 the vertices, lines 1..6 around them.
      append_point(geo, 1, s.centre, h);
      const std::vector<Vec3> v = polygon_vertices(s);
      for (int k = 0; k < 6; ++k) append_point(geo, k + 2, v[static_cast<std::size_t>(k)], h);
      for (int k = 0; k < 6; ++k)
        geo += "Line(" + std::to_string(k + 1) + ") = {" + std::to_string(k + 2) + ", " +
               std::to_string((k + 1) % 6 + 2) + "};\n";
      geo += "Curve Loop(1) = {1, 2, 3, 4, 5, 6};\nPlane Surface(1) = {1};\nPoint{1} In Surface {1};\n";
      geo += "Physical Surface(1) = {1};\n";
      break;
    }
    case Shape::rectangle:
      // PeriDEM's wall script: four corner points carrying h.
      append_polygon(geo, rectangle_corners(s.lo, s.hi), 1, 1, h);
      geo += "Plane Surface(1) = {1};\nPhysical Surface(1) = {1};\n";
      break;
    case Shape::rectangle_minus_rectangle:
      geo += "SetFactory(\"OpenCASCADE\");\n";
      append_polygon(geo, rectangle_corners(s.lo, s.hi), 1, 1, h);
      geo += "Plane Surface(1) = {1};\n";
      append_polygon(geo, rectangle_corners(s.inner_lo, s.inner_hi), 5, 2, h);
      geo += "Plane Surface(2) = {2};\n";
      // The difference may come in pieces (an inner rectangle across the outer one): keep them all.
      geo += "s() = BooleanDifference{ Surface{1}; Delete; }{ Surface{2}; Delete; };\n";
      geo += "Physical Surface(1) = {s()};\n";
      geo += "Mesh.CharacteristicLengthMax = ";
      append_number(geo, h);
      geo += ";\n";
      break;
    case Shape::sphere:
    case Shape::box:
      geo += "SetFactory(\"OpenCASCADE\");\n";
      if (s.shape == Shape::sphere) {
        append_list(geo, "Sphere(1) = {", {s.centre.x, s.centre.y, s.centre.z, s.radius});
      } else {
        // OpenCASCADE's box is corner plus lengths: the far corner is lo + (hi - lo), exact to round-off.
        append_list(geo, "Box(1) = {", {s.lo.x, s.lo.y, s.lo.z, s.hi.x - s.lo.x, s.hi.y - s.lo.y, s.hi.z - s.lo.z});
      }
      geo += "Physical Volume(1) = {1};\n";
      geo += "Mesh.CharacteristicLengthMax = ";
      append_number(geo, h);
      geo += ";\n";
      break;
  }
  return geo;
}

namespace {

/// FNV-1a: a stable hash (std::hash is not) that names the cached files.
std::uint64_t fnv1a(const std::string& text) {
  std::uint64_t hash = 14695981039346656037ull;
  for (const unsigned char c : text) {
    hash ^= c;
    hash *= 1099511628211ull;
  }
  return hash;
}

std::string read_text(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::ostringstream out;
  out << in.rdbuf();
  return out.str();
}

void write_text(const std::filesystem::path& path, const std::string& text) {
  std::ofstream out(path);
  out << text;
  out.close();
  if (!out) throw output_error(path.string(), "cannot write a mesh file (gmsh.directory)");
}

/// The last `max_lines` lines of a log, for an error message.
std::string tail(const std::string& text, std::size_t max_lines) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  std::string out;
  for (std::size_t k = lines.size() > max_lines ? lines.size() - max_lines : 0; k < lines.size(); ++k)
    out += lines[k] + "\n";
  return out;
}

/// Runs `argv` with stdout and stderr sent to files; returns the exit status (or throws when it cannot start).
int run_process(const std::vector<std::string>& argv, const std::filesystem::path& out,
                const std::filesystem::path& err) {
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  std::vector<char*> args;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  pid_t pid = 0;
  const int rc = posix_spawnp(&pid, args[0], &actions, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (rc != 0) {
    const std::string why = rc == ENOENT ? "not found: install Gmsh (Debian: apt-get install gmsh, or run "
                                           "cmake/install-debian-deps.sh) or give its path"
                                         : std::string("cannot be started: ") + std::strerror(rc);
    throw input_error("gmsh.executable", argv[0], why);
  }
  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR)
      throw input_error("gmsh.executable", argv[0], std::string("waitpid failed: ") + std::strerror(errno));
  }
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  return 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
}

}  // namespace

SimplexMesh mesh_shape(const ShapeSpec& spec, const GmshRun& run) {
  namespace fs = std::filesystem;
  if (run.msh_version != 22 && run.msh_version != 41)
    throw input_error("gmsh.msh_version", std::to_string(run.msh_version), "must be 22 or 41 (MSH 2.2 or 4.1)");
  if (run.directory.empty()) throw input_error("gmsh.directory", "\"\"", "must name a directory for the mesh files");
  const std::string geo = shape_geo(spec);
  const int dim = shape_dimension(spec.shape);
  const std::string format = run.msh_version == 22 ? "msh22" : "msh41";
  const std::string dim_flag = dim == 2 ? "-2" : "-3";

  std::error_code ec;
  fs::create_directories(run.directory, ec);
  if (ec) throw output_error(run.directory, "cannot create the mesh directory (gmsh.directory): " + ec.message());
  char hash[17];
  std::snprintf(hash, sizeof hash, "%016llx",
                static_cast<unsigned long long>(fnv1a(geo + "\n// " + dim_flag + " -format " + format)));
  const fs::path base = fs::path(run.directory) / (std::string(shape_name(spec.shape)) + "-" + hash);
  const fs::path msh = base.string() + ".msh";
  if (run.reuse && fs::exists(msh)) return read_gmsh_msh(msh.string());

  // Private names while Gmsh works, renamed into place when the mesh has been read back.
  const std::string tmp = base.string() + ".tmp" + std::to_string(getpid());
  const fs::path tmp_geo = tmp + ".geo", tmp_msh = tmp + ".msh", out_log = tmp + ".out", err_log = tmp + ".err";
  write_text(tmp_geo, geo);
  const int status = run_process(
      {run.executable, tmp_geo.string(), dim_flag, "-format", format, "-o", tmp_msh.string()}, out_log, err_log);
  const std::string what = std::string(shape_name(spec.shape)) + " mesh (" + tmp_geo.string() + ")";
  auto gmsh_failed = [&](const std::string& why) {
    std::string errors = read_text(err_log);
    if (errors.empty()) errors = tail(read_text(out_log), 20);
    return input_error("gmsh.executable", run.executable, why + " for the " + what + ":\n" + errors);
  };
  if (status != 0) throw gmsh_failed("exited with status " + std::to_string(status));
  SimplexMesh mesh;
  try {
    mesh = read_gmsh_msh(tmp_msh.string());
  } catch (const InputError& e) {
    throw gmsh_failed(std::string("wrote a mesh that cannot be used (") + e.what() + ")");
  }
  if (mesh.dimension != dim)
    throw gmsh_failed("wrote a mesh of dimension " + std::to_string(mesh.dimension) + ", not " + dim_flag.substr(1));
  for (const auto& [from, to] : {std::pair{tmp_geo, fs::path(base.string() + ".geo")}, std::pair{tmp_msh, msh}}) {
    fs::rename(from, to, ec);
    if (ec) throw output_error(run.directory, "cannot rename " + from.string() + " there: " + ec.message());
  }
  fs::remove(out_log, ec);
  fs::remove(err_log, ec);
  return mesh;
}

}  // namespace debris
