// CellList: grid dimensions, every particle in exactly one cell, cell coordinates recomputed independently,
// clamping outside a non-periodic box, periodic images of unwrapped coordinates, deterministic order.
// Offload builds: build() reads the positions on the device, so the test's points are device-resident
// columns sent there after every host-side change; the three arrays it returns are current on both sides.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "core/canonical_order.hpp"
#include "core/cell_list.hpp"
#include "core/error.hpp"
#include "core/exec.hpp"
#include "core/particles.hpp"

namespace debris {
namespace {

BoxView make_view(double lx, double ly, double lz, bool px, bool py, bool pz, double lo = 0.0) {
  BoxView b{};
  const double len[3] = {lx, ly, lz};
  const bool per[3] = {px, py, pz};
  for (int a = 0; a < 3; ++a) {
    b.lo[a] = lo;
    b.len[a] = len[a];
    b.periodic[a] = per[a] ? 1 : 0;
  }
  return b;
}

struct Points {
  exec::DeviceVector<double> x, y, z;
  int n() const { return static_cast<int>(x.size()); }
  void add(double px, double py, double pz) {
    x.push_back(px);
    y.push_back(py);
    z.push_back(pz);
  }
  /// Host -> device after the host changed the points (no-op in host builds).
  void to_device() const {
    exec::to_device(x);
    exec::to_device(y);
    exec::to_device(z);
  }
};

/// build() on the points as they are on the host now.
void build(CellList& cl, const BoxView& b, const Points& p, double min_cell_size) {
  p.to_device();
  cl.build(b, p.x.data(), p.y.data(), p.z.data(), p.n(), min_cell_size);
  cl.to_host();  // offload builds: the counting sort ran on the device
}

// Independent reference for the cell coordinate along one axis.
int expected_coord(double x, double lo, double len, int nc, bool periodic) {
  if (periodic) x = lo + (x - lo) - len * std::floor((x - lo) / len);
  const int c = static_cast<int>(std::floor((x - lo) / (len / nc)));
  return c < 0 ? 0 : (c >= nc ? nc - 1 : c);
}

void expect_consistent(const CellList& cl, const BoxView& b, const Points& p) {
  const int ncell = cl.cell_count();
  const auto dims = cl.dims();
  ASSERT_EQ(ncell, dims[0] * dims[1] * dims[2]);
  ASSERT_EQ(cl.cell_start().size(), static_cast<std::size_t>(ncell) + 1);
  ASSERT_EQ(cl.cell_start().front(), 0);
  ASSERT_EQ(cl.cell_start().back(), p.n());
  ASSERT_EQ(cl.sorted_index().size(), static_cast<std::size_t>(p.n()));
  ASSERT_EQ(cl.cell_of().size(), static_cast<std::size_t>(p.n()));

  // Every particle exactly once, in the range of its own cell, ascending within a cell.
  std::vector<int> seen(p.n(), 0);
  for (int c = 0; c < ncell; ++c) {
    ASSERT_LE(cl.cell_start()[c], cl.cell_start()[c + 1]);
    for (int k = cl.cell_start()[c]; k < cl.cell_start()[c + 1]; ++k) {
      const int i = cl.sorted_index()[k];
      ASSERT_GE(i, 0);
      ASSERT_LT(i, p.n());
      ++seen[i];
      EXPECT_EQ(cl.cell_of()[i], c);
      if (k > cl.cell_start()[c]) {
        EXPECT_LT(cl.sorted_index()[k - 1], i);
      }
    }
  }
  for (int i = 0; i < p.n(); ++i) EXPECT_EQ(seen[i], 1) << "particle " << i;

  // Cell coordinates agree with an independent computation.
  const exec::DeviceVector<double>* pos[3] = {&p.x, &p.y, &p.z};
  for (int i = 0; i < p.n(); ++i) {
    int c[3];
    for (int a = 0; a < 3; ++a) c[a] = expected_coord((*pos[a])[i], b.lo[a], b.len[a], dims[a], b.periodic[a]);
    EXPECT_EQ(cl.cell_of()[i], cl.cell_index(c[0], c[1], c[2])) << "particle " << i;
  }
}

TEST(CellList, DimensionsFollowTheAxisRules) {
  CellList cl;
  const double* no_points = nullptr;  // no particles: nothing is read
  // Periodic: floor(len / size), or 1 when that is below 3.
  cl.build(make_view(10.0, 5.5, 30.0, true, true, true), no_points, no_points, no_points, 0, 2.5);
  EXPECT_EQ(cl.dims(), (std::array<int, 3>{4, 1, 12}));
  EXPECT_DOUBLE_EQ(cl.cell_edge()[0], 2.5);
  EXPECT_DOUBLE_EQ(cl.cell_edge()[1], 5.5);
  cl.build(make_view(7.6, 7.4, 2.0, true, true, true), no_points, no_points, no_points, 0, 2.5);
  EXPECT_EQ(cl.dims(), (std::array<int, 3>{3, 1, 1}));
  // Non-periodic: floor(len / size), at least 1; 2 cells are fine.
  cl.build(make_view(10.0, 5.5, 2.0, false, false, false), no_points, no_points, no_points, 0, 2.5);
  EXPECT_EQ(cl.dims(), (std::array<int, 3>{4, 2, 1}));
  EXPECT_EQ(cl.cell_count(), 8);
  EXPECT_EQ(cl.cell_index(1, 1, 0), 5);
  EXPECT_GE(cl.cell_edge()[0], 2.5);
  EXPECT_GE(cl.cell_edge()[1], 2.5);
  EXPECT_DOUBLE_EQ(cl.cell_edge()[2], 2.0);  // shorter than the cell size: one cell, the whole axis
}

TEST(CellList, RandomParticlesLandInTheirCellsOnEveryBoxKind) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const BoxView boxes[] = {make_view(20.0, 13.0, 9.0, true, true, true, -4.0),
                           make_view(20.0, 13.0, 9.0, false, false, false, -4.0),
                           make_view(20.0, 13.0, 9.0, true, false, true, -4.0)};
  for (const BoxView& b : boxes) {
    Points p;
    for (int i = 0; i < 1500; ++i) {
      double r[3];
      for (int a = 0; a < 3; ++a) {
        // Non-periodic axes: 10% of the particles up to 2 lengths outside, to exercise clamping.
        const double t = b.periodic[a] ? u(rng) : -0.1 + 1.2 * u(rng);
        r[a] = b.lo[a] + t * b.len[a];
      }
      p.add(r[0], r[1], r[2]);
    }
    CellList cl;
    build(cl, b, p, 2.1);
    SCOPED_TRACE(std::to_string(b.periodic[0]) + std::to_string(b.periodic[1]) + std::to_string(b.periodic[2]));
    expect_consistent(cl, b, p);
    EXPECT_EQ(cl.sort_order(), cl.sorted_index());
  }
}

TEST(CellList, OutsideANonPeriodicBoxIsClampedIntoTheEdgeCells) {
  const BoxView b = make_view(10.0, 10.0, 10.0, false, false, false);
  Points p;
  p.add(-50.0, 5.0, 5.0);   // far below x: first cell on x
  p.add(60.0, 5.0, 5.0);    // far above x: last cell on x
  p.add(10.0, 10.0, 10.0);  // exactly on hi: last cell on every axis
  p.add(-0.01, 10.5, 0.0);
  CellList cl;
  build(cl, b, p, 2.0);
  ASSERT_EQ(cl.dims(), (std::array<int, 3>{5, 5, 5}));
  EXPECT_EQ(cl.cell_of()[0], cl.cell_index(0, 2, 2));
  EXPECT_EQ(cl.cell_of()[1], cl.cell_index(4, 2, 2));
  EXPECT_EQ(cl.cell_of()[2], cl.cell_index(4, 4, 4));
  EXPECT_EQ(cl.cell_of()[3], cl.cell_index(0, 4, 0));
  expect_consistent(cl, b, p);
}

TEST(CellList, UnwrappedCoordinateOnAPeriodicAxisUsesItsImage) {
  const BoxView b = make_view(10.0, 10.0, 10.0, true, true, true);
  Points p;
  p.add(10.5, 5.0, 5.0);   // image 0.5: first cell
  p.add(-0.5, 5.0, 5.0);   // image 9.5: last cell
  p.add(25.1, -13.0, 5.0);  // images 5.1 and 7.0
  CellList cl;
  build(cl, b, p, 2.0);
  EXPECT_EQ(cl.cell_of()[0], cl.cell_index(0, 2, 2));
  EXPECT_EQ(cl.cell_of()[1], cl.cell_index(4, 2, 2));
  EXPECT_EQ(cl.cell_of()[2], cl.cell_index(2, 3, 2));
}

TEST(CellList, RebuildWithTheSameCountReusesTheArrays) {
  const BoxView b = make_view(12.0, 12.0, 12.0, true, true, true);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0.0, 12.0);
  Points p;
  for (int i = 0; i < 500; ++i) p.add(u(rng), u(rng), u(rng));
  CellList cl;
  build(cl, b, p, 3.0);
  const int* sorted = cl.sorted_index().data();
  const int* start = cl.cell_start().data();
  const int* cell = cl.cell_of().data();
  for (int i = 0; i < p.n(); ++i) p.x[i] = u(rng);
  build(cl, b, p, 3.0);
  EXPECT_EQ(cl.sorted_index().data(), sorted);
  EXPECT_EQ(cl.cell_start().data(), start);
  EXPECT_EQ(cl.cell_of().data(), cell);
  expect_consistent(cl, b, p);
  EXPECT_GE(cl.bytes(), sizeof(int) * (2 * 500 + 64 + 1));
}

TEST(CellList, SparseSystemInAHugeBoxIsCoarsenedNotExploded) {
  const BoxView b = make_view(1e6, 1e6, 1e6, false, false, true);
  Points p;
  p.add(1.0, 2.0, 3.0);
  p.add(5e5, 5e5, 5e5);
  CellList cl;
  build(cl, b, p, 1.0);
  EXPECT_LE(cl.cell_count(), CellList::max_cells(p.n()));
  for (int a = 0; a < 3; ++a) EXPECT_GE(cl.cell_edge()[a], 1.0);
  EXPECT_NE(cl.dims()[2], 2);  // a periodic axis never has 2 cells
  expect_consistent(cl, b, p);
}

TEST(CellList, BadCellSizeIsAnInputError) {
  CellList cl;
  const double v = 0;
  for (double size : {0.0, -1.0, std::nan("")}) {
    try {
      cl.build(make_view(1, 1, 1, false, false, false), &v, &v, &v, 1, size);
      ADD_FAILURE() << size;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("cell_list.min_cell_size"), std::string::npos);
    }
  }
}

}  // namespace
}  // namespace debris

namespace debris {
namespace {

// The canonical order a rank computes for its share (core/canonical_order: the whole system's grid, then
// id) is the order a one-process run's cell sort gives (CellList::sort_order(ids) over all particles), so
// the two agree particle for particle; and it does not depend on the order the particles came in.
// Host arrays only (canonical_order reads host copies; the cell sort is checked on the device above).
TEST(CanonicalOrder, EqualsTheWholeSystemsCellSortByIdInAnyInputOrder) {
  if (exec::offload_build()) GTEST_SKIP() << "host copies only";
  // Walled in x and z, periodic everywhere, and walled in y or in x alone (the walled axis goes slowest).
  for (const auto per : {std::array<bool, 3>{false, true, false}, std::array<bool, 3>{true, true, true},
                         std::array<bool, 3>{true, false, true}, std::array<bool, 3>{false, true, true}}) {
    const BoxView b = make_view(7.3, 5.1, 4.4, per[0], per[1], per[2], -1.0);
    Particles p;
    std::mt19937_64 rng(21);
    std::uniform_real_distribution<double> ux(-1.0, 6.3), uy(-1.0, 4.1), uz(-1.0, 3.4);
    for (int i = 0; i < 3000; ++i) p.add(1000 - i, 1, ux(rng), uy(rng), uz(rng), 0.1);
    // Particles sharing a cell (exact duplicates of a position too): only the ids order them.
    for (int i = 0; i < 50; ++i) p.add(5000 + i, 1, 0.5, 0.5, 0.5, 0.1);
    const double cell = 0.9;
    CellList cl;
    cl.build(b, p.x.data(), p.y.data(), p.z.data(), static_cast<int>(p.size()), cell);
    const std::vector<int> by_cells = cl.sort_order(p.id.data());
    const CanonicalGrid g = CanonicalGrid::of(b, static_cast<long long>(p.size()), cell);
    EXPECT_EQ(canonical_order(g, p), by_cells);
    // Layer after layer along the slowest axis: z, or the walled axis where z is periodic.
    const int slow = !per[2] || (per[0] && per[1]) ? 2 : (!per[1] ? 1 : 0);
    EXPECT_EQ(canonical_axes(b.periodic)[2], slow);
    const auto dims = cl.dims();
    const std::array<const double*, 3> coord{p.x.data(), p.y.data(), p.z.data()};
    int last = 0;
    for (const int i : by_cells) {
      const auto a = static_cast<std::size_t>(slow);
      const int layer = cell_coordinate(coord[a][i], b.lo[slow],
                                        1.0 / cl.cell_edge()[a], dims[a], b.periodic[slow]);
      ASSERT_GE(layer, last);
      last = layer;
    }
    // Shuffled input: the same particles (by id) in the same places of the order.
    Particles q = p;
    std::vector<int> shuffle(p.size());
    for (std::size_t i = 0; i < shuffle.size(); ++i) shuffle[i] = static_cast<int>(i);
    std::shuffle(shuffle.begin(), shuffle.end(), rng);
    q.permute(shuffle);
    const std::vector<int> oq = canonical_order(g, q);
    for (std::size_t i = 0; i < oq.size(); ++i)
      ASSERT_EQ(q.id[static_cast<std::size_t>(oq[i])], p.id[static_cast<std::size_t>(by_cells[i])]) << i;
  }
}

}  // namespace
}  // namespace debris
