#include "scenarios/patch/patch_resume.hpp"

#include <charconv>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/error.hpp"

namespace debris {

namespace {

namespace fs = std::filesystem;

// The fields of one CSV line; a quoted field may hold commas and doubled quotes (as the writer's field()).
std::vector<std::string> split_fields(const std::string& line) {
  std::vector<std::string> f(1);
  bool quoted = false;
  for (std::size_t k = 0; k < line.size(); ++k) {
    const char ch = line[k];
    if (quoted) {
      if (ch == '"' && k + 1 < line.size() && line[k + 1] == '"') {
        f.back() += '"';
        ++k;
      } else if (ch == '"') {
        quoted = false;
      } else {
        f.back() += ch;
      }
    } else if (ch == '"') {
      quoted = true;
    } else if (ch == ',') {
      f.emplace_back();
    } else {
      f.back() += ch;
    }
  }
  return f;
}

// The whole of s as a number (17 digits as written: the same bits).
bool parse(const std::string& s, double& v) {
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  return ec == std::errc() && ptr == s.data() + s.size();
}

// A number of cases.csv; empty: 0. Anything else: not our table.
double number(const std::string& s, const std::string& where) {
  double v = 0;
  if (!s.empty() && !parse(s, v))
    throw input_error("--resume", where, "holds '" + s + "' where a number belongs; is it debris_patch's table?");
  return v;
}

StrengthOutcome outcome_from_name(const std::string& name, const std::string& where) {
  for (StrengthOutcome o : {StrengthOutcome::broke, StrengthOutcome::peak_held, StrengthOutcome::max_strain})
    if (name == strength_outcome_name(o)) return o;
  throw input_error("--resume", where, "names no strength outcome: '" + name + "'");
}

// The stress-strain curve a strength case wrote (write_curve_csv's columns); false when the file is missing
// or torn, so that the case runs again.
bool read_curve(const fs::path& path, std::vector<StressStrainPoint>& curve) {
  std::ifstream in(path, std::ios::binary);
  std::string line;
  if (!in || !std::getline(in, line)) return false;
  if (split_fields(line) != patch_curve_columns()) return false;
  while (std::getline(in, line)) {
    const std::vector<std::string> f = split_fields(line);
    if (f.size() != 10) return false;
    double v[10];
    for (int k = 0; k < 10; ++k)
      if (!parse(f[k], v[k])) return false;
    curve.push_back({static_cast<long>(v[0]), v[1], v[2], {v[3], v[4], v[5], v[6], v[7], v[8]}, v[9]});
  }
  return true;
}

}  // namespace

FinishedCases read_finished_cases(const std::string& dir, const std::vector<PatchCaseResult>& cases) {
  FinishedCases done;
  const fs::path table = fs::path(dir) / "cases.csv";
  std::ifstream in(table, std::ios::binary);
  if (!in) return done;
  std::string line;
  if (!std::getline(in, line)) return done;  // created, killed before the header was flushed
  if (line != patch_cases_header())
    throw input_error("--resume", table.string(),
                      "was written by another version of debris_patch (its columns differ); run afresh into "
                      "another output directory");
  const std::vector<std::string> columns = split_fields(line);
  long line_number = 1;
  while (std::getline(in, line)) {
    ++line_number;
    const std::vector<std::string> f = split_fields(line);
    if (f.size() != columns.size()) {  // the last line of a run killed while writing it
      done.dropped += "line " + std::to_string(line_number) + " of cases.csv is incomplete; ";
      continue;
    }
    const std::string where = table.string() + " line " + std::to_string(line_number);
    std::map<std::string, std::string> row;
    for (std::size_t k = 0; k < columns.size(); ++k) row[columns[k]] = f[k];
    const double index = number(row["case"], where);
    if (index < 1 || index > static_cast<double>(cases.size()) || index != static_cast<int>(index))
      throw input_error("--resume", where, "is case " + row["case"] + ", which this input does not have");
    PatchCaseResult r = cases[static_cast<std::size_t>(index) - 1];
    const PatchCase& c = r.c;
    if (row["test"] != patch_test_name(c.test) || row["sample"] != patch_case_sample(c) ||
        number(row["nu_target"], where) != c.material.poisson_ratio || number(row["s"], where) != c.material.scaling)
      throw input_error("--resume", where,
                        "is not this input's case " + row["case"] + " (" + patch_test_name(c.test) + ", " +
                            patch_case_sample(c) + "): another input wrote it");
    if (done.results.count(c.index) != 0)
      throw input_error("--resume", where, "repeats case " + row["case"] + ", already read from an earlier line");

    r.d0 = number(row["d0"], where);
    r.particles = static_cast<long>(number(row["particles"], where));
    r.deformable = static_cast<long>(number(row["deformable"], where));
    r.size_over_d0 = {number(row["Lx_over_d0"], where), number(row["Ly_over_d0"], where),
                      number(row["Lz_over_d0"], where)};
    r.volume_fraction = number(row["volume_fraction"], where);
    const std::string& status = row["status"];
    r.ok = status == "ok";
    if (!r.ok) r.error = status.rfind("failed: ", 0) == 0 ? status.substr(8) : status;
    const double dt = number(row["dt"], where), steps = number(row["steps"], where);
    const double wall = number(row["wall_seconds"], where);
    const double overlap = number(row["initial_overlap_over_r_min"], where);
    const double limit = number(row["overlap_limit"], where);
    if (c.test == PatchTest::elastic) {
      ElasticResult& e = r.elastic;
      e.eps = number(row["eps_yy"], where);
      e.sigma.xx = number(row["sigma_xx"], where);
      e.sigma.yy = number(row["sigma_yy"], where);
      e.sigma.zz = number(row["sigma_zz"], where);
      e.c11 = number(row["C11"], where);
      e.c12 = number(row["C12"], where);
      e.c13 = number(row["C13"], where);
      e.moduli = {number(row["E"], where), number(row["nu"], where)};
      e.eps_walls = number(row["eps_yy_walls"], where);
      e.sigma_part.yy = number(row["sigma_yy_part"], where);
      e.c11_walls = number(row["C11_walls"], where);
      e.c12_walls = number(row["C12_walls"], where);
      e.moduli_walls = {number(row["E_walls"], where), number(row["nu_walls"], where)};
      e.sigma0.xx = number(row["sigma0_xx"], where);
      e.sigma0.yy = number(row["sigma0_yy"], where);
      e.initial_overlap = overlap;
      e.overlap_limit = limit;
      e.dt = dt;
      e.steps = static_cast<long>(steps);
      e.wall_seconds = wall;
    } else {
      StrengthResult& s = r.strength;
      if (r.ok) {
        s.strength = number(row["strength"], where);
        s.strain_at_peak = number(row["strain_at_peak"], where);
        s.outcome = outcome_from_name(row["outcome"], where);
        s.final_over_peak = number(row["final_over_peak"], where);
        r.target = number(row["target_strength"], where);
        r.curve_file = row["curve_file"];
        if (!read_curve(fs::path(dir) / r.curve_file, s.curve)) {  // killed between the row and its curve
          done.dropped += "case " + row["case"] + "'s curve " + r.curve_file + " is missing or incomplete; ";
          continue;
        }
      }
      s.initial_overlap = overlap;
      s.overlap_limit = limit;
      s.dt = dt;
      s.steps = static_cast<long>(steps);
      s.wall_seconds = wall;
    }
    done.rows.push_back(line);
    done.results[c.index] = std::move(r);
  }
  if (!done.dropped.empty()) done.dropped.resize(done.dropped.size() - 2);  // the last "; "
  return done;
}

}  // namespace debris
