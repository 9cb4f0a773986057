#pragma once
// The rank grids the tests of tests/mpi try at each rank count: cuts along one axis, each of the three, and
// along two (and three at 8 ranks).
#include <array>
#include <vector>

namespace debris::test {

inline std::vector<std::array<int, 3>> grids_for(int ranks) {
  switch (ranks) {
    case 1: return {{1, 1, 1}};
    case 2: return {{2, 1, 1}, {1, 2, 1}, {1, 1, 2}};
    case 3: return {{3, 1, 1}, {1, 3, 1}, {1, 1, 3}};
    case 4: return {{2, 2, 1}, {4, 1, 1}, {1, 2, 2}};
    case 8: return {{2, 2, 2}};
    default: return {{ranks, 1, 1}};
  }
}

}  // namespace debris::test
