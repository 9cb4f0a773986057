// PeridemSimulation cut among MPI ranks (shared/design/scale-mpi.md, section 5). A grain belongs
// whole to the rank whose subdomain holds its centre, so bonds, bond breaking and the per-grain sums stay on
// that rank; only contact needs copies of other ranks' nodes (core/comm/pd_halo).
//
// Why an owned node's force has one process's bits on any rank count:
//  - a rank stores its nodes (owned and ghosts) in increasing id and its grains in increasing id of their
//    first node, as one process does (there the ids increase with the index: distribute() checks it), so
//    an owned node's contact row lists the same partners in the same order, and the grain-pair slots of an
//    owned grain are one process's slots;
//  - bonds and their sums are the owned grain's own, in its own node order;
//  - a ghost's position, velocity, grain centre and grain mass are its owner's (refresh_ghosts() after every
//    integration), and so is the length of its contact row (share_row_counts(): the friction's stick mass
//    of eq 20 divides a node's mass among its row; a ghost's row here is partial);
//  - the list is rebuilt on the step one process rebuilds it (the largest drift over all ranks, from the
//    positions one process has), and the ghost width covers every pair that can come within R_c before the
//    next build: the largest grain extent from its centre plus R_c plus the skin.
// Ghost nodes are integrated and get forces like owned ones (the kernels do not tell them apart); those
// values are overwritten by their owners' before anything reads them.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>

#include "core/comm/communicator.hpp"
#include "core/comm/grain_migration.hpp"
#include "core/error.hpp"
#include "core/exit_status.hpp"
#include "core/pass_timer.hpp"
#include "scenarios/common/peridem/peridem_simulation.hpp"

namespace debris {

double PeridemSimulation::ghost_width() const {
  // How far any node of a grain reaches past its grain's owner's subdomain (at a build every owned grain's
  // centre lies inside it), over all ranks, plus the contact reach. Before the ranks are cut: the farthest
  // any node lies from its grain's centre (grains.cx .. cz current), which bounds that reach.
  // Walls are owned by position: their nodes lie in their owner's subdomain at a build.
  double reach = 0;
  for (std::size_t g = 0; g < grains_.size(); ++g) {
    if (grains_.kind[g] == static_cast<int>(PdGrainKind::wall)) continue;
    for (int i = grains_.node_begin[g]; i < grains_.node_end[g]; ++i) {
      if (distributed_ && !halo_.owned_nodes()[static_cast<std::size_t>(i)]) continue;
      if (distributed_) {
        const double p[3] = {nodes_.x[i], nodes_.y[i], nodes_.z[i]};
        // (The first and last subdomains of an axis reach past the box: no face there.)
        for (int a = 0; a < 3; ++a) {
          const int c = decomposition_.coord()[a];
          if (c > 0) reach = std::max(reach, decomposition_.sub_lo(box_, a) - p[a]);
          if (c < decomposition_.grid()[a] - 1) reach = std::max(reach, p[a] - decomposition_.sub_hi(box_, a));
        }
      } else {
        const double dx = nodes_.x[i] - grains_.cx[g], dy = nodes_.y[i] - grains_.cy[g], dz = nodes_.z[i] - grains_.cz[g];
        reach = std::max(reach, std::sqrt(dx * dx + dy * dy + dz * dz));
      }
    }
  }
  if (distributed_) comm::allreduce_max(&reach, 1);
  return reach + table_.max_contact_radius() + skin_;
}

void PeridemSimulation::distribute(std::array<int, 3> rank_grid) {
  if constexpr (exec::offload_build())
    throw std::runtime_error("a PeriDEM run cut among MPI ranks runs on host threads so far: use a host build under mpirun");
  if (distributed_) throw std::logic_error("PeridemSimulation::distribute: already distributed");
  if (settings_.damping_centre_node)
    throw input_error("damping_centre_node", "true", "is not cut among MPI ranks yet: run it as one process");
  for (std::size_t i = 1; i < nodes_.size(); ++i)
    if (nodes_.id[i] <= nodes_.id[i - 1])
      throw std::logic_error("PeridemSimulation::distribute: node ids must increase with the index, grain after grain");
  state_to_host();
  // The whole system's tables that output needs on every rank (kinds, node count, ids where they have gaps).
  grain_count_ = static_cast<int>(grains_.size());
  node_total_ = nodes_.size();
  whole_kinds_.assign(grains_.kind.begin(), grains_.kind.end());
  whole_ids_.clear();
  for (std::size_t i = 0; i < nodes_.size(); ++i)
    if (nodes_.id[i] != static_cast<std::int64_t>(i)) {
      whole_ids_.assign(nodes_.id.begin(), nodes_.id.end());
      break;
    }
  // Bonds broken so far are counted once, on rank 0 (each rank counts those it breaks from here).
  if (comm::rank() != 0) broken_total_ = 0;

  // The last list build replayed on these ranks: owners, ghosts and the list chosen by the positions at
  // that build (the list's own; the current ones at a fresh set-up), so a restored run continues with its
  // list, its next build at the same step, and one process's bits. The current state comes back after.
  const std::size_t n = nodes_.size();
  const Positions now{std::vector<double>(nodes_.x.begin(), nodes_.x.end()),
                      std::vector<double>(nodes_.y.begin(), nodes_.y.end()),
                      std::vector<double>(nodes_.z.begin(), nodes_.z.end())};
  const Positions at_build = positions_at_build();
  if (at_build[0].size() != n) throw std::logic_error("PeridemSimulation::distribute: the list does not match the nodes");
  nodes_.x.assign(at_build[0].begin(), at_build[0].end());
  nodes_.y.assign(at_build[1].begin(), at_build[1].end());
  nodes_.z.assign(at_build[2].begin(), at_build[2].end());
  pd_grain_centres(nodes_, grains_, work_);
  const double width = ghost_width();

  // The box around the nodes as placed, walled on every axis (the end subdomains reach past it); an axis
  // shorter than four ghost widths (the flat axis of a 2D run) is never cut.
  const Vec3 lo = placed_lo_;
  const Vec3 hi{std::max(placed_hi_.x, lo.x + width), std::max(placed_hi_.y, lo.y + width),
                std::max(placed_hi_.z, lo.z + width)};
  box_ = Box(lo, hi, {false, false, false});
  decomposition_ = comm::Decomposition::make(box_, comm::size(), comm::rank(), width, rank_grid);

  comm::GrainStore store{nodes_, grains_, bonds_};
  comm::keep_owned_grains(decomposition_, box_, store);
  halo_.set_owned(nodes_.size(), grains_.size());
  distributed_ = true;
  halo_.borders(decomposition_, box_, ghost_width(), store);
  list_.build(nodes_, grains_, bonds_, table_.max_contact_radius(), skin_);  // not counted: one process built it
  for (std::size_t i = 0; i < nodes_.size(); ++i) {
    const auto w = static_cast<std::size_t>(whole_index(nodes_.id[i]));
    nodes_.x[i] = now[0][w];
    nodes_.y[i] = now[1][w];
    nodes_.z[i] = now[2][w];
  }
  refresh_ghosts();
  // The forces of this step travelled with the nodes; the centre damping's slot forces (the wall reactions
  // read them) are recomputed from the same state, as a restart does: the same bits.
  if (settings_.damping == PdDamping::grain_centres) pd_centre_slot_forces(table_, nodes_, grains_, list_, work_);
}

void PeridemSimulation::refresh_ghosts() {
  pd_grain_centres(nodes_, grains_, work_);
  const PassTimer timer(times_.comm);
  halo_.forward(nodes_, grains_, work_.grain_mass);
}

void PeridemSimulation::share_row_counts() {
  const std::size_t n = nodes_.size();
  work_.row_count.resize(n);
  const auto& offset = list_.offset();
  for (std::size_t i = 0; i < n; ++i) work_.row_count[i] = offset[i + 1] - offset[i];
  const PassTimer timer(times_.comm);
  halo_.forward_counts(work_.row_count.data());
}

void PeridemSimulation::rebuild_distributed() {
  std::optional<PassTimer> timer(std::in_place, times_.comm);
  // The ghosts go (their owners send them again); grains whose centre left the subdomain, and wall nodes
  // that left it, move to its owner.
  comm::GrainStore store{nodes_, grains_, bonds_};
  comm::keep_nodes(store, halo_.owned_nodes());
  try {
    times_.grains_migrated += static_cast<long>(comm::exchange_grains(decomposition_, box_, store).sent);
  } catch (const std::runtime_error& e) {
    // A grain flew past the next rank: the run has blown up, and only this rank knows.
    std::fprintf(stderr, "error (rank %d): %s; is the time step stable?\n", comm::rank(), e.what());
    comm::abort(kExitUnfinished);
  }
  halo_.set_owned(nodes_.size(), grains_.size());
  // Grains deform and break: the width follows their reach, within what the subdomains allow.
  const double width = ghost_width();
  for (int a = 0; a < 3; ++a) {
    if (decomposition_.grid()[a] == 1) continue;
    double shortest = std::numeric_limits<double>::infinity();
    for (int c = 0; c < decomposition_.grid()[a]; ++c)
      shortest = std::min(shortest, decomposition_.cut(box_, a, c + 1) - decomposition_.cut(box_, a, c));
    if (2 * width > shortest * (1 + 1e-12)) {
      const auto most = comm::Decomposition::largest_counts(box_, width);
      // Every rank finds it (the width is the largest over all): all stop alike, and the run continues from
      // its last checkpoint on fewer ranks.
      throw RunStop("'mpirun -np' = " + std::to_string(comm::size()) + " (" + decomposition_.describe() +
                    "): a grain reaches " + format_value(width) +
                    " m with its contact reach, more than half of a subdomain (" + format_value(shortest) +
                    " m along " + std::string(1, "xyz"[a]) +
                    "): continue on fewer ranks, a smaller mpirun -np (at this reach the box takes at most " +
                    std::to_string(most[0]) + " along x, " + std::to_string(most[1]) + " along y and " +
                    std::to_string(most[2]) + " along z)");
    }
  }
  halo_.borders(decomposition_, box_, width, store);
  timer.reset();
  refresh_ghosts();
  const PassTimer build_timer(times_.neighbours);
  list_.build(nodes_, grains_, bonds_, table_.max_contact_radius(), skin_);
  ++rebuilds_;
  ++times_.rebuilds;
}

}  // namespace debris
