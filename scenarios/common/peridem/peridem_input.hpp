#pragma once
// Reads a debris_peridem input file (YAML, quantities with units, paper B's model) into a ready-to-run
// system: materials, reference shapes (Gmsh shapes of scenarios/common/peridem/shape_mesh.hpp or .msh files), grains listed
// one by one and/or from a PeriDEM particle CSV, rigid walls, contact settings, gravity, run and output
// control. Unknown keys are rejected and every bad value is an InputError naming the key and the value, all
// before any output is opened, so a bad input never touches earlier results. Relative paths (mesh files,
// the particle CSV) are relative to the input file. The layout, with every key:
//
//   dimension: 2                                  # 2 (plane strain, z = 0) or 3
//   materials:                                    # by name
//     M1: {density: 1200 kg/m^3, bulk_modulus: 0.0216 GPa, shear_modulus: 0.01296 GPa,
//          fracture_energy: 50 J/m^2, horizon: 0.6 mm, lps_constants: plane_strain,   # or peridem_code (2D)
//          bond_breaking: tension}              # or tension_and_compression (|s| >= s_0, the authors' code)
//   shapes:                                       # by name; Gmsh shapes (scenarios/common/peridem/shape_mesh.hpp) or files
//     disc:  {type: circle, radius: 1 mm, mesh_size: 0.2 mm}                   # also sphere (3D)
//     hex:   {type: hexagon, radius: 1 mm, mesh_size: 0.2 mm, axis: [1, 0, 0]}
//     drum:  {type: concave_polygon, radius: 1 mm, neck_half_width: 0.2 mm, mesh_size: 0.1 mm}
//     floor: {type: rectangle, lo: [..], hi: [..], mesh_size: 0.2 mm}         # also box (3D)
//     cup:   {type: rectangle_minus_rectangle, lo, hi, inner_lo, inner_hi, mesh_size}
//     ref:   {type: mesh_file, file: mesh.msh, reference_radius: 1 mm}        # Gmsh MSH 2.2 or 4.1
//   (circle, hexagon, concave_polygon and sphere take an optional centre: [..]). A grain is its shape's
//   mesh scaled by radius / R_ref about the mesh origin, rotated about z, moved to its centre: grain shapes
//   are drawn about the origin. R_ref = reference_radius, by default the shape's radius; rectangles,
//   boxes and mesh files used by grains need reference_radius.
//   grains:                                       # explicit grains (after those of particle_file)
//     - {name: top, shape: disc, material: M1, centre: [0, 3 mm, 0], radius: 1 mm, rotation: 0,
//        velocity: [0, -2 m/s, 0], fixed: false}  # fixed: true, false, or a list of axes [x, y]
//   particle_file:                                # PeriDEM's CSV: i, x, y, z, r, o (zone i -> zones[i])
//     file: particle_locations_0.csv
//     zones: [{shape: disc, material: M1, velocity: [0, 0, 0]}, ...]
//   walls:                                        # rigid, meshed like a grain, placed as given
//     - {name: floor, shape: floor, material: M1, velocity: [0, 0, 0]}              # zero: fixed
//   contact:                                      # every pair of materials; `pairs` overrides one pair
//     contact_radius_factor: 0.95, restitution: 0.95, damping_factor: 100, friction: 0, stiffness_factor: 1,
//     damping_onset_factor: 1, damping: grain_centres,             # or node_pairs (one for the run)
//     pairs: [{materials: [M1, M2], restitution: 0.9, ...}]
//   gravity: [0, -10 m/s^2, 0]
//   stages: [...]                                 # optional: see PeridemStageChanges below
//   run: {time_step: 0.1 us, steps: 1000 (or final_time: 1 ms; with stages optional), skin: 0 (R_c), threads: 0,
//         allow_unstable_time_step: false, penetration_limit: 0.5,
//         global_damping: 0 s^-1}                # F -= c m v on particle nodes (settling; not paper B's model)
//   output: {directory: out, thermo_every: 100, trajectory_every: 0, checkpoint_every: 0,
//            progress_seconds: 10, grain_columns: 8}
//
// Grain order: the CSV's grains first in PeriDEM's order (so a grain's index is PeriDEM's particle id),
// then the explicit grains in file order, then the walls. Gmsh shapes are meshed into
// <output directory>/meshes (reused when the same script was meshed before).
#include <optional>
#include <string>
#include <vector>

#include "core/pd_nodes.hpp"
#include "kernels/peridem/pd_contact_params.hpp"
#include "kernels/peridem/pd_material.hpp"
#include "scenarios/common/peridem/peridem_simulation.hpp"
#include "scenarios/common/run/stages.hpp"

namespace debris {

class InputNode;

struct PeridemOutputSettings {
  std::string directory = "out";
  long thermo_every = 100;       // thermo CSV row, terminal line and health check
  long trajectory_every = 0;     // HDF5 + XDMF node frame (ParaView); 0 = first and last step only
  long checkpoint_every = 0;     // checkpoint.h5; 0 = at the end only
  double progress_seconds = 10;  // progress line at most this often
  long grain_columns = 8;        // per-grain thermo columns (centre, velocity, damage) up to this many grains
};

/// What a stage of a debris_peridem run changes at its start (scenarios/common/run/stages.hpp):
///   stages:
///     - {name: settle, duration: 0.06 s}
///     - name: press
///       duration: 0.09 s
///       walls:                                   # by name (unnamed walls are wall0, wall1, ...)
///         - {name: lid, place: {y_min: 31.2 mm}, velocity: [0, -0.06 m/s, 0]}   # or move_by: [dx, dy, dz]
///       gravity: [0, -10 m/s^2, 0]
///       global_damping: 100 s^-1                 # F -= c m v on particle nodes from now on (0 ends it)
/// place: one of x_min, x_max, y_min, y_max, z_min, z_max: the wall moves rigidly along that axis until its
/// lowest (min) or highest (max) node is there. A wall that would then touch a grain is an InputError
/// naming both.
struct PeridemStageChanges {
  struct WallChange {
    std::string name, key;     // the wall's name; "stages[1].walls[0]" for messages
    std::optional<Vec3> velocity;
    std::optional<Vec3> move_by;
    int place_axis = -1;       // 0, 1, 2 with place_max and place_at, or -1
    bool place_max = false;
    double place_at = 0;
  };
  std::vector<WallChange> walls;
  std::optional<Vec3> gravity;
  std::optional<double> global_damping;  // 1/s
};

struct PeridemRunConfig {
  int dimension = 2;
  std::vector<std::string> material_names;
  std::vector<PdMaterial> materials;
  std::vector<PdContactSettings> contact;  // materials^2, symmetric
  PeridemSettings settings;
  PdNodes nodes;  // empty when read without building the system
  PdGrains grains;
  std::vector<std::string> grain_names;  // one per grain and wall (thermo columns)
  long steps = 0;  // total steps of the run (from run.steps or run.final_time); -1 when the stages give it
  std::vector<StageLength> stages;
  std::vector<PeridemStageChanges> stage_changes;  // one per stage
  int threads = 0;                       // 0 = OpenMP default
  double penetration_limit = 0.5;        // health check: a node pair closer than (1 - this) R_c stops the run
  PeridemOutputSettings output;
  /// Dimensional values given as plain numbers beside others with units (InputNode::plain_beside_units).
  std::vector<std::string> plain_quantities;
  /// Input that runs but deserves a word (a horizon below twice a shape's mesh size), printed at the start.
  std::vector<std::string> warnings;
};

struct PeridemInputOptions {
  /// false: read and check every key, but neither mesh shapes nor read mesh or CSV files (a restart takes
  /// its system from the checkpoint and needs only run and output).
  bool build_system = true;
  /// Replaces output.directory (the runner's -o) before anything uses it.
  std::string output_directory;
};

/// A file named in an input: relative paths are relative to the input file's directory `base` (empty: as
/// given).
std::string resolve_input_path(const std::string& file, const std::string& base);

/// One material of a `materials:` section (density, moduli, fracture energy, horizon, lps_constants,
/// bond_breaking), validated; InputError naming the key and the value.
PdMaterial read_pd_material(const InputNode& n, int dimension);

/// Reads the whole file; InputError naming the key and the value for anything missing, malformed, out of
/// range or unknown.
PeridemRunConfig read_peridem_input(const std::string& path, const PeridemInputOptions& options = {});
PeridemRunConfig read_peridem_input(const InputNode& root, const std::string& base_directory,
                                    const PeridemInputOptions& options = {});
/// From the text (the echo a checkpoint keeps); `name` stands for the file in messages.
PeridemRunConfig read_peridem_input_text(const std::string& text, const std::string& name,
                                         const std::string& base_directory, const PeridemInputOptions& options = {});

}  // namespace debris
