#pragma once
// How many host threads a run uses: the user's count when one is given, otherwise the count that steps
// fastest, measured while the run steps and measured again as the machine's load changes.
//
// Why measure instead of using every core: a step is made of many short parallel regions, and each ends at
// a barrier. On a shared machine one process beside the run takes a core from one of its threads, and every
// barrier then waits for that thread's next time slice (measured on 2 cores beside one busy loop: the
// default 1,600-particle input 0.73 s on one thread, 2.4-2.6 s on two; 32,000 particles 2.4 s on one,
// 4.9-5.0 s on two). Small systems gain nothing from a second thread even on a quiet machine (1,600
// particles: 0.73 s on one, 0.86-0.98 s on two). Every pass gives the same bits on any thread count (fixed
// partitions and fixed-order sums), so changing the count between steps never changes a result.

#include <cstddef>
#include <iosfwd>
#include <string>
#include <vector>

namespace debris::exec {

/// Where a run's thread count comes from.
struct ThreadRequest {
  int fixed = 0;       // > 0: the count the user gave; 0: tuned while stepping
  int most = 1;        // the most threads the tuner may use (the CPUs this process may run on)
  std::string source;  // "--threads", "run.threads", "OMP_NUM_THREADS", or "tuned"
  int setup = 0;       // tuned: the threads the set-up runs on, the CPUs no other process was running on
                       // when the run started (idle_cpus()); the tuner takes over at the first step
  int busy = 0;        // tuned: other processes running then (/proc/stat procs_running, less this one)
  std::string note;    // what describe() warns of: an OMP_NUM_THREADS that is no count, more threads than CPUs
};

/// The thread count OMP_NUM_THREADS gives: its first list element ("4" or "4,2") when a whole number >= 1,
/// else 0 (unset, empty, "abc", "0", "-2": no count, so the threads are tuned).
int omp_num_threads_count(const char* value);

/// CPUs of `most` that no other process is running on now: `most` less the runnable tasks of the whole
/// machine (/proc/stat procs_running, this process's own thread not counted), at least 1. `most` when
/// /proc/stat cannot be read. `procs_running` is what to parse (tests give their own text).
int idle_cpus(int most, int* busy = nullptr);
int idle_cpus_from_proc_stat(const std::string& proc_stat, int most, int* busy = nullptr);

class ThreadTuner;

/// Resolves the request: `command_line` (--threads) wins over `input` (run.threads), which wins over the
/// OMP_NUM_THREADS environment variable. With none of them the count is tuned: the set-up runs on the CPUs
/// that are idle when the run starts (on a loaded machine a thread given a busy CPU makes every barrier of
/// the set-up wait for it), and the process's tuner (process_tuner()) takes over at the first step. Sets the OpenMP thread
/// count and returns the request. The executables call it; a program that never does (tests, benchmarks)
/// keeps OpenMP's own count and is never tuned.
ThreadRequest request_threads(int command_line, int input);

/// One line for the start of a run: the count and where it comes from.
std::string describe(const ThreadRequest& request);

/// The process's tuner when request_threads() left the count to it; nullptr otherwise.
ThreadTuner* process_tuner();
/// Prints the process tuner's summary line (the counts it chose, and for how many steps) to `out`; prints
/// nothing when the count was not tuned. Every executable ends its run with it.
void print_tuning_summary(std::ostream& out);
/// Ends the tuning (set_threads() and a fixed request call it: a count set by hand is kept).
void stop_tuning();

/// Times one step of a simulation for the process's tuner (DemSimulation::step and PeridemSimulation::step
/// hold one): the count it picks applies from the next step. Free when nothing is tuned.
class TunedStep {
 public:
  TunedStep();
  ~TunedStep();
  TunedStep(const TunedStep&) = delete;
  TunedStep& operator=(const TunedStep&) = delete;

 private:
  long long start_ns_ = -1;
};

/// Chooses among 1, 2, 4, ... up to `most` threads from measured step times. Call step_done() after every
/// step with the step's wall seconds; the count it sets (omp_set_num_threads) applies from the next step.
///
/// It times windows of steps of at least `window_seconds`. A probe times one window on each candidate count
/// and keeps the fastest (the fewer threads when within 3%: they leave the other cores to other work). Then
/// it runs on the choice and probes again after `interval` windows, an interval that doubles (up to 128)
/// while probes keep the choice and starts again at 8 when one changes it, or at once when a window runs
/// 25% slower or faster than the choice's probe (load came or went). A probe costs at most one window on
/// each other count, so on a quiet machine the tuning costs a few percent at most.
class ThreadTuner {
 public:
  ThreadTuner(int most, int first_choice, double window_seconds = 0.1);

  /// Before a step: makes sure the OpenMP count is the tuner's (a set-up between may have used others).
  void before_step();
  void step_done(double seconds);
  int threads() const { return current_; }

  /// Lines saying what was chosen and why since the last call (the first choice and each change), for the
  /// terminal; empty when nothing changed.
  std::vector<std::string> take_messages();
  /// One line for the end of the run: the share of steps on each count and how many probes ran.
  std::string summary() const;

  const std::vector<int>& candidates() const { return candidates_; }

 private:
  void window_done(double per_step);
  void start_probe();
  void choose();
  void use(int threads);
  int index_of(int threads) const;

  std::vector<int> candidates_;
  std::vector<double> probe_time_;  // seconds per step of each candidate in the current or last probe
  std::vector<long> steps_on_;      // steps run on each candidate
  double window_seconds_;
  int current_;
  double window_time_ = 0;
  long window_steps_ = 0;
  bool probing_ = false;
  std::size_t probe_next_ = 0;  // the next candidate the probe times
  int choice_ = 0;              // the count chosen by the last probe (0 before the first)
  double reference_ = 0;        // its seconds per step in that probe
  int interval_ = 8, windows_since_probe_ = 0, probes_ = 0, changes_ = 0;
  std::vector<std::string> messages_;
};

}  // namespace debris::exec
