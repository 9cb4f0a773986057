#pragma once
// Prefix sums of an int array where it lives: on the device in offload builds, so that a list build moves
// one scalar, not the array, between host and device. The sums are exact integer sums, so the
// result is the same on any device, block size or thread count as the serial loop of host builds.
#include "core/exec.hpp"

namespace debris {

/// Replaces a[0..m) by its inclusive prefix sums and returns the total, as a long long so that a caller can
/// refuse a total past INT_MAX (the entries are then wrapped ints). Host builds: one serial loop. Offload
/// builds: a must be on the device; three kernels (each block's sum, a one-thread scan of the block sums,
/// each block's own scan from its start) and the total back; `block_sums` is their scratch.
long long inclusive_scan(int* a, int m, exec::DeviceVector<long long>& block_sums);

}  // namespace debris
