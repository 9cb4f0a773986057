#include "core/neighbor_list.hpp"

#include <stdexcept>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <type_traits>

#include "core/device_scan.hpp"
#include "core/error.hpp"

namespace debris {

double NeighborList::max_radius(const Particles& p) {
  const int n = static_cast<int>(p.size());
  const double* __restrict r = p.radius.data();
  double r_max = 0.0;
  DEBRIS_RESIDENT(r);
  DEBRIS_KERNEL_MAX(r_max)
  for (int i = 0; i < n; ++i) r_max = r[i] > r_max ? r[i] : r_max;
  return r_max;
}

void NeighborList::set_max_size_classes(int classes) {
  if (classes < 1 || classes > SizeClasses::kMax)
    throw input_error("neighbor.size_classes", std::to_string(classes),
                      "must be 1 to " + std::to_string(SizeClasses::kMax));
  max_classes_ = classes;
}

void NeighborList::bin_classes(const BoxView& box, const Particles& p, const double* reach) {
  // Every array here is where the kernels run (offload builds: on the device); the host sees only the class
  // counts (from SizeClasses::of_resident) and each grid's dimensions, and a build moves scalars only.
  const int n = static_cast<int>(p.size()), k = classes_.count;
  const std::size_t un = static_cast<std::size_t>(n);
  int first[SizeClasses::kMax + 1] = {};
  for (int c = 0; c < k; ++c) first[c + 1] = first[c] + classes_.members[c];
  resize_for_overwrite(class_of_, un);
  resize_for_overwrite(members_, un);
  const double* __restrict r = p.radius.data();
  const double* __restrict x = p.x.data();
  const double* __restrict y = p.y.data();
  const double* __restrict z = p.z.data();
  int* __restrict cls = class_of_.data();
  const double l1 = classes_.lower[1], l2 = classes_.lower[2], l3 = classes_.lower[3];
  DEBRIS_RESIDENT(r, cls);
  DEBRIS_KERNEL
  for (int i = 0; i < n; ++i) cls[i] = size_class(r[i], k, l1, l2, l3);
  // Members of each class in increasing index (a stable partition: one prefix sum of "is in class c" per
  // class), so that every cell of every grid lists its particles in increasing index, as the single grid
  // does (the half list relies on it).
  exec::DeviceVector<int> rank;  // transient: n ints for the duration of the binning
  resize_for_overwrite(rank, un);
  int* __restrict rk = rank.data();
  int* __restrict mem = members_.data();
  for (int c = 0; c < k; ++c) {
    if (classes_.members[c] == 0) continue;
    DEBRIS_RESIDENT(cls, rk);
    DEBRIS_KERNEL
    for (int i = 0; i < n; ++i) rk[i] = cls[i] == c ? 1 : 0;
    const long long in_class = inclusive_scan(rk, n, scan_scratch_);
    if (in_class != classes_.members[c])
      throw std::logic_error("NeighborList::bin_classes: class " + std::to_string(c) + " holds " +
                             std::to_string(in_class) + " particles, its count says " +
                             std::to_string(classes_.members[c]));
    const int base = first[c] - 1;  // rk[i] is 1-based within the class
    DEBRIS_RESIDENT(cls, rk, mem);
    DEBRIS_KERNEL
    for (int i = 0; i < n; ++i)
      if (cls[i] == c) mem[base + rk[i]] = i;
  }

  // Grid (a, c): class c's members in cells at least reach(a, c) wide. All grids go into two flat arrays
  // (cell starts index the shared particle array directly, and each grid's entries are particle indices,
  // not member ranks), sized from the grids' dimensions first; then one CellList bins each grid in turn
  // (reading the members' coordinates through members_) and is copied into place, so the build holds one
  // grid's binning at a time, not k^2 of them.
  grids_ = ClassGrids{};
  grids_.classes = k;
  std::size_t starts = 0, sorted = 0;
  for (int a = 0; a < k; ++a)
    for (int c = 0; c < k; ++c) {
      if (classes_.members[a] == 0 || classes_.members[c] == 0) continue;
      const CellList::Grid g = CellList::grid_for(box, classes_.members[c], reach[a * k + c]);
      starts += static_cast<std::size_t>(g.dims[0]) * static_cast<std::size_t>(g.dims[1]) *
                    static_cast<std::size_t>(g.dims[2]) +
                1;
      sorted += static_cast<std::size_t>(classes_.members[c]);
    }
  resize_for_overwrite(grid_start_, starts);
  resize_for_overwrite(grid_sorted_, sorted);
  int* __restrict gs = grid_start_.data();
  int* __restrict gi = grid_sorted_.data();
  int start_base = 0, sorted_base = 0;
  for (int a = 0; a < k; ++a)
    for (int c = 0; c < k; ++c) {
      if (classes_.members[a] == 0 || classes_.members[c] == 0) continue;
      CellList& cl = grid_cells_;
      const int* m = mem + first[c];
      cl.build(box, x, y, z, classes_.members[c], reach[a * k + c], m);
      ClassGrid& g = grids_.g[a * k + c];
      const std::array<int, 3> dims = cl.dims();
      const std::array<double, 3> edge = cl.cell_edge();
      g.start_base = start_base;
      g.n0 = dims[0];
      g.n1 = dims[1];
      g.n2 = dims[2];
      for (int d = 0; d < 3; ++d) g.inv_edge[d] = 1.0 / edge[d];  // as CellList::build bins
      g.reach2 = reach[a * k + c] * reach[a * k + c];
      const int cells1 = cl.cell_count() + 1, members = classes_.members[c], s0 = start_base, i0 = sorted_base;
      const int* __restrict cs = cl.cell_start().data();
      const int* __restrict si = cl.sorted_index().data();
      DEBRIS_RESIDENT(cs, gs);
      DEBRIS_KERNEL
      for (int j = 0; j < cells1; ++j) gs[s0 + j] = cs[j] + i0;
      DEBRIS_RESIDENT(si, m, gi);
      DEBRIS_KERNEL
      for (int j = 0; j < members; ++j) gi[i0 + j] = m[si[j]];
      start_base += cells1;
      sorted_base += members;
    }
}

bool NeighborList::inside_periodic_box(const BoxView& box, const Particles& p) {
  const int n = static_cast<int>(p.size());
  const double* __restrict c[3] = {p.x.data(), p.y.data(), p.z.data()};
  int outside = 0;
  for (int a = 0; a < 3; ++a) {
    if (!box.periodic[a]) continue;
    const double* __restrict u = c[a];
    const double lo = box.lo[a], hi = box.lo[a] + box.len[a];
    DEBRIS_RESIDENT(u);
    DEBRIS_KERNEL_SUM(outside)
    for (int i = 0; i < n; ++i) outside += (u[i] < lo) | (u[i] > hi);
  }
  return outside == 0;
}

void NeighborList::check(const BoxView& box, const Particles& p, double max_cutoff, double skin,
                         double r_max_cutoff) const {
  if (!(std::isfinite(max_cutoff) && max_cutoff > 0))
    throw input_error("neighbor.max_cutoff", format_value(max_cutoff), "must be finite and > 0");
  if (!(std::isfinite(skin) && skin >= 0)) throw input_error("neighbor.skin", format_value(skin), "must be finite and >= 0");
  // The largest pair is the usual way to get max_cutoff wrong; a too small bound silently loses pairs.
  if (r_max_cutoff > max_cutoff * (1.0 + 1e-12))
    throw input_error("neighbor.max_cutoff", format_value(max_cutoff),
                      "is smaller than the cutoff of two of the largest particles, " + format_value(r_max_cutoff));
  if (p.size() > static_cast<std::size_t>(std::numeric_limits<int>::max()))
    throw input_error("particles", std::to_string(p.size()), "more particles than an int can index");
  const double reach = max_cutoff + skin;
  for (int a = 0; a < 3; ++a) {
    if (box.periodic[a] && box.len[a] < 2.0 * reach)
      throw input_error(std::string("box.") + "xyz"[a], format_value(box.len[a]),
                        "a periodic axis must be at least 2 * (max_cutoff + skin) = " + format_value(2.0 * reach) +
                            " long, or the minimum image of a neighbour pair would be ambiguous");
  }
}

int NeighborList::prefix_sum() {
  // Serial: one add per particle, and the offsets do not depend on the thread count.
  long long total = 0;
  offset_[0] = 0;
  for (std::size_t i = 1; i < offset_.size(); ++i) {
    total += offset_[i];
    if (total > std::numeric_limits<int>::max())
      throw input_error("neighbor.max_cutoff", "(list of " + std::to_string(total) + "+ entries)",
                        "too many neighbour entries for int offsets; reduce the cutoff or the skin");
    offset_[i] = static_cast<int>(total);
  }
  return static_cast<int>(total);
}

int NeighborList::device_prefix_sum() {
  const int n = static_cast<int>(offset_.size()) - 1;
  if (n <= 0) {
    offset_[0] = 0;
    exec::to_device(offset_);
    return 0;
  }
  const long long total = inclusive_scan(offset_.data() + 1, n, scan_scratch_);
  if (total > std::numeric_limits<int>::max())
    throw input_error("neighbor.max_cutoff", "(list of " + std::to_string(total) + "+ entries)",
                      "too many neighbour entries for int offsets; reduce the cutoff or the skin");
  return static_cast<int>(total);
}

void NeighborList::record(const BoxView& box, const Particles& p, double skin, NeighborKind kind) {
#if defined(DEBRIS_OFFLOAD_TARGET)
  // The positions at the build are copied on the device, where needs_rebuild reads them.
  const int n = static_cast<int>(p.size());
  x0_.resize(p.size());
  y0_.resize(p.size());
  z0_.resize(p.size());
  const double *__restrict x = p.x.data(), *__restrict y = p.y.data(), *__restrict z = p.z.data();
  double *__restrict x0 = x0_.data(), *__restrict y0 = y0_.data(), *__restrict z0 = z0_.data();
  DEBRIS_RESIDENT(x, y, z, x0, y0, z0);
  DEBRIS_KERNEL
  for (int i = 0; i < n; ++i) {
    x0[i] = x[i];
    y0[i] = y[i];
    z0[i] = z[i];
  }
#else
  x0_.assign(p.x.begin(), p.x.end());
  y0_.assign(p.y.begin(), p.y.end());
  z0_.assign(p.z.begin(), p.z.end());
#endif
  for (int a = 0; a < 3; ++a) len0_[a] = box.len[a];
  rows_ = static_cast<int>(p.size());
  skin_ = skin;
  kind_ = kind;
  built_ = true;
}

NeighborList::Saved NeighborList::save() const {
  auto host = [](const auto& v) { return std::vector<typename std::decay_t<decltype(v)>::value_type>(v.begin(), v.end()); };
  Saved s{kind_, skin_, host(offset_), host(index_), host(x0_), host(y0_), host(z0_), {len0_[0], len0_[1], len0_[2]}};
  return s;
}

void NeighborList::to_host() const {
  exec::to_host(offset_);
  exec::to_host(index_);
  exec::to_host(x0_);
  exec::to_host(y0_);
  exec::to_host(z0_);
}

void NeighborList::to_device() const {
  exec::to_device(offset_);
  exec::to_device(index_);
  exec::to_device(x0_);
  exec::to_device(y0_);
  exec::to_device(z0_);
}

void NeighborList::restore(Saved s) {
  if (s.offset.size() != s.x0.size() + 1 || s.x0.size() != s.y0.size() || s.x0.size() != s.z0.size() ||
      (!s.offset.empty() && static_cast<std::size_t>(s.offset.back()) != s.index.size()))
    throw std::runtime_error("neighbour list restore: inconsistent arrays");
  kind_ = s.kind;
  skin_ = s.skin;
  offset_.assign(s.offset.begin(), s.offset.end());
  index_.assign(s.index.begin(), s.index.end());
  x0_.assign(s.x0.begin(), s.x0.end());
  y0_.assign(s.y0.begin(), s.y0.end());
  z0_.assign(s.z0.begin(), s.z0.end());
  to_device();
  for (int a = 0; a < 3; ++a) len0_[a] = s.len0[a];
  rows_ = static_cast<int>(x0_.size());
  built_ = true;
}

bool NeighborList::needs_rebuild(const BoxView& box, const Particles& p) const {
  if (!built_ || p.size() != x0_.size()) return true;
  const double half_skin = 0.5 * skin_;
  for (int a = 0; a < 3; ++a)
    if (std::fabs(box.len[a] - len0_[a]) > half_skin) return true;

  const int n = static_cast<int>(p.size());
  const double* __restrict x = p.x.data();
  const double* __restrict y = p.y.data();
  const double* __restrict z = p.z.data();
  const double* __restrict x0 = x0_.data();
  const double* __restrict y0 = y0_.data();
  const double* __restrict z0 = z0_.data();
  const double lx = box.len[0], ly = box.len[1], lz = box.len[2];
  const int px = box.periodic[0], py = box.periodic[1], pz = box.periodic[2];
  double max_d2 = 0.0;
  DEBRIS_RESIDENT(x, y, z, x0, y0, z0);
  // nearest_image instead of minimum_image: branch-free, so this vectorises (the floor() version cost 5%
  // of a step). It is exact for drifts under 1.5 box lengths and never smaller than the true minimum
  // image beyond, so it cannot miss a rebuild.
  DEBRIS_KERNEL_MAX(max_d2)
  for (int i = 0; i < n; ++i) {
    const double dx = nearest_image(x[i] - x0[i], lx, px);
    const double dy = nearest_image(y[i] - y0[i], ly, py);
    const double dz = nearest_image(z[i] - z0[i], lz, pz);
    const double d2 = dx * dx + dy * dy + dz * dz;
    max_d2 = d2 > max_d2 ? d2 : max_d2;
  }
  return max_d2 > half_skin * half_skin;
}

void NeighborList::sort_rows() {
  const int n = static_cast<int>(offset_.size()) - 1;
  const int* __restrict off = offset_.data();
  int* __restrict idx = index_.data();
  DEBRIS_RESIDENT(off, idx);
  DEBRIS_KERNEL
  for (int i = 0; i < n; ++i) sort_row(idx + off[i], off[i + 1] - off[i]);
}

std::size_t NeighborList::bytes() const {
  std::size_t staged = 0;
  for (const auto& rows : thread_rows_) staged += rows.capacity();
  const std::size_t classes =
      sizeof(int) * (class_of_.capacity() + members_.capacity() + grid_start_.capacity() + grid_sorted_.capacity()) +
      grid_cells_.bytes();
  return sizeof(int) * (offset_.capacity() + index_.capacity() + staged) +
         sizeof(double) * (x0_.capacity() + y0_.capacity() + z0_.capacity()) + cells_.bytes() + classes;
}

}  // namespace debris
