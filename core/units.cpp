#include "core/units.hpp"

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <optional>
#include <string_view>

#include "core/error.hpp"

namespace debris::units {

namespace {

struct NamedDimension {
  Dimension dim;
  const char* name;
  const char* expectation;  // what to tell a user who gave something else
};

constexpr NamedDimension named_dimensions[] = {
    {dimensionless, "dimensionless", "a plain number such as '0.3'"},
    {length, "length", "a length such as '1.5 nm'"},
    {time, "time", "a time such as '20 fs'"},
    {mass, "mass", "a mass such as '1e-21 kg'"},
    {pressure, "pressure", "a pressure such as '73 GPa'"},
    {density, "density", "a density such as '2200 kg/m^3'"},
    {surface_energy, "surface energy", "a surface energy such as '1.5 J/m^2'"},
    {velocity, "velocity", "a velocity such as '10 m/s'"},
    {acceleration, "acceleration", "an acceleration such as '9.81 m/s^2'"},
    {force, "force", "a force such as '1 nN'"},
    {energy, "energy", "an energy such as '1e-18 J'"},
    {frequency, "frequency", "a frequency such as '1 THz'"},
};

const NamedDimension* find_named(Dimension d) {
  for (const auto& n : named_dimensions)
    if (n.dim == d) return &n;
  return nullptr;
}


/// "a length (m)", "an energy (kg m^2 s^-2)": what a unit the user wrote turned out to measure.
std::string describe(Dimension d) {
  if (d == dimensionless) return "dimensionless";
  const NamedDimension* n = find_named(d);
  if (!n) return "a quantity in " + base_units(d);
  const bool vowel = std::string_view("aeiou").find(n->name[0]) != std::string_view::npos;
  return std::string(vowel ? "an " : "a ") + n->name + " (" + base_units(d) + ")";
}

std::string expectation(Dimension d) {
  if (const NamedDimension* n = find_named(d)) return n->expectation;
  return "a quantity in " + base_units(d);
}

/// A unit as dimension exponents plus a power of ten: SI value = value * 10^decade. Every supported unit
/// is a decimal multiple of SI, which lets parse() rescale the number's own decimal text exactly.
struct Unit {
  Dimension dim{0, 0, 0};
  int decade = 0;
};

struct Symbol {
  std::string_view text;
  Unit unit;
};

constexpr Symbol base_symbols[] = {
    {"m", {length, 0}},   {"g", {mass, -3}},  {"s", {time, 0}},   {"Pa", {pressure, 0}},
    {"N", {force, 0}},    {"J", {energy, 0}}, {"W", {{1, 2, -3}, 0}}, {"Hz", {frequency, 0}},
};

constexpr std::pair<std::string_view, int> prefixes[] = {
    {"f", -15}, {"p", -12}, {"n", -9}, {"u", -6}, {"\xc2\xb5", -6} /* µ micro sign */,
    {"\xce\xbc", -6} /* μ Greek mu */, {"m", -3}, {"c", -2}, {"k", 3}, {"M", 6}, {"G", 9}, {"T", 12},
};

/// Exact symbols first, so that "m" is a metre, "mm" a millimetre and "Pa" a pascal.
std::optional<Unit> lookup(std::string_view symbol) {
  for (const auto& b : base_symbols)
    if (symbol == b.text) return b.unit;
  for (const auto& [prefix, decade] : prefixes) {
    if (!symbol.starts_with(prefix)) continue;
    const std::string_view rest = symbol.substr(prefix.size());
    for (const auto& b : base_symbols)
      if (rest == b.text) return Unit{b.unit.dim, b.unit.decade + decade};
  }
  return std::nullopt;
}

bool is_space(char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; }

std::string trim(std::string_view s) {
  std::size_t b = 0, e = s.size();
  while (b < e && is_space(s[b])) ++b;
  while (e > b && is_space(s[e - 1])) --e;
  return std::string(s.substr(b, e - b));
}

class UnitParser {
 public:
  UnitParser(const std::string& units, const std::string& text, Dimension expected, const std::string& key)
      : s_(units), text_(text), expected_(expected), key_(key) {}

  Unit parse() {
    Unit total;
    bool divided = false;
    for (bool first = true;; first = false) {
      skip_spaces();
      if (i_ == s_.size()) break;
      int sign = 1;
      if (!first) {
        const bool explicit_op = s_[i_] == '*' || s_[i_] == '/';
        if (s_[i_] == '/') {
          sign = -1;
          divided = true;
        } else if (divided) {
          // "kg/m s" reads as kg/(m s) to some and (kg/m) s to others; make the user say which.
          fail("ambiguous unit after '/'; give every factor of the denominator its own '/', e.g. 'kg/m/s'");
        }
        if (explicit_op) ++i_;
        skip_spaces();
      }
      const Unit u = factor();
      total.dim.mass += sign * u.dim.mass;
      total.dim.length += sign * u.dim.length;
      total.dim.time += sign * u.dim.time;
      total.decade += sign * u.decade;
    }
    return total;
  }

 private:
  void skip_spaces() {
    while (i_ < s_.size() && is_space(s_[i_])) ++i_;
  }

  [[noreturn]] void fail(const std::string& what) const {
    throw input_error(key_, text_, what + "; expected " + expectation(expected_));
  }

  /// One symbol with an optional integer exponent: "cm^3", "m^-1", "GPa".
  Unit factor() {
    const std::size_t start = i_;
    while (i_ < s_.size() && !is_space(s_[i_]) && s_[i_] != '*' && s_[i_] != '/' && s_[i_] != '^') ++i_;
    const std::string symbol = s_.substr(start, i_ - start);
    if (symbol.empty()) fail("missing unit symbol at '" + s_.substr(start) + "'");
    const std::optional<Unit> base = lookup(symbol);
    if (!base)
      fail("unknown unit '" + symbol +
           "' (known: m g s Pa N J W Hz with prefixes f p n u m c k M G T, e.g. nm fs kg GPa g/cm^3)");
    int power = 1;
    std::size_t j = i_;
    while (j < s_.size() && is_space(s_[j])) ++j;
    if (j < s_.size() && s_[j] == '^') {
      i_ = j + 1;
      skip_spaces();
      int sign = 1;
      if (i_ < s_.size() && (s_[i_] == '-' || s_[i_] == '+')) sign = s_[i_++] == '-' ? -1 : 1;
      const std::size_t digits = i_;
      while (i_ < s_.size() && std::isdigit(static_cast<unsigned char>(s_[i_])) && i_ - digits < 3) ++i_;
      if (i_ == digits) fail("'^' after '" + symbol + "' must be followed by an integer exponent");
      power = sign * std::stoi(s_.substr(digits, i_ - digits));
    }
    if (i_ < s_.size() && !is_space(s_[i_]) && s_[i_] != '*' && s_[i_] != '/')
      fail("unexpected '" + s_.substr(i_) + "' in the unit");
    const Dimension d = base->dim;
    return Unit{{d.mass * power, d.length * power, d.time * power}, base->decade * power};
  }

  const std::string& s_;
  const std::string& text_;
  Dimension expected_;
  const std::string& key_;
  std::size_t i_ = 0;
};

/// number * 10^decade, rounded once: the decimal exponent is shifted in the text and strtod rounds the
/// result, so "1.5 nm" gives exactly the double 1.5e-9 (hexadecimal numbers are scaled arithmetically).
double scale_decimal(const std::string& number, double value, int decade) {
  if (decade == 0) return value;
  if (number.find_first_of("xX") != std::string::npos)
    return decade > 0 ? value * std::pow(10.0, decade) : value / std::pow(10.0, -decade);
  const std::size_t e = number.find_first_of("eE");
  long exponent = decade;
  if (e != std::string::npos) exponent += std::strtol(number.c_str() + e + 1, nullptr, 10);
  const std::string shifted = number.substr(0, e) + "e" + std::to_string(exponent);
  return std::strtod(shifted.c_str(), nullptr);
}

}  // namespace

std::string base_units(Dimension d) {
  std::string out;
  const auto add = [&out](const char* symbol, int power) {
    if (power == 0) return;
    if (!out.empty()) out += ' ';
    out += symbol;
    if (power != 1) {
      out += '^';  // appended in two steps: "^" + to_string() trips GCC 12's bogus -Wrestrict
      out += std::to_string(power);
    }
  };
  add("kg", d.mass);
  add("m", d.length);
  add("s", d.time);
  return out;
}

std::string to_string(Dimension d) {
  if (d == dimensionless) return "dimensionless";
  if (const NamedDimension* n = find_named(d)) return std::string(n->name) + " (" + base_units(d) + ")";
  return base_units(d);
}

double parse(const std::string& text, Dimension expected, const std::string& key) {
  const std::string t = trim(text);
  const auto fail = [&](const std::string& what) {
    return input_error(key, "'" + text + "'", what + "; expected " + expectation(expected));
  };
  if (t.empty()) throw fail("empty value");

  char* end = nullptr;
  errno = 0;
  const double value = std::strtod(t.c_str(), &end);
  if (end == t.c_str()) throw fail("not a number");
  if (!std::isfinite(value)) throw fail("not a finite number");
  if (errno == ERANGE) throw fail("out of the range of a double");
  const std::string number(t.c_str(), static_cast<std::size_t>(end - t.c_str()));
  const std::string unit_text = trim(end);
  if (unit_text.empty()) return value;  // no unit: already in the run's own coherent units

  const Unit unit = UnitParser(unit_text, "'" + text + "'", expected, key).parse();
  if (!(unit.dim == expected)) {
    throw fail("'" + unit_text + "' is " + describe(unit.dim));
  }
  errno = 0;
  const double si = scale_decimal(number, value, unit.decade);
  if (!std::isfinite(si) || errno == ERANGE || (si == 0.0 && value != 0.0))
    throw fail("out of the range of a double once converted to SI");
  return si;
}

}  // namespace debris::units
