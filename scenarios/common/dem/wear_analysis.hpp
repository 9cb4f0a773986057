#pragma once
// The wear analysis of a sheared junction (paper A, section 4): did the junction deform plastically and
// stay part of the surfaces (ductile), or break off and roll between them as a third body (a rolling wear
// particle)? The paper decides by looking at pictures; this decides with numbers, sampled during the run.
//
// Motion, not range. Under a normal load every particle is within interaction range (r_i + r_j +
// delta_f) of a neighbour, so clusters by range alone join both walls, both bodies and the junction into
// one. Nor does persistence of range tell bonds from contacts well enough: two of the largest particles
// (7.5 nm) rolling over each other under load stay in range over ~6 nm of travel, and particles trapped
// between the surfaces stick and slip, so range-persistent chains were seen to join the two walls of a
// junction that had plainly been sheared through. What does tell is motion over a window W (`window`,
// many vibration periods, so free of thermal noise, which is ~25 m/s for 3 nm particles): each particle's
// displacement along the sliding axis as a fraction f of the top wall's (relative to the bottom wall's).
// A particle of either body has f near 0 or 1; a body rolling between them has f from 0 at its bottom to
// 1 at its top, its centre at 1/2; a sheared (ductile) junction has f spread over a layer that spans the box.
// The particles with f_min < f < f_max (`moving`), joined through pairs in range, form candidate bodies; the
// one holding most of the junction's volume is fitted by a rigid motion over W (rotation and translation,
// Kabsch, exact for any angle).
//
// The verdict, from stated thresholds (input settings, not tuned per case):
//   rolling wear particle: a candidate holding at least `min_volume_fraction` of the junction's volume that
//     moves rigidly (rms residual of the fit below `max_residual` of the spread of its displacements about
//     its centre's, or of a quarter of the walls' relative displacement if larger: a rigid body gives ~0, a
//     sheared layer ~0.7, its strain being what no rotation fits), whose centre moves at `centre_speed` (a fraction of the wall's
//     relative speed; rolling without slip: 1/2), with a rolling number 2 R omega / v in `rolling_number`
//     (1 for rolling without slip; 2R is its height, the extent of the particles kept over f_max - f_min,
//     since f grows linearly across a rolling body's height);
//   detached, not rolling: such a rigid candidate whose centre speed or spin miss those bounds;
//   ductile: no rigid candidate holding enough of the junction.
// omega is the spin about n x s (normal x sliding direction), positive when the body rolls with the wall.
//
// Each sample's own fit gives its `sample_verdict`; the verdict of the run at a sample is decided over the
// last `verdict_span` (default half the window): a rigid candidate holding enough of the junction at every
// sample of the span, judged on the span's means of residual, centre speed and rolling number. One sample's
// fit never decides alone: the rolling junctions' windows sit within 0.02-0.2 of a threshold.
//
// The analysis's state (the samples so far, the positions of the window, the pairs' range streaks) goes
// into every checkpoint (state() / restore()), so a restarted run writes the wear.csv of the run in one piece.
//
// Also reported, as diagnostics: clusters of range-persistent pairs ("bonds": in range at every sample for
// `persistence`), which hold each wall and where the junction's volume is bonded.
#include <cstdint>
#include <deque>
#include <optional>
#include <string>
#include <utility>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "core/io/key_reference.hpp"
#include "core/vec3.hpp"

namespace debris {

class DemSimulation;
class InputNode;
namespace h5 {
class Location;
}

struct WearSettings {
  long every = 0;                 // steps between samples; 0 = no analysis
  std::string bottom_wall, top_wall;  // group names
  std::string junction_label;     // the label of the junction's particles (its volume is the reference)
  int sliding_axis = 0, normal_axis = 1;
  double persistence = 0;         // s: a pair is bonded after staying in range this long
  double window = 0;              // s: displacements over this last stretch carry the kinematics
  double moving_min = 0.1, moving_max = 0.9;  // f range of particles moving with neither wall
  double min_volume_fraction = 0.25;
  double centre_speed_min = 0.25, centre_speed_max = 0.75;
  double rolling_number_min = 0.5, rolling_number_max = 1.5;
  double max_residual = 0.3;
  // The fit's scale is at least this fraction of the walls' relative displacement over the window (a body
  // translating without spin has no displacement spread to scale by).
  double residual_floor = 0.25;
  double verdict_span = -1;       // s: the run's verdict holds over this last stretch; < 0: window / 2
};

/// Reads the `wear:` section of a debris_dem input (InputError naming the key for anything bad).
WearSettings read_wear_settings(const InputNode& node);
/// Describes the keys read_wear_settings() reads, as the section `wear` of `ref`.
void document_wear_settings(KeyReference& ref);

enum class WearVerdict : int { ductile = 0, detached = 1, rolling = 2 };
const char* verdict_name(WearVerdict v);

/// One sample: the wear.csv row.
struct WearSample {
  long step = 0;
  double time = 0;
  double wall_force = 0;         // top wall's reaction along the sliding axis (the tangential force)
  double wall_slide = 0;         // top wall's displacement along the sliding axis
  double wall_normal = 0;        // ... along the normal axis
  long bonded_pairs = 0;
  bool walls_joined = false;     // one cluster holds both walls (the junction still bonds them)
  double junction_in_bottom = 0, junction_in_top = 0, junction_in_third = 0;  // shares of its volume
  // The candidate third body over the window (zeros when there is none).
  long third_particles = 0;
  double third_volume = 0;       // the junction's volume it holds, over the junction's volume
  double third_from_junction = 0;  // share of its volume that started in the junction
  double centre_speed = 0;       // its centre's displacement along the sliding axis, over the wall's
  double spin = 0;               // rad/s about n x s
  double rolling_number = 0;     // 2 R spin / v
  double residual = 0;           // rigid-fit rms residual over the wall's displacement in the interval
  bool kinematics = false;       // a fit was made (the body existed at the previous sample)
  WearVerdict sample_verdict = WearVerdict::ductile;  // from this sample's fit alone
  // Means over the samples of the last verdict_span (zeros unless each has a candidate holding enough of
  // the junction), and the verdict they give.
  double mean_centre_speed = 0, mean_rolling_number = 0, mean_residual = 0;
  WearVerdict verdict = WearVerdict::ductile;
};

/// What the analysis carries from sample to sample, as plain arrays for a checkpoint (pairs and positions
/// in id order, so the arrays do not depend on storage order).
struct WearState {
  std::vector<std::int64_t> streak_a, streak_b, streak_since;  // pair (ids a < b) in range since step
  std::vector<double> history_time;                            // the window's snapshots, oldest first
  std::vector<std::int64_t> history_count, history_id;         // particles per snapshot; their ids
  std::vector<double> history_position;                        // 3 per id
  std::vector<double> samples;                                 // sample_values() per sample
  std::size_t sample_count = 0;
};

class WearAnalysis {
 public:
  /// `settings` with their names resolved on `sim` (InputError for an unknown group or label). The
  /// junction is the particles labelled settings.junction_label now (Particles::label_names).
  WearAnalysis(const WearSettings& settings, const DemSimulation& sim);

  /// Samples the current state (call every settings.every steps).
  const WearSample& sample(const DemSimulation& sim);
  const std::vector<WearSample>& samples() const { return samples_; }

  /// wear.csv's columns with their units and meanings; the header is its names.
  static const ColumnTable& table();
  static std::vector<std::string> columns() { return table().header(); }
  static std::vector<double> row(const WearSample& s);

  /// The state to continue from (checkpoints), and back. restore() checks what it is given (InputError
  /// naming the checkpoint `path` for arrays that do not fit together).
  WearState state() const;
  void restore(const WearState& state, const std::string& path);

  /// The verdict of the run so far and a paragraph explaining it with its numbers.
  WearVerdict verdict() const;
  std::string report() const;
  /// First sample of the final unbroken stretch with a rigid third body (rolling or not; -1: none).
  long detection_index() const;

 private:
  WearSettings s_;
  int bottom_ = -1, top_ = -1;
  double wall_speed_ = 0;  // the top wall's prescribed speed along the sliding axis
  double junction_volume_ = 0;
  std::unordered_set<std::int64_t> junction_ids_;
  std::unordered_map<std::uint64_t, long> streak_;  // pair (ids) -> step since which it is in range
  // Unwrapped positions by id at the samples of the last window (the oldest is the reference).
  std::deque<std::pair<double, std::unordered_map<std::int64_t, Vec3>>> history_;
  std::vector<WearSample> samples_;
};

/// The state as the group `wear` under `at` (a checkpoint's `run` group), and back (nullopt: none there).
void write_wear_state(h5::Location& at, const WearState& state);
std::optional<WearState> read_wear_state(const h5::Location& at);

}  // namespace debris
