#include "core/cell_list.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/device_counting_sort.hpp"
#include "core/device_scan.hpp"
#include "core/error.hpp"
#include "core/exec.hpp"

namespace debris {

namespace {

long long cells_on_axis(double len, double min_cell_size, bool periodic) {
  // Bounded before the conversion: a huge box over a tiny cell must not overflow.
  const double f = std::min(std::floor(len / min_cell_size), 1e9);
  long long nc = f >= 1 ? static_cast<long long>(f) : 1;
  if (periodic && nc < 3) nc = 1;
  return nc;
}

}  // namespace

CellList::Grid CellList::grid_for(const BoxView& box, long long n, double min_cell_size) {
  if (!(std::isfinite(min_cell_size) && min_cell_size > 0)) {
    std::ostringstream v;
    v << min_cell_size;
    throw input_error("cell_list.min_cell_size", v.str(), "must be finite and > 0");
  }
  long long nc[3];
  for (int a = 0; a < 3; ++a) nc[a] = cells_on_axis(box.len[a], min_cell_size, box.periodic[a] != 0);
  // Coarsen the finest axis until the grid is O(n): larger cells are always correct, only slower.
  const long long limit = max_cells(n);
  while (nc[0] * nc[1] * nc[2] > limit) {
    const int a = static_cast<int>(std::max_element(nc, nc + 3) - nc);
    nc[a] /= 2;
    if (nc[a] < 1 || (box.periodic[a] && nc[a] < 3)) nc[a] = 1;
  }
  Grid g;
  for (int a = 0; a < 3; ++a) {
    g.dims[static_cast<std::size_t>(a)] = static_cast<int>(nc[a]);
    g.edge[static_cast<std::size_t>(a)] = box.len[a] / g.dims[static_cast<std::size_t>(a)];
  }
  return g;
}

void CellList::build(const BoxView& box, const double* x, const double* y, const double* z, int n,
                     double min_cell_size, const int* gather) {
  const Grid g = grid_for(box, n, min_cell_size);
  for (int a = 0; a < 3; ++a) {
    dims_[a] = g.dims[static_cast<std::size_t>(a)];
    edge_[a] = g.edge[static_cast<std::size_t>(a)];
  }
  n_ = n;
  for (int a = 0; a < 3; ++a) periodic_[a] = box.periodic[a];
  const int ncell = cell_count();

  // resize keeps the capacity: no reallocation when n and the grid do not grow.
  cell_of_.resize(static_cast<std::size_t>(n));
  sorted_index_.resize(static_cast<std::size_t>(n));
  cell_start_.resize(static_cast<std::size_t>(ncell) + 1);
  cursor_.resize(static_cast<std::size_t>(ncell));

  const double* __restrict px = x;
  const double* __restrict py = y;
  const double* __restrict pz = z;
  int* __restrict cell = cell_of_.data();
  int* __restrict start = cell_start_.data();
  int* __restrict sorted = sorted_index_.data();
  int* __restrict cursor = cursor_.data();
  const double lo0 = box.lo[0], lo1 = box.lo[1], lo2 = box.lo[2];
  const double inv0 = 1.0 / edge_[0], inv1 = 1.0 / edge_[1], inv2 = 1.0 / edge_[2];
  const int n0 = dims_[0], n1 = dims_[1], n2 = dims_[2];
  const int p0 = box.periodic[0], p1 = box.periodic[1], p2 = box.periodic[2];
  if (gather) {
    const int* __restrict at = gather;
    DEBRIS_RESIDENT(px, py, pz, at, cell);
    DEBRIS_KERNEL
    for (int i = 0; i < n; ++i) {
      const int a = at[i];
      const int cx = cell_coordinate(px[a], lo0, inv0, n0, p0);
      const int cy = cell_coordinate(py[a], lo1, inv1, n1, p1);
      const int cz = cell_coordinate(pz[a], lo2, inv2, n2, p2);
      cell[i] = cx + n0 * (cy + n1 * cz);
    }
  } else {
    DEBRIS_RESIDENT(px, py, pz, cell);
    DEBRIS_KERNEL
    for (int i = 0; i < n; ++i) {
      const int cx = cell_coordinate(px[i], lo0, inv0, n0, p0);
      const int cy = cell_coordinate(py[i], lo1, inv1, n1, p1);
      const int cz = cell_coordinate(pz[i], lo2, inv2, n2, p2);
      cell[i] = cx + n0 * (cy + n1 * cz);
    }
  }

#if defined(DEBRIS_OFFLOAD_TARGET)
  // On the device: the serial counting sort's result, with one scalar (the scan's total) between host and
  // device.
  counting_sort_by_bucket(cell, n, ncell, start, cursor, sorted, scan_scratch_);
#else
  // Counting sort, serial: a small part of a rebuild, and deterministic.
  std::fill(start, start + ncell + 1, 0);
  for (int i = 0; i < n; ++i) ++start[cell[i] + 1];
  for (int c = 0; c < ncell; ++c) start[c + 1] += start[c];
  std::copy(start, start + ncell, cursor);
  for (int i = 0; i < n; ++i) sorted[cursor[cell[i]]++] = i;
#endif
}

void CellList::to_host() const {
  exec::to_host(cell_start_);
  exec::to_host(sorted_index_);
  exec::to_host(cell_of_);
}

std::vector<int> CellList::sort_order() const {
  exec::to_host(sorted_index_);
  return std::vector<int>(sorted_index_.begin(), sorted_index_.end());
}

namespace {
DEBRIS_DECLARE_TARGET
// The linear index (x fastest) of the cell at place r of the canonical visit: axis a0 fastest (d0 cells),
// then a1 (d1 cells), then a2.
inline int cell_at_rank(int r, int a0, int a1, int a2, int d0, int d1, int n0, int n1) {
  int c[3];
  c[a0] = r % d0;
  c[a1] = (r / d0) % d1;
  c[a2] = r / (d0 * d1);
  return c[0] + n0 * (c[1] + n1 * c[2]);
}
DEBRIS_END_DECLARE_TARGET
}  // namespace

void CellList::sort_order(const std::int64_t* key, exec::DeviceVector<int>& order) const {
  // Kernels over the cells in their canonical places: each place's particle count, the counts' prefix sum,
  // then each cell's particles (ascending index) copied to its place and insertion-sorted by key, stably:
  // a cell holds a handful of particles. Offload builds: where the cells are, one scalar back (the scan's).
  const int ncell = cell_count(), n = n_;
  order.resize(static_cast<std::size_t>(n));
  rank_start_.resize(static_cast<std::size_t>(ncell) + 1);
  const std::array<int, 3> ax = canonical_axes(periodic_);
  const int a0 = ax[0], a1 = ax[1], a2 = ax[2], d0 = dims_[ax[0]], d1 = dims_[ax[1]];
  const int n0 = dims_[0], n1 = dims_[1];
  const int* __restrict start = cell_start_.data();
  const int* __restrict sorted = sorted_index_.data();
  const std::int64_t* __restrict k = key;
  int* __restrict place = rank_start_.data();
  int* __restrict out = order.data();
  DEBRIS_RESIDENT(start, place);
  DEBRIS_KERNEL
  for (int r = 0; r < ncell; ++r) {
    if (r == 0) place[0] = 0;
    const int c = cell_at_rank(r, a0, a1, a2, d0, d1, n0, n1);
    place[r + 1] = start[c + 1] - start[c];
  }
  inclusive_scan(place + 1, ncell, rank_scan_);
  DEBRIS_RESIDENT(start, sorted, k, place, out);
  DEBRIS_KERNEL
  for (int r = 0; r < ncell; ++r) {
    const int c = cell_at_rank(r, a0, a1, a2, d0, d1, n0, n1);
    const int first = place[r], count = start[c + 1] - start[c];
    for (int t = 0; t < count; ++t) {
      const int v = sorted[start[c] + t];
      int h = first + t;
      for (; h > first && k[out[h - 1]] > k[v]; --h) out[h] = out[h - 1];
      out[h] = v;
    }
  }
}

std::vector<int> CellList::sort_order(const std::int64_t* key) const {
  exec::DeviceVector<std::int64_t> key_scratch;
  exec::DeviceVector<int> order;
  sort_order(exec::on_device(key, static_cast<std::size_t>(n_), key_scratch), order);
  exec::to_host(order);
  return std::vector<int>(order.begin(), order.end());
}

std::size_t CellList::bytes() const {
  return sizeof(int) * (cell_start_.capacity() + sorted_index_.capacity() + cell_of_.capacity() + cursor_.capacity() +
                         rank_start_.capacity());
}

}  // namespace debris
