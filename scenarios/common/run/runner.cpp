#include "scenarios/common/run/runner.hpp"
#include "scenarios/common/run/reference_flags.hpp"

#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <limits>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <streambuf>

#include "core/comm/communicator.hpp"
#include "core/error.hpp"
#include "core/exec.hpp"
#include "core/pass_timer.hpp"
#include "core/exit_status.hpp"
#include "core/io/input.hpp"
#include "core/io/progress.hpp"
#include "core/io/thermo_csv.hpp"

namespace debris {

namespace {

using Clock = WallClock;

// The other ranks' std::cout and std::cerr go nowhere while the run lasts.
class Silenced {
 public:
  explicit Silenced(bool on) : on_(on) {
    if (!on_) return;
    out_ = std::cout.rdbuf(&null_);
    err_ = std::cerr.rdbuf(&null_);
  }
  ~Silenced() {
    if (!on_) return;
    std::cout.rdbuf(out_);
    std::cerr.rdbuf(err_);
  }
  Silenced(const Silenced&) = delete;
  Silenced& operator=(const Silenced&) = delete;

 private:
  struct Null : std::streambuf {
    int overflow(int c) override { return traits_type::not_eof(c); }
  };
  bool on_;
  Null null_;
  std::streambuf *out_ = nullptr, *err_ = nullptr;
};

bool due(long every, long step) { return every > 0 && step % every == 0; }

/// Host <-> device bytes so far (offload builds); host builds move nothing, so no call per step.
double moved_bytes() {
  if constexpr (!exec::offload_build()) return 0.0;
  const exec::TransferStats t = exec::transfer_stats();
  return t.to_host_bytes + t.to_device_bytes;
}

}  // namespace

/// What a run holds between its calls: the plan's outputs, clocks and counters.
struct Run::State {
  RunPlan plan;
  std::string program;
  RunOptions options;
  Clock::time_point started;
  long first_step = 0, last_step = 0;
  StagePlan stages;
  std::filesystem::path dir;
  std::string checkpoint;
  // The checkpoint a stopped run names: the last one this run wrote, or the one it restarted from when
  // that is the file it would overwrite.
  std::string last_good = "none (set output.checkpoint_every)";
  std::vector<std::string> cols;
  std::optional<ThermoCsv> thermo;
  std::optional<std::vector<double>> first_row;  // a restart's row at its checkpoint's step
  std::string suffix;
  std::vector<PassTime> setup_times;
  double setup_seconds = 0, output_seconds = 0, step_bytes = 0;
  Clock::time_point t0;
  long last_checkpoint = -1;
  std::optional<Progress> progress;
  bool started_outputs = false;
  std::string stop_message, report;
  // Cut among ranks: every rank runs the loop; rank 0 (root) alone writes files (the models' frames and
  // checkpoints gather the system there themselves).
  const bool root = comm::rank() == 0, many_ranks = comm::size() > 1;

  RunModel& model() { return *plan.model; }

  int stop(const std::string& problem) {
    std::cerr << program << ": stopped: " << problem << "\n"
              << program << ": the last good checkpoint is " << last_good << std::endl;
    stop_message = problem + "; the last good checkpoint is " + last_good;
    return kExitUnfinished;
  }
  int stage_starts(long step) const { return step < last_step ? stages.stage_starting_at(step) : -1; }

  void write_outputs(bool final_step) {
    const auto o0 = Clock::now();
    RunModel& m = model();
    const long step = m.step_count();
    const bool first = step == first_step;
    if (due(plan.thermo_every, step) || final_step || first) {
      // Collective: every rank computes it (a restart's first row was computed at the start).
      const auto row = first && first_row ? *first_row : m.thermo_row();
      if (root && !(plan.restored && first)) thermo->write_row(row);
      m.print_thermo(cols, row, first);
    }
    if (final_step || first || m.frame_due(step)) m.write_frame(final_step || first);
    // A checkpoint at each stage boundary too (before the stage's changes): a later stage can be rerun from it.
    const bool boundary = step > 0 && stage_starts(step) > 0;
    if ((final_step || due(plan.checkpoint_every, step) || boundary) && step != last_checkpoint &&
        !(plan.restored && first)) {
      m.write_checkpoint(checkpoint, plan.input_text);
      last_checkpoint = step;
      last_good = checkpoint + " (step " + std::to_string(step) + ")";
    }
    output_seconds += seconds_since(o0);
  }

  void begin_stage(long step) {
    const int k = stage_starts(step);
    if (k < 0) return;
    const std::string what = model().apply_stage(k);
    std::cout << "stage " << k << " '" << stages.names[static_cast<std::size_t>(k)] << "' starts at step " << step
              << (what.empty() ? std::string() : ": " + what) << std::endl;
  }

  /// Runs `f` (returning an exit status) as the run's loop does: a stage that cannot be applied is bad
  /// input (rethrown); anything else that goes wrong once outputs exist (a full disk, a file where a
  /// directory should be, out of memory) stops the run, and nothing it wrote before is touched.
  template <class F>
  int guarded(F&& f) {
    try {
      return f();
    } catch (const InputError&) {
      throw;
    } catch (const RunStop& e) {  // every rank meets it alike
      return stop("at step " + std::to_string(model().step_count()) + ": " + e.what());
    } catch (const std::bad_alloc&) {
      return stopped_on_this_rank("out of memory at step " + std::to_string(model().step_count()));
    } catch (const std::exception& e) {
      return stopped_on_this_rank("at step " + std::to_string(model().step_count()) + ": " + e.what());
    }
  }

  /// A failure this rank alone may have met (an output rank 0 cannot write, memory): one process stops
  /// as before; cut among ranks, the others cannot know, so the job ends here.
  int stopped_on_this_rank(const std::string& problem) {
    const int status = stop(problem);
    if (!many_ranks) return status;
    std::fprintf(stderr, "%s (rank %d): stopped: %s\n", program.c_str(), comm::rank(), problem.c_str());
    comm::abort(status);
  }
};

Run::Run(RunPlan plan, std::string program, RunOptions options, WallClock::time_point started)
    : s_(std::make_unique<State>()) {
  s_->plan = std::move(plan);
  s_->program = std::move(program);
  s_->options = std::move(options);
  s_->started = started;
}

Run::~Run() = default;

RunModel& Run::model() { return s_->model(); }
long Run::last_step() const { return s_->last_step; }
bool Run::done() const { return s_->model().step_count() >= s_->last_step; }
const RunPlan& Run::plan() const { return s_->plan; }
const StagePlan& Run::stages() const { return s_->stages; }
const std::string& Run::stop_message() const { return s_->stop_message; }
const std::string& Run::closing_report() const { return s_->report; }
std::string Run::directory() const { return s_->dir.string(); }
std::string Run::checkpoint_path() const { return s_->checkpoint; }

ProgressValues Run::progress() const {
  const State& s = *s_;
  const long step = s.plan.model->step_count();
  if (s.progress) return s.progress->values(step);
  ProgressValues p;
  p.first_step = s.first_step;
  p.step = step;
  p.last_step = s.last_step;
  return p;
}

PassTable Run::pass_table() const {
  const State& s = *s_;
  if (!s.started_outputs) throw std::logic_error("Run::pass_table before Run::start");
  const RunModel& model = *s.plan.model;
  PassTable t;
  t.stepping = seconds_since(s.t0);
  t.total = s.setup_seconds + t.stepping;
  t.steps = model.step_count() - s.first_step;
  // Set-up, each pass while stepping, output, and the rest (checks, stage changes, the loop itself), so the
  // shares add up to the total.
  t.rows.push_back({"set-up", s.setup_seconds, "(input, system, first forces, output files)"});
  std::vector<PassTime> passes = model.pass_times();
  for (std::size_t k = 0; k < passes.size() && k < s.setup_times.size(); ++k)
    passes[k].seconds -= s.setup_times[k].seconds;
  double accounted = s.output_seconds;
  for (const PassTime& r : passes) {
    accounted += r.seconds;
    t.rows.push_back(r);
  }
  t.rows.push_back({"output", s.output_seconds, "(thermo, frames, checkpoints)"});
  t.rows.push_back({"rest", std::max(0.0, t.stepping - accounted), "(health checks, stage changes, loop)"});
  t.items_steps_per_second =
      t.stepping > 0 ? static_cast<double>(model.items()) * static_cast<double>(t.steps) / t.stepping : 0.0;
  t.bytes_per_step = t.steps > 0 ? s.step_bytes / static_cast<double>(t.steps) : 0.0;
  return t;
}

int Run::start() {
  State& s = *s_;
  RunPlan& plan = s.plan;
  RunModel& model = s.model();
  s.first_step = model.step_count();
  if (plan.restored) std::cout << "restarting from " << s.options.restart << " at step " << s.first_step << "\n";

  // The run's length: the stages', or run.steps, which with stages may stop earlier (a chunk of a long run).
  s.stages = resolve_stages(plan.stages, plan.dt);
  const StagePlan& stages = s.stages;
  s.last_step = plan.steps;
  if (!stages.empty()) {
    if (s.last_step < 0) s.last_step = stages.end;
    if (s.last_step > stages.end)
      throw input_error("run.steps", std::to_string(s.last_step),
                        "is beyond the end of the stages (step " + std::to_string(stages.end) + ")");
  }
  if (s.last_step < s.first_step)
    throw input_error("run.steps", std::to_string(s.last_step),
                      "is before the checkpoint's step " + std::to_string(s.first_step) + " (run.steps is a total)");
  if (!stages.empty()) {
    std::cout << "stages:";
    for (std::size_t k = 0; k < stages.start.size(); ++k)
      std::cout << " " << stages.names[k] << " [" << stages.start[k] << ", "
                << (k + 1 < stages.start.size() ? stages.start[k + 1] : stages.end) << ")";
    std::cout << "\n";
    const int k = stages.stage_at(s.first_step);
    if (plan.restored && k >= 0 && stages.start[static_cast<std::size_t>(k)] != s.first_step)
      std::cout << "continuing inside stage " << k << " '" << stages.names[static_cast<std::size_t>(k)] << "'\n";
  }

  namespace fs = std::filesystem;
  s.dir = plan.directory;
  s.checkpoint = (s.dir / "checkpoint.h5").string();
  {
    std::error_code ec;
    if (plan.restored && fs::equivalent(s.options.restart, s.checkpoint, ec))
      s.last_good = s.checkpoint + " (step " + std::to_string(s.first_step) + ")";
  }
  // The set-up as built, before any file is written: a state that cannot run is bad input.
  if (!plan.restored) {
    std::string problem = model.step_check();
    if (problem.empty()) problem = model.health_check();
    if (!problem.empty())
      throw input_error(model.setup_key(), "the state at step " + std::to_string(s.first_step),
                        problem + " (nothing was written)");
  }
  return s.guarded([&] {
    if (s.root) {
      std::error_code ec;
      fs::create_directories(s.dir, ec);
      if (ec) throw output_error(s.dir.string(), "cannot create the output directory: " + ec.message());
      // A run stopped while it wrote a checkpoint leaves checkpoint.h5.tmp beside the previous one. It was
      // never sealed and renamed, so it is no result: it goes, and the run says so (unless --restart names it).
      const fs::path stale = s.checkpoint + ".tmp";
      if (fs::exists(stale, ec) && !(plan.restored && fs::equivalent(s.options.restart, stale, ec))) {
        std::error_code removing;
        fs::remove(stale, removing);
        const bool previous = fs::exists(s.checkpoint, ec);
        std::cout << (removing ? "could not remove " : "removed ") << stale.string()
                  << ", a checkpoint left unfinished by a run stopped while writing it ("
                  << (previous ? "checkpoint.h5 beside it is the last one finished"
                               : "no checkpoint was finished there")
                  << (removing ? "): " + removing.message() : ")") << "\n";
      }
    }
    s.cols = model.thermo_columns();
    // A restart keeps the rows up to its checkpoint's step, but the row at that step only where the run
    // in one piece has it too (a thermo step, the first, or the last): the run that wrote the checkpoint
    // ended there and wrote a row that is not due.
    const long first = s.first_step;
    const bool keep_first_row = due(plan.thermo_every, first) || first == 0 || s.last_step == first;
    // A row the file lost or holds cut short (a crash before it was synced) is rewritten from the
    // checkpoint where it can be: the row at the checkpoint's own step.
    if (plan.restored && keep_first_row) s.first_row = model.thermo_row();
    const std::string thermo_path = (s.dir / "thermo.csv").string();
    if (!s.root) {
      // rank 0 writes the table
    } else if (plan.restored) {
      ThermoResume resume{keep_first_row ? first : first - 1, plan.thermo_every, {}};
      if (s.first_row) resume.known.emplace(first, *s.first_row);
      s.thermo.emplace(thermo_path, s.cols, resume);
      if (!s.thermo->repair_note().empty()) std::cout << s.thermo->repair_note() << "\n";
    } else {
      s.thermo.emplace(thermo_path, s.cols);
    }
    if (s.thermo && s.thermo->dropped_to_step() > first)
      std::cout << "thermo.csv: its rows after step " << first << ", up to step " << s.thermo->dropped_to_step()
                << " (written by a run that went on past this checkpoint), are dropped; so are the other tables'\n";
    s.suffix = plan.restored ? ".restart" + std::to_string(first) : "";
    model.open_frames(s.dir.string(), s.suffix);

    // The pass table counts the stepping only: what the passes held after the set-up is subtracted.
    s.setup_times = model.pass_times();
    s.setup_seconds = seconds_since(s.started);
    s.t0 = Clock::now();
    s.started_outputs = true;

    // Stage changes come after a step's outputs: a checkpoint holds the state before them, and a restart
    // from it makes them exactly as this run does (stages.hpp).
    if (!plan.restored) s.begin_stage(first);
    s.write_outputs(s.last_step == first);
    if (plan.restored) s.begin_stage(first);
    s.progress.emplace(first, s.last_step, std::cout, plan.progress_seconds);
    return 0;
  });
}

int Run::advance(long max_steps) {
  State& s = *s_;
  if (!s.started_outputs) throw std::logic_error("Run::advance before Run::start");
  RunModel& model = s.model();
  exec::ThreadTuner* tuner = exec::process_tuner();  // the simulations' steps feed it (exec::TunedStep)
  return s.guarded([&] {
    // Offload builds: host <-> device bytes of the steps themselves, outputs and sampled checks left out (they
    // copy on purpose): a step should move only scalars, block sums and group views, never the state.
    for (long n = 0; n < max_steps && model.step_count() < s.last_step; ++n) {
      const double moved_before = moved_bytes();
      model.step();
      if (tuner)
        for (const std::string& m : tuner->take_messages())
          std::cout << m << ", from step " << model.step_count() << std::endl;
      const long step = model.step_count();
      const bool final_step = step == s.last_step;
      if (const std::string problem = model.step_check(); !problem.empty()) return s.stop(problem);
      s.step_bytes += moved_bytes() - moved_before;
      if (final_step || due(s.plan.thermo_every, step) || model.frame_due(step) ||
          due(s.plan.checkpoint_every, step) || s.stage_starts(step) > 0) {
        const std::string problem = model.health_check();
        if (!problem.empty()) return s.stop(problem);
      }
      s.write_outputs(final_step);
      s.begin_stage(step);
      const double moved_progress = moved_bytes();
      s.progress->update(step, model.items());
      s.step_bytes += moved_bytes() - moved_progress;
    }
    return 0;
  });
}

int Run::finish() {
  State& s = *s_;
  if (!done()) throw std::logic_error("Run::finish before the run's last step");
  RunModel& model = s.model();
  return s.guarded([&] {
    s.report = model.closing_report();
    if (!s.report.empty()) std::cout << s.report << "\n";
    exec::print_tuning_summary(std::cout);

    const PassTable t = pass_table();
    auto line = [&](const std::string& name, double sec, const std::string& extra) {
      std::cout << std::left << std::setw(13) << name << std::right << std::setw(10) << std::fixed
                << std::setprecision(3) << sec << std::setw(8) << std::setprecision(1)
                << (t.total > 0 ? 100 * sec / t.total : 0) << "%" << (extra.empty() ? "" : "  " + extra) << "\n"
                << std::defaultfloat;
    };
    std::cout << "\npass            seconds   share\n";
    for (const PassTime& r : t.rows) line(r.name, r.seconds, r.note);
    std::ostringstream rate;
    rate << std::setprecision(3) << t.items_steps_per_second / 1e6 << " M " << model.item_name()
         << "-steps/s while stepping";
    line("total", t.total, rate.str());
    if constexpr (exec::offload_build())
      std::cout << "device transfers while stepping: " << std::setprecision(6) << t.bytes_per_step
                << " B per step (outputs and checks left out)\n";
    std::cout << "output written to " << s.dir.string() << "/ (thermo.csv, " << model.frame_files(s.suffix)
              << ", checkpoint.h5)\n";
    return 0;
  });
}

namespace {

/// The run proper, once the plan is built: start, every step, finish.
int run_plan(RunPlan plan, const std::string& program, const RunOptions& opt, Clock::time_point started) {
  Run run(std::move(plan), program, opt, started);
  if (const int status = run.start(); status != 0) return status;
  if (const int status = run.advance(std::numeric_limits<long>::max()); status != 0) return status;
  return run.finish();
}

}  // namespace

void print_input_notes(std::ostream& out, const std::vector<std::string>& ignored_at_restart,
                       const std::vector<std::string>& plain_quantities) {
  auto joined = [](const std::vector<std::string>& keys) {
    std::string s;
    for (const std::string& k : keys) s += (s.empty() ? "" : ", ") + k;
    return s;
  };
  if (!ignored_at_restart.empty())
    out << "ignored at restart: " << joined(ignored_at_restart)
        << " (the checkpoint's system and physics continue; edit stages, run.steps or output instead)\n";
  if (!plain_quantities.empty())
    out << "note: plain numbers beside values with units are taken as they stand (SI): " << joined(plain_quantities)
        << "\n";
}

InputSource input_source(const RunOptions& options, const std::string& checkpoint_echo) {
  InputSource s;
  if (!options.input_text.empty()) {
    s.text = options.input_text;
    s.name = options.input_name;  // empty: messages name key paths, not lines of a text the user never saw
    s.base_directory = options.base_directory;
  } else if (options.input.empty()) {
    s.text = checkpoint_echo;
    s.name = options.restart + " (input echo)";
  } else {
    s.text = read_input_file(options.input);
    s.name = options.input;
    s.base_directory = std::filesystem::path(options.input).parent_path().string();
  }
  return s;
}

void continue_beside_checkpoint(RunPlan& plan, const RunOptions& options) {
  if (options.restart.empty() || !options.output.empty()) return;
  const std::filesystem::path parent = std::filesystem::path(options.restart).parent_path();
  plan.directory = parent.empty() ? "." : parent.string();
}

int run_main(int argc, char** argv, const std::string& program, const std::string& description,
             const std::string& example, const std::function<RunPlan(const RunOptions&)>& prepare,
             const KeyReference& keys, const std::vector<ColumnTable>& columns, bool runs_on_ranks) {
  const comm::Session mpi(&argc, &argv);
  if (const int status = refuse_many_processes(program, runs_on_ranks); status >= 0) return status;
  // Cut among ranks, rank 0 speaks for all (an error every rank meets is printed once).
  const Silenced others(comm::rank() != 0);
  CLI::App app{description};
  app.footer("Example, from the repository root:\n  " + example);
  RunOptions opt;
  app.add_option("-i,--input", opt.input, "YAML input file");
  app.add_option("-o,--output", opt.output, "output directory (overrides output.directory)");
  app.add_option("--restart", opt.restart,
                 "continue from a checkpoint (state and physics from it; run.steps, a total, stages and output "
                 "from -i or the input it keeps)");
  app.add_option("--threads", opt.threads,
                 "number of host threads (overrides run.threads; 0, the default: run.threads, else "
                 "OMP_NUM_THREADS, else tuned while stepping)")
      ->check(CLI::NonNegativeNumber);
  ReferenceFlags reference;
  add_reference_flags(app, reference);
  if (const int status = parse_command_line(app, argc, argv); status >= 0) return status;
  if (print_reference(reference, keys, columns)) return 0;
  if (opt.input.empty() && opt.restart.empty()) {
    std::cerr << program
              << ": give an input file (-i run.yaml) or a checkpoint (--restart checkpoint.h5); --help "
                 "for more\n";
    return kExitInput;
  }
  return exit_status_of(program, [&] {
    const auto started = Clock::now();
    RunPlan plan = prepare(opt);
    continue_beside_checkpoint(plan, opt);
    return run_plan(std::move(plan), program, opt, started);
  });
}

}  // namespace debris
