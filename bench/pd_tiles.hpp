#pragma once
// A PeriDEM system repeated side by side, for the benchmarks that need more of it than an input holds
// (BM_PdStepTiled; the weak-scaling run of bench/mpi_pd_weak_scaling.cpp, one tile per rank).
#include <algorithm>
#include <cstdint>

#include "core/pd_nodes.hpp"
#include "scenarios/common/peridem/peridem_input.hpp"

namespace debris {

/// The system tiles_x x tiles_y times side by side in the x-y plane: tile t is the input's system shifted by
/// whole multiples of its extent plus `gap` (1 mm: far beyond the contact cutoff, so tiles never touch; a
/// gap inside the contact radius puts neighbouring tiles' walls within reach of each other), the walls'
/// motion repeated. Grain order as the reader makes it: the particle grains of every tile, then the
/// walls of every tile; node ids renumbered in that order (from 0), grain after grain, as one process
/// stores an input's nodes (a run cut among ranks relies on it).
inline void tile_pd_system(PeridemRunConfig& cfg, int tiles_x, int tiles_y, double gap = 1e-3) {
  if (tiles_x * tiles_y == 1) return;
  const PdNodes in = cfg.nodes;
  const PdGrains g = cfg.grains;
  Vec3 lo{1e300, 1e300, 0}, hi{-1e300, -1e300, 0};
  for (std::size_t i = 0; i < in.size(); ++i) {
    lo.x = std::min(lo.x, in.x[i]), lo.y = std::min(lo.y, in.y[i]);
    hi.x = std::max(hi.x, in.x[i]), hi.y = std::max(hi.y, in.y[i]);
  }
  const double pitch_x = hi.x - lo.x + gap, pitch_y = hi.y - lo.y + gap;
  const int tiles = tiles_x * tiles_y;
  PdNodes out;
  PdGrains grains;
  for (const int kind : {static_cast<int>(PdGrainKind::particle), static_cast<int>(PdGrainKind::wall)})
    for (int t = 0; t < tiles; ++t)
      for (std::size_t gi = 0; gi < g.size(); ++gi) {
        if (g.kind[gi] != kind) continue;
        const double sx = (t % tiles_x) * pitch_x, sy = (t / tiles_x) * pitch_y;
        const int to = static_cast<int>(grains.size());
        grains.resize(static_cast<std::size_t>(to) + 1);
        const std::size_t k0 = out.size();
        out.resize(k0 + static_cast<std::size_t>(g.node_end[gi] - g.node_begin[gi]));
        for (int i = g.node_begin[gi]; i < g.node_end[gi]; ++i) {
          const std::size_t k = k0 + static_cast<std::size_t>(i - g.node_begin[gi]);
#define DEBRIS_COPY(name) out.name[k] = in.name[static_cast<std::size_t>(i)];
          DEBRIS_PD_NODE_DOUBLE_FIELDS(DEBRIS_COPY)
          DEBRIS_PD_NODE_INT_FIELDS(DEBRIS_COPY)
#undef DEBRIS_COPY
          out.x0[k] += sx, out.x[k] += sx, out.y0[k] += sy, out.y[k] += sy;
          out.grain[k] = to;
          out.id[k] = static_cast<std::int64_t>(k);
        }
        grains.node_begin[to] = static_cast<int>(k0);
        grains.node_end[to] = static_cast<int>(out.size());
        grains.kind[to] = g.kind[gi];
        grains.material[to] = g.material[gi];
        grains.volume[to] = g.volume[gi];
        grains.cx[to] = g.cx[gi] + sx, grains.cy[to] = g.cy[gi] + sy, grains.cz[to] = g.cz[gi];
        grains.cvx[to] = g.cvx[gi], grains.cvy[to] = g.cvy[gi], grains.cvz[to] = g.cvz[gi];
        grains.wall_vx[to] = g.wall_vx[gi], grains.wall_vy[to] = g.wall_vy[gi], grains.wall_vz[to] = g.wall_vz[gi];
      }
  cfg.nodes = std::move(out);
  cfg.grains = std::move(grains);
}

}  // namespace debris
