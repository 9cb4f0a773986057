#pragma once
// A sum of doubles whose result does not depend on the order of its terms, so it gives the same bits on any
// rank count, thread count or storage order (shared/design/scale-mpi.md, section 4): the fixed blocks of
// core/block_sums cannot survive particles moving between ranks, and MPI promises nothing about the order of
// a floating-point reduction.
//
// Each term is put on a fixed-point grid of 2^-kFractionBits (SI values of this field, 1e-30 kg to 1e12 Pa,
// lie far above it: a term keeps all 53 bits unless it is below 2^-127, about 6e-39, and anything under
// half the grid is rounded, to nearest, by the term alone). The grid values are integers and are added as
// integers, which is exact and associative; the result is rounded once, correctly, when read. An
// accumulator is kWords signed 64-bit words: kChunks digits of 32 bits, carry-save (a term touches at most
// three digits, with no carry chain), then a word that flags a non-finite or too large term. Two
// accumulators are added digit by digit, so ranks add theirs with one integer MPI_Allreduce
// (comm::allreduce below) and kernels fill one per block (exact_add is legal on a device).
#include <array>
#include <bit>
#include <cstdint>

#include "core/exec.hpp"

namespace debris::comm {

constexpr int kExactChunks = 10;         // 320 bits of digits
constexpr int kExactWords = kExactChunks + 1;  // and the invalid flag
constexpr int kExactFractionBits = 180;  // the grid: 2^-180 = 6.5e-55
constexpr int kExactLargestTermBits = 100;  // terms must be below 2^100 = 1.3e30 (else the sum is invalid)

DEBRIS_DECLARE_TARGET
/// Adds v to the accumulator acc[0 .. kExactWords). A NaN, an infinity or a term of 2^100 or more sets the
/// flag (the sum reads as NaN). Up to 2^30 terms may go into one accumulator before ExactSum::normalize.
inline void exact_add(std::int64_t* acc, double v) {
  const std::uint64_t b = std::bit_cast<std::uint64_t>(v);
  const int biased = static_cast<int>((b >> 52) & 0x7ff);
  std::uint64_t m = b & ((std::uint64_t{1} << 52) - 1);
  if (biased == 0x7ff) {
    acc[kExactChunks] = 1;
    return;
  }
  if (biased != 0) m |= std::uint64_t{1} << 52;
  if (m == 0) return;
  // v = +-m 2^(e - 1075) with e = biased (subnormals: e = 1); on the grid, m shifted left by s bits.
  int s = (biased == 0 ? 1 : biased) - 1075 + kExactFractionBits;
  if (s + 53 > kExactFractionBits + kExactLargestTermBits) {
    acc[kExactChunks] = 1;
    return;
  }
  if (s < 0) {  // below the grid: m / 2^-s rounded to nearest, ties to even
    const int k = -s;
    if (k > 54) return;
    const std::uint64_t half = std::uint64_t{1} << (k - 1);
    const std::uint64_t rest = m & ((half << 1) - 1);
    m >>= k;
    if (rest > half || (rest == half && (m & 1))) ++m;
    if (m == 0) return;
    s = 0;
  }
  // m 2^off (up to 85 bits) as three 32-bit digits from digit c on.
  const int c = s >> 5, off = s & 31;
  const std::uint64_t mask = 0xffffffffu;
  const auto d0 = static_cast<std::int64_t>((m << off) & mask);
  const auto d1 = static_cast<std::int64_t>((m >> (32 - off)) & mask);
  const auto d2 = static_cast<std::int64_t>((m >> 1) >> (63 - off));  // m >> (64 - off), 0 for off = 0
  // The sign without a branch (terms of either sign in any order would mispredict half the time):
  // (d ^ neg) - neg is d for neg = 0 and -d for neg = -1.
  const auto neg = -static_cast<std::int64_t>(b >> 63);
  acc[c] += (d0 ^ neg) - neg;
  acc[c + 1] += (d1 ^ neg) - neg;
  acc[c + 2] += (d2 ^ neg) - neg;
}
DEBRIS_END_DECLARE_TARGET

class ExactSum {
 public:
  static constexpr int kChunks = kExactChunks;
  static constexpr int kFractionBits = kExactFractionBits;
  static constexpr int kLargestTermBits = kExactLargestTermBits;

  ExactSum() = default;
  /// The sum held in an accumulator that a kernel filled (kExactWords words).
  explicit ExactSum(const std::int64_t* words);

  /// Adds one term; a NaN, an infinity or a term of 2^100 or more makes the sum invalid (value() NaN).
  void add(double v) {
    exact_add(w_.data(), v);
    // Each digit takes under 2^32 a term: carry before 2^30 terms could reach the int64 limit.
    if (++pending_ == (std::int64_t{1} << 30)) normalize();
  }

  ExactSum& operator+=(const ExactSum& o);

  /// The sum, correctly rounded to the nearest double (NaN when invalid).
  double value() const;
  bool valid() const { return w_[kChunks] == 0; }

  /// Carries every digit into [0, 2^32) but the top one, which keeps the sign: a unique representation,
  /// so equal sums have equal digits.
  void normalize();

  const std::array<std::int64_t, kExactWords>& words() const { return w_; }

 private:
  friend void allreduce(ExactSum* sums, int n);
  std::array<std::int64_t, kExactWords> w_{};  // kChunks digits, then the invalid flag
  std::int64_t pending_ = 0;                   // terms added since the last normalize()
};

/// Adds up n sums over all ranks, in place, exactly (one integer MPI_Allreduce of n x kExactWords values).
void allreduce(ExactSum* sums, int n);

}  // namespace debris::comm
