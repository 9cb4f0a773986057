#pragma once
// Particle diameters of the amorphous samples (paper section 3.2): a log-normal distribution of MODE d0 and
// standard deviation 0.2 (d_l - d_s), truncated to [d_s, d_l].
//
// Which standard deviation: the paper gives the mode and the standard deviation of "a log-normal
// distribution" and then says that it "is truncated between d_s and d_l", so both numbers describe the
// log-normal before truncation; that is what from_mode_and_sd() matches. Truncation keeps the mode (the
// density inside [d_s, d_l] is only rescaled, so its peak stays where it was as long as d0 is inside) and
// narrows the spread: truncated_sd() gives the standard deviation of what is actually drawn (for the
// paper's d_s = 0.75 d0, d_l = 1.25 d0 the bounds sit 2.5 untruncated standard deviations from the mode).
//
// With w = exp(sigma^2), a log-normal has mode m = exp(mu - sigma^2) and variance
// S^2 = (w - 1) exp(2 mu + sigma^2) = (w - 1) w^3 m^2, so t = w - 1 solves t (1 + t)^3 = (S / m)^2, one
// root t > 0 (the left side increases from 0), found by Newton; then sigma^2 = log1p(t), mu = ln m + sigma^2.
//
// Draws are by inversion of the truncated CDF, one uniform number per diameter, from std::mt19937_64 bits
// turned into a double here (not std::uniform_real_distribution or std::normal_distribution, whose output
// differs between standard libraries), so a seed gives the same diameters with any compiler.
#include <cstdint>
#include <random>
#include <string>
#include <vector>

namespace debris {

/// A double uniform in the open interval (0, 1) from the top 53 bits of one 64-bit draw.
inline double uniform_open01(std::mt19937_64& rng) { return (static_cast<double>(rng() >> 11) + 0.5) * 0x1.0p-53; }

/// Standard normal CDF Phi(z) and its complement Q(z) = Phi(-z), each accurate in its own tail.
double normal_cdf(double z);
double normal_ccdf(double z);
/// Inverse of Phi on (0, 1), to about machine precision (rational start, then one Halley step on erfc).
double normal_quantile(double p);

class TruncatedLogNormal {
 public:
  /// Log-normal of the given mode and (untruncated) standard deviation, truncated to [lo, hi]. Throws
  /// InputError naming `prefix`.d_s / .d_l / .d0 / .sd for lo <= 0, hi <= lo, a mode outside [lo, hi],
  /// sd <= 0, or non-finite values.
  static TruncatedLogNormal from_mode_and_sd(double mode, double sd, double lo, double hi,
                                             const std::string& prefix = "size_distribution");

  double mu() const { return mu_; }
  double sigma() const { return sigma_; }
  double lo() const { return lo_; }
  double hi() const { return hi_; }

  double mode() const;            // exp(mu - sigma^2), the same with and without truncation
  double untruncated_sd() const;  // the sd it was built from
  double mean() const;            // of the truncated distribution
  double truncated_sd() const;    // of the truncated distribution
  /// Probability that the untruncated log-normal falls inside [lo, hi].
  double kept_fraction() const;
  /// Density of the truncated distribution (0 outside [lo, hi]).
  double pdf(double d) const;

  /// One diameter in [lo, hi].
  double operator()(std::mt19937_64& rng) const;
  /// n diameters from a generator seeded with `seed`.
  std::vector<double> sample(std::size_t n, std::uint64_t seed) const;

 private:
  /// E[X^k] of the truncated distribution.
  double raw_moment(int k) const;

  double mu_ = 0, sigma_ = 1, lo_ = 0, hi_ = 0;
  double z_lo_ = 0, z_hi_ = 0;  // standardised log bounds
};

}  // namespace debris
