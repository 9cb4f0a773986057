#include "core/io/progress.hpp"

#include <cmath>
#include <cstdio>
#include <string>

namespace debris {

Progress::Progress(long first_step, long last_step, std::ostream& out, double interval_seconds)
    : first_(first_step), last_(last_step), out_(out), interval_(interval_seconds), start_(Clock::now()),
      last_print_(start_) {}

void Progress::update(long step, std::size_t particles) {
  const auto now = Clock::now();
  if (std::chrono::duration<double>(now - last_print_).count() < interval_) return;
  last_print_ = now;
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  const double done = static_cast<double>(step - first_);
  const double rate = done / elapsed;
  const double left = rate > 0 ? static_cast<double>(last_ - step) / rate : 0.0;
  char line[256];
  std::snprintf(line, sizeof line, "progress: step %ld of %ld (%.1f%%), %.4g steps/s, %.3g M particle-steps/s, %s left",
                step, last_, 100.0 * static_cast<double>(step) / static_cast<double>(last_ > 0 ? last_ : 1), rate,
                rate * static_cast<double>(particles) / 1e6, format_duration(left).c_str());
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
