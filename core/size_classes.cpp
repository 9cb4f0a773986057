#include "core/size_classes.hpp"

#include <algorithm>
#include <cmath>

namespace debris {

namespace {
// The class bounds from the extreme radii: powers of kRatio times r_min, so they do not depend on the
// storage order (nor on where the extremes were found).
SizeClasses bounded(double r_min, double r_max, int max_classes) {
  SizeClasses s;
  const int cap = std::clamp(max_classes, 1, SizeClasses::kMax);
  s.count = 1;
  s.lower[0] = r_min;
  double bound = r_min * SizeClasses::kRatio;
  while (s.count < cap && r_max >= bound) {
    s.lower[s.count++] = bound;
    bound *= SizeClasses::kRatio;
  }
  return s;
}
}  // namespace

SizeClasses SizeClasses::of(const double* r, int n, int max_classes) {
  if (n <= 0) return SizeClasses{};
  SizeClasses s = bounded(*std::min_element(r, r + n), *std::max_element(r, r + n), max_classes);
  for (int i = 0; i < n; ++i) {
    const int c = s.classify(r[i]);
    ++s.members[c];
    s.r_max[c] = std::max(s.r_max[c], r[i]);
  }
  return s;
}

SizeClasses SizeClasses::of_resident(const double* r, int n, int max_classes) {
  if (n <= 0) return SizeClasses{};
  double r_min = HUGE_VAL, r_max = 0.0;
  DEBRIS_RESIDENT(r);
  DEBRIS_KERNEL_MIN(r_min)
  for (int i = 0; i < n; ++i) r_min = r[i] < r_min ? r[i] : r_min;
  DEBRIS_KERNEL_MAX(r_max)
  for (int i = 0; i < n; ++i) r_max = r[i] > r_max ? r[i] : r_max;
  SizeClasses s = bounded(r_min, r_max, max_classes);
  if (s.count == 1) {  // one class holds everything: no further pass
    s.members[0] = n;
    s.r_max[0] = r_max;
    return s;
  }
  // Class c holds lower[c] <= r < lower[c + 1] (classify()): its count and its largest radius.
  for (int c = 0; c < s.count; ++c) {
    const double lo = s.lower[c], hi = c + 1 < s.count ? s.lower[c + 1] : HUGE_VAL;
    int members = 0;
    double top = 0.0;
    DEBRIS_KERNEL_SUM(members)
    for (int i = 0; i < n; ++i) members += r[i] >= lo && r[i] < hi ? 1 : 0;
    DEBRIS_KERNEL_MAX(top)
    for (int i = 0; i < n; ++i) top = r[i] >= lo && r[i] < hi && r[i] > top ? r[i] : top;
    s.members[c] = members;
    s.r_max[c] = top;
  }
  return s;
}

}  // namespace debris
