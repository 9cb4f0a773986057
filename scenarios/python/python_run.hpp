#pragma once
// One simulation as Python drives it: the executables' prepare (input or checkpoint, set-up, checks) and
// their stepwise runner (scenarios/common/run/runner.hpp), so a run from Python writes what the executable
// writes, bit for bit. What Python adds: the input as a dict, stepping with the GIL released (in chunks,
// so Ctrl-C is seen between them), the runner's exits as exceptions, and the state as numpy arrays over
// the live columns (python_state.cpp).
#include <pybind11/pybind11.h>

#include <atomic>
#include <memory>
#include <optional>
#include <string>

#include "scenarios/common/run/runner.hpp"

namespace debris {

enum class PyModel { dem, peridem };

/// How a simulation is made from Python (the executables' command line, and the input as a dict).
struct PyRunArgs {
  std::string input;        // a YAML file
  pybind11::object values;  // or a dict of its keys (None: not given)
  std::string restart, output, base_directory;
  int threads = 0;
  bool quiet = false;       // nothing printed (the same values come as return values and exceptions)
};

class PyRun {
 public:
  PyRun(PyModel model, const PyRunArgs& args);
  ~PyRun();

  PyModel kind() const { return kind_; }
  /// The run and its model, for every value and view: refused (RuntimeError) while another Python thread
  /// is inside advance(), whose steps would change them under the reader.
  Run& run() {
    check_idle();
    return *run_;
  }
  const Run& run() const {
    check_idle();
    return *run_;
  }
  RunModel& model() { return run().model(); }
  bool quiet() const { return quiet_; }

  /// At most `steps` steps (to the plan's end); the runner's outputs and checks at each. RunStopped if the
  /// run stopped (it cannot go on), KeyboardInterrupt between steps.
  void advance(long steps);
  /// To the start of the next stage (the changes it makes applied) or the end.
  void advance_stage();
  /// Closing report and pass table (printed unless quiet); once, at the plan's end.
  void finish();
  bool finished() const { return finished_; }
  /// What finish() reported before the pass table (the wear verdict's paragraph); empty before.
  const std::string& report() const { return run_->closing_report(); }

  /// Writes a checkpoint (the executable's format) to `path`, or to the run's own when empty; returns it.
  std::string checkpoint(const std::string& path);

  /// Bumped whenever an index into the state's columns may stop meaning the same item: a DEM re-sort at a
  /// neighbour rebuild (DemSimulation::layout_generation). Views made before a change refuse to be read.
  long generation();

 private:
  PyModel kind_;
  bool quiet_ = false, finished_ = false, stopped_ = false;
  std::unique_ptr<Run> run_;
  std::atomic<bool> stepping_{false};
  void check_usable() const;
  void check_idle() const;
};

/// Swaps std::cout and std::cerr for a sink while it lives, when `quiet` (the runner prints as it goes).
class QuietStreams {
 public:
  explicit QuietStreams(bool quiet);
  ~QuietStreams();
  QuietStreams(const QuietStreams&) = delete;
  QuietStreams& operator=(const QuietStreams&) = delete;

 private:
  std::streambuf *out_ = nullptr, *err_ = nullptr;
};

/// The module's exceptions (created in debris_module.cpp): InputError (a ValueError), RunStopped (a
/// RuntimeError), StaleViewError (a RuntimeError).
struct PyErrors {
  pybind11::handle input_error, run_stopped, stale_view;  // held by the module (no reference kept here: a
  // static object would be released after the interpreter is gone)
};
PyErrors& py_errors();
[[noreturn]] void raise_python(pybind11::handle type, const std::string& message);

}  // namespace debris
