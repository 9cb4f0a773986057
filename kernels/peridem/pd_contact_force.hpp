#pragma once
// PeriDEM contact between two nodes (paper B, sections 2.2-2.3), as pure functions of one node pair.
//
//   delta = |z' - z| - R_c                                                          (eq 16)
//   F_n   = K_n delta V' e_n  if delta < 0, else 0;  e_n = (z' - z) / |z' - z|      (eqs 17-18)
//   F_t   = mu |F_n| e_t,  e_t along the tangential part of v' - v                 (eqs 19-20, sign corrected)
//   F_d   = (1/V) beta_n delta_dot e_n  if delta_dot < 0 and delta < 0              (eqs 21-22)
//   beta_n from eq 23 with m_eq = 2 rho V rho' V' / (rho V + rho' V')               (eqs 23-24)
//
// Units. Eqs 17, 22 and 27 are force densities on node x (per unit volume of x: eq 32 adds them to
// rho u'', and PeriDEM integrates v += dt F / rho). Debris stores forces in newtons (PdNodes), so the node
// force is the density times V:  K_n delta V V' e_n,  beta_n delta_dot e_n,  and V/|Omega_p| beta-bar
// delta_dot_c e for the centre damping (eq 30). The first two are symmetric in the two nodes, so the two
// ends of a pair receive exactly opposite forces (Newton's third law, which the densities hide).
//
// Friction sign. Eq 20 writes F_t = -mu |F_n| e_t with e_t along v' - v, and PeriDEM's demModel.cpp codes the same
// (force_i += mu * f_n * e_t with f_n < 0): that force points along v - v', the way node x already slides
// relative to x', and accelerates the sliding. Coulomb friction opposes it: F_t = +mu |F_n| e_t here.
//
// Stick. Coulomb's law is undefined at zero sliding speed; applied as is, an explicit step overshoots and
// the sliding velocity chatters around zero. The friction of a pair is therefore also capped by the force
// that stops its relative tangential velocity within one step, m_stick |v_t| / dt, where m_stick is the
// reduced mass of m_i / n_i and m_j / n_j (n: the node's list entries, so that all the pairs of a node
// together never stop more than its own momentum; a wall node is rigid, infinitely heavy). While sliding
// faster than mu |F_n| dt / m_stick, the force is exactly eq 20's.
#include <cmath>

#include "core/exec.hpp"
#include "core/vec3.hpp"
#include "kernels/peridem/pd_contact_params.hpp"

namespace debris {

/// What node j does to node i.
struct PdContactPairResult {
  Vec3 force;      // on i, newtons (j receives the opposite)
  double delta;    // eq 16: |z_j - z_i| - R_c (negative in contact); 0 when out of range
  int in_contact;  // |z_j - z_i| < R_c
};

DEBRIS_DECLARE_TARGET

/// Eqs 24 and 29: twice the reduced mass. Swapping the arguments gives the same bits.
inline double pd_equivalent_mass(double a, double b) { return 2.0 * (a * b) / (a + b); }

/// Eq 24 or 29 when either side may be a rigid wall (rigid = 1): a wall is, for damping, a body of infinite
/// mass, so m_eq tends to twice the other side's mass, 2 m (and a collision with it damps exactly like one
/// with a grain of very large mass). Both rigid: 0, no dashpot (walls never touch walls). Symmetric in (i, j).
inline double pd_damping_mass(double mass_i, int rigid_i, double mass_j, int rigid_j) {
  if (rigid_i) return rigid_j ? 0.0 : 2.0 * mass_j;
  if (rigid_j) return 2.0 * mass_i;
  return pd_equivalent_mass(mass_i, mass_j);
}

/// Eqs 23 and 28: dashpot viscosity for the equivalent mass m_eq (0 when e_n = 1).
inline double pd_damping_coefficient(const PdContactParams& p, double m_eq) {
  return p.beta_coef * std::sqrt((p.kappa_eff * p.r_c) * m_eq);
}

/// Mass whose relative tangential motion friction may stop in one step (see the header comment):
/// share = m / n of each node, rigid = 1 for a wall node. Symmetric in (i, j).
inline double pd_stick_mass(double share_i, int rigid_i, double share_j, int rigid_j) {
  if (rigid_i) return rigid_j ? 0.0 : share_j;
  if (rigid_j) return share_i;
  return (share_i * share_j) / (share_i + share_j);
}

/// Eqs 16-18 as the signed scalar s of the force s e_n on i (s <= 0: repulsive), in newtons.
inline double pd_normal_force(const PdContactParams& p, double delta, double vol_i, double vol_j) {
  return delta < 0.0 ? (p.k_n * delta) * (vol_i * vol_j) : 0.0;
}

/// Elastic energy of the contact spring, 1/2 K_n delta^2 V V' (the potential of eq 17 times V).
inline double pd_contact_energy(const PdContactParams& p, double distance, double vol_i, double vol_j) {
  const double delta = distance - p.r_c;
  return delta < 0.0 ? 0.5 * (p.k_n * delta * delta) * (vol_i * vol_j) : 0.0;
}

/// Eqs 16-24 for node i and node j. dz = z_j - z_i, dv = v_j - v_i. same_grain: self-contact of one grain
/// across a broken bond (paper section 3.2), the normal force only. node_damping: add the dashpot of eq 22
/// (the damping between nodes of section 2.3.1) with m_eq = damping_mass (pd_damping_mass, eq 24);
/// otherwise damping is applied between grain centres.
inline PdContactPairResult pd_contact_pair_force(const PdContactParams& p, Vec3 dz, Vec3 dv, double vol_i, double vol_j,
                                                 double damping_mass, double stick_mass, double dt, int same_grain,
                                                 int node_damping) {
  PdContactPairResult out{};
  const double d2 = norm2(dz);
  if (!(d2 < p.r_c * p.r_c)) return out;  // exactly zero beyond R_c
  out.in_contact = 1;
  const double d = std::sqrt(d2);
  out.delta = d - p.r_c;
  if (d == 0.0) return out;  // coincident nodes: no direction
  const Vec3 e = (1.0 / d) * dz;

  const double f_n = pd_normal_force(p, out.delta, vol_i, vol_j);
  out.force = f_n * e;
  if (same_grain) return out;

  const double rate = dot(dv, e);  // delta_dot of eq 21
  if (p.mu > 0.0) {
    const Vec3 w = dv - rate * e;  // tangential part of v_j - v_i, eq 19
    const double w_len = norm(w);
    if (w_len > 0.0) {
      const double slide = p.mu * (-f_n);            // |F_n| mu, eq 20
      const double stick = stick_mass * w_len / dt;  // stops the relative sliding in one step
      out.force += ((slide < stick ? slide : stick) / w_len) * w;
    }
  }
  if (node_damping && rate < 0.0) {
    const double beta = pd_damping_coefficient(p, damping_mass);
    out.force += (beta * rate) * e;  // eq 22 times V
  }
  return out;
}

/// Eqs 26-29: the total damping force on grain p from partner q, before it is spread over p's nodes (eq 30).
/// dzc = z_c' - z_c, dvc = v_c' - v_c between the two centres; m_eq from eq 29 (pd_damping_mass: 2 m_p
/// against a wall). The caller checks that the two are in contact (some node pair closer than R_c).
inline Vec3 pd_centre_damping_force(const PdContactParams& p, Vec3 dzc, Vec3 dvc, double m_eq) {
  const double d2 = norm2(dzc);
  if (!(d2 > 0.0)) return Vec3{};
  const Vec3 e = (1.0 / std::sqrt(d2)) * dzc;
  const double rate = dot(dvc, e);  // eq 26
  if (!(rate < 0.0)) return Vec3{};
  const double beta = pd_damping_coefficient(p, m_eq);  // eq 28
  return (beta * rate) * e;                            // eq 27 times |Omega_p|
}

DEBRIS_END_DECLARE_TARGET

}  // namespace debris
