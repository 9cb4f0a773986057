#include "core/rough/surface_envelope.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/box.hpp"

namespace debris {

namespace {

double comp(Vec3 v, int a) { return a == 0 ? v.x : (a == 1 ? v.y : v.z); }

// The fewest grid points whose spacing is at most `spacing` (a length that is a whole number of spacings up
// to round-off gets exactly that number).
int grid_points(double length, double spacing) {
  return std::max(1, static_cast<int>(std::ceil(length / spacing * (1 - 1e-12))));
}

// Grid indices [first, last] whose points lie within `reach` of coordinate c along an axis of n points of
// spacing h from `origin`; clipped to the grid on an axis that is not periodic (where there are no images).
void footprint(double c, double reach, double origin, double h, int n, bool periodic, long& first, long& last) {
  first = static_cast<long>(std::ceil((c - reach - origin) / h));
  last = static_cast<long>(std::floor((c + reach - origin) / h));
  if (!periodic) {
    first = std::max(first, 0L);
    last = std::min(last, static_cast<long>(n) - 1);
  }
}

int wrap(long i, int n) {
  long k = i % n;
  return static_cast<int>(k < 0 ? k + n : k);
}

}  // namespace

SurfaceEnvelope surface_envelope(const Box& box, int normal_axis, EnvelopeSide side, double spacing,
                                 std::span<const double> x, std::span<const double> y, std::span<const double> z,
                                 std::span<const double> radius, std::span<const std::size_t> selection) {
  if (!(spacing > 0.0) || !std::isfinite(spacing))
    throw std::invalid_argument("surface_envelope: the grid spacing must be > 0 (got " + std::to_string(spacing) + ")");
  if (normal_axis < 0 || normal_axis > 2) throw std::invalid_argument("surface_envelope: the normal axis must be 0, 1 or 2");
  if (selection.empty()) throw std::invalid_argument("surface_envelope: no sphere selected");
  if (y.size() != x.size() || z.size() != x.size() || radius.size() != x.size())
    throw std::invalid_argument("surface_envelope: x, y, z and radius differ in length");

  SurfaceEnvelope out;
  HeightField& f = out.field;
  f.normal_axis = normal_axis;
  const int a = f.axis_a(), b = f.axis_b();
  f.origin_a = comp(box.lo(), a);
  f.origin_b = comp(box.lo(), b);
  f.length_a = box.length(a);
  f.length_b = box.length(b);
  const double na = std::ceil(f.length_a / spacing), nb = std::ceil(f.length_b / spacing);
  if (na * nb > 1e9) throw std::invalid_argument("surface_envelope: the grid spacing makes more than 1e9 grid points");
  f.n_a = grid_points(f.length_a, spacing);
  f.n_b = grid_points(f.length_b, spacing);
  const double ha = f.spacing_a(), hb = f.spacing_b();
  const bool per_a = box.periodic(a), per_b = box.periodic(b);

  // Work in "outward" heights: s * normal coordinate, s = +1 for the top, -1 for the bottom, so both sides
  // take the maximum of centre + cap.
  const double s = side == EnvelopeSide::top ? 1.0 : -1.0;
  constexpr double kNone = -std::numeric_limits<double>::infinity();
  std::vector<double> best(static_cast<std::size_t>(f.n_a) * f.n_b, kNone);
  const std::span<const double> coords[3] = {x, y, z};
  for (std::size_t k : selection) {
    if (k >= x.size())
      throw std::invalid_argument("surface_envelope: selected index " + std::to_string(k) + " of " +
                                  std::to_string(x.size()) + " spheres");
    const double pa = coords[a][k], pb = coords[b][k], pn = s * coords[normal_axis][k], r = radius[k];
    long i0, i1, j0, j1;
    footprint(pa, r, f.origin_a, ha, f.n_a, per_a, i0, i1);
    footprint(pb, r, f.origin_b, hb, f.n_b, per_b, j0, j1);
    for (long i = i0; i <= i1; ++i) {
      const double da = f.origin_a + static_cast<double>(i) * ha - pa;
      const double rem = r * r - da * da;
      if (rem < 0) continue;
      double* row = best.data() + static_cast<std::size_t>(wrap(i, f.n_a)) * f.n_b;
      for (long j = j0; j <= j1; ++j) {
        const double db = f.origin_b + static_cast<double>(j) * hb - pb;
        const double cap2 = rem - db * db;
        if (cap2 < 0) continue;
        double& v = row[wrap(j, f.n_b)];
        v = std::max(v, pn + std::sqrt(cap2));
      }
    }
  }

  // Uncovered points: the mean of their filled 4-neighbours, pass by pass from the previous pass's values.
  for (double v : best) out.filled_points += v == kNone ? 1 : 0;
  if (out.filled_points == static_cast<long>(best.size()))
    throw std::invalid_argument("surface_envelope: no selected sphere lies over the grid");
  long left = out.filled_points;
  std::vector<double> next;
  while (left > 0) {
    next = best;
    for (int i = 0; i < f.n_a; ++i)
      for (int j = 0; j < f.n_b; ++j) {
        const std::size_t at = static_cast<std::size_t>(i) * f.n_b + j;
        if (best[at] != kNone) continue;
        double sum = 0;
        int count = 0;
        auto take = [&](long ii, long jj, bool periodic_a, bool periodic_b) {
          if (!periodic_a && (ii < 0 || ii >= f.n_a)) return;
          if (!periodic_b && (jj < 0 || jj >= f.n_b)) return;
          const double v = best[static_cast<std::size_t>(wrap(ii, f.n_a)) * f.n_b + wrap(jj, f.n_b)];
          if (v == kNone) return;
          sum += v;
          ++count;
        };
        if (f.n_a > 1) take(i - 1, j, per_a, true), take(i + 1, j, per_a, true);
        if (f.n_b > 1) take(i, j - 1, true, per_b), take(i, j + 1, true, per_b);
        if (count > 0) next[at] = sum / count, --left;
      }
    best.swap(next);
  }

  f.h.resize(best.size());
  for (std::size_t k = 0; k < best.size(); ++k) f.h[k] = s * best[k];
  return out;
}

SurfaceEnvelope surface_envelope(const Box& box, int normal_axis, EnvelopeSide side, double spacing,
                                 std::span<const double> x, std::span<const double> y, std::span<const double> z,
                                 std::span<const double> radius, std::span<const char> mask) {
  if (mask.size() != x.size()) throw std::invalid_argument("surface_envelope: the mask differs in length from x");
  std::vector<std::size_t> selection;
  for (std::size_t k = 0; k < mask.size(); ++k)
    if (mask[k]) selection.push_back(k);
  return surface_envelope(box, normal_axis, side, spacing, x, y, z, radius, selection);
}

}  // namespace debris
