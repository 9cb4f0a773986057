#include "core/io/thermo_csv.hpp"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <system_error>

#include "core/error.hpp"
#include "core/io/text_format.hpp"

namespace debris {

namespace {

std::string header_of(const std::vector<std::string>& columns) {
  std::string header;
  for (const auto& c : columns) header += (header.empty() ? "" : ",") + c;
  return header;
}

std::string row_text(const std::vector<double>& values) {
  std::string line;
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (i > 0) line += ',';
    append_number(line, values[i]);
  }
  line += '\n';
  return line;
}

/// The number a whole cell holds; false for an empty cell or one holding anything else.
bool parse_cell(const char* first, const char* last, double& v) {
  if (first == last) return false;
  const auto r = std::from_chars(first, last, v);
  return r.ec == std::errc() && r.ptr == last;
}

bool is_step(double v) { return std::isfinite(v) && v == std::floor(v) && std::fabs(v) < 1e18; }

/// Whether `line` (without its line break) holds one number per column, the first a step.
bool intact_row(const std::string& line, std::size_t columns, long& step) {
  std::size_t count = 0, begin = 0;
  double first = 0;
  for (;;) {
    const std::size_t end = std::min(line.find(',', begin), line.size());
    double v = 0;
    if (!parse_cell(line.data() + begin, line.data() + end, v)) return false;
    if (count++ == 0) first = v;
    if (end == line.size()) break;
    begin = end + 1;
  }
  if (count != columns || !is_step(first)) return false;
  step = static_cast<long>(first);
  return true;
}

/// The step a damaged row starts with, when its first cell is whole (a comma follows it).
bool leading_step(const std::string& line, long& step) {
  const std::size_t comma = line.find(',');
  double v = 0;
  if (comma == std::string::npos || !parse_cell(line.data(), line.data() + comma, v) || !is_step(v)) return false;
  step = static_cast<long>(v);
  return true;
}

/// "the row of step 2000", "the rows of steps 1000, 1250 and 1500", "12 rows between steps 1000 and 3750"
/// (`steps` sorted).
std::string step_list(const std::vector<long>& steps) {
  if (steps.size() == 1) return "the row of step " + std::to_string(steps[0]);
  if (steps.size() > 4)
    return std::to_string(steps.size()) + " rows between steps " + std::to_string(steps.front()) + " and " +
           std::to_string(steps.back());
  std::string s = "the rows of steps ";
  for (std::size_t k = 0; k < steps.size(); ++k)
    s += (k == 0 ? "" : k + 1 == steps.size() ? " and " : ", ") + std::to_string(steps[k]);
  return s;
}

}  // namespace

ThermoCsv::ThermoCsv(const std::string& path, std::vector<std::string> columns)
    : path_(path), columns_(std::move(columns)) {
  if (columns_.empty()) throw std::invalid_argument("ThermoCsv '" + path + "': no columns");
  for (const auto& c : columns_) {
    // Names are written unquoted, so anything that would need CSV quoting is refused.
    if (c.empty() || c.find_first_of(",\"\r\n") != std::string::npos)
      throw std::invalid_argument("ThermoCsv '" + path + "': bad column name '" + c + "'");
  }
  out_.open(path, std::ios::binary | std::ios::trunc);
  if (!out_) throw output_error(path, std::string("cannot open for writing: ") + std::strerror(errno));
  out_ << header_of(columns_) << '\n' << std::flush;
  if (!out_) throw output_error(path, "writing the header failed (disk full?)");
}

ThermoCsv::ThermoCsv(const std::string& path, std::vector<std::string> columns, long keep_up_to_step)
    : ThermoCsv(path, std::move(columns), ThermoResume{keep_up_to_step, 0, {}}) {}

ThermoCsv::ThermoCsv(const std::string& path, std::vector<std::string> columns, const ThermoResume& resume)
    : path_(path), columns_(std::move(columns)) {
  const std::string name = std::filesystem::path(path).filename().string();
  std::string text;
  {
    std::ifstream in(path, std::ios::binary);
    if (!in) {  // nothing to resume
      *this = ThermoCsv(path, columns_);
      return;
    }
    text.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  const std::string expected = header_of(columns_);
  const std::size_t header_end = text.find('\n');
  // Empty, or cut inside the header line: nothing of it can be kept, as if it were missing.
  if (header_end == std::string::npos && expected.compare(0, text.size(), text) == 0) {
    *this = ThermoCsv(path, columns_);
    if (!text.empty()) note_ = name + ": cut inside its header line before this restart: it starts afresh";
    return;
  }
  if (text.substr(0, header_end) != expected)
    throw input_error("output", path, "cannot resume: its columns differ from this run's (" + expected + ")");

  const long keep = resume.keep_up_to_step;
  std::map<long, std::string> rows;  // the rows kept, by step
  long last_intact = -1, damaged = 0;
  std::vector<long> damaged_steps;
  std::size_t begin = header_end + 1;
  while (begin < text.size()) {
    const std::size_t end = text.find('\n', begin);
    const bool whole = end != std::string::npos;  // a row without its line break was cut short
    const std::string line = text.substr(begin, (whole ? end : text.size()) - begin);
    begin = whole ? end + 1 : text.size();
    if (line.empty()) continue;
    long step = 0;
    if (whole && intact_row(line, columns_.size(), step)) {
      if (step <= keep) {
        rows.emplace(step, line + '\n');
        last_intact = std::max(last_intact, step);
        continue;
      }
    } else if (!leading_step(line, step) || step <= keep) {
      ++damaged;
      if (leading_step(line, step)) damaged_steps.push_back(step);
      continue;
    }
    ++dropped_;  // written after the checkpoint by the run that stopped
    dropped_to_ = std::max(dropped_to_, step);
  }
  std::vector<long> rewritten, lost;
  for (const auto& [step, values] : resume.known) {
    if (step > keep || rows.count(step) != 0) continue;
    if (values.size() != columns_.size())
      throw std::logic_error("ThermoCsv '" + path + "': a known row has " + std::to_string(values.size()) +
                             " values for " + std::to_string(columns_.size()) + " columns");
    rows.emplace(step, row_text(values));
    rewritten.push_back(step);
  }
  // The rows due after the last intact one that neither the file nor the caller has, and the damaged rows
  // nothing replaced.
  if (resume.every > 0)
    for (long s = last_intact < 0 ? 0 : (last_intact / resume.every + 1) * resume.every; s <= keep; s += resume.every)
      if (rows.count(s) == 0) lost.push_back(s);
  for (long s : damaged_steps)
    if (rows.count(s) == 0) lost.push_back(s);
  std::sort(lost.begin(), lost.end());
  lost.erase(std::unique(lost.begin(), lost.end()), lost.end());

  if (damaged > 0 || !rewritten.empty() || !lost.empty()) {
    note_ = name + " was cut short or damaged before this restart:";
    if (damaged > 0)
      note_ += " " + std::to_string(damaged) + (damaged == 1 ? " row" : " rows") + " cut short or unreadable " +
               (damaged == 1 ? "is" : "are") + " dropped;";
    auto are = [](const std::vector<long>& steps) { return steps.size() == 1 ? " is " : " are "; };
    if (!rewritten.empty()) note_ += " " + step_list(rewritten) + are(rewritten) + "rewritten from the checkpoint;";
    if (!lost.empty())
      note_ += " " + step_list(lost) + are(lost) + "lost (neither intact in the file nor in the checkpoint);";
    note_.back() = '.';
  }

  std::string kept = expected + '\n';
  for (const auto& [step, line] : rows) kept += line;
  // Rewritten through a temporary file, so a crash here keeps the old table.
  const std::string tmp = path + ".tmp";
  {
    std::ofstream t(tmp, std::ios::binary | std::ios::trunc);
    t << kept;
    if (!t) throw output_error(tmp, "cannot write (disk full?)");
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0)
    throw output_error(path, std::string("cannot replace: ") + std::strerror(errno));
  out_.open(path, std::ios::binary | std::ios::app);
  if (!out_) throw output_error(path, std::string("cannot open for appending: ") + std::strerror(errno));
}

void ThermoCsv::write_row(const std::vector<double>& values) {
  if (values.size() != columns_.size())
    throw std::logic_error("ThermoCsv '" + path_ + "': row has " + std::to_string(values.size()) +
                           " values for " + std::to_string(columns_.size()) + " columns");
  const std::string line = row_text(values);
  out_.write(line.data(), static_cast<std::streamsize>(line.size()));
  out_.flush();
  if (!out_) throw output_error(path_, "writing a row failed (disk full?)");
}

}  // namespace debris
