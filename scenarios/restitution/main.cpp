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
#include <map>

#include "core/error.hpp"
#include "core/exit_status.hpp"
#include "core/exec.hpp"
#include "core/io/input.hpp"
#include "core/units.hpp"
#include "scenarios/common/peridem_input.hpp"
#include "scenarios/common/two_particle_drop.hpp"

namespace {

using namespace debris;
namespace u = debris::units;

struct Case {
  std::string name;
  TwoParticleDrop spec;
  std::string materials;
  double paper = -1;  // the paper's C_R, or -1
};

int run(const std::string& input, const std::string& output, int threads) {
  const InputNode root = InputNode::load_file(input);
  const int dimension = static_cast<int>(root.integer("dimension", 2));
  if (dimension != 2) throw input_error("dimension", std::to_string(dimension), "only 2 is supported by this scenario");
  std::map<std::string, PdMaterial> materials;
  const InputNode mats = root.child("materials");
  for (const std::string& k : mats.keys()) materials[k] = read_pd_material(mats.child(k), dimension);

  TwoParticleDrop base;
  base.mesh_size = root.quantity("mesh_size", u::length, base.mesh_size);
  base.drop_height = root.quantity("drop_height", u::length, base.drop_height);
  base.gravity = root.quantity("gravity", u::acceleration, base.gravity);
  base.damping_factor = root.quantity("damping_factor", u::dimensionless, base.damping_factor);
  base.contact_radius_factor = root.quantity("contact_radius_factor", u::dimensionless, base.contact_radius_factor);
  base.damping_onset_factor = root.quantity("damping_onset_factor", u::dimensionless, base.damping_onset_factor);
  base.start_gap = root.quantity("start_gap", u::length, base.start_gap);
  base.full_drop = root.boolean("full_drop", false);
  base.allow_unstable_time_step = root.boolean("allow_unstable_time_step", false);
  base.max_steps = root.integer("max_steps", base.max_steps);
  base.damping = root.choice("damping", {"grain_centres", "node_pairs"}, "grain_centres") == "grain_centres"
                     ? PdDamping::grain_centres
                     : PdDamping::node_pairs;
  base.mesh_directory = (std::filesystem::path(output) / "meshes").string();

  std::vector<Case> cases;
  for (const InputNode& c : root.list("cases")) {
    Case k;
    k.name = c.string("name");
    k.spec = base;
    const std::vector<double> radii = c.numbers("radii", u::length);
    if (radii.size() != 2) throw input_error(c.path() + ".radii", std::to_string(radii.size()) + " values", "give [bottom, top]");
    k.spec.bottom_radius = radii[0];
    k.spec.top_radius = radii[1];
    std::vector<std::string> names;
    for (const InputNode& e : c.list("materials")) names.push_back(e.text());
    if (names.size() != 2) throw input_error(c.path() + ".materials", std::to_string(names.size()) + " names", "give [bottom, top]");
    for (const std::string& nm : names)
      if (!materials.count(nm)) throw input_error(c.path() + ".materials", nm, "is not one of the materials above");
    k.spec.bottom_material = materials[names[0]];
    k.spec.top_material = materials[names[1]];
    k.materials = names[0] + "/" + names[1];
    k.spec.restitution = c.quantity("restitution", u::dimensionless);
    k.spec.time_step = c.quantity("time_step", u::time);
    k.spec.initial_speed = c.quantity("initial_speed", u::velocity, 0.0);
    // A mesh study (Table 4) refines the mesh and the horizon together, case by case.
    k.spec.mesh_size = c.quantity("mesh_size", u::length, base.mesh_size);
    if (!(k.spec.mesh_size > 0) || !std::isfinite(k.spec.mesh_size))
      throw input_error(c.path() + ".mesh_size", format_value(k.spec.mesh_size), "must be > 0");
    if (c.has("horizon")) {
      const double horizon = c.quantity("horizon", u::length);
      if (!(horizon > 0) || !std::isfinite(horizon))
        throw input_error(c.path() + ".horizon", format_value(horizon), "must be > 0");
      k.spec.bottom_material.horizon = k.spec.top_material.horizon = horizon;
    }
    k.paper = c.quantity("paper", u::dimensionless, -1.0);
    c.reject_unknown_keys();
    cases.push_back(k);
  }
  root.reject_unknown_keys();
  if (cases.empty()) throw input_error("cases", "(empty)", "list at least one case");

  if (threads > 0) exec::set_threads(threads);
  std::filesystem::create_directories(output);
  const std::string csv_path = (std::filesystem::path(output) / "restitution.csv").string();
  std::ofstream csv(csv_path);
  if (!csv) throw output_error(csv_path, "cannot create it");
  csv << "case,bottom_radius_m,top_radius_m,materials,restitution_parameter,time_step_s,initial_speed_m_s,"
         "paper_C_R,debris_C_R,difference,rebound_height_m,contact_time_s,steps,nodes,broken_bonds,"
         "bottom_max_damage,top_max_damage,wall_seconds,mesh_h_m,horizon_m\n";
  std::printf("%-16s %-9s %-7s %5s %8s %7s %9s %9s %8s %8s %8s %8s\n", "case", "(R1,R2)mm", "mat", "eps", "dt_us",
              "v0", "paper", "debris", "diff", "Z_bot", "Z_top", "wall_s");
  for (const Case& k : cases) {
    const TwoParticleDropResult r = run_two_particle_drop(k.spec);
    const double diff = k.paper >= 0 ? r.restitution_coefficient - k.paper : NAN;
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
  std::cout << "wrote " << csv_path << "\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"debris_restitution: PeriDEM two-particle drop tests (paper B, section 4.1)"};
  std::string input, output = "out_restitution";
  int threads = 0;
  app.add_option("-i,--input", input, "YAML input (cases)")->required();
  app.add_option("-o,--output", output, "output directory");
  app.add_option("--threads", threads, "OpenMP threads (0: default)");
  if (const int status = debris::parse_command_line(app, argc, argv); status >= 0) return status;
  return debris::exit_status_of("debris_restitution", [&] { return run(input, output, threads); });
}
