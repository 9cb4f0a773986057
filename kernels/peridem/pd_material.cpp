#include "kernels/peridem/pd_material.hpp"

#include <cmath>
#include <string>

#include "core/error.hpp"

namespace debris {

namespace {
void require(bool ok, const char* prefix, const char* key, const std::string& value, const char* valid) {
  if (!ok) throw input_error(std::string(prefix) + "." + key, value, valid);
}
bool positive(double v) { return std::isfinite(v) && v > 0; }
}  // namespace

void PdMaterial::validate(const char* prefix) const {
  require(positive(density), prefix, "density", format_value(density), "must be finite and > 0");
  require(positive(bulk_modulus), prefix, "bulk_modulus", format_value(bulk_modulus), "must be finite and > 0");
  require(positive(shear_modulus), prefix, "shear_modulus", format_value(shear_modulus), "must be finite and > 0");
  require(!std::isnan(fracture_energy) && fracture_energy > 0, prefix, "fracture_energy", format_value(fracture_energy),
          "must be > 0 (infinity: bonds never break)");
  require(positive(horizon), prefix, "horizon", format_value(horizon), "must be finite and > 0");
  require(dimension == 2 || dimension == 3, prefix, "dimension", std::to_string(dimension),
          "must be 2 (plane strain) or 3");
}

PdMaterial peridem_material_m1(int dimension) {
  // rho, K, G, G_c, epsilon, d
  return PdMaterial{1200.0, 0.0216e9, 0.01296e9, 50.0, 0.6e-3, dimension};
}

double pd_critical_stretch(const PdMaterial& m) {
  const double K = m.bulk_modulus, G = m.shear_modulus;
  const double q = 0.75 * 0.75 * 0.75 * 0.75;                                               // (3/4)^4
  return std::sqrt(m.fracture_energy / ((3.0 * G + q * (K - 5.0 * G / 3.0)) * m.horizon));  // eq 10
}

PdLpsConstants PdLpsConstants::from(const PdMaterial& m, const char* prefix) {
  m.validate(prefix);
  PdLpsConstants c;
  c.horizon = m.horizon;
  c.dimension = m.dimension;
  if (m.dimension == 3) {
    c.bulk = m.bulk_modulus;           // eq 9: 3 K theta x / m
    c.shear = 15.0 * m.shear_modulus;  // eq 9: 15 G e_d / m
  } else {
    c.bulk = m.bulk_modulus + m.shear_modulus / 3.0;  // plane strain: lambda + mu
    c.shear = 8.0 * m.shear_modulus;                  // plane strain (header: Le, Chan & Schwartz 2014)
  }
  c.critical_stretch = pd_critical_stretch(m);
  c.break_in_compression = m.break_in_compression ? 1.0 : 0.0;
  c.dilatation_factor = c.dimension * c.bulk - c.shear / c.dimension;
  return c;
}

}  // namespace debris
