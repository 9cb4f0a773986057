#include "core/rough/self_affine_input.hpp"

#include <cmath>

#include "core/error.hpp"
#include "core/io/input.hpp"
#include "core/io/key_reference.hpp"

namespace debris {

namespace {

std::string key_path(const InputNode& node, const std::string& key) {
  return node.path().empty() ? key : node.path() + "." + key;
}

// Appended piece by piece: GCC 12 warns falsely (-Wrestrict) on "..." + std::string at -O3.
std::string length_text(double v) {
  std::string s = format_value(v);
  s += " m";
  return s;
}

}  // namespace

SelfAffineSpec read_self_affine_spec(const InputNode& node) {
  if (!node.is_map())
    throw input_error(node.path(), node.is_sequence() ? "a list" : node.text(),
                      "a self-affine surface is a map: {hurst: 0.8, rms_height: 2 nm, cutoff_wavelength: 1 nm}");
  SelfAffineSpec s;
  s.hurst = node.quantity("hurst", units::dimensionless, 0.8);
  if (!(s.hurst > 0 && s.hurst < 1))
    throw input_error(key_path(node, "hurst"), format_value(s.hurst), "the Hurst exponent must be in (0, 1)");

  const bool height = node.has("rms_height"), slope = node.has("rms_slope");
  if (height && slope)
    throw input_error(key_path(node, "rms_height"), "given with rms_slope",
                      "give rms_height or rms_slope, not both (the other follows from the spectrum)");
  if (!height && !slope)
    throw input_error(key_path(node, "rms_height"), "missing", "give rms_height (a length) or rms_slope");
  if (height) {
    s.rms_height = node.quantity("rms_height", units::length);
    if (!(s.rms_height > 0) || !std::isfinite(s.rms_height))
      throw input_error(key_path(node, "rms_height"), length_text(s.rms_height), "must be a length > 0");
  } else {
    s.rms_slope = node.quantity("rms_slope", units::dimensionless);
    if (!(s.rms_slope > 0) || !std::isfinite(s.rms_slope))
      throw input_error(key_path(node, "rms_slope"), format_value(s.rms_slope), "must be > 0");
  }

  s.cutoff_wavelength = node.quantity("cutoff_wavelength", units::length);
  if (!(s.cutoff_wavelength > 0) || !std::isfinite(s.cutoff_wavelength))
    throw input_error(key_path(node, "cutoff_wavelength"), length_text(s.cutoff_wavelength), "must be a length > 0");
  s.rolloff_wavelength = node.quantity("rolloff_wavelength", units::length, 0.0);
  if (!(s.rolloff_wavelength >= 0) || !std::isfinite(s.rolloff_wavelength))
    throw input_error(key_path(node, "rolloff_wavelength"), length_text(s.rolloff_wavelength),
                      "must be a length > 0 (or 0: the box's length)");
  if (s.rolloff_wavelength > 0 && !(s.cutoff_wavelength < s.rolloff_wavelength))
    throw input_error(key_path(node, "cutoff_wavelength"), length_text(s.cutoff_wavelength),
                      "must be shorter than rolloff_wavelength = " + length_text(s.rolloff_wavelength) +
                          " (q_s > q_r)");
  s.largest_wavelength = node.quantity("largest_wavelength", units::length, 0.0);
  if (!(s.largest_wavelength >= 0) || !std::isfinite(s.largest_wavelength))
    throw input_error(key_path(node, "largest_wavelength"), length_text(s.largest_wavelength),
                      "must be a length > 0 (or 0: the box)");
  if (s.largest_wavelength > 0 && s.largest_wavelength < s.rolloff_wavelength)
    throw input_error(key_path(node, "largest_wavelength"), length_text(s.largest_wavelength),
                      "must be at least rolloff_wavelength = " + length_text(s.rolloff_wavelength));

  const long seed = node.integer("seed", 1);
  if (seed < 0) throw input_error(key_path(node, "seed"), std::to_string(seed), "must be >= 0");
  s.seed = static_cast<std::uint64_t>(seed);
  return s;
}

void document_self_affine(KeyReference& ref, const std::string& table) {
  ref.describe_section("",
                       "A self-affine random surface by Fourier filtering: power spectral density C(q) flat below "
                       "the roll-off wave number q_r, C ~ q^-2(1+H) (a profile: q^-(1+2H)) up to the cut-off q_s, "
                       "zero beyond; random phases from the seed; periodic over the box. Give `rms_height` or "
                       "`rms_slope`; the field is scaled to it exactly. The grid's spacing must be at most half "
                       "the cut-off wavelength.",
                       table);
  ref.key("hurst", table).is(KeyKind::quantity).fallback("0.8").allowed("(0, 1)")
      .means("the Hurst exponent H: heights scale as h(s x) ~ s^H h(x) between the cut-off and the roll-off");
  ref.key("rms_height", table).is(KeyKind::quantity).in(units::length).fallback_is("give this or rms_slope")
      .allowed("> 0").means("root mean square height of the surface (about its mean, which is zero)");
  ref.key("rms_slope", table).is(KeyKind::quantity).fallback_is("give this or rms_height").allowed("> 0")
      .means("root mean square gradient of the surface, from its spectrum (exact for the band-limited field)");
  ref.key("cutoff_wavelength", table).is(KeyKind::quantity).in(units::length)
      .allowed("> 0, < rolloff_wavelength, >= 2 grid spacings")
      .means("lambda_s = 2 pi / q_s: the shortest wavelength of the surface (no power above q_s)");
  ref.key("rolloff_wavelength", table).is(KeyKind::quantity).in(units::length)
      .fallback_is("0: the box's length along the first in-plane axis").allowed("> cutoff_wavelength")
      .means("lambda_r = 2 pi / q_r: longer wavelengths have the plateau's power, shorter ones fall as a power law");
  ref.key("largest_wavelength", table).is(KeyKind::quantity).in(units::length)
      .fallback_is("0: the box (every mode down to the box's length)").allowed(">= rolloff_wavelength")
      .means("lambda_l = 2 pi / q_l: no power at longer wavelengths");
  ref.key("seed", table).is(KeyKind::integer).fallback("1").allowed(">= 0")
      .means("seed of the random amplitudes and phases (mt19937_64): the same seed gives the same surface");
}

}  // namespace debris
