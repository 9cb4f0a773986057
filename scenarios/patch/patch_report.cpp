#include "scenarios/patch/patch_report.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <map>
#include <sstream>
#include <stdexcept>

#include "core/error.hpp"
#include "core/io/text_format.hpp"
#include "core/io/thermo_csv.hpp"
#include "scenarios/common/run/gnuplot.hpp"
#include "scenarios/patch/patch_keys.hpp"

namespace debris {

namespace {

namespace fs = std::filesystem;

// A CSV field: quoted when it holds a comma, a quote or a line break.
std::string field(const std::string& s) {
  if (s.find_first_of(",\"\r\n") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

std::string num(double v) {
  std::string s;
  append_number(s, v);
  return s;
}

std::string short_num(double v) {
  std::ostringstream os;
  os.precision(4);
  os << v;
  return os.str();
}

}  // namespace

std::string patch_cases_header() {
  std::string header;
  for (const std::string& c : patch_cases_table().header()) {
    if (!header.empty()) header += ',';
    header += c;
  }
  return header;
}

std::string patch_case_sample(const PatchCase& c) {
  return c.lattice ? std::string("hcp") : (c.amorphous ? c.sample_label() : c.data_file);
}

PatchCasesCsv::PatchCasesCsv(const std::string& path, const std::vector<std::string>& kept_rows) {
  out_.open(path, std::ios::binary | std::ios::trunc);
  if (!out_)
    throw input_error("output.directory", path, std::string("cannot open for writing: ") + std::strerror(errno));
  out_ << patch_cases_header() << '\n';
  for (const std::string& row : kept_rows) out_ << row << '\n';
  out_ << std::flush;
}

void PatchCasesCsv::write(const PatchCaseResult& r) {
  const PatchCase& c = r.c;
  std::vector<std::string> f;
  f.push_back(std::to_string(c.index));
  f.push_back(patch_test_name(c.test));
  f.push_back(field(patch_case_sample(c)));
  f.push_back(c.lattice ? std::string(1, "xyz"[c.hcp.c_axis]) : "");
  f.push_back(num(r.d0 / c.material.critical_diameter()));
  f.push_back(num(r.d0));
  f.push_back(num(c.material.poisson_ratio));
  f.push_back(num(c.material.scaling));
  f.push_back(std::to_string(r.particles));
  f.push_back(std::to_string(r.deformable));
  f.push_back(num(r.size_over_d0.x));
  f.push_back(num(r.size_over_d0.y));
  f.push_back(num(r.size_over_d0.z));
  const bool elastic = c.test == PatchTest::elastic;
  f.push_back(r.ok ? num(elastic ? r.elastic.dt : r.strength.dt) : "");
  f.push_back(field(r.ok ? std::string("ok") : "failed: " + r.error));
  f.push_back(r.ok ? std::to_string(elastic ? r.elastic.steps : r.strength.steps) : "");
  f.push_back(r.ok ? num(elastic ? r.elastic.wall_seconds : r.strength.wall_seconds) : "");
  if (r.ok && elastic) {
    const ElasticResult& e = r.elastic;
    const double nu_t = c.material.poisson_ratio;
    for (double v : {e.eps, e.sigma.xx, e.sigma.yy, e.sigma.zz, e.c11, e.c12, e.c13, e.moduli.E, e.moduli.nu,
                     e.moduli.E / c.material.youngs_modulus - 1.0, e.moduli.nu - nu_t})
      f.push_back(num(v));
    f.push_back(nu_t != 0.0 ? num(e.moduli.nu / nu_t - 1.0) : "");
    for (double v : {e.eps_walls, e.sigma_part.yy, e.c11_walls, e.c12_walls, e.moduli_walls.E, e.moduli_walls.nu})
      f.push_back(num(v));
  } else {
    for (int k = 0; k < 18; ++k) f.push_back("");
  }
  if (r.ok && !elastic) {
    const StrengthResult& s = r.strength;
    f.push_back(num(s.strength));
    f.push_back(num(r.target));
    f.push_back(num(s.strength / r.target));
    f.push_back(num(s.strain_at_peak));
    f.push_back(field(strength_outcome_name(s.outcome)));
    f.push_back(num(s.final_over_peak));
    f.push_back(field(r.curve_file));
  } else {
    for (int k = 0; k < 7; ++k) f.push_back("");
  }
  f.push_back(r.volume_fraction > 0 ? num(r.volume_fraction) : "");
  f.push_back(c.system_size > 0 ? num(c.system_size) : "");
  if (r.ok) {
    f.push_back(num(elastic ? r.elastic.initial_overlap : r.strength.initial_overlap));
    f.push_back(num(elastic ? r.elastic.overlap_limit : r.strength.overlap_limit));
  } else {
    f.insert(f.end(), 2, "");
  }
  if (r.ok && elastic) {
    f.push_back(num(r.elastic.sigma0.xx));
    f.push_back(num(r.elastic.sigma0.yy));
  } else {
    f.insert(f.end(), 2, "");
  }
  if (f.size() != patch_cases_table().columns.size())
    throw std::logic_error("cases.csv: a row of " + std::to_string(f.size()) + " fields under a header of " +
                           std::to_string(patch_cases_table().columns.size()) + " columns");
  std::string line;
  for (const std::string& s : f) line += (line.empty() ? "" : ",") + s;
  out_ << line << '\n' << std::flush;
  if (!out_) throw input_error("output.directory", "cases.csv", "writing failed (disk full?)");
}

const std::vector<std::string>& patch_curve_columns() {
  static const std::vector<std::string> columns = patch_curve_table().header();
  return columns;
}

void write_curve_csv(const std::string& path, const StrengthResult& r) {
  ThermoCsv csv(path, patch_curve_columns());
  for (const StressStrainPoint& p : r.curve)
    csv.write_row({static_cast<double>(p.step), p.strain, p.eps_yy, p.stress.xx, p.stress.yy, p.stress.zz, p.stress.xy,
                   p.stress.xz, p.stress.yz, p.kinetic_energy});
}

// ---------------------------------------------------------------------------------------------------------
// Plots.

namespace {

struct Series {
  std::string title;
  std::vector<std::pair<double, double>> xy;
  std::string style;  // empty: the plot's default style
};

// gnuplot string literal (single quotes; a quote is doubled).
std::string gp_string(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("''") : std::string(1, c);
  return q + "'";
}

// Writes each series as a datablock $<prefix><k> and returns the plot clauses for them.
std::string datablocks(std::ostream& gp, const std::string& prefix, const std::vector<Series>& series,
                       const std::string& style) {
  std::string clauses;
  for (std::size_t k = 0; k < series.size(); ++k) {
    const std::string name = "$" + prefix + std::to_string(k);
    gp << name << " << EOD\n";
    for (const auto& [x, y] : series[k].xy) gp << num(x) << " " << num(y) << "\n";
    gp << "EOD\n";
    const std::string& st = series[k].style.empty() ? style : series[k].style;
    clauses +=
        (clauses.empty() ? "" : ", \\\n     ") + name + " using 1:2 " + st + " title " + gp_string(series[k].title);
  }
  return clauses;
}

}  // namespace

std::string write_plots(const std::string& dir, const std::vector<PatchCaseResult>& results) {
  std::ostringstream gp;
  const std::string terminal = "set terminal pngcairo size 1100,850 noenhanced font ',11'\n";
  gp << "# debris_patch plots: run `gnuplot plots.gp` in this directory. Data are inline (from cases.csv).\n"
     << terminal << "set key below font ',10'\nset grid\n";
  // Eight colours that stay apart on white (Okabe-Ito, yellow left out), then repeated.
  const char* colours[] = {"#0072b2", "#d55e00", "#009e73", "#cc79a7", "#e69f00", "#56b4e9", "#555555", "#8c510a"};
  for (int k = 0; k < 8; ++k) gp << "set linetype " << k + 1 << " lc rgb '" << colours[k] << "' lw 2\n";
  gp << "set linetype cycle 8\n";
  std::vector<std::string> pngs;

  // Elastic: E deviation and measured nu against the target nu, one series per sample, d0 and s.
  std::map<std::string, Series> e_dev, nu_meas;
  for (const PatchCaseResult& r : results) {
    if (!r.ok || r.c.test != PatchTest::elastic || r.c.amorphous) continue;  // amorphous: against d0 below
    const std::string key = r.c.sample_label() + ", d0 = " + short_num(r.d0 / r.c.material.critical_diameter()) +
                            " d_c, s = " + short_num(r.c.material.scaling);
    e_dev[key].title = key;
    nu_meas[key].title = key;
    e_dev[key].xy.push_back(
        {r.c.material.poisson_ratio, 100.0 * (r.elastic.moduli.E / r.c.material.youngs_modulus - 1.0)});
    nu_meas[key].xy.push_back({r.c.material.poisson_ratio, r.elastic.moduli.nu});
  }
  if (!e_dev.empty()) {
    std::vector<Series> a, b;
    for (auto& [k, s] : e_dev) a.push_back(s);
    for (auto& [k, s] : nu_meas) b.push_back(s);
    gp << "\n# Fig A.4: measured E against the target nu (target: no deviation)\n"
       << "set output 'elastic_E_deviation.png'\nunset logscale\n"
       << "set title 'Elastic patch test: deviation of the measured E from the target (paper Fig A.4)'\n"
       << "set xlabel 'target Poisson ratio nu'\nset ylabel '100 (E / E_target - 1)  [%]'\n";
    const std::string ca = datablocks(gp, "edev", a, "with linespoints lw 2 pt 7");
    gp << "plot 0 with lines lc 'black' dt 4 lw 2 title 'target (paper: deviation smallest at nu = 0, at most 12% at "
          "nu = 1/4)', \\\n     "
       << ca << "\n";
    gp << "\n# Fig A.5: measured nu against the target nu\n"
       << "set output 'elastic_nu.png'\n"
       << "set title 'Elastic patch test: measured Poisson ratio (paper Fig A.5)'\n"
       << "set xlabel 'target Poisson ratio nu'\nset ylabel 'measured nu = C12 / (C11 + C12)'\n";
    const std::string cb = datablocks(gp, "nu", b, "with linespoints lw 2 pt 7");
    gp << "plot x with lines lc 'black' dt 4 lw 2 title 'target (measured = target)', \\\n     " << cb << "\n";
    pngs.push_back("elastic_E_deviation.png");
    pngs.push_back("elastic_nu.png");
  }

  // Amorphous samples against d0 / d_c (Figs 7, 8, A.6): relaxed volume fraction, E / E_target, measured nu;
  // one series per sample label, nu and s.
  {
    std::map<std::string, Series> phi, young, poisson;
    std::map<double, bool> nu_targets;
    for (const PatchCaseResult& r : results) {
      if (!r.c.amorphous || r.volume_fraction <= 0) continue;
      const double x = r.d0 / r.c.material.critical_diameter();
      const std::string key = r.c.sample_label() + ", nu = " + short_num(r.c.material.poisson_ratio) +
                              ", s = " + short_num(r.c.material.scaling);
      phi[key].title = key;  // one point per sample: the tests of one sample share it
      if (std::find_if(phi[key].xy.begin(), phi[key].xy.end(), [x](const auto& p) { return p.first == x; }) ==
          phi[key].xy.end())
        phi[key].xy.push_back({x, r.volume_fraction});
      if (r.ok && r.c.test == PatchTest::elastic) {
        young[key].title = poisson[key].title = key;
        young[key].xy.push_back({x, r.elastic.moduli.E / r.c.material.youngs_modulus});
        poisson[key].xy.push_back({x, r.elastic.moduli.nu});
        nu_targets[r.c.material.poisson_ratio] = true;
      }
    }
    auto values = [](std::map<std::string, Series>& m) {
      std::vector<Series> v;
      for (auto& [k, s] : m) {
        std::sort(s.xy.begin(), s.xy.end());
        v.push_back(s);
      }
      return v;
    };
    if (!phi.empty()) {
      gp << "\n# Fig 7: relaxed volume fraction of the amorphous samples\n"
         << terminal << "set output 'amorphous_volume_fraction.png'\nset logscale x\nunset logscale y\n"
         << "set title 'Amorphous samples: relaxed volume fraction (paper Fig 7)'\n"
         << "set xlabel 'd0 / d_c'\nset ylabel 'volume fraction (sum of sphere volumes / box volume)'\n";
      const std::string c = datablocks(gp, "phi", values(phi), "with linespoints lw 2 pt 7");
      gp << "plot [0.4:120] pi / (3 * sqrt(2)) with lines lc 'black' dt 4 lw 2 title 'HCP lattice, pi / (3 sqrt 2)', "
            "\\\n     "
         << c << "\n";
      pngs.push_back("amorphous_volume_fraction.png");
    }
    if (!young.empty()) {
      gp << "\n# Fig 8: E of the amorphous samples\n"
         << "set output 'amorphous_E_vs_d0.png'\n"
         << "set title 'Amorphous samples: measured E / target E (paper Fig 8; the paper: no result above 20 d_c, "
            "the samples give way)'\n"
         << "set xlabel 'd0 / d_c'\nset ylabel 'E / E_target'\n";
      const std::string c = datablocks(gp, "young", values(young), "with linespoints lw 2 pt 7");
      gp << "plot [0.4:120] 1 with lines lc 'black' dt 4 lw 2 title 'target', \\\n     " << c << "\n";
      gp << "\n# Fig A.6: nu of the amorphous samples\n"
         << "set output 'amorphous_nu_vs_d0.png'\n"
         << "set title 'Amorphous samples: measured Poisson ratio (paper Fig A.6: about 0.20 for a target of 0.15)'\n"
         << "set xlabel 'd0 / d_c'\nset ylabel 'measured nu'\n";
      std::string lines;
      for (const auto& [nu, unused] : nu_targets)
        lines += num(nu) + " with lines lc 'black' dt 4 lw 2 title " + gp_string("target nu = " + short_num(nu)) +
                 ", \\\n     ";
      const std::string c2 = datablocks(gp, "poisson", values(poisson), "with linespoints lw 2 pt 7");
      gp << "plot [0.4:120] " << lines
         << "0.20 with lines lc 'grey40' dt 2 lw 2 title 'paper, target 0.15: about 0.20', "
         << "\\\n     " << c2 << "\n";
      pngs.push_back("amorphous_E_vs_d0.png");
      pngs.push_back("amorphous_nu_vs_d0.png");
    }
  }

  // Strengths against d0 / d_c, one series per sample, nu and s, with eq 20 for each s.
  for (PatchTest t : {PatchTest::tension, PatchTest::shear}) {
    std::map<std::string, Series> series;
    std::map<double, double> targets;  // s -> sigma (plain strength), for the target curves
    bool any_amorphous = false;
    int no_peak = 0;
    for (const PatchCaseResult& r : results) {
      if (!r.ok || r.c.test != t) continue;
      if (r.strength.outcome == StrengthOutcome::max_strain) {  // still rising: a lower bound, not a strength
        ++no_peak;
        continue;
      }
      const std::string key = r.c.sample_label() + ", nu = " + short_num(r.c.material.poisson_ratio) +
                              ", s = " + short_num(r.c.material.scaling);
      series[key].title = key;
      series[key].xy.push_back({r.d0 / r.c.material.critical_diameter(), r.strength.strength});
      any_amorphous = any_amorphous || r.c.amorphous;
      targets[r.c.material.scaling] =
          t == PatchTest::tension ? r.c.material.tensile_strength : r.c.material.shear_strength;
    }
    if (!series.empty()) {
      std::vector<Series> v;
      for (auto& [k, s] : series) v.push_back(s);
      const std::string name = t == PatchTest::tension ? "tensile" : "shear";
      const std::string png = name + "_strength.png";
      gp << "\n# Fig " << (t == PatchTest::tension ? 5 : 6) << ": " << name << " strength against d0 / d_c\n"
         << terminal << "set output '" << png << "'\nset logscale xy\n"
         << "set title 'Strength patch test (" << patch_test_name(t) << "): measured and target strengths (paper Fig "
         << (t == PatchTest::tension ? 5 : 6) << ")"
         << (no_peak > 0 ? "; " + std::to_string(no_peak) + " case(s) that reached max_strain without a peak left out"
                         : "")
         << "'\n"
         << "set xlabel 'd0 / d_c'\nset ylabel '"
         << (t == PatchTest::tension ? "tensile strength sigma_mN" : "shear strength sigma_mT")
         << "  (peak virial stress)'\n"
         << "set samples 400\n";
      std::string clauses;
      int k = 0;
      for (const auto& [s, sigma] : targets) {
        const std::string f = "target_" + name + "_" + std::to_string(k++) + "(x)";
        gp << f << " = x > 1 ? " << num(sigma) << " * x**(-" << num(s) << ") : " << num(sigma) << "\n";
        const int dash = s == 0.0 ? 4 : 3;  // the paper: dash-dot for s = 0, dotted for s = 0.5
        clauses += f + " with lines lc 'black' dt " + std::to_string(dash) + " lw 2 title " +
                   gp_string("target, eq 20, s = " + short_num(s)) + ", \\\n     ";
        if (any_amorphous) {  // section 3.2: amorphous samples reach 50% (tension) and 56% (shear) of the target
          const double ratio = t == PatchTest::tension ? 0.50 : 0.56;
          clauses += num(ratio) + " * " + f + " with lines lc 'grey40' dt " + std::to_string(dash) + " lw 1.5 title " +
                     gp_string("paper, amorphous: " + short_num(ratio) + " x target, s = " + short_num(s)) +
                     ", \\\n     ";
        }
      }
      const std::string data = datablocks(gp, name, v, "with linespoints lw 2 pt 7");
      gp << "plot [0.4:120] " << clauses << data << "\n";
      pngs.push_back(png);
    }

    // Stress-strain curves (Fig 4 b, c): one plot per sample and nu, colour by d0, dashes by s.
    std::map<std::string, std::vector<const PatchCaseResult*>> groups;  // by file-name tag
    std::map<std::string, std::string> group_titles;
    for (const PatchCaseResult& r : results) {
      if (!r.ok || r.c.test != t) continue;
      std::string tag;  // "hcp_cy_nu0.15": letters, digits, '.', '-' and single '_'
      for (char ch : r.c.sample_label() + "_nu" + short_num(r.c.material.poisson_ratio)) {
        if (ch == '=') continue;
        const bool keep = std::isalnum(static_cast<unsigned char>(ch)) || ch == '.' || ch == '-';
        if (keep)
          tag += ch;
        else if (!tag.empty() && tag.back() != '_')
          tag += '_';
      }
      groups[tag].push_back(&r);
      group_titles[tag] = r.c.sample_label() + ", nu = " + short_num(r.c.material.poisson_ratio);
    }
    int plot = 0;
    for (const auto& [tag, members] : groups) {
      const std::string& group = group_titles[tag];
      std::vector<double> sizes, scalings;
      for (const PatchCaseResult* r : members) {
        sizes.push_back(r->d0);
        scalings.push_back(r->c.material.scaling);
      }
      for (std::vector<double>* v : {&sizes, &scalings}) {
        std::sort(v->begin(), v->end());
        v->erase(std::unique(v->begin(), v->end()), v->end());
      }
      auto rank = [](const std::vector<double>& v, double x) {
        return 1 + static_cast<int>(std::lower_bound(v.begin(), v.end(), x) - v.begin());
      };
      std::vector<Series> curves;
      for (const PatchCaseResult* r : members) {
        Series s;
        s.title = "case " + std::to_string(r->c.index) +
                  ": d0 = " + short_num(r->d0 / r->c.material.critical_diameter()) +
                  " d_c, s = " + short_num(r->c.material.scaling);
        s.style = "with lines lw 1.5 lt " + std::to_string(rank(sizes, r->d0)) + " dt " +
                  std::to_string(rank(scalings, r->c.material.scaling));
        for (const StressStrainPoint& p : r->strength.curve)
          s.xy.push_back({p.strain, t == PatchTest::tension ? p.stress.yy : p.stress.xy});
        curves.push_back(std::move(s));
      }
      const std::string cpng = "stress_strain_" + std::string(patch_test_name(t)) + "_" + tag + ".png";
      gp << "\n# Fig 4 " << (t == PatchTest::tension ? "(b)" : "(c)") << ": stress-strain curves, " << group << "\n"
         << "set terminal pngcairo size 1100," << 700 + 20 * ((curves.size() + 1) / 2)
         << " noenhanced font ',11'\nset output '" << cpng << "'\nunset logscale\n"
         << "set title "
         << gp_string("Strength patch test (" + std::string(patch_test_name(t)) + "), " + group +
                      ": stress of the deformable part")
         << "\nset xlabel '" << (t == PatchTest::tension ? "strain eps_yy" : "shear strain gamma_xy")
         << " (wall displacement / height)'\nset ylabel '" << (t == PatchTest::tension ? "sigma_yy" : "sigma_xy")
         << "'\n";
      const std::string curve_clauses = datablocks(
          gp, std::string(patch_test_name(t)) + "curve" + std::to_string(plot++) + "_", curves, "with lines lw 1.5");
      gp << "plot " << curve_clauses << "\n";
      pngs.push_back(cpng);
    }
  }
  if (pngs.empty()) return "plots: no finished case to plot";

  const fs::path script = fs::path(dir) / "plots.gp";
  {
    std::ofstream out(script, std::ios::binary | std::ios::trunc);
    out << gp.str();
    if (!out) throw input_error("output.directory", script.string(), "cannot write the plot script");
  }
  const GnuplotRun run = run_gnuplot(dir, "plots.gp", "plots.log");
  if (!run.found)
    return "plots skipped: gnuplot not found on the PATH (Debian: apt install gnuplot-nox); run `gnuplot plots.gp` "
           "in " +
           dir + " later";
  const int rc = run.status;
  if (rc != 0) return "plots failed: gnuplot exited with status " + std::to_string(rc) + " (see " + dir + "/plots.log)";
  std::string list;
  for (const std::string& p : pngs) list += (list.empty() ? "" : ", ") + p;
  return "plots drawn with gnuplot: " + list;
}

}  // namespace debris
