// comm::ExactSum: the same bits in any order and on any rank count, and the correctly rounded exact sum.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "core/comm/communicator.hpp"
#include "core/comm/exact_sum.hpp"

namespace debris::comm {
namespace {

std::uint64_t bits(double v) { return std::bit_cast<std::uint64_t>(v); }

double sum_of(const std::vector<double>& terms) {
  ExactSum s;
  for (const double t : terms) s.add(t);
  return s.value();
}

// Terms over 40 decades (1e-25 to 1e15), both signs: where a plain double sum depends on the order.
std::vector<double> wide_terms(std::size_t n, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> mantissa(1.0, 10.0), decade(-25.0, 15.0);
  std::vector<double> t(n);
  for (auto& v : t) v = (rng() & 1 ? -1.0 : 1.0) * mantissa(rng) * std::pow(10.0, std::floor(decade(rng)));
  return t;
}

TEST(ExactSum, CancellationAPlainSumLoses) {
  // 1e16 + 1 - 1e16 is 0 in doubles added left to right; the exact sum is 1.
  EXPECT_EQ(sum_of({1e16, 1.0, -1e16}), 1.0);
  EXPECT_EQ(sum_of({1e-20, 1e20, -1e20}), 1e-20);
  EXPECT_EQ(sum_of({}), 0.0);
  EXPECT_EQ(sum_of({2.5, -2.5}), 0.0);
  EXPECT_EQ(sum_of({-0.75, 0.25}), -0.5);
}

TEST(ExactSum, IsTheCorrectlyRoundedExactSum) {
  // Terms m 2^-100 with m up to 2^50: their exact sum is an integer times 2^-100 that __int128 holds, and
  // its correctly rounded double is the integer's conversion (round to nearest even), scaled.
  std::mt19937_64 rng(7);
  for (int trial = 0; trial < 200; ++trial) {
    ExactSum s;
    __int128 exact = 0;
    const int n = 1 + static_cast<int>(rng() % 5000);
    for (int k = 0; k < n; ++k) {
      const auto m = static_cast<std::int64_t>(rng() >> 14) * (rng() & 1 ? -1 : 1);
      s.add(std::ldexp(static_cast<double>(m), -100));
      exact += m;
    }
    ASSERT_EQ(bits(s.value()), bits(std::ldexp(static_cast<double>(exact), -100))) << "trial " << trial;
  }
  // Ten times 0.1 (the double nearest 0.1 is slightly above it): exactly 1.0000000000000000555..., which
  // rounds to 1.0; a running double sum gives 0.9999999999999999.
  EXPECT_EQ(sum_of(std::vector<double>(10, 0.1)), 1.0);
  // A tie between two doubles is broken to even: 1 + 2^-53 lies halfway between 1 and 1 + 2^-52.
  EXPECT_EQ(sum_of({1.0, std::ldexp(1.0, -53)}), 1.0);
  EXPECT_EQ(sum_of({1.0, std::ldexp(1.0, -53), std::ldexp(1.0, -150)}), 1.0 + std::ldexp(1.0, -52));
}

TEST(ExactSum, SameBitsInAnyOrderAndAnyGrouping) {
  auto t = wide_terms(20000, 11);
  const double forward = sum_of(t);
  std::reverse(t.begin(), t.end());
  EXPECT_EQ(bits(sum_of(t)), bits(forward));
  std::mt19937 rng(3);
  std::shuffle(t.begin(), t.end(), rng);
  EXPECT_EQ(bits(sum_of(t)), bits(forward));
  // Split into uneven parts added up separately, then merged: as threads or ranks would.
  for (const std::size_t parts : {2u, 3u, 7u, 64u}) {
    std::vector<ExactSum> part(parts);
    for (std::size_t k = 0; k < t.size(); ++k) part[(k * k + 5 * k) % parts].add(t[k]);
    ExactSum total;
    for (const auto& p : part) total += p;
    EXPECT_EQ(bits(total.value()), bits(forward)) << parts << " parts";
  }
}

TEST(ExactSum, NonFiniteOrHugeTermMakesTheSumInvalid) {
  ExactSum s;
  s.add(1.0);
  s.add(std::numeric_limits<double>::quiet_NaN());
  EXPECT_FALSE(s.valid());
  EXPECT_TRUE(std::isnan(s.value()));
  ExactSum h;
  h.add(1e31);  // above the largest term, 2^100
  EXPECT_TRUE(std::isnan(h.value()));
  ExactSum ok;
  ok.add(1e29);
  ok.add(1e29);
  EXPECT_EQ(ok.value(), 2e29);
}

TEST(ExactSum, TermsBelowTheGridRoundByThemselves) {
  // The grid is 2^-180: a term of 2^-182 rounds to 0 and one of 3 x 2^-182 to 2^-180, in any company.
  EXPECT_EQ(sum_of({std::ldexp(1.0, -182)}), 0.0);
  EXPECT_EQ(sum_of({std::ldexp(3.0, -182)}), std::ldexp(1.0, -180));
  EXPECT_EQ(sum_of({std::ldexp(3.0, -182), -std::ldexp(3.0, -182)}), 0.0);
  // A particle mass of this field keeps every bit: 1.3e-24 kg.
  EXPECT_EQ(bits(sum_of({1.3e-24})), bits(1.3e-24));
  EXPECT_EQ(bits(sum_of({4.9e-324, 1.0})), bits(1.0));  // a subnormal is far below the grid
}

TEST(ExactSum, AllRanksGetTheSerialBits) {
  // Every rank knows all 30,000 terms; each adds up a share that depends on the rank count, for three
  // quantities at once, and the allreduce gives every rank the bits of the one-process sum.
  const auto t = wide_terms(30000, 5);
  const int r = rank(), n = size();
  ExactSum s[3];
  for (std::size_t k = 0; k < t.size(); ++k) {
    if (static_cast<int>((k * 7) % static_cast<std::size_t>(n)) != r) continue;
    s[0].add(t[k]);
    s[1].add(t[k] * t[k]);
    s[2].add(-2.0 * t[k]);
  }
  allreduce(s, 3);
  ExactSum whole[3];
  for (const double v : t) {
    whole[0].add(v);
    whole[1].add(v * v);
    whole[2].add(-2.0 * v);
  }
  for (int q = 0; q < 3; ++q) EXPECT_EQ(bits(s[q].value()), bits(whole[q].value())) << "quantity " << q;
  // An invalid term on one rank makes the sum invalid on all.
  ExactSum bad;
  bad.add(r == n - 1 ? std::numeric_limits<double>::infinity() : 1.0);
  allreduce(&bad, 1);
  EXPECT_FALSE(bad.valid());
}

}  // namespace
}  // namespace debris::comm
