// debris_restitution: the two-particle tests of PeriDEM (paper B, section 4.1): a grain dropped on a fixed
// one, C_R = sqrt(H1 / H0) (eq 37) measured for every case of the input (Tables 2 and 3), or the damage of
// an impact at a given speed ("Fracture simulations"). Writes restitution.csv beside the paper's values and
// prints the same table. Bad input ends with one message naming the key and the value (exit 2).
#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>

#include "core/error.hpp"
#include "core/exit_status.hpp"
#include "core/exec.hpp"
#include "core/io/input.hpp"
#include "core/thread_tuner.hpp"
#include "scenarios/common/run/reference_flags.hpp"
#include "scenarios/restitution/restitution_input.hpp"
#include "scenarios/restitution/restitution_keys.hpp"

namespace {

using namespace debris;

int run(const std::string& input, const std::string& output, int threads) {
  const std::vector<RestitutionCase> cases = read_restitution_input_text(read_input_file(input), input, output);
  const exec::ThreadRequest request = exec::request_threads(threads, 0);
  std::cout << exec::describe(request) << "\n";
  std::filesystem::create_directories(output);
  const std::string csv_path = (std::filesystem::path(output) / "restitution.csv").string();
  // Opened with the first result: a case whose system is bad input (a mesh too coarse for its horizon, found
  // when the case is built) leaves an earlier run's table as it was.
  std::ofstream csv;
  auto open_csv = [&] {
    csv.open(csv_path);
    if (!csv) throw output_error(csv_path, "cannot create it");
    const std::vector<std::string> header = restitution_table().header();
    for (std::size_t k = 0; k < header.size(); ++k) csv << (k ? "," : "") << header[k];
    csv << '\n';
  };
  std::printf("%-16s %-9s %-7s %5s %8s %7s %9s %9s %8s %8s %8s %8s\n", "case", "(R1,R2)mm", "mat", "eps", "dt_us",
              "v0", "paper", "debris", "diff", "Z_bot", "Z_top", "wall_s");
  std::fflush(stdout);  // a case takes seconds to minutes: the header shows in a pipe or a log at once
  for (const RestitutionCase& k : cases) {
    const TwoParticleDropResult r = run_two_particle_drop(k.spec);
    const double diff = k.paper >= 0 ? r.restitution_coefficient - k.paper : NAN;
    if (!csv.is_open()) open_csv();
    csv << '"' << k.name << '"' << ',' << k.spec.bottom_radius << ',' << k.spec.top_radius << ',' << k.materials << ','
        << k.spec.restitution << ',' << k.spec.time_step << ',' << k.spec.initial_speed << ',';
    if (k.paper >= 0) csv << k.paper;
    csv << ',' << r.restitution_coefficient << ',';
    if (k.paper >= 0) csv << diff;
    csv << ',' << r.rebound_height << ',' << r.contact_time << ',' << r.steps << ',' << r.nodes << ',' << r.broken_bonds
        << ',' << r.bottom_max_damage << ',' << r.top_max_damage << ',' << r.wall_seconds << ',' << r.mesh_h << ','
        << k.spec.top_material.horizon << '\n';
    csv.flush();
    if (!csv) throw output_error(csv_path, "writing a row failed (disk full?)");
    char radii[32];
    std::snprintf(radii, sizeof radii, "(%g,%g)", k.spec.bottom_radius * 1e3, k.spec.top_radius * 1e3);
    std::printf("%-16s %-9s %-7s %5.2f %8.3f %7.2f %9s %9.4f %8s %8.3g %8.3g %8.1f\n", k.name.c_str(), radii,
                k.materials.c_str(), k.spec.restitution, k.spec.time_step * 1e6, k.spec.initial_speed,
                k.paper >= 0 ? std::to_string(k.paper).substr(0, 5).c_str() : "-", r.restitution_coefficient,
                k.paper >= 0 ? std::to_string(diff).substr(0, 7).c_str() : "-", r.bottom_max_damage,
                r.top_max_damage, r.wall_seconds);
    std::fflush(stdout);
  }
  exec::print_tuning_summary(std::cout);
  std::cout << "wrote " << csv_path << "\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (const int status = debris::refuse_many_processes("debris_restitution"); status >= 0) return status;
  CLI::App app{"debris_restitution: PeriDEM two-particle drop tests (paper B, section 4.1)"};
  std::string input, output = "out_restitution";
  int threads = 0;
  app.add_option("-i,--input", input, "YAML input (cases)");
  app.add_option("-o,--output", output, "output directory");
  app.add_option("--threads", threads, "OpenMP threads (0: default)");
  app.footer("Example, from the repository root (Tables 2-3 of paper B, about a minute):\n"
             "  ./build/bin/debris_restitution -i scenarios/restitution/tables.yaml -o out/restitution");
  debris::ReferenceFlags reference;
  debris::add_reference_flags(app, reference);
  if (const int status = debris::parse_command_line(app, argc, argv); status >= 0) return status;
  if (debris::print_reference(reference, debris::restitution_keys(), debris::restitution_output_columns())) return 0;
  if (input.empty()) {  // -i is required, except for --keys and --columns
    std::cerr << "debris_restitution: give an input file (-i cases.yaml); --help for more\n";
    return debris::kExitInput;
  }
  return debris::exit_status_of("debris_restitution", [&] { return run(input, output, threads); });
}
