#pragma once
// Reads a debris_dem input file (YAML, quantities with units) into a ready-to-run system. Everything is
// validated here, before any output is opened, so a bad input never touches earlier results.
#include <string>

#include "core/box.hpp"
#include "core/groups.hpp"
#include "core/particles.hpp"
#include "scenarios/common/dem_simulation.hpp"

namespace debris {

class InputNode;

struct DemOutputSettings {
  std::string directory = "out";
  long thermo_every = 100;      // thermo CSV row, terminal line and health check (NaN, exploding overlap)
  long dump_every = 0;          // LAMMPS dump frame (OVITO); 0 = first and last step only
  long trajectory_every = 0;    // HDF5 + XDMF frame (ParaView); 0 = same as dump_every
  long checkpoint_every = 0;    // checkpoint.h5; 0 = at the end only
  double progress_seconds = 10; // progress line at most this often
};

struct DemRunConfig {
  Box box;
  Particles particles;
  Groups groups;
  DemSettings settings;
  long steps = 0;
  int threads = 0;  // 0 = OpenMP default
  DemOutputSettings output;
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
DemRunConfig read_dem_input(const InputNode& root, const std::string& base_directory);

/// Reads the input from its text (the echo a checkpoint keeps); `name` stands for the file in messages.
DemRunConfig read_dem_input_text(const std::string& text, const std::string& name, const std::string& base_directory);

}  // namespace debris
