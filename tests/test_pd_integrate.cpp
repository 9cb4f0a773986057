// Time integration of PeriDEM nodes (kernels/peridem/pd_integrate.hpp, eq 32): the weight pass, viscous
// damping's recurrence, the parabola of a free node, fixed components and moving walls.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "tests/pd_test_grains.hpp"

namespace debris {
namespace {

using namespace pd_test;

TEST(PdIntegrate, ViscousDampingFollowsItsRecurrenceToTheTerminalVelocity) {
  PdSystem s;
  s.begin_grain(PdGrainKind::particle);
  s.add_node({0.0, 0.0, 0.0}, 2e-9, 2500.0);
  s.begin_grain(PdGrainKind::wall);
  s.add_node({1.0, 0.0, 0.0}, 2e-9, 2500.0);
  s.grains.wall_vx[1] = 0.3;
  const double c = 50.0, dt = 1e-3, gy = -9.81, v0 = 2.0;
  s.nodes.vy[0] = v0;
  const double terminal = gy / c;
  const double half = v0 + 0.5 * dt * (gy - c * v0);  // the first step's half kick
  for (int n = 1; n <= 400; ++n) {
    test::pd_weight_forces(s.nodes, s.grains, {0.0, gy, 0.0});
    test::pd_viscous_damping(s.nodes, s.grains, c);
    ASSERT_EQ(s.nodes.fx[1], 0.0) << "a wall node is not damped";
    test::pd_integrate(s.nodes, s.grains, dt, n == 1);
    const double exact = terminal + std::pow(1.0 - c * dt, n - 1) * (half - terminal);
    ASSERT_NEAR(s.nodes.vy[0], exact, 1e-12) << "step " << n;
  }
  EXPECT_NEAR(s.nodes.vy[0], terminal, 1e-3 * std::fabs(terminal));  // (0.95)^399: at the terminal velocity
  EXPECT_EQ(s.nodes.vx[1], 0.3);
}

TEST(PdIntegrate, FreeNodeFollowsTheParabolaFixedComponentsStayWallsMoveAtTheirVelocity) {
  PdSystem s;
  s.begin_grain(PdGrainKind::particle);
  s.add_node({0.1, 0.2, 0.3}, 2e-9, 2500.0);  // free
  s.add_node({1.0, 2.0, 3.0}, 2e-9, 2500.0);  // x and z fixed
  s.nodes.fixed[1] = 1 | 4;
  s.begin_grain(PdGrainKind::wall);
  s.add_node({-1.0, 0.0, 0.5}, 2e-9, 2500.0);
  s.add_node({-1.5, 0.0, 0.5}, 2e-9, 2500.0);
  s.grains.wall_vx[1] = 0.3;
  s.grains.wall_vz[1] = -0.1;
  const Vec3 v0{1.5, 4.0, -0.5}, g{0.0, -9.81, 2.0};
  s.nodes.vx[0] = v0.x;
  s.nodes.vy[0] = v0.y;
  s.nodes.vz[0] = v0.z;
  s.nodes.vx[1] = v0.x;
  s.nodes.vy[1] = v0.y;
  s.nodes.vz[1] = v0.z;
  const double dt = 1e-3;
  for (int n = 1; n <= 2000; ++n) {
    test::pd_weight_forces(s.nodes, s.grains, g);
    s.nodes.fx[2] = 1e6;  // a wall ignores forces
    test::pd_integrate(s.nodes, s.grains, dt, n == 1);
    const double t = n * dt;
    const Vec3 exact = Vec3{0.1, 0.2, 0.3} + t * v0 + (0.5 * t * t) * g;  // eq 32 is exact for constant force
    ASSERT_NEAR(s.nodes.x[0], exact.x, 1e-12 * (1 + std::fabs(exact.x))) << "step " << n;
    ASSERT_NEAR(s.nodes.y[0], exact.y, 1e-12 * (1 + std::fabs(exact.y))) << "step " << n;
    ASSERT_NEAR(s.nodes.z[0], exact.z, 1e-12 * (1 + std::fabs(exact.z))) << "step " << n;
    // The stored velocity is the half-step one, v(t - dt/2).
    ASSERT_NEAR(s.nodes.vy[0], v0.y + g.y * (t - 0.5 * dt), 1e-12);
    ASSERT_EQ(s.nodes.x[1], 1.0);
    ASSERT_EQ(s.nodes.z[1], 3.0);
    ASSERT_EQ(s.nodes.vx[1], 0.0);
    ASSERT_NEAR(s.nodes.y[1], 2.0 + t * v0.y + 0.5 * t * t * g.y, 1e-11);
    ASSERT_NEAR(s.nodes.x[2], -1.0 + 0.3 * t, 1e-12);
    ASSERT_NEAR(s.nodes.x[3], -1.5 + 0.3 * t, 1e-12);
    ASSERT_NEAR(s.nodes.z[3], 0.5 - 0.1 * t, 1e-12);
    ASSERT_EQ(s.nodes.y[3], 0.0);
    ASSERT_EQ(s.nodes.vx[2], 0.3);
  }
  // The first sweep of a step: each particle node's weight, and zero on walls, whatever the forces held.
  for (std::size_t i = 0; i < s.nodes.size(); ++i) s.nodes.fx[i] = s.nodes.fy[i] = s.nodes.fz[i] = 7.0;
  test::pd_weight_forces(s.nodes, s.grains, g);
  for (const int wall_node : {2, 3}) {
    EXPECT_EQ(s.nodes.fx[wall_node], 0.0);
    EXPECT_EQ(s.nodes.fy[wall_node], 0.0);
    EXPECT_EQ(s.nodes.fz[wall_node], 0.0);
  }
  for (const int node : {0, 1}) {
    EXPECT_EQ(s.nodes.fx[node], 0.0);
    EXPECT_DOUBLE_EQ(s.nodes.fy[node], s.nodes.mass[node] * g.y);
    EXPECT_DOUBLE_EQ(s.nodes.fz[node], s.nodes.mass[node] * g.z);
  }
  EXPECT_FALSE(std::signbit(s.nodes.fx[0]));  // g.x = 0: +0.0, as 0.0 + m * 0.0 gives
}

}  // namespace
}  // namespace debris
