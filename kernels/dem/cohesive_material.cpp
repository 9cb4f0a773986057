#include "kernels/dem/cohesive_material.hpp"

#include <limits>
#include <numbers>
#include <sstream>

#include "core/error.hpp"
#include "core/particles.hpp"

namespace debris {

namespace {
void require(bool ok, const char* prefix, const char* key, double value, const char* valid) {
  if (!ok) throw input_error(std::string(prefix) + "." + key, format_value(value), valid);
}
}  // namespace

void CohesiveMaterial::validate(const char* prefix) const {
  auto finite = [](double v) { return std::isfinite(v); };
  require(finite(youngs_modulus) && youngs_modulus > 0, prefix, "youngs_modulus", youngs_modulus, "must be > 0");
  require(finite(poisson_ratio) && poisson_ratio > -1.0 && poisson_ratio <= 0.25, prefix, "poisson_ratio",
          poisson_ratio,
          "must be in (-1, 0.25]: eq 16 gives a negative tangential stiffness above 1/4 (paper section 2.2)");
  require(finite(tensile_strength) && tensile_strength > 0, prefix, "tensile_strength", tensile_strength,
          "must be > 0");
  require(finite(shear_strength) && shear_strength >= 0, prefix, "shear_strength", shear_strength, "must be >= 0");
  require(finite(surface_energy) && surface_energy > 0, prefix, "surface_energy", surface_energy, "must be > 0");
  require(finite(restitution) && restitution > 0 && restitution <= 1, prefix, "restitution", restitution,
          "must be in (0, 1]");
  require(finite(density) && density > 0, prefix, "density", density, "must be > 0");
  require(finite(scaling) && scaling >= 0 && scaling <= 1, prefix, "scaling", scaling,
          "must be in [0, 1] (eq 10: 0 keeps the strength, 0.5 the surface energy)");
}

CohesiveMaterial table4_material(double scaling) {
  // E, nu, sigma_mN, sigma_mT, gamma, eta, rho, s
  return CohesiveMaterial{1.0, 0.15, 0.2, 0.1, 1.5, 0.95, 1.0, scaling};
}

CohesiveMaterial silica_material() { return CohesiveMaterial{73e9, 0.17, 16e9, 9e9, 1.5, 0.9, 2200.0, 0.5}; }

double CohesiveMaterial::critical_diameter() const {
  return 4.0 * surface_energy * youngs_modulus / (tensile_strength * tensile_strength);
}

double CohesiveMaterial::minimum_diameter() const { return 4.0 * surface_energy / tensile_strength; }

CohesiveCoefficients CohesiveCoefficients::from(const CohesiveMaterial& m) {
  m.validate();
  const double nu = m.poisson_ratio;
  CohesiveCoefficients c{};
  c.E = m.youngs_modulus;
  c.area_n = std::numbers::sqrt2 / (1.0 - 2.0 * nu);
  c.area_t = std::numbers::sqrt2 * (1.0 - 4.0 * nu) / ((1.0 - 2.0 * nu) * (1.0 + nu));
  c.strain_e = m.tensile_strength / m.youngs_modulus;
  c.delta_f_min = m.minimum_diameter();
  c.d_c = m.critical_diameter();
  c.s = m.scaling;
  c.sigma_t = m.shear_strength;
  c.damping = 2.0 * (1.0 - m.restitution) / std::numbers::pi;
  c.kt_over_kn = c.area_t / c.area_n;
  c.ct_over_cn = std::sqrt(c.kt_over_kn);
  return c;
}

double critical_time_step(double k_n, double m_eff) { return 2.0 * std::sqrt(m_eff / k_n); }

double critical_damping(double k_n, double m_eff) { return 2.0 * std::sqrt(k_n * m_eff); }

StabilityLimits stability_limits(const CohesiveCoefficients& c, const Particles& p) {
  StabilityLimits s{std::numeric_limits<double>::infinity(), 0.0, -1};
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double r = p.radius[i], m = p.mass[i];
    const CohesivePairParams pp = cohesive_pair_params(c, r, r, m, m);
    const double dt = critical_time_step(pp.k_n, 0.5 * m);  // = sqrt(2 m / k_N), eq 6
    if (dt < s.dt_c) s = {dt, critical_damping(pp.k_n, 0.5 * m), static_cast<long>(i)};
  }
  return s;
}

}  // namespace debris
