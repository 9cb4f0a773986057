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
#include <cstdint>

#include "core/comm/exact_sum.hpp"
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

/// Per-block partial sums that are exact: each block adds its terms into accumulators of its own
/// (comm::exact_add, comm::kExactWords int64 each, zeroed by the block first), and the host adds the
/// blocks' accumulators as integers and rounds once. The result is the correctly rounded sum of the terms,
/// the same bits for any thread count, device, block size, storage order and (summed over ranks with
/// comm::allreduce) rank count: what the sums that feed back into the dynamics (group reactions, the
/// stress that drives the box) and the thermo table use, since a rank holds its particles in an order of
/// its own (shared/design/scale-mpi.md, section 4).
///
///   std::int64_t* part = partials.reserve(K * blocks);   // accumulators
///   DEBRIS_KERNEL
///   for (int b = 0; b < blocks; ++b) {
///     std::int64_t* acc = part + K * kExactWords * b;
///     exact_zero(acc, K);
///     for (i in block b) { comm::exact_add(acc, e_i); comm::exact_add(acc + kExactWords, q_i); }
///   }
///   partials.to_host(K * blocks);
///   const auto total = partials.add_up<K>(blocks);
class ExactPartials {
 public:
  ExactPartials() = default;
  ExactPartials(const ExactPartials&) {}
  ExactPartials& operator=(const ExactPartials&) { return *this; }
  ExactPartials(ExactPartials&&) noexcept = default;
  ExactPartials& operator=(ExactPartials&&) noexcept = default;

  /// Room for at least n accumulators (n x comm::kExactWords int64), on the device in offload builds.
  std::int64_t* reserve(std::size_t n);
  /// Transfer point: device -> host of the first n accumulators after a kernel filled them.
  void to_host(std::size_t n) const;
  /// The sums of K quantities over the blocks ([block][K] accumulators), each correctly rounded.
  template <int K>
  std::array<double, K> add_up(int blocks) const {
    std::array<double, K> t{};
    add_up(blocks, K, t.data());
    return t;
  }
  void add_up(int blocks, int k, double* out) const;
  /// The same, summed over all ranks of the run first when `across_ranks` (comm::allreduce): a distributed
  /// run's global sums, correctly rounded once.
  void add_up(int blocks, int k, double* out, bool across_ranks) const;
  /// The same, kept exact (to add other ranks' sums before rounding: comm::allreduce).
  void add_up(int blocks, int k, comm::ExactSum* out) const;

 private:
  void add_up_one(int blocks, int k, int q, comm::ExactSum& sum) const;
  exec::DeviceVector<std::int64_t> v_;
};

/// Which stored particles a sum counts, and whether it adds every rank's sum. A run on one process counts
/// every particle it stores (the default); a run cut among ranks (core/comm) stores its own particles and
/// copies of its neighbours' (ghosts) side by side, counts its own (owned[i] != 0) and adds the ranks' exact
/// sums, so every rank gets the whole system's sum, the same bits as one process.
struct SumScope {
  const unsigned char* owned = nullptr;  // per stored particle, nullptr: all (host array, or resident)
  bool across_ranks = false;
};

DEBRIS_DECLARE_TARGET
/// Zeroes k accumulators (k x comm::kExactWords int64). Runs in kernels.
inline void exact_zero(std::int64_t* acc, int k) {
  for (int i = 0; i < k * comm::kExactWords; ++i) acc[i] = 0;
}
DEBRIS_END_DECLARE_TARGET

}  // namespace debris
