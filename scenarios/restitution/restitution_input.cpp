#include "scenarios/restitution/restitution_input.hpp"

#include <cmath>
#include <filesystem>
#include <map>
#include <utility>

#include "core/error.hpp"
#include "core/io/input.hpp"
#include "core/units.hpp"
#include "scenarios/common/peridem/peridem_input.hpp"
#include "scenarios/restitution/restitution_keys.hpp"

namespace debris {

namespace u = debris::units;

std::vector<RestitutionCase> read_restitution_input_text(const std::string& text, const std::string& name,
                                                         const std::string& output) {
  const InputNode root = InputNode::load_string(text, name);
  const int dimension = static_cast<int>(root.integer("dimension", 2));
  if (dimension != 2) throw input_error("dimension", std::to_string(dimension), "only 2 is supported by this scenario");
  std::map<std::string, PdMaterial> materials;
  const InputNode mats = root.child("materials");
  for (const std::string& k : mats.keys()) materials[k] = read_pd_material(mats.child(k), dimension);

  TwoParticleDrop base;
  base.mesh_size = root.quantity("mesh_size", u::length, base.mesh_size);
  base.drop_height = root.quantity("drop_height", u::length, base.drop_height);
  base.gravity = root.quantity("gravity", u::acceleration, base.gravity);
  base.damping_factor = root.quantity("damping_factor", u::dimensionless, base.damping_factor);
  base.contact_radius_factor = root.quantity("contact_radius_factor", u::dimensionless, base.contact_radius_factor);
  base.damping_onset_factor = root.quantity("damping_onset_factor", u::dimensionless, base.damping_onset_factor);
  base.start_gap = root.quantity("start_gap", u::length, base.start_gap);
  base.full_drop = root.boolean("full_drop", false);
  base.allow_unstable_time_step = root.boolean("allow_unstable_time_step", false);
  base.max_steps = root.integer("max_steps", base.max_steps);
  base.damping = root.choice("damping", {"grain_centres", "node_pairs"}, "grain_centres") == "grain_centres"
                     ? PdDamping::grain_centres
                     : PdDamping::node_pairs;
  auto centre_node = [](const InputNode& n, bool fallback) {
    return n.choice("damping_centre", {"mean", "centre_node"}, fallback ? "centre_node" : "mean") == "centre_node";
  };
  base.damping_centre_node = centre_node(root, false);
  base.mesh_directory = (std::filesystem::path(output) / "meshes").string();
  // Mesh files are relative to the input file's directory.
  const std::string input_dir = std::filesystem::path(name).parent_path().string();
  auto mesh_path = [&](const std::string& f, const std::string& key) {
    const std::string p = resolve_input_path(f, input_dir);
    if (!std::filesystem::is_regular_file(p)) throw input_error(key, p, "no such file");
    return p;
  };
  // circle_meshes: [{radius: 3 mm, file: a.msh}, ...]: every grain of that radius is that Gmsh file's mesh
  // (the meshes the authors' code ran on) instead of one Gmsh makes here; a case's `meshes` overrides it.
  std::vector<std::pair<double, std::string>> circle_meshes;
  if (root.has("circle_meshes")) {
    for (const InputNode& e : root.list("circle_meshes")) {
      const double r = e.quantity("radius", u::length);
      if (!(r > 0) || !std::isfinite(r)) throw input_error(e.path() + ".radius", format_value(r), "must be > 0");
      circle_meshes.emplace_back(r, mesh_path(e.string("file"), e.path() + ".file"));
      e.reject_unknown_keys();
    }
  }
  auto circle_mesh = [&](double r) {
    for (const auto& [radius, file] : circle_meshes)
      if (std::abs(radius - r) <= 1e-9 * radius) return file;
    return std::string();
  };

  std::vector<RestitutionCase> cases;
  for (const InputNode& c : root.list("cases")) {
    RestitutionCase k;
    k.name = c.string("name");
    k.spec = base;
    const std::vector<double> radii = c.numbers("radii", u::length);
    if (radii.size() != 2) throw input_error(c.path() + ".radii", std::to_string(radii.size()) + " values", "give [bottom, top]");
    k.spec.bottom_radius = radii[0];
    k.spec.top_radius = radii[1];
    std::vector<std::string> names;
    for (const InputNode& e : c.list("materials")) names.push_back(e.text());
    if (names.size() != 2) throw input_error(c.path() + ".materials", std::to_string(names.size()) + " names", "give [bottom, top]");
    for (const std::string& nm : names)
      if (!materials.count(nm)) throw input_error(c.path() + ".materials", nm, "is not one of the materials above");
    k.spec.bottom_material = materials[names[0]];
    k.spec.top_material = materials[names[1]];
    k.materials = names[0] + "/" + names[1];
    k.spec.restitution = c.quantity("restitution", u::dimensionless);
    k.spec.time_step = c.quantity("time_step", u::time);
    k.spec.initial_speed = c.quantity("initial_speed", u::velocity, 0.0);
    // A mesh study (Table 4) refines the mesh and the horizon together, case by case.
    k.spec.mesh_size = c.quantity("mesh_size", u::length, base.mesh_size);
    if (!(k.spec.mesh_size > 0) || !std::isfinite(k.spec.mesh_size))
      throw input_error(c.path() + ".mesh_size", format_value(k.spec.mesh_size), "must be > 0");
    if (c.has("horizon")) {
      const double horizon = c.quantity("horizon", u::length);
      if (!(horizon > 0) || !std::isfinite(horizon))
        throw input_error(c.path() + ".horizon", format_value(horizon), "must be > 0");
      k.spec.bottom_material.horizon = k.spec.top_material.horizon = horizon;
    }
    // Settings a case may change for itself (isolating runs: one setting moved, the rest as above).
    k.spec.contact_radius_factor = c.quantity("contact_radius_factor", u::dimensionless, base.contact_radius_factor);
    k.spec.damping_factor = c.quantity("damping_factor", u::dimensionless, base.damping_factor);
    k.spec.damping_onset_factor = c.quantity("damping_onset_factor", u::dimensionless, base.damping_onset_factor);
    k.spec.start_gap = c.quantity("start_gap", u::length, base.start_gap);
    k.spec.damping_centre_node = centre_node(c, base.damping_centre_node);
    k.spec.bottom_mesh_file = circle_mesh(k.spec.bottom_radius);
    k.spec.top_mesh_file = circle_mesh(k.spec.top_radius);
    if (c.has("meshes")) {
      // [bottom.msh, top.msh]: Gmsh files instead of meshing the circles (the authors' own meshes).
      std::vector<std::string> files;
      for (const InputNode& e : c.list("meshes")) files.push_back(mesh_path(e.text(), c.path() + ".meshes"));
      if (files.size() != 2)
        throw input_error(c.path() + ".meshes", std::to_string(files.size()) + " files", "give [bottom, top]");
      k.spec.bottom_mesh_file = files[0];
      k.spec.top_mesh_file = files[1];
    }
    k.paper = c.quantity("paper", u::dimensionless, -1.0);
    c.reject_unknown_keys();
    cases.push_back(k);
  }
  root.reject_unknown_keys();
  audit_keys(root, restitution_keys());
  if (cases.empty()) throw input_error("cases", "(empty)", "list at least one case");
  return cases;
}

}  // namespace debris
