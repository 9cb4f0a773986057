#pragma once
// PeriDEM contact constants for a pair of materials (paper B, sections 2.2-2.3 and 3.2), computed once on
// the host from the user's PdMaterial and contact settings (the decks' `Contact: Zone_ab` blocks):
//
//   kappa_eff = 2 kappa_1 kappa_2 / (kappa_1 + kappa_2)                                      (eq 25)
//   K_n       = 18 kappa / (pi eps^5)                                                         (eq 36)
//   R_c       = factor h_min      (factor 0.95 in every run of the paper, h_min of eq 35)
//   beta      = -2 C log(e_n) sqrt(kappa_eff R_c m_eq / (pi^2 + log(e_n)^2))                (eqs 23, 28)
//
// For two materials K_n is the harmonic mean of the two materials' own eq 36 values: with one horizon this
// is eq 36 with kappa_eff, as the paper prescribes; with two horizons (the paper never has them) it is the
// same series-spring rule applied to the whole constant. The decks' Kn_Factor multiplies K_n.
//
// Units: eq 36 is the paper's constant in 2D and in 3D alike (its 2D decks use it with nodal areas), so in
// 2D K_n delta V_i V_j is not dimensionally a force per unit thickness; we keep the paper's numbers.
#include <string>
#include <vector>

#include "core/exec.hpp"
#include "kernels/peridem/pd_material.hpp"

namespace debris {

/// What a user gives per pair of materials (the decks' names in brackets).
struct PdContactSettings {
  double contact_radius_factor = 0.95;  // R_c = factor * h_min (Contact_Radius_Factor), > 0
  double restitution = 1.0;             // e_n of eq 23 (Epsilon), in (0, 1]; 1 gives beta = 0: no damping
  double damping_factor = 100.0;        // C of eq 23, C-bar of eq 28 (Beta_n_Factor), > 0
  double friction = 0.0;                // mu of eq 20 (Friction_Coeff; 0 when Friction_On is false), >= 0
  double stiffness_factor = 1.0;        // multiplies K_n of eq 36 (Kn_Factor), > 0
  // The centre damping (eqs 26-30) acts while dist(Omega_p, Omega_p') < factor R_c: 1 is the paper's text;
  // the authors' code, which made Tables 2-3, switches it on at 1.01 R_c (between bounding circles), and
  // because it acts only while the grains approach, that 1% band matters (README, PeriDEM section).
  double damping_onset_factor = 1.0;    // in [1, 2)
};

/// Everything the contact kernels need for one pair of materials.
struct PdContactParams {
  double k_n;        // eq 36 (times the stiffness factor)
  double r_c;        // contact radius R_c
  double kappa_eff;  // eq 25
  double beta_coef;  // -2 C log(e_n) / sqrt(pi^2 + log(e_n)^2): beta = beta_coef sqrt(kappa_eff R_c m_eq)
  double mu;         // friction coefficient
  double damping_onset;  // damping_onset_factor * R_c: grain pairs closer than this are damped (eq 27)
};

/// Eqs 25, 36, 23 for materials a and b. h_min: the mesh size of eq 35 (smallest distance between two
/// nodes of the whole system). Throws InputError naming `key.<setting>` (or `key.h_min`, or
/// `key.material_a.bulk_modulus` ...) with the value, for a value outside its range.
PdContactParams pd_contact_params(const PdMaterial& a, const PdMaterial& b, const PdContactSettings& s, double h_min,
                                  const std::string& key = "contact");

/// Contact constants for every pair of materials, symmetric: pair(a, b) and pair(b, a) are the same bits.
/// The pairs are device-resident in offload builds: pd_contact_table sends them (a copy of a table must be
/// sent again, exec::to_device(copy.pairs)).
struct PdContactTable {
  int materials = 0;
  exec::DeviceVector<PdContactParams> pairs;  // pairs[a * materials + b]

  const PdContactParams& pair(int a, int b) const { return pairs[static_cast<std::size_t>(a * materials + b)]; }
  /// Largest R_c (or damping onset, when larger) over all pairs: the cutoff of the contact list.
  double max_contact_radius() const;
};

/// One set of settings for every pair of materials.
PdContactTable pd_contact_table(const std::vector<PdMaterial>& materials, const PdContactSettings& s, double h_min);
/// Settings per pair: settings[a * n + b], n = materials.size(); must be symmetric (keys `contact.a_b.*`).
PdContactTable pd_contact_table(const std::vector<PdMaterial>& materials,
                                const std::vector<PdContactSettings>& settings, double h_min);

}  // namespace debris
