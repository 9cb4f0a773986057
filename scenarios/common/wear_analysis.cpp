#include "scenarios/common/wear_analysis.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>

#include "core/error.hpp"
#include "core/io/input.hpp"
#include "scenarios/common/dem_simulation.hpp"

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
  read_range(n, "centre_speed", s.centre_speed_min, s.centre_speed_max);
  read_range(n, "rolling_number", s.rolling_number_min, s.rolling_number_max);
  s.max_residual = n.quantity("max_residual", units::dimensionless, s.max_residual);
  if (!(s.max_residual > 0)) throw input_error(n.path() + ".max_residual", format_value(s.max_residual), "must be > 0");
  return s;
}

WearAnalysis::WearAnalysis(const WearSettings& settings, const DemSimulation& sim) : s_(settings) {
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
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p.id[i] < 0 || p.id[i] >= (std::int64_t{1} << 32))
      throw input_error("wear", "particle id " + std::to_string(p.id[i]), "the analysis needs ids in [0, 2^32)");
    if (p.label[i] != junction) continue;
    junction_ids_.insert(p.id[i]);
    junction_volume_ += 4.0 / 3.0 * kPi * p.radius[i] * p.radius[i] * p.radius[i];
  }
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
  const double wall_speed = comp(top.velocity, s_.sliding_axis);

  // 1. Pairs in interaction range now; each keeps the step since which it has been in range at every sample.
  const CohesiveCutoff range{sim.coefficients()};
  const NeighborList& list = sim.neighbors();
  std::unordered_map<std::uint64_t, long> streak;
  streak.reserve(streak_.size() + 16);
  const long persistence_steps = static_cast<long>(std::ceil(s_.persistence / sim.dt() - 1e-9));
  UnionFind clusters(n);
  for (int i = 0; i < list.rows(); ++i) {
    const std::size_t a = static_cast<std::size_t>(i);
    for (int k = list.offset()[i]; k < list.offset()[i + 1]; ++k) {
      const std::size_t b = static_cast<std::size_t>(list.index()[k]);
      if (b <= a && list.kind() == NeighborKind::full) continue;  // a full list holds each pair twice
      const Vec3 d = minimum_image(bv, Vec3{p.x[a] - p.x[b], p.y[a] - p.y[b], p.z[a] - p.z[b]});
      if (norm(d) >= range(p.radius[a], p.radius[b])) continue;
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

  // 2. Clusters: which hold a wall, and the largest third body.
  std::vector<char> holds_bottom(n, 0), holds_top(n, 0);
  std::vector<double> volume(n, 0.0), junction_part(n, 0.0);
  std::vector<long> members(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t r = static_cast<std::size_t>(clusters.find(static_cast<int>(i)));
    const double v = 4.0 / 3.0 * kPi * p.radius[i] * p.radius[i] * p.radius[i];
    volume[r] += v;
    members[r] += 1;
    if (junction_ids_.count(p.id[i])) junction_part[r] += v;
    if (p.group[i] == bottom_) holds_bottom[r] = 1;
    if (p.group[i] == top_) holds_top[r] = 1;
  }
  std::size_t third = n;
  for (std::size_t r = 0; r < n; ++r) {
    if (members[r] == 0) continue;
    if (holds_bottom[r] && holds_top[r]) out.walls_joined = true;
    if (holds_bottom[r]) out.junction_in_bottom += junction_part[r] / junction_volume_;
    if (holds_top[r]) out.junction_in_top += junction_part[r] / junction_volume_;
    if (!holds_bottom[r] && !holds_top[r]) {
      out.junction_in_third += junction_part[r] / junction_volume_;
      // The candidate: the free cluster holding most of the junction (a loose particle of a slab is not one).
      if (members[r] > 1 && junction_part[r] > 0 && (third == n || junction_part[r] > junction_part[third])) third = r;
    }
  }

  // 3. The candidate's rigid-body fit from the displacements since the last sample (unwrapped positions).
  std::unordered_map<std::int64_t, Vec3> now;
  now.reserve(n);
  std::vector<Vec3> unwrapped(n);
  for (std::size_t i = 0; i < n; ++i) {
    unwrapped[i] = Vec3{p.x[i] + p.ix[i] * bv.len[0], p.y[i] + p.iy[i] * bv.len[1], p.z[i] + p.iz[i] * bv.len[2]};
    now.emplace(p.id[i], unwrapped[i]);
  }
  const double interval = out.time - previous_time_;
  if (third < n) {
    out.third_particles = members[third];
    out.third_volume = junction_part[third] / junction_volume_;
    out.third_from_junction = junction_part[third] / volume[third];
    std::vector<std::size_t> body;
    for (std::size_t i = 0; i < n; ++i)
      if (static_cast<std::size_t>(clusters.find(static_cast<int>(i))) == third) body.push_back(i);
    bool all_known = !previous_.empty() && interval > 0 && body.size() >= 4;
    for (std::size_t i : body) all_known = all_known && previous_.count(p.id[i]) > 0;
    if (all_known) {
      // Least squares over the members, mass-weighted, about the centre c at the previous sample:
      // Delta r_i = Delta c + theta x rho_i, rho_i = r_i(prev) - c(prev).
      double mass = 0;
      Vec3 c{}, dc{};
      for (std::size_t i : body) {
        const Vec3 r0 = previous_.at(p.id[i]);
        mass += p.mass[i];
        c += p.mass[i] * r0;
        dc += p.mass[i] * (unwrapped[i] - r0);
      }
      c = (1.0 / mass) * c;
      dc = (1.0 / mass) * dc;
      Eigen::Matrix3d J = Eigen::Matrix3d::Zero();
      Eigen::Vector3d L = Eigen::Vector3d::Zero();
      double lo = 1e300, hi = -1e300;
      for (std::size_t i : body) {
        const Vec3 rho = previous_.at(p.id[i]) - c;
        const Vec3 u = unwrapped[i] - previous_.at(p.id[i]) - dc;
        const Eigen::Vector3d r(rho.x, rho.y, rho.z), w(u.x, u.y, u.z);
        J += p.mass[i] * (r.squaredNorm() * Eigen::Matrix3d::Identity() - r * r.transpose());
        L += p.mass[i] * r.cross(w);
        const double h = comp(unwrapped[i], s_.normal_axis);
        lo = std::min(lo, h - p.radius[i]);
        hi = std::max(hi, h + p.radius[i]);
      }
      const Eigen::Vector3d theta = J.ldlt().solve(L);
      double res2 = 0;
      for (std::size_t i : body) {
        const Vec3 rho = previous_.at(p.id[i]) - c;
        const Vec3 u = unwrapped[i] - previous_.at(p.id[i]) - dc;
        const Vec3 e = u - cross(Vec3{theta(0), theta(1), theta(2)}, rho);
        res2 += p.mass[i] * norm2(e);
      }
      const Vec3 roll_axis = cross(axis_vector(s_.normal_axis), axis_vector(s_.sliding_axis));
      const double spin = (theta(0) * roll_axis.x + theta(1) * roll_axis.y + theta(2) * roll_axis.z) / interval;
      const double radius = 0.5 * (hi - lo);
      out.kinematics = true;
      out.spin = spin;
      if (wall_speed != 0) {
        out.centre_speed = comp(dc, s_.sliding_axis) / interval / wall_speed;
        out.rolling_number = 2.0 * radius * spin / wall_speed;
        out.residual = std::sqrt(res2 / mass) / std::abs(wall_speed * interval);
      }
    }
  }
  previous_ = std::move(now);
  previous_time_ = out.time;

  // 4. Window averages over the samples that had a fit, and the verdict.
  samples_.push_back(out);
  WearSample& last = samples_.back();
  double sum_c = 0, sum_r = 0, sum_e = 0;
  int count = 0;
  for (auto it = samples_.rbegin(); it != samples_.rend() && last.time - it->time <= s_.window * (1 + 1e-9); ++it) {
    if (!it->kinematics || it->third_volume < s_.min_volume_fraction) continue;
    sum_c += it->centre_speed;
    sum_r += it->rolling_number;
    sum_e += it->residual;
    ++count;
  }
  if (count > 0) {
    last.mean_centre_speed = sum_c / count;
    last.mean_rolling_number = sum_r / count;
    last.mean_residual = sum_e / count;
  }
  if (last.third_volume >= s_.min_volume_fraction) {
    const bool rolls = count > 0 && last.mean_centre_speed >= s_.centre_speed_min &&
                       last.mean_centre_speed <= s_.centre_speed_max &&
                       last.mean_rolling_number >= s_.rolling_number_min &&
                       last.mean_rolling_number <= s_.rolling_number_max && last.mean_residual <= s_.max_residual;
    last.verdict = rolls ? WearVerdict::rolling : WearVerdict::detached;
  }
  return last;
}

std::vector<std::string> WearAnalysis::columns() {
  return {"step",           "time",           "wall_force",        "wall_slide",       "wall_normal",
          "bonded_pairs",   "walls_joined",   "junction_in_bottom", "junction_in_top", "junction_in_third",
          "third_particles", "third_volume",  "third_from_junction", "centre_speed",    "spin",
          "rolling_number", "residual",       "mean_centre_speed", "mean_rolling_number", "mean_residual",
          "verdict"};
}

std::vector<double> WearAnalysis::row(const WearSample& s) {
  return {static_cast<double>(s.step), s.time, s.wall_force, s.wall_slide, s.wall_normal,
          static_cast<double>(s.bonded_pairs), s.walls_joined ? 1.0 : 0.0, s.junction_in_bottom, s.junction_in_top,
          s.junction_in_third, static_cast<double>(s.third_particles), s.third_volume, s.third_from_junction,
          s.centre_speed, s.spin, s.rolling_number, s.residual, s.mean_centre_speed, s.mean_rolling_number,
          s.mean_residual, static_cast<double>(static_cast<int>(s.verdict))};
}

WearVerdict WearAnalysis::verdict() const { return samples_.empty() ? WearVerdict::ductile : samples_.back().verdict; }

long WearAnalysis::detection_index() const {
  long first = -1;
  for (long k = static_cast<long>(samples_.size()) - 1; k >= 0; --k) {
    if (samples_[static_cast<std::size_t>(k)].third_volume < s_.min_volume_fraction) break;
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
  os << "wear: junction volume bonded to the bottom " << last.junction_in_bottom << ", to the top "
     << last.junction_in_top << ", in third bodies " << last.junction_in_third
     << (last.walls_joined ? "; the walls are still bonded to each other" : "; the walls are not bonded to each other");
  const long k = detection_index();
  if (k >= 0) {
    const WearSample& d = samples_[static_cast<std::size_t>(k)];
    os << "\nwear: third body of " << last.third_volume << " junction volumes (" << last.third_particles
       << " particles, " << last.third_from_junction << " of it from the junction), seen from t = " << d.time
       << " s (slide " << d.wall_slide << " m; bonds take " << s_.persistence
       << " s to count, so it broke off about then minus that)\n"
       << "wear: over the last " << s_.window << " s: centre speed " << last.mean_centre_speed
       << " of the wall's [" << s_.centre_speed_min << ", " << s_.centre_speed_max << "], rolling number "
       << last.mean_rolling_number << " [" << s_.rolling_number_min << ", " << s_.rolling_number_max
       << "], rigid-fit residual " << last.mean_residual << " [< " << s_.max_residual << "]";
  }
  return os.str();
}

}  // namespace debris
