// BM_ReferenceLoop: a fixed workload that does not depend on debris, used only as the yardstick of the
// performance-regression check (bench/perf_check.py divides a benchmark's items/s by this one's, measured
// in the same run, so that machine speed and load cancel out to first order).
//
// One item = one element of a STREAM-style triad a = b + s c over three 2 MiB arrays (6 MiB: past L2,
// inside L3, like the pass working sets) followed by one step of a scalar chain of sqrt and division
// (an in-order floating-point sum, which the compiler may not vectorise without -ffast-math). One thread,
// no OpenMP. Never change it without refreshing bench/perf_baseline.json (perf_check.py --update).
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstddef>
#include <vector>

namespace {

constexpr std::size_t kReferenceElements = std::size_t{1} << 18;  // 2 MiB per array of doubles

void BM_ReferenceLoop(benchmark::State& state) {
  static std::vector<double> a(kReferenceElements), b(kReferenceElements), c(kReferenceElements);
  for (std::size_t i = 0; i < kReferenceElements; ++i) {
    a[i] = 0.0;
    b[i] = 1.0 + 0.25 * static_cast<double>(i % 7);
    c[i] = 0.5 + 0.125 * static_cast<double>(i % 5);
  }
  const std::size_t n = kReferenceElements;
  double* pa = a.data();
  const double* pb = b.data();
  const double* pc = c.data();
  for (auto _ : state) {
    for (std::size_t i = 0; i < n; ++i) pa[i] = pb[i] + 1.5 * pc[i];
    double acc = 0.0;
    for (std::size_t i = 0; i < n; ++i) acc += std::sqrt(pa[i] * pa[i] + pb[i]) / (pc[i] + 2.0);
    benchmark::DoNotOptimize(acc);
    benchmark::ClobberMemory();  // a, b and c may have changed: the next iteration recomputes everything
  }
  state.SetItemsProcessed(state.iterations() * static_cast<long long>(n));
}

BENCHMARK(BM_ReferenceLoop)->UseRealTime()->Unit(benchmark::kMicrosecond);

}  // namespace
