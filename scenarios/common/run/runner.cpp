#include "scenarios/common/run/runner.hpp"

#include <CLI/CLI.hpp>
#include <chrono>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <sstream>

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

/// The run proper, once the plan is built (`setup_seconds` since the command started).
int run_plan(RunPlan& plan, const std::string& program, const RunOptions& opt, Clock::time_point started) {
  RunModel& model = *plan.model;
  const long first_step = model.step_count();
  if (plan.restored) std::cout << "restarting from " << opt.restart << " at step " << first_step << "\n";

  // The run's length: the stages', or run.steps, which with stages may stop earlier (a chunk of a long run).
  const StagePlan stages = resolve_stages(plan.stages, plan.dt);
  long last_step = plan.steps;
  if (!stages.empty()) {
    if (last_step < 0) last_step = stages.end;
    if (last_step > stages.end)
      throw input_error("run.steps", std::to_string(last_step),
                        "is beyond the end of the stages (step " + std::to_string(stages.end) + ")");
  }
  if (last_step < first_step)
    throw input_error("run.steps", std::to_string(last_step),
                      "is before the checkpoint's step " + std::to_string(first_step) + " (run.steps is a total)");
  if (!stages.empty()) {
    std::cout << "stages:";
    for (std::size_t k = 0; k < stages.start.size(); ++k)
      std::cout << " " << stages.names[k] << " [" << stages.start[k] << ", "
                << (k + 1 < stages.start.size() ? stages.start[k + 1] : stages.end) << ")";
    std::cout << "\n";
    const int k = stages.stage_at(first_step);
    if (plan.restored && k >= 0 && stages.start[static_cast<std::size_t>(k)] != first_step)
      std::cout << "continuing inside stage " << k << " '" << stages.names[static_cast<std::size_t>(k)] << "'\n";
  }

  namespace fs = std::filesystem;
  const fs::path dir = plan.directory;
  const std::string checkpoint = (dir / "checkpoint.h5").string();
  // The checkpoint a stopped run names: the last one this run wrote, or the one it restarted from when
  // that is the file it would overwrite.
  std::string last_good = "none (set output.checkpoint_every)";
  {
    std::error_code ec;
    if (plan.restored && fs::equivalent(opt.restart, checkpoint, ec))
      last_good = checkpoint + " (step " + std::to_string(first_step) + ")";
  }
  auto stop = [&](const std::string& problem) {
    std::cerr << program << ": stopped: " << problem << "\n"
              << program << ": the last good checkpoint is " << last_good << std::endl;
    return kExitUnfinished;
  };
  auto due = [](long every, long step) { return every > 0 && step % every == 0; };
  // The set-up as built, before any file is written: a state that cannot run is bad input.
  if (!plan.restored) {
    std::string problem = model.step_check();
    if (problem.empty()) problem = model.health_check();
    if (!problem.empty())
      throw input_error(model.setup_key(), "the state at step " + std::to_string(first_step),
                        problem + " (nothing was written)");
  }
  try {
    {
      std::error_code ec;
      fs::create_directories(dir, ec);
      if (ec) throw output_error(dir.string(), "cannot create the output directory: " + ec.message());
    }
    const auto cols = model.thermo_columns();
    // A restart keeps the rows up to its checkpoint's step, but the row at that step only where the run
    // in one piece has it too (a thermo step, the first, or the last): the run that wrote the checkpoint
    // ended there and wrote a row that is not due.
    const bool keep_first_row = due(plan.thermo_every, first_step) || first_step == 0 || last_step == first_step;
    ThermoCsv thermo =
        plan.restored ? ThermoCsv((dir / "thermo.csv").string(), cols, keep_first_row ? first_step : first_step - 1)
                      : ThermoCsv((dir / "thermo.csv").string(), cols);
    if (thermo.dropped_to_step() > first_step)
      std::cout << "thermo.csv: its rows after step " << first_step << ", up to step " << thermo.dropped_to_step()
                << " (written by a run that went on past this checkpoint), are dropped; so are the other tables'\n";
    const std::string suffix = plan.restored ? ".restart" + std::to_string(first_step) : "";
    model.open_frames(dir.string(), suffix);

    // The pass table counts the stepping only: what the passes held after the set-up is subtracted.
    const std::vector<PassTime> setup_times = model.pass_times();
    const double setup_seconds = seconds_since(started);
    const auto t0 = Clock::now();
    double output_seconds = 0.0;
    long last_checkpoint = -1;
    auto stage_starts = [&](long step) { return step < last_step ? stages.stage_starting_at(step) : -1; };

    auto write_outputs = [&](bool final_step) {
      const auto o0 = Clock::now();
      const long step = model.step_count();
      const bool first = step == first_step;
      if (due(plan.thermo_every, step) || final_step || first) {
        const auto row = model.thermo_row();
        if (!(plan.restored && first)) thermo.write_row(row);
        model.print_thermo(cols, row, first);
      }
      if (final_step || first || model.frame_due(step)) model.write_frame(final_step || first);
      // A checkpoint at each stage boundary too (before the stage's changes): a later stage can be rerun from it.
      const bool boundary = step > 0 && stage_starts(step) > 0;
      if ((final_step || due(plan.checkpoint_every, step) || boundary) && step != last_checkpoint &&
          !(plan.restored && first)) {
        model.write_checkpoint(checkpoint, plan.input_text);
        last_checkpoint = step;
        last_good = checkpoint + " (step " + std::to_string(step) + ")";
      }
      output_seconds += seconds_since(o0);
    };
    auto begin_stage = [&](long step) {
      const int k = stage_starts(step);
      if (k < 0) return;
      const std::string what = model.apply_stage(k);
      std::cout << "stage " << k << " '" << stages.names[static_cast<std::size_t>(k)] << "' starts at step " << step
                << (what.empty() ? std::string() : ": " + what) << std::endl;
    };

    // Stage changes come after a step's outputs: a checkpoint holds the state before them, and a restart
    // from it makes them exactly as this run does (stages.hpp).
    if (!plan.restored) begin_stage(first_step);
    write_outputs(last_step == first_step);
    if (plan.restored) begin_stage(first_step);
    Progress progress(first_step, last_step, std::cout, plan.progress_seconds);
    exec::ThreadTuner* tuner = exec::process_tuner();  // the simulations' steps feed it (exec::TunedStep)
    // Offload builds: host <-> device bytes of the steps themselves, outputs and sampled checks left out (they
    // copy on purpose): a step should move only scalars, block sums and group views, never the state.
    double step_bytes = 0.0;
    auto moved_bytes = [] {
      if constexpr (!exec::offload_build()) return 0.0;  // host builds move nothing: no call per step
      const exec::TransferStats t = exec::transfer_stats();
      return t.to_host_bytes + t.to_device_bytes;
    };
    while (model.step_count() < last_step) {
      const double moved_before = moved_bytes();
      model.step();
      if (tuner)
        for (const std::string& m : tuner->take_messages())
          std::cout << m << ", from step " << model.step_count() << std::endl;
      const long step = model.step_count();
      const bool final_step = step == last_step;
      if (const std::string problem = model.step_check(); !problem.empty()) return stop(problem);
      step_bytes += moved_bytes() - moved_before;
      if (final_step || due(plan.thermo_every, step) || model.frame_due(step) || due(plan.checkpoint_every, step) ||
          stage_starts(step) > 0) {
        const std::string problem = model.health_check();
        if (!problem.empty()) return stop(problem);
      }
      write_outputs(final_step);
      begin_stage(step);
      const double moved_progress = moved_bytes();
      progress.update(step, model.items());
      step_bytes += moved_bytes() - moved_progress;
    }

    const std::string report = model.closing_report();
    if (!report.empty()) std::cout << report << "\n";
    exec::print_tuning_summary(std::cout);

    // The pass table: set-up, each pass while stepping, output, and the rest (checks, stage changes, the
    // loop itself), so the shares add up to the total.
    const double stepping = seconds_since(t0);
    const double wall = setup_seconds + stepping;
    std::vector<PassTime> rows = model.pass_times();
    for (std::size_t k = 0; k < rows.size() && k < setup_times.size(); ++k) rows[k].seconds -= setup_times[k].seconds;
    double accounted = output_seconds;
    for (const PassTime& r : rows) accounted += r.seconds;
    auto line = [&](const std::string& name, double s, const std::string& extra) {
      std::cout << std::left << std::setw(13) << name << std::right << std::setw(10) << std::fixed
                << std::setprecision(3) << s << std::setw(8) << std::setprecision(1) << (wall > 0 ? 100 * s / wall : 0)
                << "%" << (extra.empty() ? "" : "  " + extra) << "\n"
                << std::defaultfloat;
    };
    std::cout << "\npass            seconds   share\n";
    line("set-up", setup_seconds, "(input, system, first forces, output files)");
    for (const PassTime& r : rows) line(r.name, r.seconds, r.note);
    line("output", output_seconds, "(thermo, frames, checkpoints)");
    line("rest", std::max(0.0, stepping - accounted), "(health checks, stage changes, loop)");
    std::ostringstream rate;
    const double steps = static_cast<double>(last_step - first_step);
    rate << std::setprecision(3) << (stepping > 0 ? static_cast<double>(model.items()) * steps / stepping / 1e6 : 0.0)
         << " M " << model.item_name() << "-steps/s while stepping";
    line("total", wall, rate.str());
    if constexpr (exec::offload_build())
      std::cout << "device transfers while stepping: " << std::setprecision(6)
                << (steps > 0 ? step_bytes / steps : 0.0) << " B per step (outputs and checks left out)\n";
    std::cout << "output written to " << dir.string() << "/ (thermo.csv, " << model.frame_files(suffix)
              << ", checkpoint.h5)\n";
    return 0;
  } catch (const InputError&) {
    throw;  // a stage that cannot be applied: bad input
  } catch (const std::bad_alloc&) {
    return stop("out of memory at step " + std::to_string(model.step_count()));
  } catch (const std::exception& e) {
    // An output that cannot be written (a full disk, a file size limit, a file where a directory should
    // be): the run cannot finish, and nothing it wrote before is touched.
    return stop("at step " + std::to_string(model.step_count()) + ": " + e.what());
  }
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
  if (options.input.empty()) {
    s.text = checkpoint_echo;
    s.name = options.restart + " (input echo)";
  } else {
    s.text = read_input_file(options.input);
    s.name = options.input;
    s.base_directory = std::filesystem::path(options.input).parent_path().string();
  }
  return s;
}

int run_main(int argc, char** argv, const std::string& program, const std::string& description,
             const std::string& example, const std::function<RunPlan(const RunOptions&)>& prepare) {
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
  if (const int status = parse_command_line(app, argc, argv); status >= 0) return status;
  if (opt.input.empty() && opt.restart.empty()) {
    std::cerr << program
              << ": give an input file (-i run.yaml) or a checkpoint (--restart checkpoint.h5); --help "
                 "for more\n";
    return kExitInput;
  }
  return exit_status_of(program, [&] {
    const auto started = Clock::now();
    RunPlan plan = prepare(opt);
    // A restart without -o continues where its checkpoint is (the thermo rows to continue are there),
    // from whatever directory it is started.
    if (!opt.restart.empty() && opt.output.empty()) {
      const std::filesystem::path parent = std::filesystem::path(opt.restart).parent_path();
      plan.directory = parent.empty() ? "." : parent.string();
    }
    return run_plan(plan, program, opt, started);
  });
}

}  // namespace debris
