#pragma once
// Sums over particles or nodes that give the same bits on any thread count or device (shared/DESIGN.md:
// sums that feed back into the dynamics, and the thermo table, are summed in fixed blocks). The items are
// cut into blocks of kSumBlock in index order; one kernel iteration sums one block in index order into its
// own slot of a BlockPartials buffer, whichever thread (or device team) runs it; the host then adds the
// blocks' sums in block order. Group reactions (core/groups), the thermo energies and the virial stress use
// it; nothing else in debris sums in fixed blocks.
//
// A kernel using it reads, per block b, the items [r.begin, r.end) of r = block_range(b, n):
//
//   const int blocks = sum_blocks(n);
//   double* part = partials.reserve(2 * static_cast<std::size_t>(blocks));
//   DEBRIS_RESIDENT(part, ...);
//   DEBRIS_KERNEL
//   for (int b = 0; b < blocks; ++b) {
//     const BlockRange r = block_range(b, n);
//     for (int i = r.begin; i < r.end; ++i) ...
//     part[2 * b] = e; part[2 * b + 1] = q;
//   }
//   partials.to_host(2 * blocks);
//   const auto total = partials.add_up<2>(blocks);
//
// Offload builds: the partials live on the device (an exec::DeviceVector, entered for exactly the life of
// its buffer), the kernel writes them there, and to_host is the one transfer of a sum (named and counted
// like every other, core/exec.hpp).
#include <array>
#include <cstddef>

#include "core/exec.hpp"

namespace debris {

/// Items per summation block: a constant, so that the sums do not depend on the thread count.
constexpr int kSumBlock = 2048;

/// Blocks of `block` items (kSumBlock unless a caller keeps an older block size) for n items.
constexpr int sum_blocks(int n, int block = kSumBlock) { return (n + block - 1) / block; }

/// The items of one block: [begin, end).
struct BlockRange {
  int begin, end;
};

DEBRIS_DECLARE_TARGET
/// Block b of n items cut into blocks of `block`: [b * block, min(n, (b + 1) * block)). Runs in kernels.
constexpr BlockRange block_range(int b, int n, int block = kSumBlock) {
  const int begin = b * block;
  return {begin, n - begin < block ? n : begin + block};
}
DEBRIS_END_DECLARE_TARGET

/// The per-block partial sums of a fixed-order sum: a buffer of doubles, device-resident in offload builds
/// (exec::DeviceVector). Derived data: a copy starts empty; a move takes the buffer and its device entry
/// along.
class BlockPartials {
 public:
  BlockPartials() = default;
  BlockPartials(const BlockPartials&) {}
  BlockPartials& operator=(const BlockPartials&) { return *this; }
  BlockPartials(BlockPartials&&) noexcept = default;
  BlockPartials& operator=(BlockPartials&&) noexcept = default;

  /// At least n doubles, on the device in offload builds; allocates only when n grows.
  double* reserve(std::size_t n);
  /// Transfer point: device -> host of the first n doubles after a kernel filled them.
  void to_host(std::size_t n) const;
  /// Block sums of K quantities, [block][K], each added up in block order (after to_host).
  template <int K>
  std::array<double, K> add_up(int blocks) const {
    std::array<double, K> t{};
    add_up(blocks, K, t.data());
    return t;
  }
  /// The same with k quantities per block known at run time (the groups' k = 3 x groups): out[0, k).
  void add_up(int blocks, int k, double* out) const;

 private:
  exec::DeviceVector<double> v_;
};

}  // namespace debris
