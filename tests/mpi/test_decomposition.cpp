// comm::Decomposition: the grid with the least surface, ownership on cut planes, thin subdomains refused.
#include <gtest/gtest.h>

#include <string>

#include "core/comm/decomposition.hpp"
#include "core/error.hpp"
#include "core/particles.hpp"

namespace debris::comm {
namespace {

Box box_of(double lx, double ly, double lz, bool periodic = true) {
  return Box({0, 0, 0}, {lx, ly, lz}, {periodic, periodic, periodic});
}

TEST(Decomposition, LeastSurfaceGrid) {
  EXPECT_EQ(Decomposition::make(box_of(1, 1, 1), 8, 0, 0.1).grid(), (std::array<int, 3>{2, 2, 2}));
  EXPECT_EQ(Decomposition::make(box_of(4, 1, 1), 4, 0, 0.1).grid(), (std::array<int, 3>{4, 1, 1}));
  EXPECT_EQ(Decomposition::make(box_of(1, 3, 1), 3, 0, 0.1).grid(), (std::array<int, 3>{1, 3, 1}));
  EXPECT_EQ(Decomposition::make(box_of(2, 2, 1), 4, 0, 0.1).grid(), (std::array<int, 3>{2, 2, 1}));
  // A tie (a cube on two ranks) goes to the cut along x.
  EXPECT_EQ(Decomposition::make(box_of(1, 1, 1), 2, 0, 0.1).grid(), (std::array<int, 3>{2, 1, 1}));
  // 12 ranks on 3 x 2 x 2: the box's own proportions.
  EXPECT_EQ(Decomposition::make(box_of(3, 2, 2), 12, 0, 0.1).grid(), (std::array<int, 3>{3, 2, 2}));
  // Thin subdomains are skipped: with ghost width 0.2 a unit box takes two subdomains per axis at most, so
  // not 4 x 1 x 1.
  EXPECT_EQ(Decomposition::make(box_of(1, 1, 1), 4, 0, 0.2).grid(), (std::array<int, 3>{2, 2, 1}));
}

TEST(Decomposition, RanksAndNeighbours) {
  const Box periodic = box_of(3, 2, 1), walled = box_of(3, 2, 1, false);
  const auto d = Decomposition::make(periodic, 6, 5, 0.1);  // 3 x 2 x 1, rank 5 at (2, 1, 0)
  ASSERT_EQ(d.grid(), (std::array<int, 3>{3, 2, 1}));
  EXPECT_EQ(d.coord(), (std::array<int, 3>{2, 1, 0}));
  EXPECT_EQ(d.rank(), 5);
  EXPECT_EQ(d.neighbour(periodic, 0, +1), 3);  // wraps to (0, 1, 0)
  EXPECT_EQ(d.neighbour(periodic, 0, -1), 4);
  EXPECT_EQ(d.neighbour(periodic, 1, +1), 2);  // (2, 0, 0)
  const auto w = Decomposition::make(walled, 6, 5, 0.1);
  EXPECT_EQ(w.neighbour(walled, 0, +1), -1);
  EXPECT_EQ(w.neighbour(walled, 1, +1), -1);
  EXPECT_EQ(w.neighbour(walled, 1, -1), 2);
  for (int r = 0; r < 6; ++r) EXPECT_EQ(d.rank_of(d.coord_of_rank(r)), r);
}

TEST(Decomposition, CutPlanesBelongToTheRankAbove) {
  const Box box({-1, 0, 0}, {2, 1, 1}, {true, false, true});
  const auto d = Decomposition::make(box, 3, 0, 0.1, {3, 1, 1});
  EXPECT_EQ(d.cut(box, 0, 0), -1.0);
  EXPECT_EQ(d.cut(box, 0, 3), 2.0);
  const double c1 = d.cut(box, 0, 1), c2 = d.cut(box, 0, 2);
  EXPECT_EQ(d.index_along(box, 0, c1), 1);
  EXPECT_EQ(d.index_along(box, 0, std::nextafter(c1, -1.0)), 0);
  EXPECT_EQ(d.index_along(box, 0, c2), 2);
  EXPECT_EQ(d.index_along(box, 0, -1.0), 0);
  EXPECT_EQ(d.index_along(box, 0, std::nextafter(2.0, 0.0)), 2);
  // Outside the box (a walled axis) the end subdomains own what strayed.
  EXPECT_EQ(d.index_along(box, 0, -5.0), 0);
  EXPECT_EQ(d.index_along(box, 0, 7.0), 2);
  EXPECT_EQ(d.owner(box, c2, 0.5, 0.5), 2);
}

TEST(Decomposition, CutsFollowADeformingBox) {
  Box box({0, 0, 0}, {4, 1, 1}, {true, true, true});
  const auto d = Decomposition::make(box, 4, 1, 0.1);
  EXPECT_EQ(d.sub_lo(box, 0), 1.0);
  EXPECT_EQ(d.sub_hi(box, 0), 2.0);
  Particles none;
  box.deform({-0.5, 0, 0}, {7.5, 1, 1}, none);
  EXPECT_EQ(d.sub_lo(box, 0), 1.5);
  EXPECT_EQ(d.sub_hi(box, 0), 3.5);
}

TEST(Decomposition, ThinSubdomainsAreANamedInputError) {
  // Ghost width 0.3 in a 1 x 1 x 2 box: at most 1, 1 and 3 subdomains per axis, so 4 ranks cannot fit.
  try {
    Decomposition::make(box_of(1, 1, 2), 4, 0, 0.3);
    FAIL() << "no error";
  } catch (const InputError& e) {
    const std::string m = e.what();
    // Named for what the user can change (the rank count, the box), lengths without a unit of their own.
    EXPECT_NE(m.find("'mpirun -np' = 4: no grid of 4 ranks fits this box: this box, 1 x 1 x 2, takes at most 1 along "
                     "x, 1 along y and 3 along z (3 ranks in all)"),
              std::string::npos)
        << m;
    EXPECT_NE(m.find("(2 x 0.3: the pair cutoff + skin"), std::string::npos) << m;
    EXPECT_NE(m.find("start at most 3 ranks (mpirun -np 3), or make the box larger"), std::string::npos) << m;
  }
  // A requested grid too thin, and one that does not multiply to the rank count.
  EXPECT_THROW(Decomposition::make(box_of(1, 1, 2), 2, 0, 0.3, {2, 1, 1}), InputError);
  EXPECT_NO_THROW(Decomposition::make(box_of(1, 1, 2), 2, 0, 0.3, {1, 1, 2}));
  try {
    Decomposition::make(box_of(1, 1, 1), 4, 0, 0.1, {2, 1, 1}, "run.rank_grid");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("'run.rank_grid' = 2 x 1 x 1: the grid must multiply to the rank count, 4"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace debris::comm
