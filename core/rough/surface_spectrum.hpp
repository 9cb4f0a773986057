#pragma once
// Measurements of a height field (height_field.hpp): its power spectral density, radially averaged, the
// height-height correlation along an axis, the Hurst exponent fitted to either, and the spectral rms slope.
// Design note: shared/design/energy-and-rough-wear.md section 3. The field is periodic, so no window is used.
//
// PSD convention (that of Jacobs, Junge and Pastewka, Surf. Topogr. 5, 013001 (2017)): with the N = n_a n_b
// grid heights h(x) and the Fourier coefficients h_k = (1 / N) sum_x h(x) exp(-i k.x), so that
// h(x) = sum_k h_k exp(i k.x),
//   C(k) = A |h_k|^2        A = L_a L_b (a profile: A = L_a, and C is C_1D)
// and Parseval reads  sum over k != 0 of C(k) = A * variance  (the variance of h about its mean), the
// discrete form of  <h^2> = (2 pi)^-2 integral C(q) d^2q. Every k of the full spectrum counts, k and -k both
// (a profile's C_1D(q) is two-sided: q and -q each carry C_1D).
// Exponents: C_2D ~ q^-2(1+H), C_1D ~ q^-(1+2H), height-height correlation ~ r^2H.
#include <limits>
#include <vector>

#include "core/rough/height_field.hpp"

namespace debris {

/// C(q) in bins of |q|: in each bin the mean |q| of its wave vectors, the mean C over them, and their number
/// (k and -k counted apart), so sum over bins of modes * c = area * variance.
struct SurfaceSpectrum {
  bool profile = false;
  double area = 0;          // L_a L_b, m^2 (a profile: L_a, m)
  double variance = 0;      // of the grid's heights about their mean, m^2
  std::vector<double> q;    // rad/m
  std::vector<double> c;    // m^4 (a profile: m^3)
  std::vector<long> modes;
};

enum class SpectrumBins {
  linear,      // |q| rounded to a multiple of dq = 2 pi / max(L_a, L_b): a profile's bins are its wave numbers
  logarithmic  // bins_per_decade per factor 10 of |q|, from the smallest non-zero |q|
};

/// The radially averaged PSD (a profile's C_1D) of f by FFT; empty bins are left out, and so is q = 0 (the mean).
SurfaceSpectrum power_spectrum(const HeightField& f, SpectrumBins bins = SpectrumBins::linear, int bins_per_decade = 10);

/// A Hurst exponent fitted by least squares of log y against log x over a range.
struct HurstFit {
  bool defined = false;               // false: a flat field, or fewer than 3 points with y > 0 in the range
  double hurst = 0, error = 0;        // H and its standard error (from the slope's)
  double slope = 0, slope_error = 0;  // d log y / d log x and its standard error
  double lo = 0, hi = 0;              // the smallest and largest x fitted
  int points = 0;
};

/// H from the PSD's bins with q_min <= q <= q_max: 2D slope = -2(1 + H), profile slope = -(1 + 2H). Each bin
/// with power is one point, unweighted; a bin holding at most 1e-24 of the total power (the FFT's round-off)
/// has none. Fit between q_r and q_s (or below the particle scale, design note).
HurstFit fit_hurst_from_psd(const SurfaceSpectrum& s, double q_min, double q_max);

/// <(h(x + r e) - h(x))^2> over the periodic grid, e along a (along = 0) or b (along = 1; not for a profile),
/// for r = 1, 2, ... grid spacings up to max_fraction of the length.
struct HeightCorrelation {
  int along = 0;
  std::vector<double> r;      // m
  std::vector<double> value;  // m^2
};

HeightCorrelation height_height_correlation(const HeightField& f, int along = 0, double max_fraction = 0.25);

/// H from the correlation's points with r_min <= r <= r_max: slope = 2H. Self-affine only well between the
/// cut-off and the roll-off wavelengths; below the cut-off the correlation grows as r^2 (a smooth surface).
HurstFit fit_hurst_from_hhcf(const HeightCorrelation& c, double r_min, double r_max);

/// The rms gradient from the spectrum, sqrt(sum over k of |k|^2 |h_k|^2): exact for the band-limited field the
/// grid samples (its trigonometric interpolant; a Nyquist mode counts as a cosine of wave number pi / spacing).
/// HeightField::rms_slope is the central-difference one, which underestimates short waves by sin(k d) / (k d).
/// With q_max: the modes with |q| <= q_max only (the slope of the field's wavelengths down to 2 pi / q_max: a
/// face of spheres measured above the particle scale).
double spectral_rms_slope(const HeightField& f, double q_max = std::numeric_limits<double>::infinity());

}  // namespace debris
