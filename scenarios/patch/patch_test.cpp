#include "scenarios/patch/patch_test.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <deque>
#include <limits>
#include <numbers>
#include <sstream>
#include <unordered_map>

#include "core/error.hpp"
#include "core/lattice.hpp"
#include "scenarios/common/dem/dem_simulation.hpp"

namespace debris {

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

double comp(const Vec3& v, int a) { return a == 0 ? v.x : (a == 1 ? v.y : v.z); }

std::string fmt(double v) {
  std::ostringstream os;
  os.precision(6);
  os << v;
  return os.str();
}

// Skin the engine picks by default (DemSettings::skin = 0): 0.2 r_min = 0.1 d_min, or 0.25 r_mean where
// d_max >= 2 d_min (DemSimulation::setup).
double default_skin(double d_min, double d_mean, double d_max) {
  return d_max >= 2 * d_min ? 0.125 * d_mean : 0.1 * d_min;
}

// Splits the particles into bottom wall (y < lo + t), top wall (y >= hi - t) and the deformable part, and
// fills the geometry of the sample. `key` names the input key for errors.
void assign_walls(PatchSample& s, double t, const std::string& key) {
  const double lo = s.box.lo().y, hi = s.box.hi().y;
  Particles& p = s.particles;
  s.groups = Groups{};
  s.bottom = s.groups.add(Group{"bottom", GroupMotion::frozen});
  s.top = s.groups.add(Group{"top", GroupMotion::frozen});
  double inner_bottom = -std::numeric_limits<double>::infinity();
  double inner_top = std::numeric_limits<double>::infinity();
  long nb = 0, nt = 0, nf = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p.y[i] < lo + t) {
      p.group[i] = s.bottom;
      inner_bottom = std::max(inner_bottom, p.y[i]);
      ++nb;
    } else if (p.y[i] >= hi - t) {
      p.group[i] = s.top;
      inner_top = std::min(inner_top, p.y[i]);
      ++nt;
    } else {
      p.group[i] = -1;
      ++nf;
    }
  }
  if (nb == 0 || nt == 0)
    throw input_error(
        key, fmt(t / s.d0),
        "the walls (this many mean diameters from the bottom and the top of the sample) hold no particle");
  if (nf == 0)
    throw input_error(key, fmt(t / s.d0), "the walls take the whole sample: no deformable part is left between them");
  s.free_count = nf;
  s.inner_bottom = inner_bottom;
  s.inner_top = inner_top;
  s.strain_height = inner_top - inner_bottom;
  s.area = s.box.length(0) * s.box.length(2);
}

}  // namespace

const char* patch_test_name(PatchTest t) {
  return t == PatchTest::elastic ? "elastic" : (t == PatchTest::tension ? "tension" : "shear");
}

const char* strength_outcome_name(StrengthOutcome o) {
  return o == StrengthOutcome::broke ? "broke" : (o == StrengthOutcome::peak_held ? "peak held" : "max strain");
}

std::string hcp_orientation_name(int c_axis) {
  if (c_axis == 1) return "c axis along the load (y), close-packed planes parallel to the walls";
  if (c_axis == 2) return "load in the close-packed plane along a*sqrt(3) (c axis along z)";
  return "load in the close-packed plane along the close-packed rows (c axis along x)";
}

PatchSample make_hcp_sample(const HcpSampleSpec& spec, const CohesiveMaterial& material) {
  material.validate("material");
  const double d_c = material.critical_diameter(), d_min = material.minimum_diameter();
  const double d0 = spec.d0;
  if (!(std::isfinite(d0) && d0 > 0))
    throw input_error("sample.d0", fmt(d0 / d_c) + " d_c", "must be a finite diameter > 0 (in units of d_c)");
  if (d0 < d_min * (1 - 1e-12))  // d0 = 0.2 d_c is d_min up to round-off
    throw input_error("sample.d0", fmt(d0 / d_c) + " d_c (d0 = " + fmt(d0) + ")",
                      "is below the minimum diameter d_min = 4 gamma / sigma_mN = " + fmt(d_min) + " = " +
                          fmt(d_min / d_c) +
                          " d_c (eq 19): particles would interact beyond their nearest neighbours; use d0 >= d_min");
  if (spec.c_axis < 0 || spec.c_axis > 2)
    throw input_error("sample.c_axis", std::to_string(spec.c_axis), "must be x, y or z");
  auto positive = [](double v, const char* key) {
    if (!(std::isfinite(v) && v > 0)) throw input_error(key, fmt(v), "must be > 0 (in units of d0)");
  };
  positive(spec.length, "sample.length");
  positive(spec.thickness, "sample.thickness");
  positive(spec.wall_thickness, "sample.wall_thickness");

  LatticeSpec lat;
  lat.kind = LatticeKind::hcp;
  lat.spacing = d0;
  lat.diameter = d0;
  lat.hcp_c_axis = spec.c_axis;
  const Vec3 period = lattice_period(lat);
  // A periodic axis must hold 2 (cutoff + skin) (core/neighbor_list): the widest pair reach of the engine.
  const CohesiveCoefficients coef = CohesiveCoefficients::from(material);
  const double reach = CohesiveCutoff{coef}(0.5 * d0, 0.5 * d0) + default_skin(d0, d0, d0);
  const double want[3] = {spec.length * d0, spec.length * d0, spec.thickness * d0};
  std::ostringstream note;
  for (int a = 0; a < 3; ++a) {
    const double per = comp(period, a);
    long n = std::max(1L, std::lround(want[a] / per));
    if (a != 1) {
      const long n_min = static_cast<long>(std::ceil(2.0 * reach / per - 1e-12));
      if (n < n_min) {
        note << "; "
             << "xyz"[a] << " raised to " << n_min << " periods (" << fmt(n_min * per / d0)
             << " d0) for the neighbour list";
        n = n_min;
      }
    }
    if (n > 100000) throw input_error(a == 2 ? "sample.thickness" : "sample.length", fmt(want[a] / d0), "is too large");
    lat.cells[static_cast<std::size_t>(a)] = static_cast<int>(n);
  }
  Lattice built = make_lattice(lat);

  PatchSample s;
  s.d0 = d0;
  s.box = Box(built.box.lo(), built.box.hi(), {true, false, true});
  s.particles = std::move(built.particles);
  s.volume_per_particle = built.box.volume() / static_cast<double>(s.particles.size());  // a^3 / sqrt 2
  s.volume_fraction = std::numbers::pi / (3.0 * std::numbers::sqrt2);
  assign_walls(s, spec.wall_thickness * d0, "sample.wall_thickness");
  const Vec3 len = s.box.length();
  std::ostringstream d;
  d << "HCP lattice, " << hcp_orientation_name(spec.c_axis) << "; " << fmt(len.x / d0) << " x " << fmt(len.y / d0)
    << " x " << fmt(len.z / d0) << " d0, " << s.particles.size() << " particles (" << s.free_count
    << " deformable), walls " << fmt(spec.wall_thickness) << " d0" << note.str();
  if (cohesive_delta_f(coef, d0) > (std::numbers::sqrt2 - 1.0) * d0)
    d << "; second neighbour shell within reach (d0 < "
      << fmt(cohesive_delta_f(coef, d0) / (std::numbers::sqrt2 - 1.0) / d_c)
      << " d_c): more than 12 interacting neighbours";
  s.description = d.str();
  return s;
}

PatchSample make_walled_sample(const Box& box, Particles particles, double wall_thickness,
                               const CohesiveMaterial& material, const std::string& key,
                               const std::string& description) {
  material.validate("material");
  if (!(box.periodic(0) && box.periodic(1) && box.periodic(2)))
    throw input_error(key, description, "the sample must be periodic in x, y and z (walls are cut from its y slabs)");
  if (particles.size() == 0) throw input_error(key, description, "holds no particle");
  if (!(std::isfinite(wall_thickness) && wall_thickness > 0))
    throw input_error("sample.wall_thickness", fmt(wall_thickness), "must be > 0 (in mean diameters)");
  const double d_min = material.minimum_diameter();
  double d_sum = 0, d_small = std::numeric_limits<double>::infinity();
  for (double r : particles.radius) {
    d_sum += 2 * r;
    d_small = std::min(d_small, 2 * r);
  }
  if (!(d_small >= d_min * (1 - 1e-12)))
    throw input_error(key, description,
                      "its smallest diameter " + fmt(d_small) + " is below d_min = 4 gamma / sigma_mN = " + fmt(d_min) +
                          " (eq 19) of the material");
  // The engine needs each periodic axis to hold 2 (cutoff + skin) of its widest pair (core/neighbor_list).
  const double r_max = *std::max_element(particles.radius.begin(), particles.radius.end());
  const double reach = CohesiveCutoff{CohesiveCoefficients::from(material)}(r_max, r_max) +
                       default_skin(d_small, d_sum / static_cast<double>(particles.size()), 2 * r_max);
  for (int a : {0, 2})
    if (box.length(a) < 2 * reach)
      throw input_error(key, description,
                        std::string("its box is ") + fmt(box.length(a)) + " long along " + "xyz"[a] +
                            ", less than 2 (cutoff + skin) = " + fmt(2 * reach) + " of its largest particles");
  box.wrap(particles);
  PatchSample s;
  s.d0 = d_sum / static_cast<double>(particles.size());
  s.volume_per_particle = box.volume() / static_cast<double>(particles.size());
  double solid = 0;
  for (double r : particles.radius) solid += 4.0 / 3.0 * std::numbers::pi * r * r * r;
  s.volume_fraction = solid / box.volume();
  s.box = Box(box.lo(), box.hi(), {true, false, true});
  for (int& iy : particles.iy) iy = 0;
  s.particles = std::move(particles);
  s.masses_from_density = false;
  assign_walls(s, wall_thickness * s.d0, "sample.wall_thickness");
  const Vec3 len = s.box.length();
  std::ostringstream d;
  d << description << "; " << fmt(len.x / s.d0) << " x " << fmt(len.y / s.d0) << " x " << fmt(len.z / s.d0)
    << " mean diameters, " << s.particles.size() << " particles (" << s.free_count << " deformable), walls "
    << fmt(wall_thickness) << " mean diameters";
  s.description = d.str();
  return s;
}

double patch_overlap_limit(double setting, double initial_overlap_over_r_min, double allowance) {
  return setting > 0 ? setting : std::max(0.0, initial_overlap_over_r_min) + allowance;
}

IsotropicModuli isotropic_from_stiffness(double c11, double c12) {
  const double sum = c11 + c12;
  return {(c11 - c12) * (c11 + 2 * c12) / sum, c12 / sum};
}

double target_strength(const CohesiveMaterial& m, PatchTest test, double d0) {
  if (test == PatchTest::elastic) return 0.0;
  const double base = test == PatchTest::tension ? m.tensile_strength : m.shear_strength;
  const double d_c = m.critical_diameter();
  return d0 > d_c ? base * std::pow(d0 / d_c, -m.scaling) : base;  // eq 20, r_i + r_j = d0
}

// ---------------------------------------------------------------------------------------------------------

namespace {

DemSimulation make_simulation(const PatchSample& s, const CohesiveMaterial& m, double time_step_fraction,
                              double damping) {
  DemSettings ds;
  ds.material = m;
  ds.time_step_fraction = time_step_fraction;
  ds.global_damping = damping;
  ds.masses_from_density = s.masses_from_density;
  return DemSimulation(s.box, s.particles, s.groups, ds);
}

// Per-particle mask of the deformable part, refreshed at every measurement (a neighbour rebuild re-sorts).
void free_mask(const Particles& p, std::vector<int>& mask) {
  mask.resize(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) mask[i] = p.group[i] < 0 ? 1 : 0;
}

double free_kinetic_energy(const Particles& p) {
  double ke = 0;
  for (std::size_t i = 0; i < p.size(); ++i)
    if (p.group[i] < 0) ke += 0.5 * p.mass[i] * (p.vx[i] * p.vx[i] + p.vy[i] * p.vy[i] + p.vz[i] * p.vz[i]);
  return ke;
}

// The engine's overlap limit is half the smaller radius, which no loaded calibrated lattice reaches. A
// sample that breaks in tension releases its elastic energy at once, though, and the halves snap back
// into each other: at nu = 1/4 and d0 = 0.67 d_c an HCP sample reached overlaps of 0.53 r that way (the
// kinetic energy of its deformable part went from 3.5 to 2.2e6 within 100 steps of the fracture). Strength
// tests therefore only stop at a whole radius (kOverlapAllowanceStrength) beyond the initial overlap.
void check_health(const DemSimulation& sim, const char* test, double overlap_limit) {
  const std::string problem = sim.health_check(overlap_limit);
  if (!problem.empty()) throw PatchRunError(std::string(test) + " test stopped: " + problem);
}

double initial_overlap_over_r_min(const DemSimulation& sim) {
  const auto& r = sim.particles().radius;
  return sim.diagnostics().max_overlap / *std::min_element(r.begin(), r.end());
}

void require_positive(double v, const char* key) {
  if (!(std::isfinite(v) && v > 0)) throw input_error(key, fmt(v), "must be > 0");
}

// Reference heights, by id, of the free particles at least interior_margin d0 from both walls: the bulk
// the elastic test fits its strain on. InputError when there is no such interior.
std::unordered_map<std::int64_t, double> interior_heights(const PatchSample& s, const ElasticSettings& es) {
  const double fit_lo = s.inner_bottom + es.interior_margin * s.d0, fit_hi = s.inner_top - es.interior_margin * s.d0;
  std::unordered_map<std::int64_t, double> y0;
  double y_min = std::numeric_limits<double>::infinity(), y_max = -y_min;
  for (std::size_t i = 0; i < s.particles.size(); ++i) {
    const double y = s.particles.y[i];
    if (s.particles.group[i] >= 0 || y < fit_lo || y > fit_hi) continue;
    y0[s.particles.id[i]] = y;
    y_min = std::min(y_min, y);
    y_max = std::max(y_max, y);
  }
  if (y0.size() < 2 || !(y_max - y_min > 0.1 * s.d0))
    throw input_error("elastic.interior_margin", fmt(es.interior_margin),
                      "leaves no interior between the walls to fit the strain on (the walls are " +
                          fmt(s.strain_height / s.d0) + " d0 apart): use a taller sample or a smaller margin");
  return y0;
}

}  // namespace

void validate(const ElasticSettings& es) {
  require_positive(es.stress, "elastic.stress");
  require_positive(es.time_step_fraction, "elastic.time_step_fraction");
  if (!(es.damping >= 0)) throw input_error("elastic.damping", fmt(es.damping), "must be >= 0 (a fraction of c_c)");
  if (es.sample_every < 1) throw input_error("elastic.sample_every", std::to_string(es.sample_every), "must be >= 1");
  if (es.window < 0) throw input_error("elastic.window", std::to_string(es.window), "must be >= 0 (0: automatic)");
  require_positive(es.tolerance, "elastic.tolerance");
  if (es.max_steps < 1) throw input_error("elastic.max_steps", std::to_string(es.max_steps), "must be >= 1");
  require_positive(es.max_strain, "elastic.max_strain");
  if (!(es.interior_margin >= 0)) throw input_error("elastic.interior_margin", fmt(es.interior_margin), "must be >= 0");
  if (!(std::isfinite(es.overlap_limit) && es.overlap_limit >= 0))
    throw input_error("elastic.overlap_limit", fmt(es.overlap_limit),
                      "must be >= 0 (in smallest radii; 0 or auto: the initial deepest overlap + " +
                          fmt(kOverlapAllowanceElastic) + ")");
}

void validate(const ElasticSettings& es, const PatchSample& s) {
  validate(es);
  interior_heights(s, es);
}

ElasticResult run_elastic_test(const PatchSample& s, const CohesiveMaterial& m, const ElasticSettings& es,
                               const PatchProgress& progress) {
  validate(es);

  const std::unordered_map<std::int64_t, double> y0 = interior_heights(s, es);

  const auto t0 = Clock::now();
  DemSimulation sim = make_simulation(s, m, es.time_step_fraction, es.damping);
  Group& top = sim.groups().list[static_cast<std::size_t>(s.top)];
  top.motion = GroupMotion::force;
  top.external_force = Vec3{0, -es.stress * s.area, 0};
  top.velocity = Vec3{};

  ElasticResult r;
  r.applied = -es.stress;
  r.initial_overlap = initial_overlap_over_r_min(sim);
  r.overlap_limit = patch_overlap_limit(es.overlap_limit, r.initial_overlap, kOverlapAllowanceElastic);
  const double h_over_d0 = s.strain_height / s.d0;
  const double tau =
      2.0 * es.damping * h_over_d0 * h_over_d0 / (std::numbers::pi * std::numbers::pi * es.time_step_fraction);
  long window = es.window > 0 ? es.window : std::max(500L, std::lround(5.0 * tau));
  window = (window + es.sample_every - 1) / es.sample_every * es.sample_every;
  r.window = window;

  // Measured every sample_every steps: strains (walls, bulk) and stresses (bulk, whole deformable part).
  struct Sample {
    long step;
    double v[6];  // eps_walls, eps, sigma xx, yy, zz (bulk), sigma_yy (part)
  };
  constexpr int kStrains = 2, kValues = 6;
  std::deque<Sample> recent;
  std::vector<int> part_mask, bulk_mask;
  double spread_eps = 0, spread_sigma = 0;
  long samples = 0;
  while (true) {
    const Particles& p = sim.particles();
    free_mask(p, part_mask);
    bulk_mask.assign(p.size(), 0);
    const double eps_w = sim.groups().list[static_cast<std::size_t>(s.top)].displacement.y / s.strain_height;
    double n = 0, sy = 0, su = 0, syy = 0, syu = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
      if (p.group[i] >= 0) continue;
      const auto it = y0.find(p.id[i]);
      if (it == y0.end()) continue;
      bulk_mask[i] = 1;
      const double y = it->second, u = p.y[i] - y;
      n += 1;
      sy += y;
      su += u;
      syy += y * y;
      syu += y * u;
    }
    const double eps = (n * syu - sy * su) / (n * syy - sy * sy);
    const double v_p = s.volume_per_particle;
    const StressTensor bulk = sim.virial_stress(bulk_mask.data(), n * v_p * (1.0 + eps));
    const StressTensor part =
        sim.virial_stress(part_mask.data(), static_cast<double>(s.free_count) * v_p * (1.0 + eps_w));
    if (samples == 0) {  // before the load has moved anything: the sample's own stress
      r.sigma0 = bulk;
      r.sigma_part0 = part;
    }
    const Sample cur{sim.step_count(), {eps_w, eps, bulk.xx, bulk.yy, bulk.zz, part.yy}};
    recent.push_back(cur);
    while (recent.front().step < cur.step - window) recent.pop_front();
    if (++samples % 10 == 0) check_health(sim, "elastic", r.overlap_limit);
    if (!(std::abs(eps_w) <= es.max_strain))
      throw PatchRunError("elastic test: the sample gave way under the stress " + fmt(es.stress) + ": |eps_yy| = " +
                          fmt(std::abs(eps_w)) + " exceeds elastic.max_strain = " + fmt(es.max_strain) + " at step " +
                          std::to_string(cur.step));

    // Stopping rule: a full window of samples whose spreads are all within the tolerance.
    if (cur.step >= window && recent.front().step == cur.step - window) {
      spread_eps = spread_sigma = 0;
      for (int k = 0; k < kValues; ++k) {
        double lo = cur.v[k], hi = cur.v[k];
        for (const Sample& q : recent) {
          lo = std::min(lo, q.v[k]);
          hi = std::max(hi, q.v[k]);
        }
        if (k < kStrains)
          spread_eps = std::max(spread_eps, (hi - lo) / std::abs(cur.v[k]));
        else
          spread_sigma = std::max(spread_sigma, (hi - lo) / es.stress);
      }
      if (spread_eps <= es.tolerance && spread_sigma <= es.tolerance) {
        r.eps_walls = eps_w;
        r.eps = eps;
        r.sigma = bulk;
        r.sigma_part = part;
        r.interior_count = static_cast<long>(n);
        break;
      }
    }
    if (sim.step_count() >= es.max_steps) {
      const std::string why =
          cur.step < window ? "the first window of " + std::to_string(window) + " steps was not complete"
                            : "over the last window of " + std::to_string(window) +
                                  " steps the strains still changed by " + fmt(spread_eps) +
                                  " of their value and the stresses by " + fmt(spread_sigma) + " of the applied stress";
      throw PatchRunError("elastic test: no equilibrium within elastic.max_steps = " + std::to_string(es.max_steps) +
                          " steps (" + why + "; elastic.tolerance = " + fmt(es.tolerance) +
                          "): raise elastic.max_steps or elastic.tolerance");
    }
    for (long k = 0; k < es.sample_every; ++k) sim.step();
    if (progress) progress(sim.step_count(), es.max_steps, sim.particles().size());
  }
  check_health(sim, "elastic", r.overlap_limit);

  r.dt = sim.dt();
  r.c11 = (r.sigma.yy - r.sigma0.yy) / r.eps;
  r.c12 = (r.sigma.xx - r.sigma0.xx) / r.eps;
  r.c13 = (r.sigma.zz - r.sigma0.zz) / r.eps;
  r.moduli = isotropic_from_stiffness(r.c11, r.c12);
  r.c11_walls = (r.sigma_part.yy - r.sigma_part0.yy) / r.eps_walls;
  r.c12_walls = (r.sigma_part.xx - r.sigma_part0.xx) / r.eps_walls;
  r.moduli_walls = isotropic_from_stiffness(r.c11_walls, r.c12_walls);
  r.steps = sim.step_count();
  r.wall_seconds = seconds_since(t0);
  return r;
}

void validate(const StrengthSettings& ss) {
  require_positive(ss.strain_rate, "strength.strain_rate");
  require_positive(ss.time_step_fraction, "strength.time_step_fraction");
  if (!(ss.damping >= 0)) throw input_error("strength.damping", fmt(ss.damping), "must be >= 0 (a fraction of c_c)");
  if (ss.sample_every < 1) throw input_error("strength.sample_every", std::to_string(ss.sample_every), "must be >= 1");
  if (!(ss.fall_fraction > 0 && ss.fall_fraction < 1))
    throw input_error("strength.fall_fraction", fmt(ss.fall_fraction), "must be in (0, 1)");
  if (!(ss.fall_strain >= 0)) throw input_error("strength.fall_strain", fmt(ss.fall_strain), "must be >= 0");
  require_positive(ss.hold_strain, "strength.hold_strain");
  require_positive(ss.max_strain, "strength.max_strain");
  if (!(std::isfinite(ss.shear_normal_stress) && ss.shear_normal_stress >= 0))
    throw input_error("strength.shear_normal_stress", fmt(ss.shear_normal_stress), "must be >= 0 (compressive)");
  if (!(std::isfinite(ss.overlap_limit) && ss.overlap_limit >= 0))
    throw input_error("strength.overlap_limit", fmt(ss.overlap_limit),
                      "must be >= 0 (in smallest radii; 0 or auto: the initial deepest overlap + " +
                          fmt(kOverlapAllowanceStrength) + ")");
}

StrengthResult run_strength_test(const PatchSample& s, const CohesiveMaterial& m, PatchTest test,
                                 const StrengthSettings& ss, const PatchProgress& progress) {
  if (test == PatchTest::elastic) throw std::invalid_argument("run_strength_test: tension or shear");
  const std::string name = patch_test_name(test);
  validate(ss);

  const auto t0 = Clock::now();
  DemSimulation sim = make_simulation(s, m, ss.time_step_fraction, ss.damping);
  const double speed = ss.strain_rate / sim.dt() * s.strain_height;
  Group& top = sim.groups().list[static_cast<std::size_t>(s.top)];
  const bool free_height = test == PatchTest::shear && !ss.shear_fixed_height;
  top.motion = free_height ? GroupMotion::force : GroupMotion::velocity;
  top.velocity = test == PatchTest::tension ? Vec3{0, speed, 0} : Vec3{speed, 0, 0};
  top.external_force = Vec3{0, -ss.shear_normal_stress * s.area, 0};
  // A wall driven along x and free along y: a force group whose x and z kicks (reaction + external force,
  // groups.hpp) are cancelled before every step, so that it keeps its prescribed x and z velocities.
  auto step = [&]() {
    if (free_height) {
      top.external_force.x = -top.reaction.x;
      top.external_force.z = -top.reaction.z;
      top.velocity.x = speed;
      top.velocity.z = 0.0;
    }
    sim.step();
  };
  const long max_steps = static_cast<long>(std::ceil(ss.max_strain / ss.strain_rate)) + ss.sample_every;

  StrengthResult r;
  r.strength = -std::numeric_limits<double>::infinity();
  r.initial_overlap = initial_overlap_over_r_min(sim);
  r.overlap_limit = patch_overlap_limit(ss.overlap_limit, r.initial_overlap, kOverlapAllowanceStrength);
  std::vector<int> mask;
  double below_since = -1;  // strain at which the stress last dropped below fall_fraction * peak, or -1
  long samples = 0;
  while (true) {
    const Particles& p = sim.particles();
    free_mask(p, mask);
    const Vec3 disp = sim.groups().list[static_cast<std::size_t>(s.top)].displacement;
    const double strain = (test == PatchTest::tension ? disp.y : disp.x) / s.strain_height;
    const double eps_yy = disp.y / s.strain_height;
    const double volume = static_cast<double>(s.free_count) * s.volume_per_particle * (1.0 + eps_yy);
    const StressTensor sigma = sim.virial_stress(mask.data(), volume);
    r.curve.push_back({sim.step_count(), strain, eps_yy, sigma, free_kinetic_energy(p)});
    const double value = test == PatchTest::tension ? sigma.yy : sigma.xy;
    if (value > r.strength) {
      r.strength = value;
      r.strain_at_peak = strain;
    }
    if (++samples % 10 == 0) check_health(sim, name.c_str(), r.overlap_limit);
    if (r.strength > 0 && value < ss.fall_fraction * r.strength) {
      if (below_since < 0) below_since = strain;
      if (strain - below_since >= ss.fall_strain) r.outcome = StrengthOutcome::broke;
    } else {
      below_since = -1;
    }
    if (r.outcome != StrengthOutcome::broke && strain - r.strain_at_peak >= ss.hold_strain)
      r.outcome = StrengthOutcome::peak_held;
    if (r.outcome != StrengthOutcome::max_strain || strain >= ss.max_strain || sim.step_count() >= max_steps) {
      r.final_over_peak = value / r.strength;
      break;
    }
    for (long k = 0; k < ss.sample_every; ++k) step();
    if (progress) progress(sim.step_count(), max_steps, sim.particles().size());
  }
  r.dt = sim.dt();
  r.steps = sim.step_count();
  r.wall_seconds = seconds_since(t0);
  return r;
}

}  // namespace debris
