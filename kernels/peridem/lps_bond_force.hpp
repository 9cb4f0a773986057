#pragma once
// The linear peridynamic solid of paper B (PeriDEM), section 2.1.1 and its discretisation of section 3.1,
// as pure functions of one bond: usable inside kernels (no allocation, no exception). Notation of the paper:
// x = |x_j - x_i| the reference length (r in the paper), y = z(x_j) - z(x_i) the current bond vector,
// e = |y| - x the extension, J the influence function, V_j the partner's volume. The constants (d, k, a G)
// come from kernels/peridem/pd_material.hpp (3D: eqs 7-9; 2D: plane strain, see there).
//
//   J(a)      = 1 - a for a in [0, 1], 0 beyond                                          (eq 7)
//   m_i       = sum_j J(x / eps) x^2 V_j                                                  (eq 34)
//   theta_i   = (d / m_i) sum_j h J(x / eps) x e V_j                                      (eqs 13, 34)
//   t_i<xi>   = h J(x / eps) [ d k theta_i x / m_i + a G (e - theta_i x / d) / m_i ]     (eqs 7, 12)
//   F_i       = sum_j (t_i<xi> + t_j<-xi>) y / |y| V_j    (force density, eq 33 with T_j<-xi> = -t_j y/|y|)
//   h(s)      = 1 if s < s_0, else 0 (for ever),  s = e / x                               (eqs 10-11)
//
// Everything a bond contributes depends on the bond's two ends through |y|, which is bitwise the same when
// computed from either end (y_i - y_j is the exact negation of y_j - y_i), so both ends of a bond always
// see the same extension and stretch, and take the same breaking decision.
#include "core/exec.hpp"
#include "core/vec3.hpp"
#include "kernels/peridem/pd_material.hpp"

namespace debris {

DEBRIS_DECLARE_TARGET

/// Influence function J of eq 7 at a = x / epsilon >= 0. (PeriDEM's code scales it by 12 in 2D, 20 in 3D;
/// every LPS quantity is homogeneous of degree 0 in J, through J / m, so the scale cancels.)
inline double lps_influence(double a) { return a < 1.0 ? 1.0 - a : 0.0; }

/// Bond stretch s = (|y| - x) / x (eqs 10-11).
inline double lps_stretch(double length, double length0) { return (length - length0) / length0; }

/// Eq 11: a bond whose stretch reaches s_0 has h = 0 from then on (tension only: h(s) = 1 for every s < s_0;
/// the PeriDEM code breaks bonds compressed past s_0 too, |s| > s_0 + 1e-10, which eq 11 does not say).
inline int lps_bond_breaks(double stretch, double critical_stretch) { return stretch >= critical_stretch ? 1 : 0; }

/// Eq 11, or with in_compression = 1 the PeriDEM code's rule: a bond compressed past s_0 breaks too.
inline int lps_bond_breaks(double stretch, double critical_stretch, int in_compression) {
  return lps_bond_breaks(in_compression ? std::fabs(stretch) : stretch, critical_stretch);
}

/// One bond's term of the weighted volume m_i of eq 34: J x^2 V_j.
inline double lps_weighted_volume_term(double J, double length0, double volume_j) {
  return J * length0 * length0 * volume_j;
}

/// A bond's weight in theta and in the force (eqs 13 and 33, h aside): J(x / eps) V_j, fixed in the reference
/// configuration (pd_weighted_volume_pass keeps it per bond entry in BondList::weight, so the sweeps neither
/// fetch V_j nor evaluate J).
inline double lps_bond_weight(double J, double volume_j) { return J * volume_j; }

/// One intact bond's term of the sum in theta_i (eq 34): J x e V_j, from the bond's weight J V_j.
inline double lps_dilatation_term(double weight, double length0, double extension) {
  return weight * length0 * extension;
}

/// theta_i = (d / m_i) sum (eq 34); a node without bonds (m_i = 0) has no dilatation.
inline double lps_dilatation(const PdLpsConstants& c, double sum, double weighted_volume) {
  return weighted_volume > 0.0 ? c.dimension * sum / weighted_volume : 0.0;
}

/// Scalar force state t_i<xi> of eq 7 (eq 12 with h = 1): the isotropic part d k theta x / m plus the
/// deviatoric part a G e_d / m, e_d = e - theta x / d (eq 8).
inline double lps_force_state(const PdLpsConstants& c, double J, double length0, double extension, double theta,
                              double weighted_volume) {
  const double e_d = extension - theta * length0 / c.dimension;
  return J * (c.dimension * c.bulk * theta * length0 + c.shear * e_d) / weighted_volume;
}

/// Force density that one intact bond adds to node i, eq 33: (T_i<xi> - T_j<-xi>) V_j with the current
/// bond vector y = y_j - y_i. Positive t (tension) pulls i towards j. A bond crushed to zero length has no
/// direction and gives no force (contact keeps nodes apart long before).
inline Vec3 lps_bond_force(const PdLpsConstants& c, Vec3 y, double length0, double volume_j, double theta_i,
                           double weighted_volume_i, double theta_j, double weighted_volume_j) {
  const double length = norm(y);
  if (!(length > 0.0)) return Vec3{};
  const double e = length - length0;
  const double J = lps_influence(length0 / c.horizon);
  const double t_i = lps_force_state(c, J, length0, e, theta_i, weighted_volume_i);
  const double t_j = lps_force_state(c, J, length0, e, theta_j, weighted_volume_j);
  return ((t_i + t_j) * volume_j / length) * y;
}

/// The force state of eq 7 split into per-node factors, for the bond-force pass:
///   t_i<xi> = J (P_i x + Q_i e),   P_i = (d k - a G / d) theta_i / m_i,   Q_i = a G / m_i
/// (eq 7 expanded: d k theta x / m + a G (e - theta x / d) / m), so the pass divides once per node, not per
/// bond. A node without bonds (m_i = 0) gets P = Q = 0.
struct LpsNodeFactors {
  double p = 0.0, q = 0.0;
};
inline LpsNodeFactors lps_node_factors(const PdLpsConstants& c, double theta, double weighted_volume) {
  if (!(weighted_volume > 0.0)) return LpsNodeFactors{};
  const double inv_m = 1.0 / weighted_volume;
  return LpsNodeFactors{c.dilatation_factor * theta * inv_m, c.shear * inv_m};
}

/// Eq 33's bond term from the node factors: the scalar s with (T_i<xi> - T_j<-xi>) V_j = s y, that is
/// (t_i + t_j) V_j / |y| = J V_j ((P_i + P_j) x + (Q_i + Q_j) e) / |y|, from the bond's weight J V_j
/// (lps_bond_weight). inv_length = 1 / |y| (0 for a bond crushed to zero length: no direction, no force). The
/// same force as lps_bond_force up to round-off.
inline double lps_bond_force_scale(double weight, double length0, double extension, double p_sum, double q_sum,
                                   double inv_length) {
  return weight * (p_sum * length0 + q_sum * extension) * inv_length;
}

/// Isotropic part of the LPS energy density at a node: k theta^2 / 2.
inline double lps_dilatation_energy(const PdLpsConstants& c, double theta) { return 0.5 * c.bulk * theta * theta; }

/// One intact bond's share of the deviatoric energy density at node i: (a G / 2 m_i) J e_d^2 V_j. With the
/// dilatation energy (and the broken-bond term below) this is the W_i whose derivative in e is t_i<xi> V_j
/// (header of pd_material.hpp).
inline double lps_deviatoric_energy_term(const PdLpsConstants& c, double J, double length0, double extension,
                                         double theta, double weighted_volume, double volume_j) {
  const double e_d = extension - theta * length0 / c.dimension;
  return 0.5 * c.shear * J * e_d * e_d * volume_j / weighted_volume;
}

/// Broken bonds drop out of theta (h = 0, eq 13) but not out of m_i (eq 34: m is fixed in the reference
/// state), so sum_intact J x e_d V_j = theta (m_i - m_i^h) / d is no longer 0 and the force of eq 12 is the
/// gradient of W_i only with this extra term, (a G / 2 m_i) (theta / d)^2 (m_i - m_i^h), m_i^h = the sum of
/// J x^2 V_j over the intact bonds (the term is 0 while no bond of i is broken).
inline double lps_broken_bond_energy(const PdLpsConstants& c, double theta, double weighted_volume,
                                     double intact_weighted_volume) {
  const double q = theta / c.dimension;
  return 0.5 * c.shear * q * q * (weighted_volume - intact_weighted_volume) / weighted_volume;
}

DEBRIS_END_DECLARE_TARGET

}  // namespace debris
