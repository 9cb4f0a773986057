#pragma once
// The executables' pictures are gnuplot scripts they write and then draw when gnuplot is installed
// (Debian: gnuplot-nox); without it the scripts stay for later. One way to find it and run it, for all.
#include <string>

namespace debris {

struct GnuplotRun {
  bool found = false;  // gnuplot is on the PATH
  int status = 0;      // its exit status (std::system's) when found; 0 = drawn
};

/// Runs `gnuplot <script>` in `dir`, its output into `dir/<log>`.
GnuplotRun run_gnuplot(const std::string& dir, const std::string& script, const std::string& log);

}  // namespace debris
