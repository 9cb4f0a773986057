#include "core/rough/surface_spectrum.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <map>
#include <numbers>
#include <stdexcept>
#include <string>

#include "core/rough/periodic_fft.hpp"

namespace debris {

namespace {

constexpr double kTwoPi = 2 * std::numbers::pi;
constexpr double kTol = 1e-9;  // relative slack at a range's ends, for bounds computed as 2 pi / lambda

bool is_profile(const HeightField& f) { return f.n_b == 1; }

// Calls visit(|q|, multiplicity, |h_k|^2) for every stored k != 0 of f's half spectrum.
template <class Visit>
void for_each_mode(const HeightField& f, Visit visit) {
  const HalfSpectrum half(f.n_a, f.n_b);
  const std::vector<std::complex<double>> x = forward_real_fft(f.h, f.n_a, f.n_b);
  const double n = static_cast<double>(f.n_a) * f.n_b;
  for (int i = 0; i < half.rows; ++i)
    for (int j = 0; j < half.cols; ++j) {
      const double qa = kTwoPi * half.k_a(i) / f.length_a;
      const double qb = is_profile(f) ? 0.0 : kTwoPi * half.k_b(j) / f.length_b;
      if (qa == 0 && qb == 0) continue;
      visit(std::hypot(qa, qb), half.multiplicity(i, j), std::norm(x[static_cast<std::size_t>(i) * half.cols + j]) / (n * n));
    }
}

// Least squares of log y against log x over the points with x in [lo, hi] and y > 0.
HurstFit fit_log_log(const std::vector<double>& x, const std::vector<double>& y, double lo, double hi) {
  HurstFit fit;
  std::vector<double> lx, ly;
  for (std::size_t k = 0; k < x.size(); ++k) {
    if (!(x[k] >= lo * (1 - kTol) && x[k] <= hi * (1 + kTol) && y[k] > 0)) continue;
    lx.push_back(std::log(x[k]));
    ly.push_back(std::log(y[k]));
    fit.lo = fit.points == 0 ? x[k] : std::min(fit.lo, x[k]);
    fit.hi = fit.points == 0 ? x[k] : std::max(fit.hi, x[k]);
    ++fit.points;
  }
  if (fit.points < 3) return fit;
  const double m = fit.points;
  double mx = 0, my = 0;
  for (int k = 0; k < fit.points; ++k) mx += lx[k], my += ly[k];
  mx /= m, my /= m;
  double sxx = 0, sxy = 0;
  for (int k = 0; k < fit.points; ++k) sxx += (lx[k] - mx) * (lx[k] - mx), sxy += (lx[k] - mx) * (ly[k] - my);
  if (!(sxx > 0)) return fit;  // every point at one x
  fit.slope = sxy / sxx;
  double ss = 0;
  for (int k = 0; k < fit.points; ++k) {
    const double r = ly[k] - my - fit.slope * (lx[k] - mx);
    ss += r * r;
  }
  fit.slope_error = std::sqrt(ss / (m - 2) / sxx);
  fit.defined = true;
  return fit;
}

}  // namespace

SurfaceSpectrum power_spectrum(const HeightField& f, SpectrumBins bins, int bins_per_decade) {
  if (f.n_a < 1 || f.n_b < 1 || f.h.size() != static_cast<std::size_t>(f.n_a) * f.n_b)
    throw std::invalid_argument("power_spectrum: the field's grid is " + std::to_string(f.n_a) + " x " +
                                std::to_string(f.n_b) + " but holds " + std::to_string(f.h.size()) + " heights");
  if (bins == SpectrumBins::logarithmic && bins_per_decade < 1)
    throw std::invalid_argument("power_spectrum: bins_per_decade = " + std::to_string(bins_per_decade) + ": must be >= 1");
  SurfaceSpectrum s;
  s.profile = is_profile(f);
  s.area = s.profile ? f.length_a : f.length_a * f.length_b;
  const double rms = f.rms_height();
  s.variance = rms * rms;
  const double dq = kTwoPi / (s.profile ? f.length_a : std::max(f.length_a, f.length_b));
  struct Bin {
    double q = 0, c = 0;
    long modes = 0;
  };
  std::map<long, Bin> binned;
  for_each_mode(f, [&](double q, int multiplicity, double power) {
    const long b = bins == SpectrumBins::linear ? std::lround(q / dq)
                                                : static_cast<long>(std::floor(std::log10(q / dq) * bins_per_decade + kTol));
    Bin& bin = binned[b];
    bin.q += multiplicity * q;
    bin.c += multiplicity * s.area * power;
    bin.modes += multiplicity;
  });
  for (const auto& [b, bin] : binned) {
    s.q.push_back(bin.q / bin.modes);
    s.c.push_back(bin.c / bin.modes);
    s.modes.push_back(bin.modes);
  }
  return s;
}

HurstFit fit_hurst_from_psd(const SurfaceSpectrum& s, double q_min, double q_max) {
  if (!(s.variance > 0)) return {};  // flat: no power anywhere, no exponent
  // A bin with a 1e-24 share of the power or less holds the transform's round-off (relative 1e-16 in the
  // amplitudes, 1e-32 in the power), not a mode of the surface: it counts as without power.
  std::vector<double> c(s.c);
  for (std::size_t k = 0; k < c.size(); ++k)
    if (s.modes[k] * c[k] <= 1e-24 * s.area * s.variance) c[k] = 0;
  HurstFit fit = fit_log_log(s.q, c, q_min, q_max);
  if (!fit.defined) return fit;
  fit.hurst = s.profile ? (-fit.slope - 1) / 2 : -fit.slope / 2 - 1;
  fit.error = fit.slope_error / 2;
  return fit;
}

HeightCorrelation height_height_correlation(const HeightField& f, int along, double max_fraction) {
  if (along != 0 && along != 1)
    throw std::invalid_argument("height_height_correlation: along = " + std::to_string(along) + ": 0 (a) or 1 (b)");
  if (along == 1 && is_profile(f))
    throw std::invalid_argument("height_height_correlation: along = 1 on a profile (it is constant along b)");
  if (!(max_fraction > 0 && max_fraction <= 1))
    throw std::invalid_argument("height_height_correlation: max_fraction must be in (0, 1]");
  HeightCorrelation c;
  c.along = along;
  const int n = along == 0 ? f.n_a : f.n_b;
  const double spacing = along == 0 ? f.spacing_a() : f.spacing_b();
  const int lags = static_cast<int>(std::floor(max_fraction * n));
  const double points = static_cast<double>(f.n_a) * f.n_b;
  for (int m = 1; m <= lags; ++m) {
    double s = 0;
    for (int i = 0; i < f.n_a; ++i) {
      const double* row = f.h.data() + static_cast<std::size_t>(i) * f.n_b;
      if (along == 0) {
        const double* next = f.h.data() + static_cast<std::size_t>((i + m) % f.n_a) * f.n_b;
        for (int j = 0; j < f.n_b; ++j) s += (next[j] - row[j]) * (next[j] - row[j]);
      } else {  // the row's last m points pair with its first m (periodic)
        for (int j = 0; j + m < f.n_b; ++j) s += (row[j + m] - row[j]) * (row[j + m] - row[j]);
        for (int j = f.n_b - m; j < f.n_b; ++j) s += (row[j + m - f.n_b] - row[j]) * (row[j + m - f.n_b] - row[j]);
      }
    }
    c.r.push_back(m * spacing);
    c.value.push_back(s / points);
  }
  return c;
}

HurstFit fit_hurst_from_hhcf(const HeightCorrelation& c, double r_min, double r_max) {
  HurstFit fit = fit_log_log(c.r, c.value, r_min, r_max);
  if (!fit.defined) return fit;
  fit.hurst = fit.slope / 2;
  fit.error = fit.slope_error / 2;
  return fit;
}

double spectral_rms_slope(const HeightField& f, double q_max) {
  double s = 0;
  for_each_mode(f, [&](double q, int multiplicity, double power) {
    if (q <= q_max) s += multiplicity * q * q * power;
  });
  return std::sqrt(s);
}

}  // namespace debris
