#include "core/comm/exact_sum.hpp"

#include <bit>
#include <cmath>
#include <limits>
#include <vector>

#include "core/comm/communicator.hpp"

namespace debris::comm {

ExactSum::ExactSum(const std::int64_t* words) {
  for (int k = 0; k < kExactWords; ++k) w_[k] = words[k];
  w_[kChunks] = w_[kChunks] != 0;
  normalize();  // the words' history is unknown: carry now
}

ExactSum& ExactSum::operator+=(const ExactSum& o) {
  ExactSum other = o;
  other.normalize();
  normalize();
  for (int c = 0; c < kChunks; ++c) w_[c] += other.w_[c];
  pending_ = 2;  // each digit now below 2^33: far from the limit
  w_[kChunks] = (w_[kChunks] | o.w_[kChunks]) != 0;
  return *this;
}

void ExactSum::normalize() {
  for (int c = 0; c + 1 < kChunks; ++c) {
    const std::int64_t carry = w_[c] >> 32;  // floor division by 2^32 (arithmetic shift)
    w_[c] -= carry * (std::int64_t{1} << 32);
    w_[c + 1] += carry;
  }
  pending_ = 0;
}

double ExactSum::value() const {
  if (!valid()) return std::numeric_limits<double>::quiet_NaN();
  ExactSum s = *this;
  s.normalize();
  double sign = 1.0;
  if (s.w_[kChunks - 1] < 0) {  // work with the magnitude: negate every digit, then carry again
    for (int c = 0; c < kChunks; ++c) s.w_[c] = -s.w_[c];
    s.normalize();
    sign = -1.0;
  }
  int h = kChunks - 1;
  while (h >= 0 && s.w_[h] == 0) --h;
  if (h < 0) return 0.0;
  // The top three digits (at least 65 significant bits, as the top one is not zero) left-aligned in 128 bits;
  // whatever lies below the 64 bits kept is folded into a sticky bit, so the one rounding of the conversion
  // to double is the correct rounding of the whole integer.
  const auto digit = [&](int c) { return c >= 0 ? static_cast<unsigned __int128>(s.w_[c]) : 0; };
  unsigned __int128 acc = (digit(h) << 64) | (digit(h - 1) << 32) | digit(h - 2);
  const auto hi = static_cast<std::uint64_t>(acc >> 64);
  const int lz = hi ? std::countl_zero(hi) : 64 + std::countl_zero(static_cast<std::uint64_t>(acc));
  acc <<= lz;
  auto top = static_cast<std::uint64_t>(acc >> 64);
  bool sticky = static_cast<std::uint64_t>(acc) != 0;
  for (int c = h - 3; c >= 0 && !sticky; --c) sticky = s.w_[c] != 0;
  if (sticky) top |= 1;
  const int exponent = 64 - lz + 32 * (h - 2) - kFractionBits;
  return sign * std::ldexp(static_cast<double>(top), exponent);
}

void allreduce(ExactSum* sums, int n) {
  if (comm::size() == 1 || n == 0) return;
  const int per = kExactWords;
  std::vector<std::int64_t> buffer(static_cast<std::size_t>(per) * static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    sums[i].normalize();  // digits below 2^32: P ranks' sum stays far from the int64 limit
    auto* row = buffer.data() + static_cast<std::size_t>(per) * static_cast<std::size_t>(i);
    for (int k = 0; k < per; ++k) row[k] = sums[i].w_[k];
  }
  allreduce_sum(buffer.data(), static_cast<int>(buffer.size()));
  for (int i = 0; i < n; ++i) sums[i] = ExactSum(buffer.data() + static_cast<std::size_t>(per) * static_cast<std::size_t>(i));
}

}  // namespace debris::comm
