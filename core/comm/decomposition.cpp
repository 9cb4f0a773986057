#include "core/comm/decomposition.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "core/error.hpp"

namespace debris::comm {

namespace {
double axis_value(Vec3 v, int a) { return a == 0 ? v.x : (a == 1 ? v.y : v.z); }

bool wide_enough(const Box& box, std::array<int, 3> g, double w) {
  for (int a = 0; a < 3; ++a)
    if (g[a] > 1 && box.length(a) / g[a] < 2.0 * w) return false;
  return true;
}

std::string grid_text(std::array<int, 3> g) {
  return std::to_string(g[0]) + " x " + std::to_string(g[1]) + " x " + std::to_string(g[2]);
}
}  // namespace

std::array<int, 3> Decomposition::largest_counts(const Box& box, double ghost_width) {
  std::array<int, 3> n{1, 1, 1};
  for (int a = 0; a < 3; ++a) {
    const double k = std::floor(box.length(a) / (2.0 * ghost_width));
    n[a] = k >= 1.0 ? static_cast<int>(std::min(k, 1e6)) : 1;
  }
  return n;
}

Decomposition Decomposition::make(const Box& box, int ranks, int rank, double ghost_width,
                                  std::array<int, 3> requested, const std::string& key) {
  if (ranks < 1 || rank < 0 || rank >= ranks)
    throw input_error(key, std::to_string(ranks), "the rank count must be at least 1");
  if (!(ghost_width > 0.0) || !std::isfinite(ghost_width))
    throw input_error("ghost width", format_value(ghost_width), "must be a positive length");
  const auto largest = largest_counts(box, ghost_width);
  const auto refuse = [&](const std::string& what) {
    // Named for what the user can change: the rank count mpirun starts, and the box. No unit is printed
    // after a length: a run of plain numbers has its own.
    const long most = static_cast<long>(largest[0]) * largest[1] * largest[2];
    std::ostringstream os;
    os << what << ": this box, " << format_value(box.length(0)) << " x " << format_value(box.length(1)) << " x "
       << format_value(box.length(2)) << ", takes at most " << largest[0] << " along x, " << largest[1]
       << " along y and " << largest[2] << " along z (" << most << (most == 1 ? " rank" : " ranks")
       << " in all), since a subdomain must be at least twice the ghost width wide on every cut axis (2 x "
       << format_value(ghost_width)
       << ": the pair cutoff + skin, and for PeriDEM grains their reach; lengths in metres, or in the "
          "input's own unit where it gives plain numbers); start at most "
       << most << (most == 1 ? " rank" : " ranks") << " (mpirun -np " << most << "), or make the box larger";
    return input_error(key, std::to_string(ranks), os.str());
  };

  std::array<int, 3> best{0, 0, 0};
  if (requested != std::array<int, 3>{0, 0, 0}) {
    if (requested[0] < 1 || requested[1] < 1 || requested[2] < 1 ||
        static_cast<long>(requested[0]) * requested[1] * requested[2] != ranks)
      throw input_error(key, grid_text(requested), "the grid must multiply to the rank count, " + std::to_string(ranks));
    if (!wide_enough(box, requested, ghost_width)) throw refuse("the grid " + grid_text(requested) + " is too thin");
    best = requested;
  } else {
    // Least surface between subdomains (the halo's size): the sum over cut axes of the area of one cut
    // plane times the number of planes. Ties go to the first grid found (the most cuts along x, then y), so
    // every rank picks the same grid.
    double best_area = std::numeric_limits<double>::infinity();
    const double lx = box.length(0), ly = box.length(1), lz = box.length(2);
    for (int px = ranks; px >= 1; --px) {
      if (ranks % px) continue;
      for (int py = ranks / px; py >= 1; --py) {
        if ((ranks / px) % py) continue;
        const int pz = ranks / px / py;
        const std::array<int, 3> g{px, py, pz};
        if (!wide_enough(box, g, ghost_width)) continue;
        const double area = (px - 1) * ly * lz + (py - 1) * lx * lz + (pz - 1) * lx * ly;
        if (area < best_area) {
          best_area = area;
          best = g;
        }
      }
    }
    if (best[0] == 0) throw refuse("no grid of " + std::to_string(ranks) + " ranks fits this box");
  }

  Decomposition d;
  d.grid_ = best;
  d.coord_ = d.coord_of_rank(rank);
  for (int a = 0; a < 3; ++a) {
    auto& f = d.fraction_[a];
    f.resize(static_cast<std::size_t>(best[a]) + 1);
    for (int i = 0; i <= best[a]; ++i) f[static_cast<std::size_t>(i)] = static_cast<double>(i) / best[a];
  }
  return d;
}

std::array<int, 3> Decomposition::coord_of_rank(int r) const {
  return {r % grid_[0], (r / grid_[0]) % grid_[1], r / (grid_[0] * grid_[1])};
}

int Decomposition::neighbour(const Box& box, int axis, int dir) const {
  auto c = coord_;
  c[axis] += dir;
  if (c[axis] < 0 || c[axis] >= grid_[axis]) {
    if (!box.periodic(axis)) return -1;
    c[axis] = (c[axis] + grid_[axis]) % grid_[axis];
  }
  return rank_of(c);
}

double Decomposition::cut(const Box& box, int axis, int i) const {
  if (i <= 0) return axis_value(box.lo(), axis);
  if (i >= grid_[axis]) return axis_value(box.hi(), axis);
  return axis_value(box.lo(), axis) + fraction_[axis][static_cast<std::size_t>(i)] * box.length(axis);
}

int Decomposition::index_along(const Box& box, int axis, double v) const {
  // The cut planes themselves decide (no division), so a coordinate on a plane goes where sub_lo/sub_hi say.
  int i = 0;
  while (i + 1 < grid_[axis] && v >= cut(box, axis, i + 1)) ++i;
  return i;
}

int Decomposition::step_along(const Box& box, int axis, double v) const {
  const int n = grid_[axis], mine = coord_[axis], k = index_along(box, axis, v);
  const bool periodic = box.periodic(axis);
  if (k == mine) return 0;
  if (k == mine + 1 || (periodic && mine == n - 1 && k == 0)) return +1;
  if (k == mine - 1 || (periodic && mine == 0 && k == n - 1)) return -1;
  return kTooFar;
}

int Decomposition::owner(const Box& box, double x, double y, double z) const {
  return rank_of({index_along(box, 0, x), index_along(box, 1, y), index_along(box, 2, z)});
}

std::string Decomposition::describe() const {
  std::string cut_axes;
  for (int a = 0; a < 3; ++a)
    if (grid_[a] > 1) cut_axes += std::string(cut_axes.empty() ? "" : ", ") + "xyz"[a];
  return grid_text(grid_) + (cut_axes.empty() ? " (not cut)" : " (cut along " + cut_axes + ")");
}

}  // namespace debris::comm
