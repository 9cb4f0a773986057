#pragma once
// Helpers of the tests that run the real executables: a command's exit status and output, and a fresh
// scratch directory under GoogleTest's temp dir.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <string>

namespace debris::test {

struct CommandResult {
  int exit_code;       // -1 when the command did not exit normally
  std::string output;  // stdout and stderr
};

/// Runs `executable args` through the shell with stderr folded into stdout.
inline CommandResult run_command(const std::string& executable, const std::string& args) {
  const std::string cmd = executable + " " + args + " 2>&1";
  FILE* pipe = popen(cmd.c_str(), "r");
  std::string out;
  std::array<char, 4096> buf{};
  while (pipe && fgets(buf.data(), buf.size(), pipe)) out += buf.data();
  const int status = pipe ? pclose(pipe) : -1;
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}

/// An empty directory `<temp>/<name>`, removed first if a previous run left it.
inline std::filesystem::path fresh_directory(const std::string& name) {
  const std::filesystem::path d = std::filesystem::path(::testing::TempDir()) / name;
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  return d;
}

}  // namespace debris::test
