// debris_dem: runs a cohesive DEM system (Pham-Ba & Molinari) described by one YAML input file on host
// threads (or a GPU in an nvptx build). Writes a thermo CSV, LAMMPS dump frames (OVITO), an HDF5 trajectory
// with an XDMF sidecar (ParaView) and checkpoints to the output directory; `--restart` continues from a
// checkpoint. Bad input ends with one message naming the key and the value, and a non-zero exit, before
// anything is written; a run whose state turns non-finite or explodes stops with a message naming the step
// and the particle, and keeps the last good checkpoint.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <optional>
#include <sstream>

#include "core/error.hpp"
#include "core/io/input.hpp"
#include "core/exec.hpp"
#include "core/io/dump_writer.hpp"
#include "core/io/progress.hpp"
#include "core/io/thermo_csv.hpp"
#include "core/io/trajectory_writer.hpp"
#include "kernels/integrate.hpp"
#include "scenarios/common/dem_input.hpp"

namespace {

using namespace debris;
using Clock = std::chrono::steady_clock;

constexpr int kExitInput = 2;     // bad input
constexpr int kExitUnstable = 3;  // the run blew up (NaN or exploding overlap)

std::vector<std::string> thermo_columns(const Groups& groups) {
  std::vector<std::string> c{"step", "time", "kinetic_energy", "elastic_energy", "max_overlap", "interacting_pairs"};
  for (const Group& g : groups.list)
    for (const char* q : {"fx", "fy", "fz", "dx", "dy", "dz"}) c.push_back(g.name + "_" + q);
  return c;
}

std::vector<double> thermo_row(const DemSimulation& sim, const CohesiveDiagnostics& d) {
  const ParticleTotals t = particle_totals(sim.particles());
  std::vector<double> row{static_cast<double>(sim.step_count()), sim.time(), t.kinetic_energy, d.elastic_energy,
                          d.max_overlap, static_cast<double>(d.interacting_pairs)};
  for (const Group& g : sim.groups().list)
    for (double v : {g.reaction.x, g.reaction.y, g.reaction.z, g.displacement.x, g.displacement.y, g.displacement.z})
      row.push_back(v);
  return row;
}

// One terminal line per thermo row; each column as wide as its name, so the header lines up.
void print_thermo(const std::vector<std::string>& cols, const std::vector<double>& row, bool header) {
  auto width = [&](std::size_t k) { return static_cast<int>(std::max<std::size_t>(cols[k].size(), 12) + 1); };
  if (header) {
    for (std::size_t k = 0; k < cols.size(); ++k) std::cout << std::setw(width(k)) << cols[k];
    std::cout << "\n";
  }
  for (std::size_t k = 0; k < row.size(); ++k) {
    if (k == 0) std::cout << std::setw(width(k)) << static_cast<long>(row[k]);
    else std::cout << std::setw(width(k)) << std::setprecision(6) << row[k];
  }
  std::cout << std::endl;
}

struct Options {
  std::string input, output, restart;
  int threads = 0;
};

int run(const Options& opt) {
  // The input: the file given, or on restart without one, the text the checkpoint keeps.
  std::string input_text, input_name = opt.input;
  std::optional<DemSimulation> restored;
  if (!opt.restart.empty()) {
    std::string echo;
    restored.emplace(DemSimulation::from_checkpoint(opt.restart, &echo));
    if (opt.input.empty()) {
      input_text = echo;
      input_name = opt.restart + " (input echo)";
    }
  }
  if (input_text.empty()) input_text = read_input_file(opt.input);
  const std::string base = opt.input.empty() ? std::string() : std::filesystem::path(opt.input).parent_path().string();
  DemRunConfig cfg = read_dem_input_text(input_text, input_name, base);
  if (!opt.output.empty()) cfg.output.directory = opt.output;
  exec::set_threads(opt.threads > 0 ? opt.threads : cfg.threads);
  std::cout << exec::startup_report() << "\n";

  // The system is validated here (radii, time step against eq 6, ...) before any file is opened. On restart
  // the state and its physics settings come from the checkpoint; run.steps (a total) and output from the input.
  DemSimulation sim = restored ? std::move(*restored)
                               : DemSimulation(cfg.box, std::move(cfg.particles), std::move(cfg.groups), cfg.settings);
  const long first_step = sim.step_count();
  if (restored) std::cout << "restarting from " << opt.restart << " at step " << first_step << "\n";
  std::cout << sim.summary() << "\n";
  if (cfg.steps < first_step)
    throw input_error("run.steps", std::to_string(cfg.steps),
                      "is before the checkpoint's step " + std::to_string(first_step) + " (run.steps is a total)");

  namespace fs = std::filesystem;
  const fs::path dir = cfg.output.directory;
  fs::create_directories(dir);
  const auto cols = thermo_columns(sim.groups());
  ThermoCsv thermo = restored ? ThermoCsv((dir / "thermo.csv").string(), cols, first_step)
                              : ThermoCsv((dir / "thermo.csv").string(), cols);
  const std::string suffix = restored ? ".restart" + std::to_string(first_step) : "";
  DumpWriter dump((dir / ("dump" + suffix + ".lammpstrj")).string());
  std::vector<std::string> group_names;
  for (const Group& g : sim.groups().list) group_names.push_back(g.name);
  TrajectoryWriter trajectory(dir.string(), "trajectory" + suffix, group_names);
  const std::string checkpoint = (dir / "checkpoint.h5").string();
  const long traj_every = cfg.output.trajectory_every > 0 ? cfg.output.trajectory_every : cfg.output.dump_every;

  const auto t0 = Clock::now();
  double output_seconds = 0.0;
  long last_checkpoint = -1;
  // `diag`: diagnostics() of this step when the caller already has them (the health check computes them).
  auto write_outputs = [&](bool final_step, const CohesiveDiagnostics* diag) {
    const auto o0 = Clock::now();
    const long step = sim.step_count();
    const bool first = step == first_step;
    if (step % cfg.output.thermo_every == 0 || final_step || first) {
      const auto row = thermo_row(sim, diag ? *diag : sim.diagnostics());
      if (!(restored && first)) thermo.write_row(row);
      print_thermo(cols, row, first);
    }
    if (final_step || first || (cfg.output.dump_every > 0 && step % cfg.output.dump_every == 0))
      dump.write_frame(step, sim.box(), sim.particles());
    if (final_step || first || (traj_every > 0 && step % traj_every == 0))
      trajectory.write_frame(step, sim.time(), sim.box(), sim.particles());
    if ((final_step || (cfg.output.checkpoint_every > 0 && step % cfg.output.checkpoint_every == 0)) &&
        step != last_checkpoint && !(restored && first)) {
      sim.write_checkpoint(checkpoint, input_text);
      last_checkpoint = step;
    }
    output_seconds += std::chrono::duration<double>(Clock::now() - o0).count();
  };

  write_outputs(cfg.steps == first_step, nullptr);
  Progress progress(first_step, cfg.steps, std::cout, cfg.output.progress_seconds);
  while (sim.step_count() < cfg.steps) {
    sim.step();
    const bool final_step = sim.step_count() == cfg.steps;
    std::optional<CohesiveDiagnostics> diag;
    if (sim.step_count() % cfg.output.thermo_every == 0 || final_step) {
      diag = sim.diagnostics();
      const std::string problem = sim.health_check(*diag);
      if (!problem.empty()) {
        std::cerr << "debris_dem: stopped: " << problem << "\n"
                  << "debris_dem: the last good checkpoint is "
                  << (last_checkpoint >= 0 ? checkpoint + " (step " + std::to_string(last_checkpoint) + ")"
                                           : std::string("none (set output.checkpoint_every)"))
                  << std::endl;
        return kExitUnstable;
      }
    }
    write_outputs(final_step, diag ? &*diag : nullptr);
    progress.update(sim.step_count(), sim.particles().size());
  }

  const double wall = std::chrono::duration<double>(Clock::now() - t0).count();
  const PassTimes& pt = sim.times();
  const double steps = static_cast<double>(cfg.steps - first_step);
  auto line = [&](const char* name, double s, const std::string& extra = "") {
    std::cout << std::left << std::setw(13) << name << std::right << std::setw(10) << std::fixed
              << std::setprecision(3) << s << std::setw(8) << std::setprecision(1) << (wall > 0 ? 100 * s / wall : 0)
              << "%" << extra << "\n";
  };
  std::cout << "\npass            seconds   share\n";
  line("neighbours", pt.neighbours, "  (" + std::to_string(pt.rebuilds) + " rebuilds, binning included)");
  line("contact", pt.contact);
  line("integration", pt.integration);
  line("groups/damp", pt.other);
  line("output", output_seconds);
  std::ostringstream rate;
  rate << "  " << std::setprecision(3) << std::defaultfloat
       << static_cast<double>(sim.particles().size()) * steps / wall / 1e6 << " M particle-steps/s";
  line("total", wall, rate.str());
  std::cout << "output written to " << dir.string() << "/ (thermo.csv, dump" << suffix << ".lammpstrj, trajectory"
            << suffix << ".xmf + .h5, checkpoint.h5)\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"debris_dem: cohesive coarse-grained DEM (Pham-Ba & Molinari) on host threads or a GPU"};
  Options opt;
  app.add_option("-i,--input", opt.input, "YAML input file");
  app.add_option("-o,--output", opt.output, "output directory (overrides output.directory)");
  app.add_option("--restart", opt.restart,
                 "continue from a checkpoint (state and physics from it; run.steps, a total, and output from -i or "
                 "the input it keeps)");
  app.add_option("--threads", opt.threads, "number of host threads (overrides run.threads)")->check(CLI::NonNegativeNumber);
  CLI11_PARSE(app, argc, argv);
  if (opt.input.empty() && opt.restart.empty()) {
    std::cerr << "debris_dem: give an input file (-i run.yaml) or a checkpoint (--restart checkpoint.h5); --help for more\n";
    return kExitInput;
  }
  try {
    return run(opt);
  } catch (const debris::InputError& e) {
    std::cerr << e.what() << std::endl;
    return kExitInput;
  } catch (const std::exception& e) {
    std::cerr << "debris_dem: error: " << e.what() << std::endl;
    return 1;
  }
}
