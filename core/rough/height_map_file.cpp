#include "core/rough/height_map_file.hpp"

#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "core/error.hpp"

namespace debris {

namespace {

InputError map_error(const std::string& path, long line, const std::string& what) {
  std::string s = "input error: height map '";  // appended: GCC 12 warns falsely (-Wrestrict) on "'" + string
  s += path;
  s += "'";
  if (line > 0) s += ", line " + std::to_string(line);
  s += ": ";
  s += what;
  return InputError(s);
}

bool separator(char c) { return c == ' ' || c == '\t' || c == ',' || c == '\r' || c == '\v' || c == '\f'; }

// A value as the C locale writes it (std::from_chars: a decimal point whatever the user's locale), with an
// optional '+'; NaN and inf read as numbers and are refused by the caller.
bool parse_number(const std::string& token, double& v) {
  const char* first = token.data();
  const char* last = first + token.size();
  if (first != last && *first == '+') ++first;
  const auto [end, ec] = std::from_chars(first, last, v);
  return ec == std::errc() && end == last && first != last;
}

}  // namespace

HeightField read_height_map(const std::string& path, int normal_axis, double spacing_a, double spacing_b,
                            double height_unit) {
  if (normal_axis < 0 || normal_axis > 2)
    throw std::invalid_argument("read_height_map: normal_axis = " + std::to_string(normal_axis) + ": must be 0, 1 or 2");
  if (!(spacing_a > 0) || !std::isfinite(spacing_a))
    throw std::invalid_argument("read_height_map: spacing_a = " + format_value(spacing_a) + ": must be > 0");
  if (!(height_unit > 0) || !std::isfinite(height_unit))
    throw std::invalid_argument("read_height_map: height_unit = " + format_value(height_unit) + ": must be > 0");
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw map_error(path, 0, "is a directory, not a file of heights");
  std::ifstream in(path);
  if (!in) throw map_error(path, 0, "cannot be opened (missing or unreadable)");

  HeightField f;
  f.normal_axis = normal_axis;
  std::string text;
  long line_no = 0, first_row_line = 0;
  int columns = 0;
  while (std::getline(in, text)) {
    ++line_no;
    const std::size_t hash = text.find('#');
    if (hash != std::string::npos) text.resize(hash);
    int count = 0;
    std::size_t p = 0;
    while (p < text.size()) {
      while (p < text.size() && separator(text[p])) ++p;
      if (p == text.size()) break;
      std::size_t e = p;
      while (e < text.size() && !separator(text[e])) ++e;
      const std::string token = text.substr(p, e - p);
      double v;
      if (!parse_number(token, v)) throw map_error(path, line_no, "'" + token + "' is not a number");
      if (!std::isfinite(v)) throw map_error(path, line_no, "'" + token + "' is not a finite height");
      f.h.push_back(v * height_unit);
      ++count;
      p = e;
    }
    if (count == 0) continue;  // blank or comment
    if (columns == 0) {
      columns = count;
      first_row_line = line_no;
    } else if (count != columns) {
      throw map_error(path, line_no,
                      std::to_string(count) + " values, but the first row (line " + std::to_string(first_row_line) +
                          ") has " + std::to_string(columns) + ": every row needs the same number");
    }
    ++f.n_a;
  }
  if (in.bad()) throw map_error(path, 0, "reading failed after line " + std::to_string(line_no));
  if (f.n_a == 0) throw map_error(path, 0, "holds no heights (empty, or only comments and blank lines)");
  f.n_b = columns;
  if (f.n_b > 1 && (!(spacing_b > 0) || !std::isfinite(spacing_b)))
    throw std::invalid_argument("read_height_map: spacing_b = " + format_value(spacing_b) + ": must be > 0 for '" +
                                path + "', which has " + std::to_string(f.n_b) + " columns");
  f.length_a = spacing_a * f.n_a;
  f.length_b = f.n_b > 1 ? spacing_b * f.n_b : (spacing_b > 0 ? spacing_b : 0.0);
  return f;
}

}  // namespace debris
