#pragma once
// A sum of doubles whose result does not depend on the order of its terms, so it gives the same bits on any
// rank count, thread count or storage order (shared/design/scale-mpi.md, section 4): the fixed blocks of
// core/block_sums cannot survive particles moving between ranks, and MPI promises nothing about the order of
// a floating-point reduction.
//
// Each term is put on a fixed-point grid of kUnit = 2^-kFractionBits (SI values of this field, 1e-30 kg to
// 1e12 Pa, lie far above it: a term keeps all 53 bits unless it is below 2^-127, about 6e-39, and anything
// under kUnit / 2 is rounded, to nearest, by the term alone). The grid values are integers and are added
// as integers, which is exact and associative; the result is rounded once, correctly, when read. Integers
// are held as kChunks signed 64-bit accumulators of 32-bit digits (carry-save: a term touches at most
// three, with no carry chain), so two ranks' sums are added by adding their chunks (one MPI_Allreduce on
// integers, comm::allreduce below).
#include <array>
#include <cstdint>
#include <cstring>

namespace debris::comm {

class ExactSum {
 public:
  static constexpr int kChunks = 10;          // 320 bits
  static constexpr int kFractionBits = 180;   // the grid: 2^-180 = 6.5e-55
  static constexpr int kLargestTermBits = 100;  // terms must be below 2^100 = 1.3e30 (else the sum is invalid)

  /// Adds one term; a NaN, an infinity or a term of 2^100 or more makes the sum invalid (value() NaN).
  void add(double v) {
    std::uint64_t b;
    std::memcpy(&b, &v, sizeof b);
    const int biased = static_cast<int>((b >> 52) & 0x7ff);
    std::uint64_t m = b & ((std::uint64_t{1} << 52) - 1);
    if (biased == 0x7ff) {
      invalid_ = 1;
      return;
    }
    if (biased != 0) m |= std::uint64_t{1} << 52;
    if (m == 0) return;
    // v = +-m 2^(biased - 1075) (subnormals: exponent of biased = 1); in grid units m is shifted by s.
    int s = (biased == 0 ? 1 : biased) - 1075 + kFractionBits;
    if (s + 53 > kFractionBits + kLargestTermBits) {
      invalid_ = 1;
      return;
    }
    if (s < 0) {  // below the grid: round m / 2^-s to nearest, ties to even
      const int k = -s;
      if (k > 54) return;
      const std::uint64_t half = std::uint64_t{1} << (k - 1);
      const std::uint64_t rest = m & ((half << 1) - 1);
      m >>= k;
      if (rest > half || (rest == half && (m & 1))) ++m;
      if (m == 0) return;
      s = 0;
    }
    const bool negative = (b >> 63) != 0;
    const int c = s >> 5;
    const unsigned __int128 w = static_cast<unsigned __int128>(m) << (s & 31);
    const auto d0 = static_cast<std::int64_t>(w & 0xffffffffu);
    const auto d1 = static_cast<std::int64_t>((w >> 32) & 0xffffffffu);
    const auto d2 = static_cast<std::int64_t>(w >> 64);
    if (negative) {
      chunk_[c] -= d0;
      chunk_[c + 1] -= d1;
      if (d2) chunk_[c + 2] -= d2;
    } else {
      chunk_[c] += d0;
      chunk_[c + 1] += d1;
      if (d2) chunk_[c + 2] += d2;
    }
    // Each chunk takes under 2^32 a term: carry before 2^30 terms could reach the int64 limit.
    if (++pending_ == (std::int64_t{1} << 30)) normalize();
  }

  ExactSum& operator+=(const ExactSum& o);

  /// The sum, correctly rounded to the nearest double (NaN when invalid).
  double value() const;
  bool valid() const { return invalid_ == 0; }

  /// Carries every chunk into [0, 2^32) but the top one, which keeps the sign: a unique representation,
  /// so equal sums have equal chunks.
  void normalize();

  const std::array<std::int64_t, kChunks>& chunks() const { return chunk_; }

 private:
  friend void allreduce(ExactSum* sums, int n);
  std::array<std::int64_t, kChunks> chunk_{};
  std::int64_t pending_ = 0;  // terms added since the last normalize()
  std::int64_t invalid_ = 0;
};

/// Adds up n sums over all ranks, in place, exactly (one integer MPI_Allreduce of n x (kChunks + 1) values).
void allreduce(ExactSum* sums, int n);

}  // namespace debris::comm
