#pragma once
// Reads a debris_dem input file (YAML, quantities with units) into a ready-to-run system. Everything is
// validated here, before any output is opened, so a bad input never touches earlier results. The system is
// built in this order: particles read (lattice or LAMMPS data) and wrapped into the box, `remove` regions
// carve it, `labels` name the bodies (Particles::label), then `groups` choose their members.
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/box.hpp"
#include "core/groups.hpp"
#include "core/particles.hpp"
#include "scenarios/common/dem/dem_simulation.hpp"
#include "scenarios/common/run/stages.hpp"
#include "scenarios/common/dem/surface_census.hpp"
#include "scenarios/common/dem/wear_analysis.hpp"

namespace debris {

class InputNode;

struct DemOutputSettings {
  std::string directory = "out";
  long thermo_every = 100;      // thermo CSV row, terminal line and health check (NaN, exploding overlap)
  long dump_every = 0;          // LAMMPS dump frame (OVITO); 0 = first and last step only
  long trajectory_every = 0;    // HDF5 + XDMF frame (ParaView); 0 = same as dump_every
  long checkpoint_every = 0;    // checkpoint.h5; 0 = at the end only
  double progress_seconds = 10; // progress line at most this often
  bool pictures = false;        // side views of the first and last step and the driven group's force (PNG)
  bool energy = true;           // the energy accounting: thermo.csv's work and dissipation columns, the balance
};

/// What a stage of a debris_dem run changes at its start (scenarios/common/run/stages.hpp); absent keys keep
/// what the previous stage had.
///   stages:
///     - name: slide
///       duration: 10 ns
///       global_damping: 0          # fraction of c_c (eq 21)
///       adhesive: true             # the pair law's adhesion and tangential parts
///       tangential: true
///       groups:                    # a group's whole motion, as in groups: (membership stays)
///         - {name: top, motion: force, velocity: [10 m/s, free, 0], stress: [0, -100 MPa, 0]}
struct DemStageChanges {
  std::optional<double> global_damping;
  std::optional<bool> adhesive, tangential;
  /// Group index and its new motion (name and members unchanged). `keep_velocity`: a force group whose
  /// stage gives no initial_velocity keeps moving as it was on its load-driven (not prescribed) axes.
  /// `set_velocity`: a free group's members all get this velocity at the stage's start (LAMMPS's `velocity
  /// group set`; a projectile launched after settling), their spins and positions untouched.
  struct GroupChange {
    int group = -1;
    Group motion;
    bool keep_velocity = false;
    std::optional<Vec3> set_velocity;
  };
  std::vector<GroupChange> groups;
};

struct DemRunConfig {
  Box box;
  Particles particles;
  Groups groups;
  DemSettings settings;
  long steps = 0;    // run.steps, a total; -1 when absent and the stages give the length
  int threads = 0;  // 0 = OpenMP default
  /// Health check: an overlap deeper than this many smallest radii stops the run (exit 3). `auto`: the
  /// deepest overlap at the start of the run plus one smallest radius (relaxed amorphous samples hold
  /// overlaps of 0.6-1.3 r_min, which the default would stop).
  double overlap_limit = 0.5;
  bool overlap_limit_auto = false;
  std::vector<StageLength> stages;
  std::vector<DemStageChanges> stage_changes;  // one per stage
  std::optional<WearSettings> wear;            // the wear analysis (wear.csv), when the input has `wear:`
  std::optional<SurfaceSettings> surfaces;     // the wear census (surfaces.csv), when the input has `surfaces:`
  DemOutputSettings output;
  /// A restart's input keys that the checkpoint overrides and whose text differs from the input the
  /// checkpoint keeps ("material", "run.time_step"): the runner names them in one line.
  std::vector<std::string> ignored_at_restart;
  /// Dimensional values given as plain numbers in a file that gives others with units (InputNode::
  /// plain_beside_units): printed as a note, since one may be a forgotten unit.
  std::vector<std::string> plain_quantities;
};

/// How an input is read: for a fresh run, or for a restart from `restored`.
struct DemInputOptions {
  /// A restart: the system (particles, box, remove, labels, groups), the material and the physics keys of
  /// `run` (time step, damping, skin, pair-law switches) come from this checkpoint's simulation. Those parts
  /// of the input are not read, so no data file is opened; the ones that differ from `checkpoint_echo`
  /// (the input the checkpoint keeps) are listed in DemRunConfig::ignored_at_restart. Stages, `wear`,
  /// `surfaces`, `output`, run.steps, run.threads and run.overlap_limit are read and applied.
  const DemSimulation* restored = nullptr;
  std::string checkpoint_echo;
};

/// Reads a group's motion from `node` into `group`: `motion` (free | frozen | velocity | force, default
/// free), `velocity`, `force` or `stress` (with `area_normal`, the area taken from `box`) and
/// `initial_velocity`. In a force group `velocity: [10 m/s, free, 0]` prescribes the axes given as
/// quantities and leaves `free` ones to the load; a nonzero load on a prescribed axis is an InputError.
/// Sets every motion field (motion, velocity, external_force, prescribed), resetting what the node does
/// not give, and nothing else (name, membership and measured values are left alone), so it also serves a
/// node that holds only motion keys (a stage changing a group's motion). On an error the group is unchanged.
void read_group_motion(const InputNode& node, const Box& box, Group& group);

/// Reads the whole file; InputError naming the key and the value for anything missing, malformed,
/// out of range or unknown. Relative paths inside it (a LAMMPS data file) are relative to the file.
DemRunConfig read_dem_input(const std::string& path);
DemRunConfig read_dem_input(const InputNode& root, const std::string& base_directory, const DemInputOptions& options = {});

/// Reads the input from its text (the echo a checkpoint keeps); `name` stands for the file in messages.
DemRunConfig read_dem_input_text(const std::string& text, const std::string& name, const std::string& base_directory,
                                 const DemInputOptions& options = {});

}  // namespace debris
