#pragma once
// The cohesive pair force of Pham-Ba & Molinari, eqs 2-5, as a pure function of one pair: the only place
// the law is written. The vectorised half-list pass, the full-list (device) pass and the virial stress all
// call cohesive_pair_force below.
//
//   F_i = -(F_N + c_N v_N) n - (F_T + c_T v_T) t                                   (eq 2)
//   F_N = k_N dN                      if dN <= delta_e                              (eq 3)
//       = k_s (delta_f - dN),  k_s = k_N delta_e / (delta_f - delta_e)   if delta_e < dN <= delta_f
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
//
// Branch-free (selects, no early return) so that the half-list pass's loop vectorises; eqs 7-17 are
// evaluated inline from the folded constants, except delta_f (eq 10, which may need a pow) and c_N (eq 12,
// a square root and the masses), which the caller brings: CohesivePairTable streams them per pair, the
// full-list pass computes them with cohesive_pair_params (the same function the table uses, so both passes
// see the same bits).
#include <cmath>

#include "core/exec.hpp"
#include "core/vec3.hpp"
#include "kernels/dem/cohesive_material.hpp"

namespace debris {

/// Switches used by relaxation phases (paper section 3.2): repulsion only, or no tangential force.
struct CohesiveOptions {
  int adhesive = 1;    // 0: normal force only where dN <= 0 (phase 1 of the amorphous relaxation)
  int tangential = 1;  // 0: no tangential spring or damping (phase 2)
};

/// One pair seen from particle i.
struct CohesivePair {
  Vec3 dx;          // minimum image of x_i - x_j
  double ri, rj;    // radii
  double delta_f;   // fracture separation, eq 10
  double c_n;       // normal damping, eq 12
  Vec3 v_rel;       // v_i - v_j
  Vec3 wi, wj;      // angular velocities
  Vec3 history;     // tangential displacement dT as seen from i, before this step
  int i_first;      // 1 if i is the pair's first particle (the lower index): the moment arms are computed
                    // from the first one's radius, so both ends of a full list get exactly opposite forces
                    // and the half list (row i < partner j) the same bits as the full list
};

/// What one pair does.
struct CohesivePairResult {
  Vec3 force;      // on i (j receives the opposite)
  Vec3 torque;     // on i, about its centre
  Vec3 torque_j;   // on j, about its centre
  Vec3 history;    // dT after this step: advanced, rescaled when it slid, zero out of range
  double delta_n;  // normal separation dN = |x_i - x_j| - r_i - r_j
  int interacting; // 1 if dN <= delta_f (dN <= 0 without adhesion)
  // What the energy accounting needs (kernels/dem/energy_accounting.hpp); unused results cost nothing, the
  // evaluator being inlined. The damping parts of eq 2, on i (j receives -damping_n, -damping_t):
  Vec3 damping_n;         // -c_N v_N n
  Vec3 damping_t;         // -c_T v_T
  Vec3 damping_torque;    // the tangential damping's torque on i
  Vec3 damping_torque_j;  // ... on j
  // Energies over this step at the velocities the force was evaluated with (joules or the input's units):
  double dissipated_normal;      // c_N v_N^2 dt: the normal dashpot's power
  double dissipated_tangential;  // c_T |v_T|^2 dt: the tangential dashpot's power
  double dissipated_sliding;     // what the tangential spring lost: F'_mT times the slip where eq 4 rescaled
                                 // it, plus its whole energy k_T |dT|^2 / 2 where the pair let go of it
  double tangential_work;        // -F_T . v_c dt: work the relative motion did against the tangential force
};

/// Per-particle sums of the pairs' energy parts (CohesivePairResult), for the energy accounting: the
/// damping forces and the tangential damping's torque on each particle, and each particle's sum of its pairs'
/// whole dissipations and tangential work (the accounting gives each end half).
enum PairEnergyColumn : int {
  kDampNx, kDampNy, kDampNz,            // normal damping force
  kDampTx, kDampTy, kDampTz,            // tangential damping force
  kDampTorqueX, kDampTorqueY, kDampTorqueZ,  // tangential damping's torque
  kPairDissNormal, kPairDissTangential, kPairDissSliding, kPairTangentialWork,
  kPairEnergyColumns
};
struct PairEnergyOut {
  double* rows = nullptr;  // particle i's parts at rows[kPairEnergyColumns * i + column]
};

DEBRIS_DECLARE_TARGET

/// Eqs 2-5 for one pair. The pair's tangential displacement is advanced by one step when update_history is
/// set (every step but the set-up force evaluation), rescaled when it slides, and zeroed when the pair is
/// out of range or has no tangential force. Values in, values out (the history travels in `pair` and comes
/// back in the result): nothing in the calling vector loop has its address taken.
DEBRIS_ALWAYS_INLINE CohesivePairResult cohesive_pair_force(const CohesiveCoefficients& c,
                                                            const CohesiveOptions& opt, CohesivePair pair,
                                                            double dt, int update_history) {
  const Vec3 dx = pair.dx;
  const double d = norm(dx);
  const double ri = pair.ri, rj = pair.rj, radsum = ri + rj;
  const double dn = d - radsum;
  // Eqs 7-9 and 11, 14-16 for this pair.
  const double r_eff = ri < rj ? ri : rj, r2 = r_eff * r_eff;
  const double delta_e = radsum * c.strain_e;
  const double delta_f = pair.delta_f;
  // The four reciprocals the pair needs from one division (the divider, not the arithmetic, limited the
  // vector loop): 1/a_m = (product of the others) / (product of all). Exact to a few ulp; the product
  // stays far inside double range for any physical units (lengths within 1e+-70).
  const double gap = delta_f > delta_e ? delta_f - delta_e : 1.0, df_safe = delta_f > 0.0 ? delta_f : 1.0;
  const double p_dr = d * radsum, p_drg = p_dr * gap;
  const double s_gf = gap * df_safe;
  const double inv_all = 1.0 / (p_drg * df_safe);
  const double inv_d = inv_all * (radsum * s_gf);
  const double inv_rs = inv_all * (d * s_gf);
  const double inv_gap = inv_all * (p_dr * df_safe);
  const double inv_df = inv_all * p_drg;
  const Vec3 n = inv_d * dx;
  const double k_n = c.E * c.area_n * r2 * inv_rs;                               // eqs 7, 15
  const double k_s = delta_f > delta_e ? k_n * delta_e * inv_gap : 0.0;          // softening slope, eq 3
  const double f_max_t = c.area_t * r2 * c.sigma_t;                              // eqs 11, 16
  const int on = dn <= (opt.adhesive ? delta_f : 0.0);

  // Eq 3 (positive in tension) and the normal part of eq 2.
  const double f_n = (opt.adhesive && dn > delta_e) ? k_s * (delta_f - dn) : k_n * dn;
  const Vec3 v_rel = pair.v_rel;
  const double v_n = dot(v_rel, n);
  const double f_normal = on ? -(f_n + pair.c_n * v_n) : 0.0;

  // Contact point velocity (arms a_i + a_j = d, the first particle's computed), tangential part.
  const double a_first = d * (pair.i_first ? ri : rj) * inv_rs;
  const double a_i = pair.i_first ? a_first : d - a_first, a_j = pair.i_first ? d - a_first : a_first;
  const Vec3 spin = lincomb(a_i, pair.wi, a_j, pair.wj);
  const Vec3 v_c = v_rel - cross(spin, n);
  const Vec3 v_t = v_c - dot(v_c, n) * n;

  // History: rotated into the tangent plane keeping its length, advanced (when updating), capped (eqs 4-5).
  const Vec3 h0 = pair.history;
  const double h2 = norm2(h0), hn = dot(h0, n);
  const Vec3 hp = h0 - hn * n;
  const double hp2 = norm2(hp);
  const double keep = hp2 > 0.0 ? std::sqrt(h2 / (hp2 > 0.0 ? hp2 : 1.0)) : 1.0;
  const Vec3 h = update_history ? lincomb(keep, hp, dt, v_t) : h0;
  const double k_t = c.kt_over_kn * k_n;                                          // eq 8
  const double share = (delta_f - dn) * inv_df;
  const double cap = (share < 1.0 ? share : 1.0) * f_max_t;                       // eq 5
  const double spring = k_t * norm(h);
  const double slide = spring > cap ? cap / (spring > 0.0 ? spring : 1.0) : 1.0;  // eq 4
  const double tangential = opt.tangential ? 1.0 : 0.0;
  const double live = on ? tangential : 0.0;
  const double k_ts = -live * k_t * slide, c_ts = -live * c.ct_over_cn * pair.c_n;  // eq 13: c_T/c_N
  const Vec3 f_t = lincomb(k_ts, h, c_ts, v_t);
  // Torques -a n x F_t on both particles (j sees -n and -F_t).
  const Vec3 arm = cross(n, f_t);
  // Slid back to the cap when updating; gone when out of range or without tangential force.
  const Vec3 history = (live * (update_history ? slide : 1.0)) * h;
  // The energy accounting's parts. The damping forces and their power at v (the pair's dissipation this
  // step: -(F_damp . v_c) dt, with the torques' share through v_c); a slip where eq 4 rescaled the spring
  // dissipates F'_mT times the length cut from dT, and a spring the pair lets go of (out of range, or
  // tangential force switched off) its whole energy.
  // Their own products, not the force's (c_N v_N, c_T v_T): GCC fuses a product into an add only where that
  // is its one use. The vector loop still contracts the force differently once these are kept, so a run with
  // the accounting and one without differ in the last bits (each the same on any thread or rank count).
  const double c_on = on ? pair.c_n : 0.0;
  const Vec3 damping_n = -c_on * (v_n * n);
  const Vec3 damping_t = (-live * c.ct_over_cn) * (pair.c_n * v_t);
  const Vec3 arm_d = cross(n, damping_t);
  const double h_len = norm(h);
  const double slip = update_history ? live * (1.0 - slide) * h_len : 0.0;
  const double kept = slide * spring;  // the spring's force after eq 4: F'_mT where it slid
  const double released = live > 0.0 ? 0.0 : 0.5 * k_t * h2;
  // Aggregate initialisation, not a default-constructed result filled in: clang's offload build left the
  // implicit constructor undefined in the host clones of the half-list pass.
  return CohesivePairResult{f_normal * n + f_t,
                            -a_i * arm,
                            -a_j * arm,
                            history,
                            dn,
                            on,
                            damping_n,
                            damping_t,
                            -a_i * arm_d,
                            -a_j * arm_d,
                            c_on * (v_n * v_n) * dt,
                            -dot(damping_t, v_t) * dt,
                            kept * slip + released,
                            -dot(f_t, v_c) * dt};
}

/// Potential of eq 3, zero for separated pairs: U(dN) = -integral of F_N from dN up to delta_f.
inline double cohesive_normal_energy(const CohesivePairParams& p, double delta_n) {
  if (delta_n > p.delta_f) return 0.0;
  const double peak = p.delta_e < p.delta_f ? p.delta_e : p.delta_f;  // where the Hookean branch ends
  if (delta_n <= peak) return 0.5 * p.k_n * (delta_n * delta_n - peak * p.delta_f);
  const double g = p.delta_f - delta_n;
  return -0.5 * p.k_n * p.delta_e / (p.delta_f - p.delta_e) * g * g;
}

/// Elastic energy stored in one pair (normal potential plus tangential spring, capped by eq 5), for
/// diagnostics.
inline double cohesive_pair_energy(const CohesivePairParams& p, const CohesiveOptions& opt, double delta_n,
                                   Vec3 history) {
  const double reach = opt.adhesive ? p.delta_f : 0.0;
  if (delta_n > reach) return 0.0;
  double u = opt.adhesive ? cohesive_normal_energy(p, delta_n) : 0.5 * p.k_n * delta_n * delta_n;
  if (opt.tangential) {
    const double share = (p.delta_f - delta_n) / p.delta_f;
    const double cap = (share < 1.0 ? share : 1.0) * p.f_max_t;
    const double h = norm(history);
    const double hh = p.k_t * h > cap ? cap / p.k_t : h;
    u += 0.5 * p.k_t * hh * hh;
  }
  return u;
}

DEBRIS_END_DECLARE_TARGET

}  // namespace debris
