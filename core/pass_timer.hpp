#pragma once
// Wall time of the passes, for the pass tables the executables print: one clock, seconds_since() a start,
// and a scoped PassTimer that adds the seconds it lived to a counter, so a step reads as its passes.
#include <chrono>

namespace debris {

using WallClock = std::chrono::steady_clock;

inline double seconds_since(WallClock::time_point t0) {
  return std::chrono::duration<double>(WallClock::now() - t0).count();
}

/// Adds the wall seconds from its construction to its destruction to `total`.
class PassTimer {
 public:
  explicit PassTimer(double& total) : total_(total), t0_(WallClock::now()) {}
  ~PassTimer() { total_ += seconds_since(t0_); }
  PassTimer(const PassTimer&) = delete;
  PassTimer& operator=(const PassTimer&) = delete;

 private:
  double& total_;
  WallClock::time_point t0_;
};

}  // namespace debris
