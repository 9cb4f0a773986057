// The box: minimum image, folding particles back with image counts (so unwrapped positions are recoverable),
// affine deformation of the box with the particles, and bad bounds.
#include <gtest/gtest.h>

#include "core/box.hpp"
#include "core/error.hpp"
#include "core/particles.hpp"

namespace debris {
namespace {

TEST(Box, MinimumImageOnPeriodicAxesOnly) {
  const Box box({0, 0, 0}, {10, 20, 30}, {true, false, true});
  const Vec3 d = minimum_image(box.view(), Vec3{9.0, 19.0, -16.0});
  EXPECT_DOUBLE_EQ(d.x, -1.0);   // 9 is nearer as -1 through the periodic x boundary
  EXPECT_DOUBLE_EQ(d.y, 19.0);   // y is not periodic: unchanged
  EXPECT_DOUBLE_EQ(d.z, 14.0);   // -16 -> +14
  // The branch-free variant used by the pair loops agrees for separations below 1.5 box lengths.
  for (double s : {-14.9, -9.0, -5.1, -4.9, 0.0, 4.9, 5.1, 9.0, 14.9})
    EXPECT_DOUBLE_EQ(nearest_image(s, 10.0, 1), minimum_image(box.view(), Vec3{s, 0, 0}).x) << s;
  EXPECT_EQ(nearest_image(7.0, 10.0, 0), 7.0);
}

TEST(Box, WrapKeepsUnwrappedPositionsThroughImageCounts) {
  const Box box({-5, 0, 0}, {5, 10, 10}, {true, true, false});
  Particles p;
  p.add(1, 1, 12.0, -0.5, 25.0, 1.0);   // x: two boxes to the right; y: just below; z: not periodic
  p.add(2, 1, -5.0, 10.0, 3.0, 1.0);    // exactly on lo (stays) and on hi (folds to lo)
  const Vec3 before[2] = {{12.0, -0.5, 25.0}, {-5.0, 10.0, 3.0}};
  box.wrap(p);
  for (std::size_t i = 0; i < p.size(); ++i) {
    EXPECT_GE(p.x[i], -5.0);
    EXPECT_LT(p.x[i], 5.0);
    EXPECT_GE(p.y[i], 0.0);
    EXPECT_LT(p.y[i], 10.0);
    EXPECT_DOUBLE_EQ(p.x[i] + 10.0 * p.ix[i], before[i].x);
    EXPECT_DOUBLE_EQ(p.y[i] + 10.0 * p.iy[i], before[i].y);
    EXPECT_EQ(p.z[i], before[i].z);
  }
  EXPECT_EQ(p.ix[0], 1);
  EXPECT_EQ(p.iy[0], -1);
  EXPECT_EQ(p.iy[1], 1);
}

TEST(Box, DeformMapsParticlesAffinely) {
  Box box({0, 0, 0}, {10, 10, 10}, {true, true, true});
  Particles p;
  p.add(1, 1, 2.0, 5.0, 10.0, 1.0);
  box.deform({0, -1, 0}, {12, 11, 10}, p);  // x stretched by 1.2, y by 1.2 about the centre, z unchanged
  EXPECT_DOUBLE_EQ(p.x[0], 2.4);
  EXPECT_DOUBLE_EQ(p.y[0], 5.0);
  EXPECT_DOUBLE_EQ(p.z[0], 10.0);
  EXPECT_DOUBLE_EQ(box.length(0), 12.0);
  EXPECT_DOUBLE_EQ(box.volume(), 12.0 * 12.0 * 10.0);
  EXPECT_TRUE(box.periodic(0));
}

TEST(Box, BadBoundsNameTheAxis) {
  try {
    Box({0, 0, 0}, {1, -1, 1}, {false, false, false});
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("box.y"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace debris
