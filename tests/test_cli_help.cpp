// Every executable's --help ends with an example command that works from the repository root: the input it
// names exists, and each runs as printed (with this build's executable and the output sent to a scratch
// directory): debris_peridem's to exit 0; the four that take about a minute, cut short after a while, must have
// started as they should (their first output) and not have stopped on an error. debris_dem's, the default
// input, is DemCliDefault's.
#include <gtest/gtest.h>

#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "core/comm/communicator.hpp"
#include "tests/cli_helpers.hpp"

namespace debris {
namespace {

namespace fs = std::filesystem;

struct Example {
  std::string program, input, output;
};

// The example line of `exe --help`: "  ./build/bin/<program> -i <input> -o <output>".
Example example_of(const std::string& exe, const std::string& program) {
  const test::CommandResult help = test::run_command(exe, "--help");
  EXPECT_EQ(help.exit_code, 0) << help.output;
  const std::string key = "Example, from the repository root";
  const std::size_t at = help.output.find(key);
  EXPECT_NE(at, std::string::npos) << help.output;
  if (at == std::string::npos) return {};
  const std::size_t line = help.output.find('\n', at) + 1;
  std::istringstream words(help.output.substr(line, help.output.find('\n', line) - line));
  std::string command, flag_i, flag_o;
  Example e;
  words >> command >> flag_i >> e.input >> flag_o >> e.output;
  e.program = fs::path(command).filename().string();
  EXPECT_EQ(command, "./build/bin/" + program) << help.output;
  EXPECT_EQ(flag_i, "-i");
  EXPECT_EQ(flag_o, "-o");
  // The help text ends with the example.
  EXPECT_EQ(help.output.find_first_not_of(" \n", help.output.find('\n', line)), std::string::npos) << help.output;
  return e;
}

TEST(CliHelp, EveryExecutableEndsWithAnExampleThatWorksFromTheRepositoryRoot) {
  const fs::path root = DEBRIS_SOURCE_DIR;
  const fs::path scratch = test::fresh_directory("debris_cli_help");
  // How each example runs: to the end, or cut short (`timeout`, exit 124) after `seconds`, long after the
  // first output a run of it prints within a second or two on an idle machine: its first lines, then a file
  // the run writes at its start (debris_restitution writes its table with the first case's result).
  const struct {
    const char* exe;
    const char* program;
    bool run;
    int seconds;  // 0: to the end
    std::vector<std::string> first_output;
    const char* written;
  } executables[] = {
      {DEBRIS_DEM_EXECUTABLE, "debris_dem", false, 0, {}, ""},  // the default input: DemCliDefault runs it
      {DEBRIS_PERIDEM_EXECUTABLE, "debris_peridem", true, 0, {"grains", "bonds"}, "thermo.csv"},
      {DEBRIS_PATCH_EXECUTABLE, "debris_patch", true, 20, {"12 case(s)", "case 1/12: elastic, hcp"}, "input.yaml"},
      {DEBRIS_AMORPHOUS_EXECUTABLE, "debris_amorphous", true, 20, {"=== sample d0_0.6_s_0: d0 = 0.6 d_c = 90"},
       "summary.csv"},
      {DEBRIS_RESTITUTION_EXECUTABLE, "debris_restitution", true, 20, {"case             (R1,R2)mm mat"}, ""},
      {DEBRIS_CALIBRATE_EXECUTABLE, "debris_calibrate", true, 20, {"calibrating for E 1, nu 0.15"},
       "calibration.csv"}};
  // All at once, in the background of one shell, each to its own log and exit status file.
  std::string all = "cd " + root.string() + " || exit 1;";
  for (const auto& x : executables) {
    SCOPED_TRACE(x.program);
    const Example e = example_of(x.exe, x.program);
    EXPECT_TRUE(fs::is_regular_file(root / e.input)) << e.input;
    if (!x.run) continue;
    const std::string limit = x.seconds > 0 ? "timeout " + std::to_string(x.seconds) + " " : "";
    const fs::path log = scratch / (std::string(x.program) + ".log");
    all += " { " + limit + x.exe + " -i " + e.input + " -o " + (scratch / x.program).string() + " > " +
           log.string() + " 2>&1; echo $? > " + log.string() + ".status; } &";
  }
  const test::CommandResult ran = test::run_command(all, "wait");
  ASSERT_EQ(ran.exit_code, 0) << ran.output;
  for (const auto& x : executables) {
    if (!x.run) continue;
    SCOPED_TRACE(x.program);
    const std::string output = test::slurp(scratch / (std::string(x.program) + ".log"));
    const int status = std::stoi(test::slurp(scratch / (std::string(x.program) + ".log.status")));
    if (x.seconds > 0)
      EXPECT_TRUE(status == 0 || status == 124) << "exit " << status << ":\n" << output;
    else
      EXPECT_EQ(status, 0) << output;
    for (const std::string& line : x.first_output) EXPECT_TRUE(test::contains(output, line)) << line << " in:\n" << output;
    EXPECT_FALSE(test::contains(output, "error:")) << output;
    if (*x.written) EXPECT_TRUE(fs::is_regular_file(scratch / x.program / x.written)) << output;
  }
}

// Started as several processes by a launcher (its environment says so), an executable that runs as one
// process (all six in a serial build) exits 2 before reading anything, the first process saying why.
TEST(CliProcesses, EveryExecutableOfASerialBuildRefusesManyProcesses) {
  if (comm::mpi_build()) GTEST_SKIP() << "an MPI build: tests/mpi runs debris_dem on ranks";
  for (const char* exe : {DEBRIS_DEM_EXECUTABLE, DEBRIS_PERIDEM_EXECUTABLE, DEBRIS_PATCH_EXECUTABLE,
                          DEBRIS_AMORPHOUS_EXECUTABLE, DEBRIS_RESTITUTION_EXECUTABLE, DEBRIS_CALIBRATE_EXECUTABLE}) {
    SCOPED_TRACE(exe);
    const test::CommandResult first =
        test::run_command("OMPI_COMM_WORLD_SIZE=3 OMPI_COMM_WORLD_RANK=0 " + std::string(exe), "-i no_such_input.yaml");
    EXPECT_EQ(first.exit_code, 2) << first.output;
    EXPECT_NE(first.output.find("'mpirun -np' = 3"), std::string::npos) << first.output;
    EXPECT_NE(first.output.find("built without MPI"), std::string::npos) << first.output;
    const test::CommandResult other =
        test::run_command("SLURM_NTASKS=3 SLURM_PROCID=2 " + std::string(exe), "-i no_such_input.yaml");
    EXPECT_EQ(other.exit_code, 2) << other.output;
    EXPECT_EQ(other.output, "") << "only the first process explains";
  }
}

}  // namespace
}  // namespace debris
