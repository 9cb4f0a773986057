#pragma once
// The debris_patch input file: which patch tests to run, on which samples, with which material, and the
// sweeps (lists of tests, orientations or data files, Poisson ratios, scalings s, diameters d0) expanded
// into one case per combination, run one after the other.
#include <string>
#include <vector>

#include "scenarios/common/dem/amorphous_sample.hpp"
#include "scenarios/patch/patch_test.hpp"

namespace debris {

class AmorphousSampleCache;

/// One run: a test on one sample with one material.
struct PatchCase {
  int index = 0;  // 1-based, in run order
  PatchTest test = PatchTest::elastic;
  CohesiveMaterial material;    // target properties (nu and s of this case)
  bool lattice = true;          // HCP lattice (true) or a LAMMPS data file
  HcpSampleSpec hcp;            // lattice: d0 (absolute), orientation, sizes
  double d0_over_dc = 0;        // lattice: as given in the input
  std::string data_file;        // data file: its path (relative paths resolved against the input file)
  double wall_thickness = 1.5;  // data file, amorphous: in mean diameters (lattice: hcp.wall_thickness)
  // Amorphous samples (kind: amorphous): made by the section 3.2 recipe (or loaded from the cache), then
  // walled like a data file. d0_over_dc holds the mode d0.
  bool amorphous = false;
  AmorphousSpec amorphous_spec;  // this case's material, d0, box (width raised to the engine's minimum)
  std::string amorphous_label;   // "amorphous", or with the system size and d_l of the discretisation study
  double system_size = 0;        // discretisation study: L in units of d_c (0: not part of one)
  std::string width_note;        // why the width differs from the input's, or empty

  /// "hcp c=y", the data file's name or the amorphous label, for tables and plot legends.
  std::string sample_label() const;
};

struct PatchConfig {
  std::vector<PatchCase> cases;
  ElasticSettings elastic;
  StrengthSettings strength;
  std::string output_directory = "out/patch";
  std::string cache_directory;  // amorphous samples; empty: <output_directory>/samples
  bool plots = true;
  double progress_seconds = 10;
  int threads = 0;  // 0: OpenMP default
};

/// Reads and checks the whole input (InputError naming the key and value for anything missing, malformed,
/// out of range or unknown). Samples are built later, by make_case_sample.
PatchConfig read_patch_input_text(const std::string& text, const std::string& name, const std::string& base_directory);
PatchConfig read_patch_input(const std::string& path);

/// Builds the sample of a case (reads its data file; amorphous: takes it from `cache`, which makes it when
/// needed, and which must then be given). InputError for a bad sample (d0 below d_min, ...); PatchRunError
/// for an amorphous sample whose relaxation failed (the message names the setting).
PatchSample make_case_sample(const PatchCase& c, AmorphousSampleCache* cache = nullptr);

/// The checks of a case's sample that cost no simulation: for an amorphous case the spec and the insertion
/// (a volume fraction the box cannot reach); otherwise the whole sample is built. InputError when bad.
void check_case_sample(const PatchCase& c);

}  // namespace debris
