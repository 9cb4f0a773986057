#pragma once
// A progress line for long runs: step, percentage, steps per second, particle-steps per second and the
// time left, printed at most every `interval` seconds (so short runs print nothing).
#include <chrono>
#include <ostream>

namespace debris {

class Progress {
 public:
  Progress(long first_step, long last_step, std::ostream& out, double interval_seconds = 10.0);
  /// Prints a line if `interval` has passed since the last one.
  void update(long step, std::size_t particles);

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
