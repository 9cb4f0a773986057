#pragma once
// Self-affine random surfaces by Fourier filtering: a field whose power spectral density is
//   C(q) = C0                         q_l <= q < q_r   (the roll-off plateau)
//   C(q) = C0 (q / q_r)^(-2(1 + H))   q_r <= q <= q_s  (self-affine, Hurst exponent H)
//   C(q) = 0                          otherwise
// with q = |(q_a, q_b)| (for a profile, C_1D(q) ~ q^(-(1 + 2H)) over the same range), random phases, a real
// field (FFTW's c2r), the mean zero, then scaled to the requested rms height exactly (or to the requested rms
// slope, the spectral one of surface_spectrum.hpp, exact for this band-limited field). Periodic over the box's
// two in-plane lengths, so it tiles a periodic box. The amplitudes are Gaussian numbers drawn from
// mt19937_64(seed) by a Box-Muller written out here, one pair per stored wave vector in a fixed order: a seed
// gives the same bits with any standard library, and the same long waves whatever the cut-off.
#include <cstdint>
#include <string>

#include "core/rough/height_field.hpp"

namespace debris {

struct SelfAffineSpec {
  double hurst = 0.8;              // H, in (0, 1)
  double rms_height = 0;           // > 0 (or give rms_slope instead: exactly one of the two is > 0)
  double rms_slope = 0;
  double rolloff_wavelength = 0;   // lambda_r = 2 pi / q_r; 0: the largest (the box's length along a)
  double cutoff_wavelength = 0;    // lambda_s = 2 pi / q_s; > 0, < lambda_r
  double largest_wavelength = 0;   // lambda_l = 2 pi / q_l; 0: the box (every mode down to the box's length)
  std::uint64_t seed = 1;
};

/// A self-affine field over [origin_a, origin_a + length_a) x [origin_b, origin_b + length_b) on an n_a x n_b
/// grid (n_b = 1: a profile along a). Throws std::invalid_argument naming the parameter and its value for H
/// outside (0, 1), a non-positive rms (or both or neither of the two), q_s <= q_r, q_l > q_r, a grid too coarse
/// for the cut-off (spacing above lambda_s / 2), or a band that holds no wave vector of the grid. Thread-safe.
HeightField generate_self_affine(const SelfAffineSpec& spec, int normal_axis, double origin_a, double origin_b,
                                 double length_a, double length_b, int n_a, int n_b);

}  // namespace debris
