#pragma once
// The debris_patch input file: which patch tests to run, on which samples, with which material, and the
// sweeps (lists of tests, orientations or data files, Poisson ratios, scalings s, diameters d0) expanded
// into one case per combination, run one after the other.
#include <string>
#include <vector>

#include "scenarios/common/patch_test.hpp"

namespace debris {

/// One run: a test on one sample with one material.
struct PatchCase {
  int index = 0;  // 1-based, in run order
  PatchTest test = PatchTest::elastic;
  CohesiveMaterial material;    // target properties (nu and s of this case)
  bool lattice = true;          // HCP lattice (true) or a LAMMPS data file
  HcpSampleSpec hcp;            // lattice: d0 (absolute), orientation, sizes
  double d0_over_dc = 0;        // lattice: as given in the input
  std::string data_file;        // data file: its path (relative paths resolved against the input file)
  double wall_thickness = 1.5;  // data file: in mean diameters (lattice: hcp.wall_thickness)

  /// "hcp c=y" or the data file's name, for tables and plot legends.
  std::string sample_label() const;
};

struct PatchConfig {
  std::vector<PatchCase> cases;
  ElasticSettings elastic;
  StrengthSettings strength;
  std::string output_directory = "out/patch";
  bool plots = true;
  double progress_seconds = 10;
  int threads = 0;  // 0: OpenMP default
};

/// Reads and checks the whole input (InputError naming the key and value for anything missing, malformed,
/// out of range or unknown). Samples are built later, by make_case_sample.
PatchConfig read_patch_input_text(const std::string& text, const std::string& name, const std::string& base_directory);
PatchConfig read_patch_input(const std::string& path);

/// Builds the sample of a case (reads its data file). InputError for a bad sample (d0 below d_min, ...).
PatchSample make_case_sample(const PatchCase& c);

}  // namespace debris
