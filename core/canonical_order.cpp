#include "core/canonical_order.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <numeric>
#include <utility>

namespace debris {

CanonicalGrid CanonicalGrid::of(const BoxView& box, long long n_total, double cell_size) {
  CanonicalGrid g;
  g.box = box;
  g.grid = CellList::grid_for(box, n_total, cell_size);
  return g;
}

long long CanonicalGrid::cell_of(double x, double y, double z) const {
  const double r[3] = {x, y, z};
  long long c[3];
  for (int a = 0; a < 3; ++a) {
    const auto k = static_cast<std::size_t>(a);
    // 1.0 / edge, as CellList::build bins.
    c[a] = cell_coordinate(r[a], box.lo[a], 1.0 / grid.edge[k], grid.dims[k], box.periodic[a]);
  }
  // The cell's place in the order CellList::sort_order(key) visits cells in.
  const std::array<int, 3> ax = canonical_axes(box.periodic);
  const auto d = [&](int a) { return static_cast<long long>(grid.dims[static_cast<std::size_t>(a)]); };
  return c[ax[0]] + d(ax[0]) * (c[ax[1]] + d(ax[1]) * c[ax[2]]);
}

std::vector<int> canonical_order(const CanonicalGrid& g, const Particles& p) {
  std::vector<std::pair<long long, std::int64_t>> key(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) key[i] = {g.cell_of(p.x[i], p.y[i], p.z[i]), p.id[i]};
  std::vector<int> order(p.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(),
            [&](int u, int v) { return key[static_cast<std::size_t>(u)] < key[static_cast<std::size_t>(v)]; });
  return order;
}

}  // namespace debris
