#include "scenarios/common/dem/amorphous_sample.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <random>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "core/error.hpp"
#include "core/pass_timer.hpp"
#include "core/io/hdf5_file.hpp"
#include "core/io/input.hpp"
#include "core/io/lammps_data.hpp"
#include "scenarios/common/dem/cohesive_material_input.hpp"
#include "scenarios/common/dem/truncated_lognormal.hpp"
#include "kernels/dem/integrate.hpp"
#include "scenarios/common/dem/dem_simulation.hpp"

namespace debris {

namespace {

using Clock = WallClock;

double sphere_volume(double r) { return 4.0 / 3.0 * std::numbers::pi * r * r * r; }

double total_sphere_volume(const Particles& p) {
  double v = 0.0;
  for (double r : p.radius) v += sphere_volume(r);
  return v;
}

bool finite(const StressTensor& s) {
  return std::isfinite(s.xx) && std::isfinite(s.yy) && std::isfinite(s.zz) && std::isfinite(s.xy) &&
         std::isfinite(s.xz) && std::isfinite(s.yz);
}

std::string stress_text(const StressTensor& s, double E) {
  std::ostringstream os;
  os.precision(3);
  os << "[xx " << s.xx / E << ", yy " << s.yy / E << ", zz " << s.zz / E << ", xy " << s.xy / E << ", xz " << s.xz / E
     << ", yz " << s.yz / E << "] E";
  return os.str();
}

}  // namespace

StressTensor stress_at_rest(DemSimulation& sim) {
  Particles& p = sim.particles();
  const exec::DeviceVector<double> v[3] = {p.vx, p.vy, p.vz};
  std::fill(p.vx.begin(), p.vx.end(), 0.0);
  std::fill(p.vy.begin(), p.vy.end(), 0.0);
  std::fill(p.vz.begin(), p.vz.end(), 0.0);
  const StressTensor s = sim.virial_stress(nullptr, sim.box().volume(), false);
  // Copied back into the same arrays (not swapped), so the columns keep their storage. particles() again:
  // virial_stress sent the zeroed velocities to the device, and this is a new host-side edit.
  sim.particles();
  std::copy(v[0].begin(), v[0].end(), p.vx.begin());
  std::copy(v[1].begin(), v[1].end(), p.vy.begin());
  std::copy(v[2].begin(), v[2].end(), p.vz.begin());
  return s;
}

namespace {

AmorphousProgress progress_of(const DemSimulation& sim, const AmorphousSpec& spec, int phase, long step,
                              const StressTensor& stress, double solid_volume) {
  AmorphousProgress pr;
  pr.phase = phase;
  pr.step = step;
  pr.stress = stress;
  pr.max_stress = max_stress_component(stress, spec.material.youngs_modulus, phase == 1 || spec.include_shear);
  pr.box_length = sim.box().length();
  pr.volume_fraction = solid_volume / sim.box().volume();
  pr.kinetic_energy = particle_totals(sim.particles()).kinetic_energy;
  pr.max_overlap = sim.diagnostics().max_overlap / spec.d_s_absolute();
  return pr;
}

}  // namespace

// ---------------------------------------------------------------------------------------------------------
// Spec.

double AmorphousSpec::d0_absolute() const { return d0 * material.critical_diameter(); }
double AmorphousSpec::d_s_absolute() const { return d_s * d0_absolute(); }
double AmorphousSpec::d_l_absolute() const {
  return d_l_fixed > 0.0 ? d_l_fixed * material.critical_diameter() : d_l * d0_absolute();
}
Vec3 AmorphousSpec::box_length() const {
  const double d = d0_absolute();
  if (box.x != 0.0 || box.y != 0.0 || box.z != 0.0) return box_absolute ? box : d * box;
  return {length * d, length * d, width * d};
}
double AmorphousSpec::skin() const { return 0.1 * d_s_absolute(); }
double AmorphousSpec::min_periodic_length() const {
  const double r_l = 0.5 * d_l_absolute();
  return 2.0 * (CohesiveCutoff{CohesiveCoefficients::from(material)}(r_l, r_l) + skin());
}

void AmorphousSpec::validate() const {
  material.validate("material");
  auto fin = [](double v) { return std::isfinite(v); };
  const double d_c = material.critical_diameter(), d_min = material.minimum_diameter();
  if (!(fin(d0) && d0 > 0.0)) throw input_error("sample.d0", format_value(d0), "must be > 0 (in units of d_c)");
  if (d0 * d_c < d_min)
    throw input_error("sample.d0", format_value(d0),
                      "d0 = " + format_value(d0 * d_c) + " is below d_min = 4 gamma / sigma_mN = " +
                          format_value(d_min) + " (eq 19; d0 must be >= " + format_value(d_min / d_c) +
                          " d_c): particles smaller than their interaction range reach past their neighbours");
  if (!(fin(d_s) && d_s > 0.0 && d_s <= 1.0))
    throw input_error("sample.d_s", format_value(d_s),
                      "must be in (0, 1] (units of d0: the mode d0 lies in [d_s, d_l])");
  if (d_s * d0 * d_c < d_min)
    throw input_error("sample.d_s", format_value(d_s),
                      "the smallest diameter d_s d0 = " + format_value(d_s * d0 * d_c) +
                          " is below d_min = " + format_value(d_min) + " (eq 19)");
  if (!(fin(d_l_fixed) && d_l_fixed >= 0.0))
    throw input_error("sample.d_l_fixed", format_value(d_l_fixed), "must be >= 0 (units of d_c; 0 = use d_l)");
  if (d_l_fixed > 0.0) {
    if (d_l_fixed < d0)
      throw input_error("sample.d_l_fixed", format_value(d_l_fixed),
                        "the largest diameter must be >= d0 = " + format_value(d0) + " d_c (the mode)");
  } else if (!(fin(d_l) && d_l >= 1.0 && d_l > d_s)) {
    throw input_error("sample.d_l", format_value(d_l),
                      "must be >= 1 and > d_s (units of d0: the mode d0 lies in [d_s, d_l])");
  }
  if (!(fin(volume_fraction) && volume_fraction > 0.0 && volume_fraction < 1.0))
    throw input_error("sample.volume_fraction", format_value(volume_fraction),
                      "cannot be reached: must be in (0, 1), the spheres' volumes summed over the box volume (the "
                      "paper inserts up to 0.75)");
  const double min_len = min_periodic_length() / d0_absolute();
  const bool general_box = box.x != 0.0 || box.y != 0.0 || box.z != 0.0;
  if (general_box) {
    const Vec3 in_d0 = (1.0 / d0_absolute()) * box_length();
    for (double v : {in_d0.x, in_d0.y, in_d0.z}) {
      std::string given = "[";  // appended: GCC 12 warns falsely (-Wrestrict) on "[" + a std::string temporary
      given += format_value(box.x) + ", " + format_value(box.y) + ", " + format_value(box.z) + "]";
      if (!(fin(v) && v > 0.0)) throw input_error("sample.box", given, "every length must be > 0");
      if (v < min_len)
        throw input_error("sample.box", given,
                          "the box is too small: a length of " + format_value(v) +
                              " d0 is below the " + format_value(min_len) +
                              " d0 (2 (cutoff of two d_l particles + skin)) that debris's neighbour list needs");
    }
  }
  for (const auto& [key, value] : {std::pair{"sample.length", length}, std::pair{"sample.width", width}}) {
    if (general_box) break;  // unused
    if (!(fin(value) && value > 0.0)) throw input_error(key, format_value(value), "must be > 0 (units of d0)");
    if (value < min_len)
      throw input_error(key, format_value(value),
                        "the box is too small: debris's neighbour list needs every periodic length to be at "
                        "least 2 (cutoff of two d_l particles + skin) = " +
                            format_value(min_len) + " d0 (LAMMPS's ghost images allow less; debris does not)");
  }
  if (!(fin(time_step_fraction) && time_step_fraction > 0.0 && time_step_fraction <= 1.0))
    throw input_error("relaxation.time_step_fraction", format_value(time_step_fraction),
                      "must be in (0, 1] (a fraction of dt_c, eq 6; the paper uses 0.1)");
  if (phase1_steps < 0) throw input_error("relaxation.phase1.steps", std::to_string(phase1_steps), "must be >= 0");
  if (!(fin(phase1_damping) && phase1_damping >= 0.0))
    throw input_error("relaxation.phase1.damping", format_value(phase1_damping), "must be >= 0 (a fraction of c_c)");
  if (!(fin(phase2_damping) && phase2_damping > 0.0))
    throw input_error("relaxation.phase2.damping", format_value(phase2_damping),
                      "must be > 0 (a fraction of c_c): without damping the sample never comes to rest");
  if (!(fin(stress_threshold) && stress_threshold > 0.0))
    throw input_error("relaxation.phase2.stress_threshold", format_value(stress_threshold), "must be > 0 (units of E)");
  if (phase2_max_steps < 1)
    throw input_error("relaxation.phase2.max_steps", std::to_string(phase2_max_steps), "must be >= 1");
  if (check_every < 1) throw input_error("relaxation.phase2.check_every", std::to_string(check_every), "must be >= 1");
  if (!(fin(box_relaxation_time) && box_relaxation_time > 0.0))
    throw input_error("relaxation.phase2.box_relaxation_time", format_value(box_relaxation_time),
                      "must be > 0 (units of the pressure-wave crossing time L / sqrt(E / rho))");
  if (!(fin(max_box_strain) && max_box_strain > 0.0 && max_box_strain <= 0.1))
    throw input_error("relaxation.phase2.max_box_strain", format_value(max_box_strain), "must be in (0, 0.1]");
}

// ---------------------------------------------------------------------------------------------------------
// Insertion.

InsertedSpheres insert_random_spheres(const AmorphousSpec& spec) {
  spec.validate();
  const double d_s = spec.d_s_absolute(), d_l = spec.d_l_absolute();
  const TruncatedLogNormal dist =
      TruncatedLogNormal::from_mode_and_sd(spec.d0_absolute(), 0.2 * (d_l - d_s), d_s, d_l, "sample");
  const Vec3 len = spec.box_length();
  InsertedSpheres out;
  out.box = Box({0, 0, 0}, len, {true, true, true});
  const double target = spec.volume_fraction * out.box.volume();
  std::mt19937_64 rng(spec.seed);
  double volume = 0.0;
  for (std::int64_t id = 1;; ++id) {
    const double d = dist(rng);
    const double x = uniform_open01(rng) * len.x, y = uniform_open01(rng) * len.y, z = uniform_open01(rng) * len.z;
    const double v = sphere_volume(0.5 * d);
    if (volume + v >= target) {
      // Keep it only if the sum ends nearer the target with it than without it.
      if (volume + v - target < target - volume) {
        out.particles.add(id, 1, x, y, z, 0.5 * d);
        volume += v;
      }
      break;
    }
    out.particles.add(id, 1, x, y, z, 0.5 * d);
    volume += v;
  }
  if (out.particles.size() == 0)
    throw input_error("sample.volume_fraction", format_value(spec.volume_fraction),
                      "cannot be reached: the box holds less than half a particle at this fraction");
  out.particles.set_mass_from_density(spec.material.density);
  out.volume_fraction = volume / out.box.volume();
  return out;
}

// ---------------------------------------------------------------------------------------------------------
// Input keys.

void read_amorphous_sample_keys(const InputNode& sample, AmorphousSpec& s) {
  s.d_s = sample.quantity("d_s", units::dimensionless, s.d_s);
  s.d_l = sample.quantity("d_l", units::dimensionless, s.d_l);
  s.d_l_fixed = sample.quantity("d_l_fixed", units::dimensionless, s.d_l_fixed);
  if (sample.has("d_l") && sample.has("d_l_fixed"))
    throw input_error("sample.d_l_fixed", format_value(s.d_l_fixed),
                      "give one of d_l (units of d0) or d_l_fixed (units of d_c)");
  s.length = sample.quantity("length", units::dimensionless, s.length);
  s.width = sample.quantity("width", units::dimensionless, s.width);
  if (sample.has("box")) {
    if (sample.has("length") || sample.has("width"))
      throw input_error("sample.box", "given with length/width", "give box: [Lx, Ly, Lz], or length and width");
    const std::vector<InputNode> b = sample.list("box");
    if (b.size() != 3) throw input_error("sample.box", std::to_string(b.size()) + " values", "give [Lx, Ly, Lz]");
    // Plain numbers are in d0, like length and width; numbers with a unit are lengths.
    int with_unit = 0;
    for (const InputNode& e : b) {
      const std::string t = e.text();
      with_unit += t.find_first_not_of("0123456789.eE+- ") != std::string::npos ? 1 : 0;
    }
    if (with_unit != 0 && with_unit != 3)
      throw input_error("sample.box", "[" + b[0].text() + ", " + b[1].text() + ", " + b[2].text() + "]",
                        "give all three in d0 (plain numbers) or all three with a length unit");
    s.box_absolute = with_unit == 3;
    const units::Dimension dim = s.box_absolute ? units::length : units::dimensionless;
    s.box = {b[0].quantity(dim), b[1].quantity(dim), b[2].quantity(dim)};
  }
  s.volume_fraction = sample.quantity("volume_fraction", units::dimensionless, s.volume_fraction);
  const long seed = sample.integer("seed", static_cast<long>(s.seed));
  if (seed < 0) throw input_error("sample.seed", std::to_string(seed), "must be >= 0");
  s.seed = static_cast<std::uint64_t>(seed);
}

void read_amorphous_relaxation_keys(const InputNode& r, AmorphousSpec& s) {
  s.time_step_fraction = r.quantity("time_step_fraction", units::dimensionless, s.time_step_fraction);
  if (r.has("phase1")) {
    const InputNode p1 = r.child("phase1");
    s.phase1_steps = p1.integer("steps", s.phase1_steps);
    s.phase1_damping = p1.quantity("damping", units::dimensionless, s.phase1_damping);
  }
  if (r.has("phase2")) {
    const InputNode p2 = r.child("phase2");
    s.phase2_damping = p2.quantity("damping", units::dimensionless, s.phase2_damping);
    s.stress_threshold = p2.quantity("stress_threshold", units::dimensionless, s.stress_threshold);
    s.include_shear = p2.boolean("include_shear", s.include_shear);
    s.phase2_max_steps = p2.integer("max_steps", s.phase2_max_steps);
    s.check_every = p2.integer("check_every", s.check_every);
    s.box_relaxation_time = p2.quantity("box_relaxation_time", units::dimensionless, s.box_relaxation_time);
    s.max_box_strain = p2.quantity("max_box_strain", units::dimensionless, s.max_box_strain);
  }
}

void document_amorphous_sample(KeyReference& ref, const std::string& section, const AmorphousSpec& d) {
  const auto key = [&](const std::string& name) -> KeyDoc& { return ref.key(section + "." + name); };
  const auto number = [&](const std::string& name, double value) -> KeyDoc& {
    return key(name).is(KeyKind::quantity).in(units::dimensionless).fallback(shortest_text(value));
  };
  number("d_s", d.d_s)
      .allowed("(0, 1]; d_s d0 >= d_min")
      .means("smallest diameter of the truncated log-normal size distribution, in units of d0")
      .eq("A eq 19");
  number("d_l", d.d_l)
      .allowed(">= 1 and > d_s; not with d_l_fixed")
      .means("largest diameter, in units of d0; the log-normal's standard deviation is 0.2 (d_l - d_s)");
  number("d_l_fixed", d.d_l_fixed)
      .allowed(">= 0; when > 0, >= d0 / d_c; not with d_l")
      .means("largest diameter in units of d_c, the same for every d0 (paper A section 4, appendix A.4); 0 uses "
             "d_l")
      .eq("A eq 18");
  number("length", d.length)
      .allowed("> 0; at least 2 (cutoff + skin) of two d_l particles")
      .means("L: the periodic box's length along x and y, in units of d0");
  number("width", d.width)
      .allowed("> 0; at least 2 (cutoff + skin) of two d_l particles")
      .means("W: the periodic box's length along z, in units of d0 (the paper's W = 3 d0 is too thin for "
             "debris's neighbour list)");
  key("box")
      .is(KeyKind::list)
      .fallback_is("L x L x W from length and width")
      .allowed("three values, each > 0 and at least 2 (cutoff + skin); not with length or width")
      .means("any periodic box [Lx, Ly, Lz] instead of length and width: plain numbers in units of d0, or three "
             "lengths with a unit (\"60 nm\", the same box for every d0)");
  number("volume_fraction", d.volume_fraction)
      .allowed("(0, 1)")
      .means("the spheres' volumes summed over the box volume at which random insertion (overlaps allowed) "
             "stops");
  key("seed")
      .is(KeyKind::integer)
      .fallback(std::to_string(d.seed))
      .allowed(">= 0")
      .means("seed of the random diameters and positions: the same seed makes the same sample");
}

void document_amorphous_relaxation(KeyReference& ref, const std::string& section, const AmorphousSpec& d) {
  ref.key(section).is(KeyKind::section).fallback_is("optional: the paper's values").means(
      "the relaxation of paper A section 3.2: phase 1 pushes overlapping spheres apart in a fixed box, phase 2 "
      "lets the adhesive packing come to rest in a box that moves to relieve its stress");
  const auto number = [&](const std::string& name, double value) -> KeyDoc& {
    return ref.key(section + "." + name).is(KeyKind::quantity).in(units::dimensionless).fallback(shortest_text(value));
  };
  const auto integer = [&](const std::string& name, long value) -> KeyDoc& {
    return ref.key(section + "." + name).is(KeyKind::integer).fallback(std::to_string(value));
  };
  number("time_step_fraction", d.time_step_fraction)
      .allowed("(0, 1]")
      .means("time step of both phases, as a fraction of the critical time step dt_c of the smallest particle")
      .eq("A eq 6");
  ref.key(section + ".phase1").is(KeyKind::section).fallback_is("optional").means(
      "phase 1: repulsive normal force only, global damping, fixed periodic box");
  integer("phase1.steps", d.phase1_steps).allowed(">= 0").means("steps of phase 1");
  number("phase1.damping", d.phase1_damping)
      .allowed(">= 0")
      .means("global damping of phase 1, as a fraction of the critical damping c_c")
      .eq("A eq 21");
  ref.key(section + ".phase2").is(KeyKind::section).fallback_is("optional").means(
      "phase 2: adhesive normal force, no tangential force, each box length scaled by 1 - (n dt / tau) "
      "sigma_aa / E every n = check_every steps until the stress is below the threshold");
  number("phase2.damping", d.phase2_damping)
      .allowed("> 0")
      .means("global damping of phase 2, as a fraction of the critical damping c_c")
      .eq("A eq 21");
  number("phase2.stress_threshold", d.stress_threshold)
      .allowed("> 0")
      .means("phase 2 ends when every counted component of the average virial stress at rest is below this, in "
             "units of E");
  ref.key(section + ".phase2.include_shear")
      .is(KeyKind::boolean)
      .fallback(d.include_shear ? "true" : "false")
      .means("count the shear stresses too; the orthogonal box cannot relax them, so phase 2 then ends at "
             "max_steps");
  integer("phase2.max_steps", d.phase2_max_steps)
      .allowed(">= 1")
      .means("most steps of phase 2; a sample not relaxed by then is an error naming this key");
  integer("phase2.check_every", d.check_every).allowed(">= 1").means("steps between stress checks and box updates");
  number("phase2.box_relaxation_time", d.box_relaxation_time)
      .allowed("> 0")
      .means("tau of the box rule, in pressure-wave crossing times L_max / sqrt(E / rho)");
  number("phase2.max_box_strain", d.max_box_strain)
      .allowed("(0, 0.1]")
      .means("largest change of a box length per update, as a strain");
}

std::string amorphous_spec_key(const AmorphousSpec& s) {
  std::ostringstream os;
  os.precision(17);
  const CohesiveMaterial& m = s.material;
  os << "material " << m.youngs_modulus << " " << m.poisson_ratio << " " << m.tensile_strength << " "
     << m.shear_strength << " " << m.surface_energy << " " << m.restitution << " " << m.density << " " << m.scaling
     << "\nsample " << s.d0 << " " << s.d_s << " " << s.d_l << " " << s.d_l_fixed << " " << s.length << " " << s.width
     << " " << s.volume_fraction << " " << s.seed << "\nrelaxation " << s.time_step_fraction << " " << s.phase1_steps
     << " " << s.phase1_damping << " " << s.phase2_damping << " " << s.stress_threshold << " " << s.include_shear << " "
     << s.phase2_max_steps << " " << s.check_every << " " << s.box_relaxation_time << " " << s.max_box_strain << "\n";
  // Only when used, so the keys of L x L x W samples (cached sample files) are unchanged.
  if (s.box.x != 0.0 || s.box.y != 0.0 || s.box.z != 0.0)
    os << "box " << s.box.x << " " << s.box.y << " " << s.box.z << (s.box_absolute ? " m" : " d0") << "\n";
  return os.str();
}

// ---------------------------------------------------------------------------------------------------------
// Relaxation.

double max_stress_component(const StressTensor& s, double E, bool with_shear) {
  double m = std::max({std::abs(s.xx), std::abs(s.yy), std::abs(s.zz)});
  if (with_shear) m = std::max({m, std::abs(s.xy), std::abs(s.xz), std::abs(s.yz)});
  return m / E;
}

double relax_phase1(DemSimulation& sim, const AmorphousSpec& spec, const AmorphousObserver& observer,
                    long report_every) {
  sim.set_options(CohesiveOptions{0, 0});  // repulsion only: dN <= 0
  sim.set_global_damping(spec.phase1_damping);
  sim.recompute_forces();
  const double solid = total_sphere_volume(sim.particles());
  auto report = [&](long step) {
    if (observer) observer(progress_of(sim, spec, 1, step, stress_at_rest(sim), solid));
  };
  report(0);
  for (long s = 1; s <= spec.phase1_steps; ++s) {
    sim.step();
    if ((report_every > 0 && s % report_every == 0) || s == spec.phase1_steps) {
      const long bad = first_non_finite(sim.particles());
      if (bad >= 0)
        throw std::runtime_error("amorphous relaxation phase 1: non-finite state at step " + std::to_string(s) +
                                 " (particle id " + std::to_string(sim.particles().id[static_cast<std::size_t>(bad)]) +
                                 "); is the time step stable?");
      report(s);
    }
  }
  return sim.diagnostics().max_overlap / spec.d_s_absolute();
}

long relax_phase2(DemSimulation& sim, const AmorphousSpec& spec, const AmorphousObserver& observer, long report_every,
                  StressTensor* final_stress) {
  sim.set_options(CohesiveOptions{1, 0});  // adhesive normal force, no tangential force
  sim.set_global_damping(spec.phase2_damping);
  sim.recompute_forces();
  const double E = spec.material.youngs_modulus;
  const double solid = total_sphere_volume(sim.particles());
  const double min_len = spec.min_periodic_length();
  const Vec3 len0 = sim.box().length();
  const double crossing = std::max({len0.x, len0.y, len0.z}) / std::sqrt(E / spec.material.density);
  const double tau = spec.box_relaxation_time * crossing;
  const long n = spec.check_every;
  const double gain = static_cast<double>(n) * sim.dt() / tau / E;  // eps_a = -gain sigma_aa (header)

  // Box lengths as compensated (Kahan) sums of their updates. Near the end an update L eps is below half
  // an ulp of L (eps ~ gain sigma with sigma ~ 1e-15 E); added directly it would round away, and the box
  // would stop at a stress of about 1.1e-16 / gain (1e-14 E for L = 100 d0). Carried, the small updates add
  // up until the length moves by one ulp, which changes the stress by only about E * 1.1e-16.
  double target[3] = {len0.x, len0.y, len0.z}, carry[3] = {0.0, 0.0, 0.0};
  double best = HUGE_VAL;
  long best_step = 0;
  StressTensor stress;
  for (long s = 0;; ++s) {
    const bool check = s % n == 0 || s == spec.phase2_max_steps;
    const bool report = observer && ((report_every > 0 && s % report_every == 0) || s == 0);
    if (check || report) stress = stress_at_rest(sim);
    if (report) observer(progress_of(sim, spec, 2, s, stress, solid));
    if (!check) {
      sim.step();
      continue;
    }
    if (!finite(stress))
      throw std::runtime_error("amorphous relaxation phase 2: non-finite stress at step " + std::to_string(s) +
                               "; is the time step stable?");
    const double m = max_stress_component(stress, E, spec.include_shear);
    if (m < best) {
      best = m;
      best_step = s;
    }
    if (m < spec.stress_threshold) {
      if (observer && !report) observer(progress_of(sim, spec, 2, s, stress, solid));
      if (final_stress) *final_stress = stress;
      return s;
    }
    if (s == spec.phase2_max_steps) {
      std::ostringstream os;
      os << "the stresses did not all fall below the threshold " << format_value(spec.stress_threshold) << " E within "
         << s << " steps: at the end the largest component counted was " << format_value(m) << " E, "
         << stress_text(stress, E) << " (smallest reached: " << format_value(best) << " E at step " << best_step
         << "); raise relaxation.phase2.max_steps or relaxation.phase2.stress_threshold";
      if (spec.include_shear && max_stress_component(stress, E, false) < spec.stress_threshold)
        os << " (only shear stresses are left above it, and the orthogonal periodic box cannot relax those: set "
              "relaxation.phase2.include_shear: false)";
      throw RelaxationStalled(input_error("relaxation.phase2.max_steps", std::to_string(spec.phase2_max_steps),
                                          os.str())
                                  .what(),
                              s, m, best, best_step);
    }
    // The box rule of the header: a stretched sample (sigma > 0) shrinks its box, a compressed one grows it.
    const double sig[3] = {stress.xx, stress.yy, stress.zz};
    const Vec3 len = sim.box().length();
    const double now[3] = {len.x, len.y, len.z};
    double next[3];
    bool moved = false;
    for (int a = 0; a < 3; ++a) {
      const double eps = std::clamp(-gain * sig[a], -spec.max_box_strain, spec.max_box_strain);
      const double y = target[a] * eps - carry[a];
      const double t = target[a] + y;
      carry[a] = (t - target[a]) - y;
      target[a] = t;
      next[a] = t;
      moved = moved || next[a] != now[a];
    }
    if (const double fraction = solid / (next[0] * next[1] * next[2]);
        spec.collapse_fraction > 0.0 && fraction > spec.collapse_fraction) {
      std::ostringstream os;
      os << "the sample collapses: at step " << s << " of phase 2 the box would shrink to a volume fraction of "
         << fraction << " (it started phase 2 at " << solid / (len0.x * len0.y * len0.z)
         << "): the pair law's attraction pulls the packing in without end";
      throw SampleCollapse(os.str(), s, fraction);
    }
    for (int a = 0; a < 3; ++a) {
      if (next[a] < min_len) {
        std::ostringstream os;
        os << "the sample is too thin: at step " << s << " of phase 2 the box's "
           << "xyz"[a] << " length would shrink to " << next[a] << ", below the " << min_len
           << " = 2 (cutoff + skin) that the neighbour list needs; start from a larger box";
        if (spec.box.x != 0.0 || spec.box.y != 0.0 || spec.box.z != 0.0)
          throw input_error("sample.box", "[" + format_value(spec.box.x) + ", " + format_value(spec.box.y) + ", " +
                                              format_value(spec.box.z) + "]",
                            os.str());
        throw input_error(a == 2 ? "sample.width" : "sample.length", format_value(a == 2 ? spec.width : spec.length),
                          os.str());
      }
    }
    if (moved) {
      const Vec3 lo = sim.box().lo();
      sim.box().deform(lo, lo + Vec3{next[0], next[1], next[2]}, sim.particles());
    }
    sim.step();
  }
}

double rescale_masses_to_density(Particles& p, const Box& box, double density) {
  double total = 0.0;
  for (double m : p.mass) total += m;
  if (!(total > 0.0)) throw std::invalid_argument("rescale_masses_to_density: the particles have no mass");
  const double f = density * box.volume() / total;
  for (std::size_t i = 0; i < p.size(); ++i) {
    p.mass[i] *= f;
    p.inertia[i] *= f;
  }
  return f;
}

AmorphousSample make_amorphous_sample(const AmorphousSpec& spec, const AmorphousObserver& observer, long report_every) {
  InsertedSpheres ins = insert_random_spheres(spec);  // validates the spec
  AmorphousSample out;
  out.inserted_fraction = ins.volume_fraction;
  out.initial_box_length = ins.box.length();

  DemSettings set;
  set.material = spec.material;
  set.time_step_fraction = spec.time_step_fraction;
  set.global_damping = spec.phase1_damping;
  set.skin = spec.skin();
  set.options = CohesiveOptions{0, 0};
  DemSimulation sim(ins.box, std::move(ins.particles), Groups{}, set);
  out.dt = sim.dt();
  out.dt_c = sim.limits().dt_c;

  auto t0 = Clock::now();
  out.phase1_max_overlap = relax_phase1(sim, spec, observer, report_every);
  out.phase1_steps = spec.phase1_steps;
  out.phase1_seconds = seconds_since(t0);

  t0 = Clock::now();
  out.phase2_steps = relax_phase2(sim, spec, observer, report_every, &out.final_stress);
  out.phase2_seconds = seconds_since(t0);
  out.final_max_stress = max_stress_component(out.final_stress, spec.material.youngs_modulus, spec.include_shear);

  // The sample at rest, in id order, wrapped into the box with fresh image flags.
  out.box = sim.box();
  out.particles = sim.particles();
  Particles& p = out.particles;
  out.box.wrap(p);
  std::vector<int> order(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) order[static_cast<std::size_t>(p.id[i] - 1)] = static_cast<int>(i);
  p.permute(order);
  std::fill(p.ix.begin(), p.ix.end(), 0);
  std::fill(p.iy.begin(), p.iy.end(), 0);
  std::fill(p.iz.begin(), p.iz.end(), 0);
  for (auto* col : {&p.vx, &p.vy, &p.vz, &p.wx, &p.wy, &p.wz, &p.fx, &p.fy, &p.fz, &p.tx, &p.ty, &p.tz})
    std::fill(col->begin(), col->end(), 0.0);
  out.final_box_length = out.box.length();
  out.relaxed_fraction = total_sphere_volume(p) / out.box.volume();
  out.mass_scale = rescale_masses_to_density(p, out.box, spec.material.density);
  return out;
}

// ---------------------------------------------------------------------------------------------------------
// Files.

namespace {
constexpr std::int64_t kSampleFormatVersion = 1;
std::vector<double> as_vector(Vec3 v) { return {v.x, v.y, v.z}; }
}  // namespace

void write_amorphous_sample(const std::string& stem, const AmorphousSample& s, const AmorphousSpec& spec,
                            const std::string& input_echo) {
  const std::filesystem::path parent = std::filesystem::path(stem).parent_path();
  if (!parent.empty()) std::filesystem::create_directories(parent);
  write_lammps_data(stem + ".data", s.box, s.particles);

  const std::string path = stem + ".h5", tmp = path + ".tmp";
  {
    h5::File f(tmp, h5::File::Mode::create);
    f.set_string_attribute("content", "debris amorphous sample (Pham-Ba & Molinari section 3.2)");
    f.set_attribute<std::int64_t>("format_version", kSampleFormatVersion);
    f.write_string("input", input_echo);
    {
      h5::Group box = f.create_group("box");
      box.write("lo", as_vector(s.box.lo()));
      box.write("hi", as_vector(s.box.hi()));
      box.write("periodic", std::vector<std::int32_t>{1, 1, 1});
    }
    {
      const Particles& p = s.particles;
      h5::Group g = f.create_group("particles");
      std::vector<double> pos;
      pos.reserve(3 * p.size());
      for (std::size_t i = 0; i < p.size(); ++i) pos.insert(pos.end(), {p.x[i], p.y[i], p.z[i]});
      g.write("id", p.id);
      g.write("position", pos, p.size(), 3);
      g.write("radius", p.radius);
      g.write("mass", p.mass);
    }
    {
      h5::Group r = f.create_group("relaxation");
      r.write_scalar("volume_fraction_inserted", s.inserted_fraction);
      r.write_scalar("volume_fraction", s.relaxed_fraction);
      r.write_scalar<std::int64_t>("phase1_steps", s.phase1_steps);
      r.write_scalar<std::int64_t>("phase2_steps", s.phase2_steps);
      r.write_scalar("phase1_max_overlap_over_d_s", s.phase1_max_overlap);
      const StressTensor& t = s.final_stress;
      r.write("final_stress_xx_yy_zz_xy_xz_yz", std::vector<double>{t.xx, t.yy, t.zz, t.xy, t.xz, t.yz});
      r.write_scalar("final_max_stress_over_E", s.final_max_stress);
      r.write("box_length_initial", as_vector(s.initial_box_length));
      r.write("box_length_final", as_vector(s.final_box_length));
      r.write_scalar("mass_scale", s.mass_scale);
      r.write_scalar("dt", s.dt);
      r.write_scalar("dt_c", s.dt_c);
    }
    {
      h5::Group g = f.create_group("spec");
      const CohesiveMaterial& m = spec.material;
      g.write("material_E_nu_sigmaN_sigmaT_gamma_eta_rho_s",
              std::vector<double>{m.youngs_modulus, m.poisson_ratio, m.tensile_strength, m.shear_strength,
                                  m.surface_energy, m.restitution, m.density, m.scaling});
      g.write_scalar("d0", spec.d0_absolute());
      g.write_scalar("d0_over_dc", spec.d0);
      g.write_scalar("d_s", spec.d_s_absolute());
      g.write_scalar("d_l", spec.d_l_absolute());
      g.write_scalar("length_over_d0", spec.length);
      g.write_scalar("width_over_d0", spec.width);
      g.write("box_over_d0", as_vector((1.0 / spec.d0_absolute()) * spec.box_length()));
      g.write_scalar("volume_fraction_target", spec.volume_fraction);
      g.write_scalar<std::int64_t>("seed", static_cast<std::int64_t>(spec.seed));
      g.write_scalar("stress_threshold_over_E", spec.stress_threshold);
    }
    f.close();
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) throw std::runtime_error("amorphous sample: cannot rename " + tmp + " to " + path + ": " + ec.message());
}

AmorphousSampleFile read_amorphous_sample(const std::string& h5_path) {
  if (!std::filesystem::exists(h5_path)) throw input_error("amorphous sample", h5_path, "no such file");
  h5::File f(h5_path, h5::File::Mode::read_only);
  if (!f.has_attribute("format_version") || f.attribute<std::int64_t>("format_version") != kSampleFormatVersion)
    throw input_error("amorphous sample", h5_path, "not an amorphous sample written by this version of debris");
  AmorphousSampleFile out;
  out.input_echo = f.read_string("input");
  {
    const h5::Group b = f.open_group("box");
    const auto lo = b.read<double>("lo").values, hi = b.read<double>("hi").values;
    out.box = Box({lo[0], lo[1], lo[2]}, {hi[0], hi[1], hi[2]}, {true, true, true});
  }
  {
    const h5::Group g = f.open_group("particles");
    const auto id = g.read<std::int64_t>("id").values;
    const auto pos = g.read<double>("position").values;
    const auto radius = g.read<double>("radius").values;
    const auto mass = g.read<double>("mass").values;
    if (pos.size() != 3 * id.size() || radius.size() != id.size() || mass.size() != id.size())
      throw input_error("amorphous sample", h5_path, "particle arrays of different lengths");
    for (std::size_t i = 0; i < id.size(); ++i) {
      out.particles.add(id[i], 1, pos[3 * i], pos[3 * i + 1], pos[3 * i + 2], radius[i]);
      out.particles.mass[i] = mass[i];
      out.particles.inertia[i] = 0.4 * mass[i] * radius[i] * radius[i];
    }
  }
  {
    const h5::Group r = f.open_group("relaxation");
    out.relaxed_fraction = r.read_scalar<double>("volume_fraction");
    const h5::Group g = f.open_group("spec");
    out.d0 = g.read_scalar<double>("d0");
    const auto m = g.read<double>("material_E_nu_sigmaN_sigmaT_gamma_eta_rho_s").values;
    out.material = CohesiveMaterial{m[0], m[1], m[2], m[3], m[4], m[5], m[6], m[7]};
  }
  return out;
}

}  // namespace debris
