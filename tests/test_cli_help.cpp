// Every executable's --help ends with an example command that works from the repository root: the input it
// names exists, and the quick one (debris_peridem's) runs to exit 0 as printed (with this build's executable
// and the output sent to a scratch directory); debris_dem's, the default input, is DemCliDefault's.
#include <gtest/gtest.h>

#include <filesystem>
#include <sstream>
#include <string>

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
                     {DEBRIS_RESTITUTION_EXECUTABLE, "debris_restitution", false}};
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

}  // namespace
}  // namespace debris
