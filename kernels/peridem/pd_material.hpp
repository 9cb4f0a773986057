#pragma once
// PeriDEM material (paper B, Table 1 and section 2.1.1): what a user gives per material. The derived
// constants of the state-based model (eqs 7-10, plane strain in 2D) are computed from these by functions
// in kernels/peridem/pd_material.cpp.
#include "core/exec.hpp"

namespace debris {

struct PdMaterial {
  double density = 0;           // rho (kg/m^3)
  double bulk_modulus = 0;      // K (Pa)
  double shear_modulus = 0;     // G (Pa)
  double fracture_energy = 0;   // G_c (J/m^2)
  double horizon = 0;           // epsilon (m)
  int dimension = 2;            // 2 (plane strain) or 3
  int break_in_compression = 0;  // 1: a bond also breaks when compressed past s_0, |s| >= s_0 (PeriDEM's code)

  /// Throws InputError naming `prefix.key` and the value for the first property out of its range: density,
  /// moduli and horizon finite and > 0, fracture energy > 0 (+infinity allowed: bonds that never break),
  /// dimension 2 or 3.
  void validate(const char* prefix = "material") const;
};

/// Material M1 of the paper's Table 1 with the horizon of section 4.1 (epsilon = 0.6 mm).
PdMaterial peridem_material_m1(int dimension = 2);

/// The constants of the linear peridynamic solid (LPS, paper eqs 7-9) in the form the bond kernels use,
/// for d = 3 and for plane strain in d = 2. With the influence function J of eq 7 and x = |xi|,
///   m_i      = sum_j J x^2 V_j                                         (eq 34)
///   theta_i  = (d / m_i) sum_j h J x e V_j,   e = |y_j - y_i| - x        (eq 34 for d = 3)
///   t_i<xi>  = h J [ d k theta_i x / m_i + a G (e - theta_i x / d) / m_i ]   (eq 12 for d = 3)
///   W_i      = k theta_i^2 / 2 + (a G / 2 m_i) [ sum_j h J (e - theta_i x / d)^2 V_j
///                                                + (theta_i / d)^2 (m_i - sum_j h J x^2 V_j) ]
/// with (d, k, a) = (3, K, 15) in 3D: the paper's eq 9 is t = J [x theta (3K/m - 15G/(3m)) + e 15G/m].
/// Plane strain (2D) uses (2, K + G/3, 8): k = lambda + mu is the in-plane bulk modulus of plane strain and
/// a = 8 makes W_i equal to the plane-strain elastic energy lambda/2 tr^2(eps) + mu eps:eps for a homogeneous
/// strain (the angular mean of (n.A n)^2 is A:A/4 for a traceless 2x2 A, 2 A:A/15 for 3x3). This is the
/// plane-strain model of Le, Chan & Schwartz (2014, IJNME 98, "A two-dimensional ordinary, state-based
/// peridynamic model for linearly elastic solids"), as NLMech's ElasticState implements it (plane strain:
/// theta = 2/m sum, alpha_s = 9 (K + G/9) / m, alpha_d = 8 G / m, which expands to the same t). The
/// PeriDEM code (PdState, the paper's runs) uses the 3D constants (3, K, 15) in 2D too: by the same algebra
/// its 2D grains respond with an in-plane bulk modulus 9K/4 (not K + G/3) and a shear modulus 15G/8 (not G),
/// about 1.9 times stiffer for M1. With (2, K + G/3, 8) a 2D grain has the paper's K and G in plane strain;
/// setting dimension = 3, bulk = K, shear = 15 G on a 2D grain reproduces the PeriDEM code instead.
/// W_i is the energy whose gradient is t, dW_i/de_j = t_i<xi_j> V_j, so the discrete force of eq 33 is exactly
/// -grad (sum_i V_i W_i) for fixed bond states. With every bond intact, sum_j J x e_d V_j = 0 by the definition
/// of theta and the second line of W_i is 0 (the textbook LPS energy); once bonds of i are broken, m_i (fixed
/// in the reference state, eq 34) exceeds the intact bonds' sum and that line is what makes eq 12's force
/// the gradient of W_i.
struct PdLpsConstants {
  double horizon = 0;           // epsilon: J(x / epsilon)
  double dimension = 3;         // d: theta = (d / m) sum ..., isotropic extension theta x / d
  double bulk = 0;              // k: K (3D), K + G/3 (plane strain)
  double shear = 0;             // a G: 15 G (3D), 8 G (plane strain)
  double critical_stretch = 0;  // s_0 of eq 10 (+infinity when G_c is)
  double break_in_compression = 0;  // 1: bonds break at |s| >= s_0, 0: at s >= s_0 (eq 11)
  double dilatation_factor = 0;  // d k - a G / d (derived by from()): P_i = this theta_i / m_i (lps_node_factors)

  /// Validates the material (InputError naming `prefix.key`) and derives the constants.
  static PdLpsConstants from(const PdMaterial& m, const char* prefix = "material");
};

/// The constants of every material, indexed by PdGrains::material: read by the bond kernels, so
/// device-resident in offload builds (to_device after filling it).
using PdLpsTable = exec::DeviceVector<PdLpsConstants>;

/// Critical stretch of eq 10, s_0 = sqrt(G_c / ((3 G + (3/4)^4 (K - 5 G / 3)) epsilon)) (Zhu & Zhao, derived
/// for 3D). The paper and the PeriDEM code use it in 2D as well, and so do we; 3 G + (3/4)^4 (K - 5G/3) =
/// 2.47 G + 0.32 K is > 0 for every K, G > 0. For M1 the bracket is 3 G (K = 5 G / 3) and s_0 = 1 / 21.6.
double pd_critical_stretch(const PdMaterial& m);

}  // namespace debris
