#pragma once
// Verlet neighbour lists in compressed rows: the neighbours of particle i are
// index()[offset()[i] .. offset()[i+1]). Built from a CellList in two kernel passes (count per row,
// prefix sum, fill at offset[i]), so the rows are the same for any thread count and the fill needs no
// atomics. A pair is listed when its centres are closer than cutoff(r_i, r_j) + skin; the list stays
// valid until some particle has drifted skin/2 (needs_rebuild).
// Narrow size distributions use one grid of cells sized for the largest pair; a wide one (largest radius
// at least twice the smallest) uses size classes (core/size_classes.hpp).
// Each row lists its neighbours in increasing index, whatever grid found them: with particles stored in a
// canonical order (by cell, then id: CellList::sort_order(key)), a row is then the same sequence of
// particles on any storage order of the input and on any decomposition, and so is every sum over it.
#include <cstddef>
#include <vector>

#include "core/box.hpp"
#include "core/cell_list.hpp"
#include "core/cell_stencil.hpp"
#include "core/exec.hpp"
#include "core/particles.hpp"
#include "core/resize_for_overwrite.hpp"
#include "core/size_classes.hpp"
#include "core/vec3.hpp"

namespace debris {

/// full: j in row i and i in row j (pair passes that write only to i); half: each pair once, in row min(i, j).
enum class NeighborKind { full, half };

DEBRIS_DECLARE_TARGET

/// Sorts a row's n neighbour indices in place, increasing. Rows are short and mostly in order already (the
/// stencil visits the cells of cell-sorted storage in increasing order but across a periodic face), so an
/// insertion sort is about one comparison per entry.
inline void sort_row(int* a, int n) {
  for (int k = 1; k < n; ++k) {
    const int v = a[k];
    int h = k;
    while (h > 0 && a[h - 1] > v) {
      a[h] = a[h - 1];
      --h;
    }
    a[h] = v;
  }
}

/// How many particles a stencil holds: room enough for the row of any particle in its centre cell.
inline int stencil_candidates(const Stencil& st, const int* cell_start, int n0, int n1) {
  int total = 0;
  for (int a = 0; a < st.nsz; ++a)
    for (int bb = 0; bb < st.nsy; ++bb)
      for (int c = 0; c < st.nsx; ++c) {
        const int cell = st.sx[c] + n0 * (st.sy[bb] + n1 * st.sz[a]);
        total += cell_start[cell + 1] - cell_start[cell];
      }
  return total;
}

/// neighbor_row's loop over the stencil. Image = false skips the minimum-image arithmetic (half of the
/// scan's cost), which is exact where no stencil cell lies across a periodic boundary.
template <bool Image, class Cutoff>
inline int neighbor_scan(int i, const double* x, const double* y, const double* z, const double* r,
                         const int* cell_start, const int* sorted, int n0, int n1, const Stencil& st,
                         const BoxView& b, Cutoff cutoff, double skin, double reach2, int half, int* out) {
  const double xi = x[i], yi = y[i], zi = z[i], ri = r[i];
  const double lx = b.len[0], ly = b.len[1], lz = b.len[2];
  const int px = b.periodic[0], py = b.periodic[1], pz = b.periodic[2];
  int count = 0;
  for (int a = 0; a < st.nsz; ++a) {
    for (int bb = 0; bb < st.nsy; ++bb) {
      for (int c = 0; c < st.nsx; ++c) {
        const int cell = st.sx[c] + n0 * (st.sy[bb] + n1 * st.sz[a]);
        const int begin = cell_start[cell], end = cell_start[cell + 1];
        // A cell lists its particles in increasing index: for a half list, a cell whose last index is
        // below i holds nothing for this row (in cell-sorted storage, about half the stencil).
        if (half && begin < end && sorted[end - 1] < i) continue;
        for (int k = begin; k < end; ++k) {
          const int j = sorted[k];
          // Indices first: a half list skips half the candidates before any arithmetic (in cell-sorted
          // storage they come in runs, so the branch predicts well).
          if (j == i || (half && j < i)) continue;
          // Positions are wrapped at a build, so separations are below one box length: no floor() needed.
          const double dx = Image ? nearest_image(xi - x[j], lx, px) : xi - x[j];
          const double dy = Image ? nearest_image(yi - y[j], ly, py) : yi - y[j];
          const double dz = Image ? nearest_image(zi - z[j], lz, pz) : zi - z[j];
          const double d2 = dx * dx + dy * dy + dz * dz;
          // reach2 = (max_cutoff + skin)^2 bounds every pair's cutoff: most candidates stop here.
          if (d2 >= reach2) continue;
          const double rc = cutoff(ri, r[j]) + skin;
          if (d2 < rc * rc) {
            if (out) out[count] = j;
            ++count;
          }
        }
      }
    }
  }
  return count;
}

/// Scans st, the stencil of particle i's cell, and writes i's neighbours to out (when not null) in stencil
/// order, then cell order, and returns how many there are. half != 0 keeps only j > i. wrapped != 0
/// promises that every coordinate on a periodic axis lies in [lo, lo + len].
template <class Cutoff>
inline int neighbor_row(int i, const Stencil& st, const double* x, const double* y, const double* z,
                        const double* r, const int* cell_start, const int* sorted, int n0, int n1, int n2,
                        const BoxView& b, Cutoff cutoff, double skin, double reach2, int half, int wrapped,
                        int* out) {
  // Away from periodic boundaries (most particles) the plain difference is the minimum image of every
  // pair within reach, provided all positions lie inside the box on its periodic axes (wrapped != 0):
  // cells are at least max_cutoff + skin wide, and an axis with 3 or more of them puts any image across
  // the boundary at least one cell width away.
  auto inside = [](int c, int nc, int periodic) { return !periodic || (nc >= 3 && c > 0 && c < nc - 1); };
  if (wrapped && inside(st.cx, n0, b.periodic[0]) && inside(st.cy, n1, b.periodic[1]) &&
      inside(st.cz, n2, b.periodic[2]))
    return neighbor_scan<false>(i, x, y, z, r, cell_start, sorted, n0, n1, st, b, cutoff, skin, reach2, half, out);
  return neighbor_scan<true>(i, x, y, z, r, cell_start, sorted, n0, n1, st, b, cutoff, skin, reach2, half, out);
}

/// The stencil, in grid g, of the cell that holds the point (px, py, pz): the cell build() would bin it in.
inline Stencil point_stencil(double px, double py, double pz, const ClassGrid& g, const BoxView& b) {
  Stencil st;
  st.cx = cell_coordinate(px, b.lo[0], g.inv_edge[0], g.n0, b.periodic[0]);
  st.cy = cell_coordinate(py, b.lo[1], g.inv_edge[1], g.n1, b.periodic[1]);
  st.cz = cell_coordinate(pz, b.lo[2], g.inv_edge[2], g.n2, b.periodic[2]);
  st.nsx = neighbor_stencil(st.cx, g.n0, b.periodic[0], st.sx);
  st.nsy = neighbor_stencil(st.cy, g.n1, b.periodic[1], st.sy);
  st.nsz = neighbor_stencil(st.cz, g.n2, b.periodic[2], st.sz);
  return st;
}

/// neighbor_row for particle i of class a in a size-class search: each class's grid (a, c) in turn, with
/// the reach of the largest (a, c) pair, written one after the other.
template <class Cutoff>
inline int neighbor_row_classes(int i, int a, const ClassGrids& G, const double* x, const double* y,
                                const double* z, const double* r, const int* start_all, const int* sorted_all,
                                const BoxView& b, Cutoff cutoff, double skin, int half, int wrapped, int* out) {
  int count = 0;
  for (int c = 0; c < G.classes; ++c) {
    const ClassGrid& g = G.g[a * G.classes + c];
    if (g.n0 == 0) continue;
    const Stencil st = point_stencil(x[i], y[i], z[i], g, b);
    count += neighbor_row(i, st, x, y, z, r, start_all + g.start_base, sorted_all, g.n0, g.n1, g.n2, b, cutoff,
                          skin, g.reach2, half, wrapped, out ? out + count : nullptr);
  }
  return count;
}

DEBRIS_END_DECLARE_TARGET

class NeighborList {
 public:
  /// Builds rows for all particles: j is a neighbour of i if |minimum_image(x_i - x_j)| < cutoff(r_i, r_j) + skin.
  /// cutoff: any callable double(double ri, double rj), symmetric, legal in a kernel (e.g. CohesiveCutoff).
  /// max_cutoff: upper bound of cutoff over all pairs; the cells have edge >= max_cutoff + skin.
  /// Positions on periodic axes must be wrapped into the box (Box::wrap), as at every engine rebuild.
  /// Throws InputError: "neighbor.max_cutoff" / "neighbor.skin" for bad values or when
  /// cutoff(r_max, r_max) > max_cutoff, "box.<axis>" when a periodic axis is shorter than
  /// 2 (max_cutoff + skin) (minimum image would be ambiguous).
  template <class Cutoff>
  void build(const BoxView& box, const Particles& p, Cutoff cutoff, double max_cutoff, double skin,
             NeighborKind kind);

  /// True when the list was never built, the particle count changed, a box length changed by more than
  /// skin/2 since the build, or some particle moved more than skin/2 (minimum image: a periodic wrap is
  /// not a move).
  bool needs_rebuild(const BoxView& box, const Particles& p) const;

  /// Everything a checkpoint needs to continue with this exact list (a rebuild would re-sort and change the
  /// summation order, so a restart would no longer be bit for bit).
  struct Saved {
    NeighborKind kind;
    double skin;
    std::vector<int> offset, index;
    std::vector<double> x0, y0, z0;  // positions at the build
    double len0[3];                  // box lengths at the build
  };
  Saved save() const;  // reads the host copies: call to_host() first in offload builds
  void restore(Saved s);  // host and device copies both set

  /// Transfer point (offload builds): the host copies of the rows and of the positions at the build
  /// (index, x0, y0, z0; the offsets are current on both sides after every build) are refreshed.
  void to_host() const;
  /// Transfer point: the device copies of everything a kernel reads, after a host-side change.
  void to_device() const;

  /// At most this many size classes (1 to SizeClasses::kMax; 1: always one grid). Takes effect at the next build.
  void set_max_size_classes(int classes);
  /// The classes of the last build (count 1: one grid, cells()).
  const SizeClasses& size_classes() const { return classes_; }
  /// Particles in the stencils scanned by the last build, summed over rows (host builds; 0 in offload builds).
  long long candidates() const { return candidates_; }

  /// True when every coordinate on a periodic axis lies in [lo, lo + len] (as after Box::wrap).
  static bool inside_periodic_box(const BoxView& box, const Particles& p);
  int rows() const { return rows_; }
  const exec::DeviceVector<int>& offset() const { return offset_; }  // size rows() + 1
  const exec::DeviceVector<int>& index() const { return index_; }    // neighbour indices
  int entries() const { return static_cast<int>(index_.size()); }  // index_ holds exactly the rows' entries
  NeighborKind kind() const { return kind_; }
  double skin() const { return skin_; }
  /// The single grid (size_classes().count == 1); with size classes it is not built.
  const CellList& cells() const { return cells_; }
  /// The list's cell list lent as scratch to a caller that bins the same particles just before the next
  /// build() (the DEM re-sort by cell): build() bins them again, so the engine holds one grid, not two.
  CellList& cells_until_next_build() { return cells_; }
  std::size_t bytes() const;  // memory held, cell lists included

 private:
  // Non-template parts of build, in neighbor_list.cpp.
  void check(const BoxView& box, const Particles& p, double max_cutoff, double skin, double r_max_cutoff) const;
  int prefix_sum();  // offset_[1..n] holds row counts on entry, the exclusive prefix sum on exit; returns the total
  // The same where offset_ lives (offload builds: on the device, only the total back); offset_[0] must be 0.
  int device_prefix_sum();
  void record(const BoxView& box, const Particles& p, double skin, NeighborKind kind);
  static double max_radius(const Particles& p);
  // Size classes: bins each class's members into its grids, given reach[a * count + b] for each class pair;
  // fills grids_ (kernel view), grid_start_ and grid_sorted_.
  void bin_classes(const BoxView& box, const Particles& p, const double* reach);
  // Host threads: offset_ and index_ from row_fn(i, room), which returns row i's length after writing it to
  // room(bound), a buffer for at most `bound` entries. Host builds only: offload builds fill on the device
  // (and their index_ is a device-mapped vector, not a row buffer).
#if !defined(DEBRIS_OFFLOAD_TARGET)
  template <class RowFn>
  void fill_rows_host(int n, RowFn row_fn);
#endif

  CellList cells_;
  // Size classes (used when classes_.count > 1): class of each particle, members of each class (ascending,
  // class after class), one cell list that bins each class pair's grid in turn, and all grids' cell starts
  // and particle indices, concatenated so that a kernel sees two flat arrays.
  int max_classes_ = SizeClasses::kMax;
  SizeClasses classes_;
  ClassGrids grids_;
  // Offload builds: all on the device, where the binning runs.
  exec::DeviceVector<int> class_of_;
  exec::DeviceVector<int> members_;
  CellList grid_cells_;  // bins one class grid at a time (bin_classes), then copied into the flat arrays
  exec::DeviceVector<int> grid_start_, grid_sorted_;
  std::vector<long long> thread_candidates_;
  long long candidates_ = 0;
  // Offload builds: both on the device (the row counts are summed there); to_host() for host readers.
  exec::DeviceVector<int> offset_;
  exec::DeviceVector<long long> scan_scratch_;  // device_prefix_sum's block sums
  exec::DeviceVector<int> index_;
  std::vector<std::vector<int>> thread_rows_;  // host build: each later thread's rows (the first's: index_)
  exec::DeviceVector<double> x0_, y0_, z0_;  // positions at the last build (offload: copied on the device)
  double len0_[3] = {0, 0, 0};        // box lengths at the last build
  int rows_ = 0;
  bool built_ = false;
  NeighborKind kind_ = NeighborKind::full;
  double skin_ = 0;
  /// Each row in increasing neighbour index (offload builds, after the fill; host builds sort each row as
  /// it is found).
  void sort_rows();
};

#if !defined(DEBRIS_OFFLOAD_TARGET)
template <class RowFn>
void NeighborList::fill_rows_host(int n, RowFn row_fn) {
  // One scan. Each thread takes a contiguous run of rows and appends them to its own buffer (with room for
  // all of a row's candidates), then the runs are copied into place: the same rows as two scans (count,
  // then fill), at about half the cost. The first thread's buffer is the index itself (its rows come first),
  // so one thread copies nothing and no thread holds a second copy of the first run. Buffers grow by a
  // quarter, not double: they are kept between builds, so their slack is memory held for the whole run.
  thread_rows_.resize(static_cast<std::size_t>(exec::threads()));
  thread_candidates_.assign(thread_rows_.size(), 0);
  int* __restrict off = offset_.data();
  int team_used = 1;
  // Thread t of a team of `team` takes rows [first_row(t, team), first_row(t + 1, team)).
  auto first_row = [n](int t, int team) { return static_cast<int>(static_cast<long long>(n) * t / team); };
  DEBRIS_HOST_PARALLEL {
    const int team = exec::team_size(), rank = exec::team_rank();
    if (rank == 0) team_used = team;
    std::vector<int>& buf = rank == 0 ? index_ : thread_rows_[static_cast<std::size_t>(rank)];
    buf.clear();
    long long scanned = 0;
    std::size_t at = 0;
    // The row function calls this with its candidate count before it writes the row.
    auto room = [&](int candidates) {
      scanned += candidates;
      const std::size_t need = at + static_cast<std::size_t>(candidates);
      if (buf.capacity() < need) buf.reserve(need + need / 4);
      buf.resize(need);
      return buf.data() + at;
    };
    for (int i = first_row(rank, team); i < first_row(rank + 1, team); ++i) {
      at = buf.size();
      off[i + 1] = row_fn(i, room);
      buf.resize(at + static_cast<std::size_t>(off[i + 1]));
    }
    thread_candidates_[static_cast<std::size_t>(rank)] = scanned;
  }
  const std::size_t entries = static_cast<std::size_t>(prefix_sum());
  if (index_.capacity() < entries) index_.reserve(entries);  // exactly: the first run is kept
  index_.resize(entries);
  candidates_ = thread_candidates_[0];
  for (int t = 1; t < team_used; ++t) {
    const std::vector<int>& buf = thread_rows_[static_cast<std::size_t>(t)];
    std::copy(buf.begin(), buf.end(), index_.begin() + off[first_row(t, team_used)]);
    candidates_ += thread_candidates_[static_cast<std::size_t>(t)];
  }
}
#endif

template <class Cutoff>
void NeighborList::build(const BoxView& box, const Particles& p, Cutoff cutoff, double max_cutoff, double skin,
                         NeighborKind kind) {
  const double r_max = max_radius(p);
  check(box, p, max_cutoff, skin, p.size() > 0 ? cutoff(r_max, r_max) : 0.0);
  const int n = static_cast<int>(p.size());
  offset_.resize(static_cast<std::size_t>(n) + 1);
  // The classes are found where the radii are (offload builds: reductions on the device; a re-sort permutes
  // the device copies only and leaves the host's stale).
  classes_ = SizeClasses::of_resident(p.radius.data(), n, max_classes_);

  const double* __restrict x = p.x.data();
  const double* __restrict y = p.y.data();
  const double* __restrict z = p.z.data();
  const double* __restrict r = p.radius.data();
  const BoxView b = box;
  const int half = kind == NeighborKind::half ? 1 : 0;
  const int wrapped = inside_periodic_box(box, p) ? 1 : 0;
  int* __restrict off = offset_.data();
  (void)off;

  if (classes_.count > 1) {
    // Reach of each class pair: the cutoff grows with both radii, so the largest pair bounds it. The margin
    // keeps a pair whose cutoff rounds a hair above the bound from falling outside the grid's stencil.
    const int k = classes_.count;
    double reach[SizeClasses::kMax * SizeClasses::kMax];
    for (int a = 0; a < k; ++a)
      for (int c = 0; c < k; ++c)
        reach[a * k + c] = (cutoff(classes_.r_max[a], classes_.r_max[c]) + skin) * (1.0 + 1e-12);
    bin_classes(box, p, reach);
    const ClassGrids grids = grids_;
    const int* __restrict cls = class_of_.data();
    const int* __restrict start_all = grid_start_.data();
    const int* __restrict sorted_all = grid_sorted_.data();
#if defined(DEBRIS_OFFLOAD_TARGET)
    DEBRIS_RESIDENT(off, cls, x, y, z, r, start_all, sorted_all);
    DEBRIS_KERNEL
    for (int i = 0; i < n; ++i) {
      if (i == 0) off[0] = 0;
      off[i + 1] = neighbor_row_classes(i, cls[i], grids, x, y, z, r, start_all, sorted_all, b, cutoff, skin, half,
                                        wrapped, nullptr);
    }
    resize_for_overwrite(index_, static_cast<std::size_t>(device_prefix_sum()));
    int* __restrict idx = index_.data();
    DEBRIS_RESIDENT(off, idx, cls, x, y, z, r, start_all, sorted_all);
    DEBRIS_KERNEL
    for (int i = 0; i < n; ++i)
      neighbor_row_classes(i, cls[i], grids, x, y, z, r, start_all, sorted_all, b, cutoff, skin, half, wrapped,
                           idx + off[i]);
    sort_rows();
    candidates_ = 0;
#else
    // As neighbor_row_classes, with each class's stencil placed once for the room and the scan.
    fill_rows_host(n, [&](int i, auto& room) {
      const ClassGrid* g = grids.g + cls[i] * k;
      Stencil st[SizeClasses::kMax];
      int candidates = 0;
      for (int c = 0; c < k; ++c) {
        if (g[c].n0 == 0) continue;
        st[c] = point_stencil(x[i], y[i], z[i], g[c], b);
        candidates += stencil_candidates(st[c], start_all + g[c].start_base, g[c].n0, g[c].n1);
      }
      int* out = room(candidates);
      int count = 0;
      for (int c = 0; c < k; ++c) {
        if (g[c].n0 == 0) continue;
        count += neighbor_row(i, st[c], x, y, z, r, start_all + g[c].start_base, sorted_all, g[c].n0, g[c].n1,
                              g[c].n2, b, cutoff, skin, g[c].reach2, half, wrapped, out + count);
      }
      sort_row(out, count);  // the classes' neighbours interleave by index
      return count;
    });
#endif
    record(box, p, skin, kind);
    return;
  }

  cells_.build(box, x, y, z, n, max_cutoff + skin);
  const int* __restrict cell_of = cells_.cell_of().data();
  const int* __restrict cell_start = cells_.cell_start().data();
  const int* __restrict sorted = cells_.sorted_index().data();
  const std::array<int, 3> dims = cells_.dims();
  const int n0 = dims[0], n1 = dims[1], n2 = dims[2];
  const double reach2 = (max_cutoff + skin) * (max_cutoff + skin);

#if defined(DEBRIS_OFFLOAD_TARGET)
  // Device: count the rows, place them (prefix sum on the device), scan again to fill.
  DEBRIS_RESIDENT(off, cell_of, x, y, z, r, cell_start, sorted);
  DEBRIS_KERNEL
  for (int i = 0; i < n; ++i) {
    if (i == 0) off[0] = 0;
    const Stencil st = cell_stencil(cell_of[i], n0, n1, n2, b.periodic);
    off[i + 1] = neighbor_row(i, st, x, y, z, r, cell_start, sorted, n0, n1, n2, b, cutoff, skin, reach2, half,
                               wrapped, nullptr);
  }
  resize_for_overwrite(index_, static_cast<std::size_t>(device_prefix_sum()));
  int* __restrict idx = index_.data();
  DEBRIS_RESIDENT(off, idx, cell_of, x, y, z, r, cell_start, sorted);
  DEBRIS_KERNEL
  for (int i = 0; i < n; ++i) {
    const Stencil st = cell_stencil(cell_of[i], n0, n1, n2, b.periodic);
    neighbor_row(i, st, x, y, z, r, cell_start, sorted, n0, n1, n2, b, cutoff, skin, reach2, half, wrapped,
                 idx + off[i]);
  }
  sort_rows();
  candidates_ = 0;
#else
  fill_rows_host(n, [&](int i, auto& room) {
    const Stencil st = cell_stencil(cell_of[i], n0, n1, n2, b.periodic);
    int* out = room(stencil_candidates(st, cell_start, n0, n1));
    const int count = neighbor_row(i, st, x, y, z, r, cell_start, sorted, n0, n1, n2, b, cutoff, skin, reach2, half,
                                   wrapped, out);
    sort_row(out, count);  // while the row is in cache
    return count;
  });
#endif
  record(box, p, skin, kind);
}

}  // namespace debris
