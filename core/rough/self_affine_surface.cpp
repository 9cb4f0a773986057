#include "core/rough/self_affine_surface.hpp"

#include <cmath>
#include <complex>
#include <numbers>
#include <random>
#include <stdexcept>
#include <utility>

#include "core/error.hpp"
#include "core/rough/periodic_fft.hpp"

namespace debris {

namespace {

constexpr double kTwoPi = 2 * std::numbers::pi;

std::invalid_argument bad(const std::string& name, double value, const std::string& what) {
  return std::invalid_argument("self-affine surface: " + name + " = " + format_value(value) + ": " + what);
}

// Two independent standard normal numbers by Box-Muller from mt19937_64's 53-bit uniforms, written out so a
// seed gives the same surface with every standard library (std::normal_distribution's algorithm is not
// specified by the standard).
std::pair<double, double> gaussian_pair(std::mt19937_64& rng) {
  const double u1 = (static_cast<double>(rng() >> 11) + 1.0) * 0x1.0p-53;  // (0, 1]: its log is finite
  const double u2 = static_cast<double>(rng() >> 11) * 0x1.0p-53;          // [0, 1)
  const double r = std::sqrt(-2.0 * std::log(u1));
  return {r * std::cos(kTwoPi * u2), r * std::sin(kTwoPi * u2)};
}

void check(const SelfAffineSpec& s, double length_a, double length_b, int n_a, int n_b) {
  if (!(n_a >= 1)) throw bad("n_a", n_a, "the grid needs at least one point along a");
  if (!(n_b >= 1)) throw bad("n_b", n_b, "the grid needs at least one point along b (1: a profile)");
  if (!(length_a > 0) || !std::isfinite(length_a)) throw bad("length_a", length_a, "must be a length > 0");
  if (n_b > 1 && (!(length_b > 0) || !std::isfinite(length_b))) throw bad("length_b", length_b, "must be a length > 0");
  if (!(s.hurst > 0 && s.hurst < 1)) throw bad("hurst", s.hurst, "the Hurst exponent must be in (0, 1)");
  if (s.rms_height < 0 || std::isnan(s.rms_height)) throw bad("rms_height", s.rms_height, "must be > 0");
  if (s.rms_slope < 0 || std::isnan(s.rms_slope)) throw bad("rms_slope", s.rms_slope, "must be > 0");
  if (s.rms_height > 0 && s.rms_slope > 0)
    throw bad("rms_height", s.rms_height, "give rms_height or rms_slope, not both (rms_slope = " +
                                              format_value(s.rms_slope) + ")");
  if (!(s.rms_height > 0) && !(s.rms_slope > 0))
    throw bad("rms_height", s.rms_height, "give one of rms_height and rms_slope > 0 (rms_slope = " +
                                              format_value(s.rms_slope) + ")");
  if (!std::isfinite(s.rms_height) || !std::isfinite(s.rms_slope))
    throw bad(std::isfinite(s.rms_height) ? "rms_slope" : "rms_height",
              std::isfinite(s.rms_height) ? s.rms_slope : s.rms_height, "must be finite");
  if (!(s.cutoff_wavelength > 0) || !std::isfinite(s.cutoff_wavelength))
    throw bad("cutoff_wavelength", s.cutoff_wavelength, "must be a length > 0");
  if (!(s.rolloff_wavelength >= 0) || !std::isfinite(s.rolloff_wavelength))
    throw bad("rolloff_wavelength", s.rolloff_wavelength, "must be a length > 0 (or 0: the box's length along a)");
  const double rolloff = s.rolloff_wavelength > 0 ? s.rolloff_wavelength : length_a;
  if (!(s.cutoff_wavelength < rolloff))
    throw bad("cutoff_wavelength", s.cutoff_wavelength,
              "must be shorter than the roll-off wavelength " + format_value(rolloff) + " (q_s > q_r)");
  if (!(s.largest_wavelength >= 0) || !std::isfinite(s.largest_wavelength))
    throw bad("largest_wavelength", s.largest_wavelength, "must be a length > 0 (or 0: the box)");
  if (s.largest_wavelength > 0 && s.largest_wavelength < rolloff)
    throw bad("largest_wavelength", s.largest_wavelength,
              "must be at least the roll-off wavelength " + format_value(rolloff) + " (q_l <= q_r)");
  // The grid must resolve the shortest wavelength with two points (the Nyquist limit).
  const double limit = s.cutoff_wavelength / 2 * (1 + 1e-12);
  if (length_a / n_a > limit)
    throw bad("grid spacing along a", length_a / n_a,
              "exceeds cutoff_wavelength / 2 = " + format_value(s.cutoff_wavelength / 2) + ": use n_a >= " +
                  format_value(std::ceil(2 * length_a / s.cutoff_wavelength * (1 - 1e-12))));
  if (n_b > 1 && length_b / n_b > limit)
    throw bad("grid spacing along b", length_b / n_b,
              "exceeds cutoff_wavelength / 2 = " + format_value(s.cutoff_wavelength / 2) + ": use n_b >= " +
                  format_value(std::ceil(2 * length_b / s.cutoff_wavelength * (1 - 1e-12))));
}

}  // namespace

HeightField generate_self_affine(const SelfAffineSpec& spec, int normal_axis, double origin_a, double origin_b,
                                 double length_a, double length_b, int n_a, int n_b) {
  if (normal_axis < 0 || normal_axis > 2) throw bad("normal_axis", normal_axis, "must be 0, 1 or 2 (x, y, z)");
  check(spec, length_a, length_b, n_a, n_b);
  const bool profile = n_b == 1;
  const double q_r = kTwoPi / (spec.rolloff_wavelength > 0 ? spec.rolloff_wavelength : length_a);
  const double q_s = kTwoPi / spec.cutoff_wavelength;
  const double q_l = spec.largest_wavelength > 0 ? kTwoPi / spec.largest_wavelength : 0.0;
  const double exponent = profile ? 1 + 2 * spec.hurst : 2 * (1 + spec.hurst);
  // Band edges a hair wide, so a cut-off of exactly two grid spacings keeps the Nyquist modes whatever the
  // round-off of 2 pi / lambda against 2 pi k / L.
  const double tol = 1e-9;

  const HalfSpectrum half(n_a, n_b);
  std::vector<std::complex<double>> x(half.size());
  std::mt19937_64 rng(spec.seed);
  double slope2 = 0;  // sum over all k of |q|^2 |X|^2: the mean squared gradient of the field (Parseval)
  bool any = false;
  for (int i = 0; i < half.rows; ++i)
    for (int j = 0; j < half.cols; ++j) {
      // One pair of normal numbers per stored entry, used or not, so a seed's modes do not depend on the band.
      const auto [g1, g2] = gaussian_pair(rng);
      const std::size_t at = static_cast<std::size_t>(i) * half.cols + j;
      const double qa = kTwoPi * half.k_a(i) / length_a;
      const double qb = profile ? 0.0 : kTwoPi * half.k_b(j) / length_b;
      const double q = std::hypot(qa, qb);
      if (q == 0 || q < q_l * (1 - tol) || q > q_s * (1 + tol)) continue;  // the mean is zero
      const double c = q < q_r ? 1.0 : std::pow(q / q_r, -exponent);
      any = true;
      const bool paired_column = half.self_paired_column(j);
      if (paired_column && 2 * i > n_a) {
        // -k is stored too (row n_a - i, filled before this one): a real field needs X(-k) = conj X(k).
        x[at] = std::conj(x[static_cast<std::size_t>(n_a - i) * half.cols + j]);
      } else if ((paired_column || profile) && (i == 0 || 2 * i == n_a)) {
        x[at] = std::sqrt(c) * g1;  // k = -k (mod the grid): X real, with the same mean square as the others
      } else {
        x[at] = std::sqrt(c / 2) * std::complex<double>(g1, g2);
      }
      slope2 += half.multiplicity(i, j) * q * q * std::norm(x[at]);
    }
  if (!any)
    throw bad("cutoff_wavelength", spec.cutoff_wavelength,
              "no wave vector of the grid lies between the largest and the cut-off wavelength (the box's lengths: " +
                  format_value(length_a) + ", " + format_value(profile ? 0.0 : length_b) + ")");

  HeightField f;
  f.normal_axis = normal_axis;
  f.origin_a = origin_a;
  f.origin_b = origin_b;
  f.length_a = length_a;
  f.length_b = length_b;
  f.n_a = n_a;
  f.n_b = n_b;
  f.h = inverse_real_fft(std::move(x), n_a, n_b);
  const double m = f.mean();  // zero up to round-off: X(0) = 0
  for (double& v : f.h) v -= m;
  // Scaled after the transform, from the grid itself: the rms height is then exact to round-off. The rms slope
  // is the spectral one (surface_spectrum.hpp), exact for the band-limited field.
  const double scale = spec.rms_height > 0 ? spec.rms_height / f.rms_height() : spec.rms_slope / std::sqrt(slope2);
  for (double& v : f.h) v *= scale;
  return f;
}

}  // namespace debris
