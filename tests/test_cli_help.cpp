// Every executable's --help ends with an example command that works from the repository root: the input it
// names exists, and the quick one (debris_peridem's) runs to exit 0 as printed (with this build's executable
// and the output sent to a scratch directory); debris_dem's, the default input, is DemCliDefault's.
#include <gtest/gtest.h>

#include <filesystem>
#include <sstream>
#include <string>

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
  const struct {
    const char* exe;
    const char* program;
    bool run;
  } executables[] = {{DEBRIS_DEM_EXECUTABLE, "debris_dem", false},  // the default input: DemCliDefault runs it
                     {DEBRIS_PERIDEM_EXECUTABLE, "debris_peridem", true},
                     {DEBRIS_PATCH_EXECUTABLE, "debris_patch", false},
                     {DEBRIS_AMORPHOUS_EXECUTABLE, "debris_amorphous", false},
                     {DEBRIS_RESTITUTION_EXECUTABLE, "debris_restitution", false},
                     {DEBRIS_CALIBRATE_EXECUTABLE, "debris_calibrate", false}};
  for (const auto& x : executables) {
    SCOPED_TRACE(x.program);
    const Example e = example_of(x.exe, x.program);
    EXPECT_TRUE(fs::is_regular_file(root / e.input)) << e.input;
    if (!x.run) continue;
    const test::CommandResult r = test::run_command(
        "cd " + root.string() + " && " + x.exe, "-i " + e.input + " -o " + (scratch / x.program).string());
    EXPECT_EQ(r.exit_code, 0) << r.output;
    EXPECT_TRUE(fs::is_regular_file(scratch / x.program / "thermo.csv")) << r.output;
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
