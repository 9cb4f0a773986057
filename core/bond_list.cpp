#include "core/bond_list.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>

#include "core/box.hpp"
#include "core/cell_list.hpp"
#include "core/error.hpp"
#include "core/exec.hpp"
#include "core/pd_nodes.hpp"

namespace debris {

namespace {

void check_grains(const PdNodes& nodes, const PdGrains& grains, const std::vector<double>& horizon_of_grain) {
  const std::size_t n = nodes.size();
  if (n > static_cast<std::size_t>(std::numeric_limits<int>::max()))
    throw input_error("pd nodes", std::to_string(n), "more nodes than an int can index");
  if (horizon_of_grain.size() < grains.size())
    throw input_error("horizon_of_grain", std::to_string(horizon_of_grain.size()) + " entries",
                      "needs one horizon per grain (" + std::to_string(grains.size()) + " grains)");
  for (std::size_t g = 0; g < grains.size(); ++g) {
    const std::string key = "grain " + std::to_string(g);
    const int b = grains.node_begin[g], e = grains.node_end[g];
    if (!(0 <= b && b <= e && static_cast<std::size_t>(e) <= n))
      throw input_error(key + " nodes", "[" + std::to_string(b) + ", " + std::to_string(e) + ")",
                        "must be a range inside [0, " + std::to_string(n) + ")");
    if (grains.kind[g] != static_cast<int>(PdGrainKind::particle)) continue;
    const double eps = horizon_of_grain[g];
    if (!(std::isfinite(eps) && eps > 0))
      throw input_error(key + " horizon", format_value(eps), "must be finite and > 0");
  }
}

// Bounding box of one grain's reference positions, padded to at least one horizon per axis so that a flat
// (2D, z = const) or thin grain still gets cells of a finite size.
BoxView grain_box(const double* x, const double* y, const double* z, int n, double horizon) {
  BoxView b{};
  const double* c[3] = {x, y, z};
  for (int a = 0; a < 3; ++a) {
    const auto [lo, hi] = std::minmax_element(c[a], c[a] + n);
    b.lo[a] = *lo;
    b.len[a] = std::max(*hi - *lo, horizon) * (1.0 + 1e-12);  // the max lies inside [lo, lo + len)
    b.periodic[a] = 0;
  }
  return b;
}

}  // namespace

BondList BondList::build(const PdNodes& nodes, const PdGrains& grains, const std::vector<double>& horizon_of_grain) {
  check_grains(nodes, grains, horizon_of_grain);
  const int n = static_cast<int>(nodes.size());
  const double *x0 = nodes.x0.data(), *y0 = nodes.y0.data(), *z0 = nodes.z0.data();
  // The search reads the host's reference positions; the cell lists bin the device's (offload builds):
  // send them first (3n doubles, once per build).
  exec::to_device(nodes.x0);
  exec::to_device(nodes.y0);
  exec::to_device(nodes.z0);

  // Per grain: a cell list of edge >= horizon over the grain's nodes, the 27 cells around each node, rows
  // sorted ascending. Two passes over the same search (count, then fill) keep the CSR arrays exact-size.
  std::vector<int> count(static_cast<std::size_t>(n), 0);
  CellList cells;
  std::vector<int> row;
  BondList list;
  list.offset.assign(static_cast<std::size_t>(n) + 1, 0);

  // Visits the partners of node i (global index) within its grain: calls f(j, |x0_j - x0_i|).
  auto for_each_partner = [&](int i, int begin, double horizon, auto&& f) {
    const std::array<int, 3> dims = cells.dims();
    const int c = cells.cell_of()[static_cast<std::size_t>(i - begin)];
    const int cx = c % dims[0], cy = (c / dims[0]) % dims[1], cz = c / (dims[0] * dims[1]);
    const int* start = cells.cell_start().data();
    const int* sorted = cells.sorted_index().data();
    for (int dz = -1; dz <= 1; ++dz) {
      const int qz = cz + dz;
      if (qz < 0 || qz >= dims[2]) continue;
      for (int dy = -1; dy <= 1; ++dy) {
        const int qy = cy + dy;
        if (qy < 0 || qy >= dims[1]) continue;
        for (int dx = -1; dx <= 1; ++dx) {
          const int qx = cx + dx;
          if (qx < 0 || qx >= dims[0]) continue;
          const int q = cells.cell_index(qx, qy, qz);
          for (int k = start[q]; k < start[q + 1]; ++k) {
            const int j = begin + sorted[k];
            if (j == i) continue;
            const double ddx = x0[j] - x0[i], ddy = y0[j] - y0[i], ddz = z0[j] - z0[i];
            const double r = std::sqrt(ddx * ddx + ddy * ddy + ddz * ddz);
            if (r < horizon) f(j, r);
          }
        }
      }
    }
  };

  for (std::size_t g = 0; g < grains.size(); ++g) {
    if (grains.kind[g] != static_cast<int>(PdGrainKind::particle)) continue;  // walls carry no bonds
    const int begin = grains.node_begin[g], end = grains.node_end[g], m = end - begin;
    if (m == 0) continue;
    const double horizon = horizon_of_grain[g];
    const BoxView box = grain_box(x0 + begin, y0 + begin, z0 + begin, m, horizon);
    cells.build(box, x0 + begin, y0 + begin, z0 + begin, m, horizon);
    cells.to_host();  // the search below runs on the host (set-up only)
    for (int i = begin; i < end; ++i) {
      int c = 0;
      for_each_partner(i, begin, horizon, [&](int j, double r) {
        // Two nodes at one place would give a bond of zero length: a stretch of 0/0 (eq 10) and no direction.
        if (r == 0.0)
          throw input_error("grain " + std::to_string(g) + " nodes",
                            "ids " + std::to_string(nodes.id[i]) + " and " + std::to_string(nodes.id[j]),
                            "coincide in the reference configuration");
        ++c;
      });
      count[static_cast<std::size_t>(i)] = c;
    }
  }
  for (int i = 0; i < n; ++i) {
    const long long next = static_cast<long long>(list.offset[i]) + count[static_cast<std::size_t>(i)];
    if (next > std::numeric_limits<int>::max())
      throw input_error("pd bonds", std::to_string(next) + "+ entries", "more bond entries than an int can index");
    list.offset[static_cast<std::size_t>(i) + 1] = static_cast<int>(next);
  }
  const std::size_t entries = static_cast<std::size_t>(list.offset.back());
  list.partner.resize(entries);
  list.length0.resize(entries);
  list.broken.assign(entries, 0);

  for (std::size_t g = 0; g < grains.size(); ++g) {
    if (grains.kind[g] != static_cast<int>(PdGrainKind::particle)) continue;
    const int begin = grains.node_begin[g], end = grains.node_end[g], m = end - begin;
    if (m == 0) continue;
    const double horizon = horizon_of_grain[g];
    const BoxView box = grain_box(x0 + begin, y0 + begin, z0 + begin, m, horizon);
    cells.build(box, x0 + begin, y0 + begin, z0 + begin, m, horizon);
    cells.to_host();  // the search below runs on the host (set-up only)
    for (int i = begin; i < end; ++i) {
      row.clear();
      for_each_partner(i, begin, horizon, [&](int j, double) { row.push_back(j); });
      std::sort(row.begin(), row.end());
      int k = list.offset[static_cast<std::size_t>(i)];
      for (const int j : row) {
        // Same expression as the search, so row i and row j hold bitwise the same reference length.
        const double ddx = x0[j] - x0[i], ddy = y0[j] - y0[i], ddz = z0[j] - z0[i];
        list.partner[static_cast<std::size_t>(k)] = j;
        list.length0[static_cast<std::size_t>(k)] = std::sqrt(ddx * ddx + ddy * ddy + ddz * ddz);
        ++k;
      }
    }
  }
  return list;
}

}  // namespace debris
