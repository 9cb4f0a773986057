// debris_calibrate: the cohesive DEM's material inputs whose amorphous sample measures the properties a user
// wants (E, nu, tensile and shear strength), found with the patch tests (the method is in
// calibration.hpp). Writes <output>/calibration.csv (one row per step that made or collapsed a sample:
// inputs, measures, errors, runs) and <output>/spread.csv (the calibrated inputs on the other seeds, so a
// user knows what "within 2%" means for one sample), and prints the calibrated inputs as a `material:` block
// for debris_dem. Exit status 0 when a run of the inputs printed met every target, 2 for bad input or a
// target out of reach (named, with the closest reachable value), 3 when the runs were spent first (also
// when the answer meets the targets only by a rescale of E that no run confirmed) or a sample did not relax.
#include <CLI/CLI.hpp>
#include <charconv>
#include <chrono>
#include <filesystem>
#include <iomanip>
#include <iostream>

#include "core/error.hpp"
#include "core/exec.hpp"
#include "core/exit_status.hpp"
#include "core/io/input.hpp"
#include "core/io/thermo_csv.hpp"
#include "scenarios/calibrate/calibrate_keys.hpp"
#include "scenarios/calibrate/calibration.hpp"
#include "scenarios/common/dem/cohesive_material_input.hpp"
#include "scenarios/common/run/reference_flags.hpp"

namespace {

using namespace debris;
namespace fs = std::filesystem;

struct Options {
  std::string input, output;
  int threads = -1;
};

struct Config {
  CalibrationSpec spec;
  std::vector<long> spread_seeds{2, 3};
  std::string directory = "out/calibrate";
  int threads = 1;
};

Config read_config(const std::string& path) {
  const InputNode root = InputNode::load_file(path);
  Config c;
  CalibrationSpec& s = c.spec;
  const InputNode t = root.child("target");
  const std::string preset = t.choice("preset", {"table4", "silica"}, "table4");
  // nu and s read here, so that the target's checks (CalibrationSpec::validate) name them target.*.
  s.target = read_cohesive_material(t, preset == "silica" ? silica_material() : table4_material(),
                                    CohesiveMaterialKeys{.required = false, .poisson_and_scaling = false});
  s.target.poisson_ratio = t.quantity("poisson_ratio", units::dimensionless, s.target.poisson_ratio);
  s.target.scaling = t.quantity("scaling", units::dimensionless, s.target.scaling);
  const InputNode sample = root.child("sample");
  s.d0 = sample.quantity("d0", units::length);
  read_amorphous_sample_keys(sample, s.sample);
  s.wall_thickness = sample.quantity("wall_thickness", units::dimensionless, s.wall_thickness);
  if (root.has("relaxation")) read_amorphous_relaxation_keys(root.child("relaxation"), s.sample);
  if (root.has("calibration")) {
    const InputNode k = root.child("calibration");
    s.max_runs = static_cast<int>(k.integer("max_runs", s.max_runs));
    s.tolerance_E = k.quantity("tolerance_E", units::dimensionless, s.tolerance_E);
    s.tolerance_nu = k.quantity("tolerance_nu", units::dimensionless, s.tolerance_nu);
    s.tolerance_strength = k.quantity("tolerance_strength", units::dimensionless, s.tolerance_strength);
    s.elastic_load = k.quantity("elastic_load", units::dimensionless, s.elastic_load);
    if (k.has("spread_seeds")) {
      c.spread_seeds.clear();
      for (double v : k.numbers("spread_seeds", units::dimensionless)) {
        if (!(v >= 1) || v != static_cast<double>(static_cast<long>(v)))
          throw input_error("calibration.spread_seeds", format_value(v), "must be whole numbers >= 1");
        c.spread_seeds.push_back(static_cast<long>(v));
      }
    }
  }
  if (root.has("output")) c.directory = root.child("output").string("directory", c.directory);
  if (root.has("run")) {
    c.threads = static_cast<int>(root.child("run").integer("threads", c.threads));
    if (c.threads < 0) throw input_error("run.threads", std::to_string(c.threads), "must be >= 0");
  }
  root.reject_unknown_keys();
  audit_keys(root, calibrate_keys());
  s.validate();
  return c;
}

std::vector<double> row(double step, int runs, bool collapsed, const CohesiveMaterial& in, const CalibrationMeasure& m,
                        const CohesiveMaterial& target) {
  const auto e = calibration_errors(target, m);
  return {step, static_cast<double>(runs), collapsed ? 1.0 : 0.0, in.youngs_modulus, in.poisson_ratio,
          in.tensile_strength, in.shear_strength, in.surface_energy, m.youngs_modulus, m.poisson_ratio,
          m.tensile_strength, m.shear_strength, e[0], e[1], e[2], e[3], m.relaxed_fraction, m.seconds};
}

std::string shortest(double v) {
  char buf[32];
  return std::string(buf, std::to_chars(buf, buf + sizeof buf, v).ptr);
}

void print_measure(const char* what, const CalibrationMeasure& m, const CohesiveMaterial& target) {
  const auto e = calibration_errors(target, m);
  std::cout << std::setprecision(5) << what << ": E " << m.youngs_modulus << " (" << std::showpos << 100 * e[0]
            << "%), nu " << std::noshowpos << m.poisson_ratio << " (" << std::showpos << e[1] << "), tension "
            << std::noshowpos << m.tensile_strength << " (" << std::showpos << 100 * e[2] << "%), shear "
            << std::noshowpos << m.shear_strength << " (" << std::showpos << 100 * e[3] << "%)" << std::noshowpos
            << "\n";
}

int run(const Options& opt) {
  Config c = read_config(opt.input);
  if (!opt.output.empty()) c.directory = opt.output;
  const int threads = opt.threads >= 0 ? opt.threads : c.threads;
  if (threads > 0) exec::set_threads(threads);
  const CalibrationSpec& spec = c.spec;
  const fs::path dir(c.directory);
  fs::create_directories(dir);
  ThermoCsv csv((dir / "calibration.csv").string(), calibration_table().header());
  const auto t0 = std::chrono::steady_clock::now();
  int index = 0;
  std::cout << "calibrating for E " << spec.target.youngs_modulus << ", nu " << spec.target.poisson_ratio
            << ", tension " << spec.target.tensile_strength << ", shear " << spec.target.shear_strength << " (d0 "
            << spec.d0 << ", s " << spec.target.scaling << ", " << spec.sample.length << " x " << spec.sample.length
            << " x " << spec.sample.width << " d0, seed " << spec.sample.seed << ")\n"
            << "the tension moves with the input " << tension_input_key(tension_input(spec)) << std::endl;
  const CalibrationResult r = calibrate(spec, [&](const CalibrationStep& s) {
    ++index;
    if (!s.stalled) csv.write_row(row(index, s.runs, s.collapsed, s.inputs, s.measured, spec.target));
    std::cout << "step " << index << " (" << s.runs << " patch runs): ";
    if (s.stalled)
      std::cout << std::setprecision(5) << "nu " << s.inputs.poisson_ratio << ", "
                << tension_input_key(tension_input(spec)) << " "
                << (tension_input(spec) == TensionInput::tensile_strength ? s.inputs.tensile_strength
                                                                          : s.inputs.surface_energy)
                << ": the sample did not relax\n";
    else if (s.collapsed)
      std::cout << std::setprecision(5) << tension_input_key(tension_input(spec)) << " "
                << (tension_input(spec) == TensionInput::tensile_strength ? s.inputs.tensile_strength
                                                                          : s.inputs.surface_energy)
                << ": the sample collapsed\n";
    else
      print_measure("measures", s.measured, spec.target);
    std::cout.flush();  // a step is a minute of patch runs: show it as it comes, in a pipe or a log too
  });
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (!(r.inputs.youngs_modulus > 0)) {  // no step made a sample: no inputs to give, none to spread
    std::cout << "\nno calibrated inputs after " << r.runs << " patch runs\nrows: " << (dir / "calibration.csv").string()
              << "\n";
    std::cerr << "debris_calibrate: " << r.why << "\n";
    return kExitUnfinished;
  }
  const CohesiveMaterial& in = r.inputs;
  // Each input in the fewest digits that read back as the same double: a copy of the block runs the very
  // inputs the calibration found (a fracture's path can move by a percent under a change in the 9th digit).
  std::cout << std::setprecision(6) << "\ncalibrated inputs after " << r.runs << " patch runs, " << std::setprecision(3)
            << wall << " s:\nmaterial:\n"
            << "  youngs_modulus: " << shortest(in.youngs_modulus) << "\n  poisson_ratio: "
            << shortest(in.poisson_ratio) << "\n  tensile_strength: " << shortest(in.tensile_strength)
            << "\n  shear_strength: " << shortest(in.shear_strength) << "\n  surface_energy: "
            << shortest(in.surface_energy) << "\n  restitution: " << shortest(in.restitution)
            << "\n  density: " << shortest(in.density) << "\n  scaling: " << shortest(in.scaling) << "\n";
  print_measure(r.expected_measured ? "they measure" : "they should measure (a step's measures with E scaled onto "
                                                       "the target; these inputs were not run)",
                r.expected, spec.target);

  // The spread: the calibrated inputs on samples of other seeds.
  ThermoCsv spread((dir / "spread.csv").string(), spread_table().header());
  spread.write_row(row(static_cast<double>(spec.sample.seed), 0, false, in, r.expected, spec.target));
  std::vector<long> collapsed;
  for (long seed : c.spread_seeds) {
    CalibrationSpec other = spec;
    other.sample.seed = static_cast<std::uint64_t>(seed);
    try {
      const CalibrationMeasure m = measure_sample(other, in);
      spread.write_row(row(static_cast<double>(seed), 0, false, in, m, spec.target));
      print_measure(("seed " + std::to_string(seed)).c_str(), m, spec.target);
    } catch (const SampleCollapse& e) {
      std::cout << "seed " << seed << ": " << e.what() << "\n";
      spread.write_row(row(static_cast<double>(seed), 0, true, in, CalibrationMeasure{}, spec.target));
      collapsed.push_back(seed);
    }
  }
  // Inputs at the collapse edge make a sample on one seed and none on another: say so where a user reads
  // the inputs, not only in the seed's line (the silica junction of scenarios/wear met it on 2 of 3 seeds).
  if (!collapsed.empty()) {
    std::cout << "warning: these inputs sit at the edge where the packing collapses: " << collapsed.size() << " of "
              << c.spread_seeds.size() << " other seeds made no sample (seed";
    for (long seed : collapsed) std::cout << " " << seed;
    std::cout << "); a sample of this recipe on another seed, or larger, may collapse too. A slightly smaller "
              << tension_input_key(tension_input(spec)) << " gives margin at the cost of some tension.\n";
  }
  std::cout << "rows: " << (dir / "calibration.csv").string() << ", " << (dir / "spread.csv").string() << "\n";
  if (r.converged) return 0;
  std::cerr << "debris_calibrate: " << r.why << "\n";
  return r.why.find("out of reach") != std::string::npos ? kExitInput : kExitUnfinished;
}

}  // namespace

int main(int argc, char** argv) {
  if (const int status = debris::refuse_many_processes("debris_calibrate"); status >= 0) return status;
  CLI::App app{"debris_calibrate: cohesive-DEM inputs whose amorphous sample measures the target E, nu and "
               "strengths"};
  Options opt;
  app.add_option("-i,--input", opt.input, "YAML input file");
  app.add_option("-o,--output", opt.output, "output directory (overrides output.directory)");
  app.add_option("--threads", opt.threads, "number of host threads (overrides run.threads)")
      ->check(CLI::NonNegativeNumber);
  app.footer("Example, from the repository root (Table 4's material on a small sample, about a minute):\n"
             "  ./build/bin/debris_calibrate -i scenarios/calibrate/table4.yaml -o out/calibrate_table4");
  debris::ReferenceFlags reference;
  debris::add_reference_flags(app, reference);
  if (const int status = debris::parse_command_line(app, argc, argv); status >= 0) return status;
  if (debris::print_reference(reference, debris::calibrate_keys(), debris::calibrate_output_columns())) return 0;
  if (opt.input.empty()) {
    std::cerr << "debris_calibrate: give an input file (-i calibrate.yaml); --help for more\n";
    return debris::kExitInput;
  }
  return debris::exit_status_of("debris_calibrate", [&] { return run(opt); });
}
