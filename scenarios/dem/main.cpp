// debris_dem: runs a cohesive DEM system (Pham-Ba & Molinari) described by one YAML input file on host
// threads (or a GPU in an nvptx build). Writes a thermo CSV and LAMMPS dump frames (OVITO) to the output
// directory. Bad input ends with one message naming the key and the value, and a non-zero exit, before
// anything is written.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <iostream>

#include "core/error.hpp"
#include "core/exec.hpp"
#include "core/io/dump_writer.hpp"
#include "core/io/thermo_csv.hpp"
#include "kernels/integrate.hpp"
#include "scenarios/common/dem_input.hpp"

namespace {

using namespace debris;

std::vector<std::string> thermo_columns(const Groups& groups) {
  std::vector<std::string> c{"step", "time", "kinetic_energy", "elastic_energy", "max_overlap", "interacting_pairs"};
  for (const Group& g : groups.list)
    for (const char* q : {"fx", "fy", "fz", "dx", "dy", "dz"}) c.push_back(g.name + "_" + q);
  return c;
}

std::vector<double> thermo_row(const DemSimulation& sim) {
  const CohesiveDiagnostics d = sim.diagnostics();
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

int run(const std::string& input, const std::string& out_override, int threads_override) {
  DemRunConfig cfg = read_dem_input(input);
  if (!out_override.empty()) cfg.output.directory = out_override;
  const int threads = threads_override > 0 ? threads_override : cfg.threads;
  exec::set_threads(threads);
  std::cout << exec::startup_report() << "\n";

  // The system is validated here (radii, time step against eq 6, ...) before any file is opened.
  DemSimulation sim(cfg.box, std::move(cfg.particles), std::move(cfg.groups), cfg.settings);
  std::cout << sim.summary() << "\n";

  std::filesystem::create_directories(cfg.output.directory);
  const std::string dir = cfg.output.directory;
  const auto cols = thermo_columns(sim.groups());
  ThermoCsv thermo(dir + "/thermo.csv", cols);
  DumpWriter dump(dir + "/dump.lammpstrj");

  const auto t0 = std::chrono::steady_clock::now();
  double output_seconds = 0.0;
  auto write_outputs = [&](bool force_dump) {
    const auto o0 = std::chrono::steady_clock::now();
    const long step = sim.step_count();
    if (step % cfg.output.thermo_every == 0 || force_dump) {
      const auto row = thermo_row(sim);
      thermo.write_row(row);
      print_thermo(cols, row, step == 0);
    }
    if (force_dump || (cfg.output.dump_every > 0 && step % cfg.output.dump_every == 0))
      dump.write_frame(step, sim.box(), sim.particles());
    output_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - o0).count();
  };
  write_outputs(true);
  for (long s = 0; s < cfg.steps; ++s) {
    sim.step();
    if (sim.step_count() % cfg.output.thermo_every == 0 || s + 1 == cfg.steps) {
      const long bad = first_non_finite(sim.particles());
      if (bad >= 0) {
        const Particles& p = sim.particles();
        const std::size_t b = static_cast<std::size_t>(bad);
        throw std::runtime_error("non-finite position, velocity or force at step " + std::to_string(sim.step_count()) +
                                 " on particle id " + std::to_string(p.id[b]) + " (x = " + std::to_string(p.x[b]) +
                                 ", fx = " + std::to_string(p.fx[b]) + "); is the time step stable?");
      }
    }
    write_outputs(s + 1 == cfg.steps);
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const PassTimes& pt = sim.times();
  const double n = static_cast<double>(sim.particles().size());
  std::cout << std::fixed << std::setprecision(3) << "\n"
            << "pass            seconds   share\n"
            << "neighbours   " << std::setw(10) << pt.neighbours << std::setw(7) << 100 * pt.neighbours / wall << "%  ("
            << pt.rebuilds << " rebuilds)\n"
            << "contact      " << std::setw(10) << pt.contact << std::setw(7) << 100 * pt.contact / wall << "%\n"
            << "integration  " << std::setw(10) << pt.integration << std::setw(7) << 100 * pt.integration / wall << "%\n"
            << "groups/damp  " << std::setw(10) << pt.other << std::setw(7) << 100 * pt.other / wall << "%\n"
            << "output       " << std::setw(10) << output_seconds << std::setw(7) << 100 * output_seconds / wall << "%\n"
            << "total        " << std::setw(10) << wall << "   " << std::setprecision(3)
            << n * static_cast<double>(cfg.steps) / wall / 1e6 << " M particle-steps/s\n"
            << "output written to " << dir << "/thermo.csv and " << dir << "/dump.lammpstrj\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"debris_dem: cohesive coarse-grained DEM (Pham-Ba & Molinari) on host threads or a GPU"};
  std::string input, out;
  int threads = 0;
  app.add_option("-i,--input", input, "YAML input file")->required();
  app.add_option("-o,--output", out, "output directory (overrides output.directory)");
  app.add_option("--threads", threads, "number of host threads (overrides run.threads)")->check(CLI::NonNegativeNumber);
  CLI11_PARSE(app, argc, argv);
  try {
    return run(input, out, threads);
  } catch (const debris::InputError& e) {
    std::cerr << e.what() << std::endl;
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "debris_dem: error: " << e.what() << std::endl;
    return 1;
  }
}
