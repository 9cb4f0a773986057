#pragma once
// What debris_patch writes: one CSV row per case, the stress-strain curve of each strength test, and gnuplot
// scripts (with their data inline, so they can be edited and re-run) drawing the results next to the
// paper's targets: E and nu against the target nu (Figs A.4, A.5), strengths against d0 / d_c with eq 20
// (Figs 5, 6), and the stress-strain curves (Fig 4).
#include <fstream>
#include <string>
#include <vector>

#include "scenarios/patch/patch_input.hpp"

namespace debris {

struct PatchCaseResult {
  PatchCase c;
  std::string description;  // the sample, in words
  long particles = 0, deformable = 0;
  Vec3 size_over_d0{};
  double d0 = 0;               // lattice: the spacing; data file: the mean diameter; amorphous: the mode d0
  double volume_fraction = 0;  // of the periodic sample (lattice: pi / (3 sqrt 2))
  bool ok = false;
  std::string error;  // why the case has no result
  ElasticResult elastic;
  StrengthResult strength;
  double target = 0;       // target strength (eq 20)
  std::string curve_file;  // strength tests: the stress-strain CSV, relative to the output directory
};

/// The header line of cases.csv (no line break).
std::string patch_cases_header();
/// What the sample column of cases.csv says of a case: "hcp", the amorphous label or the data file.
std::string patch_case_sample(const PatchCase& c);

/// The table of cases, one row written (and flushed) per finished case.
class PatchCasesCsv {
 public:
  /// Writes the header, then `kept_rows` (lines of an earlier run that --resume keeps), to a fresh file.
  explicit PatchCasesCsv(const std::string& path, const std::vector<std::string>& kept_rows = {});
  void write(const PatchCaseResult& r);

 private:
  std::ofstream out_;
};

/// The columns of a strength test's stress-strain CSV (write_curve_csv), in order.
const std::vector<std::string>& patch_curve_columns();
/// Writes the stress-strain curve of a strength test as CSV.
void write_curve_csv(const std::string& path, const StrengthResult& r);

/// Writes plots.gp into `dir` and, when gnuplot is on the PATH, runs it there to draw the PNGs. Returns a
/// line for the terminal: what was drawn, or that the plots were skipped and why.
std::string write_plots(const std::string& dir, const std::vector<PatchCaseResult>& results);

}  // namespace debris
