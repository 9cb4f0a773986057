#include "scenarios/common/run/gnuplot.hpp"

#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <system_error>

namespace debris {

namespace {

namespace fs = std::filesystem;

std::string find_gnuplot() {
  const char* path = std::getenv("PATH");
  if (!path) return {};
  std::stringstream ss(path);
  std::string dir;
  while (std::getline(ss, dir, ':')) {
    if (dir.empty()) continue;
    const fs::path p = fs::path(dir) / "gnuplot";
    std::error_code ec;
    if (fs::exists(p, ec) && !fs::is_directory(p, ec)) return p.string();
  }
  return {};
}

std::string shell_quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

}  // namespace

GnuplotRun run_gnuplot(const std::string& dir, const std::string& script, const std::string& log) {
  const std::string gnuplot = find_gnuplot();
  if (gnuplot.empty()) return {};
  const std::string cmd =
      "cd " + shell_quote(dir) + " && " + shell_quote(gnuplot) + " " + shell_quote(script) + " > " + shell_quote(log) + " 2>&1";
  return {true, std::system(cmd.c_str())};
}

}  // namespace debris
