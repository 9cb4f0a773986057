#include "scenarios/calibrate/calibration.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <utility>

#include "core/error.hpp"

namespace debris {

namespace {

// The largest Poisson ratio an input may take: eq 16's tangential cross section vanishes at 1/4.
constexpr double kLargestInputNu = 0.2499;
// Largest change of a strength input in one step (a factor 1.5; nu: 0.05), against a wild secant.
const double kLargestLogStep = std::log(1.5);
constexpr double kLargestNuStep = 0.05;
// Bisection of the reachable edge stops when the last input that made a sample and the first that
// collapsed are this close (1%): the edge is then known to better than the tolerances need.
const double kEdgeResolution = std::log(1.01);
// Prior slopes of the misses against their own inputs (nu_in; ln of the tension input; ln sigma_T): nu moves
// one for one; a Table 4 sample's tension has a log-log slope of 1.0-1.3 from sigma_N / E = 0.2 to 0.3; its
// shear strength moves at 0.4-0.6 of sigma_T (normal bonds carry part of the shear: the paper's footnote).
constexpr double kPriorSlope[3] = {1.0, 1.0, 0.5};

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// The sample of `inputs` as the patch tests take it, and the relaxation's fraction and particle count.
struct RelaxedSample {
  PatchSample sample;
  double fraction = 0;
  long particles = 0;
};

RelaxedSample relax(const CalibrationSpec& spec, const CohesiveMaterial& inputs) {
  AmorphousSpec a = spec.sample;
  a.material = inputs;
  a.d0 = spec.d0 / inputs.critical_diameter();  // the same length in units of these inputs' d_c (eq 18)
  // AmorphousSpec's collapse_fraction (1: spheres filling more than the box) marks the reachable set's edge.
  AmorphousSample relaxed = make_amorphous_sample(a);
  RelaxedSample r;
  r.fraction = relaxed.relaxed_fraction;
  r.particles = static_cast<long>(relaxed.particles.size());
  r.sample = make_walled_sample(relaxed.box, std::move(relaxed.particles), spec.wall_thickness, inputs, "sample",
                                "calibration sample");
  r.sample.volume_fraction = r.fraction;
  return r;
}

CalibrationMeasure measure_of(const RelaxedSample& r, const ElasticResult& e, const StrengthResult& t,
                              const StrengthResult& s) {
  CalibrationMeasure m;
  m.youngs_modulus = e.moduli.E;
  m.poisson_ratio = e.moduli.nu;
  m.tensile_strength = t.strength;
  m.shear_strength = s.strength;
  m.tension = t.outcome;
  m.shear = s.outcome;
  m.particles = r.particles;
  m.relaxed_fraction = r.fraction;
  return m;
}

// The inputs with every stress among them (E, sigma_N, sigma_T, gamma) times lambda: by idea 1 of the
// header they measure lambda times every stress.
CohesiveMaterial scaled(CohesiveMaterial m, double lambda) {
  m.youngs_modulus *= lambda;
  m.tensile_strength *= lambda;
  m.shear_strength *= lambda;
  m.surface_energy *= lambda;
  return m;
}

ElasticSettings elastic_settings(const CalibrationSpec& spec, const CohesiveMaterial& inputs) {
  ElasticSettings e = spec.elastic;
  e.stress = spec.elastic_load * inputs.youngs_modulus;
  return e;
}

// The tension input's value, which the loop moves in logarithms.
double tension_value(TensionInput t, const CohesiveMaterial& m) {
  return t == TensionInput::tensile_strength ? m.tensile_strength : m.surface_energy;
}
void set_tension_value(TensionInput t, CohesiveMaterial& m, double v) {
  (t == TensionInput::tensile_strength ? m.tensile_strength : m.surface_energy) = v;
}

// Why the calibration stops at a sample that did not relax (the last of `steps`). The relaxation depends on
// nu and the tension input as ratios to E (sigma_T has no part in it, and E only scales it: idea 1), so
// the target behind it is the one whose input this step moved from the last sample that relaxed, or, at
// the first step, the targets' own inputs.
std::string did_not_relax(const CalibrationSpec& spec, TensionInput knob, const std::vector<CalibrationStep>& steps,
                          const RelaxationStalled& e) {
  const CohesiveMaterial& t = spec.target;
  const CohesiveMaterial& now = steps.back().inputs;
  const CalibrationStep* before = nullptr;
  std::size_t before_index = 0;
  for (std::size_t k = 0; k + 1 < steps.size(); ++k)
    if (!steps[k].collapsed && !steps[k].stalled) {
      before = &steps[k];
      before_index = k + 1;
    }
  const std::string key = tension_input_key(knob);
  auto ratio = [&](const CohesiveMaterial& m) { return tension_value(knob, m) / m.youngs_modulus; };
  std::string what = "the sample did not relax with these targets: in step " + std::to_string(steps.size()) + " ";
  std::string target;
  if (!before) {
    what += "(the targets' own inputs)";
    target = "tensile_strength " + format_value(t.tensile_strength) + " (" +
             format_value(t.tensile_strength / t.youngs_modulus) + " of E), with surface_energy " +
             format_value(t.surface_energy) + " and poisson_ratio " + format_value(t.poisson_ratio);
  } else if (ratio(before->inputs) != ratio(now)) {
    const CalibrationMeasure& m = before->measured;
    what += "the input " + key + " was " + format_value(tension_value(knob, now)) + ", moved " +
            (ratio(now) < ratio(before->inputs) ? "down" : "up") + " from " +
            format_value(tension_value(knob, before->inputs)) + " in step " + std::to_string(before_index) +
            ", whose sample measured a tension of " +
            format_value(m.tensile_strength / m.youngs_modulus * t.youngs_modulus) + " with E on target";
    target = "tensile_strength " + format_value(t.tensile_strength) + " (" +
             format_value(t.tensile_strength / t.youngs_modulus) + " of E)";
  } else if (before->inputs.poisson_ratio != now.poisson_ratio) {
    what += "the input poisson_ratio was " + format_value(now.poisson_ratio) + ", moved from " +
            format_value(before->inputs.poisson_ratio) + " in step " + std::to_string(before_index) +
            ", whose sample measured " + format_value(before->measured.poisson_ratio);
    target = "poisson_ratio " + format_value(t.poisson_ratio);
  } else {
    what += "the inputs were step " + std::to_string(before_index) + "'s with every stress scaled to put E on target";
    target = "youngs_modulus " + format_value(t.youngs_modulus) + " (E only scales the relaxation: the same "
             "packing as step " + std::to_string(before_index) + "'s but for rounding)";
  }
  what += ", and phase 2 of the relaxation left a stress of " + format_value(e.max_stress) + " E after " +
          std::to_string(e.steps) + " steps (relaxation.phase2.max_steps), above its threshold " +
          format_value(spec.sample.stress_threshold) + " E; the target that drives it is " + target;
  if (e.best_step == e.steps)
    what += ". The stress was still falling: a larger relaxation.phase2.max_steps in the input's relaxation "
            "section may let it finish";
  return what;
}

}  // namespace

void CalibrationSpec::validate() const {
  auto positive = [](double v, const char* key) {
    if (!(v > 0) || !std::isfinite(v)) throw input_error(key, format_value(v), "must be a positive number");
  };
  positive(target.youngs_modulus, "target.youngs_modulus");
  positive(target.tensile_strength, "target.tensile_strength");
  positive(target.shear_strength, "target.shear_strength");
  positive(target.surface_energy, "target.surface_energy");
  positive(target.density, "target.density");
  if (!(target.poisson_ratio >= 0 && target.poisson_ratio < 0.25))
    throw input_error("target.poisson_ratio", format_value(target.poisson_ratio),
                      "cannot be reached: the pair law's Poisson ratio input stops at 0.25 (eq 16: the tangential "
                      "cross section vanishes there), and amorphous samples measure within a few hundredths of "
                      "their input; give a target in [0, 0.25)");
  if (!(target.restitution > 0 && target.restitution <= 1))
    throw input_error("target.restitution", format_value(target.restitution), "must be in (0, 1]");
  if (!(target.scaling >= 0) || !std::isfinite(target.scaling))
    throw input_error("target.scaling", format_value(target.scaling), "must be >= 0");
  positive(d0, "sample.d0");
  if (d0 < target.minimum_diameter())
    throw input_error("sample.d0", format_value(d0),
                      "is below the target's smallest particle size d_min = 4 gamma / sigma_N = " +
                          format_value(target.minimum_diameter()) + " (eq 19)");
  positive(wall_thickness, "sample.wall_thickness");
  positive(elastic_load, "calibration.elastic_load");
  for (const auto& [v, key] : {std::pair{tolerance_E, "calibration.tolerance_E"},
                               std::pair{tolerance_nu, "calibration.tolerance_nu"},
                               std::pair{tolerance_strength, "calibration.tolerance_strength"}})
    positive(v, key);
  if (max_runs < 3)
    throw input_error("calibration.max_runs", std::to_string(max_runs),
                      "must be at least 3 (one evaluation: elastic, tension, shear)");
  debris::validate(elastic);
  debris::validate(strength);
}

TensionInput tension_input(const CalibrationSpec& spec) {
  // Every pair past d_c when the smallest pair (two particles of d_s) is; with s > 0 its delta_f is then
  // sqrt(4 gamma (r_i + r_j) / E) for s = 1/2, below delta_e, and sigma_N no longer sets the peak force.
  const double smallest_pair = spec.sample.d_s * spec.d0;
  return spec.target.scaling > 0 && smallest_pair > spec.target.critical_diameter() ? TensionInput::surface_energy
                                                                                    : TensionInput::tensile_strength;
}

const char* tension_input_key(TensionInput t) {
  return t == TensionInput::tensile_strength ? "tensile_strength" : "surface_energy";
}

CalibrationMeasure measure_sample(const CalibrationSpec& spec, const CohesiveMaterial& inputs) {
  const auto t0 = Clock::now();
  const RelaxedSample r = relax(spec, inputs);
  const ElasticResult e = run_elastic_test(r.sample, inputs, elastic_settings(spec, inputs));
  const StrengthResult t = run_strength_test(r.sample, inputs, PatchTest::tension, spec.strength);
  const StrengthResult s = run_strength_test(r.sample, inputs, PatchTest::shear, spec.strength);
  CalibrationMeasure m = measure_of(r, e, t, s);
  m.seconds = seconds_since(t0);
  return m;
}

std::array<double, 4> calibration_errors(const CohesiveMaterial& t, const CalibrationMeasure& m) {
  return {m.youngs_modulus / t.youngs_modulus - 1, m.poisson_ratio - t.poisson_ratio,
          m.tensile_strength / t.tensile_strength - 1, m.shear_strength / t.shear_strength - 1};
}

CalibrationResult calibrate(const CalibrationSpec& spec, const std::function<void(const CalibrationStep&)>& report) {
  spec.validate();
  const CohesiveMaterial& target = spec.target;
  CalibrationResult result;
  const TensionInput knob = tension_input(spec);
  result.tension_input = knob;

  // The targets as ratios to E (idea 1); the loop runs at the target's E.
  const double want_t = target.tensile_strength / target.youngs_modulus;
  const double want_s = target.shear_strength / target.youngs_modulus;
  auto misses = [&](const CalibrationMeasure& m) {
    return std::array<double, 3>{m.poisson_ratio - target.poisson_ratio,
                                 std::log(m.tensile_strength / m.youngs_modulus / want_t),
                                 std::log(m.shear_strength / m.youngs_modulus / want_s)};
  };
  auto within = [&](const std::array<double, 3>& r) {
    return std::array<bool, 3>{std::abs(r[0]) <= spec.tolerance_nu,
                               std::abs(std::expm1(r[1])) <= spec.tolerance_strength,
                               std::abs(std::expm1(r[2])) <= spec.tolerance_strength};
  };

  CohesiveMaterial x = target;  // eqs 7-16 are built to give the targets: the first guess
  std::optional<RelaxedSample> sample;  // kept while nu and the tension input stay
  CohesiveMaterial sample_inputs;
  ElasticResult elastic{};  // of the sample and nu kept
  bool have_elastic = false;

  // The reachable edge of the tension input: the largest value that made a sample, the smallest that
  // collapsed (logarithms).
  double edge_good = -std::numeric_limits<double>::infinity();
  double edge_bad = std::numeric_limits<double>::infinity();
  double most_t = 0;  // the largest tensile strength over E any sample measured
  double most_t_input = 0;  // ... and its tension input
  // Set once the tension is known to be out of reach: the tension input then stays at most_t_input (the
  // closest reachable) and the loop goes on with nu and sigma_T alone.
  bool tension_out_of_reach = false;

  // The good steps' inputs and misses.
  struct Point {
    double nu_in, log_k, log_b;
    std::array<double, 3> r;
    CohesiveMaterial inputs;  // exactly, so that an input kept is bit for bit the same (and so the sample)
  };
  std::vector<Point> good;
  std::optional<RelaxationStalled> stall;

  for (;;) {
    const auto t0 = Clock::now();
    CalibrationStep step;
    step.inputs = x;
    const bool same_sample = sample && sample_inputs.poisson_ratio == x.poisson_ratio &&
                             tension_value(knob, sample_inputs) == tension_value(knob, x);
    const double log_k = std::log(tension_value(knob, x) / x.youngs_modulus);
    try {
      if (!same_sample) {
        sample.reset();
        sample = relax(spec, x);
        sample_inputs = x;
        have_elastic = false;
      }
      if (!have_elastic) {
        have_elastic = true;
        elastic = run_elastic_test(sample->sample, x, elastic_settings(spec, x));
        ++step.runs_this_step;
      }
      const StrengthResult t = run_strength_test(sample->sample, x, PatchTest::tension, spec.strength);
      const StrengthResult s = run_strength_test(sample->sample, x, PatchTest::shear, spec.strength);
      step.runs_this_step += 2;
      step.measured = measure_of(*sample, elastic, t, s);
    } catch (const SampleCollapse&) {
      step.collapsed = true;
      sample.reset();
    } catch (const RelaxationStalled& e) {
      step.stalled = true;
      sample.reset();
      stall = e;
    }
    step.measured.seconds = seconds_since(t0);
    result.runs += step.runs_this_step;
    step.runs = result.runs;
    result.steps.push_back(step);
    if (report) report(step);

    if (step.stalled) {
      result.why = did_not_relax(spec, knob, result.steps, *stall);
      break;
    }
    if (step.collapsed) {
      edge_bad = std::min(edge_bad, log_k);
      if (good.empty()) {
        result.why = "the target's own inputs make no sample: " + std::string(tension_input_key(knob)) + " = " +
                     format_value(tension_value(knob, x)) +
                     " collapses the relaxation (its attraction reaches too far for this recipe)";
        break;
      }
    } else {
      const std::array<double, 3> r = misses(step.measured);
      good.push_back({x.poisson_ratio, log_k, std::log(x.shear_strength / x.youngs_modulus), r, x});
      edge_good = std::max(edge_good, log_k);
      if (step.measured.tensile_strength / step.measured.youngs_modulus > most_t) {
        most_t = step.measured.tensile_strength / step.measured.youngs_modulus;
        most_t_input = tension_value(knob, x);
      }
      const auto ok = within(r);
      const bool e_ok = std::abs(step.measured.youngs_modulus / target.youngs_modulus - 1) <= spec.tolerance_E;
      if (ok[0] && (ok[1] || tension_out_of_reach) && ok[2] && e_ok) {
        result.converged = !tension_out_of_reach;
        break;
      }
      // The ratios are met: the same inputs times lambda = E* / E measured (idea 1), run to confirm, since
      // a test's path through a fracture can wander by a percent or two under the rounding of a rescale.
      if (ok[0] && (ok[1] || tension_out_of_reach) && ok[2]) {
        if (result.runs + 3 > spec.max_runs) break;
        const double lambda = target.youngs_modulus / step.measured.youngs_modulus;
        x = scaled(x, lambda);
        if (tension_out_of_reach) most_t_input *= lambda;
        continue;
      }
    }
    const Point& last = good.back();
    const auto ok = within(last.r);
    // Out of reach: tension needs more than the edge allows.
    if (!tension_out_of_reach && !ok[1] && last.r[1] < 0 && edge_bad - edge_good <= kEdgeResolution) {
      const double closest = most_t * target.youngs_modulus;
      result.why = "target tensile_strength " + format_value(target.tensile_strength) +
                   " is out of reach for this sample recipe: the most a sample measured is " + format_value(closest) +
                   " (with E on target); the input that limits it is " + tension_input_key(knob) + ": at " +
                   format_value(std::exp(edge_bad) * target.youngs_modulus) + " (with E = " +
                   format_value(target.youngs_modulus) + ") the relaxed packing collapses, its attraction "
                   "reaching past its neighbours, and " + format_value(std::exp(edge_good) * target.youngs_modulus) +
                   " is the largest that made a sample";
      tension_out_of_reach = true;
    }
    if (!ok[0] && ((last.nu_in >= kLargestInputNu && last.r[0] < 0) || (last.nu_in <= 0 && last.r[0] > 0))) {
      result.why = "target poisson_ratio " + format_value(target.poisson_ratio) +
                   " is out of reach for this sample: with the input poisson_ratio at its " +
                   (last.nu_in > 0 ? "upper limit 0.25 (eq 16)" : "lower limit 0") + " it measures " +
                   format_value(last.r[0] + target.poisson_ratio) + ", the closest it reaches";
      break;
    }
    if (result.runs + 3 > spec.max_runs) break;

    // The next inputs (idea 2): one input moves per step, the first target out of tolerance in the order
    // tension, nu, shear (the tension input repacks the sample and moves all three; sigma_T moves the shear
    // alone and reruns two tests, not three). Its step is a secant through the last two steps that differ
    // in that input alone, or the prior slope; a slope outside half to twice the prior is the samples'
    // noise over a small step (a Table 4 sample's tension wanders by 2-5% between neighbouring inputs).
    int j = -1;
    for (int k : {1, 0, 2})
      if (j < 0 && !ok[static_cast<std::size_t>(k)] && !(k == 1 && tension_out_of_reach)) j = k;
    CohesiveMaterial next = last.inputs;
    if (tension_out_of_reach) set_tension_value(knob, next, most_t_input);
    if (j < 0) {  // only the tension was off, and it was just found out of reach: measure at the closest
      x = next;
      continue;
    }
    auto input_of = [](const Point& p, int k) { return k == 0 ? p.nu_in : k == 1 ? p.log_k : p.log_b; };
    double slope = kPriorSlope[j];
    for (std::size_t a = good.size(); a-- > 1;) {
      const Point& p1 = good[a];
      const Point& p0 = good[a - 1];
      bool only_j = true;
      for (int k = 0; k < 3; ++k)
        if (k != j && input_of(p0, k) != input_of(p1, k)) only_j = false;
      if (!only_j || input_of(p0, j) == input_of(p1, j)) continue;
      slope = (p1.r[static_cast<std::size_t>(j)] - p0.r[static_cast<std::size_t>(j)]) /
              (input_of(p1, j) - input_of(p0, j));
      break;  // the latest such pair
    }
    slope = std::clamp(slope, 0.5 * kPriorSlope[j], 2.0 * kPriorSlope[j]);
    const double d = -last.r[static_cast<std::size_t>(j)] / slope;
    if (j == 0) next.poisson_ratio = std::clamp(last.nu_in + std::clamp(d, -kLargestNuStep, kLargestNuStep), 0.0,
                                                kLargestInputNu);
    if (j == 2)
      next.shear_strength =
          next.youngs_modulus * std::exp(last.log_b + std::clamp(d, -kLargestLogStep, kLargestLogStep));
    if (j == 1) {
      double k = last.log_k + std::clamp(d, -kLargestLogStep, kLargestLogStep);
      // Never at or past an input that collapsed: halfway (in logarithm) from the largest good one instead.
      if (k >= edge_bad) k = 0.5 * (edge_good + edge_bad);
      set_tension_value(knob, next, next.youngs_modulus * std::exp(k));
    }
    x = next;
  }

  // The result: the step closest to every target (the last one when converged), E put onto the target by
  // scaling every stress input by lambda = E* / E measured (idea 1), nu as it is.
  // With the tension out of reach: the closest of the steps at the closest reachable tension input.
  auto worst = [&](const CalibrationStep& st) {
    const auto r = misses(st.measured);
    const double t = tension_out_of_reach ? 0.0 : std::abs(std::expm1(r[1])) / spec.tolerance_strength;
    return std::max({std::abs(r[0]) / spec.tolerance_nu, t, std::abs(std::expm1(r[2])) / spec.tolerance_strength});
  };
  const CalibrationStep* best = nullptr;
  for (const auto& st : result.steps)
    if (!st.collapsed && !st.stalled && (!tension_out_of_reach || tension_value(knob, st.inputs) == most_t_input) &&
        (!best || worst(st) <= worst(*best)))
      best = &st;
  double lambda = 1;
  if (result.converged) {
    result.inputs = result.steps.back().inputs;
    result.expected = result.steps.back().measured;
    result.expected_measured = true;
  } else if (best) {
    lambda = target.youngs_modulus / best->measured.youngs_modulus;
    result.inputs = scaled(best->inputs, lambda);
    result.expected = best->measured;
    result.expected.youngs_modulus *= lambda;
    result.expected.tensile_strength *= lambda;
    result.expected.shear_strength *= lambda;
    result.expected_measured = lambda == 1;
  }
  if (!result.converged && result.why.empty() && best) {
    const auto e = calibration_errors(target, result.expected);
    const char* names[] = {"youngs_modulus", "poisson_ratio", "tensile_strength", "shear_strength"};
    const double tol[] = {spec.tolerance_E, spec.tolerance_nu, spec.tolerance_strength, spec.tolerance_strength};
    std::string missed;
    for (std::size_t k = 0; k < 4; ++k)
      if (std::abs(e[k]) > tol[k])
        missed += (missed.empty() ? "" : ", ") + std::string(names[k]) + " off by " + format_value(e[k]);
    const std::string spent = " after " + std::to_string(result.runs) + " patch runs (calibration.max_runs = " +
                              std::to_string(spec.max_runs) + ")";
    if (!missed.empty()) {
      result.why = "not within the tolerances" + spent + ": " + missed;
    } else {
      // Every ratio to E is met, and only E is off: idea 1's rescale puts it on target, but the run that
      // would confirm the rescaled inputs (a fracture's path can wander by a percent or two) did not fit.
      const auto step = static_cast<std::size_t>(best - result.steps.data()) + 1;
      result.why = "not confirmed" + spent + ": youngs_modulus measured " +
                   format_value(best->measured.youngs_modulus) + " (off by " +
                   format_value(best->measured.youngs_modulus / target.youngs_modulus - 1) + ") in step " +
                   std::to_string(step) + ", whose poisson_ratio, tensile_strength / E and shear_strength / E are "
                   "within the tolerances; the inputs given are that step's with every stress input times " +
                   format_value(lambda) + ", which puts E on target (with d0 and the density fixed, E is the "
                   "only scale of stress), but the 3 patch runs that would confirm them did not fit; raise "
                   "calibration.max_runs to " + std::to_string(result.runs + 3) +
                   " or run them through debris_patch";
    }
  }
  return result;
}

}  // namespace debris
