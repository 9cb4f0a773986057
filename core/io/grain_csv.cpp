#include "core/io/grain_csv.hpp"

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <string_view>

#include "core/error.hpp"

namespace debris {

namespace {

std::string_view trim(std::string_view s) {
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string_view::npos) return {};
  return s.substr(b, s.find_last_not_of(" \t\r") - b + 1);
}

std::vector<std::string_view> split_commas(std::string_view s) {
  std::vector<std::string_view> out;
  while (true) {
    const auto comma = s.find(',');
    out.push_back(trim(s.substr(0, comma)));
    if (comma == std::string_view::npos) break;
    s.remove_prefix(comma + 1);
  }
  return out;
}

}  // namespace

std::vector<GrainRecord> read_grain_csv(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw input_error("grain file", path, std::string("cannot be opened for reading: ") + std::strerror(errno));
  static const char* columns[6] = {"i", "x", "y", "z", "r", "o"};
  auto fail = [&](std::size_t line, const std::string& column, std::string_view value, const std::string& what) {
    return input_error(column, "'" + std::string(value) + "'",
                       what + " (" + path + " line " + std::to_string(line + 1) + ")");
  };

  std::vector<GrainRecord> grains;
  bool header = false;
  std::size_t line = 0;
  for (std::string text; std::getline(in, text); ++line) {
    if (trim(text).empty()) continue;
    const std::vector<std::string_view> t = split_commas(text);
    if (!header) {
      bool same = t.size() == 6;
      for (std::size_t k = 0; same && k < 6; ++k) same = t[k] == columns[k];
      if (!same) {
        const bool loc_rad = t.size() == 5 && t[0] == "i" && t[4] == "r";
        throw fail(line, "grain file header", trim(text),
                   loc_rad ? "has no orientation column 'o' (PeriDEM's loc_rad format draws orientations at random; "
                             "give them: 'i, x, y, z, r, o')"
                           : "expected the header 'i, x, y, z, r, o'");
      }
      header = true;
      continue;
    }
    if (t.size() != 6)
      throw fail(line, "grain file", trim(text),
                 "expected 6 comma-separated values (i, x, y, z, r, o), found " + std::to_string(t.size()));
    GrainRecord g;
    long long zone = 0;
    const auto [zone_end, zone_ec] = std::from_chars(t[0].data(), t[0].data() + t[0].size(), zone);
    if (zone_ec != std::errc() || zone_end != t[0].data() + t[0].size())
      throw fail(line, "i", t[0], "the zone index must be a whole number");
    if (zone < 0 || zone > std::numeric_limits<int>::max()) throw fail(line, "i", t[0], "the zone index must be >= 0");
    g.zone = static_cast<int>(zone);
    double v[5];
    for (std::size_t k = 1; k < 6; ++k) {
      const auto [end, ec] = std::from_chars(t[k].data(), t[k].data() + t[k].size(), v[k - 1]);
      if (ec != std::errc() || end != t[k].data() + t[k].size() || !std::isfinite(v[k - 1]))
        throw fail(line, columns[k], t[k], "not a finite number");
    }
    g.x = v[0];
    g.y = v[1];
    g.z = v[2];
    g.radius = v[3];
    g.orientation = v[4];
    if (!(g.radius > 0)) throw fail(line, "r", t[4], "the radius must be > 0");
    grains.push_back(g);
  }
  if (in.bad()) throw input_error("grain file", path, "cannot be read");
  if (!header) throw input_error("grain file", path, "is empty: expected the header 'i, x, y, z, r, o'");
  return grains;
}

}  // namespace debris
