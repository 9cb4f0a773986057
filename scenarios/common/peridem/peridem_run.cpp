#include "scenarios/common/peridem/peridem_run.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include "core/error.hpp"
#include "core/exec.hpp"
#include "core/io/input.hpp"
#include "core/io/node_trajectory_writer.hpp"
#include "scenarios/common/peridem/peridem_input.hpp"
#include "scenarios/common/run/runner.hpp"

namespace debris {

namespace {
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

std::vector<std::string> peridem_thermo_columns(const PeridemSimulation& sim, int dimension, bool per_grain) {
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
std::vector<double> peridem_thermo_row(PeridemSimulation& sim, const PeridemDiagnostics& d, int dimension, bool per_grain) {
  const PeridemSimulation& view = sim;  // reads: not edits (offload builds: no transfer back to the device)
  std::vector<double> row{static_cast<double>(sim.step_count()),
                          sim.time(),
                          d.kinetic_energy,
                          d.bond_energy,
                          d.contact_energy,
                          d.max_damage,
                          static_cast<double>(d.broken_bonds),
                          static_cast<double>(d.contact_pairs)};
  const PdGrains& g = view.grains();
  const std::vector<Vec3> reaction = sim.wall_reactions();
  for (std::size_t k = 0; k < g.size(); ++k)
    if (is_wall(g, k)) {
      row.push_back(reaction[k].x);
      row.push_back(reaction[k].y);
      if (dimension == 3) row.push_back(reaction[k].z);
    }
  if (!per_grain) return row;
  sim.refresh_grain_centres();
  view.grains();  // the centres just refreshed, brought back to the host (offload builds; g is that copy)
  const PdNodes& n = view.nodes();
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
void peridem_print_thermo(const std::vector<std::string>& cols, const std::vector<double>& row, std::size_t shown,
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

// debris_peridem's side of the runner: a PeridemSimulation with its thermo columns, node frames, health
// checks and stage changes (walls placed or set moving, gravity).
class PeridemRunModel final : public RunModel {
 public:
  PeridemSimulation& simulation() { return sim_; }
  PeridemRunModel(PeridemSimulation sim, PeridemRunConfig cfg) : sim_(std::move(sim)), cfg_(std::move(cfg)) {
    per_grain_ = grain_columns(sim_, cfg_.output);
    const std::size_t n = thermo_columns().size();
    terminal_ = n;
    if (terminal_ > kTerminalColumns) {
      terminal_ = kGlobalColumns;
      for (std::size_t k = 0; k < view().grains().size(); ++k)
        if (is_wall(view().grains(), k)) terminal_ += cfg_.dimension == 2 ? 2 : 3;
    }
    // Every wall a stage names must be a wall of this system (a restart's system comes from its checkpoint).
    for (const PeridemStageChanges& c : cfg_.stage_changes)
      for (const PeridemStageChanges::WallChange& w : c.walls) (void)wall_index(w);
  }

  long step_count() const override { return sim_.step_count(); }
  double time() const override { return sim_.time(); }
  void step() override { sim_.step(); }
  std::size_t items() const override { return sim_.node_count(); }  // every step: no transfer
  const char* item_name() const override { return "node"; }

  std::string setup_key() const override { return "grains"; }
  std::string health_check() override {
    std::string problem = sim_.health_check();
    if (problem.empty()) problem = sim_.explosion_check();
    return problem;
  }
  // Every step (and at set-up), not only with the sampled checks above: a body passes through another
  // within a few steps of a fast impact.
  std::string step_check() override { return sim_.penetration_check(cfg_.penetration_limit); }
  std::vector<std::string> thermo_columns() const override {
    return peridem_thermo_columns(sim_, cfg_.dimension, per_grain_);
  }
  std::vector<double> thermo_row() override {
    const PeridemDiagnostics d = sim_.diagnostics();
    return peridem_thermo_row(sim_, d, cfg_.dimension, per_grain_);
  }
  void print_thermo(const std::vector<std::string>& cols, const std::vector<double>& row, bool header) const override {
    peridem_print_thermo(cols, row, terminal_, header);
  }

  void open_frames(const std::string& dir, const std::string& suffix) override {
    trajectory_.emplace(dir, "trajectory" + suffix, view().nodes(), view().grains(), sim_.grain_names());
    broken_fraction_.assign(sim_.node_count(), 0.0);
  }
  bool frame_due(long step) const override {
    return cfg_.output.trajectory_every > 0 && step % cfg_.output.trajectory_every == 0;
  }
  void write_frame(bool) override {
    sim_.refresh_damage(broken_fraction_.data());
    trajectory_->write_frame(sim_.step_count(), sim_.time(), view().nodes(), broken_fraction_);
  }
  std::string frame_files(const std::string& suffix) const override { return "trajectory" + suffix + ".xmf + .h5"; }
  void write_checkpoint(const std::string& path, const std::string& input) const override {
    sim_.write_checkpoint(path, input);
  }

  std::string apply_stage(int k) override {
    const PeridemStageChanges& c = cfg_.stage_changes[static_cast<std::size_t>(k)];
    std::ostringstream os;
    os << std::setprecision(6);
    if (c.gravity) {
      sim_.set_gravity(*c.gravity);
      os << "gravity (" << c.gravity->x << ", " << c.gravity->y << ", " << c.gravity->z << ") m/s^2; ";
    }
    if (c.global_damping) {
      sim_.set_global_damping(*c.global_damping);
      os << "global damping " << *c.global_damping << " 1/s; ";
    }
    for (const PeridemStageChanges::WallChange& w : c.walls) {
      const int g = wall_index(w);
      Vec3 d{};
      if (w.move_by) d = *w.move_by;
      if (w.place_axis >= 0) {
        const PdNodes& n = view().nodes();
        const auto& coord = w.place_axis == 0 ? n.x : (w.place_axis == 1 ? n.y : n.z);
        const std::size_t gk = static_cast<std::size_t>(g);
        double edge = coord[static_cast<std::size_t>(view().grains().node_begin[gk])];
        for (int i = view().grains().node_begin[gk]; i < view().grains().node_end[gk]; ++i)
          edge = w.place_max ? std::max(edge, coord[static_cast<std::size_t>(i)])
                             : std::min(edge, coord[static_cast<std::size_t>(i)]);
        (w.place_axis == 0 ? d.x : (w.place_axis == 1 ? d.y : d.z)) = w.place_at - edge;
      }
      if (w.move_by || w.place_axis >= 0) {
        sim_.move_wall(g, d);
        os << "wall " << w.name << " moved by (" << d.x << ", " << d.y << ", " << d.z << ") m; ";
      }
      if (w.velocity) {
        sim_.set_wall_velocity(g, *w.velocity);
        os << "wall " << w.name << " velocity (" << w.velocity->x << ", " << w.velocity->y << ", " << w.velocity->z
           << ") m/s; ";
      }
    }
    sim_.recompute_forces();  // once, for all of the stage's changes
    std::string what = os.str();
    return what.empty() ? what : what.substr(0, what.size() - 2);
  }

  std::vector<PassTime> pass_times() const override {
    const PeridemPassTimes& t = sim_.times();
    std::ostringstream builds;  // not "(" + std::to_string(..): GCC 12 warns (-Wrestrict) falsely on that
    builds << "(" << t.rebuilds << " contact list builds in all";
    if (t.self_contact_updates > 0) builds << ", " << t.self_contact_updates << " updates for broken bonds";
    builds << ")";
    return {{"integration", t.integration, ""},
            {"neighbours", t.neighbours, builds.str()},
            {"bonds", t.bonds, ""},
            {"contact", t.contact, ""},
            {"other", t.other, "(zero forces, gravity)"}};
  }

 private:
  // The simulation for reading: const accessors bring back what changed and are not edits, which the
  // non-const ones would be (sent back to the device before the next step, offload builds).
  const PeridemSimulation& view() const { return sim_; }
  int wall_index(const PeridemStageChanges::WallChange& w) const {
    const std::vector<std::string>& names = sim_.grain_names();
    for (std::size_t k = 0; k < names.size(); ++k)
      if (names[k] == w.name && is_wall(sim_.grains(), k)) return static_cast<int>(k);
    throw input_error(w.key + ".name", w.name, "is not a wall of this system");
  }

  PeridemSimulation sim_;
  PeridemRunConfig cfg_;
  bool per_grain_ = false;
  std::size_t terminal_ = 0;
  std::optional<NodeTrajectoryWriter> trajectory_;
  std::vector<double> broken_fraction_;
};

}  // namespace

PeridemSimulation& peridem_simulation(RunModel& model) {
  auto* m = dynamic_cast<PeridemRunModel*>(&model);
  if (!m) throw std::invalid_argument("peridem_simulation: not a model of prepare_peridem_run");
  return m->simulation();
}

RunPlan prepare_peridem_run(const RunOptions& opt) {
  // On restart the state and its physics come from the checkpoint; run.steps (a total), stages and output
  // from the input.
  std::string echo;
  std::optional<PeridemSimulation> restored;
  if (!opt.restart.empty()) restored.emplace(PeridemSimulation::from_checkpoint(opt.restart, &echo));
  const InputSource in = input_source(opt, echo);
  PeridemInputOptions io;
  io.build_system = !restored;  // on restart the system comes from the checkpoint
  io.output_directory = opt.output;
  PeridemRunConfig cfg = read_peridem_input_text(in.text, in.name, in.base_directory, io);
  // The parts a checkpoint fixes (the system and its physics): named where -i gives them otherwise.
  std::vector<std::string> ignored;
  if (restored && (!opt.input.empty() || !opt.input_text.empty()))
    ignored = differing_keys(InputNode::load_string(in.text, in.name), InputNode::load_string(echo, "the checkpoint's input"),
                             {"dimension", "materials", "shapes", "grains", "particle_file", "walls", "contact", "gravity",
                              "run.time_step", "run.skin", "run.allow_unstable_time_step", "run.global_damping"});
  const exec::ThreadRequest threads = exec::request_threads(opt.threads, cfg.threads);
  std::cout << exec::startup_report() << "\n" << exec::describe(threads) << "\n";
  print_input_notes(std::cout, ignored, cfg.plain_quantities);

  // The system is validated here (time step against the stable one, ...) before any output is opened.
  std::optional<PeridemSimulation> built;
  if (!restored) {
    built.emplace(std::move(cfg.nodes), std::move(cfg.grains), cfg.materials, cfg.contact, cfg.settings,
                  cfg.grain_names);
  }
  PeridemSimulation& sim = restored ? *restored : *built;
  std::cout << sim.summary() << "\n";
  RunPlan plan = make_run_plan(cfg, sim.dt(), restored.has_value(), threads, in.text);
  plan.model = std::make_unique<PeridemRunModel>(std::move(sim), std::move(cfg));
  return plan;
}

}  // namespace debris
