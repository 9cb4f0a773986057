#pragma once
// The cells around a cell of a grid (c-1, c, c+1 on each axis, wrapped or clipped): what the DEM neighbour
// search (core/neighbor_list.hpp) and the PeriDEM contact list (core/pd_contact_list.hpp) both scan.
#include "core/exec.hpp"

namespace debris {

DEBRIS_DECLARE_TARGET

/// Cells visited along one axis around cell c: c-1, c, c+1, wrapped on a periodic axis, clipped on a
/// non-periodic one, each cell at most once (a 1-cell axis gives just c). Returns how many.
inline int neighbor_stencil(int c, int nc, int periodic, int* out) {
  int k = 0;
  for (int d = -1; d <= 1; ++d) {
    int cc = c + d;
    if (periodic) {
      cc = cc < 0 ? cc + nc : (cc >= nc ? cc - nc : cc);
    } else if (cc < 0 || cc >= nc) {
      continue;
    }
    if (k > 0 && cc == out[0]) continue;  // 1 or 2 cells on a periodic axis: c+1 wraps onto a cell already listed
    out[k++] = cc;
  }
  return k;
}

/// The cells around one cell: its coordinates, and for each axis the cells visited and how many.
struct Stencil {
  int cx, cy, cz;
  int sx[3], sy[3], sz[3];
  int nsx, nsy, nsz;
};

/// The stencil of cell ci in an n0 x n1 x n2 grid.
inline Stencil cell_stencil(int ci, int n0, int n1, int n2, const int periodic[3]) {
  Stencil st;
  st.cx = ci % n0;
  st.cy = (ci / n0) % n1;
  st.cz = ci / (n0 * n1);
  st.nsx = neighbor_stencil(st.cx, n0, periodic[0], st.sx);
  st.nsy = neighbor_stencil(st.cy, n1, periodic[1], st.sy);
  st.nsz = neighbor_stencil(st.cz, n2, periodic[2], st.sz);
  return st;
}

DEBRIS_END_DECLARE_TARGET

}  // namespace debris
