#include "scenarios/common/dem/dem_run.hpp"

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include "core/comm/communicator.hpp"
#include "core/error.hpp"
#include "core/exec.hpp"
#include "core/io/dump_writer.hpp"
#include "core/io/hdf5_file.hpp"
#include "core/io/thermo_csv.hpp"
#include "core/io/trajectory_writer.hpp"
#include "kernels/dem/integrate.hpp"
#include "scenarios/common/run/checkpoint_file.hpp"
#include "scenarios/common/dem/dem_input.hpp"
#include "scenarios/common/dem/dem_keys.hpp"
#include "scenarios/common/dem/run_pictures.hpp"
#include "scenarios/common/dem/height_map_output.hpp"
#include "scenarios/common/dem/surface_census.hpp"
#include "scenarios/common/run/runner.hpp"

namespace debris {

namespace {

std::vector<std::string> dem_thermo_columns(const Groups& groups, bool energy) {
  std::vector<std::string> names;
  for (const Group& g : groups.list) names.push_back(g.name);
  return dem_thermo_table().header({{"group", names}}, energy ? std::vector<std::string>{"energy"}
                                                              : std::vector<std::string>{});
}

std::vector<double> dem_thermo_row(const DemSimulation& sim, const CohesiveDiagnostics& d) {
  const ParticleTotals t = sim.totals();  // the whole system's, on every rank
  std::vector<double> row{static_cast<double>(sim.step_count()), sim.time(), t.kinetic_energy, d.elastic_energy,
                          d.max_overlap, static_cast<double>(d.interacting_pairs)};
  const bool energy = sim.settings().energy_accounting;
  const EnergyBalance b = energy ? sim.energy_balance(d) : EnergyBalance{};
  for (std::size_t k = 0; k < sim.groups().size(); ++k) {
    const Group& g = sim.groups().list[k];
    for (double v : {g.reaction.x, g.reaction.y, g.reaction.z, g.displacement.x, g.displacement.y, g.displacement.z})
      row.push_back(v);
    if (energy) row.push_back(b.totals.drive_work[k]);
  }
  if (energy)
    for (double v : {b.work_in(), b.stage_work, b.totals.dissipated_normal, b.totals.dissipated_tangential,
                     b.totals.dissipated_sliding, b.totals.dissipated_global, b.totals.tangential_work, b.residual()})
      row.push_back(v);
  return row;
}

// The closing lines: where the work went, W_in = dKE + dPE + sum of D + residual.
std::string energy_report(const EnergyBalance& b) {
  std::ostringstream os;
  os << std::setprecision(4);
  const double in = b.work_in();
  os << "energy balance since the start (J): work in " << in << " (drives " << b.drive_work() << ", stages "
     << b.stage_work << ")\n  = kinetic change " << b.kinetic - b.kinetic0 << " + elastic change "
     << b.elastic - b.elastic0 << " + dissipated " << b.totals.dissipated() << " (normal damping "
     << b.totals.dissipated_normal << ", tangential damping " << b.totals.dissipated_tangential << ", sliding "
     << b.totals.dissipated_sliding << ", global damping " << b.totals.dissipated_global << ")\n  + residual "
     << b.residual();
  if (in != 0.0) os << " (" << 100.0 * b.residual() / std::abs(in) << "% of the work in)";
  os << "; tangential work " << b.totals.tangential_work;
  return os.str();
}

// One terminal line per thermo row; each column as wide as its name, so the header lines up.
void dem_print_thermo(const std::vector<std::string>& cols, const std::vector<double>& row, bool header) {
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

// debris_dem's side of the runner: a DemSimulation with its thermo columns, dump and trajectory frames,
// health check and stage changes.
// What a checkpoint keeps of the run beside the system (its `run` group): the health check's limit as it
// was in force, and the wear analysis's and the wear census's states, so a restart checks and reports as the
// run in one piece.
struct DemRunState {
  std::optional<double> overlap_limit;
  std::optional<WearState> wear;
  std::optional<SurfaceCensusState> surfaces;
};

void write_run_state(h5::File& f, double overlap_limit, const std::optional<WearAnalysis>& wear,
                     const std::optional<SurfaceCensus>& surfaces) {
  h5::Group run = f.create_group("run");
  run.write_scalar<double>("overlap_limit", overlap_limit);
  if (wear) write_wear_state(run, wear->state());
  if (surfaces) write_surface_state(run, surfaces->state());
}

DemRunState read_run_state(const h5::File& f) {
  DemRunState st;
  if (!f.has("run")) return st;  // checkpoints from before 2026-12-03
  const h5::Group run = f.open_group("run");
  st.overlap_limit = run.read_scalar<double>("overlap_limit");
  if (!(*st.overlap_limit > 0) || !std::isfinite(*st.overlap_limit))
    throw unsound_checkpoint(f.file_path(), "run/overlap_limit is not a positive number");
  st.wear = read_wear_state(run);
  st.surfaces = read_surface_state(run);
  return st;
}

class DemRunModel final : public RunModel {
 public:
  DemSimulation& simulation() { return sim_; }
  const WearAnalysis* wear() const { return wear_ ? &*wear_ : nullptr; }
  const SurfaceCensus* surfaces() const { return surfaces_ ? &*surfaces_ : nullptr; }
  DemRunModel(DemSimulation sim, DemRunConfig cfg, DemRunState restored = {}, std::string checkpoint = {})
      : sim_(std::move(sim)), cfg_(std::move(cfg)) {
    // `auto`: the deepest overlap the run started with, plus one smallest radius (the patch tests' allowance
    // for a sample that fractures and snaps back); a restart keeps the limit of the run it continues.
    if (cfg_.overlap_limit_auto && restored.overlap_limit) {
      overlap_limit_ = *restored.overlap_limit;
    } else if (cfg_.overlap_limit_auto) {
      overlap_limit_ = sim_.diagnostics().max_overlap / sim_.smallest_radius() + 1.0;
    } else {
      overlap_limit_ = cfg_.overlap_limit;
    }
    if (cfg_.wear) {
      // The analysis reads the whole system: rank 0 holds it when the run is cut among ranks.
      wear_restored_ = restored.wear.has_value();
      sim_.with_whole_system([&](const DemSimulation& whole) {
        wear_.emplace(*cfg_.wear, whole);
        if (restored.wear) wear_->restore(*restored.wear, checkpoint);
      });
    }
    if (cfg_.surfaces) {
      surfaces_restored_ = restored.surfaces.has_value();
      sim_.with_whole_system([&](const DemSimulation& whole) {
        surfaces_.emplace(*cfg_.surfaces, whole);
        if (restored.surfaces) surfaces_->restore(*restored.surfaces, checkpoint);
      });
    }
  }
  std::string describe() const {
    std::ostringstream os;
    os << sim_.summary() << "\nhealth check: overlaps deeper than " << overlap_limit_ << " smallest radii stop the run"
       << (cfg_.overlap_limit_auto ? " (auto: the deepest initial overlap + 1)" : "");
    return os.str();
  }

  long step_count() const override { return sim_.step_count(); }
  double time() const override { return sim_.time(); }
  void step() override {
    sim_.step();
    if (cfg_.wear && sim_.step_count() % cfg_.wear->every == 0) sample_wear();
    if (cfg_.surfaces && sim_.step_count() % cfg_.surfaces->every == 0) sample_surfaces();
  }
  std::size_t items() const override { return sim_.particle_count(); }  // every step: no transfer
  const char* item_name() const override { return "particle"; }

  std::string setup_key() const override { return "particles"; }
  std::string health_check() override {
    diag_ = sim_.diagnostics();
    diag_step_ = sim_.step_count();
    return sim_.health_check(*diag_, overlap_limit_);
  }
  std::vector<std::string> thermo_columns() const override {
    return dem_thermo_columns(sim_.groups(), sim_.settings().energy_accounting);
  }
  std::vector<double> thermo_row() override {
    if (!diag_ || diag_step_ != sim_.step_count()) {
      diag_ = sim_.diagnostics();
      diag_step_ = sim_.step_count();
    }
    return dem_thermo_row(sim_, *diag_);
  }
  void print_thermo(const std::vector<std::string>& cols, const std::vector<double>& row, bool header) const override {
    dem_print_thermo(cols, row, header);
  }

  void open_frames(const std::string& dir, const std::string& suffix) override {
    namespace fs = std::filesystem;
    output_dir_ = dir;
    if (cfg_.output.pictures && suffix.empty())
      sim_.with_whole_system(
          [&](const DemSimulation& whole) { write_side_view(dir, "side_start", whole.particles(), picture_units()); });
    // Cut among ranks, every rank writes its own rows of the trajectory (one file, collective).
    std::vector<std::string> names;
    for (const Group& g : sim_.groups().list) names.push_back(g.name);
    if (root_ || sim_.distributed()) trajectory_.emplace(dir, "trajectory" + suffix, names, sim_.distributed());
    // The other ranks' share of rank 0's first sample below (the analysis gathers the system).
    if (cfg_.wear && !root_ && (suffix.empty() || !wear_restored_)) sample_wear();
    if (cfg_.surfaces && !root_ && (suffix.empty() || !surfaces_restored_)) sample_surfaces();
    if (!root_) return;  // rank 0 writes the other files
    dump_.emplace((fs::path(dir) / ("dump" + suffix + ".lammpstrj")).string());
    if (wear_) {
      // A restart continues wear.csv from the analysis's state in the checkpoint, which holds the sample
      // of its own step when one was due, and every sample before: a row the file lost or holds cut short
      // is rewritten from them.
      const std::string path = (fs::path(dir) / "wear.csv").string();
      if (suffix.empty()) {
        wear_csv_.emplace(path, WearAnalysis::columns());
      } else {
        ThermoResume resume{sim_.step_count(), cfg_.wear->every, {}};
        if (wear_restored_)
          for (const WearSample& w : wear_->samples())
            if (w.step <= sim_.step_count()) resume.known.emplace(w.step, WearAnalysis::row(w));
        wear_csv_.emplace(path, WearAnalysis::columns(), resume);
        if (!wear_csv_->repair_note().empty()) std::cout << wear_csv_->repair_note() << "\n";
      }
      if (suffix.empty()) {
        sample_wear();
      } else if (!wear_restored_) {
        // A checkpoint without the analysis (written before 2026-12-03, or by a run without `wear:`).
        std::cout << "wear analysis: the checkpoint holds no wear state; it starts afresh at the restart (its "
                     "window and bonds count from here)\n";
        sample_wear(false);
      }
    }
    if (surfaces_) open_surfaces(dir, suffix);
  }
  bool frame_due(long step) const override { return due(cfg_.output.dump_every, step) || due(trajectory_every(), step); }
  void write_frame(bool every_stream) override {
    const long step = sim_.step_count();
    // Read through the const accessor: a frame brings the particles back from the device (offload builds)
    // without marking the host copy edited.
    const DemSimulation& sim = sim_;
    if (every_stream || due(trajectory_every(), step))
      trajectory_->write_frame(step, sim.time(), sim.box(), sim.particles(), sim.frame_share());
    // The text dump is one stream: rank 0 writes it from the gathered system.
    if (every_stream || due(cfg_.output.dump_every, step))
      sim_.with_whole_system([&](const DemSimulation& whole) { dump_->write_frame(step, whole.box(), whole.particles()); });
  }
  std::string frame_files(const std::string& suffix) const override {
    return "dump" + suffix + ".lammpstrj, trajectory" + suffix + ".xmf + .h5" + (wear_ ? ", wear.csv" : "") +
           (surfaces_ ? ", surfaces.csv, surfaces_histogram.csv, surfaces_debris.csv" : "") +
           (heights_ ? ", surfaces_heights.h5" : "") +
           (cfg_.output.pictures ? std::string(", side_view.png, tangential_force.png") +
                                       (sim_.settings().energy_accounting ? ", energy_balance.png" : "")
                                 : "") +
           (surfaces_ && cfg_.output.pictures ? ", surfaces.png" : "");
  }
  void write_checkpoint(const std::string& path, const std::string& input) const override {
    // Cut among ranks: every rank writes its rows, rank 0 (which holds the wear analysis) the run state.
    sim_.write_checkpoint(path, input, [&](h5::File& f) { write_run_state(f, overlap_limit_, wear_, surfaces_); });
  }

  std::string apply_stage(int k) override {
    const DemStageChanges& c = cfg_.stage_changes[static_cast<std::size_t>(k)];
    std::ostringstream os;
    // What the changes do to the energy content is work done on the system (velocities set, the pair law
    // switched); a spring let go at the switch is dissipated, not work, and stays in the content.
    const double content = sim_.energy_content();
    if (c.global_damping) {
      sim_.set_global_damping(*c.global_damping);
      os << "global damping " << *c.global_damping << " c_c; ";
    }
    if (c.adhesive || c.tangential) {
      CohesiveOptions o = sim_.settings().options;
      if (c.adhesive) o.adhesive = *c.adhesive ? 1 : 0;
      if (c.tangential) o.tangential = *c.tangential ? 1 : 0;
      sim_.set_options(o);
      os << "adhesive " << (o.adhesive ? "on" : "off") << ", tangential " << (o.tangential ? "on" : "off") << "; ";
    }
    for (const DemStageChanges::GroupChange& gc : c.groups) {
      Group& g = sim_.groups().list[static_cast<std::size_t>(gc.group)];
      const Vec3 moving = g.velocity;
      g.motion = gc.motion.motion;
      g.velocity = gc.motion.velocity;
      g.external_force = gc.motion.external_force;
      g.prescribed = gc.motion.prescribed;
      if (gc.keep_velocity) {  // the load-driven axes go on as they were moving
        if (!g.prescribed[0]) g.velocity.x = moving.x;
        if (!g.prescribed[1]) g.velocity.y = moving.y;
        if (!g.prescribed[2]) g.velocity.z = moving.z;
      }
      os << "group " << g.name << " " << motion_name(g.motion);
      if (gc.set_velocity) {
        Particles& p = sim_.particles();  // a host-side edit (offload builds send it before the next kernel)
        const Vec3 v = *gc.set_velocity;
        for (std::size_t i = 0; i < p.size(); ++i)
          if (p.group[i] == gc.group) {
            p.vx[i] = v.x;
            p.vy[i] = v.y;
            p.vz[i] = v.z;
          }
        os << ", members at velocity (" << v.x << ", " << v.y << ", " << v.z << ") m/s";
      }
      os << "; ";
    }
    // The changes act on this step's forces too (damping, reactions), as they would have at set-up.
    sim_.recompute_forces();
    if (sim_.settings().energy_accounting) sim_.add_stage_work(sim_.energy_content() - content);
    std::string what = os.str();
    return what.empty() ? what : what.substr(0, what.size() - 2);
  }

  std::vector<PassTime> pass_times() const override {
    const PassTimes& t = sim_.times();
    std::string rebuilds = "(";  // appended, not "(" + ... + ...: GCC 12 warns falsely (-Wrestrict) on that
    rebuilds += std::to_string(t.rebuilds);
    rebuilds += " rebuilds in all, binning included)";
    std::vector<PassTime> rows{
        {"neighbours", t.neighbours, rebuilds},
        {"contact", t.contact, ""},
        {"integration", t.integration, ""},
        {"groups/damp", t.other, ""}};
    if (sim_.distributed()) {
      std::ostringstream note;
      note << "(" << sim_.decomposition().describe() << "; rank 0's halo " << sim_.halo().forward_bytes()
           << " B per step; " << migrated_in_all_ << " particles crossed a cut, over all ranks)";
      rows.push_back({"comm", t.comm, note.str()});
    }
    if (wear_) rows.push_back({"wear", wear_seconds_, "(bonds, clusters, rigid fits: wear.csv)"});
    if (surfaces_) rows.push_back({"surfaces", surfaces_seconds_, "(states, clusters, contact: surfaces.csv)"});
    return rows;
  }
  std::string closing_report() override {
    migrated_in_all_ = sim_.migrated_in_all();  // every rank closes the run: the sum is collective
    std::string report = sim_.settings().energy_accounting ? energy_report(sim_.energy_balance(sim_.diagnostics()))
                                                           : std::string();
    if (wear_) {  // appended piecewise: GCC 12 warns falsely (-Wrestrict) on "\n" + std::string
      if (!report.empty()) report += '\n';
      report += wear_->report();
    }
    if (surfaces_) {
      if (!report.empty()) report += '\n';
      report += surfaces_->report();
    }
    if (cfg_.output.pictures) {
      sim_.with_whole_system([&](const DemSimulation& whole) {
        write_side_view(output_dir_, "side_end", whole.particles(), picture_units());
        if (!report.empty()) report += '\n';
        const auto& r = whole.particles().radius;
        report += draw_run_pictures(output_dir_, whole.groups(), picture_units(), whole.box().lo(), whole.box().hi(),
                                    r.empty() ? 0.0 : *std::max_element(r.begin(), r.end()),
                                    whole.settings().energy_accounting);
        if (surfaces_) {
          report += '\n';
          report += draw_surface_pictures(output_dir_, *surfaces_, picture_units());
        }
      });
    }
    return report;
  }

 private:
  static bool due(long every, long step) { return every > 0 && step % every == 0; }
  // Collective when the run is cut among ranks: every rank gathers, rank 0 samples and writes.
  void sample_wear(bool write = true) {
    const auto t0 = std::chrono::steady_clock::now();
    sim_.with_whole_system([&](const DemSimulation& whole) {
      const WearSample& w = wear_->sample(whole);
      if (wear_csv_ && write) wear_csv_->write_row(WearAnalysis::row(w));
    });
    wear_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  // The census as the wear analysis: collective when cut among ranks, rank 0 samples and writes.
  void sample_surfaces(bool write = true) {
    const auto t0 = std::chrono::steady_clock::now();
    sim_.with_whole_system([&](const DemSimulation& whole) {
      const SurfaceSample& s = surfaces_->sample(whole);
      if (surfaces_csv_ && write) {
        surfaces_csv_->write_row(SurfaceCensus::row(s));
        for (const std::vector<double>& row : surfaces_->histogram_rows(s)) histogram_csv_->write_row(row);
        for (const std::vector<double>& row : SurfaceCensus::debris_rows(s)) debris_csv_->write_row(row);
      }
      if (heights_ && write) heights_->append(s.step, s.time, s.slide, surfaces_->bottom_face(), surfaces_->top_face());
    });
    surfaces_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  // surfaces.csv resumes as wear.csv does; surfaces_histogram.csv and surfaces_debris.csv (several rows per
  // sample) are written anew from the census's samples, which the checkpoint holds up to its step.
  void open_surfaces(const std::string& dir, const std::string& suffix) {
    namespace fs = std::filesystem;
    const std::string path = (fs::path(dir) / "surfaces.csv").string();
    const std::string histogram = (fs::path(dir) / "surfaces_histogram.csv").string();
    const std::string debris = (fs::path(dir) / "surfaces_debris.csv").string();
    const std::string heights = (fs::path(dir) / "surfaces_heights.h5").string();
    if (cfg_.surfaces->height_maps) {
      // A continued run keeps the maps of the samples its checkpoint holds, and drops any written after it.
      long keep = -1;
      if (!suffix.empty() && surfaces_restored_) {
        keep = 0;
        for (const SurfaceSample& s : surfaces_->samples()) keep += s.step <= sim_.step_count() ? 1 : 0;
      }
      heights_.emplace(heights, keep);
    }
    if (suffix.empty()) {
      surfaces_csv_.emplace(path, SurfaceCensus::columns());
      histogram_csv_.emplace(histogram, SurfaceCensus::histogram_columns());
      debris_csv_.emplace(debris, SurfaceCensus::debris_columns());
      sample_surfaces();
      return;
    }
    ThermoResume resume{sim_.step_count(), cfg_.surfaces->every, {}};
    if (surfaces_restored_)
      for (const SurfaceSample& s : surfaces_->samples())
        if (s.step <= sim_.step_count()) resume.known.emplace(s.step, SurfaceCensus::row(s));
    surfaces_csv_.emplace(path, SurfaceCensus::columns(), resume);
    if (!surfaces_csv_->repair_note().empty()) std::cout << surfaces_csv_->repair_note() << "\n";
    histogram_csv_.emplace(histogram, SurfaceCensus::histogram_columns());
    debris_csv_.emplace(debris, SurfaceCensus::debris_columns());
    if (surfaces_restored_)
      for (const SurfaceSample& s : surfaces_->samples())
        if (s.step <= sim_.step_count()) {
          for (const std::vector<double>& row : surfaces_->histogram_rows(s)) histogram_csv_->write_row(row);
          for (const std::vector<double>& row : SurfaceCensus::debris_rows(s)) debris_csv_->write_row(row);
        }
    if (!surfaces_restored_) {
      std::cout << "surfaces: the checkpoint holds no census state of this version; it starts afresh at the restart "
                   "(its window, states and work count from here; surfaces_histogram.csv and surfaces_debris.csv "
                   "start afresh)\n";
      sample_surfaces(false);
    }
  }
  PictureUnits picture_units() const {
    const Vec3 extent = sim_.box().hi() - sim_.box().lo();
    return PictureUnits::for_extent(std::max({extent.x, extent.y, extent.z}));
  }
  long trajectory_every() const {
    return cfg_.output.trajectory_every > 0 ? cfg_.output.trajectory_every : cfg_.output.dump_every;
  }

  DemSimulation sim_;
  DemRunConfig cfg_;
  const bool root_ = comm::rank() == 0;  // writes the files of a run cut among ranks
  double overlap_limit_ = 0.5;
  std::int64_t migrated_in_all_ = 0;  // for the pass table, summed when the run closes
  std::optional<CohesiveDiagnostics> diag_;
  long diag_step_ = -1;
  std::optional<DumpWriter> dump_;
  std::optional<TrajectoryWriter> trajectory_;
  std::optional<WearAnalysis> wear_;
  std::optional<ThermoCsv> wear_csv_;
  std::string output_dir_;
  bool wear_restored_ = false;
  double wear_seconds_ = 0;
  std::optional<SurfaceCensus> surfaces_;
  std::optional<ThermoCsv> surfaces_csv_, histogram_csv_, debris_csv_;
  std::optional<HeightMapWriter> heights_;
  bool surfaces_restored_ = false;
  double surfaces_seconds_ = 0;
};

}  // namespace

DemSimulation& dem_simulation(RunModel& model) {
  auto* m = dynamic_cast<DemRunModel*>(&model);
  if (!m) throw std::invalid_argument("dem_simulation: not a model of prepare_dem_run");
  return m->simulation();
}

const WearAnalysis* dem_wear_analysis(const RunModel& model) {
  const auto* m = dynamic_cast<const DemRunModel*>(&model);
  if (!m) throw std::invalid_argument("dem_wear_analysis: not a model of prepare_dem_run");
  return m->wear();
}

const SurfaceCensus* dem_surface_census(const RunModel& model) {
  const auto* m = dynamic_cast<const DemRunModel*>(&model);
  if (!m) throw std::invalid_argument("dem_surface_census: not a model of prepare_dem_run");
  return m->surfaces();
}

RunPlan prepare_dem_run(const RunOptions& opt) {
  // On restart the system and its physics come from the checkpoint (no data file is read); run.steps (a
  // total), run.threads, the health check, stages, the wear analysis and output from the input.
  std::string echo;
  std::optional<DemSimulation> restored;
  DemRunState run_state;
  if (!opt.restart.empty())
    restored.emplace(DemSimulation::from_checkpoint(opt.restart, &echo,
                                                    [&](const h5::File& f) { run_state = read_run_state(f); }));
  const InputSource in = input_source(opt, echo);
  DemInputOptions io;
  if (restored) {
    io.restored = &*restored;
    io.checkpoint_echo = echo;
  }
  DemRunConfig cfg = read_dem_input_text(in.text, in.name, in.base_directory, io);
  if (!opt.output.empty()) cfg.output.directory = opt.output;
  const exec::ThreadRequest threads = exec::request_threads(opt.threads, cfg.threads);
  std::cout << exec::startup_report() << "\n" << exec::describe(threads) << "\n";
  print_input_notes(std::cout, cfg.ignored_at_restart, cfg.plain_quantities);

  // The system is validated here (radii, time step against eq 6, ...) before any file is opened.
  DemSimulation sim = restored ? std::move(*restored)
                               : DemSimulation(cfg.box, std::move(cfg.particles), std::move(cfg.groups), cfg.settings);
  for (std::size_t k = 0; k < cfg.stage_changes.size(); ++k) {
    const DemStageChanges& c = cfg.stage_changes[k];
    if (c.global_damping) sim.check_global_damping(*c.global_damping, "stages[" + std::to_string(k) + "].global_damping");
    for (const DemStageChanges::GroupChange& gc : c.groups)
      if (static_cast<std::size_t>(gc.group) >= sim.groups().size() ||
          sim.groups().list[static_cast<std::size_t>(gc.group)].name != gc.motion.name)
        throw input_error("stages.groups.name", gc.motion.name, "is not a group of the checkpoint's system");
  }
  RunPlan plan = make_run_plan(cfg, sim.dt(), restored.has_value(), threads, in.text);
  if (cfg.surfaces) {  // the run's length: the stages' total, or run.steps without stages
    const long length = cfg.stages.empty() ? cfg.steps : resolve_stages(cfg.stages, sim.dt()).end;
    check_surface_window(*cfg.surfaces, static_cast<double>(length) * sim.dt());
  }
  auto model = std::make_unique<DemRunModel>(std::move(sim), std::move(cfg), std::move(run_state), opt.restart);
  std::cout << model->describe() << "\n";
  plan.model = std::move(model);
  return plan;
}

}  // namespace debris
