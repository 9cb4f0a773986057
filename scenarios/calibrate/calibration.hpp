#pragma once
// Calibration of the cohesive DEM's material inputs from the properties a user wants.
//
// Paper A's eqs 7-16 turn E, nu, sigma_{m,N}, sigma_{m,T} and gamma into pair parameters, but an amorphous
// sample measures E, nu and the strengths off their inputs (the paper's section 3.2 finds tension at ~50%,
// shear at ~56%; scenarios/patch/RESULTS.md) and section 3.4 leaves the correction to the user. Here it is
// done with the patch tests debris has (elastic, tension, shear on a relaxed sample), in three ideas:
//
//  1. Dimensional analysis makes E exact. With d0 and the density fixed, the recipe and the tests have no
//     scale of stress but E: inputs (lambda E, nu, lambda sigma_N, lambda sigma_T, lambda gamma) relax to the
//     same packing (d_c = 4 gamma E / sigma_N^2 and delta_e / d = sigma_N / E do not change; time scales as
//     lambda^-1/2) and measure lambda times every stress. So the loop works on the ratios to E (nu,
//     sigma_N / E, sigma_T / E, gamma / E) at the target's E, and one multiplication at the end puts E on
//     target. The elastic test's load is a fixed fraction of the inputs' E (paper: 0.01 with E = 1) so that
//     it scales too. Measured: a Table 4 sample at lambda = 0.83, 1.1 and 2 gives the same four ratios to 4
//     digits.
//  2. Each remaining target has one input that moves it most: nu_in moves nu (slope near 1), sigma_T moves
//     the shear strength (it caps every tangential force, eq 11), and one input moves the tensile strength:
//     sigma_N (delta_e, eq 9), or the surface energy gamma where s > 0 and every pair of the sample is past
//     d_c, because there delta_f = sqrt(4 gamma (r_i + r_j) / E) (eq 10 with s = 1/2) caps the pair force
//     before delta_e and sigma_N drops out. Each moves by its own secant step (in logarithms for the
//     strengths); a target already within its tolerance keeps its input.
//  3. The reachable set has an edge. Raising the tension input lengthens the attraction (delta_e or delta_f
//     over d); past some reach the relaxed packing pulls itself in without end (a Table 4 sample at
//     d0 = 0.6 d_c collapses at sigma_N / E = 0.32; it relaxes at 0.31). The relaxation stops such a sample
//     (AmorphousSpec::collapse_fraction) and the loop bisects between the largest input that made a sample
//     and the smallest that collapsed; a target past the edge is answered with the largest tensile strength
//     a sample reached and the input that limits it. nu has an edge too: the input stops at 0.25 (eq 16).
//
// Only sigma_T changing keeps the relaxed sample (the relaxation has no tangential force) and the elastic
// test (the tangential cap is far from the elastic test's 1% strain): then only tension and shear rerun.
#include <array>
#include <functional>
#include <string>
#include <vector>

#include "kernels/dem/cohesive_material.hpp"
#include "scenarios/common/dem/amorphous_sample.hpp"
#include "scenarios/patch/patch_test.hpp"

namespace debris {

struct CalibrationSpec {
  // The targets: E, nu, tensile and shear strength. Surface energy, restitution, density and s are the
  // user's; gamma / E is kept as the target's unless gamma is the tension input.
  CohesiveMaterial target = table4_material();
  double d0 = 0;  // mode diameter of the sample, in the material's length units
  // The sample recipe (size in d0, size distribution, volume fraction, seed, relaxation); its material and
  // d0 are set by each evaluation.
  AmorphousSpec sample;
  double wall_thickness = 1.5;  // in d0, each wall of the patch tests
  double elastic_load = 0.01;   // the elastic test's compressive stress over the inputs' E (section 3)
  ElasticSettings elastic;      // its stress is elastic_load E_in in every evaluation
  StrengthSettings strength;
  // Accuracy wanted: relative for E and the strengths, absolute for nu (by default 2%, 0.01, 3%).
  double tolerance_E = 0.02, tolerance_nu = 0.01, tolerance_strength = 0.03;
  int max_runs = 20;  // patch runs in all (an evaluation is up to three: elastic, tension, shear)

  /// InputError naming the key ("target.poisson_ratio", "sample.d0", "calibration.max_runs", ...) for a
  /// target or setting no calibration can meet: nu outside [0, 0.25) (the pair law's input stops at 0.25,
  /// eq 16), a strength, modulus, surface energy, density or d0 that is not positive, fewer than three runs.
  void validate() const;
};

/// Which input moves the tensile strength for this spec (idea 2 of the header).
enum class TensionInput { tensile_strength, surface_energy };
TensionInput tension_input(const CalibrationSpec& spec);
const char* tension_input_key(TensionInput t);  // "tensile_strength" or "surface_energy"

/// What one sample of given inputs measures.
struct CalibrationMeasure {
  double youngs_modulus = 0, poisson_ratio = 0, tensile_strength = 0, shear_strength = 0;
  StrengthOutcome tension = StrengthOutcome::max_strain, shear = StrengthOutcome::max_strain;
  long particles = 0;
  double relaxed_fraction = 0;
  double seconds = 0;  // relaxation (when one ran) and the tests
};

/// Relaxes the sample of `spec` with `inputs` (seed: spec.sample.seed) and runs the three tests.
/// SampleCollapse when the relaxation pulls the packing in without end, RelaxationStalled when it does not
/// come to rest within relaxation.phase2.max_steps.
CalibrationMeasure measure_sample(const CalibrationSpec& spec, const CohesiveMaterial& inputs);

struct CalibrationStep {
  CohesiveMaterial inputs;     // what was run (at the target's E while the ratios are found)
  CalibrationMeasure measured;
  int runs = 0;                // patch runs so far, this step's included
  int runs_this_step = 0;      // 0 when the sample collapsed, 2 when only sigma_T changed, else 3
  bool collapsed = false;
  bool stalled = false;        // the relaxation did not come to rest within relaxation.phase2.max_steps
};

struct CalibrationResult {
  CohesiveMaterial inputs;      // the calibrated inputs (E scaled onto the target)
  CalibrationMeasure expected;  // what they measure: the last step's measures when converged, else by idea 1
  // True when `expected` was measured on `inputs` themselves; false when it is a step's measures scaled
  // onto the target's E by idea 1, inputs that no run has tried.
  bool expected_measured = false;
  std::vector<CalibrationStep> steps;
  int runs = 0;
  bool converged = false;
  // When not converged: which target is out of reach or was not met and what limits it, or, when the
  // answer meets every target by idea 1 alone, that the run confirming it did not fit in max_runs.
  std::string why;
  TensionInput tension_input = TensionInput::tensile_strength;
};

/// Finds the inputs (validate() first). Stops when every target is within its tolerance, when max_runs
/// patch runs are spent, when a target is out of reach (`why` names the closest reachable value and
/// the input that limits it), or when a sample does not relax (`why` names the target whose input the
/// step moved). `report` (may be empty) is called after each step.
CalibrationResult calibrate(const CalibrationSpec& spec,
                            const std::function<void(const CalibrationStep&)>& report = {});

/// The four errors of `m` against the targets: relative for E and the strengths, absolute for nu.
std::array<double, 4> calibration_errors(const CohesiveMaterial& target, const CalibrationMeasure& m);

}  // namespace debris
