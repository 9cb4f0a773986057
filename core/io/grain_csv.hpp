#pragma once
// PeriDEM's particle list (`particle_locations_0.csv`, File_Data_Type loc_rad_orient):
//   i, x, y, z, r, o
//   0, 0.067190, 0.001249, 0.000000, 0.000949, 2.414390
// one grain a line: zone index i (0-based: zone i is the deck's Zone_{i+1}), centre (x, y, z) in metres,
// radius r in metres (the grain is its zone's reference mesh scaled by r / R_ref), orientation o in
// radians (a rotation about z). PeriDEM's older loc_rad files (no `o` column) have their orientations
// drawn at random by PeriDEM; debris needs them given, so such files are rejected.
#include <string>
#include <vector>

namespace debris {

struct GrainRecord {
  int zone = 0;
  double x = 0, y = 0, z = 0;
  double radius = 0;
  double orientation = 0;
};

/// Throws InputError naming the file and the line for a missing or different header, a wrong number of
/// columns, a value that is not a number, a negative zone, a radius that is not > 0, a non-finite value.
std::vector<GrainRecord> read_grain_csv(const std::string& path);

}  // namespace debris
