// debris_patch: the patch tests of the cohesive DEM (Pham-Ba & Molinari, section 3): elastic (confined
// compression: C11, C12, E, nu), tension and shear (strengths), on HCP lattices in either orientation or on
// samples read from LAMMPS data files, swept over tests, samples, nu, s and d0 as the YAML input says.
// Writes cases.csv (one row per case), the stress-strain curve of each strength test, and PNG plots drawn
// by gnuplot next to the paper's targets. Bad input ends with a message naming the key and the value and
// exit status 2, before anything is run or written; a case that cannot finish (no equilibrium within the
// step limit, a sample that gives way, a blown-up state) is reported in its row and on the terminal, the
// other cases still run, and the exit status is 3. --resume continues a sweep an earlier run of the same
// input left unfinished in the output directory: the cases of its cases.csv are kept and the others run.
#include <CLI/CLI.hpp>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <memory>
#include <sstream>

#include "core/error.hpp"
#include "core/exit_status.hpp"
#include "core/io/input.hpp"
#include "core/exec.hpp"
#include "core/io/progress.hpp"
#include "core/thread_tuner.hpp"
#include "scenarios/common/run/reference_flags.hpp"
#include "scenarios/patch/amorphous_cache.hpp"
#include "scenarios/patch/patch_input.hpp"
#include "scenarios/patch/patch_keys.hpp"
#include "scenarios/patch/patch_report.hpp"
#include "scenarios/patch/patch_resume.hpp"

namespace {

using namespace debris;
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;


struct Options {
  std::string input, output;
  int threads = 0;
  bool resume = false;
};

std::string describe_case(const PatchCase& c) {
  std::ostringstream os;
  os << patch_test_name(c.test) << ", " << c.sample_label();
  if (c.lattice || c.amorphous) os << ", d0 = " << c.d0_over_dc << " d_c";
  os << ", nu = " << c.material.poisson_ratio << ", s = " << c.material.scaling;
  return os.str();
}

std::string result_line(const PatchCaseResult& r) {
  std::ostringstream os;
  os << std::setprecision(5);
  if (!r.ok) return "  FAILED: " + r.error;
  if (r.c.test == PatchTest::elastic) {
    const ElasticResult& e = r.elastic;
    os << "  C11 = " << e.c11 << ", C12 = " << e.c12 << ", C13 = " << e.c13 << "  ->  E = " << e.moduli.E << " ("
       << std::showpos << 100 * (e.moduli.E / r.c.material.youngs_modulus - 1) << std::noshowpos
       << "%), nu = " << e.moduli.nu << " (target " << r.c.material.poisson_ratio << ")\n"
       << "  walls: eps_yy = " << e.eps_walls << " (bulk " << e.eps << "), E = " << e.moduli_walls.E
       << ", nu = " << e.moduli_walls.nu << "; sigma_yy of the deformable part " << e.sigma_part.yy << " (applied "
       << e.applied << ")\n"
       << "  " << e.steps << " steps (window " << e.window << "), " << std::setprecision(3) << e.wall_seconds << " s";
    if (r.c.amorphous)
      os << "\n  initial stress of the bulk (subtracted): [" << e.sigma0.xx << ", " << e.sigma0.yy << ", "
         << e.sigma0.zz << "]; deepest initial overlap " << e.initial_overlap << " r_min, health-check limit "
         << e.overlap_limit << " r_min";
  } else {
    const StrengthResult& s = r.strength;
    os << "  strength = " << s.strength << " (target " << r.target << ", ratio " << s.strength / r.target
       << ") at strain " << s.strain_at_peak << "; " << strength_outcome_name(s.outcome) << ", final stress "
       << s.final_over_peak << " of the peak\n"
       << "  " << s.steps << " steps, " << std::setprecision(3) << s.wall_seconds << " s";
  }
  return os.str();
}

int run(const Options& opt) {
  const std::string text = read_input_file(opt.input);
  PatchConfig cfg = read_patch_input_text(text, opt.input, fs::path(opt.input).parent_path().string());
  if (!opt.output.empty()) cfg.output_directory = opt.output;
  const exec::ThreadRequest threads = exec::request_threads(opt.threads, cfg.threads);
  std::cout << exec::startup_report() << "\n" << exec::describe(threads) << std::endl;

  // Every sample is built (amorphous ones: checked) once before anything runs, so that a bad case stops the
  // sweep before it starts. The facts of an amorphous sample are filled in when it is made.
  std::vector<PatchCaseResult> results;
  auto fill = [](PatchCaseResult& r, const PatchSample& s) {
    r.description = s.description;
    r.particles = static_cast<long>(s.particles.size());
    r.deformable = s.free_count;
    r.d0 = r.c.amorphous ? r.c.amorphous_spec.d0_absolute() : s.d0;  // amorphous: the mode, as the paper plots it
    r.size_over_d0 = (1.0 / r.d0) * s.box.length();
    r.volume_fraction = s.volume_fraction;
    r.target = target_strength(r.c.material, r.c.test, r.d0);
  };
  for (const PatchCase& c : cfg.cases) {
    PatchCaseResult r;
    r.c = c;
    if (c.amorphous) {
      check_case_sample(c);
      r.d0 = c.amorphous_spec.d0_absolute();
      r.target = target_strength(c.material, c.test, r.d0);
    } else {
      const PatchSample s = make_case_sample(c);
      if (c.test == PatchTest::elastic) validate(cfg.elastic, s);
      fill(r, s);
    }
    results.push_back(r);
  }
  std::cout << cfg.cases.size() << " case(s)\n";

  const fs::path dir = cfg.output_directory;
  FinishedCases finished;
  if (opt.resume) {
    // The same input or nothing: case k of another input is another case.
    if (fs::exists(dir / "input.yaml")) {
      if (read_input_file((dir / "input.yaml").string()) != text)
        throw input_error("--resume", dir.string(),
                          "holds the results of another input (its input.yaml differs from " + opt.input +
                              "); resume with that input, or run this one into another output directory");
    }
    finished = read_finished_cases(dir.string(), results);
    std::cout << "resume: " << finished.results.size() << " of " << results.size() << " case(s) finished in "
              << dir.string() << "/cases.csv, kept"
              << (finished.dropped.empty() ? "" : " (run again: " + finished.dropped + ")") << std::endl;
  }
  fs::create_directories(dir);
  fs::create_directories(dir / "curves");
  {
    std::ofstream echo(dir / "input.yaml", std::ios::binary | std::ios::trunc);
    echo << text;
  }
  PatchCasesCsv table((dir / "cases.csv").string(), finished.rows);
  AmorphousSampleCache cache(cfg.cache_directory.empty() ? (dir / "samples").string() : cfg.cache_directory, std::cout);

  const auto t0 = Clock::now();
  int failed = 0;
  for (PatchCaseResult& r : results) {
    const PatchCase& c = r.c;
    std::cout << "\ncase " << c.index << "/" << results.size() << ": " << describe_case(c) << std::endl;
    if (const auto kept = finished.results.find(c.index); kept != finished.results.end()) {
      r = kept->second;
      if (!r.ok) ++failed;
      const std::string line = result_line(r);  // its first line: the rest restates settings not in the table
      std::cout << "  finished by an earlier run (--resume)\n" << line.substr(0, line.find('\n')) << std::endl;
      continue;
    }
    if (!c.amorphous) std::cout << "  " << r.description << std::endl;
    std::unique_ptr<Progress> progress;
    const PatchProgress report = [&](long step, long limit, std::size_t n) {
      if (!progress) progress = std::make_unique<Progress>(0, limit, std::cout, cfg.progress_seconds);
      progress->update(step, n);
    };
    try {
      const PatchSample s = make_case_sample(c, &cache);
      if (c.amorphous) {
        fill(r, s);
        std::cout << "  " << r.description << std::endl;
      }
      if (c.test == PatchTest::elastic) {
        r.elastic = run_elastic_test(s, c.material, cfg.elastic, report);
      } else {
        r.strength = run_strength_test(s, c.material, c.test, cfg.strength, report);
        std::ostringstream name;
        name << "curves/case_" << std::setw(3) << std::setfill('0') << c.index << "_" << patch_test_name(c.test)
             << ".csv";
        r.curve_file = name.str();
        write_curve_csv((dir / r.curve_file).string(), r.strength);
      }
      r.ok = true;
    } catch (const PatchRunError& e) {
      r.error = e.what();
      ++failed;
    } catch (const InputError& e) {  // an amorphous sample too small for its interior margin, ...
      if (!c.amorphous) throw;
      r.error = e.what();
      ++failed;
    }
    table.write(r);
    std::cout << result_line(r) << std::endl;
  }
  const double wall = std::chrono::duration<double>(Clock::now() - t0).count();

  std::cout << "\n" << (cfg.plots ? write_plots(dir.string(), results) : "plots: off (output.plots: false)") << "\n";
  std::cout << results.size() << " case(s) in " << format_duration(wall) << " (" << std::setprecision(4) << wall
            << " s); results in " << dir.string() << "/ (cases.csv, curves/, plots.gp, *.png)\n";
  if (failed > 0) {
    std::cerr << "debris_patch: " << failed << " case(s) could not finish:\n";
    for (const PatchCaseResult& r : results)
      if (!r.ok) std::cerr << "  case " << r.c.index << " (" << describe_case(r.c) << "): " << r.error << "\n";
    return kExitUnfinished;
  }
  exec::print_tuning_summary(std::cout);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (const int status = debris::refuse_many_processes("debris_patch"); status >= 0) return status;
  CLI::App app{
      "debris_patch: patch tests of the cohesive DEM (Pham-Ba & Molinari, section 3): elastic constants "
      "and strengths of HCP lattices and amorphous samples"};
  Options opt;
  app.add_option("-i,--input", opt.input, "YAML input file");
  app.add_option("-o,--output", opt.output, "output directory (overrides output.directory)");
  app.add_option("--threads", opt.threads, "number of host threads (overrides threads)")->check(CLI::NonNegativeNumber);
  app.add_flag("--resume", opt.resume,
               "continue the sweep an earlier run of the same input left in the output directory: keep the "
               "cases of its cases.csv (and their curves), run the others, plot them all");
  app.footer("Example, from the repository root (the elastic patch test over nu, about a minute):\n"
             "  ./build/bin/debris_patch -i scenarios/patch/elastic_nu_sweep.yaml -o out/patch_elastic");
  debris::ReferenceFlags reference;
  debris::add_reference_flags(app, reference);
  if (const int status = debris::parse_command_line(app, argc, argv); status >= 0) return status;
  if (debris::print_reference(reference, debris::patch_keys(), debris::patch_output_columns())) return 0;
  if (opt.input.empty()) {
    std::cerr << "debris_patch: give an input file (-i patch.yaml); --help for more\n";
    return debris::kExitInput;
  }
  return debris::exit_status_of("debris_patch", [&] { return run(opt); });
}
