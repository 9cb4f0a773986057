#include "scenarios/common/dem/wear_analysis.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>
#include <stdexcept>

#include "core/error.hpp"
#include "core/io/hdf5_file.hpp"
#include "core/io/input.hpp"
#include "scenarios/common/dem/dem_simulation.hpp"

namespace debris {

namespace {

constexpr double kPi = 3.14159265358979323846;

double comp(const Vec3& v, int a) { return a == 0 ? v.x : (a == 1 ? v.y : v.z); }

Vec3 axis_vector(int a) { return {a == 0 ? 1.0 : 0.0, a == 1 ? 1.0 : 0.0, a == 2 ? 1.0 : 0.0}; }

int read_axis(const InputNode& n, const std::string& key, const std::string& fallback) {
  const std::string a = n.choice(key, {"x", "y", "z"}, fallback);
  return a == "x" ? 0 : (a == "y" ? 1 : 2);
}

void read_range(const InputNode& n, const std::string& key, double& lo, double& hi) {
  if (!n.has(key)) return;
  const std::vector<double> v = n.numbers(key, units::dimensionless);
  if (v.size() != 2 || !(v[0] < v[1]) || !std::isfinite(v[0]) || !std::isfinite(v[1]))
    throw input_error(n.path() + "." + key, std::to_string(v.size()) + " values", "give [min, max] with min < max");
  lo = v[0];
  hi = v[1];
}

// Pair key from two permanent ids (each below 2^32, checked at set-up).
std::uint64_t pair_key(std::int64_t a, std::int64_t b) {
  if (a > b) std::swap(a, b);
  return (static_cast<std::uint64_t>(a) << 32) | static_cast<std::uint64_t>(b);
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
  void unite(int a, int b) {
    a = find(a);
    b = find(b);
    if (a != b) parent[static_cast<std::size_t>(std::max(a, b))] = std::min(a, b);
  }
};

}  // namespace

const char* verdict_name(WearVerdict v) {
  switch (v) {
    case WearVerdict::ductile: return "ductile";
    case WearVerdict::detached: return "detached, not rolling";
    case WearVerdict::rolling: return "rolling wear particle";
  }
  return "?";
}

WearSettings read_wear_settings(const InputNode& n) {
  WearSettings s;
  s.every = n.integer("every");
  if (s.every < 1) throw input_error(n.path() + ".every", std::to_string(s.every), "must be >= 1 (steps)");
  s.bottom_wall = n.string("bottom_wall");
  s.top_wall = n.string("top_wall");
  s.junction_label = n.string("junction_label");
  s.sliding_axis = read_axis(n, "sliding_axis", "x");
  s.normal_axis = read_axis(n, "normal_axis", "y");
  if (s.sliding_axis == s.normal_axis)
    throw input_error(n.path() + ".normal_axis", std::string(1, "xyz"[s.normal_axis]), "must differ from sliding_axis");
  s.persistence = n.quantity("persistence", units::time);
  if (!(s.persistence > 0) || !std::isfinite(s.persistence))
    throw input_error(n.path() + ".persistence", format_value(s.persistence), "must be > 0 (a time)");
  s.window = n.quantity("window", units::time);
  if (!(s.window > 0) || !std::isfinite(s.window))
    throw input_error(n.path() + ".window", format_value(s.window), "must be > 0 (a time)");
  s.min_volume_fraction = n.quantity("min_volume_fraction", units::dimensionless, s.min_volume_fraction);
  if (!(s.min_volume_fraction > 0 && s.min_volume_fraction <= 1))
    throw input_error(n.path() + ".min_volume_fraction", format_value(s.min_volume_fraction), "must be in (0, 1]");
  read_range(n, "moving", s.moving_min, s.moving_max);
  if (!(s.moving_min > 0 && s.moving_max < 1))
    throw input_error(n.path() + ".moving", "[" + format_value(s.moving_min) + ", " + format_value(s.moving_max) + "]",
                      "must lie inside (0, 1): fractions of the wall's displacement");
  read_range(n, "centre_speed", s.centre_speed_min, s.centre_speed_max);
  read_range(n, "rolling_number", s.rolling_number_min, s.rolling_number_max);
  s.max_residual = n.quantity("max_residual", units::dimensionless, s.max_residual);
  if (!(s.max_residual > 0)) throw input_error(n.path() + ".max_residual", format_value(s.max_residual), "must be > 0");
  s.residual_floor = n.quantity("residual_floor", units::dimensionless, s.residual_floor);
  if (!(s.residual_floor > 0) || !std::isfinite(s.residual_floor))
    throw input_error(n.path() + ".residual_floor", format_value(s.residual_floor),
                      "must be > 0 (a fraction of the walls' relative displacement over the window)");
  s.verdict_span = n.quantity("verdict_span", units::time, 0.5 * s.window);
  if (!(s.verdict_span >= 0) || !std::isfinite(s.verdict_span))
    throw input_error(n.path() + ".verdict_span", format_value(s.verdict_span), "must be >= 0 (a time; 0: the last sample alone)");
  return s;
}

void document_wear_settings(KeyReference& r) {
  const WearSettings d;  // the reader's defaults
  const auto range = [](double lo, double hi) {
    std::string t = "[";  // appended: GCC 12 warns falsely (-Wrestrict) on "[" + std::string
    t += format_value(lo);
    t += ", ";
    t += format_value(hi);
    t += "]";
    return t;
  };
  r.describe_section("wear",
                     "The wear analysis of a sheared junction (paper A, section 4): every `every` steps it samples "
                     "each particle's displacement along the sliding axis over the last `window`, as a fraction f of "
                     "the top wall's, fits the body moving with neither wall by a rigid motion, writes a row of "
                     "`wear.csv`, and the run ends with its verdict: ductile, detached (not rolling) or rolling wear "
                     "particle. Every threshold below is a setting.");
  r.key("wear").is(KeyKind::section).fallback_is("no analysis")
      .means("the wear analysis of a sheared junction, written to `wear.csv`, with a verdict at the end");
  r.key("wear.every").is(KeyKind::integer).allowed(">= 1").means("steps between two samples");
  r.key("wear.bottom_wall").is(KeyKind::text)
      .allowed("a group of `groups`, not `top_wall`, holding no particle of the junction")
      .means("the group of the fixed wall: f = 0");
  r.key("wear.top_wall").is(KeyKind::text)
      .allowed("a group of `groups`, not `bottom_wall`, holding no particle of the junction")
      .means("the group of the sliding wall: f = 1; its reaction and displacement head the row");
  r.key("wear.junction_label").is(KeyKind::text).allowed("a label of `labels` that holds particles")
      .means("the label of the junction's particles, whose volume is the reference of every share");
  r.key("wear.sliding_axis").one_of({"x", "y", "z"}).fallback("x").means("the axis the top wall slides along");
  r.key("wear.normal_axis").one_of({"x", "y", "z"}).fallback("y").allowed("not `sliding_axis`")
      .means("the axis normal to the sliding surfaces");
  r.key("wear.persistence").is(KeyKind::quantity).in(units::time).allowed("> 0")
      .means("diagnostics only: a pair in interaction range at every sample this long counts as a bond");
  r.key("wear.window").is(KeyKind::quantity).in(units::time).allowed("> 0")
      .means("the displacements over this last stretch of the run decide (many vibration periods)");
  r.key("wear.min_volume_fraction").is(KeyKind::quantity).in(units::dimensionless)
      .fallback(format_value(d.min_volume_fraction)).allowed("(0, 1]")
      .means("the least share of the junction's volume a wear particle holds");
  r.key("wear.moving").is(KeyKind::numbers).in(units::dimensionless).fallback(range(d.moving_min, d.moving_max))
      .allowed("[min, max], 0 < min < max < 1")
      .means("the particles with min < f < max move with neither wall: the candidate bodies");
  r.key("wear.centre_speed").is(KeyKind::numbers).in(units::dimensionless)
      .fallback(range(d.centre_speed_min, d.centre_speed_max)).allowed("[min, max], min < max")
      .means("a rolling body's centre displacement over the top wall's (rolling without slip: 0.5)");
  r.key("wear.rolling_number").is(KeyKind::numbers).in(units::dimensionless)
      .fallback(range(d.rolling_number_min, d.rolling_number_max)).allowed("[min, max], min < max")
      .means("a rolling body's 2 R omega / v (rolling without slip: 1)");
  r.key("wear.max_residual").is(KeyKind::quantity).in(units::dimensionless).fallback(format_value(d.max_residual))
      .allowed("> 0")
      .means("the most rms residual of the rigid fit over the displacement spread for a rigid body (rigid ~0, "
             "a sheared layer ~0.7)");
  r.key("wear.residual_floor").is(KeyKind::quantity).in(units::dimensionless)
      .fallback(format_value(d.residual_floor)).allowed("> 0")
      .means("the fit's scale is at least this fraction of the walls' relative displacement over the window");
  r.key("wear.verdict_span").is(KeyKind::quantity).in(units::time).fallback_is("half of `window`")
      .allowed(">= 0 (0: the last sample alone)")
      .means("the verdict needs a rigid candidate at every sample of this last stretch, judged on its means");
}

WearAnalysis::WearAnalysis(const WearSettings& settings, const DemSimulation& sim) : s_(settings) {
  if (s_.verdict_span < 0) s_.verdict_span = 0.5 * s_.window;
  bottom_ = sim.groups().find(s_.bottom_wall);
  top_ = sim.groups().find(s_.top_wall);
  if (bottom_ < 0) throw input_error("wear.bottom_wall", s_.bottom_wall, "no such group");
  if (top_ < 0) throw input_error("wear.top_wall", s_.top_wall, "no such group");
  if (bottom_ == top_) throw input_error("wear.top_wall", s_.top_wall, "must differ from bottom_wall");
  const Particles& p = sim.particles();
  const std::vector<std::string>& labels = p.label_names;
  const auto it = std::find(labels.begin(), labels.end(), s_.junction_label);
  if (it == labels.end()) throw input_error("wear.junction_label", s_.junction_label, "no such label");
  const int junction = static_cast<int>(it - labels.begin()) + 1;  // label k names label_names[k - 1]
  std::vector<std::pair<std::int64_t, double>> members;  // (id, volume)
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p.id[i] < 0 || p.id[i] >= (std::int64_t{1} << 32))
      throw input_error("wear", "particle id " + std::to_string(p.id[i]), "the analysis needs ids in [0, 2^32)");
    if (p.label[i] != junction) continue;
    junction_ids_.insert(p.id[i]);
    members.emplace_back(p.id[i], 4.0 / 3.0 * kPi * p.radius[i] * p.radius[i] * p.radius[i]);
  }
  // Summed in id order: a restart, whose particles are stored in another order than at step 0, gets the
  // same bits.
  std::sort(members.begin(), members.end());
  for (const auto& m : members) junction_volume_ += m.second;
  if (junction_ids_.empty()) throw input_error("wear.junction_label", s_.junction_label, "labels no particle");
  // A wall reaching into the junction (thicker than its slab) would hold the junction rigidly.
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p.label[i] != junction || (p.group[i] != bottom_ && p.group[i] != top_)) continue;
    const bool top_wall = p.group[i] == top_;
    throw input_error(top_wall ? "wear.top_wall" : "wear.bottom_wall", top_wall ? s_.top_wall : s_.bottom_wall,
                      "the wall holds particle id " + std::to_string(p.id[i]) + " of the junction '" +
                          s_.junction_label + "': it is thicker than its slab (the wall must end before the junction)");
  }
}

const WearSample& WearAnalysis::sample(const DemSimulation& sim) {
  const Particles& p = sim.particles();
  const Box& box = sim.box();
  const BoxView bv = box.view();
  const long step = sim.step_count();
  const std::size_t n = p.size();
  WearSample out;
  out.step = step;
  out.time = sim.time();
  const Group& top = sim.groups().list[static_cast<std::size_t>(top_)];
  out.wall_force = comp(top.reaction, s_.sliding_axis);
  out.wall_slide = comp(top.displacement, s_.sliding_axis);
  out.wall_normal = comp(top.displacement, s_.normal_axis);

  // 1. Pairs in interaction range now; each keeps the step since which it has been in range at every sample.
  const CohesiveCutoff range{sim.coefficients()};
  const NeighborList& list = sim.neighbors();
  std::unordered_map<std::uint64_t, long> streak;
  streak.reserve(streak_.size() + 16);
  const long persistence_steps = static_cast<long>(std::ceil(s_.persistence / sim.dt() - 1e-9));
  UnionFind clusters(n);
  std::vector<std::pair<int, int>> in_range;  // the pairs in range now, each once (step 3 joins bodies by them)
  for (int i = 0; i < list.rows(); ++i) {
    const std::size_t a = static_cast<std::size_t>(i);
    for (int k = list.offset()[i]; k < list.offset()[i + 1]; ++k) {
      const std::size_t b = static_cast<std::size_t>(list.index()[k]);
      if (b <= a && list.kind() == NeighborKind::full) continue;  // a full list holds each pair twice
      const Vec3 d = minimum_image(bv, Vec3{p.x[a] - p.x[b], p.y[a] - p.y[b], p.z[a] - p.z[b]});
      if (norm(d) >= range(p.radius[a], p.radius[b])) continue;
      in_range.emplace_back(static_cast<int>(a), static_cast<int>(b));
      const std::uint64_t key = pair_key(p.id[a], p.id[b]);
      const auto old = streak_.find(key);
      const long since = old == streak_.end() ? step : old->second;
      streak.emplace(key, since);
      if (step - since >= persistence_steps) {
        clusters.unite(static_cast<int>(a), static_cast<int>(b));
        ++out.bonded_pairs;
      }
    }
  }
  streak_ = std::move(streak);

  // 2. Bond clusters (diagnostics): which hold a wall, where the junction's volume is bonded.
  std::vector<char> holds_bottom(n, 0), holds_top(n, 0);
  std::vector<double> junction_part(n, 0.0);
  std::vector<double> volume_of(n);
  std::vector<char> in_junction(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    volume_of[i] = 4.0 / 3.0 * kPi * p.radius[i] * p.radius[i] * p.radius[i];
    in_junction[i] = junction_ids_.count(p.id[i]) ? 1 : 0;
    const std::size_t r = static_cast<std::size_t>(clusters.find(static_cast<int>(i)));
    if (in_junction[i]) junction_part[r] += volume_of[i];
    if (p.group[i] == bottom_) holds_bottom[r] = 1;
    if (p.group[i] == top_) holds_top[r] = 1;
  }
  for (std::size_t r = 0; r < n; ++r) {
    if (holds_bottom[r] && holds_top[r]) out.walls_joined = true;
    if (holds_bottom[r]) out.junction_in_bottom += junction_part[r] / junction_volume_;
    if (holds_top[r]) out.junction_in_top += junction_part[r] / junction_volume_;
    if (!holds_bottom[r] && !holds_top[r]) out.junction_in_third += junction_part[r] / junction_volume_;
  }

  // 3. The third body, by its motion over the last `window`: every particle's displacement along the sliding
  // axis as a fraction f of the top wall's (relative to the bottom wall's); particles moving with neither
  // wall (f_min < f < f_max) joined through pairs in range now; the component holding most of the junction,
  // fitted by a rigid-body motion (rotation and translation, exact for any angle: Kabsch).
  std::vector<Vec3> unwrapped(n);
  std::unordered_map<std::int64_t, Vec3> now;
  now.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    unwrapped[i] = Vec3{p.x[i] + p.ix[i] * bv.len[0], p.y[i] + p.iy[i] * bv.len[1], p.z[i] + p.iz[i] * bv.len[2]};
    now.emplace(p.id[i], unwrapped[i]);
  }
  history_.push_back({out.time, std::move(now)});
  // Keep the snapshots back to one window ago (and the one just before, the reference).
  while (history_.size() > 2 && out.time - history_[1].first >= s_.window * (1 - 1e-9)) history_.pop_front();
  const auto& [t0, ref] = history_.front();
  const double interval = out.time - t0;
  double wall_shift = 0, base_shift = 0, wall_mass = 0, base_mass = 0;
  for (std::size_t i = 0; i < n && interval > 0; ++i) {
    const auto it = ref.find(p.id[i]);
    if (it == ref.end()) continue;
    const double dx = comp(unwrapped[i] - it->second, s_.sliding_axis);
    if (p.group[i] == top_) wall_shift += p.mass[i] * dx, wall_mass += p.mass[i];
    if (p.group[i] == bottom_) base_shift += p.mass[i] * dx, base_mass += p.mass[i];
  }
  if (wall_mass > 0) wall_shift /= wall_mass;
  if (base_mass > 0) base_shift /= base_mass;
  const double relative = wall_shift - base_shift;
  // Only over a whole window, and only while the walls slide relative to each other.
  if (interval >= s_.window * (1 - 1e-9) && std::abs(relative) > 0) {
    std::vector<char> between(n, 0);
    std::vector<Vec3> start(n);
    for (std::size_t i = 0; i < n; ++i) {
      const auto it = ref.find(p.id[i]);
      if (it == ref.end() || p.group[i] == bottom_ || p.group[i] == top_) continue;
      start[i] = it->second;
      const double f = (comp(unwrapped[i] - start[i], s_.sliding_axis) - base_shift) / relative;
      between[i] = f > s_.moving_min && f < s_.moving_max ? 1 : 0;
    }
    UnionFind bodies(n);
    for (const auto& [a, b] : in_range)
      if (between[static_cast<std::size_t>(a)] && between[static_cast<std::size_t>(b)]) bodies.unite(a, b);
    std::vector<double> share(n, 0.0);
    std::vector<long> count(n, 0);
    for (std::size_t i = 0; i < n; ++i) {
      if (!between[i]) continue;
      const std::size_t r = static_cast<std::size_t>(bodies.find(static_cast<int>(i)));
      count[r] += 1;
      if (in_junction[i]) share[r] += volume_of[i];
    }
    std::size_t third = n;
    for (std::size_t r = 0; r < n; ++r)
      if (count[r] >= 4 && share[r] > 0 && (third == n || share[r] > share[third])) third = r;
    if (third < n) {
      std::vector<std::size_t> body;
      for (std::size_t i = 0; i < n; ++i)
        if (between[i] && static_cast<std::size_t>(bodies.find(static_cast<int>(i))) == third) body.push_back(i);
      // Its members joined through minimum images, but their unwrapped positions may sit in different periodic
      // images (a body across a periodic face): move each, now and at the start alike, to the image nearest
      // the first member, so the fit sees one body (bodies are far smaller than half the box).
      const Vec3 anchor = unwrapped[body.front()];
      for (std::size_t i : body) {
        Vec3 shift{};
        for (int a = 0; a < 3; ++a) {
          if (!bv.periodic[a]) continue;
          const double k = std::round((comp(unwrapped[i], a) - comp(anchor, a)) / bv.len[a]);
          (a == 0 ? shift.x : (a == 1 ? shift.y : shift.z)) = -k * bv.len[a];
        }
        unwrapped[i] += shift;
        start[i] += shift;
      }
      double mass = 0, volume = 0;
      Vec3 c0{}, c1{};
      double lo = 1e300, hi = -1e300;
      for (std::size_t i : body) {
        mass += p.mass[i];
        volume += volume_of[i];
        c0 += p.mass[i] * start[i];
        c1 += p.mass[i] * unwrapped[i];
        const double h = comp(unwrapped[i], s_.normal_axis);
        lo = std::min(lo, h - p.radius[i]);
        hi = std::max(hi, h + p.radius[i]);
      }
      c0 = (1.0 / mass) * c0;
      c1 = (1.0 / mass) * c1;
      // Kabsch: the rotation R maximising sum m (r1 - c1) . R (r0 - c0), from the SVD of their covariance.
      Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
      for (std::size_t i : body) {
        const Vec3 a = start[i] - c0, b = unwrapped[i] - c1;
        H += p.mass[i] * Eigen::Vector3d(a.x, a.y, a.z) * Eigen::Vector3d(b.x, b.y, b.z).transpose();
      }
      const Eigen::JacobiSVD<Eigen::Matrix3d> svd(H, Eigen::ComputeFullU | Eigen::ComputeFullV);
      Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
      D(2, 2) = (svd.matrixV() * svd.matrixU().transpose()).determinant() < 0 ? -1.0 : 1.0;
      const Eigen::Matrix3d R = svd.matrixV() * D * svd.matrixU().transpose();
      // The fit's error against the motion it had to explain: the spread of the displacements about the
      // centre's (a rigid body: ~0; a sheared layer: ~0.7, its strain is what no rotation fits), or a quarter
      // of the walls' relative displacement when that spread is smaller (a body translating without spin).
      double res2 = 0, spread2 = 0;
      for (std::size_t i : body) {
        const Vec3 a = start[i] - c0, b = unwrapped[i] - c1;
        const Eigen::Vector3d e = R * Eigen::Vector3d(a.x, a.y, a.z) - Eigen::Vector3d(b.x, b.y, b.z);
        res2 += p.mass[i] * e.squaredNorm();
        spread2 += p.mass[i] * norm2(b - a);
      }
      const double scale = std::max(std::sqrt(spread2 / mass), s_.residual_floor * std::abs(relative));
      // The rotation angle about the rolling axis n x s (positive when the body rolls with the wall).
      const Eigen::AngleAxisd aa(R);
      const Vec3 roll_axis = cross(axis_vector(s_.normal_axis), axis_vector(s_.sliding_axis));
      const double angle = aa.angle() * (aa.axis()(0) * roll_axis.x + aa.axis()(1) * roll_axis.y +
                                         aa.axis()(2) * roll_axis.z);
      // For a body rolling without slip f grows linearly across its height, so the particles kept
      // (f_min < f < f_max) span that fraction of it: the rolling radius is their extent over it, halved.
      const double radius = 0.5 * (hi - lo) / (s_.moving_max - s_.moving_min);
      out.kinematics = true;
      out.third_particles = static_cast<long>(body.size());
      out.third_volume = share[third] / junction_volume_;
      out.third_from_junction = share[third] / volume;
      out.spin = angle / interval;
      out.centre_speed = (comp(c1 - c0, s_.sliding_axis) - base_shift) / relative;
      out.rolling_number = 2.0 * radius * angle / relative;
      out.residual = std::sqrt(res2 / mass) / scale;
    }
  }

  // 4. This sample's own verdict: a third body (enough of the junction, moving rigidly) that rolls, or not.
  auto judge = [&](double volume, double residual, double centre_speed, double rolling_number) {
    if (volume < s_.min_volume_fraction || residual > s_.max_residual) return WearVerdict::ductile;
    const bool rolls = centre_speed >= s_.centre_speed_min && centre_speed <= s_.centre_speed_max &&
                       rolling_number >= s_.rolling_number_min && rolling_number <= s_.rolling_number_max;
    return rolls ? WearVerdict::rolling : WearVerdict::detached;
  };
  samples_.push_back(out);
  WearSample& last = samples_.back();
  if (last.kinematics)
    last.sample_verdict = judge(last.third_volume, last.residual, last.centre_speed, last.rolling_number);

  // 5. The verdict over the last verdict_span: a candidate holding enough of the junction at every sample
  // of it (and samples back to its start), judged on its means.
  const double from = last.time - s_.verdict_span * (1 + 1e-9);
  std::size_t first = samples_.size() - 1;
  while (first > 0 && samples_[first - 1].time >= from) --first;
  const bool covered = samples_[first].time <= last.time - s_.verdict_span * (1 - 1e-9);
  bool held = covered;
  double residual = 0, centre = 0, rolling = 0, min_volume = 1;
  for (std::size_t k = first; k < samples_.size() && held; ++k) {
    const WearSample& w = samples_[k];
    held = w.kinematics && w.third_volume >= s_.min_volume_fraction;
    residual += w.residual;
    centre += w.centre_speed;
    rolling += w.rolling_number;
    min_volume = std::min(min_volume, w.third_volume);
  }
  if (held) {
    const double count = static_cast<double>(samples_.size() - first);
    last.mean_residual = residual / count;
    last.mean_centre_speed = centre / count;
    last.mean_rolling_number = rolling / count;
    last.verdict = judge(min_volume, last.mean_residual, last.mean_centre_speed, last.mean_rolling_number);
  }
  return last;
}

const ColumnTable& WearAnalysis::table() {
  static const ColumnTable t{
      "wear.csv",
      "One row every `wear.every` steps: the sheared junction's state and the verdict (`wear:` section; "
      "verdicts are 0 ductile, 1 detached, 2 rolling wear particle).",
      {
          {"step", "-", "time step number", ""},
          {"time", "s", "simulated time", ""},
          {"wall_force", "N", "the top wall's reaction along the sliding axis (the tangential force)", ""},
          {"wall_slide", "m", "the top wall's displacement along the sliding axis", ""},
          {"wall_normal", "m", "the top wall's displacement along the normal axis", ""},
          {"bonded_pairs", "-", "pairs in interaction range at every sample of the last `wear.persistence`", ""},
          {"walls_joined", "-", "1 when one cluster of bonded pairs holds both walls, else 0", ""},
          {"junction_in_bottom", "-", "share of the junction's volume in the bottom wall's cluster", ""},
          {"junction_in_top", "-", "share of the junction's volume in the top wall's cluster", ""},
          {"junction_in_third", "-", "share of the junction's volume bonded to neither wall", ""},
          {"third_particles", "-", "particles of the candidate third body over the window (0: none)", ""},
          {"third_volume", "-", "the junction's volume the candidate holds, over the junction's volume", ""},
          {"third_from_junction", "-", "share of the candidate's volume that started in the junction", ""},
          {"centre_speed", "-", "the candidate's centre displacement along the slide over the top wall's", ""},
          {"spin", "rad/s", "the candidate's spin about normal x sliding direction, positive when it rolls with the wall", ""},
          {"rolling_number", "-", "2 R spin / v: 1 when it rolls without slip", ""},
          {"residual", "-", "rms residual of the candidate's rigid-motion fit over the window, scaled", ""},
          {"verdict", "-", "the run's verdict at this sample, over the last `wear.verdict_span`", ""},
          {"sample_verdict", "-", "the verdict of this sample's fit alone", ""},
          {"mean_centre_speed", "-", "mean centre_speed over the verdict span", ""},
          {"mean_rolling_number", "-", "mean rolling_number over the verdict span", ""},
          {"mean_residual", "-", "mean residual over the verdict span", ""},
      }};
  return t;
}

std::vector<double> WearAnalysis::row(const WearSample& s) {
  return {static_cast<double>(s.step), s.time, s.wall_force, s.wall_slide, s.wall_normal,
          static_cast<double>(s.bonded_pairs), s.walls_joined ? 1.0 : 0.0, s.junction_in_bottom, s.junction_in_top,
          s.junction_in_third, static_cast<double>(s.third_particles), s.third_volume, s.third_from_junction,
          s.centre_speed, s.spin, s.rolling_number, s.residual, static_cast<double>(static_cast<int>(s.verdict)),
          static_cast<double>(static_cast<int>(s.sample_verdict)), s.mean_centre_speed, s.mean_rolling_number,
          s.mean_residual};
}

WearVerdict WearAnalysis::verdict() const { return samples_.empty() ? WearVerdict::ductile : samples_.back().verdict; }

long WearAnalysis::detection_index() const {
  long first = -1;
  for (long k = static_cast<long>(samples_.size()) - 1; k >= 0; --k) {
    if (samples_[static_cast<std::size_t>(k)].verdict == WearVerdict::ductile) break;
    first = k;
  }
  return first;
}

std::string WearAnalysis::report() const {
  std::ostringstream os;
  os.precision(3);
  if (samples_.empty()) return "wear: no sample taken";
  const WearSample& last = samples_.back();
  os << "wear: verdict " << verdict_name(last.verdict) << " at step " << last.step << " (t = " << last.time
     << " s, the top wall slid " << last.wall_slide << " m)\n";
  if (last.kinematics)
    os << "wear: over the last " << s_.window << " s, the candidate third body holds " << last.third_volume
       << " of the junction's volume [>= " << s_.min_volume_fraction << "] (" << last.third_particles << " particles, "
       << last.third_from_junction << " of its volume from the junction); rigid-fit residual " << last.residual
       << " [<= " << s_.max_residual << "], centre speed " << last.centre_speed << " of the wall's ["
       << s_.centre_speed_min << ", " << s_.centre_speed_max << "], rolling number " << last.rolling_number << " ["
       << s_.rolling_number_min << ", " << s_.rolling_number_max << "]\n";
  else
    os << "wear: no candidate third body over the last " << s_.window << " s\n";
  if (last.verdict != WearVerdict::ductile)
    os << "wear: over the last " << s_.verdict_span << " s (the verdict's span) its means: residual "
       << last.mean_residual << ", centre speed " << last.mean_centre_speed << ", rolling number "
       << last.mean_rolling_number << "\n";
  else
    os << "wear: no rigid candidate holding enough of the junction at every sample of the last "
       << s_.verdict_span << " s (the verdict's span)\n";
  const long k = detection_index();
  if (k >= 0) {
    const WearSample& d = samples_[static_cast<std::size_t>(k)];
    os << "wear: a rigid third body since t = " << d.time << " s (slide " << d.wall_slide
       << " m; the window reaches back " << s_.window << " s from there)\n";
  }
  os << "wear: bonds (pairs in range for " << s_.persistence << " s) hold " << last.junction_in_bottom
     << " of the junction's volume to the bottom wall, " << last.junction_in_top << " to the top wall, "
     << last.junction_in_third << " to neither; "
     << (last.walls_joined ? "a chain of them joins the walls" : "no chain of them joins the walls");
  return os.str();
}

namespace {

std::vector<double> sample_values(const WearSample& s) {
  std::vector<double> v = WearAnalysis::row(s);
  v.push_back(s.kinematics ? 1.0 : 0.0);
  return v;
}

WearVerdict verdict_of(double v) {
  const int k = static_cast<int>(v);
  if (v != k || k < 0 || k > 2) throw std::invalid_argument("no verdict");
  return static_cast<WearVerdict>(k);
}

WearSample sample_from(const double* v) {
  WearSample s;
  s.step = static_cast<long>(v[0]);
  s.time = v[1];
  s.wall_force = v[2];
  s.wall_slide = v[3];
  s.wall_normal = v[4];
  s.bonded_pairs = static_cast<long>(v[5]);
  s.walls_joined = v[6] != 0;
  s.junction_in_bottom = v[7];
  s.junction_in_top = v[8];
  s.junction_in_third = v[9];
  s.third_particles = static_cast<long>(v[10]);
  s.third_volume = v[11];
  s.third_from_junction = v[12];
  s.centre_speed = v[13];
  s.spin = v[14];
  s.rolling_number = v[15];
  s.residual = v[16];
  s.verdict = verdict_of(v[17]);
  s.sample_verdict = verdict_of(v[18]);
  s.mean_centre_speed = v[19];
  s.mean_rolling_number = v[20];
  s.mean_residual = v[21];
  s.kinematics = v[22] != 0;
  return s;
}

constexpr std::size_t kSampleValues = 23;

}  // namespace

WearState WearAnalysis::state() const {
  WearState st;
  std::vector<std::pair<std::uint64_t, long>> pairs(streak_.begin(), streak_.end());
  std::sort(pairs.begin(), pairs.end());
  for (const auto& [key, since] : pairs) {
    st.streak_a.push_back(static_cast<std::int64_t>(key >> 32));
    st.streak_b.push_back(static_cast<std::int64_t>(key & 0xffffffffu));
    st.streak_since.push_back(since);
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
  for (const WearSample& w : samples_) {
    const std::vector<double> v = sample_values(w);
    st.samples.insert(st.samples.end(), v.begin(), v.end());
  }
  st.sample_count = samples_.size();
  return st;
}

void WearAnalysis::restore(const WearState& st, const std::string& path) {
  auto check = [&](bool ok, const std::string& what) {
    if (!ok) throw input_error("restart", path, "is not a sound checkpoint: wear/" + what);
  };
  check(st.streak_a.size() == st.streak_b.size() && st.streak_a.size() == st.streak_since.size(),
        "streak arrays differ in length");
  check(st.history_time.size() == st.history_count.size(), "history_time and history_count differ in length");
  std::int64_t ids = 0;
  for (std::int64_t c : st.history_count) {
    check(c >= 0, "history_count holds a negative count");
    ids += c;
  }
  check(st.history_id.size() == static_cast<std::size_t>(ids) && st.history_position.size() == 3 * st.history_id.size(),
        "history_id / history_position do not hold history_count's particles");
  check(st.samples.size() == kSampleValues * st.sample_count, "samples do not hold " + std::to_string(kSampleValues) +
                                                                  " values per sample");
  std::unordered_map<std::uint64_t, long> streak;
  for (std::size_t k = 0; k < st.streak_a.size(); ++k) {
    check(st.streak_a[k] >= 0 && st.streak_b[k] >= 0 && st.streak_a[k] < (std::int64_t{1} << 32) &&
              st.streak_b[k] < (std::int64_t{1} << 32),
          "streak ids outside [0, 2^32)");
    streak.emplace(pair_key(st.streak_a[k], st.streak_b[k]), static_cast<long>(st.streak_since[k]));
  }
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
  std::vector<WearSample> samples;
  try {
    for (std::size_t k = 0; k < st.sample_count; ++k) samples.push_back(sample_from(&st.samples[kSampleValues * k]));
  } catch (const std::invalid_argument&) {
    check(false, "samples hold a verdict that is none of 0, 1, 2");
  }
  streak_ = std::move(streak);
  history_ = std::move(history);
  samples_ = std::move(samples);
}

void write_wear_state(h5::Location& at, const WearState& st) {
  h5::Group g = at.create_group("wear");
  g.write("streak_a", st.streak_a);
  g.write("streak_b", st.streak_b);
  g.write("streak_since", st.streak_since);
  g.write("history_time", st.history_time);
  g.write("history_count", st.history_count);
  g.write("history_id", st.history_id);
  g.write("history_position", st.history_position);
  g.write("samples", st.samples);
  g.write_scalar<std::int64_t>("sample_count", static_cast<std::int64_t>(st.sample_count));
}

std::optional<WearState> read_wear_state(const h5::Location& at) {
  if (!at.has("wear")) return std::nullopt;
  const h5::Group g = at.open_group("wear");
  WearState st;
  st.streak_a = g.read<std::int64_t>("streak_a").values;
  st.streak_b = g.read<std::int64_t>("streak_b").values;
  st.streak_since = g.read<std::int64_t>("streak_since").values;
  st.history_time = g.read<double>("history_time").values;
  st.history_count = g.read<std::int64_t>("history_count").values;
  st.history_id = g.read<std::int64_t>("history_id").values;
  st.history_position = g.read<double>("history_position").values;
  st.samples = g.read<double>("samples").values;
  const auto count = g.read_scalar<std::int64_t>("sample_count");
  if (count < 0) throw std::runtime_error("wear/sample_count is negative");
  st.sample_count = static_cast<std::size_t>(count);
  return st;
}

}  // namespace debris
