// The thread tuner against a model machine whose step time on each thread count is known (and changes
// when "load" comes): it must find the fastest count, prefer fewer threads when the difference is noise,
// follow the load both ways, and cost little while it probes.
#include <gtest/gtest.h>

#include <cstdlib>
#include <functional>
#include <map>
#include <optional>
#include <sstream>
#include <string>

#include "core/exec.hpp"
#include "core/thread_tuner.hpp"

namespace debris::exec {
namespace {

// Runs `steps` steps on the model machine (seconds per step as a function of the count and the step) and
// returns the total time; the tuner decides the count of each step.
struct Outcome {
  double seconds = 0;
  std::map<int, long> steps_on;
};
Outcome run(ThreadTuner& tuner, long first, long steps, const std::function<double(int threads, long step)>& machine) {
  Outcome r;
  for (long k = first; k < first + steps; ++k) {
    const double t = machine(tuner.threads(), k);
    r.seconds += t;
    ++r.steps_on[tuner.threads()];
    tuner.step_done(t);
  }
  return r;
}

class ThreadTunerTest : public ::testing::Test {
 protected:
  void TearDown() override { set_threads(saved_); }
  int saved_ = threads();
};

TEST_F(ThreadTunerTest, CandidatesArePowersOfTwoUpToTheMost) {
  EXPECT_EQ(ThreadTuner(1, 1).candidates(), (std::vector<int>{1}));
  EXPECT_EQ(ThreadTuner(2, 1).candidates(), (std::vector<int>{1, 2}));
  EXPECT_EQ(ThreadTuner(6, 1).candidates(), (std::vector<int>{1, 2, 4, 6}));
  EXPECT_EQ(ThreadTuner(16, 16).candidates(), (std::vector<int>{1, 2, 4, 8, 16}));
}

TEST_F(ThreadTunerTest, FindsTheFastestCountAndSetsIt) {
  // A quiet 8-core machine where 4 threads are fastest (memory bound beyond).
  const std::map<int, double> per_step{{1, 4e-3}, {2, 2.2e-3}, {4, 1.3e-3}, {8, 1.4e-3}};
  ThreadTuner tuner(8, 1, 0.01);
  const Outcome r = run(tuner, 0, 20000, [&](int t, long) { return per_step.at(t); });
  EXPECT_EQ(tuner.threads(), 4);
  EXPECT_EQ(threads(), 4);  // the OpenMP count follows
  // Probing costs little: within 5% of always running on 4.
  EXPECT_LT(r.seconds, 1.05 * 20000 * 1.3e-3);
  const auto messages = tuner.take_messages();
  ASSERT_EQ(messages.size(), 1u);  // the first choice; later probes keep it and say nothing
  EXPECT_NE(messages[0].find("threads: 4 of up to 8"), std::string::npos) << messages[0];
  EXPECT_TRUE(tuner.take_messages().empty());
}

TEST_F(ThreadTunerTest, TakesFewerThreadsWhenTheDifferenceIsNoise) {
  ThreadTuner tuner(2, 2, 0.01);
  run(tuner, 0, 2000, [](int t, long) { return t == 1 ? 1.00e-3 : 0.99e-3; });
  EXPECT_EQ(tuner.threads(), 1);
}

TEST_F(ThreadTunerTest, FollowsTheLoadBothWays) {
  // Two cores. Quiet: 2 threads step in 0.6 ms, 1 in 1 ms. From step 10,000 to 30,000 a process beside the
  // run takes a core: every barrier then waits for a time slice, and 2 threads step in 3 ms, 1 in 1.1 ms.
  auto machine = [](int t, long k) {
    const bool loaded = k >= 10000 && k < 30000;
    if (t == 1) return loaded ? 1.1e-3 : 1.0e-3;
    return loaded ? 3.0e-3 : 0.6e-3;
  };
  ThreadTuner tuner(2, 1, 0.02);
  run(tuner, 0, 10000, machine);
  EXPECT_EQ(tuner.threads(), 2);
  const Outcome loaded = run(tuner, 10000, 20000, machine);
  EXPECT_EQ(tuner.threads(), 1);
  // The tuner noticed within a window or two, and its later probes of 2 threads cost at most a few windows.
  EXPECT_LT(loaded.seconds, 1.10 * 20000 * 1.1e-3);
  run(tuner, 30000, 20000, machine);
  EXPECT_EQ(tuner.threads(), 2);
  const std::string summary = tuner.summary();
  EXPECT_NE(summary.find(" 1 for "), std::string::npos) << summary;
  EXPECT_NE(summary.find(" 2 for "), std::string::npos) << summary;
  EXPECT_NE(summary.find("2 changes"), std::string::npos) << summary;
}

TEST_F(ThreadTunerTest, ASingleCandidateNeverProbes) {
  ThreadTuner tuner(1, 1, 0.0);
  run(tuner, 0, 100, [](int, long) { return 1e-3; });
  EXPECT_EQ(tuner.threads(), 1);
  EXPECT_TRUE(tuner.take_messages().empty());
}

// The test's own environment must not decide which half runs: OMP_NUM_THREADS is set aside while it runs
// and put back after.
class SavedOmpNumThreads {
 public:
  SavedOmpNumThreads() {
    if (const char* v = std::getenv("OMP_NUM_THREADS")) saved_ = v;
    unsetenv("OMP_NUM_THREADS");
  }
  ~SavedOmpNumThreads() {
    if (saved_) setenv("OMP_NUM_THREADS", saved_->c_str(), 1);
    else unsetenv("OMP_NUM_THREADS");
  }

 private:
  std::optional<std::string> saved_;
};

TEST(ThreadRequest, UserCountsWinInOrderAndOtherwiseTheCountIsTuned) {
  const SavedOmpNumThreads environment;
  const int saved = threads();
  ThreadRequest r = request_threads(3, 2);
  EXPECT_EQ(r.fixed, 3);
  EXPECT_EQ(r.source, "--threads");
  EXPECT_EQ(threads(), 3);
  r = request_threads(0, 2);
  EXPECT_EQ(r.fixed, 2);
  EXPECT_EQ(r.source, "run.threads");
  {
    r = request_threads(0, 0);
    EXPECT_EQ(r.fixed, 0);
    EXPECT_EQ(r.source, "tuned");
    EXPECT_GE(r.most, 1);
    EXPECT_NE(describe(r).find("tuned while stepping"), std::string::npos);
    ASSERT_NE(process_tuner(), nullptr);
    EXPECT_GE(r.setup, 1);
    EXPECT_LE(r.setup, r.most);
    EXPECT_EQ(threads(), r.setup);  // the set-up runs on the CPUs idle at the start
    EXPECT_NE(describe(r).find("set-up on " + std::to_string(r.setup)), std::string::npos);
    { TunedStep step; EXPECT_EQ(threads(), 1); }  // the tuner's count from the first step on
    std::ostringstream summary;
    print_tuning_summary(summary);
    EXPECT_EQ(summary.str(), process_tuner()->summary() + "\n");  // the one line every executable ends with
  }
  set_threads(saved);
  std::ostringstream none;
  print_tuning_summary(none);  // a count set by hand ends the tuning: no summary
  EXPECT_EQ(none.str(), "");
}

// OMP_NUM_THREADS counts only when it is one: a whole number >= 1, or a list starting with one (nesting).
// Anything else is ignored with a warning and the count is tuned; more threads than CPUs are warned of.
TEST(ThreadRequest, AnOmpNumThreadsThatIsNoCountIsIgnoredWithAWarning) {
  EXPECT_EQ(omp_num_threads_count("4"), 4);
  EXPECT_EQ(omp_num_threads_count(" 2 "), 2);
  EXPECT_EQ(omp_num_threads_count("4,2"), 4);
  for (const char* bad : {"", "abc", "0", "-2", "2.5", "1e3", "4x"}) EXPECT_EQ(omp_num_threads_count(bad), 0) << bad;
  EXPECT_EQ(omp_num_threads_count(nullptr), 0);
  const SavedOmpNumThreads environment;
  const int saved = threads();
  setenv("OMP_NUM_THREADS", "abc", 1);
  ThreadRequest r = request_threads(0, 0);
  EXPECT_EQ(r.source, "tuned");
  EXPECT_NE(describe(r).find("warning: OMP_NUM_THREADS='abc' is not a thread count"), std::string::npos) << describe(r);
  r = request_threads(r.most + 1, 0);
  EXPECT_NE(describe(r).find("warning: " + std::to_string(r.most + 1) + " threads on " + std::to_string(r.most) + " CPUs"),
            std::string::npos)
      << describe(r);
  r = request_threads(1, 0);
  EXPECT_EQ(describe(r), "threads: 1 (--threads)");
  set_threads(saved);
}

// The set-up's count: the CPUs no other process runs on, from /proc/stat's procs_running (which counts
// this process's own running thread).
TEST(ThreadRequest, SetUpThreadsAreTheCpusOtherProcessesLeaveIdle) {
  const std::string quiet = "cpu  1 2 3\nctxt 5\nprocs_running 1\nprocs_blocked 0\n";
  const std::string one_busy = "cpu  1 2 3\nprocs_running 2\nprocs_blocked 0\n";
  const std::string crowded = "procs_running 9\n";
  int busy = -1;
  EXPECT_EQ(idle_cpus_from_proc_stat(quiet, 2, &busy), 2);
  EXPECT_EQ(busy, 0);
  EXPECT_EQ(idle_cpus_from_proc_stat(one_busy, 2, &busy), 1);
  EXPECT_EQ(busy, 1);
  EXPECT_EQ(idle_cpus_from_proc_stat(one_busy, 16, &busy), 15);
  EXPECT_EQ(idle_cpus_from_proc_stat(crowded, 4, &busy), 1);  // never fewer than one
  EXPECT_EQ(busy, 8);
  EXPECT_EQ(idle_cpus_from_proc_stat("no such line\n", 4), 4);  // unreadable: all of them
  const int here = idle_cpus(2);
  EXPECT_GE(here, 1);
  EXPECT_LE(here, 2);
}

}  // namespace
}  // namespace debris::exec
