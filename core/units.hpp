#pragma once
// Physical quantities with units in input files: "73 GPa", "2.2 g/cm^3", "20 fs" are converted to SI once,
// when the input is read, so nothing downstream ever sees a unit. A plain number carries no unit and is
// taken as given, in the run's own coherent units (the paper's Table 4 is unitless).
#include <string>

namespace debris::units {

/// Exponents of kg, m and s: enough for every mechanical quantity a DEM input needs.
struct Dimension {
  int mass, length, time;
  friend bool operator==(Dimension, Dimension) = default;
};

inline constexpr Dimension dimensionless{0, 0, 0}, length{0, 1, 0}, time{0, 0, 1}, mass{1, 0, 0},
    pressure{1, -1, -2}, density{1, -3, 0}, surface_energy{1, 0, -2}, velocity{0, 1, -1},
    acceleration{0, 1, -2}, force{1, 1, -2}, energy{1, 2, -2}, frequency{0, 0, -1};

/// The dimension in SI base units, "kg m^-1 s^-2"; empty for a dimensionless quantity.
std::string base_units(Dimension d);

/// "pressure (kg m^-1 s^-2)" for a named dimension, "kg m^2 s^-3" otherwise, "dimensionless" for none.
std::string to_string(Dimension d);

/// Parses a number with an optional unit ("73 GPa", "20fs", "kg m^-3", "1.5 J/m^2") and returns it in SI.
/// Units: m, g, s, Pa, N, J, W, Hz with the prefixes f p n u µ m c k M G T; factors are joined by '*' or
/// a space, divided by '/', raised by '^n' (n may be negative). Once a '/' appears every later factor needs
/// its own '/' ("kg/m/s", not the ambiguous "kg/m s"). Throws InputError naming `key` and the text when
/// the text is malformed or its unit does not have the dimension `expected`.
double parse(const std::string& text, Dimension expected, const std::string& key);

}  // namespace debris::units
