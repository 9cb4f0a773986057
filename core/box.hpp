#pragma once
// The simulation domain: an orthogonal box [lo, hi), periodic or not per axis, with the
// minimum-image convention and affine deformation (the amorphous relaxation moves periodic walls).
#include <array>
#include <cmath>

#include "core/vec3.hpp"

namespace debris {

/// Plain view of the box for kernels (copied by value into a target region).
struct BoxView {
  double lo[3];
  double len[3];
  int periodic[3];
};

/// Minimum image of a separation vector: kernels call this for every pair.
inline Vec3 minimum_image(const BoxView& b, Vec3 d) {
  if (b.periodic[0]) d.x -= b.len[0] * std::floor(d.x / b.len[0] + 0.5);
  if (b.periodic[1]) d.y -= b.len[1] * std::floor(d.y / b.len[1] + 0.5);
  if (b.periodic[2]) d.z -= b.len[2] * std::floor(d.z / b.len[2] + 0.5);
  return d;
}

/// Minimum image for separations shorter than 1.5 box lengths, without floor(): what the neighbour list
/// guarantees between rebuilds (positions wrapped at the rebuild, drift < skin/2, box >= 2 cutoffs).
/// Branch-free, so pair loops vectorise.
inline double nearest_image(double d, double len, int periodic) {
  const double half = 0.5 * len;
  const double shift = static_cast<double>(d > half) - static_cast<double>(d < -half);
  return periodic ? d - shift * len : d;
}

class Particles;

class Box {
 public:
  Box() = default;
  /// Throws InputError if hi <= lo on any axis.
  Box(Vec3 lo, Vec3 hi, std::array<bool, 3> periodic);

  Vec3 lo() const { return lo_; }
  Vec3 hi() const { return hi_; }
  Vec3 length() const { return hi_ - lo_; }
  double length(int axis) const;
  bool periodic(int axis) const { return periodic_[axis]; }
  std::array<bool, 3> periodic() const { return periodic_; }
  double volume() const;
  BoxView view() const;

  /// Folds every particle on a periodic axis back into [lo, hi), counting the crossings in its image flags.
  void wrap(Particles& p) const;
  /// The same on the device copies (offload builds: a kernel per periodic axis, same arithmetic, same bits);
  /// wrap() in host builds.
  void wrap_resident(Particles& p) const;

  /// Moves the box to [new_lo, new_hi) and maps every particle position affinely with it.
  void deform(Vec3 new_lo, Vec3 new_hi, Particles& p);

 private:
  Vec3 lo_{0, 0, 0}, hi_{1, 1, 1};
  std::array<bool, 3> periodic_{false, false, false};
};

}  // namespace debris
