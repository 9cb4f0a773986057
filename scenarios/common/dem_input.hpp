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
  long thermo_every = 100;  // thermo CSV row and terminal line
  long dump_every = 0;      // LAMMPS dump frame; 0 = first and last step only
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

/// Reads the whole file; InputError naming the key and the value for anything missing, malformed,
/// out of range or unknown. Relative paths inside it (a LAMMPS data file) are relative to the file.
DemRunConfig read_dem_input(const std::string& path);
DemRunConfig read_dem_input(const InputNode& root, const std::string& base_directory);

}  // namespace debris
