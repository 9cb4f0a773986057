#include "scenarios/common/peridem/peridem_run.hpp"
#include "scenarios/common/peridem/peridem_keys.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include "core/comm/communicator.hpp"
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

bool is_wall(const std::vector<int>& kinds, std::size_t k) { return kinds[k] == static_cast<int>(PdGrainKind::wall); }

bool grain_columns(const PeridemSimulation& sim, const PeridemOutputSettings& out) {
  const std::vector<int> kinds = sim.grain_kinds();
  std::size_t particles = 0;
  for (std::size_t k = 0; k < kinds.size(); ++k) particles += is_wall(kinds, k) ? 0 : 1;
  return particles <= static_cast<std::size_t>(out.grain_columns);
}

std::vector<std::string> peridem_thermo_columns(const PeridemSimulation& sim, int dimension, bool per_grain) {
  const std::vector<int> kinds = sim.grain_kinds();
  const std::vector<std::string>& names = sim.grain_names();
  std::vector<std::string> walls, grains;
  for (std::size_t k = 0; k < kinds.size(); ++k) (is_wall(kinds, k) ? walls : grains).push_back(names[k]);
  std::vector<std::string> conditions;
  if (dimension == 3) conditions.push_back("3D");
  if (per_grain) conditions.push_back("per grain");
  if (dimension == 3 && per_grain) conditions.push_back("3D per grain");
  return peridem_thermo_table().header({{"wall", walls}, {"grain", grains}}, conditions);
}

/// Needs diagnostics() of this step first (damage). Collective in a run cut among ranks.
std::vector<double> peridem_thermo_row(PeridemSimulation& sim, const PeridemDiagnostics& d, int dimension, bool per_grain) {
  std::vector<double> row{static_cast<double>(sim.step_count()),
                          sim.time(),
                          d.kinetic_energy,
                          d.bond_energy,
                          d.contact_energy,
                          d.max_damage,
                          static_cast<double>(d.broken_bonds),
                          static_cast<double>(d.contact_pairs)};
  const std::vector<int> kinds = sim.grain_kinds();
  const std::vector<Vec3> reaction = sim.wall_reactions();
  for (std::size_t k = 0; k < kinds.size(); ++k)
    if (is_wall(kinds, k)) {
      row.push_back(reaction[k].x);
      row.push_back(reaction[k].y);
      if (dimension == 3) row.push_back(reaction[k].z);
    }
  if (!per_grain) return row;
  const std::vector<PdGrainState> grains = sim.grain_states();
  for (std::size_t k = 0; k < kinds.size(); ++k) {
    if (is_wall(kinds, k)) continue;
    const PdGrainState& s = grains[k];
    const std::vector<double> centre =
        dimension == 2 ? std::vector<double>{s.centre.x, s.centre.y, s.velocity.x, s.velocity.y}
                       : std::vector<double>{s.centre.x, s.centre.y, s.centre.z, s.velocity.x, s.velocity.y, s.velocity.z};
    row.insert(row.end(), centre.begin(), centre.end());
    row.push_back(s.kinetic_energy);
    row.push_back(s.damage);
    row.push_back(static_cast<double>(s.broken_bonds));
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
      const std::vector<int> kinds = sim_.grain_kinds();
      for (std::size_t k = 0; k < kinds.size(); ++k)
        if (is_wall(kinds, k)) terminal_ += cfg_.dimension == 2 ? 2 : 3;
    }
    // Every wall a stage names must be a wall of this system (a restart's system comes from its checkpoint).
    for (const PeridemStageChanges& c : cfg_.stage_changes)
      for (const PeridemStageChanges::WallChange& w : c.walls) (void)wall_index(w);
  }

  long step_count() const override { return sim_.step_count(); }
  double time() const override { return sim_.time(); }
  void step() override { sim_.step(); }
  std::size_t items() const override { return sim_.node_count(); }  // every step: no transfer or message
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

  // Cut among ranks, every rank writes its own nodes' rows of the trajectory (one file, collective).
  void open_frames(const std::string& dir, const std::string& suffix) override {
    const PdGrains& g = view().grains();
    trajectory_.emplace(dir, "trajectory" + suffix, view().nodes(), sim_.frame_share(),
                        std::vector<int>(g.id.begin(), g.id.end()), sim_.grain_kinds(), sim_.grain_names(),
                        sim_.distributed());
  }
  bool frame_due(long step) const override {
    return cfg_.output.trajectory_every > 0 && step % cfg_.output.trajectory_every == 0;
  }
  void write_frame(bool) override {
    broken_fraction_.assign(view().nodes().size(), 0.0);  // the nodes held (grains move between ranks)
    sim_.refresh_damage(broken_fraction_.data());
    trajectory_->write_frame(sim_.step_count(), sim_.time(), view().nodes(), sim_.frame_share(), broken_fraction_);
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
      if (w.place_axis >= 0)
        (w.place_axis == 0 ? d.x : (w.place_axis == 1 ? d.y : d.z)) =
            w.place_at - view().wall_edge(g, w.place_axis, w.place_max);
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
    std::vector<PassTime> rows{{"integration", t.integration, ""},
                               {"neighbours", t.neighbours, builds.str()},
                               {"bonds", t.bonds, ""},
                               {"contact", t.contact, ""},
                               {"other", t.other, "(zero forces, gravity)"}};
    if (sim_.distributed()) {
      std::ostringstream note;
      note << "(" << sim_.decomposition().describe() << "; rank 0's halo " << sim_.halo_bytes_per_step()
           << " B per step to " << sim_.ghost_nodes() << " ghost nodes, " << t.grains_migrated
           << " grains migrated from rank 0)";
      rows.push_back({"comm", t.comm, note.str()});
    }
    return rows;
  }

 private:
  // The simulation for reading: const accessors bring back what changed and are not edits, which the
  // non-const ones would be (sent back to the device before the next step, offload builds).
  const PeridemSimulation& view() const { return sim_; }
  int wall_index(const PeridemStageChanges::WallChange& w) const {
    const std::vector<std::string>& names = sim_.grain_names();
    const std::vector<int> kinds = sim_.grain_kinds();
    for (std::size_t k = 0; k < names.size(); ++k)
      if (names[k] == w.name && is_wall(kinds, k)) return static_cast<int>(k);
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
  for (const std::string& w : cfg.warnings) std::cout << "warning: " << w << "\n";

  // The system is validated here (time step against the stable one, ...) before any output is opened.
  std::optional<PeridemSimulation> built;
  if (!restored) {
    built.emplace(std::move(cfg.nodes), std::move(cfg.grains), cfg.materials, cfg.contact, cfg.settings,
                  cfg.grain_names);
  }
  PeridemSimulation& sim = restored ? *restored : *built;
  std::cout << sim.summary() << "\n";
  // Under mpirun: the system cut among the ranks, as at its last list build (a restart's, too: checkpoints
  // hold the whole system, from any rank count).
  if (comm::size() > 1) {
    sim.distribute();
    std::cout << "cut among ranks: " << sim.decomposition().describe() << "\n";
  }
  RunPlan plan = make_run_plan(cfg, sim.dt(), restored.has_value(), threads, in.text);
  plan.model = std::make_unique<PeridemRunModel>(std::move(sim), std::move(cfg));
  return plan;
}

}  // namespace debris
