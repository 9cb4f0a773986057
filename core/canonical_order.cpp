#include "core/canonical_order.hpp"

#include <algorithm>
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
  const double c[3] = {x, y, z};
  long long cell = 0;
  for (int a = 2; a >= 0; --a) {
    const auto k = static_cast<std::size_t>(a);
    // 1.0 / edge, as CellList::build bins.
    cell = cell * grid.dims[k] + cell_coordinate(c[a], box.lo[a], 1.0 / grid.edge[k], grid.dims[k], box.periodic[a]);
  }
  return cell;
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
