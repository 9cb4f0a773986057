#pragma once
// LAMMPS data files with atom_style sphere, so that packings can go to and come from LAMMPS and OVITO:
//   Atoms # sphere:  atom-ID atom-type diameter density x y z [ix iy iz]
//   Velocities:      atom-ID vx vy vz wx wy wz
// Only orthogonal boxes. Periodicity is not stored in a data file, so the caller says which axes are.
#include <array>
#include <string>
#include <vector>

#include "core/box.hpp"
#include "core/particles.hpp"

namespace debris {

struct LammpsData {
  Box box;
  Particles particles;           // in file order; mass = density * 4/3 pi r^3, inertia = 2/5 m r^2, group -1
  std::vector<double> density;   // per particle, as written in the file
};

/// Throws InputError naming the file and the line for anything malformed or inconsistent.
LammpsData read_lammps_data(const std::string& path, std::array<bool, 3> periodic);

/// Writes particles sorted by id, with density = mass / volume and a Velocities section, readable by
/// LAMMPS `read_data` with atom_style sphere and by read_lammps_data() with every bit preserved. The file
/// is written beside `path` and renamed onto it, so a crash never leaves half a file.
void write_lammps_data(const std::string& path, const Box& box, const Particles& p);

}  // namespace debris
