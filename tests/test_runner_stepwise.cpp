// The runner driven step by step (scenarios/common/run/runner.hpp, Run), as a driver other than the
// executables does it: a run advanced in uneven chunks (1, 2, 3, ... steps) writes the thermo.csv of the
// executable's run in one go byte for byte, and a checkpoint of the same size, for both models; and a run
// cannot be finished before its last step.
#include <gtest/gtest.h>

#include <filesystem>
#include <functional>
#include <stdexcept>
#include <string>

#include "scenarios/common/dem/dem_run.hpp"
#include "scenarios/common/peridem/peridem_run.hpp"
#include "tests/cli_helpers.hpp"

namespace debris {
namespace {

namespace fs = std::filesystem;
const std::string kSource = DEBRIS_SOURCE_DIR;

/// Runs `input` through Run in chunks of 1, 2, 3, ... steps into `out`; returns the last status.
int run_in_chunks(const std::function<RunPlan(const RunOptions&)>& prepare, const std::string& input,
                  const std::string& out) {
  RunOptions opt;
  opt.input = input;
  opt.output = out;
  opt.threads = 1;
  Run run(prepare(opt), "stepwise", opt, WallClock::now());
  if (const int status = run.start(); status != 0) return status;
  EXPECT_THROW(run.finish(), std::logic_error);  // not done yet
  for (long chunk = 1; !run.done(); ++chunk)
    if (const int status = run.advance(chunk); status != 0) return status;
  EXPECT_EQ(run.model().step_count(), run.last_step());
  return run.finish();
}

/// The executable's run of `input` and Run's in chunks, each into its own folder of `d`: the same thermo.csv.
void expect_chunks_equal_executable(const std::string& executable,
                                    const std::function<RunPlan(const RunOptions&)>& prepare,
                                    const std::string& input, const fs::path& d) {
  const test::CommandResult exe =
      test::run_command(executable, "-i " + input + " -o " + (d / "exe").string() + " --threads 1");
  ASSERT_EQ(exe.exit_code, 0) << exe.output;
  ASSERT_EQ(run_in_chunks(prepare, input, (d / "chunks").string()), 0);
  const std::string thermo = test::slurp(d / "exe" / "thermo.csv");
  EXPECT_FALSE(thermo.empty());
  EXPECT_EQ(test::slurp(d / "chunks" / "thermo.csv"), thermo);
  EXPECT_EQ(test::slurp(d / "chunks" / "checkpoint.h5").size(), test::slurp(d / "exe" / "checkpoint.h5").size());
}

TEST(RunnerStepwise, DemRunInChunksEqualsTheExecutablesRun) {
  const fs::path d = test::fresh_directory("debris_runner_stepwise_dem");
  std::string text = test::slurp(fs::path(kSource) / "scenarios/dem/hcp_wall_load.yaml");
  text = test::replace(test::replace(text, "steps: 4000", "steps: 300"), "thermo_every: 200", "thermo_every: 20");
  ASSERT_NE(text.find("steps: 300"), std::string::npos);
  ASSERT_NE(text.find("thermo_every: 20\n"), std::string::npos);
  expect_chunks_equal_executable(DEBRIS_DEM_EXECUTABLE, prepare_dem_run, test::write_text_file(d, "dem.yaml", text), d);
}

TEST(RunnerStepwise, PeridemRunInChunksEqualsTheExecutablesRun) {
  const fs::path d = test::fresh_directory("debris_runner_stepwise_peridem");
  std::string text = test::slurp(fs::path(kSource) / "scenarios/peridem/compressive_small.yaml");
  for (std::size_t at = text.find("file: data/"); at != std::string::npos; at = text.find("file: data/", at + 1))
    text.replace(at, 11, "file: " + kSource + "/scenarios/peridem/data/");
  text = test::replace(test::replace(text, "steps: 20000", "steps: 300"), "thermo_every: 200", "thermo_every: 20");
  ASSERT_NE(text.find("steps: 300"), std::string::npos);
  expect_chunks_equal_executable(DEBRIS_PERIDEM_EXECUTABLE, prepare_peridem_run,
                                 test::write_text_file(d, "peridem.yaml", text), d);
}

}  // namespace
}  // namespace debris
