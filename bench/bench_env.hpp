#pragma once
// Sizes from the environment for the benchmark suites: DEBRIS_BENCH_SIZES (bench_dem.cpp) and
// DEBRIS_PD_TILES (bench_peridem.cpp) replace their default lists, e.g. for bench/gpu_check.sh.
#include <cstdio>
#include <cstdlib>
#include <vector>

namespace debris {

/// The comma-separated whole numbers in $name, each in [lo, hi], or `fallback` when it is unset or empty.
/// Anything else stops the benchmark binary with exit 2, naming the variable, its value and `what`.
inline std::vector<int> env_int_list(const char* name, long lo, long hi, std::vector<int> fallback, const char* what) {
  const char* env = std::getenv(name);
  if (!env || !*env) return fallback;
  std::vector<int> values;
  for (const char* p = env; *p;) {
    char* end = nullptr;
    const long v = std::strtol(p, &end, 10);
    if (end == p || v < lo || v > hi || (*end != ',' && *end != '\0')) {
      std::fprintf(stderr, "%s = '%s': give %s (%ld to %ld) separated by commas\n", name, env, what, lo, hi);
      std::exit(2);
    }
    values.push_back(static_cast<int>(v));
    p = *end == ',' ? end + 1 : end;
  }
  return values;
}

}  // namespace debris
