#pragma once
// The one runner of debris_dem and debris_peridem (shared/DESIGN.md: the executables' main loops are one
// runner, not two copies). It owns what every run does the same way:
//
//   command line (-i, -o, --restart, --threads) -> input or checkpoint -> set-up -> per step: stage
//   changes, step, health check before anything is written, thermo row, frames, checkpoint, progress ->
//   pass table
//
// and leaves what differs (the system, its thermo columns, its frames and checkpoint) to a RunModel that
// each executable implements over its simulation. Exit statuses: 0 done, 2 bad input (nothing written),
// 3 the run stopped on a failed health check (the last good checkpoint is named), 1 anything else.
#include <functional>
#include <iosfwd>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "core/error.hpp"  // kExitInput, kExitUnfinished
#include "core/io/key_reference.hpp"
#include "core/io/progress.hpp"
#include "core/pass_timer.hpp"  // WallClock
#include "core/thread_tuner.hpp"
#include "scenarios/common/run/stages.hpp"

namespace debris {


/// The command line every executable takes, and what other drivers give instead of a file.
struct RunOptions {
  std::string input, output, restart;
  int threads = 0;
  // The input as text rather than a file (the Python module's dict, emitted as YAML): used when not empty,
  // named `input_name` in messages (empty: a text whose lines the user never saw, as a Python dict's, whose
  // messages name the key path alone); relative paths in it are taken from `base_directory`.
  std::string input_text, input_name, base_directory;
};

/// One row of the pass table: wall seconds of one pass since the set-up ended.
struct PassTime {
  std::string name;
  double seconds = 0;
  std::string note;  // e.g. "(12 rebuilds)"
};

/// The pass table a run prints at its end, as values: set-up, each pass, output and the rest, whose seconds
/// add up to `total`; the rate is items (particles, nodes) times steps per second while stepping.
struct PassTable {
  std::vector<PassTime> rows;
  double total = 0, stepping = 0;
  long steps = 0;
  double items_steps_per_second = 0;
  double bytes_per_step = 0;  // offload builds: host <-> device bytes per step, outputs and checks left out
};

/// How the runner sees a simulation. Host-side, called a few times per step at most: virtual calls are fine.
class RunModel {
 public:
  virtual ~RunModel() = default;

  virtual long step_count() const = 0;
  virtual double time() const = 0;
  virtual void step() = 0;
  /// Particles or nodes: the unit of the rate the runner reports, and its name ("particle", "node").
  virtual std::size_t items() const = 0;
  virtual const char* item_name() const = 0;

  /// Empty when the state is sound; otherwise a message naming the step and the particle or node. Called
  /// before anything is written from a step, so no output ever holds a broken state.
  virtual std::string health_check() = 0;
  /// The input key a failed check of the set-up names ("particles", "grains"): a fresh run's step-0 state
  /// is checked before any file is written, and a set-up that fails is bad input (exit 2).
  virtual std::string setup_key() const = 0;
  /// A check cheap enough for every step (PeriDEM's penetration of one body into another, which a sampled
  /// check lets pass between samples); empty when sound. Called after every step and at set-up, before
  /// health_check() there, so health_check() need not repeat it.
  virtual std::string step_check() { return {}; }

  virtual std::vector<std::string> thermo_columns() const = 0;
  /// The thermo row of the current step (may reuse what health_check() computed at this step).
  virtual std::vector<double> thermo_row() = 0;
  /// One terminal line for the row (with the header above it when `header`).
  virtual void print_thermo(const std::vector<std::string>& columns, const std::vector<double>& row,
                            bool header) const = 0;

  /// Opens the frame writers (trajectory, dump) in `directory`; `suffix` is "" or ".restart<step>", so a
  /// restart never overwrites the frames of the run it continues.
  virtual void open_frames(const std::string& directory, const std::string& suffix) = 0;
  /// Whether a frame is due at `step` (the runner adds the first and the last step).
  virtual bool frame_due(long step) const = 0;
  /// Writes the frames due at this step; every stream's when `every_stream` (the first and last steps).
  virtual void write_frame(bool every_stream) = 0;
  /// The files open_frames() writes, for the closing line ("dump.lammpstrj, trajectory.xmf + .h5").
  virtual std::string frame_files(const std::string& suffix) const = 0;

  /// Everything needed to continue bit for bit, and the input's text, written atomically to `path`.
  virtual void write_checkpoint(const std::string& path, const std::string& input_text) const = 0;

  /// Makes the changes the input gives for stage k (InputError if they cannot be made, e.g. a wall placed
  /// into a grain); returns a line saying what changed.
  virtual std::string apply_stage(int k) = 0;

  /// The passes' accumulated wall times (set-up included: the runner subtracts what they held after it).
  virtual std::vector<PassTime> pass_times() const = 0;

  /// Printed at the end of a finished run, before the pass table (a verdict, a summary); may be empty.
  virtual std::string closing_report() { return {}; }
};

/// What an executable's input and set-up hand to the runner.
struct RunPlan {
  std::unique_ptr<RunModel> model;
  std::string input_text;  // kept in every checkpoint
  bool restored = false;   // continuing from a checkpoint
  long steps = -1;         // run.steps (a total, >= 0), or -1 when the stages give the length
  std::vector<StageLength> stages;
  double dt = 0;  // the time step, for the stages' durations
  std::string directory;
  long thermo_every = 100;      // thermo row, terminal line
  long checkpoint_every = 0;    // 0: at the end only
  double progress_seconds = 10;
  exec::ThreadRequest threads;  // fixed by the user, or tuned while stepping (core/thread_tuner.hpp)
};

/// The plan of a run from its configuration: every executable's config names its run length `steps`, its
/// `stages` and its `output` settings (directory, thermo_every, checkpoint_every, progress_seconds) alike.
/// The caller adds the model.
template <class Config>
RunPlan make_run_plan(const Config& cfg, double dt, bool restored, const exec::ThreadRequest& threads,
                      std::string input_text) {
  RunPlan plan;
  plan.restored = restored;
  plan.threads = threads;
  plan.input_text = std::move(input_text);
  plan.steps = cfg.steps;
  plan.stages = cfg.stages;
  plan.dt = dt;
  plan.directory = cfg.output.directory;
  plan.thermo_every = cfg.output.thermo_every;
  plan.checkpoint_every = cfg.output.checkpoint_every;
  plan.progress_seconds = cfg.output.progress_seconds;
  return plan;
}

/// The input of a run: the file given with -i, or on restart without one, the text the checkpoint keeps.
struct InputSource {
  std::string text, name, base_directory;
};
InputSource input_source(const RunOptions& options, const std::string& checkpoint_echo);

/// The lines an executable prints after reading its input: the keys a restart's -i changed that the
/// checkpoint overrides ("ignored at restart: material, run.time_step"), and the dimensional values given as
/// plain numbers beside others with units (a note). Nothing for empty lists.
void print_input_notes(std::ostream& out, const std::vector<std::string>& ignored_at_restart,
                       const std::vector<std::string>& plain_quantities);

/// A restart without -o continues where its checkpoint is (the thermo rows to continue are there), from
/// whatever directory it is started: sets plan.directory so.
void continue_beside_checkpoint(RunPlan& plan, const RunOptions& options);

/// One run of a plan, step by step: what run_main does between the set-up and the exit, for drivers that
/// step a run themselves (the Python module, scenarios/python). start() checks the set-up (InputError when it
/// cannot run, before anything is written), opens the outputs and writes the first step's; advance(n) makes
/// at most n steps, never past the plan's last, each with its checks, outputs, stage changes and progress
/// line; finish(), once done(), prints the closing report and the pass table. Each returns an exit status: 0,
/// or kExitUnfinished when the run stopped (a failed check, an output that cannot be written; the message
/// names the step and the last good checkpoint), after which the run must not be advanced again.
class Run {
 public:
  Run(RunPlan plan, std::string program, RunOptions options, WallClock::time_point started);
  ~Run();
  Run(const Run&) = delete;
  Run& operator=(const Run&) = delete;

  int start();
  int advance(long max_steps);
  int finish();
  bool done() const;
  long last_step() const;
  RunModel& model();
  const RunPlan& plan() const;
  /// The stages on the step axis (empty without stages), once started.
  const StagePlan& stages() const;
  /// What the last kExitUnfinished said ("at step 812: ...; the last good checkpoint is ..."); else empty.
  const std::string& stop_message() const;
  /// What finish() printed before the pass table (the model's closing report); empty before.
  const std::string& closing_report() const;
  /// Where the run is (core/io/progress.hpp): zero rates before start().
  ProgressValues progress() const;
  /// The table finish() prints; available at any time after start().
  PassTable pass_table() const;
  /// The output directory and the checkpoint file the run writes.
  std::string directory() const;
  std::string checkpoint_path() const;

 private:
  struct State;
  std::unique_ptr<State> s_;
};

/// Parses the command line, calls `prepare` (reads the input or the checkpoint, chooses the threads,
/// builds and validates the system; InputError for bad input), then runs. Returns the exit status. `example`
/// (a command that works from the repository root) ends the --help text.
///
/// Under mpirun (an MPI build), a program whose model runs cut among ranks (`runs_on_ranks`) runs the same
/// steps, checks and decisions on every rank, which all take part in the collective parts (sums, gathers);
/// rank 0 alone prints and writes files (the other ranks' std::cout and std::cerr are silenced). An error
/// every rank meets (bad input, a failed health check) ends all with its status; one only rank 0 meets (an
/// output it cannot write) ends the job (comm::abort) with exit 3. Other programs are refused (exit 2).
/// `keys` and `columns` are what `--keys` and `--columns` print (reference_flags.hpp).
int run_main(int argc, char** argv, const std::string& program, const std::string& description,
             const std::string& example, const std::function<RunPlan(const RunOptions&)>& prepare,
             const KeyReference& keys, const std::vector<ColumnTable>& columns, bool runs_on_ranks = false);

}  // namespace debris
