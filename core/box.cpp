#include "core/box.hpp"

#include "core/exec.hpp"

#include <sstream>

#include "core/error.hpp"
#include "core/particles.hpp"

namespace debris {

namespace {
double comp(Vec3 v, int a) { return a == 0 ? v.x : (a == 1 ? v.y : v.z); }
}  // namespace

Box::Box(Vec3 lo, Vec3 hi, std::array<bool, 3> periodic) : lo_(lo), hi_(hi), periodic_(periodic) {
  for (int a = 0; a < 3; ++a) {
    if (!(comp(hi, a) > comp(lo, a)) || !std::isfinite(comp(hi, a) - comp(lo, a))) {
      std::ostringstream v;
      v << "[" << comp(lo, a) << ", " << comp(hi, a) << "]";
      throw input_error(std::string("box.") + "xyz"[a], v.str(), "hi must be larger than lo");
    }
  }
}

double Box::length(int axis) const { return comp(hi_, axis) - comp(lo_, axis); }

double Box::volume() const { return length(0) * length(1) * length(2); }

BoxView Box::view() const {
  BoxView v{};
  for (int a = 0; a < 3; ++a) {
    v.lo[a] = comp(lo_, a);
    v.len[a] = length(a);
    v.periodic[a] = periodic_[a] ? 1 : 0;
  }
  return v;
}

void Box::wrap(Particles& p) const {
  const BoxView b = view();
  double* pos[3] = {p.x.data(), p.y.data(), p.z.data()};
  int* img[3] = {p.ix.data(), p.iy.data(), p.iz.data()};
  const int n = static_cast<int>(p.size());
  for (int a = 0; a < 3; ++a) {
    if (!b.periodic[a]) continue;
    double* x = pos[a];
    int* im = img[a];
    const double lo = b.lo[a], len = b.len[a];
    for (int i = 0; i < n; ++i) {
      const double shift = std::floor((x[i] - lo) / len);
      if (shift != 0.0) {
        x[i] -= shift * len;
        im[i] += static_cast<int>(shift);
        // Round-off can leave x == hi exactly; fold it once more.
        if (x[i] >= lo + len) {
          x[i] -= len;
          im[i] += 1;
        }
      }
    }
  }
}

void Box::wrap_resident(Particles& p) const {
#if defined(DEBRIS_OFFLOAD_TARGET)
  const BoxView b = view();
  double* pos[3] = {p.x.data(), p.y.data(), p.z.data()};
  int* img[3] = {p.ix.data(), p.iy.data(), p.iz.data()};
  const int n = static_cast<int>(p.size());
  for (int a = 0; a < 3; ++a) {
    if (!b.periodic[a]) continue;
    double* x = pos[a];
    int* im = img[a];
    const double lo = b.lo[a], len = b.len[a];
    DEBRIS_RESIDENT(x, im);
    DEBRIS_KERNEL
    for (int i = 0; i < n; ++i) {
      const double shift = std::floor((x[i] - lo) / len);
      if (shift != 0.0) {
        x[i] -= shift * len;
        im[i] += static_cast<int>(shift);
        if (x[i] >= lo + len) {
          x[i] -= len;
          im[i] += 1;
        }
      }
    }
  }
#else
  wrap(p);
#endif
}

void Box::deform(Vec3 new_lo, Vec3 new_hi, Particles& p) {
  const Box next(new_lo, new_hi, periodic_);
  double* pos[3] = {p.x.data(), p.y.data(), p.z.data()};
  const int n = static_cast<int>(p.size());
  for (int a = 0; a < 3; ++a) {
    const double lo0 = comp(lo_, a), lo1 = comp(new_lo, a);
    const double scale = next.length(a) / length(a);
    if (scale == 1.0 && lo0 == lo1) continue;
    double* x = pos[a];
    for (int i = 0; i < n; ++i) x[i] = lo1 + (x[i] - lo0) * scale;
  }
  *this = next;
}

}  // namespace debris
