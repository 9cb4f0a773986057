#pragma once
// A progress line for long runs: step, percentage, steps per second, particle-steps per second and the
// time left, printed at most every `interval` seconds (so short runs print nothing).
#include <chrono>
#include <ostream>

namespace debris {

/// Where a run is, as the progress line says it.
struct ProgressValues {
  long first_step = 0, step = 0, last_step = 0;
  double seconds = 0;           // wall seconds since the first step
  double steps_per_second = 0;  // since then (0 before a step is made)
  double seconds_left = 0;      // at that rate
};

class Progress {
 public:
  Progress(long first_step, long last_step, std::ostream& out, double interval_seconds = 10.0);
  /// Prints a line if `interval` has passed since the last one.
  void update(long step, std::size_t particles);
  /// The line's numbers at `step`, now.
  ProgressValues values(long step) const;

 private:
  using Clock = std::chrono::steady_clock;
  long first_, last_;
  std::ostream& out_;
  double interval_;
  Clock::time_point start_, last_print_;
};

/// "1:02:03" or "2:03" for a number of seconds.
std::string format_duration(double seconds);

}  // namespace debris
