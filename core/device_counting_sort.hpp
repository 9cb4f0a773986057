#pragma once
// A counting sort by bucket where the items are: on the device in offload builds, so that sorting moves one
// scalar (the scan's total) between host and device. Each bucket lists its items in increasing index, the
// serial counting sort's result, whatever the order the atomic fill took (each bucket is then
// insertion-sorted: buckets hold a handful of items).
#include "core/exec.hpp"

namespace debris {

/// Items 0..items-1 with bucket_of[i] in [0, buckets), or < 0 for an item that goes in no bucket. Writes
/// start[0..buckets] (bucket b's items are sorted[start[b] .. start[b+1])) and sorted; cursor (buckets ints)
/// and block_sums are scratch. All arrays where the kernels run (on the device in offload builds). Returns
/// the items sorted (start[buckets]).
long long counting_sort_by_bucket(const int* bucket_of, int items, int buckets, int* start, int* cursor, int* sorted,
                                  exec::DeviceVector<long long>& block_sums);

}  // namespace debris
