#include "core/rough/height_field.hpp"

#include <cmath>

namespace debris {

namespace {

double component(Vec3 v, int a) { return a == 0 ? v.x : (a == 1 ? v.y : v.z); }

// Grid index and fraction of coordinate c on a periodic axis of n points over [origin, origin + length).
void locate(double c, double origin, double length, int n, int& i0, int& i1, double& t) {
  const double s = (c - origin) / length * n;
  const double f = std::floor(s);
  t = s - f;
  long k = static_cast<long>(f) % n;
  if (k < 0) k += n;
  i0 = static_cast<int>(k);
  i1 = i0 + 1 == n ? 0 : i0 + 1;
}

}  // namespace

double HeightField::height(double a, double b) const {
  int i0, i1;
  double ta;
  locate(a, origin_a, length_a, n_a, i0, i1, ta);
  if (n_b == 1) return (1 - ta) * at(i0, 0) + ta * at(i1, 0);
  int j0, j1;
  double tb;
  locate(b, origin_b, length_b, n_b, j0, j1, tb);
  return (1 - ta) * ((1 - tb) * at(i0, j0) + tb * at(i0, j1)) + ta * ((1 - tb) * at(i1, j0) + tb * at(i1, j1));
}

double HeightField::height_under(Vec3 p) const { return height(component(p, axis_a()), component(p, axis_b())); }

double HeightField::mean() const {
  double s = 0;
  for (double v : h) s += v;
  return h.empty() ? 0 : s / static_cast<double>(h.size());
}

double HeightField::rms_height() const {
  if (h.empty()) return 0;
  const double m = mean();
  double s = 0;
  for (double v : h) s += (v - m) * (v - m);
  return std::sqrt(s / static_cast<double>(h.size()));
}

double HeightField::rms_slope() const {
  if (h.empty()) return 0;
  const double da = spacing_a(), db = n_b > 1 ? spacing_b() : 0;
  double s = 0;
  for (int i = 0; i < n_a; ++i) {
    const int ip = (i + 1) % n_a, im = (i + n_a - 1) % n_a;
    for (int j = 0; j < n_b; ++j) {
      const double ga = (at(ip, j) - at(im, j)) / (2 * da);
      double gb = 0;
      if (n_b > 1) gb = (at(i, (j + 1) % n_b) - at(i, (j + n_b - 1) % n_b)) / (2 * db);
      s += ga * ga + gb * gb;
    }
  }
  return std::sqrt(s / static_cast<double>(h.size()));
}

}  // namespace debris
