#include "core/device_counting_sort.hpp"

#include "core/device_scan.hpp"

namespace debris {

long long counting_sort_by_bucket(const int* bucket_of, int items, int buckets, int* start, int* cursor, int* sorted,
                                  exec::DeviceVector<long long>& block_sums) {
  const int* __restrict b = bucket_of;
  int* __restrict first = start;
  int* __restrict fill = cursor;
  int* __restrict out = sorted;
  // Counts (atomic adds: they do not depend on their order), then their prefix sum.
  DEBRIS_RESIDENT(b, first);
  DEBRIS_KERNEL
  for (int c = 0; c <= buckets; ++c) first[c] = 0;
  DEBRIS_KERNEL
  for (int i = 0; i < items; ++i) {
    if (b[i] >= 0) {
      DEBRIS_PRAGMA(omp atomic update)
      ++first[b[i] + 1];
    }
  }
  const long long total = inclusive_scan(first + 1, buckets, block_sums);
  // Fill through atomic cursors (any order within a bucket), then each bucket sorted ascending.
  DEBRIS_RESIDENT(b, first, fill, out);
  DEBRIS_KERNEL
  for (int c = 0; c < buckets; ++c) fill[c] = first[c];
  DEBRIS_KERNEL
  for (int i = 0; i < items; ++i) {
    if (b[i] >= 0) {
      int at;
      DEBRIS_PRAGMA(omp atomic capture)
      at = fill[b[i]]++;
      out[at] = i;
    }
  }
  DEBRIS_KERNEL
  for (int c = 0; c < buckets; ++c)
    for (int k = first[c] + 1; k < first[c + 1]; ++k) {
      const int v = out[k];
      int h = k;
      for (; h > first[c] && out[h - 1] > v; --h) out[h] = out[h - 1];
      out[h] = v;
    }
  return total;
}

}  // namespace debris
