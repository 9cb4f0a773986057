// debris_amorphous: makes relaxed amorphous samples of the cohesive DEM (Pham-Ba & Molinari, section 3.2;
// the recipe is in scenarios/common/dem/amorphous_sample.hpp) from one YAML input, one sample or a sweep over d0
// and s. Writes, into the output directory: each sample as samples/<tag>.data (LAMMPS) and .h5, its
// relaxation history relax_<tag>.csv, one row per sample in summary.csv, and the paper's Fig 7 (relaxed
// volume fraction vs d0 / d_c per s, with the HCP packing fraction) as volume_fraction_vs_d0.png when
// gnuplot is installed. Bad input ends with one message naming the key and the value and exit status 2,
// before anything is written or run.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <optional>
#include <sstream>

#include "core/error.hpp"
#include "core/exit_status.hpp"
#include "core/exec.hpp"
#include "core/io/input.hpp"
#include "core/io/thermo_csv.hpp"
#include "core/thread_tuner.hpp"
#include "scenarios/amorphous/amorphous_input.hpp"
#include "scenarios/amorphous/amorphous_keys.hpp"
#include "scenarios/common/dem/amorphous_sample.hpp"
#include "scenarios/common/run/gnuplot.hpp"
#include "scenarios/common/run/reference_flags.hpp"

namespace {

using namespace debris;
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

std::string number_tag(double v) {
  std::ostringstream os;
  os << std::setprecision(6) << v;
  return os.str();
}

void print_progress(const AmorphousProgress& p, const Vec3& len0, double E, bool header) {
  if (header)
    std::cout << "phase      step  max|s|/E      sxx/E      syy/E      szz/E      sxy/E      sxz/E      syz/E"
                 "    Lx/Lx0    Ly/Ly0    Lz/Lz0      phi   kinetic    ovl/d_s\n";
  std::cout << std::setw(5) << p.phase << std::setw(10) << p.step << std::scientific << std::setprecision(2);
  for (double v : {p.max_stress, p.stress.xx / E, p.stress.yy / E, p.stress.zz / E, p.stress.xy / E, p.stress.xz / E,
                   p.stress.yz / E})
    std::cout << std::setw(11) << v;
  std::cout << std::fixed << std::setprecision(6) << std::setw(10) << p.box_length.x / len0.x << std::setw(10)
            << p.box_length.y / len0.y << std::setw(10) << p.box_length.z / len0.z << std::setprecision(4)
            << std::setw(9) << p.volume_fraction << std::scientific << std::setprecision(2) << std::setw(10)
            << p.kinetic_energy << std::fixed << std::setprecision(3) << std::setw(10) << p.max_overlap << "\n"
            << std::defaultfloat << std::flush;
}

/// Writes the gnuplot script of Fig 7 and runs gnuplot if it is installed; returns what happened.
std::string plot_volume_fraction(const fs::path& dir, const std::vector<double>& d0s,
                                 const std::vector<double>& scalings) {
  const fs::path script = dir / "volume_fraction_vs_d0.gp";
  {
    std::ofstream gp(script);
    gp << "# Relaxed volume fraction vs d0 (Pham-Ba & Molinari Fig 7), from summary.csv.\n"
       << "set datafile separator ','\n"
       << "set terminal pngcairo size 900,600\n"
       << "set output 'volume_fraction_vs_d0.png'\n"
       << "set logscale x 2\n"
       << "set xrange [" << d0s.front() / 1.5 << ":" << d0s.back() * 1.5 << "]\n"
       << "set xlabel 'd_0 / d_c'\n"
       << "set ylabel 'relaxed volume fraction'\n"
       << "set yrange [*<0.6:0.9<*]\n"
       << "set key top right\n"
       << "set grid\n"
       << "hcp = pi / (3 * sqrt(2))\n"
       << "plot ";
    for (double s : scalings)
      gp << "'summary.csv' skip 1 using 1:($2 == " << std::setprecision(17) << s
         << " ? $6 : 1/0) with linespoints pt 7 title 'debris, s = " << std::setprecision(6) << s << "', \\\n     ";
    gp << "hcp with lines dt 2 lc rgb 'black' title 'HCP, {/Symbol p} / (3 {/Symbol \\326}2) = 0.7405'\n";
  }
  const GnuplotRun run = run_gnuplot(dir.string(), "volume_fraction_vs_d0.gp", "volume_fraction_vs_d0.log");
  if (!run.found) return "gnuplot not found: plot skipped (script " + script.string() + ")";
  if (run.status != 0) return "gnuplot failed on " + script.string() + ": plot not made";
  return "plot: " + (dir / "volume_fraction_vs_d0.png").string();
}

struct Options {
  std::string input, output;
  int threads = 0;
};

int run(const Options& opt) {
  const std::string text = read_input_file(opt.input);
  AmorphousConfig cfg = read_amorphous_config(text, opt.input);
  if (!opt.output.empty()) cfg.directory = opt.output;
  const exec::ThreadRequest threads = exec::request_threads(opt.threads, cfg.threads);
  std::cout << exec::startup_report() << "\n" << exec::describe(threads) << "\n";

  const fs::path dir = cfg.directory;
  fs::create_directories(dir);
  if (cfg.save_samples) fs::create_directories(dir / "samples");
  ThermoCsv summary((dir / "summary.csv").string(), amorphous_summary_table().header());
  const auto t_all = Clock::now();

  for (double s_value : cfg.scalings) {
    for (double d0 : cfg.d0s) {
      AmorphousSpec spec = cfg.base;
      spec.material.scaling = s_value;
      spec.d0 = d0;
      const double E = spec.material.youngs_modulus;
      const std::string tag = "d0_" + number_tag(d0) + "_s_" + number_tag(s_value);
      std::cout << "\n=== sample " << tag << ": d0 = " << d0 << " d_c = " << spec.d0_absolute() << ", d in ["
                << spec.d_s_absolute() << ", " << spec.d_l_absolute() << "], box " << spec.box_length().x / spec.d0_absolute()
                << " x " << spec.box_length().y / spec.d0_absolute() << " x "
                << spec.box_length().z / spec.d0_absolute() << " d0, s = " << s_value << ", seed " << spec.seed << std::endl;

      ThermoCsv relax((dir / ("relax_" + tag + ".csv")).string(), amorphous_relax_table().header());
      const Vec3 len0 = spec.box_length();
      int last_phase = 0;
      auto observer = [&](const AmorphousProgress& p) {
        print_progress(p, len0, E, p.phase != last_phase);
        last_phase = p.phase;
        relax.write_row({static_cast<double>(p.phase), static_cast<double>(p.step), p.max_stress, p.stress.xx / E,
                         p.stress.yy / E, p.stress.zz / E, p.stress.xy / E, p.stress.xz / E, p.stress.yz / E,
                         p.box_length.x, p.box_length.y, p.box_length.z, p.volume_fraction, p.kinetic_energy,
                         p.max_overlap});
      };
      const auto t0 = Clock::now();
      const AmorphousSample sample = [&] {
        try {
          return make_amorphous_sample(spec, observer, cfg.thermo_every);
        } catch (const SampleCollapse& e) {  // bad input: no relaxed sample exists for this material and recipe
          const CohesiveMaterial& m = spec.material;
          throw input_error("material", "surface_energy " + format_value(m.surface_energy) + ", tensile_strength " +
                                            format_value(m.tensile_strength) + ", youngs_modulus " +
                                            format_value(m.youngs_modulus),
                            std::string(e.what()) + ". The pair attraction reaches past the neighbours: its reach "
                            "delta_f (eq 9) over d0 is (sigma_N / E) / (d0 / d_c) below d_c and (sigma_N / E) / "
                            "sqrt(d0 / d_c) above it with s = 1/2, so a smaller tensile_strength over "
                            "youngs_modulus or a larger sample.d0 shortens it (at a fixed size in metres, a smaller "
                            "surface_energy)");
        }
      }();
      const double wall = std::chrono::duration<double>(Clock::now() - t0).count();
      if (cfg.save_samples) write_amorphous_sample((dir / "samples" / tag).string(), sample, spec, text);

      const StressTensor& st = sample.final_stress;
      const Vec3 a = sample.initial_box_length, b = sample.final_box_length;
      summary.write_row({d0,
                         s_value,
                         spec.d0_absolute(),
                         static_cast<double>(sample.particles.size()),
                         sample.inserted_fraction,
                         sample.relaxed_fraction,
                         static_cast<double>(sample.phase1_steps),
                         static_cast<double>(sample.phase2_steps),
                         sample.phase1_max_overlap,
                         st.xx / E,
                         st.yy / E,
                         st.zz / E,
                         st.xy / E,
                         st.xz / E,
                         st.yz / E,
                         sample.final_max_stress,
                         b.x / a.x - 1.0,
                         b.y / a.y - 1.0,
                         b.z / a.z - 1.0,
                         sample.mass_scale,
                         sample.dt,
                         wall});
      const double psteps =
          static_cast<double>(sample.particles.size()) * static_cast<double>(sample.phase1_steps + sample.phase2_steps);
      std::cout << std::setprecision(6) << "N = " << sample.particles.size() << ", volume fraction "
                << sample.inserted_fraction << " inserted -> " << sample.relaxed_fraction
                << " relaxed; phase 2: " << sample.phase2_steps
                << " steps to max |sigma_aa| = " << sample.final_max_stress << " E (shear left: " << std::abs(st.xy / E)
                << ", " << std::abs(st.xz / E) << ", " << std::abs(st.yz / E) << " E); box strain " << b.x / a.x - 1.0
                << ", " << b.y / a.y - 1.0 << ", " << b.z / a.z - 1.0 << "; masses x " << sample.mass_scale << "; "
                << std::setprecision(3) << wall << " s (" << sample.phase1_seconds << " + " << sample.phase2_seconds
                << "), " << psteps / wall / 1e6 << " M particle-steps/s\n";
      if (cfg.save_samples) std::cout << "saved " << (dir / "samples" / tag).string() << ".data and .h5\n";
    }
  }
  const double total = std::chrono::duration<double>(Clock::now() - t_all).count();
  std::cout << "\n"
            << std::setprecision(4) << "all samples: " << total
            << " s wall; summary: " << (dir / "summary.csv").string() << "\n";
  if (cfg.plot) std::cout << plot_volume_fraction(dir, cfg.d0s, cfg.scalings) << "\n";
  exec::print_tuning_summary(std::cout);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (const int status = debris::refuse_many_processes("debris_amorphous"); status >= 0) return status;
  CLI::App app{"debris_amorphous: relaxed amorphous samples of the cohesive DEM (Pham-Ba & Molinari section 3.2)"};
  Options opt;
  app.add_option("-i,--input", opt.input, "YAML input file");
  app.add_option("-o,--output", opt.output, "output directory (overrides output.directory)");
  app.add_option("--threads", opt.threads, "number of host threads (overrides run.threads)")
      ->check(CLI::NonNegativeNumber);
  app.footer("Example, from the repository root (one relaxed sample, about a minute):\n"
             "  ./build/bin/debris_amorphous -i scenarios/amorphous/default.yaml -o out/amorphous_default");
  debris::ReferenceFlags reference;
  debris::add_reference_flags(app, reference);
  if (const int status = debris::parse_command_line(app, argc, argv); status >= 0) return status;
  if (debris::print_reference(reference, debris::amorphous_keys(), debris::amorphous_output_columns())) return 0;
  if (opt.input.empty()) {
    std::cerr << "debris_amorphous: give an input file (-i sample.yaml); --help for more\n";
    return debris::kExitInput;
  }
  return debris::exit_status_of("debris_amorphous", [&] { return run(opt); });
}
