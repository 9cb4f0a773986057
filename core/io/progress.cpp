#include "core/io/progress.hpp"

#include <cmath>
#include <cstdio>
#include <string>

namespace debris {

Progress::Progress(long first_step, long last_step, std::ostream& out, double interval_seconds)
    : first_(first_step), last_(last_step), out_(out), interval_(interval_seconds), start_(Clock::now()),
      last_print_(start_) {}

ProgressValues Progress::values(long step) const {
  ProgressValues v;
  v.first_step = first_;
  v.step = step;
  v.last_step = last_;
  v.seconds = std::chrono::duration<double>(Clock::now() - start_).count();
  const double done = static_cast<double>(step - first_);
  v.steps_per_second = v.seconds > 0 && done > 0 ? done / v.seconds : 0.0;
  v.seconds_left = v.steps_per_second > 0 ? static_cast<double>(last_ - step) / v.steps_per_second : 0.0;
  return v;
}

void Progress::update(long step, std::size_t particles) {
  const auto now = Clock::now();
  if (std::chrono::duration<double>(now - last_print_).count() < interval_) return;
  last_print_ = now;
  const ProgressValues v = values(step);
  char line[256];
  std::snprintf(line, sizeof line, "progress: step %ld of %ld (%.1f%%), %.4g steps/s, %.3g M particle-steps/s, %s left",
                step, last_, 100.0 * static_cast<double>(step) / static_cast<double>(last_ > 0 ? last_ : 1),
                v.steps_per_second, v.steps_per_second * static_cast<double>(particles) / 1e6,
                format_duration(v.seconds_left).c_str());
  out_ << line << std::endl;
}

std::string format_duration(double seconds) {
  const long s = std::lround(seconds);
  char buf[64];
  if (s >= 3600)
    std::snprintf(buf, sizeof buf, "%ld:%02ld:%02ld", s / 3600, (s / 60) % 60, s % 60);
  else
    std::snprintf(buf, sizeof buf, "%ld:%02ld", s / 60, s % 60);
  return buf;
}

}  // namespace debris
