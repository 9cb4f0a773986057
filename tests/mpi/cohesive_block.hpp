#pragma once
// The cohesive block the tests of tests/mpi cut among ranks: an FCC lattice of spheres 100 length units
// wide at contact, sizes spread 2% (every pair its own constants) and positions displaced by 0.3.
#include <array>
#include <cstdint>

#include "core/lattice.hpp"

namespace debris::test {

inline Lattice cohesive_block(std::array<int, 3> cells, std::uint64_t seed) {
  LatticeSpec spec;
  spec.kind = LatticeKind::fcc;
  spec.spacing = 100;
  spec.diameter = 100;
  spec.size_spread = 0.02;
  spec.displacement = 0.3;
  spec.cells = cells;
  spec.seed = seed;
  return make_lattice(spec);
}

}  // namespace debris::test
