#pragma once
// The discrete Fourier transforms of a periodic height grid (core/rough), through FFTW without exposing it:
// the generator fills a half spectrum and transforms it back (c2r), the spectra transform a field forward
// (r2c). FFTW's planner is not thread-safe, so every plan is made and destroyed under one lock (executing a
// plan is thread-safe). Plans use FFTW_ESTIMATE: a few transforms per run, where measuring the fastest plan
// would cost more than it saves.
//
// Unnormalised, as FFTW:  forward X(k) = sum_x h(x) exp(-i k.x);  inverse h(x) = sum_k X(k) exp(+i k.x), the
// sum over all k. A real grid's spectrum is Hermitian, X(-k) = conj X(k), so only half of it is stored; see
// HalfSpectrum for which wave vectors it holds.
#include <complex>
#include <vector>

namespace debris {

/// The half spectrum of an n_a x n_b real grid (row-major, as HeightField::h). 2D: rows i = 0..n_a-1 times
/// columns j = 0..n_b/2, wave numbers (k_a, k_b) = (i <= n_a/2 ? i : i - n_a, j) in units of 2 pi / L.
/// A profile (n_b = 1): one column of rows i = 0..n_a/2, k_a = i. Entry (i, j) at index i * cols + j.
struct HalfSpectrum {
  int n_a = 0, n_b = 0;
  int rows = 0, cols = 0;
  HalfSpectrum(int na, int nb)
      : n_a(na), n_b(nb), rows(nb == 1 ? na / 2 + 1 : na), cols(nb == 1 ? 1 : nb / 2 + 1) {}
  std::size_t size() const { return static_cast<std::size_t>(rows) * cols; }
  int k_a(int i) const { return n_b == 1 || i <= n_a / 2 ? i : i - n_a; }
  int k_b(int j) const { return j; }
  /// Whether column j holds both k and -k (its entries pair up as (i, j) and (n_a - i, j)): the column
  /// k_b = 0 and, for even n_b, the Nyquist column k_b = n_b / 2. A profile's one column is not such a column:
  /// its -k are not stored.
  bool self_paired_column(int j) const { return n_b > 1 && (j == 0 || 2 * j == n_b); }
  /// How many wave vectors of the full spectrum entry (i, j) stands for: 2 (k and its unstored -k), or 1
  /// where -k is k itself or is stored too.
  int multiplicity(int i, int j) const {
    if (n_b == 1) return i == 0 || 2 * i == n_a ? 1 : 2;
    return self_paired_column(j) ? 1 : 2;
  }
};

/// X(k) of the real grid h over its half spectrum (r2c).
std::vector<std::complex<double>> forward_real_fft(const std::vector<double>& h, int n_a, int n_b);

/// h(x) = sum over all k of X(k) exp(i k.x) from the half spectrum (c2r). The caller makes the stored half
/// Hermitian where it holds both k and -k (HalfSpectrum::self_paired_column; real X where k = -k).
std::vector<double> inverse_real_fft(std::vector<std::complex<double>> half, int n_a, int n_b);

}  // namespace debris
