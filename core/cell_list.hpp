#pragma once
// Binning of particles into a regular grid of cells by counting sort: cell of each particle (a kernel),
// count per cell, exclusive prefix sum (cell_start), stable fill (sorted_index); all on the device in
// offload builds. Neighbour searches visit
// the 27 cells around a particle's cell; sorting particles in memory by cell (Particles::permute with
// sort_order()) keeps those visits cache-friendly.
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/box.hpp"
#include "core/exec.hpp"

namespace debris {

DEBRIS_DECLARE_TARGET
/// Cell coordinate of x along one axis of nc cells of edge 1 / inv_edge from lo. Periodic: the periodic
/// image of the coordinate, so an unwrapped particle still lands in the right cell. Otherwise clamped into
/// [0, nc). fmax maps NaN to 0, so bad input can never index outside the grid. Public so that a search can
/// place a point that is not in the grid (another size class) exactly as build() would.
inline int cell_coordinate(double x, double lo, double inv_edge, int nc, int periodic) {
  double t = (x - lo) * inv_edge;
  if (periodic) t -= nc * std::floor(t / nc);
  t = std::fmin(std::fmax(t, 0.0), nc - 1.0);
  return static_cast<int>(t);
}
DEBRIS_END_DECLARE_TARGET

/// The order the canonical order (sort_order(key), core/canonical_order) visits cells in: the axes from the
/// fastest to the slowest. x fastest and z slowest, unless z is periodic and another axis is walled: that
/// axis goes slowest. Why: threads own contiguous rows of the half-list pass, and along a periodic slowest
/// axis the first layer of cells has its partners across the face in the last layer, held by another
/// thread, so every step their data crossed between cores (the Table 6 junction, walled in y and periodic
/// in z, gained nothing from a second thread). Along a walled axis a layer's partners are its neighbours.
inline std::array<int, 3> canonical_axes(const int periodic[3]) {
  if (!periodic[2]) return {0, 1, 2};
  if (!periodic[1]) return {0, 2, 1};
  if (!periodic[0]) return {1, 2, 0};
  return {0, 1, 2};
}

class CellList {
 public:
  /// Bins n particles into cells whose edge is >= min_cell_size on every axis. In offload builds x, y, z
  /// must be on the device (device copies are read).
  /// Periodic axis: floor(len / min_cell_size) cells, or 1 cell when that is < 3 (the 27-cell stencil
  /// would otherwise visit a cell twice; minimum image handles the rest); an unwrapped coordinate is
  /// binned as its periodic image. Non-periodic axis: cells cover [lo, lo + len), particles outside are
  /// clamped into the first / last cell, which keeps neighbours within one cell of each other.
  /// The grid is coarsened if it would exceed max_cells(n) cells (sparse systems in large boxes).
  /// Throws InputError ("cell_list.min_cell_size") unless min_cell_size is finite and > 0.
  /// With `gather`, particle i of the n is the one at gather[i] in x, y, z (a subset binned without a copy of
  /// its coordinates); sorted_index() and cell_of() still count 0 .. n-1.
  void build(const BoxView& box, const double* x, const double* y, const double* z, int n, double min_cell_size,
             const int* gather = nullptr);

  std::array<int, 3> dims() const { return {dims_[0], dims_[1], dims_[2]}; }
  int cell_count() const { return dims_[0] * dims_[1] * dims_[2]; }
  /// Edge length of the cells along each axis (len / dims); build() bins with 1.0 / cell_edge()[a].
  std::array<double, 3> cell_edge() const { return {edge_[0], edge_[1], edge_[2]}; }
  int particles() const { return n_; }

  /// Size cell_count() + 1: particles of cell c are sorted_index()[cell_start()[c] .. cell_start()[c+1]).
  const exec::DeviceVector<int>& cell_start() const { return cell_start_; }
  /// Particle indices grouped by cell, ascending within a cell (deterministic).
  const exec::DeviceVector<int>& sorted_index() const { return sorted_index_; }
  /// Cell of each particle.
  const exec::DeviceVector<int>& cell_of() const { return cell_of_; }

  /// Linear index of cell (cx, cy, cz), x fastest.
  int cell_index(int cx, int cy, int cz) const { return cx + dims_[0] * (cy + dims_[1] * cz); }

  /// New order that groups particles by cell, for Particles::permute: sorted_index() itself (offload builds:
  /// brought to the host first).
  std::vector<int> sort_order() const;
  /// The canonical order: by cell, the cells in canonical_axes() order (x fastest; the slowest axis z, or a
  /// walled one), each cell's particles in increasing `key` (host array, one per particle: the permanent ids).
  /// The order then depends only on the positions and the ids, not on the order the particles came in: the
  /// canonical order that makes sums the same bits on any storage order, and so on any rank count
  /// (shared/design/scale-mpi.md, section 4).
  std::vector<int> sort_order(const std::int64_t* key) const;
  /// The same order into `order`, computed where the cells are (offload builds: key on the device, order
  /// left there; only the prefix sum's total moves).
  void sort_order(const std::int64_t* key, exec::DeviceVector<int>& order) const;

  /// Offload builds: the three arrays are built on the device; a host reader brings them back first.
  void to_host() const;
  /// Bytes held by the arrays.
  std::size_t bytes() const;

  /// Upper bound on the number of cells for n particles: cell bookkeeping stays O(n) in memory and time.
  static long long max_cells(long long n) { return 8LL * (n > 0 ? n : 0) + 4096; }

  /// The grid build() makes for n particles: cells per axis and their edges. A rank that holds a part of a
  /// system asks for the whole system's grid with the whole count (core/canonical_order).
  struct Grid {
    std::array<int, 3> dims{};
    std::array<double, 3> edge{};
  };
  static Grid grid_for(const BoxView& box, long long n, double min_cell_size);

 private:
  int dims_[3] = {0, 0, 0};
  double edge_[3] = {0, 0, 0};
  int n_ = 0;
  int periodic_[3] = {0, 0, 0};
  // Offload builds: the arrays are built on the device and stay there (to_host() for a host reader).
  exec::DeviceVector<int> cell_start_;
  exec::DeviceVector<int> sorted_index_;
  exec::DeviceVector<int> cell_of_;
  exec::DeviceVector<int> cursor_;              // fill position per cell, kept to avoid reallocating
  exec::DeviceVector<long long> scan_scratch_;  // the prefix sum's block sums
  // sort_order's scratch: where each canonical place's particles start, and the prefix sum's block sums.
  mutable exec::DeviceVector<int> rank_start_;
  mutable exec::DeviceVector<long long> rank_scan_;
};

}  // namespace debris
