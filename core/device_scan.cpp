#include "core/device_scan.hpp"

#include <algorithm>

namespace debris {

long long inclusive_scan(int* a, int m, [[maybe_unused]] exec::DeviceVector<long long>& block_sums) {
  if (m <= 0) return 0;
#if defined(DEBRIS_OFFLOAD_TARGET)
  constexpr int kBlock = 2048;
  const int nb = (m + kBlock - 1) / kBlock;
  block_sums.resize(static_cast<std::size_t>(nb));
  long long* __restrict bs = block_sums.data();
  int* __restrict v = a;
  DEBRIS_RESIDENT(v, bs);
  DEBRIS_KERNEL
  for (int b = 0; b < nb; ++b) {
    const int end = b * kBlock + kBlock < m ? b * kBlock + kBlock : m;
    long long s = 0;
    for (int i = b * kBlock; i < end; ++i) s += v[i];
    bs[b] = s;
  }
  long long total = 0;
  // The block sums' own scan: a few hundred numbers for millions of entries, one device thread.
  DEBRIS_PRAGMA(omp target map(tofrom : total))
  {
    long long run = 0;
    for (int b = 0; b < nb; ++b) {
      const long long s = bs[b];
      bs[b] = run;
      run += s;
    }
    total = run;
  }
  DEBRIS_KERNEL
  for (int b = 0; b < nb; ++b) {
    const int end = b * kBlock + kBlock < m ? b * kBlock + kBlock : m;
    long long run = bs[b];
    for (int i = b * kBlock; i < end; ++i) {
      run += v[i];
      v[i] = static_cast<int>(run);
    }
  }
  return total;
#else
  long long run = 0;
  for (int i = 0; i < m; ++i) {
    run += a[i];
    a[i] = static_cast<int>(run);
  }
  return run;
#endif
}

}  // namespace debris
