#include "scenarios/common/peridem/peridem_input.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <map>
#include <optional>

#include "core/bond_list.hpp"
#include "core/error.hpp"
#include "scenarios/common/peridem/grain_placement.hpp"
#include "scenarios/common/peridem/gmsh_api.hpp"
#include "scenarios/common/peridem/peridem_simulation.hpp"
#include "core/io/grain_csv.hpp"
#include "core/io/input.hpp"
#include "core/memory_budget.hpp"
#include "scenarios/common/peridem/shape_mesh.hpp"
#include "scenarios/common/peridem/peridem_keys.hpp"

namespace debris {

namespace {
// The memory a node surely takes: its columns (21 doubles, 2 ints, an int64 id) and its position at the
// contact list's last build (3 doubles). A lower bound, so that the check never refuses a system that fits:
// the bonds come on top, and their number per node varies with the horizon (measured peaks: the 500-grain
// deck, 12.6 bonds per node, 160 bytes per node above a 2-disc run; two discs meshed at horizon / 20,
// 400 bonds per node, 7.7 KiB per node).
constexpr double kPdBytesPerNode = 24 * sizeof(double) + 2 * sizeof(int) + sizeof(std::int64_t);
}  // namespace

namespace {

namespace fs = std::filesystem;
namespace u = units;

std::string vec_text(Vec3 v) {
  return "[" + format_value(v.x) + ", " + format_value(v.y) + ", " + format_value(v.z) + "]";
}

void require_positive(double v, const std::string& key) {
  if (!(v > 0) || !std::isfinite(v)) throw input_error(key, format_value(v), "must be a finite number > 0");
}

/// Names become thermo column prefixes and HDF5 strings: letters, digits, '_', '-', '.'.
void check_name(const std::string& name, const std::string& key) {
  const bool ok = !name.empty() && std::all_of(name.begin(), name.end(), [](unsigned char c) {
    return std::isalnum(c) || c == '_' || c == '-' || c == '.';
  });
  if (!ok) throw input_error(key, "'" + name + "'", "a name holds only letters, digits, '_', '-' and '.'");
}

std::string key_of(const InputNode& n, const std::string& key) { return n.path().empty() ? key : n.path() + "." + key; }

/// In 2D every position and velocity lies in the plane z = 0.
Vec3 in_plane(const InputNode& n, const std::string& key, Vec3 v, int dimension) {
  if (dimension == 2 && v.z != 0)
    throw input_error(key_of(n, key), vec_text(v), "must have z = 0 in a 2D run (dimension: 2)");
  return v;
}
Vec3 planar(const InputNode& n, const std::string& key, u::Dimension dim, Vec3 fallback, int dimension) {
  return in_plane(n, key, n.vec3(key, dim, fallback), dimension);
}
/// A key that must be given (or is known to be there): read without a default.
Vec3 planar(const InputNode& n, const std::string& key, u::Dimension dim, int dimension) {
  return in_plane(n, key, n.vec3(key, dim), dimension);
}


// ---- materials ----------------------------------------------------------------------------------------

// ---- shapes ---------------------------------------------------------------------------------------------

struct ShapeInput {
  std::string name, path;  // "disc", "shapes.disc"
  bool from_file = false;
  ShapeSpec spec;                   // Gmsh shapes
  std::string file;                 // mesh_file: resolved path
  std::optional<double> reference;  // R_ref: scales a grain by radius / R_ref
};

ShapeInput read_shape(const InputNode& n, const std::string& name, const std::string& base, int dimension) {
  ShapeInput s;
  s.name = name;
  s.path = n.path();
  const std::string type = n.choice("type", {"circle", "hexagon", "concave_polygon", "rectangle",
                                             "rectangle_minus_rectangle", "sphere", "box", "mesh_file"});
  if (n.has("reference_radius")) {
    s.reference = n.quantity("reference_radius", u::length);
    require_positive(*s.reference, s.path + ".reference_radius");
  }
  if (type == "mesh_file") {
    s.from_file = true;
    s.file = resolve_input_path(n.string("file"), base);
    return s;
  }
  if (!gmsh_api_available()) throw input_error(s.path + ".type", type, gmsh_api_missing());
  const double h = n.quantity("mesh_size", u::length);
  require_positive(h, s.path + ".mesh_size");
  ShapeSpec& sp = s.spec;
  auto radius = [&] {
    const double r = n.quantity("radius", u::length);
    require_positive(r, s.path + ".radius");
    return r;
  };
  if (type == "circle" || type == "sphere") {
    const double r = radius();
    const Vec3 c = n.vec3("centre", u::length, Vec3{});
    sp = type == "circle" ? ShapeSpec::make_circle(r, h, c) : ShapeSpec::make_sphere(r, h, c);
    if (!s.reference) s.reference = r;
  } else if (type == "hexagon" || type == "concave_polygon") {
    const double r = radius();
    const Vec3 c = n.vec3("centre", u::length, Vec3{});
    const Vec3 a = n.vec3("axis", u::dimensionless, Vec3{1, 0, 0});
    if (type == "hexagon") {
      sp = ShapeSpec::make_hexagon(r, h, c, a);
    } else {
      const double w = n.quantity("neck_half_width", u::length);
      require_positive(w, s.path + ".neck_half_width");
      sp = ShapeSpec::make_concave_polygon(r, w, h, c, a);
    }
    if (!s.reference) s.reference = r;
  } else if (type == "rectangle" || type == "box") {
    const Vec3 lo = n.vec3("lo", u::length), hi = n.vec3("hi", u::length);
    sp = type == "rectangle" ? ShapeSpec::make_rectangle(lo, hi, h) : ShapeSpec::make_box(lo, hi, h);
  } else {
    sp = ShapeSpec::make_rectangle_minus_rectangle(n.vec3("lo", u::length), n.vec3("hi", u::length),
                                                   n.vec3("inner_lo", u::length), n.vec3("inner_hi", u::length), h);
  }
  if (shape_dimension(sp.shape) != dimension)
    throw input_error(s.path + ".type", type,
                      "is a " + std::to_string(shape_dimension(sp.shape)) + "D shape in a run of dimension " +
                          std::to_string(dimension));
  try {
    validate_shape(sp);
  } catch (const InputError& e) {
    throw InputError(std::string(e.what()) + " (in '" + s.path + "')");
  }
  return s;
}

// Eq 33 bonds a node to the nodes of its grain closer than the horizon: a grain meshed as coarse as its
// horizon is a cloud of unbonded nodes that never deforms nor breaks. A shape is checked with each material
// that uses it, at the largest scale a grain gives it (the widest node spacing against the fixed horizon), by
// building the bonds of that one grain. Every node bonded but horizon / mesh size below 2: a warning (the
// paper's runs use 4.2-5.2).
void check_grain_bonds(const ShapeInput& shape, const ReferenceGrain& reference, double scale,
                       const PdMaterial& material, const std::string& material_key,
                       std::vector<std::string>& warnings) {
  PdNodes nodes;
  PdGrains grains;
  GrainRecord at_scale;
  at_scale.radius = scale * reference.radius;
  place_grain(reference, at_scale, nodes, grains);
  const BondList bonds = BondList::build(nodes, grains, {material.horizon});
  std::size_t unbonded = 0;
  for (std::size_t i = 0; i < bonds.nodes(); ++i) unbonded += bonds.offset[i + 1] == bonds.offset[i] ? 1 : 0;
  // A Gmsh shape's spacing is its mesh_size (times the grain's scale); a mesh file's is measured (eq 35).
  const double h = shape.from_file ? pd_mesh_size(nodes, grains) : scale * shape.spec.mesh_size;
  const double ratio = material.horizon / h;
  const std::string key = shape.from_file ? shape.path + ".file" : shape.path + ".mesh_size";
  const std::string value = shape.from_file ? shape.file : format_value(shape.spec.mesh_size) + " m";
  std::string spacing = "mesh size h = " + format_value(h) + " m";
  if (scale != 1) spacing += " (the largest grain of this shape, scaled by " + format_value(scale) + ")";
  const std::string against = material_key + " = " + format_value(material.horizon) + " m against the " + spacing +
                              ": horizon / h = " + format_value(ratio);
  if (unbonded > 0)
    throw input_error(key, value,
                      "leaves " + std::to_string(unbonded) + " of the " + std::to_string(bonds.nodes()) +
                          " nodes of a grain without a bond (eq 33: no node of the grain within the horizon), "
                          "with " + against + "; mesh the shape finer or widen the horizon: horizon / h of 2 or "
                          "more (the paper's runs use 4.2-5.2)");
  if (ratio < 2)
    warnings.push_back(key + " = " + value + ": " + against +
                       " is below 2: few bonds per node, a grain that is barely a continuum (the paper's runs use "
                       "4.2-5.2)");
}

// ---- contact --------------------------------------------------------------------------------------------

PdContactSettings read_contact_settings(const InputNode& n, PdContactSettings s) {
  s.contact_radius_factor = n.quantity("contact_radius_factor", u::dimensionless, s.contact_radius_factor);
  s.restitution = n.quantity("restitution", u::dimensionless, s.restitution);
  s.damping_factor = n.quantity("damping_factor", u::dimensionless, s.damping_factor);
  s.friction = n.quantity("friction", u::dimensionless, s.friction);
  s.stiffness_factor = n.quantity("stiffness_factor", u::dimensionless, s.stiffness_factor);
  s.damping_onset_factor = n.quantity("damping_onset_factor", u::dimensionless, s.damping_onset_factor);
  return s;
}

int material_index(const PeridemRunConfig& cfg, const std::string& name, const std::string& key) {
  const auto it = std::find(cfg.material_names.begin(), cfg.material_names.end(), name);
  if (it == cfg.material_names.end()) {
    std::string known;
    for (const std::string& m : cfg.material_names) known += (known.empty() ? "" : ", ") + m;
    throw input_error(key, "'" + name + "'", "is not one of the materials (" + known + ")");
  }
  return static_cast<int>(it - cfg.material_names.begin());
}

void read_contact(const InputNode& root, PeridemRunConfig& cfg) {
  const std::size_t nm = cfg.materials.size();
  PdContactSettings all;
  std::optional<InputNode> c;
  if (root.has("contact")) c = root.child("contact");
  if (c) {
    all = read_contact_settings(*c, all);
    cfg.settings.damping = c->choice("damping", {"grain_centres", "node_pairs"}, "grain_centres") == "grain_centres"
                               ? PdDamping::grain_centres
                               : PdDamping::node_pairs;
  }
  cfg.contact.assign(nm * nm, all);
  // Checked here with a material against itself and h = 1: the ranges do not depend on either.
  auto check = [&](const PdContactSettings& s, int a, int b, const std::string& key) {
    pd_contact_params(cfg.materials[static_cast<std::size_t>(a)], cfg.materials[static_cast<std::size_t>(b)], s, 1.0,
                      key);
  };
  check(all, 0, 0, "contact");
  if (!c || !c->has("pairs")) return;
  std::vector<bool> given(nm * nm, false);
  for (const InputNode& p : c->list("pairs")) {
    const std::vector<InputNode> names = p.list("materials");
    if (names.size() != 2)
      throw input_error(p.path() + ".materials", std::to_string(names.size()) + " names", "give two: [M1, M2]");
    const int a = material_index(cfg, names[0].text(), names[0].path());
    const int b = material_index(cfg, names[1].text(), names[1].path());
    const std::size_t ab = static_cast<std::size_t>(a) * nm + static_cast<std::size_t>(b);
    const std::size_t ba = static_cast<std::size_t>(b) * nm + static_cast<std::size_t>(a);
    if (given[ab])
      throw input_error(p.path() + ".materials", "[" + names[0].text() + ", " + names[1].text() + "]",
                        "this pair of materials is given twice");
    const PdContactSettings s = read_contact_settings(p, all);
    check(s, a, b, p.path());
    cfg.contact[ab] = cfg.contact[ba] = s;
    given[ab] = given[ba] = true;
  }
}

// ---- grains and walls -----------------------------------------------------------------------------------

/// Bits of PdNodes::fixed: `fixed: true` (every axis), `false`, or a list of axes [x, y].
int read_fixed(const InputNode& n, int dimension) {
  if (!n.has("fixed")) return 0;
  if (!n.child("fixed").is_sequence()) return n.boolean("fixed") ? (dimension == 2 ? 3 : 7) : 0;
  int bits = 0;
  for (const InputNode& a : n.list("fixed")) {
    const std::string t = a.text();
    if (t == "x")
      bits |= 1;
    else if (t == "y")
      bits |= 2;
    else if (t == "z")
      bits |= 4;
    else
      throw input_error(a.path(), t, "an axis is x, y or z");
  }
  return bits;
}

struct GrainInput {
  std::string name;
  std::string shape;
  int material = 0;
  GrainRecord record;
  Vec3 velocity;
  int fixed = 0;
};

struct ZoneInput {
  std::string shape;
  int material = 0;
  Vec3 velocity;
  int fixed = 0;
};

struct WallInput {
  std::string name, shape;
  int material = 0;
  Vec3 velocity;
};

const ShapeInput& find_shape(const std::map<std::string, ShapeInput>& shapes, const std::string& name,
                             const std::string& key) {
  const auto it = shapes.find(name);
  if (it == shapes.end()) {
    std::string known;
    for (const auto& [k, v] : shapes) known += (known.empty() ? "" : ", ") + k;
    throw input_error(key, "'" + name + "'", "is not one of the shapes (" + (known.empty() ? "none" : known) + ")");
  }
  return it->second;
}

/// Meshes (Gmsh) or reads (.msh) each shape once.
class MeshCache {
 public:
  MeshCache(const std::map<std::string, ShapeInput>& shapes, std::string directory, int dimension)
      : shapes_(shapes), directory_(std::move(directory)), dimension_(dimension) {}

  const SimplexMesh& mesh(const std::string& name) {
    auto it = meshes_.find(name);
    if (it != meshes_.end()) return it->second;
    const ShapeInput& s = shapes_.at(name);
    SimplexMesh m;
    if (s.from_file) {
      if (!fs::exists(s.file)) throw input_error(s.path + ".file", s.file, "no such mesh file");
      m = read_mesh_file(s.file);
      if (m.dimension != dimension_)
        throw input_error(
            s.path + ".file", s.file,
            "holds a " + std::to_string(m.dimension) + "D mesh in a run of dimension " + std::to_string(dimension_));
    } else {
      GmshRun run;
      run.directory = directory_;
      m = mesh_shape(s.spec, run);
    }
    if (dimension_ == 2)
      for (const Vec3& v : m.nodes)
        if (v.z != 0)
          throw input_error(s.path, "a node at z = " + format_value(v.z), "a 2D mesh must lie in the plane z = 0");
    return meshes_.emplace(name, std::move(m)).first->second;
  }

  ReferenceGrain reference(const std::string& name, int material, const std::string& key) {
    const ShapeInput& s = shapes_.at(name);
    if (!s.reference)
      throw input_error(s.path + ".reference_radius", "(absent)",
                        "a shape used by grains (" + key +
                            ") needs its reference radius R_ref: grains are scaled by "
                            "radius / R_ref");
    return make_reference_grain(mesh(name), *s.reference, material, s.path);
  }

 private:
  const std::map<std::string, ShapeInput>& shapes_;
  std::string directory_;
  int dimension_;
  std::map<std::string, SimplexMesh> meshes_;
};

void set_grain_state(PdNodes& nodes, const PdGrains& grains, int g, Vec3 v, int fixed) {
  for (int i = grains.node_begin[static_cast<std::size_t>(g)]; i < grains.node_end[static_cast<std::size_t>(g)]; ++i) {
    nodes.fixed[i] = fixed;
    nodes.vx[i] = fixed & 1 ? 0.0 : v.x;
    nodes.vy[i] = fixed & 2 ? 0.0 : v.y;
    nodes.vz[i] = fixed & 4 ? 0.0 : v.z;
  }
}

// What stage `st` changes (its name and length were read by read_stage_lengths). Walls are named as in
// walls: (an unnamed one is wall<k>); the wall's grain index is found at run time, on the built system.
PeridemStageChanges read_stage_changes(const InputNode& st, const std::vector<WallInput>& walls, int dim, double dt) {
  PeridemStageChanges c;
  if (st.has("gravity")) c.gravity = planar(st, "gravity", u::acceleration, dim);
  if (st.has("global_damping")) {
    c.global_damping = st.quantity("global_damping", u::frequency);
    PeridemSimulation::check_global_damping(*c.global_damping, dt, st.path() + ".global_damping");
  }
  if (!st.has("walls")) return c;
  for (const InputNode& w : st.list("walls")) {
    PeridemStageChanges::WallChange wc;
    wc.key = w.path();
    wc.name = w.string("name");
    bool known = false;
    std::string names;
    for (std::size_t k = 0; k < walls.size(); ++k) {
      const std::string n = walls[k].name.empty() ? "wall" + std::to_string(k) : walls[k].name;
      known = known || n == wc.name;
      names += (names.empty() ? "" : ", ") + n;
    }
    if (!known)
      throw input_error(w.path() + ".name", wc.name,
                        "no such wall (walls: " + (names.empty() ? std::string("none") : names) + ")");
    for (const PeridemStageChanges::WallChange& o : c.walls)
      if (o.name == wc.name) throw input_error(w.path() + ".name", wc.name, "the stage changes this wall twice");
    if (w.has("velocity")) wc.velocity = planar(w, "velocity", u::velocity, dim);
    if (w.has("move_by") && w.has("place"))
      throw input_error(w.path() + ".place", "given with move_by", "give one of place or move_by");
    if (w.has("move_by")) wc.move_by = planar(w, "move_by", u::length, dim);
    if (w.has("place")) {
      const InputNode p = w.child("place");
      const std::vector<std::string> sides{"x_min", "x_max", "y_min", "y_max", "z_min", "z_max"};
      const std::vector<std::string> keys = p.is_map() ? p.keys() : std::vector<std::string>{};
      if (keys.size() != 1 || std::find(sides.begin(), sides.end(), keys.front()) == sides.end())
        throw input_error(p.path(), p.is_scalar() ? p.text() : (keys.empty() ? std::string("{}") : keys.front()),
                          "give one of x_min, x_max, y_min, y_max, z_min, z_max: where the wall's lowest or highest "
                          "node goes, e.g. {y_min: 31.2 mm}");
      const std::size_t side = static_cast<std::size_t>(std::find(sides.begin(), sides.end(), keys.front()) - sides.begin());
      wc.place_axis = static_cast<int>(side / 2);
      wc.place_max = side % 2 == 1;
      if (dim == 2 && wc.place_axis == 2) throw input_error(p.path(), keys.front(), "a 2D run has no z to place along");
      wc.place_at = p.quantity(keys.front(), u::length);
      if (!std::isfinite(wc.place_at)) throw input_error(p.path() + "." + keys.front(), format_value(wc.place_at), "must be finite");
    }
    if (!wc.velocity && !wc.move_by && wc.place_axis < 0)
      throw input_error(w.path(), wc.name, "a wall change needs velocity, place or move_by");
    c.walls.push_back(wc);
  }
  return c;
}

}  // namespace

std::string resolve_input_path(const std::string& file, const std::string& base) {
  fs::path p = file;
  if (p.is_relative() && !base.empty()) p = fs::path(base) / p;
  return p.string();
}

PdMaterial read_pd_material(const InputNode& n, int dimension) {
  PdMaterial m;
  m.density = n.quantity("density", u::density);
  m.bulk_modulus = n.quantity("bulk_modulus", u::pressure);
  m.shear_modulus = n.quantity("shear_modulus", u::pressure);
  m.fracture_energy = n.quantity("fracture_energy", u::surface_energy);
  m.horizon = n.quantity("horizon", u::length);
  m.dimension = dimension;
  // plane_strain: the 2D constants that give a grain the material's K and G (kernels/peridem/pd_material.hpp);
  // peridem_code: the 3D constants on the 2D grain, as the authors' code (and so the paper's runs) does.
  if (dimension == 2) {
    if (n.choice("lps_constants", {"plane_strain", "peridem_code"}, "plane_strain") == "peridem_code") m.dimension = 3;
  }
  // tension: eq 11 as the paper writes it; tension_and_compression: the authors' code, |s| >= s_0.
  m.break_in_compression =
      n.choice("bond_breaking", {"tension", "tension_and_compression"}, "tension") == "tension_and_compression";
  m.validate(n.path().c_str());
  return m;
}

PeridemRunConfig read_peridem_input(const std::string& path, const PeridemInputOptions& options) {
  const InputNode root = InputNode::load_file(path);
  return read_peridem_input(root, fs::path(path).parent_path().string(), options);
}

PeridemRunConfig read_peridem_input_text(const std::string& text, const std::string& name,
                                         const std::string& base_directory, const PeridemInputOptions& options) {
  return read_peridem_input(InputNode::load_string(text, name), base_directory, options);
}

PeridemRunConfig read_peridem_input(const InputNode& root, const std::string& base,
                                    const PeridemInputOptions& options) {
  PeridemRunConfig cfg;
  cfg.dimension = static_cast<int>(root.integer("dimension", 2));
  if (cfg.dimension != 2 && cfg.dimension != 3)
    throw input_error("dimension", std::to_string(cfg.dimension), "must be 2 (plane strain) or 3");
  const int dim = cfg.dimension;

  // Materials, by name, in file order.
  const InputNode mats = root.child("materials");
  for (const std::string& k : mats.keys()) {
    check_name(k, "materials." + k);
    cfg.material_names.push_back(k);
    cfg.materials.push_back(read_pd_material(mats.child(k), dim));
  }
  if (cfg.materials.empty()) throw input_error("materials", "(empty)", "define at least one material");

  // Shapes.
  std::map<std::string, ShapeInput> shapes;
  if (root.has("shapes")) {
    const InputNode sh = root.child("shapes");
    for (const std::string& k : sh.keys()) {
      check_name(k, "shapes." + k);
      shapes.emplace(k, read_shape(sh.child(k), k, base, dim));
    }
  }

  // Grains: from the particle file (zones), then listed one by one.
  std::vector<ZoneInput> zones;
  std::string csv_path;
  if (root.has("particle_file")) {
    const InputNode pf = root.child("particle_file");
    csv_path = resolve_input_path(pf.string("file"), base);
    for (const InputNode& z : pf.list("zones")) {
      ZoneInput zone;
      zone.shape = z.string("shape");
      find_shape(shapes, zone.shape, z.path() + ".shape");
      zone.material = material_index(cfg, z.string("material"), z.path() + ".material");
      zone.velocity = planar(z, "velocity", u::velocity, Vec3{}, dim);
      zone.fixed = read_fixed(z, dim);
      zones.push_back(zone);
    }
    if (zones.empty()) throw input_error(pf.path() + ".zones", "(empty)", "give one {shape, material} per zone");
  }
  std::vector<GrainInput> listed;
  if (root.has("grains")) {
    for (const InputNode& g : root.list("grains")) {
      GrainInput in;
      in.name = g.string("name", "");
      if (!in.name.empty()) check_name(in.name, g.path() + ".name");
      in.shape = g.string("shape");
      const ShapeInput& s = find_shape(shapes, in.shape, g.path() + ".shape");
      in.material = material_index(cfg, g.string("material"), g.path() + ".material");
      const Vec3 c = planar(g, "centre", u::length, dim);  // required: a missing centre names the key
      in.record.x = c.x, in.record.y = c.y, in.record.z = c.z;
      if (g.has("radius")) {
        in.record.radius = g.quantity("radius", u::length);
        require_positive(in.record.radius, g.path() + ".radius");
      } else {
        if (!s.reference)
          throw input_error(g.path() + ".radius", "(absent)",
                            "give the grain's radius: its shape '" + in.shape + "' has no reference radius");
        in.record.radius = *s.reference;
      }
      in.record.orientation = g.quantity("rotation", u::dimensionless, 0.0);
      if (!std::isfinite(in.record.orientation))
        throw input_error(g.path() + ".rotation", format_value(in.record.orientation), "must be finite (radians)");
      in.velocity = planar(g, "velocity", u::velocity, Vec3{}, dim);
      in.fixed = read_fixed(g, dim);
      listed.push_back(in);
    }
  }
  std::vector<WallInput> walls;
  if (root.has("walls")) {
    for (const InputNode& w : root.list("walls")) {
      WallInput in;
      in.name = w.string("name", "");
      if (!in.name.empty()) check_name(in.name, w.path() + ".name");
      in.shape = w.string("shape");
      find_shape(shapes, in.shape, w.path() + ".shape");
      in.material = material_index(cfg, w.string("material"), w.path() + ".material");
      in.velocity = planar(w, "velocity", u::velocity, Vec3{}, dim);
      walls.push_back(in);
    }
  }
  if (zones.empty() && listed.empty())
    throw input_error("grains", "(none)", "give grains (a 'grains' list and/or a 'particle_file')");

  read_contact(root, cfg);
  cfg.settings.gravity = planar(root, "gravity", u::acceleration, Vec3{}, dim);

  // Run control.
  const InputNode run = root.child("run");
  cfg.settings.time_step = run.quantity("time_step", u::time);
  require_positive(cfg.settings.time_step, "run.time_step");
  std::vector<InputNode> stage_nodes;
  cfg.stages = read_stage_lengths(root, &stage_nodes);
  for (const InputNode& st : stage_nodes) cfg.stage_changes.push_back(read_stage_changes(st, walls, dim, cfg.settings.time_step));
  const bool has_steps = run.has("steps"), has_final = run.has("final_time");
  if (!cfg.stages.empty() && !has_steps && !has_final) {
    cfg.steps = -1;  // the stages' length
  } else if (has_steps == has_final) {
    throw input_error("run.steps", has_steps ? "given with final_time" : "(absent)",
                      "give exactly one of run.steps (a number of steps) or run.final_time (a time)");
  } else if (has_steps) {
    cfg.steps = run.integer("steps");
    if (cfg.steps < 0) throw input_error("run.steps", std::to_string(cfg.steps), "must be >= 0");
  } else {
    const double t = run.quantity("final_time", u::time);
    if (!(t >= 0) || !std::isfinite(t)) throw input_error("run.final_time", format_value(t), "must be >= 0");
    const double n = std::round(t / cfg.settings.time_step);
    if (n > 1e15) throw input_error("run.final_time", format_value(t), "is more than 1e15 time steps");
    cfg.steps = static_cast<long>(n);
  }
  cfg.settings.skin = run.quantity("skin", u::length, 0.0);
  if (!(cfg.settings.skin >= 0))
    throw input_error("run.skin", format_value(cfg.settings.skin), "must be >= 0 (0: R_c)");
  cfg.settings.allow_unstable_time_step = run.boolean("allow_unstable_time_step", false);
  cfg.settings.global_damping = run.quantity("global_damping", u::frequency, 0.0);
  PeridemSimulation::check_global_damping(cfg.settings.global_damping, cfg.settings.time_step, "run.global_damping");
  cfg.penetration_limit = run.quantity("penetration_limit", u::dimensionless, cfg.penetration_limit);
  if (!(cfg.penetration_limit > 0 && cfg.penetration_limit <= 1))
    throw input_error("run.penetration_limit", format_value(cfg.penetration_limit),
                      "must be in (0, 1]: the depth R_c - |z' - z|, as a fraction of R_c, past which a node pair "
                      "of two bodies stops the run (1: never)");
  cfg.threads = static_cast<int>(run.integer("threads", 0));
  if (cfg.threads < 0) throw input_error("run.threads", std::to_string(cfg.threads), "must be >= 0");

  if (root.has("output")) {
    const InputNode out = root.child("output");
    PeridemOutputSettings& o = cfg.output;
    o.directory = out.string("directory", o.directory);
    o.thermo_every = out.integer("thermo_every", o.thermo_every);
    if (o.thermo_every < 1) throw input_error("output.thermo_every", std::to_string(o.thermo_every), "must be >= 1");
    o.trajectory_every = out.integer("trajectory_every", o.trajectory_every);
    if (o.trajectory_every < 0)
      throw input_error("output.trajectory_every", std::to_string(o.trajectory_every), "must be >= 0");
    o.checkpoint_every = out.integer("checkpoint_every", o.checkpoint_every);
    if (o.checkpoint_every < 0)
      throw input_error("output.checkpoint_every", std::to_string(o.checkpoint_every), "must be >= 0");
    o.progress_seconds = out.quantity("progress_seconds", u::time, o.progress_seconds);
    if (!(o.progress_seconds > 0))
      throw input_error("output.progress_seconds", format_value(o.progress_seconds), "must be > 0");
    o.grain_columns = out.integer("grain_columns", o.grain_columns);
    if (o.grain_columns < 0) throw input_error("output.grain_columns", std::to_string(o.grain_columns), "must be >= 0");
  }
  if (!options.output_directory.empty()) cfg.output.directory = options.output_directory;
  root.reject_unknown_keys();
  audit_keys(root, peridem_keys());
  cfg.plain_quantities = root.plain_beside_units();
  if (!options.build_system) return cfg;

  // The system: every key is known to be sound; now the files.
  MeshCache meshes(shapes, (fs::path(cfg.output.directory) / "meshes").string(), dim);
  const int planar_bit = dim == 2 ? 4 : 0;  // 2D: nodes stay in z = 0
  std::vector<GrainRecord> records;
  std::vector<ReferenceGrain> refs;
  if (!zones.empty()) {
    if (!fs::exists(csv_path)) throw input_error("particle_file.file", csv_path, "no such file");
    records = read_grain_csv(csv_path);
    if (records.empty()) throw input_error("particle_file.file", csv_path, "lists no grain");
    for (std::size_t z = 0; z < zones.size(); ++z)
      refs.push_back(
          meshes.reference(zones[z].shape, zones[z].material, "particle_file.zones[" + std::to_string(z) + "]"));
  }
  {
    // The nodes of every grain and wall, counted from their meshes before any is placed: a system too
    // large for int indices or for the machine's memory is refused here.
    double nodes = 0;
    for (const GrainRecord& r : records)
      if (r.zone >= 0 && static_cast<std::size_t>(r.zone) < refs.size())
        nodes += static_cast<double>(refs[static_cast<std::size_t>(r.zone)].volume.size());
    for (std::size_t k = 0; k < listed.size(); ++k)
      nodes += static_cast<double>(
          meshes.reference(listed[k].shape, listed[k].material, "grains[" + std::to_string(k) + "]").volume.size());
    for (const WallInput& w : walls) nodes += static_cast<double>(meshes.mesh(w.shape).nodes.size());
    const std::string shown = format_value(nodes) + " nodes";
    if (nodes > static_cast<double>(std::numeric_limits<int>::max()))
      throw input_error("grains", shown, "more nodes than debris can index (" +
                                             std::to_string(std::numeric_limits<int>::max()) + ")");
    check_memory("grains", shown, nodes, kPdBytesPerNode, "node");
  }
  {
    // Every particle grain bonded (check_grain_bonds): each shape and material at its largest scale.
    std::map<std::pair<std::string, int>, double> largest_scale;
    auto note_scale = [&](const std::string& shape, int material, double scale) {
      double& s = largest_scale.try_emplace({shape, material}, scale).first->second;
      s = std::max(s, scale);
    };
    for (const GrainRecord& r : records)
      if (r.zone >= 0 && static_cast<std::size_t>(r.zone) < refs.size()) {
        const ZoneInput& z = zones[static_cast<std::size_t>(r.zone)];
        note_scale(z.shape, z.material, r.radius / refs[static_cast<std::size_t>(r.zone)].radius);
      }
    for (std::size_t k = 0; k < listed.size(); ++k)
      note_scale(listed[k].shape, listed[k].material, listed[k].record.radius / *shapes.at(listed[k].shape).reference);
    for (const auto& [which, scale] : largest_scale) {
      const auto& [shape, material] = which;
      const std::size_t m = static_cast<std::size_t>(material);
      check_grain_bonds(shapes.at(shape), meshes.reference(shape, material, "shapes." + shape), scale,
                        cfg.materials[m], "materials." + cfg.material_names[m] + ".horizon", cfg.warnings);
    }
  }
  if (!zones.empty()) {
    place_grains(refs, records, cfg.nodes, cfg.grains);
    // place_grains goes zone by zone, file order within a zone (scenarios/common/peridem/grain_placement.hpp).
    int g = 0;
    for (std::size_t z = 0; z < zones.size(); ++z)
      for (const GrainRecord& r : records)
        if (r.zone == static_cast<int>(z)) {
          set_grain_state(cfg.nodes, cfg.grains, g, zones[z].velocity, zones[z].fixed | planar_bit);
          cfg.grain_names.push_back("grain" + std::to_string(g));
          ++g;
        }
  }
  for (std::size_t k = 0; k < listed.size(); ++k) {
    const GrainInput& in = listed[k];
    const std::string key = "grains[" + std::to_string(k) + "]";
    const int g = place_grain(meshes.reference(in.shape, in.material, key), in.record, cfg.nodes, cfg.grains);
    set_grain_state(cfg.nodes, cfg.grains, g, in.velocity, in.fixed | planar_bit);
    cfg.grain_names.push_back(in.name.empty() ? "grain" + std::to_string(g) : in.name);
  }
  for (std::size_t k = 0; k < walls.size(); ++k) {
    const WallInput& in = walls[k];
    const int g =
        append_wall(meshes.mesh(in.shape), in.material, cfg.nodes, cfg.grains, "walls[" + std::to_string(k) + "]");
    cfg.grains.wall_vx[static_cast<std::size_t>(g)] = in.velocity.x;
    cfg.grains.wall_vy[static_cast<std::size_t>(g)] = in.velocity.y;
    cfg.grains.wall_vz[static_cast<std::size_t>(g)] = in.velocity.z;
    for (int i = cfg.grains.node_begin[static_cast<std::size_t>(g)];
         i < cfg.grains.node_end[static_cast<std::size_t>(g)]; ++i) {
      cfg.nodes.vx[i] = in.velocity.x;
      cfg.nodes.vy[i] = in.velocity.y;
      cfg.nodes.vz[i] = in.velocity.z;
    }
    cfg.grain_names.push_back(in.name.empty() ? "wall" + std::to_string(k) : in.name);
  }
  for (std::size_t a = 0; a < cfg.grain_names.size(); ++a)
    for (std::size_t b = a + 1; b < cfg.grain_names.size(); ++b)
      if (cfg.grain_names[a] == cfg.grain_names[b])
        throw input_error("name", "'" + cfg.grain_names[a] + "'", "two grains or walls have this name");
  return cfg;
}

}  // namespace debris
