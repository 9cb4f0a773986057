#pragma once
// Sums over particles or nodes that give the same bits on any thread count (shared/DESIGN.md: sums that
// feed back into the dynamics, and the thermo table, are summed in fixed blocks). The items are cut into
// blocks of kSumBlock in index order; one kernel iteration sums one block in index order into its own
// slot of a BlockPartials buffer, whichever thread (or device team) runs it; the host then adds the
// blocks' sums in block order. Group reactions (core/groups) and the thermo energies use it.
//
// A kernel using it reads, per block b, items [b * kSumBlock, min(n, (b + 1) * kSumBlock)):
//
//   const int blocks = sum_blocks(n);
//   double* part = partials.reserve(2 * static_cast<std::size_t>(blocks));
//   DEBRIS_KERNEL
//   for (int b = 0; b < blocks; ++b) { ... part[2 * b] = e; part[2 * b + 1] = q; }
//   partials.to_host(2 * blocks);
//   const auto total = partials.add_up<2>(blocks);
#include <array>
#include <cstddef>
#include <vector>

namespace debris {

/// Items per summation block: a constant, so that the sums do not depend on the thread count.
constexpr int kSumBlock = 2048;

/// Blocks of kSumBlock for n items.
inline int sum_blocks(int n) { return (n + kSumBlock - 1) / kSumBlock; }

/// The per-block partial sums of a fixed-order sum: a buffer of doubles, entered on the device in offload
/// builds when it grows and released when freed. Derived data: a copy starts empty, a move takes the buffer
/// and its device entry along.
class BlockPartials {
 public:
  BlockPartials() = default;
  BlockPartials(const BlockPartials&) {}
  BlockPartials& operator=(const BlockPartials&) { return *this; }
  BlockPartials(BlockPartials&& o) noexcept { v_.swap(o.v_); }
  BlockPartials& operator=(BlockPartials&& o) noexcept;
  ~BlockPartials() { release(); }

  /// At least n doubles, entered on the device; allocates only when n grows.
  double* reserve(std::size_t n);
  /// Device -> host of the first n doubles after a kernel filled them.
  void to_host(std::size_t n);
  /// Block sums of K quantities, [block][K], added up in block order (after to_host).
  template <int K>
  std::array<double, K> add_up(int blocks) const {
    std::array<double, K> t{};
    for (int b = 0; b < blocks; ++b)
      for (int q = 0; q < K; ++q) t[static_cast<std::size_t>(q)] += v_[static_cast<std::size_t>(K * b + q)];
    return t;
  }

 private:
  void release();
  std::vector<double> v_;
};

}  // namespace debris
