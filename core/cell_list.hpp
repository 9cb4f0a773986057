#pragma once
// Binning of particles into a regular grid of cells by counting sort: cell of each particle (a kernel),
// count per cell, exclusive prefix sum (cell_start), stable fill (sorted_index). Neighbour searches visit
// the 27 cells around a particle's cell; sorting particles in memory by cell (Particles::permute with
// sort_order()) keeps those visits cache-friendly.
#include <array>
#include <cstddef>
#include <vector>

#include "core/box.hpp"

namespace debris {

class CellList {
 public:
  /// Bins n particles into cells whose edge is >= min_cell_size on every axis.
  /// Periodic axis: floor(len / min_cell_size) cells, or 1 cell when that is < 3 (the 27-cell stencil
  /// would otherwise visit a cell twice; minimum image handles the rest); an unwrapped coordinate is
  /// binned as its periodic image. Non-periodic axis: cells cover [lo, lo + len), particles outside are
  /// clamped into the first / last cell, which keeps neighbours within one cell of each other.
  /// The grid is coarsened if it would exceed max_cells(n) cells (sparse systems in large boxes).
  /// Throws InputError ("cell_list.min_cell_size") unless min_cell_size is finite and > 0.
  void build(const BoxView& box, const double* x, const double* y, const double* z, int n, double min_cell_size);

  std::array<int, 3> dims() const { return {dims_[0], dims_[1], dims_[2]}; }
  int cell_count() const { return dims_[0] * dims_[1] * dims_[2]; }
  /// Edge length of the cells along each axis (len / dims).
  std::array<double, 3> cell_edge() const { return {edge_[0], edge_[1], edge_[2]}; }
  int particles() const { return n_; }

  /// Size cell_count() + 1: particles of cell c are sorted_index()[cell_start()[c] .. cell_start()[c+1]).
  const std::vector<int>& cell_start() const { return cell_start_; }
  /// Particle indices grouped by cell, ascending within a cell (deterministic).
  const std::vector<int>& sorted_index() const { return sorted_index_; }
  /// Cell of each particle.
  const std::vector<int>& cell_of() const { return cell_of_; }

  /// Linear index of cell (cx, cy, cz), x fastest.
  int cell_index(int cx, int cy, int cz) const { return cx + dims_[0] * (cy + dims_[1] * cz); }

  /// New order that groups particles by cell, for Particles::permute: sorted_index() itself.
  std::vector<int> sort_order() const { return sorted_index_; }

  /// Bytes held by the arrays.
  std::size_t bytes() const;

  /// Upper bound on the number of cells for n particles: cell bookkeeping stays O(n) in memory and time.
  static long long max_cells(int n) { return 8LL * (n > 0 ? n : 0) + 4096; }

 private:
  int dims_[3] = {0, 0, 0};
  double edge_[3] = {0, 0, 0};
  int n_ = 0;
  std::vector<int> cell_start_;
  std::vector<int> sorted_index_;
  std::vector<int> cell_of_;
  std::vector<int> cursor_;  // fill position per cell, kept to avoid reallocating
};

}  // namespace debris
