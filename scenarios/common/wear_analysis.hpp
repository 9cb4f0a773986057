#pragma once
// The wear analysis of a sheared junction (paper A, section 4): did the junction deform plastically and
// stay part of the surfaces (ductile), or break off and roll between them as a third body (a rolling wear
// particle)? The paper decides by looking at pictures; this decides with numbers, sampled during the run.
//
// Bonds, not ranges. Under a normal load every particle is within interaction range (r_i + r_j + delta_f)
// of a neighbour, so clusters by range alone join both walls, both bodies and the junction into one. A
// cohesive solid keeps its bonds, though, while a rolling body's contacts with the surfaces come and go: a
// pair at a rolling contact stays in range only while the body turns through the contact's width w,
// w / (v/2) for a wall speed v (about 1.2 ns for w = 6 nm at 10 m/s). So a pair is *bonded* once it has
// been within range at every sample for `persistence` (longer than that), and clusters are the connected
// components of the bonded pairs. The walls' clusters hold the walls' members; a *third body* is a cluster
// holding no wall member, and the candidate wear particle is the one holding most of the junction's volume.
// How long is long enough: the longest-lived contact that is not a bond is one between two of the largest
// particles (diameter d_l) rolling or sliding over each other under load, which stays in range over a
// relative travel of 2 sqrt(2 d_l delta_f + delta_f^2) (6.2 nm for d_l = 7.5 nm, delta_f = 0.62 nm), at v/2
// for a body rolling on a surface: 1.2 ns at 10 m/s. Twice that is safe.
//
// Kinematics without thermal noise. Instantaneous velocities are dominated by vibration (about 25 m/s for
// 3 nm silica particles, more than the wall speed), but a displacement over the sampling interval (many
// vibration periods) is not: the centre velocity and the spin of the candidate come from a least-squares
// rigid-body fit of its members' displacements between two samples, Delta r_i = Delta c + theta x (r_i - c),
// whose residual says how rigid it moved. They are averaged over the last `window` of samples.
//
// The verdict, from stated thresholds (input settings, not tuned per case):
//   rolling wear particle: a third body holding at least `min_volume_fraction` of the junction's volume,
//     whose centre moves at `centre_speed` (a fraction of the wall speed; a body rolling without slip
//     between a fixed and a moving surface moves at 1/2), with a rolling number 2 R omega / v in
//     `rolling_number` (1 for rolling without slip; R is half its height along the normal), and a rigid-fit
//     residual below `max_residual` (rms, as a fraction of the wall's displacement in the interval);
//   detached, not rolling: such a third body whose kinematics miss those bounds;
//   ductile: no such third body (the junction stays bonded to the surfaces).
// omega is the spin about n x s (normal x sliding direction), positive when the body rolls with the wall.
#include <cstdint>
#include <deque>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "core/vec3.hpp"

namespace debris {

class DemSimulation;
class InputNode;

struct WearSettings {
  long every = 0;                 // steps between samples; 0 = no analysis
  std::string bottom_wall, top_wall;  // group names
  std::string junction_label;     // the label of the junction's particles (its volume is the reference)
  int sliding_axis = 0, normal_axis = 1;
  double persistence = 0;         // s: a pair is bonded after staying in range this long
  double window = 0;              // s: kinematics averaged over the samples of this last stretch
  double min_volume_fraction = 0.25;
  double centre_speed_min = 0.25, centre_speed_max = 0.75;
  double rolling_number_min = 0.5, rolling_number_max = 1.5;
  double max_residual = 0.3;
};

/// Reads the `wear:` section of a debris_dem input (InputError naming the key for anything bad).
WearSettings read_wear_settings(const InputNode& node);

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
  // The largest third body (zeros when there is none).
  long third_particles = 0;
  double third_volume = 0;       // the junction's volume it holds, over the junction's volume
  double third_from_junction = 0;  // share of its volume that started in the junction
  double centre_speed = 0;       // of its centre along the sliding axis, over the wall speed
  double spin = 0;               // rad/s about n x s
  double rolling_number = 0;     // 2 R spin / v
  double residual = 0;           // rigid-fit rms residual over the wall's displacement in the interval
  bool kinematics = false;       // a fit was made (the body existed at the previous sample)
  // Averages over the window, and the verdict at this sample.
  double mean_centre_speed = 0, mean_rolling_number = 0, mean_residual = 0;
  WearVerdict verdict = WearVerdict::ductile;
};

class WearAnalysis {
 public:
  /// `settings` with their names resolved on `sim` (InputError for an unknown group or label). The
  /// junction is the particles labelled settings.junction_label now (Particles::label_names).
  WearAnalysis(const WearSettings& settings, const DemSimulation& sim);

  /// Samples the current state (call every settings.every steps).
  const WearSample& sample(const DemSimulation& sim);
  const std::vector<WearSample>& samples() const { return samples_; }

  static std::vector<std::string> columns();
  static std::vector<double> row(const WearSample& s);

  /// The verdict of the run so far and a paragraph explaining it with its numbers.
  WearVerdict verdict() const;
  std::string report() const;
  /// First sample of the final unbroken stretch with a third body of sufficient volume (-1: none).
  long detection_index() const;

 private:
  WearSettings s_;
  int bottom_ = -1, top_ = -1;
  double wall_speed_ = 0;  // the top wall's prescribed speed along the sliding axis
  double junction_volume_ = 0;
  std::unordered_set<std::int64_t> junction_ids_;
  std::unordered_map<std::uint64_t, long> streak_;  // pair (ids) -> step since which it is in range
  std::unordered_map<std::int64_t, Vec3> previous_;  // unwrapped position by id at the last sample
  double previous_time_ = 0;
  std::vector<WearSample> samples_;
};

}  // namespace debris
