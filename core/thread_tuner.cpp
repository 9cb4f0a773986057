#include "core/thread_tuner.hpp"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <memory>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <sstream>

namespace debris::exec {

namespace {

constexpr double kSameSpeed = 1.03;     // within 3%: take the fewer threads
constexpr double kLoadChanged = 1.25;   // a window this much slower or faster than the probe: probe again
constexpr int kFirstInterval = 8, kLongestInterval = 128;
constexpr int kMostMessages = 10;

std::string per_step_text(double seconds) {
  std::ostringstream os;
  os << std::setprecision(3);
  if (seconds < 1e-3)
    os << seconds * 1e6 << " us";
  else
    os << seconds * 1e3 << " ms";
  return os.str();
}

}  // namespace

namespace {
std::unique_ptr<ThreadTuner>& the_process_tuner() {
  static std::unique_ptr<ThreadTuner> tuner;
  return tuner;
}
long long now_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}
}  // namespace

ThreadRequest request_threads(int command_line, int input) {
  ThreadRequest r;
  r.most = std::max(1, omp_get_num_procs());  // respects the process's CPU affinity (taskset, cgroups)
  if (command_line > 0) {
    r.fixed = command_line;
    r.source = "--threads";
  } else if (input > 0) {
    r.fixed = input;
    r.source = "run.threads";
  } else if (const char* env = std::getenv("OMP_NUM_THREADS"); env && *env) {
    if (omp_num_threads_count(env) > 0) {
      r.fixed = omp_get_max_threads();  // as the OpenMP runtime read it
      r.source = "OMP_NUM_THREADS";
    } else {
      r.note = "OMP_NUM_THREADS='" + std::string(env) + "' is not a thread count (a whole number >= 1): ignored";
    }
  }
  if (r.fixed > 0) {
    if (r.fixed > r.most)
      r.note = std::to_string(r.fixed) + " threads on " + std::to_string(r.most) +
               " CPUs: the threads share CPUs and each step waits for the slowest (fewer may step faster)";
    stop_tuning();
    omp_set_num_threads(r.fixed);
    return r;
  }
  r.source = "tuned";
  // The tuner starts on one thread: the cheap guess on a loaded machine, and on a quiet one the probe
  // reaches the others within its first windows.
  the_process_tuner() = std::make_unique<ThreadTuner>(r.most, 1);
  r.setup = idle_cpus(r.most, &r.busy);
  omp_set_num_threads(r.setup);
  return r;
}

int idle_cpus_from_proc_stat(const std::string& proc_stat, int most, int* busy) {
  const std::string key = "procs_running ";
  const std::size_t at = proc_stat.find("\n" + key);
  const std::size_t from = at == std::string::npos ? (proc_stat.rfind(key, 0) == 0 ? 0 : std::string::npos)
                                                   : at + 1;
  if (from == std::string::npos) return most;
  const long running = std::strtol(proc_stat.c_str() + from + key.size(), nullptr, 10);
  const long others = std::max(0L, running - 1);  // this process's own thread is running: it reads the file
  if (busy) *busy = static_cast<int>(std::min<long>(others, 1 << 20));
  return static_cast<int>(std::clamp<long>(most - others, 1, most));
}

int idle_cpus(int most, int* busy) {
  std::ifstream in("/proc/stat");
  if (!in) return most;
  std::stringstream text;
  text << in.rdbuf();
  return idle_cpus_from_proc_stat(text.str(), most, busy);
}

int omp_num_threads_count(const char* value) {
  if (!value) return 0;
  const std::string v(value);
  const std::string first = v.substr(0, v.find(','));
  const auto begin = first.find_first_not_of(" \t"), end = first.find_last_not_of(" \t");
  if (begin == std::string::npos) return 0;
  const std::string digits = first.substr(begin, end - begin + 1);
  if (digits.empty() || digits.size() > 9 || digits.find_first_not_of("0123456789") != std::string::npos) return 0;
  return std::stoi(digits);
}

std::string describe(const ThreadRequest& request) {
  const std::string warning = request.note.empty() ? "" : "\nwarning: " + request.note;
  if (request.fixed > 0) return "threads: " + std::to_string(request.fixed) + " (" + request.source + ")" + warning;
  return "threads: tuned while stepping, 1 to " + std::to_string(request.most) +
         " (the count that steps fastest under this machine's load; --threads, run.threads or OMP_NUM_THREADS "
         "fix it); set-up on " + std::to_string(request.setup) + " (" + std::to_string(request.busy) +
         " other process" + (request.busy == 1 ? "" : "es") + " running at start)" + warning;
}


ThreadTuner* process_tuner() { return the_process_tuner().get(); }
void stop_tuning() { the_process_tuner().reset(); }

void print_tuning_summary(std::ostream& out) {
  if (const ThreadTuner* t = process_tuner()) out << t->summary() << "\n";
}

TunedStep::TunedStep() {
  if (ThreadTuner* t = process_tuner()) {
    t->before_step();
    start_ns_ = now_ns();
  }
}

TunedStep::~TunedStep() {
  if (start_ns_ >= 0)
    if (ThreadTuner* t = process_tuner()) t->step_done(1e-9 * static_cast<double>(now_ns() - start_ns_));
}

ThreadTuner::ThreadTuner(int most, int first_choice, double window_seconds)
    : window_seconds_(window_seconds), current_(std::max(1, first_choice)) {
  for (int c = 1; c < most; c *= 2) candidates_.push_back(c);
  candidates_.push_back(std::max(1, most));
  probe_time_.assign(candidates_.size(), 0.0);
  steps_on_.assign(candidates_.size(), 0);
  if (index_of(current_) < 0) current_ = candidates_.back();
  use(current_);
  start_probe();
}

int ThreadTuner::index_of(int threads) const {
  for (std::size_t k = 0; k < candidates_.size(); ++k)
    if (candidates_[k] == threads) return static_cast<int>(k);
  return -1;
}

void ThreadTuner::use(int threads) {
  current_ = threads;
  omp_set_num_threads(threads);
}

void ThreadTuner::before_step() {
  if (omp_get_max_threads() != current_) omp_set_num_threads(current_);
}

void ThreadTuner::step_done(double seconds) {
  ++steps_on_[static_cast<std::size_t>(index_of(current_))];
  window_time_ += seconds;
  ++window_steps_;
  if (window_time_ < window_seconds_) return;
  const double per_step = window_time_ / static_cast<double>(window_steps_);
  window_time_ = 0;
  window_steps_ = 0;
  window_done(per_step);
}

void ThreadTuner::start_probe() {
  probing_ = true;
  probe_next_ = 0;
  std::fill(probe_time_.begin(), probe_time_.end(), 0.0);
  // The current count first: its window needs no switch.
}

void ThreadTuner::window_done(double per_step) {
  if (candidates_.size() == 1) return;
  if (probing_) {
    probe_time_[static_cast<std::size_t>(index_of(current_))] = per_step;
    // The next candidate not yet timed in this probe, in ascending order.
    while (probe_next_ < candidates_.size() && probe_time_[probe_next_] > 0) ++probe_next_;
    if (probe_next_ < candidates_.size())
      use(candidates_[probe_next_]);
    else
      choose();
    return;
  }
  ++windows_since_probe_;
  if (per_step > kLoadChanged * reference_ || per_step * kLoadChanged < reference_) {
    interval_ = kFirstInterval;
    start_probe();
  } else if (windows_since_probe_ >= interval_) {
    start_probe();
  }
}

void ThreadTuner::choose() {
  const double fastest = *std::min_element(probe_time_.begin(), probe_time_.end());
  int best = candidates_.back();
  for (std::size_t k = 0; k < candidates_.size(); ++k)
    if (probe_time_[k] <= kSameSpeed * fastest) {
      best = candidates_[k];
      break;
    }
  const bool first = choice_ == 0, changed = best != choice_;
  if (first || changed) {
    if (!first) ++changes_;
    if (changes_ < kMostMessages) {
      std::ostringstream os;
      os << "threads: " << best << " of up to " << candidates_.back() << " (a step took";
      for (std::size_t k = 0; k < candidates_.size(); ++k)
        os << (k ? "," : "") << " " << per_step_text(probe_time_[k]) << " on " << candidates_[k];
      os << ")";
      messages_.push_back(os.str());
    } else if (changes_ == kMostMessages) {
      messages_.push_back("threads: the load keeps changing; further changes are counted at the end");
    }
  }
  interval_ = changed ? kFirstInterval : std::min(kLongestInterval, 2 * interval_);
  choice_ = best;
  reference_ = probe_time_[static_cast<std::size_t>(index_of(best))];
  probing_ = false;
  windows_since_probe_ = 0;
  ++probes_;
  use(best);
}

std::vector<std::string> ThreadTuner::take_messages() {
  std::vector<std::string> out;
  out.swap(messages_);
  return out;
}

std::string ThreadTuner::summary() const {
  long total = 0;
  for (long s : steps_on_) total += s;
  std::ostringstream os;
  os << "threads tuned while stepping:";
  bool any = false;
  for (std::size_t k = 0; k < candidates_.size(); ++k) {
    if (steps_on_[k] == 0) continue;
    const double share = 100.0 * static_cast<double>(steps_on_[k]) / static_cast<double>(std::max(1L, total));
    os << (any ? "," : "") << " " << candidates_[k] << " for ";
    if (share < 0.5)
      os << "<1";  // a probe's few steps
    else
      os << std::fixed << std::setprecision(0) << share;
    os << "% of steps";
    any = true;
  }
  os << " (" << probes_ << (probes_ == 1 ? " probe, " : " probes, ") << changes_
     << (changes_ == 1 ? " change)" : " changes)");
  return os.str();
}

}  // namespace debris::exec
