#pragma once
// The cohesive pair force of Pham-Ba & Molinari, eqs 2-5, as a pure function of one pair.
//
//   F_i = -(F_N + c_N v_N) n - (F_T + c_T v_T) t                                   (eq 2)
//   F_N = k_N dN                      if dN <= delta_e                              (eq 3)
//       = -k_N delta_e (dN - delta_f) / (delta_f - delta_e)   if delta_e < dN <= delta_f
//       = 0                           if dN > delta_f (the whole force, damping included, vanishes;
//                                     also when delta_f < delta_e, as eq 10 gives for d > d_c, s > 0)
//   F_T = min(k_T |dT|, F'_mT)                                                      (eq 4)
//   F'_mT = min((delta_f - dN) / delta_f, 1) F_mT                                   (eq 5)
//
// n points from j to i, so a positive (tensile) F_N pulls i toward j. The tangential displacement dT is a
// vector history per pair: zero when the pair starts interacting, rotated into the current tangent plane
// (magnitude kept) and incremented by the relative tangential velocity at the contact point times dt;
// when the spring exceeds F'_mT it is rescaled to F'_mT (eq 4: the spring slides). Damping is added
// outside that cap, as eq 2 writes it. The law is reversible: a pair that comes back within delta_f
// interacts again, with a fresh history.
//
// The contact point splits the centre line in the ratio r_i : r_j (arms a_i + a_j = |x_i - x_j|), so the
// tangential force produces torques that conserve angular momentum exactly, also for pairs in tension.
#include "core/exec.hpp"
#include "core/vec3.hpp"
#include "kernels/dem/cohesive_material.hpp"

namespace debris {

/// Switches used by relaxation phases (paper section 3.2): repulsion only, or no tangential force.
struct CohesiveOptions {
  int adhesive = 1;    // 0: normal force only where dN <= 0 (phase 1 of the amorphous relaxation)
  int tangential = 1;  // 0: no tangential spring or damping (phase 2)
};

/// What one pair does to particle i.
struct CohesivePairResult {
  Vec3 force;      // on i (j receives the opposite)
  Vec3 torque;     // on i, about its centre
  double delta_n;  // normal separation dN = |x_i - x_j| - r_i - r_j
  int interacting; // 1 if dN <= delta_f
};

DEBRIS_DECLARE_TARGET

/// Normal force law of eq 3 (positive in tension). For d > d_c and s > 0, eq 10 gives delta_f < delta_e:
/// the force is Hookean up to delta_f and drops to zero there (Fig A.2), so the matched strength is the
/// sigma (d/d_c)^-s of eq 20 and the surface energy stays gamma.
inline double cohesive_normal_force(const CohesivePairParams& p, double delta_n) {
  if (delta_n > p.delta_f) return 0.0;
  if (delta_n <= p.delta_e) return p.k_n * delta_n;
  return -p.k_n * p.delta_e / (p.delta_f - p.delta_e) * (delta_n - p.delta_f);
}

/// Potential of eq 3, zero for separated pairs: U(dN) = -integral of F_N from dN up to delta_f.
inline double cohesive_normal_energy(const CohesivePairParams& p, double delta_n) {
  if (delta_n > p.delta_f) return 0.0;
  const double peak = p.delta_e < p.delta_f ? p.delta_e : p.delta_f;  // where the Hookean branch ends
  if (delta_n <= peak) return 0.5 * p.k_n * (delta_n * delta_n - peak * p.delta_f);
  const double g = p.delta_f - delta_n;
  return -0.5 * p.k_n * p.delta_e / (p.delta_f - p.delta_e) * g * g;
}

/// Rescaled maximum tangential force of eq 5.
inline double cohesive_max_tangential_force(const CohesivePairParams& p, double delta_n) {
  const double f = (p.delta_f - delta_n) / p.delta_f;
  return (f < 1.0 ? f : 1.0) * p.f_max_t;
}

/// Eqs 2-5 for the pair (i, j). dx = minimum image of x_i - x_j. `history` is this pair's tangential
/// displacement as seen from i; it is advanced by one step when update_history is set (every step but
/// the set-up force evaluation), and reset when the pair is out of range.
inline CohesivePairResult cohesive_pair_force(const CohesivePairParams& p, const CohesiveOptions& opt, Vec3 dx,
                                              double ri, double rj, Vec3 vi, Vec3 vj, Vec3 wi, Vec3 wj,
                                              Vec3& history, double dt, int update_history) {
  CohesivePairResult out{};
  const double d = norm(dx);
  out.delta_n = d - ri - rj;
  const double reach = opt.adhesive ? p.delta_f : 0.0;
  if (out.delta_n > reach) {
    history = Vec3{};
    return out;
  }
  out.interacting = 1;
  const Vec3 n = (1.0 / d) * dx;

  // Normal part of eq 2.
  const Vec3 v_rel = vi - vj;
  const double v_n = dot(v_rel, n);
  const double f_n = cohesive_normal_force(p, out.delta_n);
  out.force = -(f_n + p.c_n * v_n) * n;
  if (!opt.tangential) {
    history = Vec3{};
    return out;
  }

  // Relative velocity of the two material points at the contact point, tangential part.
  const double a_i = d * ri / (ri + rj), a_j = d * rj / (ri + rj);
  const Vec3 v_c = v_rel - cross(a_i * wi + a_j * wj, n);
  const Vec3 v_t = v_c - dot(v_c, n) * n;

  // Tangential history: rotate into the current tangent plane keeping its length, then add this step.
  Vec3 h = history;
  const double cap = cohesive_max_tangential_force(p, out.delta_n);
  if (update_history) {
    const double h2 = norm2(h);
    if (h2 > 0.0) {
      h = h - dot(h, n) * n;
      const double hp2 = norm2(h);
      if (hp2 > 0.0) h = std::sqrt(h2 / hp2) * h;
    }
    h += dt * v_t;
    const double spring = p.k_t * norm(h);
    if (spring > cap) h = (cap / spring) * h;  // eq 4: the spring slides at F'_mT
    history = h;
  }
  // Eq 4 as a min, so that the set-up evaluation (no update) obeys the cap too.
  const double spring = p.k_t * norm(h);
  const double scale = spring > cap ? cap / spring : 1.0;
  const Vec3 f_t = -(scale * p.k_t) * h - p.c_t * v_t;
  out.force += f_t;
  out.torque = -a_i * cross(n, f_t);
  return out;
}

/// Elastic energy stored in one pair (normal potential plus tangential spring), for diagnostics.
inline double cohesive_pair_energy(const CohesivePairParams& p, const CohesiveOptions& opt, double delta_n,
                                   Vec3 history) {
  const double reach = opt.adhesive ? p.delta_f : 0.0;
  if (delta_n > reach) return 0.0;
  double u = opt.adhesive ? cohesive_normal_energy(p, delta_n) : 0.5 * p.k_n * delta_n * delta_n;
  if (opt.tangential) {
    const double cap = cohesive_max_tangential_force(p, delta_n);
    const double h = norm(history);
    const double hh = p.k_t * h > cap ? cap / p.k_t : h;
    u += 0.5 * p.k_t * hh * hh;
  }
  return u;
}

DEBRIS_END_DECLARE_TARGET

}  // namespace debris
