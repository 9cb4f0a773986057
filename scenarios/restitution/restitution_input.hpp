#pragma once
// The debris_restitution input file: the materials, the settings every drop shares, and the cases (Tables 2
// and 3 of paper B, or an impact at a given speed). Read apart from the run so that every case is checked
// before the first one runs, and so that the fuzzer (tests/fuzz) can reach the reader.
#include <string>
#include <vector>

#include "scenarios/restitution/two_particle_drop.hpp"

namespace debris {

struct RestitutionCase {
  std::string name;
  TwoParticleDrop spec;
  std::string materials;  // "bottom/top"
  double paper = -1;      // the paper's C_R, or -1
};

/// Reads and checks the whole input from its text; `name` stands for the file in messages, and Gmsh meshes
/// go to <output_directory>/meshes. InputError naming the key and the value for anything missing,
/// malformed, out of range or unknown, or for no case at all.
std::vector<RestitutionCase> read_restitution_input_text(const std::string& text, const std::string& name,
                                                         const std::string& output_directory);

}  // namespace debris
