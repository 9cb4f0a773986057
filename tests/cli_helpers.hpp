#pragma once
// Helpers of the tests that run the real executables or write files: a command's exit status and output,
// a fresh scratch directory under GoogleTest's temp dir, a small text file, a file's text, the frames an XDMF file lists.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace debris::test {

struct CommandResult {
  int exit_code;       // -1 when the command did not exit normally
  std::string output;  // stdout and stderr
};

/// The `material:` section of a debris_dem input for the Table 4 material of paper A (reduced units), which
/// the command-line tests' small inputs share; tests edit its lines ("poisson_ratio: 0.15") to make bad ones.
inline constexpr const char* kTable4MaterialYaml = R"(material:
  youngs_modulus: 1
  poisson_ratio: 0.15
  tensile_strength: 0.2
  shear_strength: 0.1
  surface_energy: 1.5
  restitution: 0.95
  density: 1
)";

/// Runs `executable args` through the shell with stderr folded into stdout.
inline CommandResult run_command(const std::string& executable, const std::string& args) {
  const std::string cmd = executable + " " + args + " 2>&1";
  FILE* pipe = popen(cmd.c_str(), "r");
  std::string out;
  std::array<char, 4096> buf{};
  while (pipe && fgets(buf.data(), buf.size(), pipe)) out += buf.data();
  const int status = pipe ? pclose(pipe) : -1;
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}

/// An empty directory `<temp>/<name>`, removed first if a previous run left it.
inline std::filesystem::path fresh_directory(const std::string& name) {
  const std::filesystem::path d = std::filesystem::path(::testing::TempDir()) / name;
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  return d;
}

/// `text` with its first `from` replaced by `to`, the way the tests make a bad input from a good one; a test
/// failure when `from` is not there (an edit that did nothing would test the unedited input).
inline bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

template <class V>
double sum(const V& v) {
  double s = 0;
  for (double x : v) s += x;
  return s;
}

inline std::string replace(std::string text, const std::string& from, const std::string& to) {
  const auto pos = text.find(from);
  EXPECT_NE(pos, std::string::npos) << from;
  if (pos != std::string::npos) text.replace(pos, from.size(), to);
  return text;
}

/// Writes `text` to `dir`/`name` and returns the path.
inline std::string write_text_file(const std::filesystem::path& dir, const std::string& name, const std::string& text) {
  const std::filesystem::path path = dir / name;
  std::ofstream(path) << text;
  return path.string();
}

/// The same, as a path.
inline std::filesystem::path write(const std::filesystem::path& dir, const std::string& name, const std::string& text) {
  return std::filesystem::path(write_text_file(dir, name, text));
}

/// The whole file as text ("" when it cannot be read).
inline std::string slurp(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

/// A CSV file's rows as column name -> cell text (the first line names the columns; quoted cells are kept
/// whole, without their quotes; empty lines and lines starting with '#' are skipped).
inline std::vector<std::map<std::string, std::string>> read_csv_rows(const std::filesystem::path& path) {
  std::istringstream in(slurp(path));
  auto split = [](const std::string& line) {
    std::vector<std::string> cells(1);
    bool quoted = false;
    for (char c : line) {
      if (c == '"') quoted = !quoted;
      else if (c == ',' && !quoted) cells.emplace_back();
      else if (c != '\r') cells.back() += c;
    }
    return cells;
  };
  std::string line;
  std::vector<std::map<std::string, std::string>> rows;
  if (!std::getline(in, line)) return rows;
  const std::vector<std::string> header = split(line);
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    const std::vector<std::string> cells = split(line);
    std::map<std::string, std::string> row;
    for (std::size_t k = 0; k < header.size() && k < cells.size(); ++k) row[header[k]] = cells[k];
    rows.push_back(row);
  }
  return rows;
}

/// The number in column `key` of a row from read_csv_rows (a test failure and NaN when it is missing).
inline double csv_number(const std::map<std::string, std::string>& row, const std::string& key) {
  const auto it = row.find(key);
  EXPECT_NE(it, row.end()) << "no column " << key;
  if (it == row.end() || it->second.empty()) return std::numeric_limits<double>::quiet_NaN();
  return std::stod(it->second);
}

/// A numeric CSV with a header row (thermo.csv): columns by name, rows of doubles.
struct NumberTable {
  std::vector<std::string> columns;
  std::vector<std::vector<double>> rows;
  /// The index of column `name` (a test failure and 0 when it is missing).
  std::size_t column(const std::string& name) const {
    for (std::size_t k = 0; k < columns.size(); ++k)
      if (columns[k] == name) return k;
    ADD_FAILURE() << "no column " << name;
    return 0;
  }
  /// Mean of column `name` over the rows whose first cell (the step) lies in [first, last].
  double mean(const std::string& name, double first, double last) const {
    const std::size_t c = column(name);
    double sum = 0;
    int count = 0;
    for (const auto& r : rows)
      if (r[0] >= first && r[0] <= last) {
        sum += r[c];
        ++count;
      }
    EXPECT_GT(count, 0);
    return count ? sum / count : 0.0;
  }
};

inline NumberTable read_number_table(const std::filesystem::path& path) {
  NumberTable t;
  std::istringstream in(slurp(path));
  std::string line;
  std::getline(in, line);
  std::stringstream head(line);
  for (std::string cell; std::getline(head, cell, ',');) t.columns.push_back(cell);
  while (std::getline(in, line)) {
    std::vector<double> row;
    std::stringstream ss(line);
    for (std::string cell; std::getline(ss, cell, ',');) row.push_back(std::stod(cell));
    t.rows.push_back(row);
  }
  return t;
}

/// How many frames an XDMF trajectory lists (one <Time> per frame).
inline int count_xmf_frames(const std::filesystem::path& xmf) {
  const std::string x = slurp(xmf);
  int frames = 0;
  for (auto at = x.find("<Time "); at != std::string::npos; at = x.find("<Time ", at + 1)) ++frames;
  return frames;
}

}  // namespace debris::test
