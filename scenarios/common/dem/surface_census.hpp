#pragma once
// The wear census of a sliding interface (the `surfaces:` section of a debris_dem input): two bodies, each
// with a driven group, slide on each other; every `every` steps the census says where every particle moves,
// what has worn off, and what the interface carries. Unlike the junction's verdict (wear_analysis.hpp), it
// judges no mechanism: it counts.
//
// Which body a particle moves with (its state). Over the last `window` of the run (before the window has
// filled: since the first sample, the oldest position kept), each particle's displacement along the sliding
// axis, less the bottom driven group's, over the top driven group's less the bottom's, is its fraction f:
// f < moving_min moves with the bottom body, f > moving_max with the top body, and in between with neither,
// the third body. f needs the driven groups to have slid relative to each other: while they slid less than
// `min_slide` over that interval (a settling stage, the first sample) every particle keeps its last state.
// A particle starts in the body whose labels (or group) hold it, the driven group's members in their
// body's; a particle of neither body starts in the third body until its motion puts it elsewhere.
// Transferred material started in one body and now moves with the other.
//
// Which third-body particles form one wear particle: the graph of the pairs in interaction range now (the
// neighbour list's pairs closer than r_i + r_j + delta_f, eq 10, as the junction analysis decides "in
// range"), restricted to third-body particles; each connected component is a cluster, with its volume
// (4/3 pi r^3 summed), its equivalent diameter (6 V / pi)^(1/3), and a size histogram of them per sample.
//
// Attached or detached, by the graph alone: the same pairs in range over all particles, whatever their state.
// A connected component holding a member of a body's driven group is attached to that body; one holding
// members of both driven groups bridges the interface (the bodies still hold together through it: counted
// apart, in bridging_*); every other component is a detached wear particle (detached_*).
// Why both definitions: f cannot tell a shear band (attached to a body, f spread between 0 and 1) from debris
// (detached), and the graph cannot tell a debris particle rolling in contact with a surface (in range of it:
// attached) from one stuck to it. So the f-based columns (bottom_*, top_*, third_*, transferred_*,
// wear_volume, clusters, largest_*, the histogram and surfaces_debris.csv) and the graph-based ones
// (attached_*, bridging_*, detached_*) stand side by side; README's census section says which is which.
//
// The tangential work of a wear particle (Garcia-Suarez et al., JMPS 2023: a debris particle's volume grows
// as W_t^(3/2) in 3D): each particle's `tangential_work` column (the energy accounting's half of each of its
// pairs' work of the tangential force) is recorded, by id, at the sample where it becomes third body (by f;
// for a particle that starts with neither body, at the first sample), and forgotten when it leaves the third
// body. A third-body cluster's W_t is the sum over its members of their column now less that record.
// surfaces_debris.csv holds one row per cluster and sample (rank by volume, particles, volume, equivalent
// diameter, W_t, shares by origin), and V_d = c W_t^a is fitted over the last sample's clusters with
// W_t > 0 (report(), surfaces.png). With the accounting off (`output.energy: false`) the columns are all 0:
// W_t is written as NaN (the file keeps its columns in every run) and the report says why there is no fit.
//
// What the interface carries: the top driven group's reaction along the slide and the normal (their ratio,
// the friction coefficient), the tangential work the drives did along the slide so far (the trapezoid
// between samples), the contact tangential work (the energy accounting's own exact sum of its
// `tangential_work` column: the work the pairs' relative motion did against their tangential forces, over
// every pair of the system, at every step; the drives' work pays for it and for everything else too: normal
// damping, elastic and kinetic energy), and the real contact area: the pairs in range joining a particle
// moving with the bottom body to one moving with the top body, each with its contact cross-section A_N of
// eqs 14-15.
//
// Every sum runs over the particles (or pairs) in id order, so the rows are the same bits whatever the
// storage order (thread count, a restart's re-sort). The census's state (each particle's state, the
// window's positions, the bins, the tangential work at joining, every sample so far with its clusters) goes
// into every checkpoint (state() / restore()), so a chunked run writes the files of the run in one piece.
#include <cstdint>
#include <deque>
#include <optional>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "core/io/key_reference.hpp"
#include "core/rough/height_field.hpp"
#include "core/vec3.hpp"

namespace debris {

class DemSimulation;
class InputNode;
struct PictureUnits;
namespace h5 {
class Location;
}

/// One body of the census: its particles at the start, given by `labels` (one or more names of `labels:`)
/// or by `group` (one of the two), and the group whose motion is the body's (`driven`).
struct SurfaceBodySettings {
  std::vector<std::string> labels;
  std::string group;
  std::string driven;
};

struct SurfaceSettings {
  long every = 0;                   // steps between samples; 0 = no census
  SurfaceBodySettings bottom, top;  // f = 0 and f = 1
  int sliding_axis = 0, normal_axis = 1;
  double window = 0;                          // s: displacements over this last stretch give f
  double moving_min = 0.1, moving_max = 0.9;  // f range of the third body
  std::vector<double> histogram_bins;         // m: equivalent-diameter bin edges, increasing; empty: the default
  double min_slide = -1;                      // m: the least relative slide for f to classify; < 0: the smallest radius
  // Roughness of the two faces (surface_roughness.hpp): the envelopes' grid spacing (< 0: the smallest particle's
  // radius), the wavelengths the Hurst exponent is fitted over (< 0: two largest diameters; half the box along
  // the first in-plane axis), and whether the height maps go to surfaces_heights.h5.
  double roughness_spacing = -1;
  double fit_shortest = -1, fit_longest = -1;
  bool height_maps = true;
};

/// Reads the `surfaces:` section of a debris_dem input (InputError naming the key for anything bad).
SurfaceSettings read_surface_settings(const InputNode& node);
/// Describes the keys read_surface_settings() reads, as the section `surfaces` of `ref`.
void document_surface_settings(KeyReference& ref);
/// InputError naming surfaces.window when it is longer than the run (`run_time` s: the stages' total, or
/// run.steps without stages, times the time step).
void check_surface_window(const SurfaceSettings& settings, double run_time);

enum class SurfaceState : int { bottom = 0, top = 1, third = 2 };

/// One third-body cluster (a wear particle by f) at one sample: a row of surfaces_debris.csv.
struct SurfaceDebris {
  long rank = 0;  // 1 for the largest volume of its sample (equal volumes: the one holding the smaller id first)
  long particles = 0;
  double volume = 0, diameter = 0;
  double tangential_work = 0;  // J: its members' tangential_work since each joined the third body (NaN: no accounting)
  double from_bottom = 0, from_top = 0, from_neither = 0;  // shares of its volume by the body they started in
};

/// One sample: the surfaces.csv row, and the histogram's and surfaces_debris.csv's rows.
struct SurfaceSample {
  long step = 0;
  double time = 0;
  double slide = 0;             // the driven groups' relative displacement along the slide since the start
  double tangential_force = 0;  // the top driven group's reaction along the slide
  double normal_force = 0;      // ... along the normal
  double friction_coefficient = 0;
  double tangential_work = 0;  // J, accumulated over the samples (tangential_work_increment)
  double contact_tangential_work = 0;  // J, the accounting's sum of the tangential_work column (NaN: it is off)
  long contact_pairs = 0;
  double contact_area = 0;
  double bottom_volume = 0, top_volume = 0, third_volume = 0;
  double to_bottom_volume = 0, to_top_volume = 0;  // transferred: started in the top (bottom) body
  double wear_volume = 0;                          // third body + transferred both ways
  long bottom_particles = 0, top_particles = 0, third_particles = 0;
  long clusters = 0;
  double largest_volume = 0;
  long largest_particles = 0;
  double largest_diameter = 0;
  double largest_from_bottom = 0, largest_from_top = 0, largest_from_neither = 0;  // shares of its volume
  // By the graph of all pairs in range: the components holding the bottom driven group's members (not the
  // top's), the top's (not the bottom's), both (bridging), neither (detached wear particles).
  long attached_bottom_particles = 0, attached_top_particles = 0;
  long bridging_particles = 0, bridging_clusters = 0;
  long detached_particles = 0, detached_clusters = 0;
  double detached_volume = 0, largest_detached_volume = 0;
  double window_time = 0;   // the time the displacements span (0: no earlier position yet)
  double window_slide = 0;  // the driven groups' relative slide over it
  bool classified = false;  // f classified the particles (else each kept its last state)
  // Each face's roughness: the bottom body's top face, the top body's bottom face (by state), each mean height,
  // rms height, rms slope, H from the PSD with its error, H from the height-height correlation (NaN: no fit).
  double bottom_mean_height = 0, bottom_rms_height = 0, bottom_rms_slope = 0;
  double bottom_hurst = 0, bottom_hurst_error = 0, bottom_hurst_hhcf = 0;
  double top_mean_height = 0, top_rms_height = 0, top_rms_slope = 0;
  double top_hurst = 0, top_hurst_error = 0, top_hurst_hhcf = 0;
  // Kept for the next sample's work (not in the row): the driven groups' reactions and displacements along
  // the slide.
  double top_shift = 0, bottom_force = 0, bottom_shift = 0;
  // The histogram: per bin, the third-body clusters and their volume.
  std::vector<double> bin_clusters, bin_volume;
  // The third-body clusters, largest first (surfaces_debris.csv's rows).
  std::vector<SurfaceDebris> debris;
};

/// The work the drives did along the slide between two samples: each driven group's drive holds it against
/// the reaction R the particles exert on it, so it does -R . dx; the trapezoid over the two samples' reactions
/// (W_t = sum of -R_s dx_s). The one place this is computed: an exact per-step figure from the energy
/// accounting can replace it.
double tangential_work_increment(double top_force_before, double top_force_after, double top_shift_before,
                                 double top_shift_after, double bottom_force_before, double bottom_force_after,
                                 double bottom_shift_before, double bottom_shift_after);

/// A power law V = c W^exponent fitted by least squares in log-log (points with V > 0 and W > 0).
struct PowerFit {
  bool made = false;  // at least two points with different W
  double exponent = 0, prefactor = 0;
  long points = 0;
};
PowerFit fit_power_law(const std::vector<double>& w, const std::vector<double>& v);

/// What the census carries from sample to sample, as plain arrays for a checkpoint (in id order).
struct SurfaceCensusState {
  std::vector<std::int64_t> state_id, state_value;      // each particle's state (SurfaceState)
  std::vector<double> history_time;                     // the window's snapshots, oldest first
  std::vector<std::int64_t> history_count, history_id;  // particles per snapshot; their ids
  std::vector<double> history_position;                 // 3 per id
  std::vector<double> bin_edges;
  std::vector<double> samples;  // sample_values() per sample
  std::size_t sample_count = 0;
  std::vector<std::int64_t> joined_id;  // third-body particles: the tangential_work column when they joined it
  std::vector<double> joined_value;
  std::vector<std::int64_t> debris_count;  // per sample: its third-body clusters
  std::vector<double> debris;              // their values (debris_values()), sample after sample
};

class SurfaceCensus {
 public:
  /// `settings` with their names resolved on `sim` (InputError naming the key for an unknown label or
  /// group, the same body twice, a body without particles).
  SurfaceCensus(const SurfaceSettings& settings, const DemSimulation& sim);

  /// Samples the current state (call every settings.every steps).
  const SurfaceSample& sample(const DemSimulation& sim);
  const std::vector<SurfaceSample>& samples() const { return samples_; }
  /// The faces' height maps of the last sample (the bottom body's top face, the top body's bottom face).
  const HeightField& bottom_face() const { return bottom_face_; }
  const HeightField& top_face() const { return top_face_; }
  /// The wavelengths the faces' Hurst exponents are fitted over (m).
  double fit_shortest() const { return fit_shortest_; }
  double fit_longest() const { return fit_longest_; }
  const std::vector<double>& bin_edges() const { return edges_; }
  const SurfaceSettings& settings() const { return s_; }
  /// The current state of the particle with this id (its starting one before the first sample).
  SurfaceState state_of(std::int64_t id) const;

  /// surfaces.csv's columns with their units and meanings; the header is its names.
  static const ColumnTable& table();
  static std::vector<std::string> columns() { return table().header(); }
  static std::vector<double> row(const SurfaceSample& s);
  /// surfaces_histogram.csv's: one row per sample and bin.
  static const ColumnTable& histogram_table();
  static std::vector<std::string> histogram_columns() { return histogram_table().header(); }
  std::vector<std::vector<double>> histogram_rows(const SurfaceSample& s) const;
  /// surfaces_debris.csv's: one row per sample and third-body cluster, largest first.
  static const ColumnTable& debris_table();
  static std::vector<std::string> debris_columns() { return debris_table().header(); }
  static std::vector<std::vector<double>> debris_rows(const SurfaceSample& s);

  /// The state to continue from (checkpoints), and back (InputError naming the checkpoint `path` for arrays
  /// that do not fit together).
  SurfaceCensusState state() const;
  void restore(const SurfaceCensusState& state, const std::string& path);

  /// Wear volume against tangential work over the samples so far.
  PowerFit wear_fit() const;
  /// V_d = c W_t^a over the last sample's third-body clusters with W_t > 0 (none made without the accounting).
  PowerFit debris_fit() const;
  /// Whether the run has the energy accounting, which W_t per cluster and contact_tangential_work need.
  bool energy_accounting() const { return energy_; }
  /// A paragraph on the last sample with its numbers ("surfaces: ...").
  std::string report() const;

 private:
  SurfaceSettings s_;
  int bottom_driven_ = -1, top_driven_ = -1;
  double min_slide_ = 0;
  std::vector<double> edges_;
  std::unordered_map<std::int64_t, int> origin_;  // id -> the body it started in (SurfaceState; third: neither)
  std::unordered_map<std::int64_t, int> state_;   // id -> its state now
  std::unordered_map<std::int64_t, double> joined_;  // third-body id -> its tangential_work when it joined
  bool energy_ = false;                              // the run has the energy accounting
  // Unwrapped positions by id at the samples of the last window (the oldest is the reference).
  std::deque<std::pair<double, std::unordered_map<std::int64_t, Vec3>>> history_;
  std::vector<SurfaceSample> samples_;
  double spacing_ = 0, fit_shortest_ = 0, fit_longest_ = 0;
  HeightField bottom_face_, top_face_;
};

/// The state as the group `surfaces` under `at` (a checkpoint's `run` group), and back (nullopt: none there).
void write_surface_state(h5::Location& at, const SurfaceCensusState& state);
std::optional<SurfaceCensusState> read_surface_state(const h5::Location& at);

/// Writes surfaces.gp in `dir` (surfaces.png from surfaces.csv: wear volume against the slide and, log-log
/// with the fitted exponent, against the tangential work; friction coefficient and contact area against the
/// slide; detached and third-body volume against the slide; from surfaces_debris.csv, log-log, the last
/// sample's wear particles' volume against their tangential work with the fitted exponent) and runs gnuplot
/// there. Returns the line the run prints: what was drawn, or why not.
std::string draw_surface_pictures(const std::string& dir, const SurfaceCensus& census, const PictureUnits& units);

}  // namespace debris
