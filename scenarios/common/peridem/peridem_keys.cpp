#include "scenarios/common/peridem/peridem_keys.hpp"

#include <stdexcept>

#include "core/units.hpp"
#include "scenarios/common/run/stages.hpp"

namespace debris {

namespace {
namespace u = units;
const char* kNames = "letters, digits, `_`, `-`, `.`";
}  // namespace

void document_pd_material(KeyReference& r, const std::string& p) {
  r.key(p).is(KeyKind::section).fallback_is("").means("one material: density, elastic moduli, fracture energy and horizon");
  r.key(p + ".density").is(KeyKind::quantity).in(u::density).allowed("> 0, finite").means("mass density rho")
      .eq("B Table 1");
  r.key(p + ".bulk_modulus").is(KeyKind::quantity).in(u::pressure).allowed("> 0, finite")
      .means("bulk modulus kappa of the state-based (LPS) model; also sets the contact stiffness")
      .eq("B eqs 7-10, 25, 36");
  r.key(p + ".shear_modulus").is(KeyKind::quantity).in(u::pressure).allowed("> 0, finite")
      .means("shear modulus G of the LPS model").eq("B eqs 7-10");
  r.key(p + ".fracture_energy").is(KeyKind::quantity).in(u::surface_energy).allowed("> 0; `inf`: bonds never break")
      .means("critical energy release rate G_c; sets the critical stretch s_0 past which a bond breaks for good")
      .eq("B eq 10");
  r.key(p + ".horizon").is(KeyKind::quantity).in(u::length)
      .allowed("> 0, finite; every node of a grain bonded (horizon / mesh size >= 2 advised)")
      .means("peridynamic horizon epsilon: a node is bonded to the nodes of its grain closer than this; also "
             "sets the contact stiffness")
      .eq("B eqs 7, 10, 33, 36");
  r.key(p + ".lps_constants").one_of({"plane_strain", "peridem_code"}).fallback("plane_strain")
      .allowed("2D runs only")
      .means("`plane_strain`: the 2D constants that give a grain the material's K and G; `peridem_code`: the 3D "
             "constants on the 2D grain, as the authors' code (about 1.9 times stiffer)")
      .eq("B eqs 7-9");
  r.key(p + ".bond_breaking").one_of({"tension", "tension_and_compression"}).fallback("tension")
      .means("`tension`: a bond breaks once its stretch s >= s_0; `tension_and_compression`: once |s| >= s_0, as "
             "the authors' code")
      .eq("B eq 11");
}

KeyDoc& document_pd_contact_setting(KeyReference& r, const std::string& path, const std::string& setting) {
  KeyDoc& d = r.key(path);
  if (setting == "damping")
    return d.one_of({"grain_centres", "node_pairs"})
        .means("where contact damping acts: between the centres of two grains (`grain_centres`) or between "
               "each pair of touching nodes (`node_pairs`); one choice for the whole run")
        .eq("B eqs 21-30");
  d.is(KeyKind::quantity).in(u::dimensionless);
  if (setting == "contact_radius_factor")
    return d.allowed("> 0, finite")
        .means("contact radius R_c = factor h, h the smallest node spacing of the whole system")
        .eq("B eq 35");
  if (setting == "restitution")
    return d.allowed("(0, 1]").means("damping parameter epsilon_n of the contact damping; 1: no damping")
        .eq("B eqs 23, 28");
  if (setting == "damping_factor")
    return d.allowed("> 0, finite").means("the constant C (C-bar between grain centres) of the damping coefficient")
        .eq("B eqs 23, 28");
  if (setting == "friction")
    return d.allowed(">= 0, finite").means("Coulomb friction coefficient mu between nodes in contact")
        .eq("B eqs 19-20");
  if (setting == "stiffness_factor")
    return d.allowed("> 0, finite").means("multiplies the normal contact stiffness K_n").eq("B eq 36");
  if (setting == "damping_onset_factor")
    return d.allowed("[1, 2)")
        .means("the grain-centre damping acts while two grains are closer than this times R_c (1: the paper's "
               "text; the authors' code: 1.01)")
        .eq("B eq 27");
  throw std::logic_error("document_pd_contact_setting: no setting '" + setting + "'");
}

namespace {

const char* const kContactSettings[] = {"contact_radius_factor", "restitution", "damping_factor",
                                        "friction", "stiffness_factor", "damping_onset_factor"};

void document_shapes(KeyReference& r) {
  r.describe_section("shapes",
                     "A shape is meshed once, by Gmsh in-process (into `<output directory>/meshes`) or read from a "
                     "mesh file. A grain is its shape's mesh scaled by radius / R_ref about the mesh origin, rotated "
                     "about z and moved to its centre, so grain shapes are drawn about the origin; a wall is its "
                     "shape's mesh as drawn.");
  r.key("shapes").is(KeyKind::section).fallback_is("none").allowed(std::string("names: ") + kNames)
      .means("the reference shapes of grains and walls, by name");
  const std::string s = "shapes.<name>";
  r.key(s).is(KeyKind::section).fallback_is("").means("one shape: a Gmsh geometry, or a mesh file");
  r.key(s + ".type")
      .one_of({"circle", "hexagon", "concave_polygon", "rectangle", "rectangle_minus_rectangle", "sphere", "box",
               "mesh_file"})
      .allowed("`sphere` and `box` in 3D runs only, the others but `mesh_file` in 2D runs only")
      .means("the geometry, or `mesh_file`: a mesh read from `file`")
      .eq("B Fig 18");
  r.key(s + ".file").is(KeyKind::text).fallback_is("required by `mesh_file`")
      .allowed("an existing mesh file (ASCII MSH 2.2 or 4.1; other formats through Gmsh) of the run's dimension")
      .means("the mesh file, relative to the input file's directory");
  r.key(s + ".mesh_size").is(KeyKind::quantity).in(u::length).fallback_is("required by the Gmsh shapes")
      .allowed("> 0, finite").means("Gmsh's characteristic length h (the target edge length)");
  r.key(s + ".radius").is(KeyKind::quantity).in(u::length)
      .fallback_is("required by circle, sphere, hexagon, concave_polygon").allowed("> 0, finite")
      .means("a circle's or sphere's radius; a hexagon's or concave polygon's distance from centre to outer vertex");
  r.key(s + ".centre").is(KeyKind::vector).in(u::length).fallback("[0, 0, 0]").allowed("finite")
      .means("the centre of a circle, sphere, hexagon or concave polygon");
  r.key(s + ".axis").is(KeyKind::vector).in(u::dimensionless).fallback("[1, 0, 0]").allowed("non-zero, z = 0")
      .means("hexagon, concave polygon: the direction from the centre to the first vertex").eq("B Fig 18");
  r.key(s + ".neck_half_width").is(KeyKind::quantity).in(u::length).fallback_is("required by concave_polygon")
      .allowed("(0, radius / 2)").means("concave polygon: the distance w from the centre to each neck vertex")
      .eq("B Fig 18b");
  r.key(s + ".lo").is(KeyKind::vector).in(u::length)
      .fallback_is("required by rectangle, box, rectangle_minus_rectangle").allowed("finite")
      .means("the lower corner of a rectangle (in the plane z = lo.z) or box");
  r.key(s + ".hi").is(KeyKind::vector).in(u::length)
      .fallback_is("required by rectangle, box, rectangle_minus_rectangle")
      .allowed("> lo along x, y (and z for a box); a rectangle's z = lo.z").means("the upper corner");
  r.key(s + ".inner_lo").is(KeyKind::vector).in(u::length).fallback_is("required by rectangle_minus_rectangle")
      .allowed("z = lo.z").means("the lower corner of the rectangle taken away");
  r.key(s + ".inner_hi").is(KeyKind::vector).in(u::length).fallback_is("required by rectangle_minus_rectangle")
      .allowed("> inner_lo; the inner rectangle overlaps the outer one without covering it")
      .means("the upper corner of the rectangle taken away");
  r.key(s + ".reference_radius").is(KeyKind::quantity).in(u::length)
      .fallback_is("the shape's `radius`; rectangles, boxes and mesh files used by grains need it")
      .allowed("> 0, finite").means("R_ref: a grain of radius r is the shape's mesh scaled by r / R_ref");
}

/// velocity and fixed of a listed grain or a particle-file zone.
void document_grain_state(KeyReference& r, const std::string& p) {
  r.key(p + ".velocity").is(KeyKind::vector).in(u::velocity).fallback("[0, 0, 0]").allowed("2D: z = 0")
      .means("the initial velocity of every node");
  r.key(p + ".fixed").is(KeyKind::boolean).or_a_list().fallback("false").allowed("true, false, or a list of axes [x, y, z]")
      .means("nodes held at rest: `true` along every axis, a list along the axes named");
}

void document_grains(KeyReference& r) {
  r.key("grains").is(KeyKind::list).fallback_is("none")
      .allowed("at least one grain here or in `particle_file`")
      .means("grains listed one by one, placed after those of `particle_file`");
  r.key("grains.name").is(KeyKind::text).fallback_is("`grain<k>`, k the grain's index")
      .allowed(std::string(kNames) + "; unique among grains and walls")
      .means("the grain's name, which prefixes its thermo columns");
  r.key("grains.shape").is(KeyKind::text).allowed("a name under `shapes`").means("the grain's reference shape");
  r.key("grains.material").is(KeyKind::text).allowed("a name under `materials`").means("the grain's material");
  r.key("grains.centre").is(KeyKind::vector).in(u::length).allowed("2D: z = 0")
      .means("where the shape's mesh origin goes");
  r.key("grains.radius").is(KeyKind::quantity).in(u::length).fallback_is("the shape's `reference_radius`")
      .allowed("> 0, finite").means("the grain's radius r: the mesh is scaled by r / R_ref");
  r.key("grains.rotation").is(KeyKind::quantity).in(u::dimensionless).fallback("0").allowed("finite")
      .means("rotation about z, in radians");
  document_grain_state(r, "grains");

  r.describe_section("particle_file",
                     "PeriDEM's particle list, a CSV with the header `i, x, y, z, r, o`: one grain a line, its zone "
                     "i (0-based), centre, radius and orientation (radians, about z), in SI units. Its grains come "
                     "first, zone by zone and in file order within a zone, named `grain<k>`.");
  r.key("particle_file").is(KeyKind::section).fallback_is("none")
      .allowed("at least one grain here or in `grains`").means("grains placed from a PeriDEM particle list");
  r.key("particle_file.file").is(KeyKind::text).allowed("an existing CSV listing at least one grain")
      .means("the particle list, relative to the input file's directory");
  r.key("particle_file.zones").is(KeyKind::list).allowed("at least one entry")
      .means("what the grains of each zone are: entry i for the rows of zone i");
  r.key("particle_file.zones.shape").is(KeyKind::text).allowed("a name under `shapes`")
      .means("the zone's reference shape");
  r.key("particle_file.zones.material").is(KeyKind::text).allowed("a name under `materials`")
      .means("the zone's material");
  document_grain_state(r, "particle_file.zones");
}

void document_walls(KeyReference& r) {
  r.key("walls").is(KeyKind::list).fallback_is("none")
      .means("rigid walls, each its shape's mesh as drawn, moving at a constant velocity (stages may move them)");
  r.key("walls.name").is(KeyKind::text).fallback_is("`wall<k>`, k the wall's place in `walls`")
      .allowed(std::string(kNames) + "; unique among grains and walls")
      .means("the wall's name, which prefixes its reaction columns and names it in `stages`");
  r.key("walls.shape").is(KeyKind::text).allowed("a name under `shapes`").means("the wall's shape");
  r.key("walls.material").is(KeyKind::text).allowed("a name under `materials`")
      .means("the wall's material (its bulk modulus and horizon enter the contact stiffness)");
  r.key("walls.velocity").is(KeyKind::vector).in(u::velocity).fallback("[0, 0, 0]").allowed("2D: z = 0")
      .means("the wall's velocity; zero: a fixed wall");
}

void document_contact(KeyReference& r) {
  r.describe_section("contact",
                     "Node-to-node contact between different bodies and across broken bonds: a normal spring K_n, "
                     "damping and friction, within the contact radius R_c. One set of settings for every pair of "
                     "materials, which `pairs` overrides pair by pair.");
  r.key("contact").is(KeyKind::section).fallback_is("every setting at its default")
      .means("the contact law of every pair of materials");
  for (const char* setting : kContactSettings) {
    KeyDoc& d = document_pd_contact_setting(r, std::string("contact.") + setting, setting);
    const std::string name = setting;
    d.fallback(name == "contact_radius_factor" ? "0.95"
               : name == "damping_factor"      ? "100"
               : name == "friction"            ? "0"
                                               : "1");
  }
  document_pd_contact_setting(r, "contact.damping", "damping").fallback("grain_centres");
  r.key("contact.pairs").is(KeyKind::list).fallback_is("none").allowed("each pair of materials at most once")
      .means("the settings of one pair of materials, over those of `contact`");
  r.key("contact.pairs.materials").is(KeyKind::list).allowed("two names under `materials`")
      .means("the pair, [a, b] (either order)");
  for (const char* setting : kContactSettings)
    document_pd_contact_setting(r, std::string("contact.pairs.") + setting, setting)
        .fallback_is(std::string("the value of `contact.") + setting + "`");
}

void document_run(KeyReference& r) {
  r.key("run").is(KeyKind::section).means("time step, length and numerics of the run");
  r.key("run.time_step").is(KeyKind::quantity).in(u::time)
      .allowed("> 0; at most the stable estimate unless `allow_unstable_time_step`")
      .means("the time step dt").eq("B eq 32");
  r.key("run.steps").is(KeyKind::integer).fallback_is("give steps or final_time; with stages, their length")
      .allowed(">= 0; with stages at most their end")
      .means("the run's last step, counted from step 0 (a restart's too)");
  r.key("run.final_time").is(KeyKind::quantity).in(u::time)
      .fallback_is("give steps or final_time; with stages, their length").allowed(">= 0")
      .means("the run's length as a time, rounded to whole steps");
  r.key("run.skin").is(KeyKind::quantity).in(u::length).fallback("0").allowed(">= 0")
      .means("Verlet skin of the contact list; 0: the contact radius R_c");
  r.key("run.allow_unstable_time_step").is(KeyKind::boolean).fallback("false")
      .means("run a time step above the stable estimate (the bonds' largest frequency and one contact spring)");
  r.key("run.global_damping").is(KeyKind::quantity).in(u::frequency).fallback("0")
      .allowed(">= 0, rate * time_step < 1")
      .means("a viscous damping rate c: F -= c m v on every grain node (to settle a pack; not in paper B's model)");
  r.key("run.penetration_limit").is(KeyKind::quantity).in(u::dimensionless).fallback("0.5").allowed("(0, 1]")
      .means("a node pair of two bodies closer than (1 - this) R_c stops the run (exit 3; at set-up exit 2); 1: "
             "never");
  r.key("run.threads").is(KeyKind::integer).fallback("0").allowed(">= 0")
      .means("host threads (`--threads` overrides); 0: OMP_NUM_THREADS, else tuned while stepping");
}

void document_stage_changes(KeyReference& r) {
  r.key("stages.gravity").is(KeyKind::vector).in(u::acceleration).fallback_is("unchanged").allowed("2D: z = 0")
      .means("gravity from this stage on");
  r.key("stages.global_damping").is(KeyKind::quantity).in(u::frequency).fallback_is("unchanged")
      .allowed(">= 0, rate * run.time_step < 1").means("the viscous damping rate from this stage on (0 ends it)");
  r.key("stages.walls").is(KeyKind::list).fallback_is("none").allowed("each wall at most once per stage")
      .means("changes to walls, by name; each gives velocity, place or move_by");
  r.key("stages.walls.name").is(KeyKind::text).allowed("a wall's name (`wall<k>` for an unnamed one)")
      .means("the wall changed");
  r.key("stages.walls.velocity").is(KeyKind::vector).in(u::velocity).fallback_is("unchanged").allowed("2D: z = 0")
      .means("the wall's velocity from this stage on");
  r.key("stages.walls.move_by").is(KeyKind::vector).in(u::length).fallback_is("no move")
      .allowed("2D: z = 0; not with `place`").means("moves the wall rigidly by this");
  r.key("stages.walls.place").is(KeyKind::section).fallback_is("no move")
      .allowed("one key: `x_min`, `x_max`, `y_min`, `y_max`, `z_min`, `z_max` (z in 3D only); not with `move_by`")
      .means("moves the wall rigidly along one axis until its lowest (`_min`) or highest (`_max`) node is at the "
             "given coordinate; a wall that then touches a grain is bad input");
  r.key("stages.walls.place.<side>").is(KeyKind::quantity).in(u::length).allowed("finite")
      .means("that coordinate, e.g. `{y_min: 31.2 mm}`");
}

void document_output(KeyReference& r) {
  r.key("output").is(KeyKind::section).fallback_is("every setting at its default")
      .means("what is written, and how often");
  r.key("output.directory").is(KeyKind::text).fallback("out")
      .means("the output directory, relative to the working directory (`-o` overrides it)");
  r.key("output.thermo_every").is(KeyKind::integer).fallback("100").allowed(">= 1")
      .means("steps between thermo rows, terminal lines and health checks");
  r.key("output.trajectory_every").is(KeyKind::integer).fallback("0").allowed(">= 0")
      .means("steps between node frames of the trajectory; 0: the first and last step only");
  r.key("output.checkpoint_every").is(KeyKind::integer).fallback("0").allowed(">= 0")
      .means("steps between checkpoints, written also at each stage's start and at the end; 0: only those");
  r.key("output.progress_seconds").is(KeyKind::quantity).in(u::time).fallback("10").allowed("> 0")
      .means("wall time between progress lines, at least");
  r.key("output.grain_columns").is(KeyKind::integer).fallback("8").allowed(">= 0")
      .means("the per-grain thermo columns are written when the run has at most this many grains");
}

}  // namespace

const KeyReference& peridem_keys() {
  static const KeyReference ref = [] {
    KeyReference r("debris_peridem");
    r.key("dimension").is(KeyKind::integer).fallback("2").allowed("2 or 3")
        .means("2: plane strain, every node in the plane z = 0; 3: three dimensions");
    r.describe_section("materials",
                       "Materials by name; grains, walls and contact pairs name them. The paper's M1 and M2 are "
                       "in Table 1.");
    r.key("materials").is(KeyKind::section).allowed(std::string("at least one; names: ") + kNames)
        .means("the materials, by name").eq("B Table 1");
    document_pd_material(r, "materials.<name>");
    document_shapes(r);
    document_grains(r);
    document_walls(r);
    document_contact(r);
    r.key("gravity").is(KeyKind::vector).in(u::acceleration).fallback("[0, 0, 0]").allowed("2D: z = 0")
        .means("gravitational acceleration of the grains' nodes (walls move only as told)");
    document_run(r);
    document_stage_lengths(r);
    document_stage_changes(r);
    document_output(r);
    return r;
  }();
  return ref;
}

const ColumnTable& peridem_thermo_table() {
  static const ColumnTable t{
      "thermo.csv",
      "One row every `output.thermo_every` steps (and at the first and last step); SI, or the input's own units "
      "when it gives none. Walls are the rigid walls of `walls:`; the per-grain columns are written when the run "
      "has at most `output.grain_columns` grains.",
      {
          {"step", "-", "time step number, counted from the start of the run", ""},
          {"time", "s", "simulated time", ""},
          {"kinetic_energy", "J", "kinetic energy of the grains' nodes (walls left out)", ""},
          {"bond_energy", "J", "peridynamic strain energy of the grains' bonds", ""},
          {"contact_energy", "J", "energy stored in the node-to-node and node-to-wall contact springs", ""},
          {"max_damage", "-",
           "largest damage Z of a node: its largest |bond stretch| / s_0, broken bonds included, so Z >= 1 where "
           "a bond has broken and it keeps growing as the pieces part (paper B eq 14)",
           ""},
          {"broken_bonds", "-", "bonds broken so far", ""},
          {"contact_pairs", "-", "node pairs closer than the contact radius R_c, each counted once", ""},
          {"<wall>_fx", "N", "x component of the total contact force on the wall", ""},
          {"<wall>_fy", "N", "y component of that force", ""},
          {"<wall>_fz", "N", "z component of that force", "3D"},
          {"<grain>_x", "m", "x of the grain's centre of mass", "per grain"},
          {"<grain>_y", "m", "y of the grain's centre of mass", "per grain"},
          {"<grain>_z", "m", "z of the grain's centre of mass", "3D per grain"},
          {"<grain>_vx", "m/s", "x velocity of the grain's centre of mass", "per grain"},
          {"<grain>_vy", "m/s", "y velocity of the grain's centre of mass", "per grain"},
          {"<grain>_vz", "m/s", "z velocity of the grain's centre of mass", "3D per grain"},
          {"<grain>_kinetic_energy", "J", "the grain's kinetic energy", "per grain"},
          {"<grain>_damage", "-", "largest damage Z of the grain's nodes", "per grain"},
          {"<grain>_broken_bonds", "-", "bonds broken in the grain", "per grain"},
      }};
  return t;
}

std::vector<ColumnTable> peridem_output_columns() { return {peridem_thermo_table()}; }

}  // namespace debris
