#pragma once
// Size classes for the neighbour search of polydisperse systems (the idea of LAMMPS's `neigh_modify multi`).
// One grid sized for the largest pair makes every small particle scan the cells of a large one: at a size
// ratio of 6.7 that is 700-800 candidates for some 15 neighbours. Instead particles are split by radius
// into classes a factor kRatio apart, and the members of class b are binned once for each class a, in
// cells as wide as the reach of the largest (a, b) pair: a particle of class a scans, in each class b,
// the 27 cells around it in grid (a, b), so small particles look at small cells for small partners and
// at large, sparse cells for large ones. All grids use the same 27-cell stencil as the single grid.
#include <vector>

#include "core/box.hpp"
#include "core/exec.hpp"

namespace debris {

DEBRIS_DECLARE_TARGET
/// The class of a radius: the largest c < count with radius >= lower_c (class 0 open below), the bounds
/// lower_1..3 passed as scalars so that a kernel can call it without mapping an array. The one rule that
/// SizeClasses::classify and the device binning (NeighborList) both use.
inline int size_class(double radius, int count, double lower1, double lower2, double lower3) {
  int c = 0;
  if (count > 1 && radius >= lower1) c = 1;
  if (c == 1 && count > 2 && radius >= lower2) c = 2;
  if (c == 2 && count > 3 && radius >= lower3) c = 3;
  return c;
}
DEBRIS_END_DECLARE_TARGET

struct SizeClasses {
  static constexpr int kMax = 4;          // grids: kMax^2 at most, each a counting sort of one class
  static constexpr double kRatio = 2.0;   // radius ratio covered by one class
  int count = 1;
  double lower[kMax] = {};   // class c holds lower[c] <= r < lower[c + 1]; the last class is open above
  double r_max[kMax] = {};   // largest radius in class c (0 when the class is empty)
  int members[kMax] = {};    // particles in class c

  /// Classes for radii r[0..n): count = 1 + the number of factors kRatio from the smallest radius to the
  /// largest, capped at max_classes (>= 1). A narrow distribution (r_max < 2 r_min) gives one class.
  static SizeClasses of(const double* r, int n, int max_classes);
  /// The same classes found where r is (offload builds: r on the device, reductions there, scalars back).
  static SizeClasses of_resident(const double* r, int n, int max_classes);
  static_assert(kMax == 4, "size_class() takes kMax - 1 bounds");
  int classify(double radius) const { return size_class(radius, count, lower[1], lower[2], lower[3]); }
};

DEBRIS_DECLARE_TARGET
/// One grid of a size-class search: the members of class b binned in cells at least reach(a, b) wide,
/// scanned by particles of class a. cell_start values index the shared sorted array directly.
struct ClassGrid {
  int start_base = 0;       // this grid's cell_start begins at start_all[start_base]
  int n0 = 0, n1 = 0, n2 = 0;  // cells per axis; n0 == 0: nothing to scan (a or b empty)
  double inv_edge[3] = {0, 0, 0};
  double reach2 = 0;        // (cutoff(r_max[a], r_max[b]) + skin)^2, with a hair of margin
};

/// The grids of all class pairs, by value in a kernel: grid (a, b) is g[a * classes + b].
struct ClassGrids {
  int classes = 0;
  ClassGrid g[SizeClasses::kMax * SizeClasses::kMax];
};
DEBRIS_END_DECLARE_TARGET

}  // namespace debris
