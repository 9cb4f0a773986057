#pragma once
// The pictures a debris_dem run draws at its end when `output.pictures: true`: a side view (x against y,
// every particle a dot coloured by the body it started in, or by its group) of the first and the last step,
// and the tangential force on the driven group (the first group moved by velocity or force) against its
// displacement along x, from thermo.csv. Written as gnuplot scripts with their data beside them, then drawn
// with gnuplot when it is installed (Debian: gnuplot-nox); without it the scripts stay for later.
#include <string>

#include "core/io/key_reference.hpp"
#include "core/vec3.hpp"

namespace debris {

class Particles;
class Groups;

/// The units the pictures are drawn in: nm and uN for a system in SI units (lengths below a millimetre),
/// the input's own units otherwise (Table 4's unitless material).
struct PictureUnits {
  double length = 1, force = 1;  // factors from the input's units
  std::string length_name = "length", force_name = "force";
  static PictureUnits for_extent(double box_extent);
};

/// The columns of side_start.dat and side_end.dat; write_side_view() takes its header from it.
const ColumnTable& side_view_table();

/// Writes `<dir>/<name>.dat`: x, y, radius and a colour index per particle (its label, else its group + 1).
void write_side_view(const std::string& dir, const std::string& name, const Particles& p, const PictureUnits& u);

/// Writes pictures.gp in `dir` (side_view.png from side_start.dat / side_end.dat, tangential_force.png from
/// thermo.csv) and runs gnuplot there. Returns the line the run prints: what was drawn, or why not.
/// Both side views span the box [lo, hi] (the input's units) plus half a particle.
/// energy: also energy_balance.png, from thermo.csv's energy columns (the accounting on).
std::string draw_run_pictures(const std::string& dir, const Groups& groups, const PictureUnits& u, Vec3 lo, Vec3 hi,
                              double max_radius, bool energy = false);

}  // namespace debris
