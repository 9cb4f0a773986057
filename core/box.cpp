#include "core/box.hpp"

#include "core/exec.hpp"

#include <cmath>
#include <sstream>

#include "core/error.hpp"
#include "core/particles.hpp"

namespace debris {

namespace {
double comp(Vec3 v, int a) { return a == 0 ? v.x : (a == 1 ? v.y : v.z); }

DEBRIS_DECLARE_TARGET
// One coordinate of a periodic axis folded into [lo, lo + len), its image count moved with it: what
// Box::wrap does on the host and Box::wrap_resident in a kernel.
inline void fold_into_box(double& x, int& image, double lo, double len) {
  const double shift = std::floor((x - lo) / len);
  if (shift != 0.0) {
    x -= shift * len;
    image += static_cast<int>(shift);
    // Round-off can leave x == hi exactly; fold it once more.
    if (x >= lo + len) {
      x -= len;
      image += 1;
    }
  }
}
DEBRIS_END_DECLARE_TARGET
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
    for (int i = 0; i < n; ++i) fold_into_box(x[i], im[i], lo, len);
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
    for (int i = 0; i < n; ++i) fold_into_box(x[i], im[i], lo, len);
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
