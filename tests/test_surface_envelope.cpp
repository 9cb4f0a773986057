// A body's face as a height field (core/rough/surface_envelope.hpp): the envelope of hand-placed spheres
// against their caps sqrt(r^2 - d^2) worked out by hand, periodic images across the seam, the selection, the
// uncovered points; and a lattice block carved by a rough surface region (core/region.hpp) whose envelope
// follows the surface that carved it.
#include "core/rough/surface_envelope.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <vector>

#include "core/box.hpp"
#include "core/lattice.hpp"
#include "core/region.hpp"

namespace debris {
namespace {

constexpr double kPi = 3.14159265358979323846;

struct Spheres {
  std::vector<double> x, y, z, r;
  void add(double px, double py, double pz, double pr) { x.push_back(px), y.push_back(py), z.push_back(pz), r.push_back(pr); }
};

SurfaceEnvelope envelope(const Box& box, const Spheres& s, EnvelopeSide side, double spacing,
                         std::vector<std::size_t> selection = {}) {
  if (selection.empty())
    for (std::size_t k = 0; k < s.x.size(); ++k) selection.push_back(k);
  return surface_envelope(box, 1, side, spacing, s.x, s.y, s.z, s.r, selection);
}

// Grid point (i, j) of a 0.5 grid from the origin.
double at(const SurfaceEnvelope& e, double x, double z) {
  return e.field.at(static_cast<int>(std::lround(x / 0.5)), static_cast<int>(std::lround(z / 0.5)));
}

TEST(SurfaceEnvelope, OneSphereIsItsCap) {
  // Box 10 x 10 x 10, grid 0.5 (20 x 20), one sphere of radius 1 at (5, 3, 5).
  const Box box({0, 0, 0}, {10, 10, 10}, {true, false, true});
  Spheres s;
  s.add(5, 3, 5, 1);
  const SurfaceEnvelope top = envelope(box, s, EnvelopeSide::top, 0.5);
  ASSERT_EQ(top.field.n_a, 20);
  ASSERT_EQ(top.field.n_b, 20);
  EXPECT_EQ(top.field.normal_axis, 1);
  EXPECT_DOUBLE_EQ(at(top, 5, 5), 4.0);                            // the pole
  EXPECT_DOUBLE_EQ(at(top, 5.5, 5), 3 + std::sqrt(1 - 0.25));      // d = 0.5
  EXPECT_DOUBLE_EQ(at(top, 5.5, 4.5), 3 + std::sqrt(1 - 0.5));     // d^2 = 0.5
  EXPECT_DOUBLE_EQ(at(top, 5, 6), 3.0);                            // d = r: the equator
  EXPECT_DOUBLE_EQ(at(top, 4, 5), 3.0);
  // Covered: the grid offsets (i, j) with (0.5 i)^2 + (0.5 j)^2 <= 1, i.e. i^2 + j^2 <= 4: 13 of the 400.
  EXPECT_EQ(top.filled_points, 400 - 13);
  // The rest took their neighbours' values: within the cap's range.
  for (double h : top.field.h) {
    EXPECT_GE(h, 3.0);
    EXPECT_LE(h, 4.0);
  }
  const SurfaceEnvelope bottom = envelope(box, s, EnvelopeSide::bottom, 0.5);
  EXPECT_DOUBLE_EQ(at(bottom, 5, 5), 2.0);
  EXPECT_DOUBLE_EQ(at(bottom, 5.5, 5), 3 - std::sqrt(0.75));
  EXPECT_EQ(bottom.filled_points, 387);
}

TEST(SurfaceEnvelope, HighestOfOverlappingSpheresAndOnlyTheSelected) {
  const Box box({0, 0, 0}, {10, 10, 10}, {true, false, true});
  Spheres s;
  s.add(5, 3, 5, 1);      // 0
  s.add(6, 3.2, 5, 0.8);  // 1: higher in the middle of the two
  s.add(5, 9, 5, 1);      // 2: far above (not selected below)
  // At x = 5.5 (z = 5): sphere 0 gives 3 + sqrt(0.75) = 3.866; sphere 1 gives 3.2 + sqrt(0.64 - 0.25) = 3.8245.
  // At x = 6: sphere 0 gives 3 (its equator), sphere 1 its pole 4.0.
  const SurfaceEnvelope e = envelope(box, s, EnvelopeSide::top, 0.5, {0, 1});
  EXPECT_DOUBLE_EQ(at(e, 5.5, 5), 3 + std::sqrt(0.75));
  EXPECT_DOUBLE_EQ(at(e, 6, 5), 4.0);
  EXPECT_DOUBLE_EQ(at(e, 5, 5), 4.0);
  // Bottom: the lowest: at x = 6, sphere 1's south pole 2.4 against sphere 0's equator 3.
  EXPECT_DOUBLE_EQ(at(envelope(box, s, EnvelopeSide::bottom, 0.5, {0, 1}), 6, 5), 2.4);
  // With sphere 2 selected too, it is the top over its footprint; by mask, the same as by indices.
  const std::vector<char> all{1, 1, 1};
  const SurfaceEnvelope with2 = surface_envelope(box, 1, EnvelopeSide::top, 0.5, s.x, s.y, s.z, s.r, all);
  EXPECT_DOUBLE_EQ(at(with2, 5, 5), 10.0);
  EXPECT_DOUBLE_EQ(at(with2, 6, 5), 9.0);
  const std::vector<char> first_two{1, 1, 0};
  EXPECT_EQ(surface_envelope(box, 1, EnvelopeSide::top, 0.5, s.x, s.y, s.z, s.r, first_two).field.h, e.field.h);
  // Nothing selected, a bad spacing, an index out of range: refused.
  EXPECT_THROW(surface_envelope(box, 1, EnvelopeSide::top, 0.5, s.x, s.y, s.z, s.r, std::vector<char>{0, 0, 0}),
               std::invalid_argument);
  EXPECT_THROW(envelope(box, s, EnvelopeSide::top, 0.0), std::invalid_argument);
  EXPECT_THROW(envelope(box, s, EnvelopeSide::top, 0.5, {0, 3}), std::invalid_argument);
}

TEST(SurfaceEnvelope, PeriodicImagesAcrossTheSeam) {
  // A sphere of radius 1 at x = 9.8, z = 0.1 in a box [0, 10) periodic in x and z: its image reaches the grid
  // points x = 0 and 0.5 (distances 0.2, 0.7) and z = 9.5 (distance 0.6 through the z seam).
  Spheres s;
  s.add(9.8, 3, 0.1, 1);
  const Box periodic({0, 0, 0}, {10, 10, 10}, {true, false, true});
  const SurfaceEnvelope e = envelope(periodic, s, EnvelopeSide::top, 0.5);
  // (Distances through the seam carry the round-off of 10 - 9.8: 1e-12.)
  EXPECT_NEAR(e.field.at(0, 0), 3 + std::sqrt(1 - 0.2 * 0.2 - 0.1 * 0.1), 1e-12);
  EXPECT_NEAR(e.field.at(1, 0), 3 + std::sqrt(1 - 0.7 * 0.7 - 0.1 * 0.1), 1e-12);
  EXPECT_NEAR(e.field.at(0, 19), 3 + std::sqrt(1 - 0.2 * 0.2 - 0.6 * 0.6), 1e-12);
  EXPECT_NEAR(e.field.at(19, 0), 3 + std::sqrt(1 - 0.3 * 0.3 - 0.1 * 0.1), 1e-12);
  // A sphere straddling nothing on the other side of a wall: x not periodic, so x = 0 is not covered by it
  // (the grid point there takes a neighbour's value, counted), while x = 9.5 is.
  const Box walls({0, 0, 0}, {10, 10, 10}, {false, false, true});
  const SurfaceEnvelope w = envelope(walls, s, EnvelopeSide::top, 0.5);
  EXPECT_NEAR(w.field.at(19, 0), 3 + std::sqrt(1 - 0.3 * 0.3 - 0.1 * 0.1), 1e-12);
  // Covered with images: offsets from (9.8, 0.1) within 1 on the grid; without the x images, those with
  // x >= 10 drop out.
  long covered_periodic = 0, covered_walls = 0;
  for (int i = -3; i <= 23; ++i)
    for (int j = -3; j <= 23; ++j) {
      const double dx = 0.5 * i - 9.8, dz = 0.5 * j - 0.1;
      if (dx * dx + dz * dz > 1) continue;
      ++covered_periodic;
      if (i < 20) ++covered_walls;
    }
  EXPECT_EQ(e.filled_points, 400 - covered_periodic);
  EXPECT_EQ(w.filled_points, 400 - covered_walls);
  EXPECT_GT(covered_periodic, covered_walls);
}

// The sum of sines carved into the lattice (normal y): amplitudes 2 and 1.5 diameters, wavelengths the box's
// x length (24 diameters) and half its z length (12.1 diameters).
struct Sines {
  double lx, lz, mean;
  double operator()(double x, double z) const {
    return mean + 2.0 * std::sin(2 * kPi * x / lx) + 1.5 * std::cos(2 * kPi * 2 * z / lz + 0.7);
  }
};

TEST(Carve, RoughTopOfALatticeFollowsTheSurface) {
  // HCP of diameter = spacing = 1, close-packed planes across y; 24 x 12 x 14 cells: box 24 x 19.6 x 24.2.
  LatticeSpec spec;
  spec.kind = LatticeKind::hcp;
  spec.cells = {24, 12, 14};
  Lattice lat = make_lattice(spec);
  const Box box(lat.box.lo(), lat.box.hi(), {true, false, true});
  const Sines h{box.length(0), box.length(2), 12.0};
  HeightField f;
  f.normal_axis = 1;
  f.length_a = box.length(0), f.length_b = box.length(2);
  f.n_a = 240, f.n_b = 242;
  for (int i = 0; i < f.n_a; ++i)
    for (int j = 0; j < f.n_b; ++j) f.h.push_back(h(i * f.spacing_a(), j * f.spacing_b()));
  const Region above = Region::surface(std::make_shared<const HeightField>(f), false, "two sines");

  Particles& p = lat.particles;
  const std::size_t before = p.size();
  std::vector<char> remove(p.size(), 0);
  for (std::size_t i = 0; i < p.size(); ++i) remove[i] = above.contains({p.x[i], p.y[i], p.z[i]}) ? 1 : 0;
  p.remove_if(remove);
  ASSERT_GT(p.size(), before / 3);
  ASSERT_LT(p.size(), before * 3 / 4);
  // Every centre left is under the surface.
  for (std::size_t i = 0; i < p.size(); ++i) ASSERT_LT(p.y[i], h(p.x[i], p.z[i]));

  const double d = 1.0;
  const SurfaceEnvelope e = surface_envelope(box, 1, EnvelopeSide::top, 0.25, p.x, p.y, p.z, p.radius,
                                             std::vector<char>(p.size(), 1));
  double sum = 0, sum2 = 0, most_above = -1e300, most_below = 1e300;
  const long n = static_cast<long>(e.field.h.size());
  for (int i = 0; i < e.field.n_a; ++i)
    for (int j = 0; j < e.field.n_b; ++j) {
      const double diff = e.field.at(i, j) - h(e.field.origin_a + i * e.field.spacing_a(), e.field.origin_b + j * e.field.spacing_b());
      sum += diff, sum2 += diff * diff;
      most_above = std::max(most_above, diff), most_below = std::min(most_below, diff);
    }
  const double rms = std::sqrt(sum2 / n), mean = sum / n, rms_about_mean = std::sqrt(sum2 / n - mean * mean);
  std::printf("[ carve    ] %zu of %zu particles kept; grid %d x %d, %ld filled; envelope - surface: rms %.3f d, "
              "mean %.3f d, rms about the mean %.3f d, from %.3f d to %.3f d\n",
              p.size(), before, e.field.n_a, e.field.n_b, e.filled_points, rms / d, mean / d, rms_about_mean / d,
              most_below / d, most_above / d);
  // The requirement.
  EXPECT_LT(rms, 0.5 * d);
  // HCP stacked along y leaves straight channels through its C sites, 1/sqrt(3) = 0.577 from every sphere's
  // axis (more than r = 0.5): grid points over them see no sphere and are filled. They are a few per cent of
  // the face.
  EXPECT_GT(e.filled_points, 0);
  EXPECT_LT(e.filled_points, n / 20);
  // Above the surface by at most a cap on a centre under it, reached over an in-plane distance r along which the
  // surface falls by at most r times its steepest slope (2 (2 pi / 24) + 1.5 (2 pi 2 / 24.25) = 1.30).
  const double steepest = 2.0 * 2 * kPi / h.lx + 1.5 * 2 * kPi * 2 / h.lz;
  EXPECT_LE(most_above, 0.5 * d * (1 + steepest));
}

}  // namespace
}  // namespace debris
