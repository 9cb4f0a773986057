#include "scenarios/common/dem/run_pictures.hpp"

#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "core/groups.hpp"
#include "core/particles.hpp"
#include "scenarios/common/run/gnuplot.hpp"

namespace debris {

namespace fs = std::filesystem;

PictureUnits PictureUnits::for_extent(double box_extent) {
  if (box_extent < 1e-3) return PictureUnits{1e9, 1e6, "nm", "uN"};
  return PictureUnits{};
}

const ColumnTable& side_view_table() {
  static const ColumnTable t{
      "side_start.dat, side_end.dat",
      "With `output.pictures: true`: the particles at the first and the last step, one line per particle after a "
      "`#` header line, which `pictures.gp` draws as side_view.png. Lengths in nm for a box under 1 mm, else in "
      "the input's own units.",
      {
          {"x", "nm", "position along x (wrapped into the box)", ""},
          {"y", "nm", "position along y", ""},
          {"radius", "nm", "radius", ""},
          {"colour", "-", "the particle's label (the body it started in), else its group + 1; 0 for neither", ""},
      }};
  return t;
}

void write_side_view(const std::string& dir, const std::string& name, const Particles& p, const PictureUnits& u) {
  std::ofstream out(fs::path(dir) / (name + ".dat"));
  out << '#';
  for (const std::string& c : side_view_table().header()) out << ' ' << c;
  out << "  (lengths in " << (u.length_name == "length" ? std::string("the input's units") : u.length_name)
      << "; colour: the label, else the group + 1)\n";
  for (std::size_t i = 0; i < p.size(); ++i) {
    const int colour = p.label[i] > 0 ? p.label[i] : p.group[i] + 1;
    out << p.x[i] * u.length << ' ' << p.y[i] * u.length << ' ' << p.radius[i] * u.length << ' ' << colour << '\n';
  }
  if (!out) throw std::runtime_error("cannot write " + (fs::path(dir) / (name + ".dat")).string());
}

std::string draw_run_pictures(const std::string& dir, const Groups& groups, const PictureUnits& u, Vec3 lo, Vec3 hi,
                              double max_radius, bool energy) {
  const fs::path d(dir);
  std::string driven;
  for (const Group& g : groups.list)
    if (g.motion == GroupMotion::velocity || g.motion == GroupMotion::force) {
      driven = g.name;
      break;
    }
  std::ofstream gp(d / "pictures.gp");
  gp << "# debris_dem pictures: run `gnuplot pictures.gp` in this directory.\n"
     << "set terminal pngcairo size 1200,520 font ',11'\n"
     << "set output 'side_view.png'\n"
     << "set multiplot layout 1,2\n"
     << "set size ratio -1\nunset key\n"
     << "set xrange [" << (lo.x - max_radius) * u.length << ":" << (hi.x + max_radius) * u.length << "]\n"
     << "set yrange [" << (lo.y - max_radius) * u.length << ":" << (hi.y + max_radius) * u.length << "]\n"
     << "set xlabel 'x (" << u.length_name << ")'\nset ylabel 'y (" << u.length_name
     << ")'\n"
     << "# one colour per body (label) or group, in the order the input names them\n"
     << "set palette defined (1 '#4477aa', 2 '#ee6677', 3 '#228833', 4 '#888888', 5 '#333333', 6 '#ccbb44')\n"
     << "set palette maxcolors 6\nset cbrange [0.5:6.5]\nunset colorbox\n"
     << "set style fill transparent solid 0.7 noborder\n"
     << "set title 'first step' noenhanced\n"
     << "plot 'side_start.dat' using 1:2:3:4 with circles palette\n"
     << "set title 'last step' noenhanced\n"
     << "plot 'side_end.dat' using 1:2:3:4 with circles palette\n"
     << "unset multiplot\n";
  if (!driven.empty())
    gp << "set terminal pngcairo size 800,520 font ',11'\n"
       << "set output 'tangential_force.png'\n"
       << "set size noratio\nset autoscale\nset datafile separator ','\nset key off\n"
       << "set title 'tangential force on " << driven << " against its slide' noenhanced\n"
       << "set xlabel 'sliding distance (" << u.length_name << ")'\nset ylabel 'F_x (" << u.force_name << ")'\n"
       << "plot 'thermo.csv' using (column('" << driven << "_dx') * " << u.length << "):(column('" << driven
       << "_fx') * " << u.force << ") with lines lw 2\n";
  if (energy) {
    // Where the work went: the dissipated energy by mechanism stacked, then the elastic and the kinetic
    // energy's changes since the start, against the work done on the system (thermo.csv's columns).
    const std::string e = std::to_string(u.force * u.length);
    auto col = [](const char* name) { return "column('" + std::string(name) + "')"; };
    const std::string d1 = col("dissipated_normal"), d2 = d1 + " + " + col("dissipated_tangential"),
                      d3 = d2 + " + " + col("dissipated_sliding"), d4 = d3 + " + " + col("dissipated_global"),
                      d5 = d4 + " + " + col("elastic_energy") + " - PE0",
                      d6 = d5 + " + " + col("kinetic_energy") + " - KE0";
    auto band = [&](const std::string& lo_expr, const std::string& hi_expr, const char* title, const char* colour) {
      return "'thermo.csv' using (column('time') * 1e9):((" + lo_expr + ") * " + e + "):((" + hi_expr + ") * " + e +
             ") with filledcurves fc rgb '" + colour + "' title '" + title + "'";
    };
    gp << "set terminal pngcairo size 900,560 font ',11'\n"
       << "set output 'energy_balance.png'\n"
       << "set size noratio\nset autoscale\nset datafile separator ','\nset key top left\n"
       << "stats 'thermo.csv' using (column('elastic_energy')) every ::0::0 nooutput\nPE0 = STATS_min\n"
       << "stats 'thermo.csv' using (column('kinetic_energy')) every ::0::0 nooutput\nKE0 = STATS_min\n"
       << "set title 'where the work went: work in = dissipated + elastic change + kinetic change + residual'\n"
       << "set xlabel 'time (ns)'\nset ylabel 'energy (" << u.force_name << " " << u.length_name << ")'\n"
       << "set style fill solid 0.6 noborder\n"
       << "plot " << band("0", d1, "normal damping", "#4477aa") << ", \\\n  "
       << band(d1, d2, "tangential damping", "#66ccee") << ", \\\n  " << band(d2, d3, "sliding", "#228833")
       << ", \\\n  " << band(d3, d4, "global damping", "#ccbb44") << ", \\\n  "
       << band(d4, d5, "elastic change", "#ee6677") << ", \\\n  " << band(d5, d6, "kinetic change", "#aa3377")
       << ", \\\n  'thermo.csv' using (column('time') * 1e9):(column('work_in') * " << e
       << ") with lines lw 2 lc rgb 'black' title 'work in'\n";
  }
  gp.close();
  if (!gp) return "pictures: cannot write " + (d / "pictures.gp").string();
  const GnuplotRun run = run_gnuplot(dir, "pictures.gp", "pictures.log");
  if (!run.found)
    return "pictures skipped: gnuplot not found (Debian: apt install gnuplot-nox); run `gnuplot pictures.gp` in " +
           dir + " later";
  if (run.status != 0) return "pictures failed: gnuplot could not draw them (see " + dir + "/pictures.log)";
  return "pictures: " + (d / "side_view.png").string() + (driven.empty() ? "" : ", " + (d / "tangential_force.png").string()) +
         (energy ? ", " + (d / "energy_balance.png").string() : "");
}

}  // namespace debris
