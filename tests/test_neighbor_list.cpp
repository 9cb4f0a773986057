// NeighborList against a brute-force all-pairs search with minimum image, for random polydisperse systems
// with per-pair cutoffs, in periodic, non-periodic and mixed boxes, with one grid and with size classes
// (size ratios 3 and 7); Verlet rebuild criterion; independence of the thread count.
// Offload builds: the systems are made on the host and sent to the device (to_device) after every host-side
// change, as a simulation does; the rows are read on the host after the list's to_host().
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "core/box.hpp"
#include "core/error.hpp"
#include "core/exec.hpp"
#include "core/neighbor_list.hpp"
#include "core/particles.hpp"
#include "kernels/dem/cohesive_material.hpp"

namespace debris {
namespace {

DEBRIS_DECLARE_TARGET
// r_i + r_j + 0.3 (r_i + r_j): a per-pair cutoff like the cohesive one, but simple to bound.
struct PolyCutoff {
  double operator()(double ri, double rj) const { return 1.3 * (ri + rj); }
};
DEBRIS_END_DECLARE_TARGET

constexpr double kMaxCutoff = 1.3 * 3.0;  // radii <= 1.5
constexpr double kSkin = 0.3;

struct System {
  Box box;
  Particles p;
};

// n particles, radii uniform in [0.5, 1.5] * scale; on non-periodic axes 10% of them lie outside the box.
System random_system(int n, Vec3 lo, Vec3 len, std::array<bool, 3> periodic, std::uint64_t seed, double scale = 1) {
  System s{Box(lo, lo + len, periodic), Particles{}};
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double l[3] = {len.x, len.y, len.z}, o[3] = {lo.x, lo.y, lo.z};
  for (int i = 0; i < n; ++i) {
    double r[3];
    for (int a = 0; a < 3; ++a) {
      const double t = periodic[a] ? u(rng) : -0.05 + 1.1 * u(rng);
      r[a] = o[a] + t * l[a];
    }
    s.p.add(i, 1, r[0], r[1], r[2], scale * (0.5 + u(rng)));
  }
  to_device(s.p);
  return s;
}

// n particles with radii from 0.3 to 2.0 (ratio 6.7), most of them small as in a log-normal sample:
// r = 0.3 * 6.7^(u^2). Positions as in random_system (10% outside the box on non-periodic axes).
constexpr double kWideMaxCutoff = 1.3 * 4.0;
System wide_system(int n, Vec3 lo, Vec3 len, std::array<bool, 3> periodic, std::uint64_t seed) {
  System s = random_system(n, lo, len, periodic, seed);
  std::mt19937_64 rng(seed + 1000);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (std::size_t i = 0; i < s.p.size(); ++i) {
    const double t = u(rng);
    s.p.radius[i] = std::min(2.0, 0.3 * std::pow(2.0 / 0.3, t * t));
  }
  s.p.radius[0] = 0.3;  // both ends of the range present
  s.p.radius[1] = 2.0;
  to_device(s.p);
  return s;
}

using Pairs = std::vector<std::pair<int, int>>;

// All ordered pairs (i, j), i != j, within cutoff + skin: the reference.
template <class Cutoff>
Pairs brute_force(const System& s, Cutoff cutoff, double skin) {
  const BoxView b = s.box.view();
  const Particles& p = s.p;
  Pairs out;
  for (int i = 0; i < static_cast<int>(p.size()); ++i) {
    for (int j = 0; j < static_cast<int>(p.size()); ++j) {
      if (i == j) continue;
      const Vec3 d = minimum_image(b, Vec3{p.x[i] - p.x[j], p.y[i] - p.y[j], p.z[i] - p.z[j]});
      const double rc = cutoff(p.radius[i], p.radius[j]) + skin;
      if (norm2(d) < rc * rc) out.emplace_back(i, j);
    }
  }
  return out;  // sorted by construction
}

Pairs listed_pairs(const NeighborList& nl) {
  nl.to_host();
  Pairs out;
  for (int i = 0; i < nl.rows(); ++i)
    for (int k = nl.offset()[i]; k < nl.offset()[i + 1]; ++k) out.emplace_back(i, nl.index()[k]);
  return out;
}

// Full and half lists against the brute force, with at most max_classes size classes.
template <class Cutoff>
void expect_lists_match(const System& s, const Pairs& ref, Cutoff cutoff, double max_cutoff, double skin,
                        int max_classes) {
  SCOPED_TRACE("at most " + std::to_string(max_classes) + " size classes");
  const BoxView b = s.box.view();
  const int n = static_cast<int>(s.p.size());
  NeighborList full;
  full.set_max_size_classes(max_classes);
  full.build(b, s.p, cutoff, max_cutoff, skin, NeighborKind::full);
  EXPECT_LE(full.size_classes().count, max_classes);
  ASSERT_EQ(full.rows(), n);
  ASSERT_EQ(full.offset().size(), static_cast<std::size_t>(n) + 1);
  EXPECT_EQ(full.kind(), NeighborKind::full);
  EXPECT_EQ(full.skin(), skin);
  if (!exec::offload_build()) EXPECT_GE(full.candidates(), full.entries());  // counted by host builds only
  Pairs got = listed_pairs(full);
  ASSERT_EQ(got.size(), static_cast<std::size_t>(full.entries()));
  std::sort(got.begin(), got.end());
  EXPECT_TRUE(std::adjacent_find(got.begin(), got.end()) == got.end()) << "a pair listed twice in a row";
  EXPECT_EQ(got, ref);  // ref holds (i, j) and (j, i): the full list is symmetric
  for (const auto& [i, j] : got) EXPECT_TRUE(std::binary_search(got.begin(), got.end(), std::make_pair(j, i)));

  NeighborList half;
  half.set_max_size_classes(max_classes);
  half.build(b, s.p, cutoff, max_cutoff, skin, NeighborKind::half);
  EXPECT_EQ(half.kind(), NeighborKind::half);
  EXPECT_EQ(2 * half.entries(), full.entries());
  Pairs got_half = listed_pairs(half);
  for (const auto& [i, j] : got_half) ASSERT_LT(i, j) << "half list: a pair belongs in row min(i, j)";
  std::sort(got_half.begin(), got_half.end());
  EXPECT_TRUE(std::adjacent_find(got_half.begin(), got_half.end()) == got_half.end());
  Pairs ref_half;
  for (const auto& [i, j] : ref)
    if (i < j) ref_half.emplace_back(i, j);
  EXPECT_EQ(got_half, ref_half);
  EXPECT_GE(full.bytes(), sizeof(int) * (full.offset().size() + full.index().size()) + 3 * sizeof(double) * n);
}

// One grid, and as many size classes as the radii call for (and two, where that is fewer).
template <class Cutoff>
void expect_matches_brute_force(const System& s, Cutoff cutoff, double max_cutoff, double skin) {
  const int n = static_cast<int>(s.p.size());
  const Pairs ref = brute_force(s, cutoff, skin);
  ASSERT_GT(ref.size(), static_cast<std::size_t>(2 * n)) << "the test system should have neighbours";
  for (int classes : {1, 2, SizeClasses::kMax}) expect_lists_match(s, ref, cutoff, max_cutoff, skin, classes);
}

TEST(NeighborList, PeriodicBoxMatchesBruteForce) {
  const System s = random_system(2000, {-3, 0, 5}, {30, 28, 32}, {true, true, true}, 11);
  expect_matches_brute_force(s, PolyCutoff{}, kMaxCutoff, kSkin);
}

// Inside a periodic box the scan skips the minimum-image arithmetic for particles away from its faces; a
// particle left outside the box (up to a quarter box length here, the separations the neighbour list allows)
// must switch that off and still give every pair.
TEST(NeighborList, PositionsOutsideThePeriodicBoxMatchBruteForce) {
  System s = random_system(2000, {-3, 0, 5}, {30, 28, 32}, {true, true, true}, 21);
  int moved = 0;
  for (std::size_t i = 0; i < s.p.size(); ++i)
    if (s.p.x[i] < -3 + 0.25 * 30) {
      s.p.x[i] += 30;
      ++moved;
    }
  ASSERT_GT(moved, 100);
  to_device(s.p);
  EXPECT_FALSE(NeighborList::inside_periodic_box(s.box.view(), s.p));
  expect_matches_brute_force(s, PolyCutoff{}, kMaxCutoff, kSkin);
  s.box.wrap(s.p);
  to_device(s.p);
  EXPECT_TRUE(NeighborList::inside_periodic_box(s.box.view(), s.p));
}

TEST(NeighborList, NonPeriodicBoxMatchesBruteForce) {
  const System s = random_system(2000, {0, 0, 0}, {30, 28, 32}, {false, false, false}, 12);
  expect_matches_brute_force(s, PolyCutoff{}, kMaxCutoff, kSkin);
}

TEST(NeighborList, MixedBoxMatchesBruteForce) {
  // y non-periodic with only 2 cells, x and z periodic.
  const System s = random_system(2000, {0, -1, 0}, {40, 10, 45}, {true, false, true}, 13);
  NeighborList nl;
  nl.set_max_size_classes(1);
  nl.build(s.box.view(), s.p, PolyCutoff{}, kMaxCutoff, kSkin, NeighborKind::full);
  EXPECT_EQ(nl.cells().dims()[1], 2);
  expect_matches_brute_force(s, PolyCutoff{}, kMaxCutoff, kSkin);
}

TEST(NeighborList, SmallPeriodicBoxesWithOneAndThreeCellsPerAxis) {
  // x: 9 / 4.2 -> 2 cells -> 1 cell; y: 3 cells, every stencil wraps; z: 7 cells.
  const System s = random_system(400, {0, 0, 0}, {9.0, 13.0, 30.0}, {true, true, true}, 14);
  NeighborList nl;
  nl.set_max_size_classes(1);
  nl.build(s.box.view(), s.p, PolyCutoff{}, kMaxCutoff, kSkin, NeighborKind::full);
  EXPECT_EQ(nl.cells().dims(), (std::array<int, 3>{1, 3, 7}));
  expect_matches_brute_force(s, PolyCutoff{}, kMaxCutoff, kSkin);

  // One cell on every axis, box just above 2 (max_cutoff + skin): neighbours through every face.
  const System t = random_system(60, {0, 0, 0}, {8.5, 8.5, 8.5}, {true, true, true}, 15);
  nl.build(t.box.view(), t.p, PolyCutoff{}, kMaxCutoff, kSkin, NeighborKind::full);
  EXPECT_EQ(nl.cells().dims(), (std::array<int, 3>{1, 1, 1}));
  expect_matches_brute_force(t, PolyCutoff{}, kMaxCutoff, kSkin);
}

TEST(NeighborList, CohesiveCutoffMatchesBruteForce) {
  CohesiveMaterial m;
  m.youngs_modulus = 1e9;
  m.poisson_ratio = 0.2;
  m.tensile_strength = 1e7;
  m.shear_strength = 5e6;
  m.surface_energy = 2.0;
  m.restitution = 0.5;
  m.density = 2000;
  m.scaling = 0.5;
  const CohesiveCutoff cutoff{CohesiveCoefficients::from(m)};
  const double scale = 4e-5;  // radii 2e-5 .. 6e-5 m straddle d_c = 8e-5 m: both branches of eq 10
  const double max_cutoff = cutoff(1.5 * scale, 1.5 * scale);
  const System s = random_system(1000, {0, 0, 0}, Vec3{18, 18, 18} * scale, {true, false, true}, 16, scale);
  expect_matches_brute_force(s, cutoff, max_cutoff, 0.1 * scale);
}

// Size ratio 6.7 (as the silica samples of the wear junction): three size classes, every pair found in
// periodic, non-periodic and mixed boxes, with particles outside the box, and far fewer candidates scanned
// than with one grid sized for the largest pair.
TEST(NeighborList, SizeRatioSevenMatchesBruteForce) {
  const System per = wide_system(5000, {-3, 0, 5}, {30, 28, 32}, {true, true, true}, 71);
  const System non = wide_system(5000, {0, 0, 0}, {30, 28, 32}, {false, false, false}, 72);
  const System mix = wide_system(5000, {0, -1, 0}, {36, 14, 36}, {true, false, true}, 73);
  for (const System* s : {&per, &non, &mix}) {
    expect_matches_brute_force(*s, PolyCutoff{}, kWideMaxCutoff, kSkin);
    NeighborList one, classes;
    one.set_max_size_classes(1);
    one.build(s->box.view(), s->p, PolyCutoff{}, kWideMaxCutoff, kSkin, NeighborKind::full);
    classes.build(s->box.view(), s->p, PolyCutoff{}, kWideMaxCutoff, kSkin, NeighborKind::full);
    EXPECT_EQ(classes.size_classes().count, 3);
    if (!exec::offload_build()) EXPECT_LT(3 * classes.candidates(), one.candidates());
  }
  // Unwrapped positions on a periodic axis (up to a quarter box beyond it, the separations the list allows):
  // the image-free shortcut must switch off.
  System out = per;
  for (std::size_t i = 0; i < out.p.size(); ++i)
    if (out.p.z[i] < 5 + 0.25 * 32) out.p.z[i] += 32;
  to_device(out.p);  // a copy too: its columns are new device buffers
  EXPECT_FALSE(NeighborList::inside_periodic_box(out.box.view(), out.p));
  expect_matches_brute_force(out, PolyCutoff{}, kWideMaxCutoff, kSkin);
}

// The cohesive cutoff (eq 10, both branches) over a size ratio of 7, in the junction's boundaries.
TEST(NeighborList, CohesiveCutoffSizeRatioSevenMatchesBruteForce) {
  const CohesiveCutoff cutoff{CohesiveCoefficients::from(silica_material())};
  const double scale = 1e-9;
  System s = wide_system(4000, {0, 0, 0}, Vec3{24, 20, 24} * scale, {true, false, true}, 74);
  for (std::size_t i = 0; i < s.p.size(); ++i) {
    s.p.x[i] *= scale;
    s.p.y[i] *= scale;
    s.p.z[i] *= scale;
    s.p.radius[i] *= scale;
  }
  to_device(s.p);
  const double max_cutoff = cutoff(2.0 * scale, 2.0 * scale);
  expect_matches_brute_force(s, cutoff, max_cutoff, 0.05 * scale);
}

TEST(NeighborList, SizeClassesAreInputChecked) {
  NeighborList nl;
  EXPECT_THROW(nl.set_max_size_classes(0), InputError);
  EXPECT_THROW(nl.set_max_size_classes(SizeClasses::kMax + 1), InputError);
  const double r[] = {1.0, 1.9, 2.0, 3.9, 4.0, 100.0};
  const SizeClasses c = SizeClasses::of(r, 6, SizeClasses::kMax);
  EXPECT_EQ(c.count, SizeClasses::kMax);
  EXPECT_EQ(c.members[0], 2);
  EXPECT_EQ(c.members[1], 2);
  EXPECT_EQ(c.members[2], 1);
  EXPECT_EQ(c.members[3], 1);  // the last class is open above
  EXPECT_EQ(c.r_max[3], 100.0);
  EXPECT_EQ(SizeClasses::of(r, 2, SizeClasses::kMax).count, 1);  // 1.9 / 1.0 < 2: one grid
}

// The classes a build finds where the radii are (on the device in offload builds: two reductions and, with
// several classes, a count and a maximum per class) are the host count's, for every cap on the classes.
TEST(NeighborList, SizeClassesWhereTheRadiiAreEqualTheHostCount) {
  std::mt19937_64 rng(9);
  std::lognormal_distribution<double> size(0.0, 0.8);
  exec::DeviceVector<double> r(5000);
  for (double& v : r) v = 0.5 * size(rng);
  // Radii exactly on the first two bounds (2 and 4 times the smallest): lower[c] <= r is class c.
  const auto smallest = std::min_element(r.begin(), r.end()) - r.begin();
  r[smallest == 17 ? 18 : 17] = 2.0 * r[static_cast<std::size_t>(smallest)];
  r[smallest == 19 ? 20 : 19] = 4.0 * r[static_cast<std::size_t>(smallest)];
  exec::to_device(r);
  const int n = static_cast<int>(r.size());
  for (int cap = 1; cap <= SizeClasses::kMax; ++cap) {
    const SizeClasses host = SizeClasses::of(r.data(), n, cap), here = SizeClasses::of_resident(r.data(), n, cap);
    ASSERT_EQ(here.count, host.count) << "cap " << cap;
    EXPECT_EQ(here.count, cap) << "the radii span more than a factor 2^3";
    for (int c = 0; c < host.count; ++c) {
      EXPECT_EQ(here.lower[c], host.lower[c]) << "cap " << cap << ", class " << c;
      EXPECT_EQ(here.members[c], host.members[c]) << "cap " << cap << ", class " << c;
      EXPECT_EQ(here.r_max[c], host.r_max[c]) << "cap " << cap << ", class " << c;
    }
  }
}

TEST(NeighborList, RebuildOnlyAfterMovingMoreThanHalfTheSkin) {
  System s = random_system(500, {0, 0, 0}, {20, 20, 20}, {true, true, true}, 21);
  s.p.x[0] = 20.0 - 0.01;  // next to the periodic face
  to_device(s.p);
  NeighborList nl;
  EXPECT_TRUE(nl.needs_rebuild(s.box.view(), s.p)) << "never built";
  nl.build(s.box.view(), s.p, PolyCutoff{}, kMaxCutoff, kSkin, NeighborKind::full);
  EXPECT_FALSE(nl.needs_rebuild(s.box.view(), s.p));

  // Every particle 0.49 skin (just under skin / 2) in a random direction: still valid. Particle 0 moves
  // along +x through the periodic face and is wrapped: a wrap is not a move.
  std::mt19937_64 rng(22);
  std::normal_distribution<double> g(0.0, 1.0);
  System moved = s;
  for (std::size_t i = 0; i < moved.p.size(); ++i) {
    Vec3 d{g(rng), g(rng), g(rng)};
    if (i == 0) d = {1, 0, 0};
    d = (0.49 * kSkin / norm(d)) * d;
    moved.p.x[i] += d.x;
    moved.p.y[i] += d.y;
    moved.p.z[i] += d.z;
  }
  moved.box.wrap(moved.p);
  to_device(moved.p);
  ASSERT_NEAR(moved.p.x[0], 0.49 * kSkin - 0.01, 1e-12);
  ASSERT_EQ(moved.p.ix[0], 1);
  EXPECT_FALSE(nl.needs_rebuild(s.box.view(), moved.p));

  // One particle 0.51 skin: rebuild.
  System one = s;
  one.p.y[123] += 0.51 * kSkin;
  to_device(one.p);
  EXPECT_TRUE(nl.needs_rebuild(s.box.view(), one.p));
  one.p.y[123] -= 0.02 * kSkin;  // 0.49 skin: fine again
  to_device(one.p);
  EXPECT_FALSE(nl.needs_rebuild(s.box.view(), one.p));

  // Box length changed by more than skin / 2 in total, particles unmoved.
  BoxView grown = s.box.view();
  grown.len[2] += 0.49 * kSkin;
  EXPECT_FALSE(nl.needs_rebuild(grown, s.p));
  grown.len[2] += 0.02 * kSkin;
  EXPECT_TRUE(nl.needs_rebuild(grown, s.p));

  // Particle count changed.
  System more = s;
  more.p.add(500, 1, 1.0, 1.0, 1.0, 1.0);
  to_device(more.p);
  EXPECT_TRUE(nl.needs_rebuild(s.box.view(), more.p));
}

TEST(NeighborList, SameRowsWithOneAndTwoThreads) {
  const System s = random_system(2000, {0, -1, 0}, {30, 12, 30}, {true, false, true}, 31);
  const System w = wide_system(4000, {0, -1, 0}, {30, 14, 30}, {true, false, true}, 32);
  const int before = exec::threads();
  for (const auto& [sys, max_cutoff] : {std::make_pair(&s, kMaxCutoff), std::make_pair(&w, kWideMaxCutoff)})
    for (int classes : {1, SizeClasses::kMax})
      for (NeighborKind kind : {NeighborKind::full, NeighborKind::half}) {
        NeighborList one, two;
        one.set_max_size_classes(classes);
        two.set_max_size_classes(classes);
        exec::set_threads(1);
        one.build(sys->box.view(), sys->p, PolyCutoff{}, max_cutoff, kSkin, kind);
        exec::set_threads(2);
        two.build(sys->box.view(), sys->p, PolyCutoff{}, max_cutoff, kSkin, kind);
        EXPECT_GT(one.entries(), 0);
        one.to_host();
        two.to_host();
        EXPECT_EQ(one.offset(), two.offset());
        EXPECT_EQ(one.index(), two.index());
        EXPECT_EQ(one.candidates(), two.candidates());
      }
  exec::set_threads(before);
}

TEST(NeighborList, RowsFollowStencilThenCellOrder) {
  // Rebuilding from the same input gives the same arrays; within one stencil cell, ascending indices.
  const System s = random_system(800, {0, 0, 0}, {20, 20, 20}, {true, true, true}, 41);
  NeighborList a, b;
  a.set_max_size_classes(1);
  b.set_max_size_classes(1);
  a.build(s.box.view(), s.p, PolyCutoff{}, kMaxCutoff, kSkin, NeighborKind::full);
  b.build(s.box.view(), s.p, PolyCutoff{}, kMaxCutoff, kSkin, NeighborKind::full);
  a.to_host();
  b.to_host();
  EXPECT_EQ(a.index(), b.index());
  const auto& cell = a.cells().cell_of();
  for (int i = 0; i < a.rows(); ++i)
    for (int k = a.offset()[i] + 1; k < a.offset()[i + 1]; ++k) {
      const int j0 = a.index()[k - 1], j1 = a.index()[k];
      if (cell[j0] == cell[j1]) {
        EXPECT_LT(j0, j1);
      }
    }
}

TEST(NeighborList, PeriodicBoxShorterThanTwiceTheReachIsAnInputError) {
  const System s = random_system(50, {0, 0, 0}, {8.3, 20, 20}, {true, true, true}, 51);
  NeighborList nl;
  try {
    nl.build(s.box.view(), s.p, PolyCutoff{}, kMaxCutoff, kSkin, NeighborKind::full);
    FAIL() << "8.3 < 2 * (3.9 + 0.3)";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("box"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("8.3"), std::string::npos) << e.what();
  }
  // The same length on a non-periodic axis is fine.
  const System t = random_system(50, {0, 0, 0}, {8.3, 20, 20}, {false, true, true}, 51);
  EXPECT_NO_THROW(nl.build(t.box.view(), t.p, PolyCutoff{}, kMaxCutoff, kSkin, NeighborKind::full));
}

TEST(NeighborList, MaxCutoffBelowTheLargestPairIsAnInputError) {
  const System s = random_system(50, {0, 0, 0}, {20, 20, 20}, {true, true, true}, 61);
  NeighborList nl;
  for (double bad : {2.0, 0.0, -1.0}) {
    try {
      nl.build(s.box.view(), s.p, PolyCutoff{}, bad, kSkin, NeighborKind::full);
      ADD_FAILURE() << bad;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("neighbor.max_cutoff"), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(nl.build(s.box.view(), s.p, PolyCutoff{}, kMaxCutoff, -0.1, NeighborKind::full), InputError);
}

}  // namespace
}  // namespace debris
