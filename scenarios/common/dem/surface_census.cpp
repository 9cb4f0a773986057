#include "scenarios/common/dem/surface_census.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numeric>
#include <sstream>
#include <stdexcept>
#include <tuple>
#include <type_traits>

#include "core/error.hpp"
#include "core/io/hdf5_file.hpp"
#include "core/io/input.hpp"
#include "core/rough/surface_envelope.hpp"
#include "scenarios/common/dem/dem_simulation.hpp"
#include "scenarios/common/dem/run_pictures.hpp"
#include "scenarios/common/dem/surface_roughness.hpp"
#include "scenarios/common/run/gnuplot.hpp"

namespace debris {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr int kBottom = static_cast<int>(SurfaceState::bottom);
constexpr int kTop = static_cast<int>(SurfaceState::top);
constexpr int kThird = static_cast<int>(SurfaceState::third);

double comp(const Vec3& v, int a) { return a == 0 ? v.x : (a == 1 ? v.y : v.z); }

double sphere_volume(double r) { return 4.0 / 3.0 * kPi * r * r * r; }
double equivalent_diameter(double volume) { return std::cbrt(6.0 * volume / kPi); }

int read_axis(const InputNode& n, const std::string& key, const std::string& fallback) {
  const std::string a = n.choice(key, {"x", "y", "z"}, fallback);
  return a == "x" ? 0 : (a == "y" ? 1 : 2);
}

std::string list_text(const std::vector<std::string>& names) {
  if (names.size() == 1) return names[0];
  std::string t = "[";
  for (std::size_t k = 0; k < names.size(); ++k) {
    if (k > 0) t += ", ";
    t += names[k];
  }
  t += "]";
  return t;
}

SurfaceBodySettings read_body(const InputNode& n, const std::string& key) {
  const InputNode b = n.child(key);
  SurfaceBodySettings s;
  const bool by_label = b.has("label"), by_group = b.has("group");
  if (by_label == by_group)
    throw input_error(b.path(), by_label ? "label and group" : "neither label nor group",
                      "give the body's particles by one of `label` (a name or a list) or `group`");
  if (by_label) {
    if (b.child("label").is_sequence()) {
      for (const InputNode& e : b.list("label")) s.labels.push_back(e.text());
      if (s.labels.empty()) throw input_error(b.path() + ".label", "[]", "name at least one label");
    } else {
      s.labels.push_back(b.string("label"));
    }
  } else {
    s.group = b.string("group");
  }
  s.driven = b.string("driven");
  return s;
}

struct UnionFind {
  std::vector<int> parent;
  explicit UnionFind(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  int find(int i) {
    while (parent[static_cast<std::size_t>(i)] != i) {
      parent[static_cast<std::size_t>(i)] = parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(i)])];
      i = parent[static_cast<std::size_t>(i)];
    }
    return i;
  }
  // The root of a set is its smallest member, whatever order the pairs come in.
  void unite(int a, int b) {
    a = find(a);
    b = find(b);
    if (a != b) parent[static_cast<std::size_t>(std::max(a, b))] = std::min(a, b);
  }
};

// surfaces.csv's columns in order: f(field) for each, so the row and its way back from a checkpoint cannot
// disagree (SurfaceCensus::table() names them in the same order).
template <class Sample, class F>
void for_each_column(Sample& s, F&& f) {
  f(s.step), f(s.time), f(s.slide), f(s.tangential_force), f(s.normal_force), f(s.friction_coefficient);
  f(s.tangential_work), f(s.contact_tangential_work), f(s.contact_pairs), f(s.contact_area);
  f(s.bottom_volume), f(s.top_volume), f(s.third_volume), f(s.to_bottom_volume), f(s.to_top_volume);
  f(s.wear_volume), f(s.bottom_particles), f(s.top_particles), f(s.third_particles), f(s.clusters);
  f(s.largest_volume), f(s.largest_particles), f(s.largest_diameter), f(s.largest_from_bottom);
  f(s.largest_from_top), f(s.largest_from_neither);
  f(s.attached_bottom_particles), f(s.attached_top_particles), f(s.bridging_particles), f(s.bridging_clusters);
  f(s.detached_particles), f(s.detached_volume), f(s.detached_clusters), f(s.largest_detached_volume);
  f(s.window_time), f(s.window_slide), f(s.classified);
  f(s.bottom_mean_height), f(s.bottom_rms_height), f(s.bottom_rms_slope), f(s.bottom_hurst), f(s.bottom_hurst_error);
  f(s.bottom_hurst_hhcf), f(s.top_mean_height), f(s.top_rms_height), f(s.top_rms_slope), f(s.top_hurst);
  f(s.top_hurst_error), f(s.top_hurst_hhcf);
}

// surfaces_debris.csv's values of one cluster, after the sample's step and slide.
template <class Debris, class F>
void for_each_debris_value(Debris& d, F&& f) {
  f(d.rank), f(d.particles), f(d.volume), f(d.diameter), f(d.tangential_work), f(d.from_bottom), f(d.from_top);
  f(d.from_neither);
}
constexpr std::size_t kDebrisValues = 8;

template <class T>
void assign_value(T& to, double v) {
  if constexpr (std::is_same_v<T, bool>) {
    to = v != 0;
  } else {
    to = static_cast<T>(v);
  }
}

}  // namespace

SurfaceSettings read_surface_settings(const InputNode& n) {
  SurfaceSettings s;
  s.every = n.integer("every");
  if (s.every < 1) throw input_error(n.path() + ".every", std::to_string(s.every), "must be >= 1 (steps)");
  s.bottom = read_body(n, "bottom");
  s.top = read_body(n, "top");
  s.sliding_axis = read_axis(n, "sliding_axis", "x");
  s.normal_axis = read_axis(n, "normal_axis", "y");
  if (s.sliding_axis == s.normal_axis)
    throw input_error(n.path() + ".normal_axis", std::string(1, "xyz"[s.normal_axis]), "must differ from sliding_axis");
  s.window = n.quantity("window", units::time);
  if (!(s.window > 0) || !std::isfinite(s.window))
    throw input_error(n.path() + ".window", format_value(s.window), "must be > 0 (a time)");
  if (n.has("moving")) {
    const std::vector<double> v = n.numbers("moving", units::dimensionless);
    if (v.size() != 2 || !(v[0] < v[1]) || !(v[0] > 0 && v[1] < 1))
      throw input_error(n.path() + ".moving",
                        v.size() == 2 ? "[" + format_value(v[0]) + ", " + format_value(v[1]) + "]"
                                      : std::to_string(v.size()) + " values",
                        "give [min, max] with 0 < min < max < 1 (fractions of the top body's relative displacement)");
    s.moving_min = v[0];
    s.moving_max = v[1];
  }
  if (n.has("histogram_bins")) {
    s.histogram_bins = n.numbers("histogram_bins", units::length);
    bool ok = s.histogram_bins.size() >= 2;
    for (std::size_t k = 0; k < s.histogram_bins.size() && ok; ++k)
      ok = std::isfinite(s.histogram_bins[k]) && s.histogram_bins[k] > 0 &&
           (k == 0 || s.histogram_bins[k] > s.histogram_bins[k - 1]);
    if (!ok)
      throw input_error(n.path() + ".histogram_bins", std::to_string(s.histogram_bins.size()) + " values",
                        "give at least two increasing diameters > 0 (the bins' edges)");
  }
  if (n.has("min_slide")) {
    s.min_slide = n.quantity("min_slide", units::length);
    if (!(s.min_slide > 0) || !std::isfinite(s.min_slide))
      throw input_error(n.path() + ".min_slide", format_value(s.min_slide), "must be > 0 (a length)");
  }
  if (n.has("roughness")) {
    const InputNode r = n.child("roughness");
    if (r.has("grid_spacing")) {
      s.roughness_spacing = r.quantity("grid_spacing", units::length);
      if (!(s.roughness_spacing > 0) || !std::isfinite(s.roughness_spacing))
        throw input_error(r.path() + ".grid_spacing", format_value(s.roughness_spacing), "must be > 0 (a length)");
    }
    if (r.has("fit")) {
      const std::vector<double> v = r.numbers("fit", units::length);
      if (v.size() != 2 || !(v[0] > 0) || !(v[1] > v[0]) || !std::isfinite(v[1]))
        throw input_error(r.path() + ".fit", r.yaml_of("fit"),
                          "give [shortest, longest] wavelengths, 0 < shortest < longest");
      s.fit_shortest = v[0];
      s.fit_longest = v[1];
    }
    s.height_maps = r.boolean("height_maps", true);
  }
  return s;
}

void check_surface_window(const SurfaceSettings& s, double run_time) {
  if (s.window > run_time * (1 + 1e-9))
    throw input_error("surfaces.window", format_value(s.window),
                      "is longer than the run (" + format_value(run_time) + " s): the window would never fill");
}

void document_surface_settings(KeyReference& r) {
  const SurfaceSettings d;  // the reader's defaults
  r.describe_section("surfaces",
                     "The wear census of a sliding interface: every `every` steps each particle is put with the "
                     "bottom body, the top body or neither (the third body) by its displacement along the slide "
                     "over the last `window`, as a fraction f of the top driven group's relative to the bottom "
                     "one's; the third body's particles joined by pairs in interaction range form its clusters "
                     "(wear particles). Each sample is a row of `surfaces.csv` (volumes, transfer, wear volume, "
                     "clusters, friction coefficient, tangential work, real contact area) and rows of "
                     "`surfaces_histogram.csv`; with `output.pictures`, `surfaces.png`.");
  r.key("surfaces").is(KeyKind::section).fallback_is("no census")
      .means("the wear census of the interface between two bodies, written to `surfaces.csv`");
  r.key("surfaces.every").is(KeyKind::integer).allowed(">= 1").means("steps between two samples");
  for (const char* body : {"bottom", "top"}) {
    const std::string b = std::string("surfaces.") + body;
    const bool bottom = std::string(body) == "bottom";
    r.key(b).is(KeyKind::section).allowed("`label` or `group`, and `driven`")
        .means(bottom ? "the body f = 0 stands for" : "the body f = 1 stands for");
    r.key(b + ".label").is(KeyKind::text).or_a_list().fallback_is("give `label` or `group`")
        .allowed(std::string("labels of `labels`, none of the ") + (bottom ? "top" : "bottom") + " body's")
        .means("the body's particles at the start: those with these labels (and the driven group's)");
    r.key(b + ".group").is(KeyKind::text).fallback_is("give `label` or `group`")
        .allowed(std::string("a group of `groups`, not the ") + (bottom ? "top" : "bottom") + " body's")
        .means("the body's particles at the start: this group's (and the driven group's)");
    r.key(b + ".driven").is(KeyKind::text)
        .allowed(std::string("a group of `groups` holding particles, not the ") + (bottom ? "top" : "bottom") +
                 " body's driven group")
        .means(bottom ? "the group whose displacement is the bottom body's (f = 0)"
                      : "the group whose displacement is the top body's (f = 1); its reaction gives the friction "
                        "coefficient");
  }
  r.key("surfaces.sliding_axis").one_of({"x", "y", "z"}).fallback("x").means("the axis the bodies slide along");
  r.key("surfaces.normal_axis").one_of({"x", "y", "z"}).fallback("y").allowed("not `sliding_axis`")
      .means("the axis normal to the interface");
  r.key("surfaces.window").is(KeyKind::quantity).in(units::time)
      .allowed("> 0, at most the run's length (the stages' total, or `run.steps` without stages)")
      .means("f is the displacement over this last stretch of the run (before it has filled: since the first "
             "sample)");
  std::string moving = "[";  // appended: GCC 12 warns falsely (-Wrestrict) on "[" + std::string
  moving += format_value(d.moving_min);
  moving += ", ";
  moving += format_value(d.moving_max);
  moving += "]";
  r.key("surfaces.moving").is(KeyKind::numbers).in(units::dimensionless).fallback(moving)
      .allowed("[min, max], 0 < min < max < 1")
      .means("f < min moves with the bottom body, f > max with the top body, in between with neither (the third "
             "body)");
  r.key("surfaces.histogram_bins").is(KeyKind::numbers).in(units::length)
      .fallback_is("edges d_s 2^((k - 1/2) / 3), d_s the smallest particle's diameter, up to the equivalent "
                   "diameter of all particles: each bin doubles the volume, bin k holds clusters of about 2^k "
                   "smallest particles")
      .allowed("at least two increasing diameters > 0")
      .means("the edges of the equivalent-diameter bins of surfaces_histogram.csv (a cluster below the first "
             "edge counts in the first bin, one above the last in the last)");
  r.key("surfaces.min_slide").is(KeyKind::quantity).in(units::length)
      .fallback_is("the smallest particle's radius").allowed("> 0")
      .means("f classifies only when the driven groups slid at least this far relative to each other over the "
             "window; before, each particle keeps its last state");
  r.key("surfaces.roughness").is(KeyKind::section).fallback_is("measured with the defaults below")
      .means("the roughness of the two faces each sample: the envelope of each body's spheres (by state) on a grid, "
             "its rms height, rms slope and Hurst exponent (surfaces.csv), the height maps in surfaces_heights.h5");
  r.key("surfaces.roughness.grid_spacing").is(KeyKind::quantity).in(units::length)
      .fallback_is("the smallest particle's radius").allowed("> 0")
      .means("the height maps' grid spacing (at most this; the grid spans the box's in-plane lengths)");
  r.key("surfaces.roughness.fit").is(KeyKind::numbers).in(units::length)
      .fallback_is("[two largest particle diameters, half the box along the first in-plane axis]")
      .allowed("[shortest, longest], 0 < shortest < longest")
      .means("the wavelengths the Hurst exponent is fitted over: the PSD between 2 pi / longest and 2 pi / shortest, "
             "the height-height correlation between shortest / 2 and longest / 2; shorter wavelengths are the "
             "particles' own bumps, not roughness");
  r.key("surfaces.roughness.height_maps").is(KeyKind::boolean).fallback("true")
      .means("writes each sample's two height maps to surfaces_heights.h5 (HDF5: /samples/<k>/bottom and /top)");
}

double tangential_work_increment(double top_force_before, double top_force_after, double top_shift_before,
                                 double top_shift_after, double bottom_force_before, double bottom_force_after,
                                 double bottom_shift_before, double bottom_shift_after) {
  // The reaction is the force of the particles on the driven group; the drive that moves it exerts the
  // opposite and does -R dx on the system. Trapezoid between two samples: exact for a reaction that changes
  // linearly in between, an estimate of the stick-slip in between otherwise.
  return -0.5 * (top_force_before + top_force_after) * (top_shift_after - top_shift_before) -
         0.5 * (bottom_force_before + bottom_force_after) * (bottom_shift_after - bottom_shift_before);
}

PowerFit fit_power_law(const std::vector<double>& w, const std::vector<double>& v) {
  PowerFit fit;
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  long n = 0;
  for (std::size_t k = 0; k < w.size() && k < v.size(); ++k) {
    if (!(w[k] > 0) || !(v[k] > 0) || !std::isfinite(w[k]) || !std::isfinite(v[k])) continue;
    const double x = std::log(w[k]), y = std::log(v[k]);
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
    ++n;
  }
  fit.points = n;
  if (n < 2) return fit;
  const double dn = static_cast<double>(n);
  const double var = sxx - sx * sx / dn;
  if (!(var > 1e-12 * std::max(1.0, sxx))) return fit;
  fit.made = true;
  fit.exponent = (sxy - sx * sy / dn) / var;
  fit.prefactor = std::exp((sy - fit.exponent * sx) / dn);
  return fit;
}

SurfaceCensus::SurfaceCensus(const SurfaceSettings& settings, const DemSimulation& sim)
    : s_(settings), energy_(sim.settings().energy_accounting) {
  const Groups& groups = sim.groups();
  const Particles& p = sim.particles();
  const std::vector<std::string>& labels = p.label_names;
  // Each body's members at the start: a label index set or a group.
  struct Body {
    std::vector<int> labels;  // label k names label_names[k - 1]
    int group = -1;
    int driven = -1;
  };
  auto resolve = [&](const SurfaceBodySettings& b, const std::string& at) {
    Body out;
    for (const std::string& name : b.labels) {
      const auto it = std::find(labels.begin(), labels.end(), name);
      if (it == labels.end()) throw input_error(at + ".label", name, "no such label");
      out.labels.push_back(static_cast<int>(it - labels.begin()) + 1);
    }
    if (!b.group.empty()) {
      out.group = groups.find(b.group);
      if (out.group < 0) throw input_error(at + ".group", b.group, "no such group");
    }
    out.driven = groups.find(b.driven);
    if (out.driven < 0) throw input_error(at + ".driven", b.driven, "no such group");
    if (std::none_of(p.group.begin(), p.group.end(), [&](int g) { return g == out.driven; }))
      throw input_error(at + ".driven", b.driven, "the group holds no particle");
    return out;
  };
  const Body bottom = resolve(s_.bottom, "surfaces.bottom");
  const Body top = resolve(s_.top, "surfaces.top");
  for (int l : top.labels)
    if (std::find(bottom.labels.begin(), bottom.labels.end(), l) != bottom.labels.end())
      throw input_error("surfaces.top.label", labels[static_cast<std::size_t>(l - 1)],
                        "is the bottom body's label too: the two bodies must differ");
  if (top.group >= 0 && top.group == bottom.group)
    throw input_error("surfaces.top.group", s_.top.group, "is the bottom body's group too: the two bodies must differ");
  if (top.driven == bottom.driven)
    throw input_error("surfaces.top.driven", s_.top.driven,
                      "is the bottom body's driven group too: the two bodies must move apart");
  bottom_driven_ = bottom.driven;
  top_driven_ = top.driven;

  auto holds = [&](const Body& b, std::size_t i) {
    if (p.group[i] == b.driven) return true;
    if (b.group >= 0) return p.group[i] == b.group;
    return std::find(b.labels.begin(), b.labels.end(), p.label[i]) != b.labels.end();
  };
  double smallest = 0, total = 0;
  std::vector<std::pair<std::int64_t, double>> volumes;  // (id, volume), summed in id order below
  std::vector<char> in_bottom(p.size(), 0), in_top(p.size(), 0);
  for (std::size_t i = 0; i < p.size(); ++i) {
    const bool b = holds(bottom, i), t = holds(top, i);
    if (b && t) {
      // Only through a driven group that the other body's labels or group also hold.
      const bool bottom_driven = p.group[i] == bottom.driven;
      throw input_error(bottom_driven ? "surfaces.bottom.driven" : "surfaces.top.driven",
                        bottom_driven ? s_.bottom.driven : s_.top.driven,
                        "holds particle id " + std::to_string(p.id[i]) + " of the " +
                            (bottom_driven ? "top" : "bottom") + " body: the two bodies must not share particles");
    }
    in_bottom[i] = b;
    in_top[i] = t;
    const int origin = b ? kBottom : (t ? kTop : kThird);
    origin_.emplace(p.id[i], origin);
    state_.emplace(p.id[i], origin);
    smallest = i == 0 ? p.radius[i] : std::min(smallest, p.radius[i]);
    volumes.emplace_back(p.id[i], sphere_volume(p.radius[i]));
  }
  if (std::find(in_bottom.begin(), in_bottom.end(), 1) == in_bottom.end())
    throw input_error(s_.bottom.labels.empty() ? "surfaces.bottom.group" : "surfaces.bottom.label",
                      s_.bottom.labels.empty() ? s_.bottom.group : list_text(s_.bottom.labels), "holds no particle");
  if (std::find(in_top.begin(), in_top.end(), 1) == in_top.end())
    throw input_error(s_.top.labels.empty() ? "surfaces.top.group" : "surfaces.top.label",
                      s_.top.labels.empty() ? s_.top.group : list_text(s_.top.labels), "holds no particle");
  std::sort(volumes.begin(), volumes.end());
  for (const auto& v : volumes) total += v.second;
  min_slide_ = s_.min_slide > 0 ? s_.min_slide : smallest;
  const double largest = 2.0 * *std::max_element(p.radius.begin(), p.radius.end());
  spacing_ = s_.roughness_spacing > 0 ? s_.roughness_spacing : smallest;
  const int axis_a = s_.normal_axis == 0 ? 1 : 0;
  fit_shortest_ = s_.fit_shortest > 0 ? s_.fit_shortest : 2.0 * largest;
  fit_longest_ = s_.fit_longest > 0 ? s_.fit_longest : 0.5 * sim.box().length(axis_a);
  if (!s_.histogram_bins.empty()) {
    edges_ = s_.histogram_bins;
  } else {
    // Each bin doubles the volume; bin k is centred (in log) on 2^k smallest particles, so the clusters of
    // 1, 2, 4, ... equal particles never sit on an edge.
    const double d_s = 2.0 * smallest, d_all = equivalent_diameter(total);
    for (int k = 0;; ++k) {
      edges_.push_back(d_s * std::exp2((k - 0.5) / 3.0));
      if (edges_.back() > d_all && k >= 1) break;
    }
  }
}

SurfaceState SurfaceCensus::state_of(std::int64_t id) const {
  const auto it = state_.find(id);
  if (it == state_.end()) throw std::out_of_range("surfaces: no particle id " + std::to_string(id));
  return static_cast<SurfaceState>(it->second);
}

const SurfaceSample& SurfaceCensus::sample(const DemSimulation& sim) {
  const Particles& p = sim.particles();
  const BoxView bv = sim.box().view();
  const std::size_t n = p.size();
  SurfaceSample out;
  out.step = sim.step_count();
  out.time = sim.time();
  const Group& top = sim.groups().list[static_cast<std::size_t>(top_driven_)];
  const Group& bottom = sim.groups().list[static_cast<std::size_t>(bottom_driven_)];
  const int s = s_.sliding_axis;
  out.tangential_force = comp(top.reaction, s);
  out.normal_force = comp(top.reaction, s_.normal_axis);
  out.friction_coefficient = out.normal_force != 0 ? std::abs(out.tangential_force) / std::abs(out.normal_force) : 0.0;
  out.top_shift = comp(top.displacement, s);
  out.bottom_shift = comp(bottom.displacement, s);
  out.bottom_force = comp(bottom.reaction, s);
  out.slide = out.top_shift - out.bottom_shift;
  if (!samples_.empty()) {
    const SurfaceSample& b = samples_.back();
    out.tangential_work = b.tangential_work +
                          tangential_work_increment(b.tangential_force, out.tangential_force, b.top_shift,
                                                    out.top_shift, b.bottom_force, out.bottom_force, b.bottom_shift,
                                                    out.bottom_shift);
  }
  // The contact forces' tangential work: the accounting's own exact sum of its column.
  energy_ = sim.settings().energy_accounting;
  out.contact_tangential_work = energy_ ? sim.energy_totals().tangential_work : kNaN;

  // The particles in id order: every sum below runs in it, so no storage order changes a bit.
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return p.id[a] < p.id[b]; });
  std::vector<int> rank(n);
  for (std::size_t k = 0; k < n; ++k) rank[order[k]] = static_cast<int>(k);

  // 1. Each particle's state from f over the window (or since the first sample).
  std::vector<Vec3> unwrapped(n);
  std::unordered_map<std::int64_t, Vec3> now;
  now.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    unwrapped[i] = Vec3{p.x[i] + p.ix[i] * bv.len[0], p.y[i] + p.iy[i] * bv.len[1], p.z[i] + p.iz[i] * bv.len[2]};
    now.emplace(p.id[i], unwrapped[i]);
  }
  history_.push_back({out.time, std::move(now)});
  // Keep the snapshots back to one window ago (and the one just before, the reference), as the junction's
  // analysis does.
  while (history_.size() > 2 && out.time - history_[1].first >= s_.window * (1 - 1e-9)) history_.pop_front();
  const auto& [t0, ref] = history_.front();
  out.window_time = out.time - t0;
  std::vector<double> dx(n, 0.0);
  std::vector<char> known(n, 0);
  double top_dx = 0, top_mass = 0, bottom_dx = 0, bottom_mass = 0;
  for (std::size_t i : order) {
    const auto it = ref.find(p.id[i]);
    if (it == ref.end()) continue;
    known[i] = 1;
    dx[i] = comp(unwrapped[i] - it->second, s);
    if (p.group[i] == top_driven_) top_dx += p.mass[i] * dx[i], top_mass += p.mass[i];
    if (p.group[i] == bottom_driven_) bottom_dx += p.mass[i] * dx[i], bottom_mass += p.mass[i];
  }
  if (top_mass > 0) top_dx /= top_mass;
  if (bottom_mass > 0) bottom_dx /= bottom_mass;
  const double relative = top_dx - bottom_dx;
  out.window_slide = relative;
  out.classified = out.window_time > 0 && std::abs(relative) >= min_slide_;
  if (out.classified) {
    for (std::size_t i = 0; i < n; ++i) {
      if (!known[i]) continue;
      int st = kThird;
      if (p.group[i] == bottom_driven_) {
        st = kBottom;
      } else if (p.group[i] == top_driven_) {
        st = kTop;
      } else {
        const double f = (dx[i] - bottom_dx) / relative;
        st = f < s_.moving_min ? kBottom : (f > s_.moving_max ? kTop : kThird);
      }
      state_[p.id[i]] = st;
    }
  }
  std::vector<int> st(n), origin(n);
  for (std::size_t i = 0; i < n; ++i) {
    const auto it = state_.find(p.id[i]);
    const auto o = origin_.find(p.id[i]);
    // A particle the census has not seen (none is added during a run): with neither body.
    st[i] = it == state_.end() ? kThird : it->second;
    origin[i] = o == origin_.end() ? kThird : o->second;
    // Each third-body particle's tangential_work when it joined the third body: now, if it just did (or
    // starts there); forgotten when it leaves.
    if (st[i] == kThird)
      joined_.try_emplace(p.id[i], p.tangential_work[i]);
    else
      joined_.erase(p.id[i]);
  }

  // 2. Pairs in interaction range now (as the junction analysis decides it): third-body pairs join clusters,
  // pairs joining the two bodies are the real contact.
  const CohesiveCutoff range{sim.coefficients()};
  const double area_n = sim.coefficients().area_n;
  const NeighborList& list = sim.neighbors();
  UnionFind clusters(n);  // over ranks (id order), so the roots do not depend on the storage order
  UnionFind whole(n);     // the same over all pairs in range, whatever the states: attached or detached
  std::vector<std::tuple<std::int64_t, std::int64_t, double>> contacts;
  for (int i = 0; i < list.rows(); ++i) {
    const std::size_t a = static_cast<std::size_t>(i);
    for (int k = list.offset()[i]; k < list.offset()[i + 1]; ++k) {
      const std::size_t b = static_cast<std::size_t>(list.index()[k]);
      if (b <= a && list.kind() == NeighborKind::full) continue;  // a full list holds each pair twice
      const Vec3 d = minimum_image(bv, Vec3{p.x[a] - p.x[b], p.y[a] - p.y[b], p.z[a] - p.z[b]});
      if (norm(d) >= range(p.radius[a], p.radius[b])) continue;
      whole.unite(rank[a], rank[b]);
      if (st[a] == kThird && st[b] == kThird) {
        clusters.unite(rank[a], rank[b]);
      } else if ((st[a] == kBottom && st[b] == kTop) || (st[a] == kTop && st[b] == kBottom)) {
        // The pair's contact cross-section A_N = sqrt(2) r_eff^2 / (1 - 2 nu), r_eff = min(r_i, r_j): paper
        // A eqs 14-15 (the area its normal stiffness, eq 7, acts over).
        const double r_eff = std::min(p.radius[a], p.radius[b]);
        contacts.emplace_back(std::min(p.id[a], p.id[b]), std::max(p.id[a], p.id[b]), area_n * r_eff * r_eff);
      }
    }
  }
  std::sort(contacts.begin(), contacts.end());
  out.contact_pairs = static_cast<long>(contacts.size());
  for (const auto& c : contacts) out.contact_area += std::get<2>(c);

  // 3. Volumes, transfer and the third body's clusters, in id order.
  std::vector<double> cluster_volume(n, 0.0), from_bottom(n, 0.0), from_top(n, 0.0), from_neither(n, 0.0);
  std::vector<double> cluster_work(n, 0.0);
  std::vector<long> cluster_count(n, 0);
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t i = order[k];
    const double v = sphere_volume(p.radius[i]);
    if (st[i] == kBottom) {
      out.bottom_volume += v;
      ++out.bottom_particles;
      if (origin[i] == kTop) out.to_bottom_volume += v;
    } else if (st[i] == kTop) {
      out.top_volume += v;
      ++out.top_particles;
      if (origin[i] == kBottom) out.to_top_volume += v;
    } else {
      out.third_volume += v;
      ++out.third_particles;
      const std::size_t r = static_cast<std::size_t>(clusters.find(static_cast<int>(k)));
      cluster_volume[r] += v;
      ++cluster_count[r];
      (origin[i] == kBottom ? from_bottom : origin[i] == kTop ? from_top : from_neither)[r] += v;
      cluster_work[r] += p.tangential_work[i] - joined_.at(p.id[i]);
    }
  }
  out.wear_volume = out.third_volume + out.to_bottom_volume + out.to_top_volume;
  const std::size_t bins = edges_.size() - 1;
  out.bin_clusters.assign(bins, 0.0);
  out.bin_volume.assign(bins, 0.0);
  std::size_t largest = n;
  for (std::size_t r = 0; r < n; ++r) {
    if (cluster_count[r] == 0) continue;
    ++out.clusters;
    if (largest == n || cluster_volume[r] > cluster_volume[largest]) largest = r;
    const double d = equivalent_diameter(cluster_volume[r]);
    const std::size_t at = static_cast<std::size_t>(std::upper_bound(edges_.begin(), edges_.end(), d) - edges_.begin());
    const std::size_t bin = at == 0 ? 0 : std::min(at - 1, bins - 1);
    out.bin_clusters[bin] += 1;
    out.bin_volume[bin] += cluster_volume[r];
  }
  // The clusters as wear particles, largest first (equal volumes: in the order of their smallest ids).
  for (std::size_t r = 0; r < n; ++r) {
    if (cluster_count[r] == 0) continue;
    SurfaceDebris c;
    c.particles = cluster_count[r];
    c.volume = cluster_volume[r];
    c.diameter = equivalent_diameter(c.volume);
    c.tangential_work = energy_ ? cluster_work[r] : kNaN;
    c.from_bottom = from_bottom[r] / c.volume;
    c.from_top = from_top[r] / c.volume;
    c.from_neither = from_neither[r] / c.volume;
    out.debris.push_back(c);
  }
  std::stable_sort(out.debris.begin(), out.debris.end(),
                   [](const SurfaceDebris& a, const SurfaceDebris& b) { return a.volume > b.volume; });
  for (std::size_t k = 0; k < out.debris.size(); ++k) out.debris[k].rank = static_cast<long>(k) + 1;
  if (largest < n) {
    out.largest_volume = cluster_volume[largest];
    out.largest_particles = cluster_count[largest];
    out.largest_diameter = equivalent_diameter(cluster_volume[largest]);
    out.largest_from_bottom = from_bottom[largest] / cluster_volume[largest];
    out.largest_from_top = from_top[largest] / cluster_volume[largest];
    out.largest_from_neither = from_neither[largest] / cluster_volume[largest];
  }

  // 4. Attached or detached, by the graph of all pairs in range: which driven groups each component holds.
  std::vector<char> holds_bottom(n, 0), holds_top(n, 0);
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t i = order[k];
    const std::size_t r = static_cast<std::size_t>(whole.find(static_cast<int>(k)));
    if (p.group[i] == bottom_driven_) holds_bottom[r] = 1;
    if (p.group[i] == top_driven_) holds_top[r] = 1;
  }
  std::vector<double> component_volume(n, 0.0);
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t i = order[k];
    const std::size_t r = static_cast<std::size_t>(whole.find(static_cast<int>(k)));
    const bool root = r == k;  // a component's root is its first member in id order
    if (holds_bottom[r] && holds_top[r]) {
      ++out.bridging_particles;
      out.bridging_clusters += root;
    } else if (holds_bottom[r]) {
      ++out.attached_bottom_particles;
    } else if (holds_top[r]) {
      ++out.attached_top_particles;
    } else {
      const double v = sphere_volume(p.radius[i]);
      ++out.detached_particles;
      out.detached_clusters += root;
      out.detached_volume += v;
      component_volume[r] += v;
    }
  }
  for (std::size_t r = 0; r < n; ++r)
    out.largest_detached_volume = std::max(out.largest_detached_volume, component_volume[r]);

  // 5. The faces' roughness: the envelope of each body's spheres by state (the third body and the material in
  // flight are no part of a face; transferred material is part of the face it moves with).
  std::vector<char> bottom_mask(n, 0), top_mask(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const int st = state_.at(p.id[i]);
    bottom_mask[i] = st == kBottom;
    top_mask[i] = st == kTop;
  }
  auto face = [&](const std::vector<char>& mask, EnvelopeSide side, HeightField& keep) {
    if (std::find(mask.begin(), mask.end(), 1) == mask.end()) {  // no particle moves with this body: no face
      keep = HeightField{};
      keep.normal_axis = s_.normal_axis;
      keep.n_a = keep.n_b = 1;
      keep.h = {kNaN};
      return std::vector<double>(face_columns("").size(), kNaN);
    }
    keep = surface_envelope(sim.box(), s_.normal_axis, side, spacing_, std::span<const double>(p.x.data(), n),
                            std::span<const double>(p.y.data(), n), std::span<const double>(p.z.data(), n),
                            std::span<const double>(p.radius.data(), n), std::span<const char>(mask))
               .field;
    return face_values(measure_face(keep, fit_shortest_, fit_longest_));
  };
  const std::vector<double> b = face(bottom_mask, EnvelopeSide::top, bottom_face_);
  const std::vector<double> t = face(top_mask, EnvelopeSide::bottom, top_face_);
  out.bottom_mean_height = b[0], out.bottom_rms_height = b[1], out.bottom_rms_slope = b[2];
  out.bottom_hurst = b[3], out.bottom_hurst_error = b[4], out.bottom_hurst_hhcf = b[5];
  out.top_mean_height = t[0], out.top_rms_height = t[1], out.top_rms_slope = t[2];
  out.top_hurst = t[3], out.top_hurst_error = t[4], out.top_hurst_hhcf = t[5];
  samples_.push_back(std::move(out));
  return samples_.back();
}

const ColumnTable& SurfaceCensus::table() {
  static const ColumnTable t{
      "surfaces.csv",
      "One row every `surfaces.every` steps: the census of the interface (`surfaces:` section). The states bottom, "
      "top and third body come from f, each particle's displacement along the slide over the window as a "
      "fraction of the top driven group's (both relative to the bottom driven group's); the clusters from the "
      "graph of pairs in interaction range among third-body particles; attached, bridging and detached from the "
      "graph of pairs in range among all particles, whatever their f (README: which columns use which).",
      {
          {"step", "-", "time step number", ""},
          {"time", "s", "simulated time", ""},
          {"slide", "m",
           "sliding distance: the top driven group's displacement along the slide less the bottom one's, since the "
           "start",
           ""},
          {"tangential_force", "N", "the top driven group's reaction along the sliding axis", ""},
          {"normal_force", "N", "the top driven group's reaction along the normal axis", ""},
          {"friction_coefficient", "-", "|tangential_force| / |normal_force| (0 while the normal force is 0)", ""},
          {"tangential_work", "J",
           "work the drives did along the slide since the first sample: minus each driven group's reaction times "
           "its displacement, trapezoid between samples",
           ""},
          {"contact_tangential_work", "J",
           "work the pairs' relative motion did against their tangential forces over the whole system since the "
           "start: the sum of the energy accounting's per-particle tangential_work, exact at every step (NaN with "
           "`output.energy: false`)",
           ""},
          {"contact_pairs", "-",
           "pairs in interaction range joining a particle of the bottom body to one of the top body (by state)", ""},
          {"contact_area", "m^2",
           "the real contact area: those pairs' contact cross-sections A_N summed (paper A eqs 14-15)", ""},
          {"bottom_volume", "m^3", "volume of the particles moving with the bottom body (f < moving min)", ""},
          {"top_volume", "m^3", "volume of the particles moving with the top body (f > moving max)", ""},
          {"third_volume", "m^3", "volume of the particles moving with neither body: the third body", ""},
          {"transferred_to_bottom", "m^3", "volume that started in the top body and moves with the bottom body", ""},
          {"transferred_to_top", "m^3", "volume that started in the bottom body and moves with the top body", ""},
          {"wear_volume", "m^3", "third_volume + transferred_to_bottom + transferred_to_top", ""},
          {"bottom_particles", "-", "particles moving with the bottom body", ""},
          {"top_particles", "-", "particles moving with the top body", ""},
          {"third_particles", "-", "particles of the third body", ""},
          {"clusters", "-", "the third body's clusters: its particles connected by pairs in interaction range", ""},
          {"largest_cluster_volume", "m^3", "volume of the largest cluster (0: no third body)", ""},
          {"largest_cluster_particles", "-", "its particles", ""},
          {"largest_cluster_diameter", "m", "its equivalent diameter (6 V / pi)^(1/3)", ""},
          {"largest_from_bottom", "-", "share of its volume that started in the bottom body", ""},
          {"largest_from_top", "-", "share of its volume that started in the top body", ""},
          {"largest_from_neither", "-", "share of its volume that started in neither body", ""},
          {"attached_bottom_particles", "-",
           "particles connected by pairs in range to the bottom driven group and not to the top one (any f)", ""},
          {"attached_top_particles", "-",
           "particles connected by pairs in range to the top driven group and not to the bottom one (any f)", ""},
          {"bridging_particles", "-",
           "particles connected by pairs in range to both driven groups: the interface still holds together "
           "through them",
           ""},
          {"bridging_clusters", "-", "the connected components holding members of both driven groups", ""},
          {"detached_particles", "-", "particles connected by pairs in range to neither driven group (any f)", ""},
          {"detached_volume", "m^3", "their volume (4/3 pi r^3 summed)", ""},
          {"detached_clusters", "-", "the components they form: the detached wear particles", ""},
          {"largest_detached_volume", "m^3", "volume of the largest of them (0: none)", ""},
          {"window_time", "s", "the time f's displacements span: the window, or less before it has filled", ""},
          {"window_slide", "m", "the driven groups' relative slide over that time", ""},
          {"classified", "-",
           "1 when f classified the particles; 0 when window_slide was below `surfaces.min_slide` and each kept its "
           "last state",
           ""},
          {"bottom_mean_height", "m",
           "the bottom body's face (the upper envelope of the spheres moving with it, on the `surfaces.roughness` "
           "grid): its mean height along the normal",
           ""},
          {"bottom_rms_height", "m", "its root mean square height about that mean", ""},
          {"bottom_rms_slope", "-",
           "its root mean square slope, from its spectrum over the wavelengths down to the shortest of "
           "`surfaces.roughness.fit` (the spheres' own caps are steeper at any roughness)",
           ""},
          {"bottom_hurst", "-",
           "its Hurst exponent H from the radially averaged PSD, C ~ q^-2(1+H), fitted over `surfaces.roughness.fit` "
           "(NaN: too few points with power, a flat face)",
           ""},
          {"bottom_hurst_error", "-", "the fit's standard error of H", ""},
          {"bottom_hurst_hhcf", "-",
           "H from the height-height correlation along the first in-plane axis, ~ r^2H (a check on bottom_hurst)",
           ""},
          {"top_mean_height", "m", "the top body's face (the lower envelope of the spheres moving with it)", ""},
          {"top_rms_height", "m", "its root mean square height", ""},
          {"top_rms_slope", "-", "its root mean square slope", ""},
          {"top_hurst", "-", "its Hurst exponent from the PSD", ""},
          {"top_hurst_error", "-", "the fit's standard error", ""},
          {"top_hurst_hhcf", "-", "H from the height-height correlation", ""},
      }};
  return t;
}

std::vector<double> SurfaceCensus::row(const SurfaceSample& s) {
  std::vector<double> v;
  v.reserve(table().columns.size());
  for_each_column(s, [&](const auto& x) { v.push_back(static_cast<double>(x)); });
  return v;
}

const ColumnTable& SurfaceCensus::histogram_table() {
  static const ColumnTable t{
      "surfaces_histogram.csv",
      "With `surfaces:`, one row per sample and equivalent-diameter bin (`surfaces.histogram_bins`): the third "
      "body's clusters by size.",
      {
          {"step", "-", "time step number of the sample", ""},
          {"time", "s", "simulated time", ""},
          {"bin", "-", "the bin's index, from 0", ""},
          {"diameter_min", "m", "the bin's lower edge (the first bin also holds smaller clusters)", ""},
          {"diameter_max", "m", "its upper edge (the last bin also holds larger clusters)", ""},
          {"clusters", "-", "clusters whose equivalent diameter (6 V / pi)^(1/3) falls in the bin", ""},
          {"volume", "m^3", "their volume", ""},
      }};
  return t;
}

std::vector<std::vector<double>> SurfaceCensus::histogram_rows(const SurfaceSample& s) const {
  std::vector<std::vector<double>> rows;
  for (std::size_t k = 0; k + 1 < edges_.size(); ++k)
    rows.push_back({static_cast<double>(s.step), s.time, static_cast<double>(k), edges_[k], edges_[k + 1],
                    k < s.bin_clusters.size() ? s.bin_clusters[k] : 0.0,
                    k < s.bin_volume.size() ? s.bin_volume[k] : 0.0});
  return rows;
}

const ColumnTable& SurfaceCensus::debris_table() {
  static const ColumnTable t{
      "surfaces_debris.csv",
      "With `surfaces:`, one row per sample and third-body cluster (by f: the third body's particles joined by "
      "pairs in range), largest first: the wear particles with the tangential work done on them, for V_d against "
      "W_t (Garcia-Suarez et al. 2023: V_d ~ W_t^(3/2) in 3D).",
      {
          {"step", "-", "time step number of the sample", ""},
          {"slide", "m", "the sample's sliding distance (surfaces.csv's slide)", ""},
          {"rank", "-", "the cluster's rank by volume in its sample, 1 for the largest", ""},
          {"particles", "-", "its particles", ""},
          {"volume", "m^3", "its volume V_d (4/3 pi r^3 summed)", ""},
          {"diameter", "m", "its equivalent diameter (6 V_d / pi)^(1/3)", ""},
          {"tangential_work", "J",
           "W_t: its members' tangential_work (the energy accounting's per-particle column) since each joined the "
           "third body, summed (NaN with `output.energy: false`)",
           ""},
          {"from_bottom", "-", "share of its volume that started in the bottom body", ""},
          {"from_top", "-", "share of its volume that started in the top body", ""},
          {"from_neither", "-", "share of its volume that started in neither body", ""},
      }};
  return t;
}

std::vector<std::vector<double>> SurfaceCensus::debris_rows(const SurfaceSample& s) {
  std::vector<std::vector<double>> rows;
  for (const SurfaceDebris& d : s.debris) {
    std::vector<double> row{static_cast<double>(s.step), s.slide};
    for_each_debris_value(d, [&](const auto& x) { row.push_back(static_cast<double>(x)); });
    rows.push_back(std::move(row));
  }
  return rows;
}

PowerFit SurfaceCensus::debris_fit() const {
  std::vector<double> w, v;
  if (!samples_.empty() && energy_)
    for (const SurfaceDebris& d : samples_.back().debris) {
      w.push_back(d.tangential_work);
      v.push_back(d.volume);
    }
  return fit_power_law(w, v);
}

PowerFit SurfaceCensus::wear_fit() const {
  std::vector<double> w, v;
  for (const SurfaceSample& x : samples_) {
    w.push_back(x.tangential_work);
    v.push_back(x.wear_volume);
  }
  return fit_power_law(w, v);
}

std::string SurfaceCensus::report() const {
  std::ostringstream os;
  os.precision(3);
  if (samples_.empty()) return "surfaces: no sample taken";
  const SurfaceSample& l = samples_.back();
  os << "surfaces: at step " << l.step << " (slide " << l.slide << " m): wear volume " << l.wear_volume
     << " m^3 = third body " << l.third_volume << " m^3 (" << l.third_particles << " particles in " << l.clusters
     << (l.clusters == 1 ? " cluster" : " clusters") << ") + transferred " << l.to_bottom_volume
     << " m^3 to the bottom body, " << l.to_top_volume << " m^3 to the top body\n";
  if (l.clusters > 0)
    os << "surfaces: the largest cluster holds " << l.largest_particles << " particles, " << l.largest_volume
       << " m^3 (equivalent diameter " << l.largest_diameter << " m; " << l.largest_from_bottom
       << " of it from the bottom body, " << l.largest_from_top << " from the top body, " << l.largest_from_neither
       << " from neither)\n";
  double mu = 0;
  long sliding = 0;
  for (const SurfaceSample& x : samples_)
    if (x.slide != 0) mu += x.friction_coefficient, ++sliding;
  os << "surfaces: friction coefficient " << l.friction_coefficient;
  if (sliding > 0) os << " (mean over the " << sliding << " samples since the slide began " << mu / sliding << ")";
  os << ", real contact area " << l.contact_area << " m^2 over " << l.contact_pairs << " pairs, tangential work "
     << l.tangential_work << " J by the drives";
  if (energy_) os << ", " << l.contact_tangential_work << " J against the contacts' tangential forces";
  const PowerFit fit = wear_fit();
  if (fit.made)
    os << "; wear volume ~ W_t^" << fit.exponent << " (least squares in log-log over " << fit.points << " samples)";
  else
    os << "; too few samples with wear and work for a power law";
  // By the graph of all pairs in range.
  os << "\nsurfaces: by the pairs in range, " << l.detached_particles << " particles (" << l.detached_volume
     << " m^3) are detached in " << l.detached_clusters
     << (l.detached_clusters == 1 ? " wear particle" : " wear particles");
  if (l.detached_clusters > 0) os << " (the largest " << l.largest_detached_volume << " m^3)";
  os << "; " << l.attached_bottom_particles << " are attached to the bottom body, " << l.attached_top_particles
     << " to the top body";
  if (l.bridging_clusters > 0)
    os << "; the interface still bridges: " << l.bridging_particles << " particles in " << l.bridging_clusters
       << (l.bridging_clusters == 1 ? " cluster" : " clusters") << " holding both driven groups";
  else
    os << "; nothing bridges the two bodies";
  // Each wear particle's volume against the tangential work done on it (the last sample's clusters).
  os << "\nsurfaces: wear particles against their tangential work (surfaces_debris.csv): ";
  const PowerFit d = debris_fit();
  if (!energy_)
    os << "no W_t, the energy accounting is off (`output.energy: false`): the particles' tangential_work column "
          "is not kept, so surfaces_debris.csv's tangential_work is NaN and no V_d(W_t) is fitted";
  else if (d.made)
    os << "V_d = " << d.prefactor << " W_t^" << d.exponent << " (SI; least squares in log-log over the last sample's "
       << d.points << " clusters with W_t > 0; Garcia-Suarez et al. 2023 find 3/2 in 3D)";
  else
    os << "too few of the last sample's clusters (" << d.points << ") with W_t > 0 and different W_t for a power law";
  if (!l.classified)
    os << "\nsurfaces: the states of the last sample are those of an earlier one: the driven groups slid "
       << l.window_slide << " m over its window, less than min_slide (" << min_slide_ << " m)";
  return os.str();
}

namespace {

// The values of a sample in a checkpoint: its row, the work's carry-over, its histogram (its clusters go
// apart, as many as it has).
std::size_t row_values() { return SurfaceCensus::table().columns.size(); }
constexpr std::size_t kExtraValues = 3;

std::vector<double> sample_values(const SurfaceSample& s) {
  std::vector<double> v = SurfaceCensus::row(s);
  v.insert(v.end(), {s.top_shift, s.bottom_force, s.bottom_shift});
  v.insert(v.end(), s.bin_clusters.begin(), s.bin_clusters.end());
  v.insert(v.end(), s.bin_volume.begin(), s.bin_volume.end());
  return v;
}

SurfaceSample sample_from(const double* v, std::size_t bins) {
  SurfaceSample s;
  std::size_t k = 0;
  for_each_column(s, [&](auto& x) { assign_value(x, v[k++]); });
  s.top_shift = v[k];
  s.bottom_force = v[k + 1];
  s.bottom_shift = v[k + 2];
  k += kExtraValues;
  s.bin_clusters.assign(v + k, v + k + bins);
  s.bin_volume.assign(v + k + bins, v + k + 2 * bins);
  return s;
}

}  // namespace

SurfaceCensusState SurfaceCensus::state() const {
  SurfaceCensusState st;
  std::vector<std::pair<std::int64_t, int>> states(state_.begin(), state_.end());
  std::sort(states.begin(), states.end());
  for (const auto& [id, value] : states) {
    st.state_id.push_back(id);
    st.state_value.push_back(value);
  }
  for (const auto& [t, positions] : history_) {
    std::vector<std::pair<std::int64_t, Vec3>> by_id(positions.begin(), positions.end());
    std::sort(by_id.begin(), by_id.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    st.history_time.push_back(t);
    st.history_count.push_back(static_cast<std::int64_t>(by_id.size()));
    for (const auto& [id, x] : by_id) {
      st.history_id.push_back(id);
      st.history_position.insert(st.history_position.end(), {x.x, x.y, x.z});
    }
  }
  st.bin_edges = edges_;
  for (const SurfaceSample& s : samples_) {
    const std::vector<double> v = sample_values(s);
    st.samples.insert(st.samples.end(), v.begin(), v.end());
  }
  st.sample_count = samples_.size();
  std::vector<std::pair<std::int64_t, double>> joined(joined_.begin(), joined_.end());
  std::sort(joined.begin(), joined.end());
  for (const auto& [id, w] : joined) {
    st.joined_id.push_back(id);
    st.joined_value.push_back(w);
  }
  for (const SurfaceSample& s : samples_) {
    st.debris_count.push_back(static_cast<std::int64_t>(s.debris.size()));
    for (const SurfaceDebris& d : s.debris)
      for_each_debris_value(d, [&](const auto& x) { st.debris.push_back(static_cast<double>(x)); });
  }
  return st;
}

void SurfaceCensus::restore(const SurfaceCensusState& st, const std::string& path) {
  auto check = [&](bool ok, const std::string& what) {
    if (!ok) throw input_error("restart", path, "is not a sound checkpoint: surfaces/" + what);
  };
  check(st.state_id.size() == st.state_value.size(), "state_id and state_value differ in length");
  for (std::int64_t v : st.state_value) check(v >= kBottom && v <= kThird, "state_value holds a value not 0, 1 or 2");
  check(st.history_time.size() == st.history_count.size(), "history_time and history_count differ in length");
  std::int64_t ids = 0;
  for (std::int64_t c : st.history_count) {
    check(c >= 0, "history_count holds a negative count");
    ids += c;
  }
  check(st.history_id.size() == static_cast<std::size_t>(ids) && st.history_position.size() == 3 * st.history_id.size(),
        "history_id / history_position do not hold history_count's particles");
  bool edges_ok = st.bin_edges.size() >= 2;
  for (std::size_t k = 1; k < st.bin_edges.size() && edges_ok; ++k) edges_ok = st.bin_edges[k] > st.bin_edges[k - 1];
  check(edges_ok, "bin_edges are not at least two increasing values");
  const std::size_t bins = st.bin_edges.size() - 1;
  const std::size_t per_sample = row_values() + kExtraValues + 2 * bins;
  check(st.samples.size() == per_sample * st.sample_count,
        "samples do not hold " + std::to_string(per_sample) + " values per sample");
  check(st.joined_id.size() == st.joined_value.size(), "joined_id and joined_value differ in length");
  check(st.debris_count.size() == st.sample_count, "debris_count does not hold one count per sample");
  std::int64_t clusters = 0;
  for (std::int64_t c : st.debris_count) {
    check(c >= 0, "debris_count holds a negative count");
    clusters += c;
  }
  check(st.debris.size() == kDebrisValues * static_cast<std::size_t>(clusters),
        "debris does not hold " + std::to_string(kDebrisValues) + " values per cluster of debris_count");
  std::unordered_map<std::int64_t, int> states;
  for (std::size_t k = 0; k < st.state_id.size(); ++k) states[st.state_id[k]] = static_cast<int>(st.state_value[k]);
  std::deque<std::pair<double, std::unordered_map<std::int64_t, Vec3>>> history;
  std::size_t at = 0;
  for (std::size_t s = 0; s < st.history_time.size(); ++s) {
    std::unordered_map<std::int64_t, Vec3> positions;
    positions.reserve(static_cast<std::size_t>(st.history_count[s]));
    for (std::int64_t k = 0; k < st.history_count[s]; ++k, ++at)
      positions.emplace(st.history_id[at], Vec3{st.history_position[3 * at], st.history_position[3 * at + 1],
                                                st.history_position[3 * at + 2]});
    history.emplace_back(st.history_time[s], std::move(positions));
  }
  std::vector<SurfaceSample> samples;
  std::size_t value = 0;
  for (std::size_t k = 0; k < st.sample_count; ++k) {
    samples.push_back(sample_from(&st.samples[per_sample * k], bins));
    for (std::int64_t c = 0; c < st.debris_count[k]; ++c) {
      SurfaceDebris d;
      for_each_debris_value(d, [&](auto& x) { assign_value(x, st.debris[value++]); });
      samples.back().debris.push_back(d);
    }
  }
  std::unordered_map<std::int64_t, double> joined;
  for (std::size_t k = 0; k < st.joined_id.size(); ++k) joined[st.joined_id[k]] = st.joined_value[k];
  // Particles the checkpoint does not name keep the state they start with.
  for (const auto& [id, value] : states) state_[id] = value;
  edges_ = st.bin_edges;
  history_ = std::move(history);
  samples_ = std::move(samples);
  joined_ = std::move(joined);
}

void write_surface_state(h5::Location& at, const SurfaceCensusState& st) {
  h5::Group g = at.create_group("surfaces");
  g.write("state_id", st.state_id);
  g.write("state_value", st.state_value);
  g.write("history_time", st.history_time);
  g.write("history_count", st.history_count);
  g.write("history_id", st.history_id);
  g.write("history_position", st.history_position);
  g.write("bin_edges", st.bin_edges);
  g.write("samples", st.samples);
  g.write_scalar<std::int64_t>("sample_count", static_cast<std::int64_t>(st.sample_count));
  g.write("joined_id", st.joined_id);
  g.write("joined_value", st.joined_value);
  g.write("debris_count", st.debris_count);
  g.write("debris", st.debris);
}

std::optional<SurfaceCensusState> read_surface_state(const h5::Location& at) {
  if (!at.has("surfaces")) return std::nullopt;
  const h5::Group g = at.open_group("surfaces");
  // A census written before 2026-12-07 (no graph columns, no tangential work per cluster): its samples do not fit
  // this version's rows, so the census starts afresh as from a checkpoint without one.
  if (!g.has("joined_id")) return std::nullopt;
  SurfaceCensusState st;
  st.state_id = g.read<std::int64_t>("state_id").values;
  st.state_value = g.read<std::int64_t>("state_value").values;
  st.history_time = g.read<double>("history_time").values;
  st.history_count = g.read<std::int64_t>("history_count").values;
  st.history_id = g.read<std::int64_t>("history_id").values;
  st.history_position = g.read<double>("history_position").values;
  st.bin_edges = g.read<double>("bin_edges").values;
  st.samples = g.read<double>("samples").values;
  const auto count = g.read_scalar<std::int64_t>("sample_count");
  if (count < 0) throw std::runtime_error("surfaces/sample_count is negative");
  st.sample_count = static_cast<std::size_t>(count);
  st.joined_id = g.read<std::int64_t>("joined_id").values;
  st.joined_value = g.read<double>("joined_value").values;
  st.debris_count = g.read<std::int64_t>("debris_count").values;
  st.debris = g.read<double>("debris").values;
  return st;
}

namespace {

// gnuplot's text for a power law V = c W^b drawn in the pictures' units (V' = V volume, W' = W energy:
// V' = c volume energy^-b W'^b), and its exponent for a title.
struct FitText {
  std::string function, exponent;
};
FitText fit_text(const PowerFit& fit, double volume, double energy) {
  std::ostringstream prefactor, power, exponent;
  prefactor.precision(17);
  power.precision(17);
  exponent.precision(4);
  prefactor << fit.prefactor * volume * std::pow(energy, -fit.exponent);
  power << fit.exponent;
  exponent << fit.exponent;
  return {prefactor.str() + " * x ** " + power.str(), exponent.str()};
}

// A panel with nothing to draw on a log scale (gnuplot refuses a plot without a point): its title and a line
// saying why, on empty axes.
void empty_panel(std::ostream& script, const std::string& title, const std::string& why) {
  script << "unset logscale\n"
         << "set title '" << title << "' noenhanced\n"
         << "set xrange [0:1]\nset yrange [0:1]\n"
         << "set label 1 '" << why << "' at graph 0.5, 0.5 center noenhanced\n"
         << "plot 2 notitle\n"
         << "unset label 1\nset autoscale xy\n";
}

}  // namespace

std::string draw_surface_pictures(const std::string& dir, const SurfaceCensus& census, const PictureUnits& u) {
  namespace fs = std::filesystem;
  const fs::path d(dir);
  const bool si = u.length_name == "nm";
  const double volume = u.length * u.length * u.length, area = u.length * u.length, energy = u.length * u.force;
  const std::string length_name = u.length_name, volume_name = si ? "nm^3" : "length^3",
                    area_name = si ? "nm^2" : "length^2", energy_name = si ? "fJ" : "energy";
  const PowerFit fit = census.wear_fit();
  std::ofstream script(d / "surfaces.gp");
  script << "# debris_dem's wear census pictures: run `gnuplot surfaces.gp` in this directory.\n"
         << "set terminal pngcairo size 1200,1350 font ',11'\n"
         << "set output 'surfaces.png'\n"
         << "set datafile separator ','\n"
         << "set multiplot layout 3,2\n"
         << "set key bottom right\n"
         << "set title 'wear volume against the slide' noenhanced\n"
         << "set xlabel 'sliding distance (" << length_name << ")'\n"
         << "set ylabel 'volume (" << volume_name << ")' noenhanced\n"
         << "plot 'surfaces.csv' using (column('slide') * " << u.length << "):(column('wear_volume') * " << volume
         << ") with lines lw 2 title 'wear volume', '' using (column('slide') * " << u.length
         << "):(column('third_volume') * " << volume << ") with lines title 'third body', '' using (column('slide') * "
         << u.length << "):((column('transferred_to_bottom') + column('transferred_to_top')) * " << volume
         << ") with lines title 'transferred'\n"
         << "set xlabel 'tangential work (" << energy_name << ")' noenhanced\n"
         << "# the samples with wear and work (a log scale has no place for 0)\n"
         << "both(w, v) = w > 0 && v > 0\n";
  if (fit.points == 0) {
    empty_panel(script, "wear volume against tangential work", "no sample with both wear and work yet");
  } else {
    script << "set logscale xy\n";
    if (fit.made) {
      const FitText f = fit_text(fit, volume, energy);
      script
          << "set title 'wear volume against tangential work: exponent " << f.exponent << " (" << fit.points
          << " samples)' noenhanced\n"
          << "fit_line(x) = " << f.function << "\n"
          << "plot 'surfaces.csv' using (both(column('tangential_work'), column('wear_volume')) ? "
          << "column('tangential_work') * " << energy << " : 1/0):(column('wear_volume') * " << volume
          << ") with points pt 7 ps 0.6 title 'samples', fit_line(x) with lines lw 2 title 'least-squares power law' "
          << "noenhanced\n";
    } else {
      script << "set title 'wear volume against tangential work: too few samples for a fit' noenhanced\n"
             << "plot 'surfaces.csv' using (both(column('tangential_work'), column('wear_volume')) ? "
             << "column('tangential_work') * " << energy << " : 1/0):(column('wear_volume') * " << volume
             << ") with points pt 7 ps 0.6 title 'samples'\n";
    }
  }
  script << "unset logscale\n"
         << "set key off\n"
         << "set xlabel 'sliding distance (" << length_name << ")'\n"
         << "# once sliding (before it, the normal force may be near 0 and the ratio meaningless)\n"
         << "set title 'friction coefficient (top driven group: |tangential| / |normal| reaction)' noenhanced\n"
         << "set ylabel 'friction coefficient'\n"
         << "plot 'surfaces.csv' using (column('slide') > 0 ? column('slide') * " << u.length
         << " : 1/0):(column('friction_coefficient')) with lines lw 2\n"
         << "set title 'real contact area' noenhanced\n"
         << "set ylabel 'area (" << area_name << ")' noenhanced\n"
         << "plot 'surfaces.csv' using (column('slide') * " << u.length << "):(column('contact_area') * " << area
         << ") with lines lw 2\n"
         << "# the two definitions of worn material side by side: f (third body) and the graph (detached)\n"
         << "set key top left\n"
         << "set title 'third body (by f), detached (by the pairs in range)' noenhanced\n"
         << "set ylabel 'volume (" << volume_name << ")' noenhanced\n"
         << "plot 'surfaces.csv' using (column('slide') * " << u.length << "):(column('third_volume') * " << volume
         << ") with lines lw 2 title 'third body', '' using (column('slide') * " << u.length
         << "):(column('detached_volume') * " << volume << ") with lines lw 2 title 'detached', '' using "
         << "(column('slide') * " << u.length << "):(column('largest_detached_volume') * " << volume
         << ") with lines title 'largest detached'\n";
  // The last sample's wear particles: V_d against W_t (surfaces_debris.csv).
  const PowerFit debris = census.debris_fit();
  const long last = census.samples().empty() ? -1 : census.samples().back().step;
  script << "set key bottom right\n"
         << "set xlabel 'tangential work on the particle W_t (" << energy_name << ")' noenhanced\n"
         << "set ylabel 'its volume V_d (" << volume_name << ")' noenhanced\n";
  if (!census.energy_accounting()) {
    empty_panel(script, "wear particles: V_d against W_t",
                "no W_t: the energy accounting is off (output.energy: false)");
  } else if (debris.points == 0) {
    empty_panel(script, "wear particles: V_d against W_t", "no third-body cluster with W_t > 0 at the last sample");
  } else {
    script << "set logscale xy\n";
    const std::string title = "wear particles at step " + std::to_string(last) + ": ";
    if (debris.made) {
      const FitText f = fit_text(debris, volume, energy);
      script << "set title '" << title << "V_d ~ W_t^" << f.exponent << " (" << debris.points
             << " clusters; 3D theory: 3/2)' noenhanced\n"
             << "debris_line(x) = " << f.function << "\n";
    } else {
      script << "set title '" << title << "too few for a fit of V_d(W_t)' noenhanced\n";
    }
    script << "plot 'surfaces_debris.csv' using (column('step') == " << last
           << " && column('tangential_work') > 0 ? column('tangential_work') * " << energy
           << " : 1/0):(column('volume') * " << volume << ") with points pt 7 ps 0.8 title 'third-body clusters'"
           << (debris.made ? ", debris_line(x) with lines lw 2 title 'least-squares power law' noenhanced" : "") << "\n"
           << "unset logscale\n";
  }
  script << "unset multiplot\n";
  script.close();
  if (!script) return "pictures: cannot write " + (d / "surfaces.gp").string();
  const GnuplotRun run = run_gnuplot(dir, "surfaces.gp", "surfaces.log");
  if (!run.found)
    return "pictures skipped: gnuplot not found (Debian: apt install gnuplot-nox); run `gnuplot surfaces.gp` in " +
           dir + " later";
  if (run.status != 0) return "pictures failed: gnuplot could not draw surfaces.png (see " + dir + "/surfaces.log)";
  return "pictures: " + (d / "surfaces.png").string();
}

}  // namespace debris
