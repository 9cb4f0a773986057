// What a PeriDEM run says of its whole system (output rows, node frames, the checks that stop a run, where
// a stage places a wall), the same on one process and on a run cut among ranks: there each rank
// computes it for what it owns, as one process computes it, and the ranks put the parts together.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "core/comm/communicator.hpp"
#include "core/comm/pack.hpp"
#include "scenarios/common/peridem/peridem_simulation.hpp"

namespace debris {

std::int64_t PeridemSimulation::whole_index(std::int64_t id) const {
  if (whole_ids_.empty()) return id;  // ids 0, 1, 2, ...: the index itself
  return std::lower_bound(whole_ids_.begin(), whole_ids_.end(), id) - whole_ids_.begin();
}

std::vector<int> PeridemSimulation::grain_kinds() const {
  if (distributed_) return whole_kinds_;
  return std::vector<int>(grains_.kind.begin(), grains_.kind.end());  // constant: current on the host
}

std::vector<PdGrainState> PeridemSimulation::grain_states() {
  // Centres current for this step: on ranks, the held grains' recomputed and the ghosts' from their owners.
  if (distributed_) {
    refresh_ghosts();
  } else {
    refresh_grain_centres();
  }
  const PeridemSimulation& view = *this;  // reads (offload builds: brought back, not marked as edited)
  const PdGrains& g = view.grains();
  const PdNodes& n = view.nodes();
  const BondList& b = view.bonds();
  std::vector<PdGrainState> states(distributed_ ? static_cast<std::size_t>(grain_count_) : g.size());
  std::vector<char> mine;
  for (std::size_t k = 0; k < g.size(); ++k) {
    if (g.kind[k] == static_cast<int>(PdGrainKind::wall) || !owns_grain(k)) continue;
    PdGrainState s;
    long entries = 0;  // broken bonds seen from both ends
    for (int i = g.node_begin[k]; i < g.node_end[k]; ++i) {
      const auto u = static_cast<std::size_t>(i);
      s.damage = std::max(s.damage, n.damage[u]);
      s.kinetic_energy += 0.5 * n.mass[u] * (n.vx[u] * n.vx[u] + n.vy[u] * n.vy[u] + n.vz[u] * n.vz[u]);
      for (int e = b.offset[u]; e < b.offset[u + 1]; ++e) entries += b.broken[static_cast<std::size_t>(e)] ? 1 : 0;
    }
    s.broken_bonds = entries / 2;
    s.centre = {g.cx[k], g.cy[k], g.cz[k]};
    s.velocity = {g.cvx[k], g.cvy[k], g.cvz[k]};
    if (!distributed_) {
      states[k] = s;
    } else {
      comm::pack_value(static_cast<std::int32_t>(g.id[k]), mine);
      comm::pack_value(s, mine);
    }
  }
  if (!distributed_) return states;
  for (const std::vector<char>& part : comm::gather_to_all(mine)) {
    comm::Unpacker u(part);
    while (!u.done()) {
      const auto id = static_cast<std::size_t>(u.value<std::int32_t>());
      states[id] = u.value<PdGrainState>();
    }
  }
  return states;
}

double PeridemSimulation::wall_edge(int whole_g, int axis, bool max) const {
  const int g = local_grain(whole_g);
  double edge = max ? -std::numeric_limits<double>::infinity() : std::numeric_limits<double>::infinity();
  if (g >= 0) {
    const PdNodes& n = nodes();
    const auto& coord = axis == 0 ? n.x : (axis == 1 ? n.y : n.z);
    const auto k = static_cast<std::size_t>(g);
    for (int i = grains_.node_begin[k]; i < grains_.node_end[k]; ++i)
      edge = max ? std::max(edge, coord[static_cast<std::size_t>(i)]) : std::min(edge, coord[static_cast<std::size_t>(i)]);
  }
  if (distributed_) (max ? comm::allreduce_max : comm::allreduce_min)(&edge, 1);  // each rank holds pieces
  return edge;
}

NodeFrameShare PeridemSimulation::frame_share() const {
  if (!distributed_) return NodeFrameShare::all_of(nodes_);
  NodeFrameShare share;
  share.total = node_total_;
  for (std::size_t i = 0; i < nodes_.size(); ++i) {
    if (!owns_node(i)) continue;
    share.which.push_back(static_cast<int>(i));
    share.rows.push_back(whole_index(nodes_.id[i]));
  }
  return share;
}

namespace {
// One process reports the problem at the node of lowest index, which is the lowest id: so do the ranks.
// One number over all ranks when no rank has a problem.
std::string lowest_id_message(std::int64_t id, const std::string& problem) {
  const double mine = problem.empty() ? std::numeric_limits<double>::infinity() : static_cast<double>(id);
  double least = mine;
  comm::allreduce_min(&least, 1);
  if (least == std::numeric_limits<double>::infinity()) return {};
  return comm::first_message(mine == least ? problem : std::string());
}
}  // namespace

std::string PeridemSimulation::health_check() const {
  std::int64_t id = 0;
  const std::string problem = local_health_check(&id);
  return distributed_ ? lowest_id_message(id, problem) : problem;
}

std::string PeridemSimulation::explosion_check() const {
  std::int64_t id = 0;
  const std::string problem = local_explosion_check(&id);
  return distributed_ ? lowest_id_message(id, problem) : problem;
}

std::string PeridemSimulation::penetration_check(double limit) const {
  std::int64_t id = 0;
  if (!distributed_) return local_penetration_check(limit, &id);
  // Every step: the deepest pair over all ranks first, and the pair only when it is too deep.
  double deepest = deepest_penetration();
  comm::allreduce_max(&deepest, 1);
  if (!(deepest > limit)) return {};
  const std::string problem = local_penetration_check(limit, &id);
  return lowest_id_message(id, problem);
}

}  // namespace debris
