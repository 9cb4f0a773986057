// Quantities with units in input files are converted to SI exactly as the equivalent literal would be.
#include "core/units.hpp"

#include <gtest/gtest.h>

#include <string>

#include "core/error.hpp"

namespace debris {
namespace {

using units::parse;

/// The message of the InputError that parse() throws, or "" if it does not throw.
std::string parse_error(const std::string& text, units::Dimension dim, const std::string& key = "k") {
  try {
    parse(text, dim, key);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(UnitsParse, ExamplesConvertToSi) {
  // Decimal prefixes are applied to the number's text, so each result is the nearest double to the SI value.
  EXPECT_EQ(parse("73 GPa", units::pressure, "E"), 7.3e10);
  EXPECT_EQ(parse("1.5 nm", units::length, "d"), 1.5e-9);
  EXPECT_EQ(parse("20 fs", units::time, "dt"), 2e-14);
  EXPECT_EQ(parse("2200 kg/m^3", units::density, "rho"), 2200.0);
  EXPECT_EQ(parse("2.2 g/cm^3", units::density, "rho"), 2200.0);
  EXPECT_EQ(parse("1.5 N/m", units::surface_energy, "gamma"), 1.5);
  EXPECT_EQ(parse("1.5 J/m^2", units::surface_energy, "gamma"), 1.5);
  EXPECT_EQ(parse("10 m/s", units::velocity, "v"), 10.0);
  EXPECT_EQ(parse("9.81 m/s^2", units::acceleration, "g"), 9.81);
  EXPECT_EQ(parse("100 MPa", units::pressure, "p"), 1e8);
  EXPECT_EQ(parse("1e-3", units::dimensionless, "x"), 1e-3);
  EXPECT_EQ(parse("-0.5", units::dimensionless, "x"), -0.5);
}

TEST(UnitsParse, PlainNumberIsKeptInRunUnits) {
  EXPECT_EQ(parse("73", units::pressure, "E"), 73.0);
  EXPECT_EQ(parse("  0.25 ", units::length, "d"), 0.25);
  EXPECT_EQ(parse("+4e2", units::time, "t"), 400.0);
}

TEST(UnitsParse, PrefixesAndBaseUnits) {
  EXPECT_EQ(parse("3 ps", units::time, "t"), 3e-12);
  EXPECT_EQ(parse("3 ns", units::time, "t"), 3e-9);
  EXPECT_EQ(parse("3 us", units::time, "t"), 3e-6);
  EXPECT_EQ(parse("3 \xc2\xb5s", units::time, "t"), 3e-6);  // micro sign
  EXPECT_EQ(parse("3 \xce\xbcs", units::time, "t"), 3e-6);  // Greek mu
  EXPECT_EQ(parse("3 ms", units::time, "t"), 3e-3);
  EXPECT_EQ(parse("3 s", units::time, "t"), 3.0);
  EXPECT_EQ(parse("3 um", units::length, "l"), 3e-6);
  EXPECT_EQ(parse("3 mm", units::length, "l"), 3e-3);
  EXPECT_EQ(parse("3 cm", units::length, "l"), 3e-2);
  EXPECT_EQ(parse("3 m", units::length, "l"), 3.0);
  EXPECT_EQ(parse("3 km", units::length, "l"), 3e3);
  EXPECT_EQ(parse("3 mg", units::mass, "m"), 3e-6);
  EXPECT_EQ(parse("3 g", units::mass, "m"), 3e-3);
  EXPECT_EQ(parse("3 kg", units::mass, "m"), 3.0);
  EXPECT_EQ(parse("3 kPa", units::pressure, "p"), 3e3);
  EXPECT_EQ(parse("3 Pa", units::pressure, "p"), 3.0);
  EXPECT_EQ(parse("3 TPa", units::pressure, "p"), 3e12);
  EXPECT_EQ(parse("3 mN", units::force, "f"), 3e-3);
  EXPECT_EQ(parse("3 kN", units::force, "f"), 3e3);
  EXPECT_EQ(parse("3 nN", units::force, "f"), 3e-9);
  EXPECT_EQ(parse("3 mJ", units::energy, "e"), 3e-3);
  EXPECT_EQ(parse("3 fJ", units::energy, "e"), 3e-15);
  EXPECT_EQ(parse("3 W/m", units::Dimension{1, 1, -3}, "q"), 3.0);
  EXPECT_EQ(parse("3 GHz", units::frequency, "f"), 3e9);
  EXPECT_EQ(parse("3 Hz", units::frequency, "f"), 3.0);
}

TEST(UnitsParse, ProductsQuotientsAndExponents) {
  EXPECT_EQ(parse("2200 kg m^-3", units::density, "rho"), 2200.0);
  EXPECT_EQ(parse("2200 kg*m^-3", units::density, "rho"), 2200.0);
  EXPECT_EQ(parse("2200 kg / m^3", units::density, "rho"), 2200.0);
  EXPECT_EQ(parse("5 N*m", units::energy, "e"), 5.0);
  EXPECT_EQ(parse("5 N m", units::energy, "e"), 5.0);
  EXPECT_EQ(parse("5 kg m^2 s^-2", units::energy, "e"), 5.0);
  EXPECT_EQ(parse("5 kg/m/s^2", units::pressure, "p"), 5.0);
  EXPECT_EQ(parse("5 m s^-1", units::velocity, "v"), 5.0);
  EXPECT_EQ(parse("5 s^-1", units::frequency, "f"), 5.0);
  EXPECT_EQ(parse("5 nm/ps", units::velocity, "v"), 5e3);
  EXPECT_EQ(parse("2 m/m", units::dimensionless, "ratio"), 2.0);
}

TEST(UnitsParse, NoSpaceBetweenNumberAndUnit) {
  EXPECT_EQ(parse("20fs", units::time, "dt"), 2e-14);
  EXPECT_EQ(parse("1.5e2GPa", units::pressure, "E"), 1.5e11);
  EXPECT_EQ(parse("2e-3m", units::length, "l"), 2e-3);
}

TEST(UnitsParse, ExponentInTheNumberCombinesWithThePrefix) {
  EXPECT_EQ(parse("7.3e1 GPa", units::pressure, "E"), 7.3e10);
  EXPECT_EQ(parse("1.5E-3 nm", units::length, "d"), 1.5e-12);
  EXPECT_EQ(parse("-2.5 MPa", units::pressure, "p"), -2.5e6);
}

TEST(UnitsParse, DimensionMismatchNamesKeyTextAndExpectation) {
  const std::string msg = parse_error("73 nm", units::pressure, "material.youngs_modulus");
  EXPECT_NE(msg.find("material.youngs_modulus"), std::string::npos) << msg;
  EXPECT_NE(msg.find("73 nm"), std::string::npos) << msg;
  EXPECT_NE(msg.find("expected a pressure such as '73 GPa'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("is a length"), std::string::npos) << msg;

  EXPECT_NE(parse_error("1.5 N", units::surface_energy).find("force"), std::string::npos);
  EXPECT_NE(parse_error("2 m/m", units::length).find("dimensionless"), std::string::npos);
  EXPECT_NE(parse_error("1 kg m^2 s^-3", units::energy).find("kg m^2 s^-3"), std::string::npos);
}

TEST(UnitsParse, MalformedTextThrows) {
  for (const char* bad : {"abc", "1.2.3", "5 furlongs", "nan", "inf", "-inf", "", "   ", "GPa", "1e999",
                          "5 m^", "5 m^x", "5 /s", "5 m/", "5 m**s", "5 kg/m s", "5 m^2kg", "5 Gm Pa"}) {
    const std::string msg = parse_error(bad, units::length, "geometry.size");
    EXPECT_NE(msg, "") << "'" << bad << "' was accepted";
    EXPECT_NE(msg.find("geometry.size"), std::string::npos) << msg;
  }
  EXPECT_NE(parse_error("5 furlongs", units::length).find("unknown unit 'furlongs'"), std::string::npos);
  EXPECT_NE(parse_error("5 kg/m s", units::pressure).find("ambiguous"), std::string::npos);
  EXPECT_NE(parse_error("abc", units::length).find("not a number"), std::string::npos);
}

TEST(UnitsParse, ExactSymbolsWinOverPrefixes) {
  EXPECT_EQ(parse("1 m", units::length, "l"), 1.0);     // metre, not milli-something
  EXPECT_EQ(parse("1 Pa", units::pressure, "p"), 1.0);  // pascal
  EXPECT_EQ(parse("1 mm", units::length, "l"), 1e-3);
  EXPECT_EQ(parse("1 ms", units::time, "t"), 1e-3);
  EXPECT_NE(parse_error("1 ms", units::length), "");  // a millisecond is not a metre-second
}

TEST(UnitsToString, NamesAndBaseUnits) {
  EXPECT_EQ(units::to_string(units::pressure), "pressure (kg m^-1 s^-2)");
  EXPECT_EQ(units::to_string(units::density), "density (kg m^-3)");
  EXPECT_EQ(units::to_string(units::length), "length (m)");
  EXPECT_EQ(units::to_string(units::dimensionless), "dimensionless");
  EXPECT_EQ(units::to_string(units::Dimension{1, 2, -3}), "kg m^2 s^-3");
}

}  // namespace
}  // namespace debris
