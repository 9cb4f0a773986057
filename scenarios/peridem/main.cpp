// debris_peridem: runs a PeriDEM system (paper B: peridynamic grains that deform and break, in contact with
// each other and with rigid walls) described by one YAML input file (scenarios/common/peridem_input.hpp).
// Writes a thermo CSV (energies, damage, broken bonds, contacts, wall reactions and, for runs with few
// grains, each grain's centre, velocity and damage), HDF5 + XDMF node frames with damage, grain id and
// velocity (ParaView) and checkpoints to the output directory; `--restart` continues from a checkpoint bit
// for bit. Bad input ends with one message naming the key and the value and exit 2, before anything is
// written; a run whose state turns non-finite or explodes stops with exit 3 and a message naming the step
// and the node, and keeps the last good checkpoint.
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
#include "core/io/node_trajectory_writer.hpp"
#include "core/io/progress.hpp"
#include "core/io/thermo_csv.hpp"
#include "scenarios/common/peridem_input.hpp"

namespace {

using namespace debris;
using Clock = std::chrono::steady_clock;

constexpr int kExitInput = 2;     // bad input
constexpr int kExitUnstable = 3;  // the run blew up (NaN, or nodes jumping past the contact radius)
constexpr std::size_t kGlobalColumns = 8;
constexpr std::size_t kTerminalColumns = 24;  // the terminal shows every column up to this many

bool is_wall(const PdGrains& g, std::size_t k) { return g.kind[k] == static_cast<int>(PdGrainKind::wall); }

std::size_t particle_grains(const PdGrains& g) {
  std::size_t n = 0;
  for (std::size_t k = 0; k < g.size(); ++k) n += is_wall(g, k) ? 0 : 1;
  return n;
}

bool grain_columns(const PeridemSimulation& sim, const PeridemOutputSettings& out) {
  return particle_grains(sim.grains()) <= static_cast<std::size_t>(out.grain_columns);
}

std::vector<std::string> thermo_columns(const PeridemSimulation& sim, int dimension, bool per_grain) {
  std::vector<std::string> c{"step",           "time",       "kinetic_energy", "bond_energy",
                             "contact_energy", "max_damage", "broken_bonds",   "contact_pairs"};
  const PdGrains& g = sim.grains();
  const std::vector<std::string>& names = sim.grain_names();
  const std::vector<const char*> force =
      dimension == 2 ? std::vector<const char*>{"fx", "fy"} : std::vector<const char*>{"fx", "fy", "fz"};
  for (std::size_t k = 0; k < g.size(); ++k)
    if (is_wall(g, k))
      for (const char* q : force) c.push_back(names[k] + "_" + q);
  if (!per_grain) return c;
  const std::vector<const char*> q =
      dimension == 2
          ? std::vector<const char*>{"x", "y", "vx", "vy", "kinetic_energy", "damage", "broken_bonds"}
          : std::vector<const char*>{"x", "y", "z", "vx", "vy", "vz", "kinetic_energy", "damage", "broken_bonds"};
  for (std::size_t k = 0; k < g.size(); ++k)
    if (!is_wall(g, k))
      for (const char* s : q) c.push_back(names[k] + "_" + s);
  return c;
}

/// Bonds of grain g that are broken (each bond counted once: the list holds it from both ends).
long grain_broken_bonds(const PeridemSimulation& sim, std::size_t g) {
  const BondList& b = sim.bonds();
  long entries = 0;
  for (int i = sim.grains().node_begin[g]; i < sim.grains().node_end[g]; ++i)
    for (int k = b.offset[static_cast<std::size_t>(i)]; k < b.offset[static_cast<std::size_t>(i) + 1]; ++k)
      entries += b.broken[static_cast<std::size_t>(k)] ? 1 : 0;
  return entries / 2;
}

/// Needs diagnostics() of this step first (damage, grain centres).
std::vector<double> thermo_row(PeridemSimulation& sim, const PeridemDiagnostics& d, int dimension, bool per_grain) {
  std::vector<double> row{static_cast<double>(sim.step_count()),
                          sim.time(),
                          d.kinetic_energy,
                          d.bond_energy,
                          d.contact_energy,
                          d.max_damage,
                          static_cast<double>(d.broken_bonds),
                          static_cast<double>(d.contact_pairs)};
  const PdGrains& g = sim.grains();
  const std::vector<Vec3> reaction = sim.wall_reactions();
  for (std::size_t k = 0; k < g.size(); ++k)
    if (is_wall(g, k)) {
      row.push_back(reaction[k].x);
      row.push_back(reaction[k].y);
      if (dimension == 3) row.push_back(reaction[k].z);
    }
  if (!per_grain) return row;
  sim.refresh_grain_centres();
  const PdNodes& n = sim.nodes();
  for (std::size_t k = 0; k < g.size(); ++k) {
    if (is_wall(g, k)) continue;
    double damage = 0, kinetic = 0;
    for (int i = g.node_begin[k]; i < g.node_end[k]; ++i) {
      damage = std::max(damage, n.damage[i]);
      kinetic += 0.5 * n.mass[i] * (n.vx[i] * n.vx[i] + n.vy[i] * n.vy[i] + n.vz[i] * n.vz[i]);
    }
    const std::vector<double> centre =
        dimension == 2 ? std::vector<double>{g.cx[k], g.cy[k], g.cvx[k], g.cvy[k]}
                       : std::vector<double>{g.cx[k], g.cy[k], g.cz[k], g.cvx[k], g.cvy[k], g.cvz[k]};
    row.insert(row.end(), centre.begin(), centre.end());
    row.push_back(kinetic);
    row.push_back(damage);
    row.push_back(static_cast<double>(grain_broken_bonds(sim, k)));
  }
  return row;
}

// One terminal line per thermo row; each column as wide as its name, so the header lines up. Rows with
// more than kTerminalColumns columns show the global and wall columns (the CSV has them all).
void print_thermo(const std::vector<std::string>& cols, const std::vector<double>& row, std::size_t shown,
                  bool header) {
  auto width = [&](std::size_t k) { return static_cast<int>(std::max<std::size_t>(cols[k].size(), 11) + 1); };
  if (header) {
    for (std::size_t k = 0; k < shown; ++k) std::cout << std::setw(width(k)) << cols[k];
    std::cout << "\n";
  }
  for (std::size_t k = 0; k < shown; ++k) {
    if (k == 0 || k == 6 || k == 7)
      std::cout << std::setw(width(k)) << static_cast<long>(row[k]);
    else
      std::cout << std::setw(width(k)) << std::setprecision(5) << row[k];
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
  std::optional<PeridemSimulation> restored;
  if (!opt.restart.empty()) {
    std::string echo;
    restored.emplace(PeridemSimulation::from_checkpoint(opt.restart, &echo));
    if (opt.input.empty()) {
      input_text = echo;
      input_name = opt.restart + " (input echo)";
    }
  }
  if (input_text.empty()) input_text = read_input_file(opt.input);
  const std::string base = opt.input.empty() ? std::string() : std::filesystem::path(opt.input).parent_path().string();
  PeridemInputOptions io;
  io.build_system = !restored;  // on restart the system comes from the checkpoint
  io.output_directory = opt.output;
  PeridemRunConfig cfg = read_peridem_input_text(input_text, input_name, base, io);
  exec::set_threads(opt.threads > 0 ? opt.threads : cfg.threads);
  std::cout << exec::startup_report() << "\n";

  // The system is validated here (time step against the stable one, ...) before any output is opened. On
  // restart the state and its physics come from the checkpoint; run.steps (a total) and output from the input.
  std::optional<PeridemSimulation> built;
  if (!restored) {
    built.emplace(std::move(cfg.nodes), std::move(cfg.grains), cfg.materials, cfg.contact, cfg.settings);
    built->set_grain_names(cfg.grain_names);
  }
  PeridemSimulation& sim = restored ? *restored : *built;
  const long first_step = sim.step_count();
  if (restored) std::cout << "restarting from " << opt.restart << " at step " << first_step << "\n";
  std::cout << sim.summary() << "\n";
  if (cfg.steps < first_step)
    throw input_error("run.steps", std::to_string(cfg.steps),
                      "is before the checkpoint's step " + std::to_string(first_step) + " (run.steps is a total)");

  namespace fs = std::filesystem;
  const fs::path dir = cfg.output.directory;
  fs::create_directories(dir);
  const bool per_grain = grain_columns(sim, cfg.output);
  const auto cols = thermo_columns(sim, cfg.dimension, per_grain);
  std::size_t terminal = cols.size();
  if (terminal > kTerminalColumns) {
    terminal = kGlobalColumns;
    for (std::size_t k = 0; k < sim.grains().size(); ++k)
      if (is_wall(sim.grains(), k)) terminal += cfg.dimension == 2 ? 2 : 3;
  }
  ThermoCsv thermo = restored ? ThermoCsv((dir / "thermo.csv").string(), cols, first_step)
                              : ThermoCsv((dir / "thermo.csv").string(), cols);
  const std::string suffix = restored ? ".restart" + std::to_string(first_step) : "";
  NodeTrajectoryWriter trajectory(dir.string(), "trajectory" + suffix, sim.nodes(), sim.grains(), sim.grain_names());
  const std::string checkpoint = (dir / "checkpoint.h5").string();
  std::vector<double> broken_fraction(sim.nodes().size());

  const auto t0 = Clock::now();
  double output_seconds = 0.0;
  long last_checkpoint = -1;
  auto due = [&](long every, long step) { return every > 0 && step % every == 0; };
  auto write_outputs = [&](bool final_step) {
    const auto o0 = Clock::now();
    const long step = sim.step_count();
    const bool first = step == first_step;
    if (due(cfg.output.thermo_every, step) || final_step || first) {
      const PeridemDiagnostics d = sim.diagnostics();
      const auto row = thermo_row(sim, d, cfg.dimension, per_grain);
      if (!(restored && first)) thermo.write_row(row);
      print_thermo(cols, row, terminal, first);
    }
    if (final_step || first || due(cfg.output.trajectory_every, step)) {
      sim.refresh_damage(broken_fraction.data());
      trajectory.write_frame(step, sim.time(), sim.nodes(), broken_fraction);
    }
    if ((final_step || due(cfg.output.checkpoint_every, step)) && step != last_checkpoint && !(restored && first)) {
      sim.write_checkpoint(checkpoint, input_text);
      last_checkpoint = step;
    }
    output_seconds += std::chrono::duration<double>(Clock::now() - o0).count();
  };

  write_outputs(cfg.steps == first_step);
  Progress progress(first_step, cfg.steps, std::cout, cfg.output.progress_seconds);
  while (sim.step_count() < cfg.steps) {
    sim.step();
    const long step = sim.step_count();
    const bool final_step = step == cfg.steps;
    // Checked before anything is written from this step, so a checkpoint never holds a broken state.
    if (final_step || due(cfg.output.thermo_every, step) || due(cfg.output.trajectory_every, step) ||
        due(cfg.output.checkpoint_every, step)) {
      std::string problem = sim.health_check();
      if (problem.empty()) problem = sim.explosion_check();
      if (!problem.empty()) {
        std::cerr << "debris_peridem: stopped: " << problem << "\n"
                  << "debris_peridem: the last good checkpoint is "
                  << (last_checkpoint >= 0 ? checkpoint + " (step " + std::to_string(last_checkpoint) + ")"
                                           : std::string("none (set output.checkpoint_every)"))
                  << std::endl;
        return kExitUnstable;
      }
    }
    write_outputs(final_step);
    progress.update(step, sim.nodes().size());
  }

  const double wall = std::chrono::duration<double>(Clock::now() - t0).count();
  const PeridemPassTimes& pt = sim.times();
  const double steps = static_cast<double>(cfg.steps - first_step);
  auto line = [&](const char* name, double s, const std::string& extra = "") {
    std::cout << std::left << std::setw(13) << name << std::right << std::setw(10) << std::fixed << std::setprecision(3)
              << s << std::setw(8) << std::setprecision(1) << (wall > 0 ? 100 * s / wall : 0) << "%" << extra << "\n"
              << std::defaultfloat;
  };
  std::cout << "\npass            seconds   share\n";
  line("integration", pt.integration);
  line("neighbours", pt.neighbours, "  (" + std::to_string(pt.rebuilds) + " contact list builds)");
  line("bonds", pt.bonds);
  line("contact", pt.contact);
  line("other", pt.other);
  line("output", output_seconds, "  (thermo, trajectory, checkpoints)");
  std::ostringstream rate;
  rate << "  " << std::setprecision(3) << (wall > 0 ? static_cast<double>(sim.nodes().size()) * steps / wall / 1e6 : 0)
       << " M node-steps/s";
  line("total", wall, rate.str());
  std::cout << "output written to " << dir.string() << "/ (thermo.csv, trajectory" << suffix
            << ".xmf + .h5, checkpoint.h5)\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"debris_peridem: PeriDEM (peridynamic grains with DEM contact, paper B) on host threads or a GPU"};
  Options opt;
  app.add_option("-i,--input", opt.input, "YAML input file");
  app.add_option("-o,--output", opt.output, "output directory (overrides output.directory)");
  app.add_option("--restart", opt.restart,
                 "continue from a checkpoint (state and physics from it; run.steps, a total, and output from -i or "
                 "the input it keeps)");
  app.add_option("--threads", opt.threads, "number of host threads (overrides run.threads)")
      ->check(CLI::NonNegativeNumber);
  CLI11_PARSE(app, argc, argv);
  if (opt.input.empty() && opt.restart.empty()) {
    std::cerr << "debris_peridem: give an input file (-i run.yaml) or a checkpoint (--restart checkpoint.h5); --help "
                 "for more\n";
    return kExitInput;
  }
  try {
    return run(opt);
  } catch (const debris::InputError& e) {
    std::cerr << "debris_peridem: " << e.what() << std::endl;
    return kExitInput;
  } catch (const std::exception& e) {
    std::cerr << "debris_peridem: error: " << e.what() << std::endl;
    return 1;
  }
}
