#include "scenarios/common/dem/truncated_lognormal.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/error.hpp"

namespace debris {

namespace {

constexpr double kInvSqrt2 = 0.70710678118654752440;

/// P(a < Z < b) for a standard normal Z, from whichever tail keeps the difference accurate.
double normal_interval(double a, double b) {
  if (a > 0.0) return normal_ccdf(a) - normal_ccdf(b);
  return normal_cdf(b) - normal_cdf(a);
}

/// Quantile for p in (0, 0.5]: Acklam's rational approximation (relative error < 1.2e-9), then one Halley
/// step on Phi(x) - p, which brings it to round-off (Phi is evaluated with erfc, accurate in this tail).
double lower_quantile(double p) {
  static constexpr double a[] = {-3.969683028665376e+01, 2.209460984245205e+02,  -2.759285104469687e+02,
                                 1.383577518672690e+02,  -3.066479806614716e+01, 2.506628277459239e+00};
  static constexpr double b[] = {-5.447609879822406e+01, 1.615858368580409e+02, -1.556989798598866e+02,
                                 6.680131188771972e+01, -1.328068155288572e+01};
  static constexpr double c[] = {-7.784894002430293e-03, -3.223964580411365e-01, -2.400758277161838e+00,
                                 -2.549732539343734e+00, 4.374664141464968e+00,  2.938163982698783e+00};
  static constexpr double d[] = {7.784695709041462e-03, 3.224671290700398e-01, 2.445134137142996e+00,
                                 3.754408661907416e+00};
  double x;
  if (p < 0.02425) {
    const double q = std::sqrt(-2.0 * std::log(p));
    x = (((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
        ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1.0);
  } else {
    const double q = p - 0.5, r = q * q;
    x = (((((a[0] * r + a[1]) * r + a[2]) * r + a[3]) * r + a[4]) * r + a[5]) * q /
        (((((b[0] * r + b[1]) * r + b[2]) * r + b[3]) * r + b[4]) * r + 1.0);
  }
  const double e = normal_cdf(x) - p;
  const double u = e * std::sqrt(2.0 * std::numbers::pi) * std::exp(0.5 * x * x);
  return x - u / (1.0 + 0.5 * x * u);
}

}  // namespace

double normal_cdf(double z) { return 0.5 * std::erfc(-z * kInvSqrt2); }

double normal_ccdf(double z) { return 0.5 * std::erfc(z * kInvSqrt2); }

double normal_quantile(double p) {
  if (!(p > 0.0)) return -HUGE_VAL;
  if (!(p < 1.0)) return HUGE_VAL;
  // 1 - p is exact for p >= 0.5, so the upper half reuses the lower one without losing digits.
  return p <= 0.5 ? lower_quantile(p) : -lower_quantile(1.0 - p);
}

TruncatedLogNormal TruncatedLogNormal::from_mode_and_sd(double mode, double sd, double lo, double hi,
                                                        const std::string& prefix) {
  auto finite = [](double v) { return std::isfinite(v); };
  if (!(finite(lo) && lo > 0.0))
    throw input_error(prefix + ".d_s", format_value(lo), "the smallest diameter must be > 0");
  if (!(finite(hi) && hi > lo))
    throw input_error(prefix + ".d_l", format_value(hi),
                      "the largest diameter must be larger than the smallest, d_s = " + format_value(lo));
  if (!(finite(mode) && mode >= lo && mode <= hi))
    throw input_error(prefix + ".d0", format_value(mode),
                      "the mode must lie inside [d_s, d_l] = [" + format_value(lo) + ", " + format_value(hi) + "]");
  if (!(finite(sd) && sd > 0.0))
    throw input_error(prefix + ".sd", format_value(sd), "the standard deviation must be > 0");

  // t (1 + t)^3 = r^2, Newton from t = r^2: h(t) = t (1 + t)^3 - r^2 is increasing and convex for t > 0 and
  // h(r^2) >= 0, so the iterates decrease monotonically onto the root.
  const double r2 = (sd / mode) * (sd / mode);
  double t = r2;
  for (int it = 0; it < 200; ++it) {
    const double u = 1.0 + t;
    const double h = t * u * u * u - r2;
    const double dh = u * u * (1.0 + 4.0 * t);
    const double next = t - h / dh;
    if (!(next < t)) break;  // no more progress: converged to round-off
    t = next;
  }
  TruncatedLogNormal dist;
  const double s2 = std::log1p(t);
  dist.sigma_ = std::sqrt(s2);
  dist.mu_ = std::log(mode) + s2;
  dist.lo_ = lo;
  dist.hi_ = hi;
  dist.z_lo_ = (std::log(lo) - dist.mu_) / dist.sigma_;
  dist.z_hi_ = (std::log(hi) - dist.mu_) / dist.sigma_;
  if (!(dist.kept_fraction() > 0.0))
    throw input_error(prefix + ".sd", format_value(sd),
                      "leaves no probability inside [d_s, d_l] in double precision; widen the bounds or the sd");
  return dist;
}

double TruncatedLogNormal::mode() const { return std::exp(mu_ - sigma_ * sigma_); }

double TruncatedLogNormal::untruncated_sd() const {
  // Var = (exp(sigma^2) - 1) exp(2 mu + sigma^2).
  return std::sqrt(std::expm1(sigma_ * sigma_)) * std::exp(mu_ + 0.5 * sigma_ * sigma_);
}

double TruncatedLogNormal::kept_fraction() const { return normal_interval(z_lo_, z_hi_); }

// ln X = mu + sigma Z, so E[X^k ; a < Z < b] = exp(k mu + k^2 sigma^2 / 2) P(a - k sigma < Z < b - k sigma).
double TruncatedLogNormal::raw_moment(int k) const {
  const double ks = k * sigma_;
  return std::exp(k * mu_ + 0.5 * ks * ks) * normal_interval(z_lo_ - ks, z_hi_ - ks) / kept_fraction();
}

double TruncatedLogNormal::mean() const { return raw_moment(1); }

double TruncatedLogNormal::truncated_sd() const {
  const double m = mean();
  return std::sqrt(std::max(0.0, raw_moment(2) - m * m));
}

double TruncatedLogNormal::pdf(double d) const {
  if (!(d >= lo_ && d <= hi_)) return 0.0;
  const double z = (std::log(d) - mu_) / sigma_;
  return std::exp(-0.5 * z * z) / (d * sigma_ * std::sqrt(2.0 * std::numbers::pi)) / kept_fraction();
}

double TruncatedLogNormal::operator()(std::mt19937_64& rng) const {
  const double u = uniform_open01(rng);
  // Invert the CDF inside [z_lo, z_hi]; when the whole range is in the upper tail, work with Q = 1 - Phi so
  // that the two bounds' probabilities do not both round to 1.
  double z;
  if (z_lo_ > 0.0) {
    const double q_lo = normal_ccdf(z_lo_), q_hi = normal_ccdf(z_hi_);
    z = -normal_quantile(q_lo - u * (q_lo - q_hi));
  } else {
    const double p_lo = normal_cdf(z_lo_), p_hi = normal_cdf(z_hi_);
    z = normal_quantile(p_lo + u * (p_hi - p_lo));
  }
  // Round-off at the ends may step just outside the bounds; the bounds are hard limits.
  return std::clamp(std::exp(mu_ + sigma_ * z), lo_, hi_);
}

std::vector<double> TruncatedLogNormal::sample(std::size_t n, std::uint64_t seed) const {
  std::mt19937_64 rng(seed);
  std::vector<double> out(n);
  for (double& d : out) d = (*this)(rng);
  return out;
}

}  // namespace debris
