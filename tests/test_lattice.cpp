// Lattice generators: a perfect FCC or HCP crystal under periodic boundaries has 12 nearest neighbours at
// the spacing and none closer (checked by brute force with minimum image), the box is a whole number of
// periods, and the random spread and displacement are bounded and reproducible.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <string>

#include "core/error.hpp"
#include "core/lattice.hpp"

namespace debris {
namespace {

double comp(Vec3 v, int a) { return a == 0 ? v.x : (a == 1 ? v.y : v.z); }

Vec3 separation(const BoxView& b, const Particles& p, std::size_t i, std::size_t j) {
  return minimum_image(b, Vec3{p.x[i] - p.x[j], p.y[i] - p.y[j], p.z[i] - p.z[j]});
}

Lattice periodic_lattice(const LatticeSpec& spec) {
  Lattice l = make_lattice(spec);
  l.box = Box(l.box.lo(), l.box.hi(), {true, true, true});
  return l;
}

// Every particle: exactly 12 neighbours at distance a, none closer.
void expect_twelve_nearest(const LatticeSpec& spec) {
  const Lattice l = periodic_lattice(spec);
  const BoxView b = l.box.view();
  const Particles& p = l.particles;
  const double a = spec.spacing, tol = 1e-9 * a;
  for (std::size_t i = 0; i < p.size(); ++i) {
    int at_a = 0, closer = 0;
    for (std::size_t j = 0; j < p.size(); ++j) {
      if (j == i) continue;
      const double d = norm(separation(b, p, i, j));
      if (std::fabs(d - a) < tol) ++at_a;
      else if (d < a) ++closer;
    }
    ASSERT_EQ(at_a, 12) << "particle " << i;
    ASSERT_EQ(closer, 0) << "particle " << i;
  }
}

TEST(Lattice, FccHasTwelveNearestNeighboursAtSpacing) {
  LatticeSpec s;
  s.kind = LatticeKind::fcc;
  s.spacing = 1.7;
  s.cells = {2, 3, 2};
  expect_twelve_nearest(s);
}

TEST(Lattice, HcpHasTwelveNearestNeighboursInEveryOrientation) {
  for (int c = 0; c < 3; ++c) {
    LatticeSpec s;
    s.kind = LatticeKind::hcp;
    s.spacing = 0.8;
    s.hcp_c_axis = c;
    s.cells = {2, 2, 2};
    s.cells[c == 0 ? 1 : 0] = 3;  // first in-plane axis has period a: 3 periods keep the minimum image unique
    SCOPED_TRACE("c axis " + std::to_string(c));
    expect_twelve_nearest(s);
  }
}

// HCP, unlike FCC, has a particle straight above and below at distance c = a sqrt(8/3), along the c axis,
// and 6 of its 12 nearest neighbours lie in the close-packed plane (zero c component).
TEST(Lattice, HcpStackingIsAlongTheChosenAxis) {
  for (int c = 0; c < 3; ++c) {
    LatticeSpec s;
    s.kind = LatticeKind::hcp;
    s.hcp_c_axis = c;
    s.cells = {2, 2, 2};
    s.cells[c == 0 ? 1 : 0] = 3;
    s.cells[c] = 3;  // 3 periods along c: the particles at +c and -c are distinct images
    const Lattice l = periodic_lattice(s);
    const BoxView b = l.box.view();
    const Particles& p = l.particles;
    const double a = s.spacing, cc = a * std::sqrt(8.0 / 3.0);
    for (std::size_t i = 0; i < p.size(); ++i) {
      int above_below = 0, in_plane = 0;
      for (std::size_t j = 0; j < p.size(); ++j) {
        if (j == i) continue;
        const Vec3 d = separation(b, p, i, j);
        const double r = norm(d);
        if (std::fabs(r - cc) < 1e-9) {
          ++above_below;
          EXPECT_NEAR(std::fabs(comp(d, c)), cc, 1e-9);
        }
        if (std::fabs(r - a) < 1e-9 && std::fabs(comp(d, c)) < 1e-9) ++in_plane;
      }
      ASSERT_EQ(above_below, 2) << "c axis " << c << " particle " << i;
      ASSERT_EQ(in_plane, 6) << "c axis " << c << " particle " << i;
    }
  }
  // FCC has no shell at a sqrt(8/3).
  LatticeSpec f;
  f.cells = {2, 2, 2};
  const Lattice l = periodic_lattice(f);
  const BoxView b = l.box.view();
  for (std::size_t j = 1; j < l.particles.size(); ++j)
    EXPECT_GT(std::fabs(norm(separation(b, l.particles, 0, j)) - std::sqrt(8.0 / 3.0)), 1e-3);
}

TEST(Lattice, BoxIsCellsTimesPeriod) {
  const double a = 1.3;
  LatticeSpec f;
  f.spacing = a;
  f.cells = {2, 3, 4};
  f.origin = {-1.0, 2.0, 0.5};
  const Lattice lf = make_lattice(f);
  for (int ax = 0; ax < 3; ++ax) {
    EXPECT_NEAR(lf.box.length(ax), f.cells[ax] * a * std::sqrt(2.0), 1e-12);
    EXPECT_FALSE(lf.box.periodic(ax));
  }
  EXPECT_DOUBLE_EQ(lf.box.lo().x, -1.0);
  EXPECT_DOUBLE_EQ(lf.box.lo().y, 2.0);
  EXPECT_DOUBLE_EQ(lf.box.lo().z, 0.5);

  LatticeSpec h = f;
  h.kind = LatticeKind::hcp;
  h.hcp_c_axis = 1;  // x period a, z period a sqrt 3, y period c
  const Lattice lh = make_lattice(h);
  EXPECT_NEAR(lh.box.length(0), 2 * a, 1e-12);
  EXPECT_NEAR(lh.box.length(1), 3 * a * std::sqrt(8.0 / 3.0), 1e-12);
  EXPECT_NEAR(lh.box.length(2), 4 * a * std::sqrt(3.0), 1e-12);
  h.hcp_c_axis = 0;  // y period a, z period a sqrt 3, x period c
  const Lattice lx = make_lattice(h);
  EXPECT_NEAR(lx.box.length(0), 2 * a * std::sqrt(8.0 / 3.0), 1e-12);
  EXPECT_NEAR(lx.box.length(1), 3 * a, 1e-12);
  EXPECT_NEAR(lx.box.length(2), 4 * a * std::sqrt(3.0), 1e-12);
  h.hcp_c_axis = 2;  // x period a, y period a sqrt 3, z period c
  const Lattice lz = make_lattice(h);
  EXPECT_NEAR(lz.box.length(0), 2 * a, 1e-12);
  EXPECT_NEAR(lz.box.length(1), 3 * a * std::sqrt(3.0), 1e-12);
  EXPECT_NEAR(lz.box.length(2), 4 * a * std::sqrt(8.0 / 3.0), 1e-12);
}

TEST(Lattice, CountIdsAndFieldsOfAPerfectLattice) {
  for (LatticeKind kind : {LatticeKind::fcc, LatticeKind::hcp}) {
    LatticeSpec s;
    s.kind = kind;
    s.cells = {3, 2, 5};
    s.diameter = 0.9;
    s.type = 3;
    const Lattice l = make_lattice(s);
    const Particles& p = l.particles;
    ASSERT_EQ(p.size(), 4u * 3 * 2 * 5);
    std::set<std::int64_t> ids(p.id.begin(), p.id.end());
    EXPECT_EQ(ids.size(), p.size());
    EXPECT_EQ(*ids.begin(), 1);
    EXPECT_EQ(*ids.rbegin(), static_cast<std::int64_t>(p.size()));
    const Vec3 lo = l.box.lo(), hi = l.box.hi();
    for (std::size_t i = 0; i < p.size(); ++i) {
      EXPECT_DOUBLE_EQ(p.radius[i], 0.45);
      EXPECT_EQ(p.type[i], 3);
      EXPECT_EQ(p.group[i], -1);
      EXPECT_EQ(p.mass[i], 0.0);
      EXPECT_EQ(p.inertia[i], 0.0);
      // Placed strictly inside the box, off its faces.
      EXPECT_GT(p.x[i], lo.x);
      EXPECT_LT(p.x[i], hi.x);
      EXPECT_GT(p.y[i], lo.y);
      EXPECT_LT(p.y[i], hi.y);
      EXPECT_GT(p.z[i], lo.z);
      EXPECT_LT(p.z[i], hi.z);
    }
  }
}

TEST(Lattice, SizeSpreadAndDisplacementStayInBounds) {
  LatticeSpec perfect;
  perfect.kind = LatticeKind::hcp;
  perfect.cells = {10, 10, 10};
  perfect.diameter = 2.0;
  LatticeSpec s = perfect;
  s.size_spread = 0.2;
  s.displacement = 0.05;
  s.seed = 42;
  const Lattice l0 = make_lattice(perfect);
  const Lattice l = make_lattice(s);
  const Particles& p = l.particles;
  ASSERT_EQ(p.size(), 4000u);
  double sum = 0, d_min = 1e300, d_max = 0, max_shift = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double d = 2 * p.radius[i];
    sum += d;
    d_min = std::min(d_min, d);
    d_max = std::max(d_max, d);
    max_shift = std::max({max_shift, std::fabs(p.x[i] - l0.particles.x[i]), std::fabs(p.y[i] - l0.particles.y[i]),
                          std::fabs(p.z[i] - l0.particles.z[i])});
  }
  EXPECT_GE(d_min, 2.0 * 0.8);
  EXPECT_LE(d_max, 2.0 * 1.2);
  // The spread is really used: close to both ends of the interval.
  EXPECT_LT(d_min, 2.0 * 0.81);
  EXPECT_GT(d_max, 2.0 * 1.19);
  // Mean of 4000 uniform draws: standard error 0.4 / sqrt(3 * 4000) = 0.0037.
  EXPECT_NEAR(sum / p.size(), 2.0, 0.015);
  EXPECT_LE(max_shift, 0.05);
  EXPECT_GT(max_shift, 0.049);
}

TEST(Lattice, SameSeedSameParticlesOtherSeedOthers) {
  LatticeSpec s;
  s.cells = {3, 3, 3};
  s.size_spread = 0.1;
  s.displacement = 0.02;
  s.seed = 7;
  const Particles a = make_lattice(s).particles;
  const Particles b = make_lattice(s).particles;
  EXPECT_EQ(a.x, b.x);
  EXPECT_EQ(a.y, b.y);
  EXPECT_EQ(a.z, b.z);
  EXPECT_EQ(a.radius, b.radius);
  s.seed = 8;
  const Particles c = make_lattice(s).particles;
  std::size_t differ_x = 0, differ_r = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    differ_x += a.x[i] != c.x[i];
    differ_r += a.radius[i] != c.radius[i];
  }
  EXPECT_EQ(differ_x, a.size());
  EXPECT_EQ(differ_r, a.size());
}

void expect_input_error(LatticeSpec s, const std::string& key) {
  try {
    make_lattice(s);
    ADD_FAILURE() << "no InputError for " << key;
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("'" + key + "'"), std::string::npos) << e.what();
  }
}

TEST(Lattice, InvalidSpecNamesTheKey) {
  LatticeSpec s;
  EXPECT_NO_THROW(validate(s));
  LatticeSpec t = s;
  t.spacing = 0;
  expect_input_error(t, "lattice.spacing");
  t = s;
  t.diameter = -1;
  expect_input_error(t, "lattice.diameter");
  t = s;
  t.size_spread = 1.0;
  expect_input_error(t, "lattice.size_spread");
  t.size_spread = -0.1;
  expect_input_error(t, "lattice.size_spread");
  t = s;
  t.displacement = -0.01;
  expect_input_error(t, "lattice.displacement");
  t = s;
  t.cells = {1, 0, 1};
  expect_input_error(t, "lattice.cells");
  t = s;
  t.hcp_c_axis = 3;
  expect_input_error(t, "lattice.hcp_c_axis");
  t.hcp_c_axis = -1;
  expect_input_error(t, "lattice.hcp_c_axis");
  // The message carries the value too.
  t = s;
  t.spacing = -2.5;
  try {
    validate(t);
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("-2.5"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace debris
