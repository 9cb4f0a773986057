#include "kernels/peridem/pd_contact_params.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/error.hpp"

namespace debris {

namespace {

void require(bool ok, const std::string& key, double value, const char* valid) {
  if (!ok) throw input_error(key, format_value(value), valid);
}

bool finite(double v) { return std::isfinite(v); }

void check_material(const PdMaterial& m, const std::string& key) {
  require(finite(m.bulk_modulus) && m.bulk_modulus > 0, key + ".bulk_modulus", m.bulk_modulus,
          "must be finite and > 0 (eqs 25, 36)");
  require(finite(m.horizon) && m.horizon > 0, key + ".horizon", m.horizon, "must be finite and > 0 (eq 36)");
}

void check_settings(const PdContactSettings& s, const std::string& key) {
  require(finite(s.contact_radius_factor) && s.contact_radius_factor > 0, key + ".contact_radius_factor",
          s.contact_radius_factor, "must be finite and > 0 (the paper uses 0.95)");
  require(finite(s.restitution) && s.restitution > 0 && s.restitution <= 1, key + ".restitution", s.restitution,
          "must be in (0, 1] (eq 23 takes its logarithm; 1 means no damping)");
  require(finite(s.damping_factor) && s.damping_factor > 0, key + ".damping_factor", s.damping_factor,
          "must be finite and > 0 (C of eq 23; the paper uses 100)");
  require(finite(s.friction) && s.friction >= 0, key + ".friction", s.friction, "must be finite and >= 0");
  require(finite(s.stiffness_factor) && s.stiffness_factor > 0, key + ".stiffness_factor", s.stiffness_factor,
          "must be finite and > 0");
  require(finite(s.damping_onset_factor) && s.damping_onset_factor >= 1 && s.damping_onset_factor < 2,
          key + ".damping_onset_factor", s.damping_onset_factor, "must be in [1, 2) (1: the paper's text; 1.01: its code)");
}

// Eq 36 for one material.
double own_stiffness(const PdMaterial& m) {
  const double e = m.horizon;
  return 18.0 * m.bulk_modulus / (std::numbers::pi * e * e * e * e * e);
}

// 2 a b / (a + b), written so that swapping a and b gives the same bits.
double harmonic_mean(double a, double b) { return 2.0 * (a * b) / (a + b); }

}  // namespace

PdContactParams pd_contact_params(const PdMaterial& a, const PdMaterial& b, const PdContactSettings& s, double h_min,
                                  const std::string& key) {
  check_material(a, key + ".material_a");
  check_material(b, key + ".material_b");
  check_settings(s, key);
  require(finite(h_min) && h_min > 0, key + ".h_min", h_min, "must be finite and > 0 (mesh size of eq 35)");

  PdContactParams p{};
  p.kappa_eff = harmonic_mean(a.bulk_modulus, b.bulk_modulus);
  p.k_n = s.stiffness_factor * harmonic_mean(own_stiffness(a), own_stiffness(b));
  p.r_c = s.contact_radius_factor * h_min;
  const double l = std::log(s.restitution);  // <= 0
  p.beta_coef = -2.0 * s.damping_factor * l / std::sqrt(std::numbers::pi * std::numbers::pi + l * l);
  p.mu = s.friction;
  p.damping_onset = s.damping_onset_factor * p.r_c;
  return p;
}

double PdContactTable::max_contact_radius() const {
  double r = 0.0;
  for (const PdContactParams& p : pairs) r = std::max({r, p.r_c, p.damping_onset});
  return r;
}

PdContactTable pd_contact_table(const std::vector<PdMaterial>& materials, const PdContactSettings& s, double h_min) {
  const std::size_t n = materials.size();
  return pd_contact_table(materials, std::vector<PdContactSettings>(n * n, s), h_min);
}

PdContactTable pd_contact_table(const std::vector<PdMaterial>& materials,
                                const std::vector<PdContactSettings>& settings, double h_min) {
  const int n = static_cast<int>(materials.size());
  if (settings.size() != static_cast<std::size_t>(n) * static_cast<std::size_t>(n))
    throw input_error("contact", std::to_string(settings.size()) + " pair settings",
                      "need one per ordered pair of materials, " + std::to_string(n * n));
  PdContactTable t;
  t.materials = n;
  t.pairs.resize(settings.size());
  for (int a = 0; a < n; ++a) {
    for (int b = a; b < n; ++b) {
      const std::string key = "contact." + std::to_string(a) + "_" + std::to_string(b);
      const PdContactSettings& s = settings[static_cast<std::size_t>(a * n + b)];
      const PdContactSettings& r = settings[static_cast<std::size_t>(b * n + a)];
      if (s.contact_radius_factor != r.contact_radius_factor || s.restitution != r.restitution ||
          s.damping_factor != r.damping_factor || s.friction != r.friction || s.stiffness_factor != r.stiffness_factor ||
          s.damping_onset_factor != r.damping_onset_factor)
        throw input_error("contact." + std::to_string(b) + "_" + std::to_string(a), "(differs)",
                          "must equal " + key + ": contact between two materials is one law");
      // Computed once and mirrored, so that both ends of a pair read the same bits.
      const PdContactParams p = pd_contact_params(materials[static_cast<std::size_t>(a)],
                                                  materials[static_cast<std::size_t>(b)], s, h_min, key);
      t.pairs[static_cast<std::size_t>(a * n + b)] = p;
      t.pairs[static_cast<std::size_t>(b * n + a)] = p;
    }
  }
  exec::to_device(t.pairs);  // read by the contact kernels (offload builds)
  return t;
}

}  // namespace debris
