#pragma once
// The order particles are stored in, the same whatever order they came in and however the box is cut among
// ranks (shared/design/scale-mpi.md, section 4): by the cell of one grid (cells in canonical_axes order),
// then by permanent id. The grid is
// the one CellList::build makes for the whole box and the whole system's particle count, so a rank that
// holds its own particles and its ghosts computes every key exactly as a one-process run does (a ghost is
// binned by its owner's coordinates, which it keeps bit for bit). With storage in this order and each
// neighbour row in increasing index, every per-particle sum of the half-list pass adds the same terms in the
// same order on any rank count.
#include <vector>

#include "core/box.hpp"
#include "core/cell_list.hpp"
#include "core/particles.hpp"

namespace debris {

struct CanonicalGrid {
  BoxView box{};
  CellList::Grid grid;
  /// The grid of CellList::build for `n_total` particles in `box` with cells at least `cell_size` wide.
  static CanonicalGrid of(const BoxView& box, long long n_total, double cell_size);
  /// The place, in the canonical order of cells (canonical_axes), of the cell a point falls in (as
  /// CellList::build bins it: periodic images folded, walled axes clamped).
  long long cell_of(double x, double y, double z) const;
};

/// The permutation that sorts `p` (host copies) by (cell, id): new index i holds the particle at order[i].
std::vector<int> canonical_order(const CanonicalGrid& g, const Particles& p);

}  // namespace debris
