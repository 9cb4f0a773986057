#include "scenarios/python/python_run.hpp"

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <iostream>
#include <limits>
#include <streambuf>

#include "core/error.hpp"
#include "scenarios/common/dem/dem_run.hpp"
#include "scenarios/common/dem/dem_simulation.hpp"
#include "scenarios/common/peridem/peridem_run.hpp"
#include "scenarios/python/python_input.hpp"

namespace debris {

namespace py = pybind11;

namespace {

/// A stream buffer that drops everything (quiet runs).
class NullBuffer : public std::streambuf {
 protected:
  int overflow(int c) override { return c == traits_type::eof() ? 0 : c; }
  std::streamsize xsputn(const char*, std::streamsize n) override { return n; }
};
NullBuffer g_null;

/// Raises the flag while it lives (however the scope is left).
struct SteppingFlag {
  std::atomic<bool>& flag;
  explicit SteppingFlag(std::atomic<bool>& f) : flag(f) { flag = true; }
  ~SteppingFlag() { flag = false; }
  SteppingFlag(const SteppingFlag&) = delete;
  SteppingFlag& operator=(const SteppingFlag&) = delete;
};

const char* program_name(PyModel m) { return m == PyModel::dem ? "debris.Dem" : "debris.Peridem"; }

}  // namespace

QuietStreams::QuietStreams(bool quiet) {
  if (!quiet) return;
  out_ = std::cout.rdbuf(&g_null);
  err_ = std::cerr.rdbuf(&g_null);
}

QuietStreams::~QuietStreams() {
  if (out_) std::cout.rdbuf(out_);
  if (err_) std::cerr.rdbuf(err_);
}

PyErrors& py_errors() {
  static PyErrors e;
  return e;
}

void raise_python(py::handle type, const std::string& message) {
  PyErr_SetString(type.ptr(), message.c_str());
  throw py::error_already_set();
}

PyRun::PyRun(PyModel model, const PyRunArgs& args) : kind_(model), quiet_(args.quiet) {
  RunOptions opt;
  opt.input = args.input;
  opt.restart = args.restart;
  opt.output = args.output;
  opt.threads = args.threads;
  if (!args.values.is_none()) {
    if (!args.input.empty()) throw py::value_error("give the input as a file or as a dict, not both");
    opt.input_text = yaml_from_python(args.values);
    opt.input_name = "";  // errors name the key path: the YAML text's lines are not the user's
    opt.base_directory = args.base_directory.empty() ? std::filesystem::current_path().string() : args.base_directory;
  }
  if (opt.input.empty() && opt.input_text.empty() && opt.restart.empty())
    throw py::value_error("give an input (a YAML file or a dict of its keys) or a checkpoint (restart=...)");
  if (opt.threads < 0) throw py::value_error("threads = " + std::to_string(opt.threads) + ": must be >= 0");

  const QuietStreams quiet(quiet_);
  const auto started = WallClock::now();
  RunPlan plan = model == PyModel::dem ? prepare_dem_run(opt) : prepare_peridem_run(opt);
  continue_beside_checkpoint(plan, opt);
  run_ = std::make_unique<Run>(std::move(plan), program_name(model), opt, started);
  if (run_->start() != 0) raise_python(py_errors().run_stopped, run_->stop_message());
}

PyRun::~PyRun() = default;

void PyRun::check_idle() const {
  if (stepping_) throw std::runtime_error("the simulation is stepping in another thread: read or edit it after run() returns");
}

void PyRun::check_usable() const {
  check_idle();
  if (stopped_) raise_python(py_errors().run_stopped, "the run stopped earlier: " + run_->stop_message());
}

void PyRun::advance(long steps) {
  check_usable();
  if (steps < 0) throw py::value_error("steps = " + std::to_string(steps) + ": must be >= 0");
  // Chunks of growing length up to about a fifth of a second each, the GIL released inside: other Python
  // threads run meanwhile, and Ctrl-C is acted on between chunks.
  long chunk = 1;
  while (steps > 0 && !run_->done()) {
    const long n = std::min(chunk, steps);
    const auto t0 = std::chrono::steady_clock::now();
    int status = 0;
    try {
      const SteppingFlag flag(stepping_);
      const py::gil_scoped_release release;
      const QuietStreams quiet(quiet_);
      status = run_->advance(n);
    } catch (const InputError&) {  // a stage whose changes cannot be made: the executable ends there too
      stopped_ = true;
      throw;
    }
    if (status != 0) {
      stopped_ = true;
      raise_python(py_errors().run_stopped, run_->stop_message());
    }
    steps -= n;
    if (PyErr_CheckSignals() != 0) throw py::error_already_set();
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (seconds < 0.1 && chunk < std::numeric_limits<long>::max() / 2) chunk *= 2;
  }
}

void PyRun::advance_stage() {
  check_usable();
  const StagePlan& st = run_->stages();
  const long now = model().step_count();
  long next = run_->last_step();
  for (const long s : st.start)
    if (s > now) {
      next = std::min(next, s);
      break;
    }
  advance(next - now);
}

void PyRun::finish() {
  check_usable();
  if (finished_) return;
  if (!run_->done())
    throw py::value_error("finish() at step " + std::to_string(model().step_count()) + ": the plan ends at step " +
                          std::to_string(run_->last_step()) + " (run() to get there)");
  const QuietStreams quiet(quiet_);
  if (run_->finish() != 0) {
    stopped_ = true;
    raise_python(py_errors().run_stopped, run_->stop_message());
  }
  finished_ = true;
}

std::string PyRun::checkpoint(const std::string& path) {
  const std::string target = path.empty() ? run_->checkpoint_path() : path;
  model().write_checkpoint(target, run_->plan().input_text);
  return target;
}

long PyRun::generation() {
  return kind_ == PyModel::dem ? dem_simulation(model()).layout_generation() : 0;  // PeriDEM nodes keep their order
}

}  // namespace debris
