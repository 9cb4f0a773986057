#include "scenarios/common/dem/dem_input.hpp"

#include <cmath>
#include <algorithm>
#include <filesystem>
#include <limits>
#include <sstream>

#include "core/error.hpp"
#include "core/io/input.hpp"
#include "core/io/lammps_data.hpp"
#include "scenarios/common/dem/replicate_sample.hpp"
#include "core/lattice.hpp"
#include "core/memory_budget.hpp"
#include "core/region.hpp"
#include "scenarios/common/dem/cohesive_material_input.hpp"
#include "scenarios/common/dem/dem_keys.hpp"

namespace debris {

namespace {

// Peak memory of debris_dem per particle, set-up, stepping and output (the system and its copies while it
// is built, neighbour list, contact history, frame and checkpoint buffers). Measured: FCC blocks of 32,000
// and 256,000 particles (spacing = diameter, 2 steps, 1 thread) peaked at 47,144 and 264,960 KiB of
// resident memory, 996 bytes per particle more.
constexpr double kDemBytesPerParticle = 1000.0;
// Particles are indexed by int.
constexpr long kMaxParticles = std::numeric_limits<int>::max();

using units::Dimension;

int axis_of(const InputNode& n, const std::string& key, const std::string& fallback) {
  const std::string a = n.choice(key, {"x", "y", "z"}, fallback);
  return a == "x" ? 0 : (a == "y" ? 1 : 2);
}

LatticeSpec read_lattice(const InputNode& l) {
  LatticeSpec spec;
  spec.kind = l.choice("kind", {"fcc", "hcp"}) == "fcc" ? LatticeKind::fcc : LatticeKind::hcp;
  spec.spacing = l.quantity("spacing", units::length);
  spec.diameter = l.quantity("diameter", units::length, spec.spacing);
  spec.size_spread = l.quantity("size_spread", units::dimensionless, 0.0);
  spec.displacement = l.quantity("displacement", units::length, 0.0);
  const std::vector<InputNode> cells = l.list("cells");
  if (cells.size() != 3) throw input_error(l.path() + ".cells", std::to_string(cells.size()) + " values", "give [nx, ny, nz]");
  for (int a = 0; a < 3; ++a) {
    const double c = cells[static_cast<std::size_t>(a)].quantity(units::dimensionless);
    if (c != std::floor(c) || c < 1 || c > 1e6)
      throw input_error(l.path() + ".cells", format_value(c), "cell counts must be whole numbers >= 1");
    spec.cells[static_cast<std::size_t>(a)] = static_cast<int>(c);
  }
  {
    // Both unit cells hold 4 particles. Refused before anything is allocated: too many for int indices,
    // or for the machine's memory.
    const double n = 4.0 * spec.cells[0] * spec.cells[1] * spec.cells[2];
    std::string shown = "[";  // appended: GCC 12 warns falsely (-Wrestrict) on "[" + std::string at -O3
    for (int a = 0; a < 3; ++a) shown += std::to_string(spec.cells[static_cast<std::size_t>(a)]) + (a < 2 ? ", " : "]");
    check_memory(l.path() + ".cells", shown, n, kDemBytesPerParticle, "particle");
    if (n > static_cast<double>(kMaxParticles))
      throw input_error(l.path() + ".cells", shown,
                        "makes " + format_value(n) + " particles, more than the " + std::to_string(kMaxParticles) +
                            " debris can index");
  }
  spec.origin = l.vec3("origin", units::length, Vec3{0, 0, 0});
  spec.seed = static_cast<std::uint64_t>(l.integer("seed", 1));
  spec.hcp_c_axis = axis_of(l, "hcp_c_axis", "y");
  validate(spec, l.path());
  return spec;
}

std::array<bool, 3> read_periodic(const InputNode& b) {
  std::array<bool, 3> periodic{false, false, false};
  if (!b.has("periodic")) return periodic;
  const std::vector<InputNode> p = b.list("periodic");
  if (p.size() != 3) throw input_error(b.path() + ".periodic", std::to_string(p.size()) + " values", "give [x, y, z] as true/false");
  for (std::size_t a = 0; a < 3; ++a) {
    const std::string t = p[a].text();
    if (t == "true" || t == "yes") periodic[a] = true;
    else if (t == "false" || t == "no") periodic[a] = false;
    else throw input_error(p[a].path(), t, "must be true or false");
  }
  return periodic;
}

// A region as read for carving the particles: a rough surface in it must be resolvable by them
// (check_surface_resolution, against the largest particle now in the system).
Region read_carving_region(const InputNode& n, const std::string& base_directory, const DemRunConfig& cfg) {
  Region region = read_region(n, &cfg.box, base_directory);
  if (!region.surfaces().empty()) {
    double largest = 0;
    for (double r : cfg.particles.radius) largest = std::max(largest, 2 * r);
    check_surface_resolution(region, largest);
  }
  return region;
}

// The entries of a key that takes one item or a list of them.
std::vector<InputNode> one_or_list(const InputNode& root, const std::string& key) {
  return root.child(key).is_sequence() ? root.list(key) : std::vector<InputNode>{root.child(key)};
}

// `remove`: one region or a list; each deletes the particles still inside it, in order. Positions as read
// (wrapped into the box on periodic axes, see core/region.hpp).
void read_removal(const InputNode& root, const std::string& base_directory, DemRunConfig& cfg) {
  if (!root.has("remove")) return;
  Particles& p = cfg.particles;
  std::vector<char> inside;
  for (const InputNode& n : one_or_list(root, "remove")) {
    const Region region = read_carving_region(n, base_directory, cfg);
    inside.assign(p.size(), 0);
    std::size_t count = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
      inside[i] = region.contains({p.x[i], p.y[i], p.z[i]}) ? 1 : 0;
      count += static_cast<std::size_t>(inside[i]);
    }
    const std::string key = n.path();
    if (count == 0)
      throw input_error(key, region.describe(),
                        "the region removes no particle (of the " + std::to_string(p.size()) +
                            " left): is it outside the box, or are its units off?");
    if (count == p.size())
      throw input_error(key, region.describe(),
                        "the removal leaves no particle (it takes all " + std::to_string(count) + " that were left)");
    p.remove_if(inside);
  }
}

// `labels`: [{name, region}, ...], assigned in order, a later entry overriding an earlier one where they
// overlap (paint the bodies, then the walls over them). Label k is entry k-1; 0 stays "unlabelled".
void read_labels(const InputNode& root, const std::string& base_directory, DemRunConfig& cfg) {
  if (!root.has("labels")) return;
  Particles& p = cfg.particles;
  std::fill(p.label.begin(), p.label.end(), 0);
  p.label_names.clear();
  std::vector<std::string> paths;
  for (const InputNode& l : root.list("labels")) {
    const std::string name = l.string("name");
    if (name.empty()) throw input_error(l.path() + ".name", "\"\"", "a label needs a name");
    if (std::find(p.label_names.begin(), p.label_names.end(), name) != p.label_names.end())
      throw input_error(l.path() + ".name", name, "the name is already used by an earlier label");
    const Region region = read_carving_region(l.child("region"), base_directory, cfg);
    p.label_names.push_back(name);
    paths.push_back(l.path());
    const int k = static_cast<int>(p.label_names.size());
    for (std::size_t i = 0; i < p.size(); ++i)
      if (region.contains({p.x[i], p.y[i], p.z[i]})) p.label[i] = k;
  }
  std::vector<long> count(p.label_names.size() + 1, 0);
  for (int k : p.label) ++count[static_cast<std::size_t>(k)];
  for (std::size_t k = 1; k < count.size(); ++k)
    if (count[k] == 0)
      throw input_error(paths[k - 1] + ".name", p.label_names[k - 1],
                        "the label holds no particle (its region selects none, or later labels take them all)");
}

// "groups[1].stress", or "stress" for a key of the root (a stage's motion node read on its own).
std::string key_path(const InputNode& n, const std::string& key) { return n.path().empty() ? key : n.path() + "." + key; }

// The text of a 3-vector as the input gave it, "[10 m/s, free, 0]", for messages.
std::string vector_text(const InputNode& n, const std::string& key) {
  std::string t = "[";
  const std::vector<InputNode> e = n.list(key);
  for (std::size_t a = 0; a < e.size(); ++a) t += (a ? ", " : "") + (e[a].is_scalar() ? e[a].text() : std::string("..."));
  return t + "]";
}

void read_groups(const InputNode& root, const std::string& base_directory, DemRunConfig& cfg) {
  if (!root.has("groups")) return;
  for (const InputNode& g : root.list("groups")) {
    Group group;
    group.name = g.string("name");
    // The name heads thermo.csv columns (name_fx, ...): no CSV separators, quotes or line breaks in it.
    if (group.name.empty() || group.name.find_first_of(",\"\n\r") != std::string::npos)
      throw input_error(g.path() + ".name", "'" + group.name + "'",
                        "a group name must be non-empty, without ',', '\"' or line breaks (it heads thermo.csv columns)");
    for (const Group& other : cfg.groups.list)
      if (other.name == group.name) throw input_error(g.path() + ".name", group.name, "two groups have this name");
    read_group_motion(g, cfg.box, group);
    // Membership: a region, particle types, or explicit ids (any combination narrows it down).
    Region region;
    bool any_rule = false;
    if (g.has("region")) {
      any_rule = true;
      region = read_carving_region(g.child("region"), base_directory, cfg);
    }
    std::vector<long> types, ids;
    if (g.has("types")) {
      any_rule = true;
      for (const InputNode& t : g.list("types")) types.push_back(t.integer());
    }
    if (g.has("ids")) {
      any_rule = true;
      for (const InputNode& t : g.list("ids")) ids.push_back(t.integer());
    }
    if (!any_rule)
      throw input_error(g.path(), group.name, "a group needs a 'region', 'types' or 'ids' to choose its members");
    const int index = cfg.groups.add(group);
    Particles& p = cfg.particles;
    long members = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
      bool in = region.contains({p.x[i], p.y[i], p.z[i]});
      if (!types.empty()) in = in && std::find(types.begin(), types.end(), p.type[i]) != types.end();
      if (!ids.empty()) in = in && std::find(ids.begin(), ids.end(), p.id[i]) != ids.end();
      if (!in) continue;
      if (p.group[i] >= 0 && p.group[i] != index)
        throw input_error(g.path() + ".name", group.name,
                          "particle id " + std::to_string(p.id[i]) + " is already in group '" +
                              cfg.groups.list[static_cast<std::size_t>(p.group[i])].name + "' (a particle moves with one group)");
      p.group[i] = index;
      ++members;
    }
    if (members == 0) throw input_error(g.path() + ".name", group.name, "the group selects no particle");
  }
}

// What stage `st` changes; its name and length were read by read_stage_lengths.
DemStageChanges read_stage_changes(const InputNode& st, const DemRunConfig& cfg) {
  DemStageChanges c;
  if (st.has("global_damping")) {
    const double d = st.quantity("global_damping", units::dimensionless);
    if (!(d >= 0.0) || !std::isfinite(d))
      throw input_error(st.path() + ".global_damping", format_value(d), "must be >= 0 (a fraction of c_c, eq 21)");
    c.global_damping = d;
  }
  if (st.has("adhesive")) c.adhesive = st.boolean("adhesive");
  if (st.has("tangential")) c.tangential = st.boolean("tangential");
  if (st.has("groups")) {
    for (const InputNode& g : st.list("groups")) {
      const std::string name = g.string("name");
      DemStageChanges::GroupChange change;
      change.group = cfg.groups.find(name);
      if (change.group < 0) {
        std::string known;
        for (const Group& gr : cfg.groups.list) known += (known.empty() ? "" : ", ") + gr.name;
        throw input_error(g.path() + ".name", name,
                          "no such group (groups: " + (known.empty() ? std::string("none") : known) + ")");
      }
      for (const DemStageChanges::GroupChange& other : c.groups)
        if (other.group == change.group)
          throw input_error(g.path() + ".name", name, "the stage changes this group twice");
      change.motion = cfg.groups.list[static_cast<std::size_t>(change.group)];
      read_group_motion(g, cfg.box, change.motion);
      change.keep_velocity = change.motion.motion == GroupMotion::force && !g.has("initial_velocity");
      if (g.has("set_velocity")) {
        if (change.motion.motion != GroupMotion::free)
          throw input_error(key_path(g, "set_velocity"), vector_text(g, "set_velocity"),
                            "only a free group's members take a velocity of their own; a rigid group moves "
                            "with its 'velocity' (motion: velocity) or its load (motion: force)");
        change.set_velocity = g.vec3("set_velocity", units::velocity);
      }
      c.groups.push_back(change);
    }
  }
  return c;
}

}  // namespace

namespace {

// Fills the motion fields of `group`, which start at their defaults.
void read_motion_fields(const InputNode& g, const Box& box, Group& group) {
  const std::string motion = g.choice("motion", {"free", "frozen", "velocity", "force"}, "free");
  group.motion = motion == "free"       ? GroupMotion::free
                 : motion == "frozen"   ? GroupMotion::frozen
                 : motion == "velocity" ? GroupMotion::velocity
                                        : GroupMotion::force;
  if (group.motion == GroupMotion::velocity) {
    if (g.has("velocity") && g.child("velocity").is_sequence())
      for (const InputNode& e : g.list("velocity"))
        if (e.is_scalar() && e.text() == "free")
          throw input_error(key_path(g, "velocity"), vector_text(g, "velocity"),
                            "a velocity group prescribes every axis; for a free axis use 'motion: force' with a load");
    group.velocity = g.vec3("velocity", units::velocity);
    return;
  }
  if (group.motion != GroupMotion::force) return;

  // Optional per-axis velocity: a quantity prescribes the axis, `free` leaves it to the load.
  Vec3 prescribed_velocity{};
  if (g.has("velocity")) {
    const std::vector<InputNode> v = g.list("velocity");
    if (v.size() != 3)
      throw input_error(key_path(g, "velocity"), std::to_string(v.size()) + " values",
                        "give [vx, vy, vz], each a velocity or 'free' (left to the load)");
    double c[3] = {0, 0, 0};
    for (std::size_t a = 0; a < 3; ++a) {
      const bool is_free = v[a].is_scalar() && v[a].text() == "free";
      group.prescribed[a] = !is_free;  // a non-scalar entry falls to quantity(), whose error names it
      if (!is_free) c[a] = v[a].quantity(units::velocity);
    }
    prescribed_velocity = {c[0], c[1], c[2]};
  }

  const bool has_force = g.has("force"), has_stress = g.has("stress");
  if (has_force == has_stress)
    throw input_error(key_path(g, "force"), has_force ? "both force and stress" : "neither",
                      "a force group needs exactly one of 'force' (a vector) or 'stress' (a traction vector)");
  const std::string load_key = has_force ? "force" : "stress";
  const Vec3 load = has_force ? g.vec3("force", units::force) : g.vec3("stress", units::pressure);
  if (has_force) {
    group.external_force = load;
  } else {
    const double comps[3] = {std::abs(load.x), std::abs(load.y), std::abs(load.z)};
    const int largest = comps[0] >= comps[1] && comps[0] >= comps[2] ? 0 : (comps[1] >= comps[2] ? 1 : 2);
    const int normal = axis_of(g, "area_normal", std::string(1, "xyz"[largest]));
    double area = 1.0;
    for (int a = 0; a < 3; ++a)
      if (a != normal) area *= box.length(a);
    group.external_force = area * load;
  }
  // A prescribed axis takes no load: the wall would not move under it, and its kick is dropped.
  const double load_c[3] = {load.x, load.y, load.z};
  for (int a = 0; a < 3; ++a)
    if (group.prescribed[static_cast<std::size_t>(a)] && load_c[a] != 0.0)
      throw input_error(key_path(g, load_key), vector_text(g, load_key),
                        std::string("the ") + "xyz"[a] + " velocity is prescribed (" + key_path(g, "velocity") + " = " +
                            vector_text(g, "velocity") + "), so that axis takes no load; give 0 there or make it 'free'");

  // initial_velocity starts the free axes; on a prescribed axis it can only repeat the prescribed value.
  const Vec3 initial = g.vec3("initial_velocity", units::velocity, Vec3{});
  const double init_c[3] = {initial.x, initial.y, initial.z};
  const double pres_c[3] = {prescribed_velocity.x, prescribed_velocity.y, prescribed_velocity.z};
  double v[3];
  for (int a = 0; a < 3; ++a) {
    const bool fixed = group.prescribed[static_cast<std::size_t>(a)];
    if (fixed && init_c[a] != 0.0 && init_c[a] != pres_c[a])
      throw input_error(key_path(g, "initial_velocity"), vector_text(g, "initial_velocity"),
                        std::string("the ") + "xyz"[a] + " velocity is prescribed by " +
                            key_path(g, "velocity") + "; give initial values for the free axes only (0 on prescribed ones)");
    v[a] = fixed ? pres_c[a] : init_c[a];
  }
  group.velocity = {v[0], v[1], v[2]};
}

}  // namespace

void read_group_motion(const InputNode& node, const Box& box, Group& group) {
  // Every motion field is reset, so a stage that changes a group's motion starts from a clean slate; the
  // group is changed only once the whole node has been read (a bad node leaves it as it was).
  Group next = group;
  next.motion = GroupMotion::free;
  next.velocity = Vec3{};
  next.external_force = Vec3{};
  next.prescribed = {false, false, false};
  read_motion_fields(node, box, next);
  group = std::move(next);
}

DemRunConfig read_dem_input(const std::string& path) {
  const InputNode root = InputNode::load_file(path);
  return read_dem_input(root, std::filesystem::path(path).parent_path().string());
}

namespace {

// The run keys a checkpoint fixes (DemSettings); the others (steps, threads, overlap_limit) apply at a restart.
const std::vector<std::string> kPhysicsRunKeys{"time_step", "time_step_fraction", "allow_unstable_time_step",
                                               "global_damping", "skin", "adhesive", "tangential"};

// A restart: the parts of `root` the checkpoint fixes are skipped (never read: no data file is opened), and
// those whose text differs from the input the checkpoint keeps are listed.
void skip_restored_parts(const InputNode& root, const DemInputOptions& options, DemRunConfig& cfg) {
  const InputNode echo = InputNode::load_string(options.checkpoint_echo, "the checkpoint's input");
  std::vector<std::string> fixed{"material", "particles", "box", "remove", "labels", "groups"};
  for (const std::string& key : fixed) root.skip(key);
  if (root.has("run"))
    for (const std::string& key : kPhysicsRunKeys) root.child("run").skip(key);
  for (const std::string& key : kPhysicsRunKeys) fixed.push_back("run." + key);
  cfg.ignored_at_restart = differing_keys(root, echo, fixed);
  cfg.box = options.restored->box();
  cfg.groups = options.restored->groups();
}


// The system: material, particles (a lattice or a LAMMPS data file) wrapped into the box, carved, labelled,
// grouped.
void read_system(const InputNode& root, const std::string& base_directory, DemRunConfig& cfg) {
  cfg.settings.material = read_cohesive_material(root.child("material"), {}, {.required = true});

  // Particles: a built-in lattice or a LAMMPS data file (atom_style sphere).
  const InputNode parts = root.child("particles");
  const bool has_lattice = parts.has("lattice"), has_data = parts.has("lammps_data");
  if (has_lattice == has_data)
    throw input_error("particles", has_lattice ? "lattice and lammps_data" : "nothing",
                      "give exactly one of 'lattice' or 'lammps_data'");
  const InputNode box_node = root.has("box") ? root.child("box") : InputNode::load_string("{}", "box");
  const std::array<bool, 3> periodic = read_periodic(box_node);
  bool masses_given = false;
  if (has_lattice) {
    Lattice lat = make_lattice(read_lattice(parts.child("lattice")));
    cfg.particles = std::move(lat.particles);
    cfg.box = Box(lat.box.lo(), lat.box.hi(), periodic);
  } else {
    const std::string given = parts.string("lammps_data");
    std::filesystem::path file = given;
    if (file.is_relative() && !base_directory.empty()) file = std::filesystem::path(base_directory) / file;
    // Named by its key, with the path it was looked for at: a relative path follows the input file, not
    // the working directory, which is what a copied input most often trips over.
    std::error_code ec;
    if (!std::filesystem::is_regular_file(file, ec))
      throw input_error(parts.path() + ".lammps_data", given,
                        std::string(std::filesystem::exists(file, ec) ? "is not a file" : "no such file") +
                            " (looked for at " + file.lexically_normal().string() +
                            (std::filesystem::path(given).is_relative() && !base_directory.empty()
                                 ? "; a relative path is taken from the input file's folder"
                                 : "") +
                            ")");
    LammpsData data = read_lammps_data(file.string(), periodic);
    cfg.particles = std::move(data.particles);
    cfg.box = Box(data.box.lo(), data.box.hi(), periodic);
    masses_given = parts.boolean("masses_from_file", false);
  }
  if (parts.has("replicate")) {
    const std::vector<double> n = parts.numbers("replicate", units::dimensionless);
    const std::string key = parts.path() + ".replicate";
    if (n.size() != 3) throw input_error(key, parts.yaml_of("replicate"), "give three counts [n_x, n_y, n_z]");
    std::array<int, 3> count{};
    double total = static_cast<double>(cfg.particles.size());
    for (int a = 0; a < 3; ++a) {
      if (!(n[a] >= 1) || n[a] != std::floor(n[a]) || n[a] > 1000)
        throw input_error(key, parts.yaml_of("replicate"), "each count is a whole number from 1 to 1000");
      count[a] = static_cast<int>(n[a]);
      total *= n[a];
    }
    if (total > 2e9)
      throw input_error(key, parts.yaml_of("replicate"),
                        "would make " + format_value(total) + " particles (at most 2e9 fit the index type)");
    replicate_sample(cfg.particles, cfg.box, count);
  }
  if (box_node.has("lo") || box_node.has("hi")) {
    cfg.box = Box(box_node.vec3("lo", units::length, cfg.box.lo()), box_node.vec3("hi", units::length, cfg.box.hi()),
                  periodic);
  }
  // Regions test positions in the box (core/region.hpp): fold the periodic axes now, as the first
  // neighbour build would (same arithmetic, so a run is unchanged), counting the crossings in ix/iy/iz.
  cfg.box.wrap(cfg.particles);
  // Carving, then labels, then groups, so that labels and groups see the carved system.
  read_removal(root, base_directory, cfg);
  read_labels(root, base_directory, cfg);
  read_groups(root, base_directory, cfg);
  cfg.settings.masses_from_density = !masses_given;
}

// The physics keys of `run`.
void read_physics(const InputNode& run, DemSettings& s) {
  if (run.has("time_step") && run.has("time_step_fraction"))
    throw input_error("run.time_step", "given with time_step_fraction", "give one of time_step (absolute) or time_step_fraction (of dt_c)");
  s.time_step = run.quantity("time_step", units::time, 0.0);
  if (run.has("time_step") && !(s.time_step > 0.0)) throw input_error("run.time_step", format_value(s.time_step), "must be > 0");
  s.time_step_fraction = run.quantity("time_step_fraction", units::dimensionless, 0.1);
  if (!(s.time_step_fraction > 0.0))
    throw input_error("run.time_step_fraction", format_value(s.time_step_fraction), "must be > 0 (a fraction of dt_c, eq 6)");
  s.allow_unstable_time_step = run.boolean("allow_unstable_time_step", false);
  s.global_damping = run.quantity("global_damping", units::dimensionless, 0.0);
  if (!(s.global_damping >= 0.0)) throw input_error("run.global_damping", format_value(s.global_damping), "must be >= 0 (a fraction of c_c, eq 21)");
  s.skin = run.quantity("skin", units::length, 0.0);
  if (s.skin < 0.0) throw input_error("run.skin", format_value(s.skin), "must be >= 0");
  s.options.adhesive = run.boolean("adhesive", true) ? 1 : 0;
  s.options.tangential = run.boolean("tangential", true) ? 1 : 0;
}

// The health check's limit and the threads.
void read_checks(const InputNode& run, DemRunConfig& cfg) {
  if (run.has("overlap_limit")) {
    if (run.child("overlap_limit").text() == "auto") {
      cfg.overlap_limit_auto = true;
    } else {
      cfg.overlap_limit = run.quantity("overlap_limit", units::dimensionless);
      if (!(cfg.overlap_limit > 0) || !std::isfinite(cfg.overlap_limit))
        throw input_error("run.overlap_limit", format_value(cfg.overlap_limit),
                          "must be > 0 (in smallest radii) or auto (the deepest initial overlap + one smallest radius)");
    }
  }
  cfg.threads = static_cast<int>(run.integer("threads", 0));
  if (cfg.threads < 0) throw input_error("run.threads", std::to_string(cfg.threads), "must be >= 0");
}

void read_output(const InputNode& out, DemOutputSettings& o) {
  o.directory = out.string("directory", o.directory);
  o.thermo_every = out.integer("thermo_every", o.thermo_every);
  if (o.thermo_every < 1) throw input_error("output.thermo_every", std::to_string(o.thermo_every), "must be >= 1");
  o.dump_every = out.integer("dump_every", o.dump_every);
  if (o.dump_every < 0) throw input_error("output.dump_every", std::to_string(o.dump_every), "must be >= 0");
  o.trajectory_every = out.integer("trajectory_every", 0);
  if (o.trajectory_every < 0)
    throw input_error("output.trajectory_every", std::to_string(o.trajectory_every), "must be >= 0");
  o.checkpoint_every = out.integer("checkpoint_every", 0);
  if (o.checkpoint_every < 0)
    throw input_error("output.checkpoint_every", std::to_string(o.checkpoint_every), "must be >= 0");
  o.progress_seconds = out.quantity("progress_seconds", units::time, 10.0);
  if (!(o.progress_seconds > 0))
    throw input_error("output.progress_seconds", format_value(o.progress_seconds), "must be > 0");
  o.pictures = out.boolean("pictures", false);
  o.energy = out.boolean("energy", true);
}

// Stages, run control, the wear analysis, the wear census and output. `restored`: the physics keys of `run` were skipped.
void read_run_control(const InputNode& root, DemRunConfig& cfg, bool restored) {
  const InputNode run = root.child("run");
  std::vector<InputNode> stage_nodes;
  cfg.stages = read_stage_lengths(root, &stage_nodes);
  for (const InputNode& st : stage_nodes) cfg.stage_changes.push_back(read_stage_changes(st, cfg));
  // With stages, run.steps may stop the run early (a chunk of a long run); without, it is the length.
  cfg.steps = cfg.stages.empty() || run.has("steps") ? run.integer("steps") : -1;
  if (run.has("steps") && cfg.steps < 0) throw input_error("run.steps", std::to_string(cfg.steps), "must be >= 0");
  if (!restored) read_physics(run, cfg.settings);
  read_checks(run, cfg);
  if (root.has("wear")) cfg.wear = read_wear_settings(root.child("wear"));
  if (root.has("surfaces")) cfg.surfaces = read_surface_settings(root.child("surfaces"));
  if (root.has("output")) read_output(root.child("output"), cfg.output);
  // A restart keeps the accounting of the run it continues (its sums are in the checkpoint).
  if (!restored) cfg.settings.energy_accounting = cfg.output.energy;
}

}  // namespace

DemRunConfig read_dem_input(const InputNode& root, const std::string& base_directory, const DemInputOptions& options) {
  DemRunConfig cfg;
  if (options.restored) {
    skip_restored_parts(root, options, cfg);
  } else {
    read_system(root, base_directory, cfg);
  }
  read_run_control(root, cfg, options.restored != nullptr);
  root.reject_unknown_keys();
  audit_keys(root, dem_keys());
  cfg.plain_quantities = root.plain_beside_units();
  return cfg;
}

DemRunConfig read_dem_input_text(const std::string& text, const std::string& name, const std::string& base_directory,
                                 const DemInputOptions& options) {
  return read_dem_input(InputNode::load_string(text, name), base_directory, options);
}

}  // namespace debris
