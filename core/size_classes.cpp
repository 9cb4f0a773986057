#include "core/size_classes.hpp"

#include <algorithm>

namespace debris {

SizeClasses SizeClasses::of(const double* r, int n, int max_classes) {
  SizeClasses s;
  if (n <= 0) return s;
  const double r_min = *std::min_element(r, r + n), r_max = *std::max_element(r, r + n);
  const int cap = std::clamp(max_classes, 1, kMax);
  s.count = 1;
  s.lower[0] = r_min;
  // Bounds are powers of kRatio times r_min, so they do not depend on the storage order.
  double bound = r_min * kRatio;
  while (s.count < cap && r_max >= bound) {
    s.lower[s.count++] = bound;
    bound *= kRatio;
  }
  for (int i = 0; i < n; ++i) {
    const int c = s.classify(r[i]);
    ++s.members[c];
    s.r_max[c] = std::max(s.r_max[c], r[i]);
  }
  return s;
}

}  // namespace debris
