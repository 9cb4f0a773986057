// DemSimulation cut among MPI ranks (shared/design/scale-mpi.md): the set-up that keeps a rank's own
// particles, the rebuild that migrates them with their pair state and lays the ghosts around them, and the
// ways between a distributed run and the whole system as one process holds it: with_whole_system()
// gathers that on rank 0 (for the LAMMPS dump and the wear analysis), frame_share() and whole_rows() say
// where a rank's particles stand in a trajectory frame and in a one-process checkpoint (each rank writes its
// own rows), and a run restored from a checkpoint on any rank count replays the last rebuild on its own
// ranks (distribute_restored()).
#include <algorithm>
#include <cstdio>
#include <numeric>
#include <unordered_map>
#include <stdexcept>
#include <string>

#include "core/canonical_order.hpp"
#include "core/comm/communicator.hpp"
#include "core/comm/migration.hpp"
#include "core/comm/pack.hpp"
#include "core/error.hpp"
#include "core/pass_timer.hpp"
#include "scenarios/common/dem/dem_simulation.hpp"

namespace debris {

void DemSimulation::distribute() {
  if constexpr (exec::offload_build())
    throw std::runtime_error("a run cut among MPI ranks runs on host threads so far: use a host build under mpirun");
  if (!settings_.sort_by_cell)
    throw std::logic_error("DemSimulation: a run cut among ranks stores its particles in the canonical order");
  decomposition_ = comm::Decomposition::make(box_, comm::size(), comm::rank(), max_cutoff_ + skin_, settings_.rank_grid);
  remember_ids();
  box_.wrap(p_);
  comm::keep_owned(decomposition_, box_, p_);
  owned_.assign(p_.size(), 1);
}

void DemSimulation::remember_ids() {
  ids_in_order_.assign(p_.id.begin(), p_.id.end());
  std::sort(ids_in_order_.begin(), ids_in_order_.end());
  first_id_ = ids_in_order_.empty() ? 0 : ids_in_order_.front();
  // Consecutive ids (a lattice's, a LAMMPS data file's) need no table: the row is id - first id.
  if (!ids_in_order_.empty() && ids_in_order_.back() - first_id_ + 1 == static_cast<std::int64_t>(ids_in_order_.size()))
    ids_in_order_.clear();
}

FrameShare DemSimulation::frame_share() const {
  if (!distributed_) return FrameShare::all_of(particles());  // the host copy as the device left it
  FrameShare share;
  for (std::size_t i = 0; i < p_.size(); ++i)
    if (owned_[i]) share.which.push_back(static_cast<int>(i));
  std::sort(share.which.begin(), share.which.end(),
            [&](int a, int b) { return p_.id[static_cast<std::size_t>(a)] < p_.id[static_cast<std::size_t>(b)]; });
  share.total = particle_count();
  share.rows.resize(share.which.size());
  for (std::size_t k = 0; k < share.which.size(); ++k) {
    const std::int64_t id = p_.id[static_cast<std::size_t>(share.which[k])];
    if (ids_in_order_.empty()) share.rows[k] = id - first_id_;
    else share.rows[k] = std::lower_bound(ids_in_order_.begin(), ids_in_order_.end(), id) - ids_in_order_.begin();
  }
  return share;
}

std::int64_t DemSimulation::migrated_in_all() const {
  if (!distributed_) return 0;
  std::int64_t sent = times_.migrated;
  comm::allreduce_sum(&sent, 1);
  return sent;
}

void DemSimulation::rebuild_distributed() {
  {
    const PassTimer timer(times_.comm);
    // The pair state seen from each owned particle travels with it; the ghosts go (their owners send them
    // again). Owned particles keep their order until the canonical sort below.
    comm::PairRows rows;
    if (list_.rows() > 0) history_.rows_seen_from(p_, list_, owned_.data(), rows);
    std::vector<char> ghost(p_.size());
    for (std::size_t i = 0; i < p_.size(); ++i) ghost[i] = owned_[i] ? 0 : 1;
    p_.remove_if(ghost);
    if (rows.offset.size() != p_.size() + 1) rows.offset.assign(p_.size() + 1, 0);
    box_.wrap(p_);
    try {
      times_.migrated += static_cast<long>(comm::exchange(decomposition_, box_, p_, &rows).sent);
    } catch (const std::runtime_error& e) {
      // A particle flew past the next rank: the run has blown up, and only this rank knows (core/comm/migration).
      std::fprintf(stderr, "error (rank %d): %s; is the time step stable?\n", comm::rank(), e.what());
      comm::abort(kExitUnfinished);
    }
    const std::size_t owned = p_.size();
    halo_.borders(decomposition_, box_, max_cutoff_ + skin_, p_, owned);
    // Owned particles and ghosts together in the order one process would store the whole system in.
    build_grid_ = CanonicalGrid::of(box_.view(), n_total_, max_cutoff_ + skin_);
    const std::vector<int> order = canonical_order(build_grid_, p_);
    p_.permute(order);
    halo_.permute(order);
    owned_.resize(p_.size());
    std::vector<int> stored_at(owned);  // where each owned particle (and its pair rows) went
    for (std::size_t i = 0; i < p_.size(); ++i) {
      owned_[i] = order[i] < static_cast<int>(owned) ? 1 : 0;
      if (owned_[i]) stored_at[static_cast<std::size_t>(order[i])] = static_cast<int>(i);
    }
    history_.remember_rows(p_, rows, stored_at);
    ++layout_generation_;
  }
  const PassTimer timer(times_.neighbours);
  list_.build(box_.view(), p_, CohesiveCutoff{coef_}, max_cutoff_, skin_,
              pass_ == PairPass::half ? NeighborKind::half : NeighborKind::full);
  history_.carry_over(p_, list_);
  if (pass_ == PairPass::half) index_half_pass();
  ++times_.rebuilds;
}

namespace {
// A neighbour list and its pair state put together row by row (the whole system's from the ranks' rows, or a
// rank's share of the whole system's), then installed.
struct ListAssembly {
  NeighborList::Saved list;
  std::vector<double> hx, hy, hz;
  explicit ListAssembly(const NeighborList::Saved& like)
      : list{like.kind, like.skin, {0}, {}, {}, {}, {}, {like.len0[0], like.len0[1], like.len0[2]}} {}
  void begin_row(double x0, double y0, double z0) {
    list.x0.push_back(x0);
    list.y0.push_back(y0);
    list.z0.push_back(z0);
  }
  void entry(int j, double a, double b, double c) {
    list.index.push_back(j);
    hx.push_back(a);
    hy.push_back(b);
    hz.push_back(c);
  }
  void end_row() { list.offset.push_back(static_cast<int>(list.index.size())); }
  void install(NeighborList& l, ContactHistory& h) {
    l.restore(std::move(list));
    h.hx.assign(hx.begin(), hx.end());
    h.hy.assign(hy.begin(), hy.end());
    h.hz.assign(hz.begin(), hz.end());
  }
};

// Kept in the order packed.
struct GatheredRows {
  std::vector<long long> cell;
  std::vector<double> x0, y0, z0;
  std::vector<std::size_t> offset{0};
  std::vector<std::int64_t> partner;
  std::vector<double> h;  // 3 per entry
};
}  // namespace

void DemSimulation::with_whole_system(const std::function<void(const DemSimulation&)>& use) const {
  if (!distributed_) return use(*this);
  // Each rank sends its owned particles: their columns, the cell they were sorted by at the last build, their
  // positions then, and their rows of the half list (partner ids and pair state). Every listed pair of the
  // whole system is in the row of an owned particle on some rank, exactly once.
  std::vector<int> mine;
  for (std::size_t i = 0; i < p_.size(); ++i)
    if (owned_[i]) mine.push_back(static_cast<int>(i));
  const NeighborList::Saved built = list_.save();
  std::vector<char> out;
  comm::pack_records(p_, mine, out);
  for (const int i : mine) {
    const auto u = static_cast<std::size_t>(i);
    comm::pack_value(static_cast<std::int64_t>(build_grid_.cell_of(built.x0[u], built.y0[u], built.z0[u])), out);
    for (const double c : {built.x0[u], built.y0[u], built.z0[u]}) comm::pack_value(c, out);
    comm::pack_value(static_cast<std::int64_t>(built.offset[u + 1] - built.offset[u]), out);
    for (int k = built.offset[u]; k < built.offset[u + 1]; ++k) {
      const auto e = static_cast<std::size_t>(k);
      comm::pack_value(p_.id[static_cast<std::size_t>(built.index[e])], out);
      for (const double v : {history_.hx[e], history_.hy[e], history_.hz[e]}) comm::pack_value(v, out);
    }
  }
  const std::vector<std::vector<char>> all = comm::gather_to_root(out);
  if (comm::rank() != 0) return;

  Particles whole;
  whole.label_names = p_.label_names;
  GatheredRows g;
  for (const std::vector<char>& message : all) {
    comm::Unpacker u(message);
    const std::size_t n = u.records(whole).second;
    for (std::size_t k = 0; k < n; ++k) {
      g.cell.push_back(static_cast<long long>(u.value<std::int64_t>()));
      g.x0.push_back(u.value<double>());
      g.y0.push_back(u.value<double>());
      g.z0.push_back(u.value<double>());
      const auto entries = static_cast<std::size_t>(u.value<std::int64_t>());
      for (std::size_t e = 0; e < entries; ++e) {
        g.partner.push_back(u.value<std::int64_t>());
        for (int c = 0; c < 3; ++c) g.h.push_back(u.value<double>());
      }
      g.offset.push_back(g.partner.size());
    }
  }
  if (static_cast<long long>(whole.size()) != n_total_)
    throw std::logic_error("DemSimulation::with_whole_system: gathered " + std::to_string(whole.size()) + " of " +
                           std::to_string(n_total_) + " particles");
  // One process's storage order: by the cell at the build, then by id.
  std::vector<int> order(whole.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    const auto ua = static_cast<std::size_t>(a), ub = static_cast<std::size_t>(b);
    return g.cell[ua] != g.cell[ub] ? g.cell[ua] < g.cell[ub] : whole.id[ua] < whole.id[ub];
  });
  whole.permute(order);
  std::vector<int> index_of_id(static_cast<std::size_t>(whole.max_id() + 1), -1);
  for (std::size_t i = 0; i < whole.size(); ++i) index_of_id[static_cast<std::size_t>(whole.id[i])] = static_cast<int>(i);
  ListAssembly rows(built);
  for (std::size_t i = 0; i < whole.size(); ++i) {
    const auto o = static_cast<std::size_t>(order[i]);
    rows.begin_row(g.x0[o], g.y0[o], g.z0[o]);
    for (std::size_t e = g.offset[o]; e < g.offset[o + 1]; ++e) {
      const int j = index_of_id[static_cast<std::size_t>(g.partner[e])];
      if (j <= static_cast<int>(i) && built.kind == NeighborKind::half)
        throw std::logic_error("DemSimulation::with_whole_system: a half-list row out of the canonical order");
      rows.entry(j, g.h[3 * e], g.h[3 * e + 1], g.h[3 * e + 2]);
    }
    rows.end_row();
  }

  DemSimulation image{Restored{}};
  image.box_ = box_;
  image.p_ = std::move(whole);
  image.groups_ = groups_;
  image.settings_ = settings_;
  image.settings_.distribute = false;
  image.coef_ = coef_;
  image.limits_ = limits_;
  image.limit_radius_ = limit_radius_;
  image.limit_mass_ = limit_mass_;
  image.pass_ = pass_;
  image.dt_ = dt_;
  image.damping_ = damping_;
  image.skin_ = skin_;
  image.max_cutoff_ = max_cutoff_;
  image.step_ = step_;
  image.time_ = time_;
  rows.install(image.list_, image.history_);
  use(image);
}

DemSimulation::WholeRows DemSimulation::whole_rows(const NeighborList::Saved& built) const {
  WholeRows w;
  const std::size_t n = p_.size();
  auto entries_of = [&](std::size_t i) { return static_cast<std::int64_t>(built.offset[i + 1] - built.offset[i]); };
  if (!distributed_) {
    w.owned.resize(n);
    std::iota(w.owned.begin(), w.owned.end(), 0);
    w.row.assign(w.owned.begin(), w.owned.end());
    w.first_entry.assign(built.offset.begin(), built.offset.begin() + static_cast<std::ptrdiff_t>(n));
    w.particles = static_cast<std::int64_t>(n);
    w.entries = static_cast<std::int64_t>(built.index.size());
    return w;
  }
  // One process stores the system in the canonical order of the last build: by cell, then by id within a
  // cell. Per cell, summed over the ranks: its particles, the ranks holding some, their list entries.
  const auto& dims = build_grid_.grid.dims;
  const std::size_t cells = static_cast<std::size_t>(dims[0]) * static_cast<std::size_t>(dims[1]) *
                            static_cast<std::size_t>(dims[2]);
  std::vector<long long> cell(n);
  for (std::size_t i = 0; i < n; ++i) cell[i] = build_grid_.cell_of(built.x0[i], built.y0[i], built.z0[i]);
  std::vector<std::int64_t> per_cell(3 * cells, 0);
  for (std::size_t i = 0; i < n; ++i)
    if (owned_[i]) {
      const auto c = static_cast<std::size_t>(cell[i]);
      per_cell[3 * c] += 1;
      per_cell[3 * c + 1] = 1;
      per_cell[3 * c + 2] += entries_of(i);
    }
  if (per_cell.size() > static_cast<std::size_t>(INT32_MAX)) throw std::runtime_error("checkpoint: too many cells");
  comm::allreduce_sum(per_cell.data(), static_cast<int>(per_cell.size()));
  std::vector<std::int64_t> first_row(cells), first_entry(cells);
  for (std::size_t c = 0; c < cells; ++c) {
    first_row[c] = w.particles;
    first_entry[c] = w.entries;
    w.particles += per_cell[3 * c];
    w.entries += per_cell[3 * c + 2];
  }
  // A cell that several ranks hold particles of: every rank learns them all (id, entries) to place its own.
  std::vector<char> out;
  for (std::size_t i = 0; i < n; ++i)
    if (owned_[i] && per_cell[3 * static_cast<std::size_t>(cell[i]) + 1] > 1) {
      comm::pack_value(static_cast<std::int64_t>(cell[i]), out);
      comm::pack_value(p_.id[i], out);
      comm::pack_value(entries_of(i), out);
    }
  struct Member {
    std::int64_t id, entries;
  };
  std::unordered_map<long long, std::vector<Member>> shared;
  for (const std::vector<char>& message : comm::gather_to_all(out)) {
    comm::Unpacker u(message);
    while (!u.done()) {
      const auto c = static_cast<long long>(u.value<std::int64_t>());
      const auto id = u.value<std::int64_t>();
      shared[c].push_back({id, u.value<std::int64_t>()});
    }
  }
  for (auto& [c, members] : shared)
    std::sort(members.begin(), members.end(), [](const Member& a, const Member& b) { return a.id < b.id; });

  // This rank stores its particles in the same order, so the owned ones of a cell no other rank holds come
  // one after another, by id.
  std::vector<double> row(n, -1.0);  // exact: rows < 2^53
  long long current = -1;
  std::int64_t before = 0, entries_before = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (!owned_[i]) continue;
    const long long c = cell[i];
    const auto uc = static_cast<std::size_t>(c);
    std::int64_t r = first_row[uc], e = first_entry[uc];
    if (per_cell[3 * uc + 1] > 1) {
      for (const Member& m : shared.at(c)) {
        if (m.id == p_.id[i]) break;
        ++r;
        e += m.entries;
      }
    } else {
      if (c != current) current = c, before = 0, entries_before = 0;
      r += before++;
      e += entries_before;
      entries_before += entries_of(i);
    }
    w.owned.push_back(static_cast<int>(i));
    w.first_entry.push_back(e);
    row[i] = static_cast<double>(r);
  }
  // A ghost's row comes from its owner, for the list entries that name it.
  halo_.forward_values(row);
  w.row.assign(n, -1);
  for (std::size_t i = 0; i < n; ++i) w.row[i] = static_cast<std::int64_t>(row[i]);
  return w;
}

void DemSimulation::distribute_restored(std::array<int, 3> rank_grid) {
  if constexpr (exec::offload_build())
    throw std::runtime_error("a run cut among MPI ranks runs on host threads so far: use a host build under mpirun");
  // This object holds the whole system as one process did at the checkpoint. The last rebuild is replayed
  // on this rank count: owners and ghosts chosen by the positions at the build (the list's x0), stored in
  // the whole system's order (the canonical order of that build), and the list and history restricted to
  // them. Every owned particle then has its listed partners, and sums run as they did.
  settings_.rank_grid = rank_grid;
  n_total_ = static_cast<long long>(p_.size());
  distributed_ = true;
  remember_ids();
  decomposition_ = comm::Decomposition::make(box_, comm::size(), comm::rank(), max_cutoff_ + skin_, rank_grid);
  const NeighborList::Saved built = list_.save();
  Particles at_build = p_;
  at_build.x.assign(built.x0.begin(), built.x0.end());
  at_build.y.assign(built.y0.begin(), built.y0.end());
  at_build.z.assign(built.z0.begin(), built.z0.end());
  comm::keep_owned(decomposition_, box_, at_build);
  const std::size_t owned = at_build.size();
  halo_.borders(decomposition_, box_, max_cutoff_ + skin_, at_build, owned);
  std::vector<int> index_of_id(static_cast<std::size_t>(p_.max_id() + 1), -1);
  for (std::size_t i = 0; i < p_.size(); ++i) index_of_id[static_cast<std::size_t>(p_.id[i])] = static_cast<int>(i);
  std::vector<int> order(at_build.size());
  std::iota(order.begin(), order.end(), 0);
  auto global = [&](int i) { return index_of_id[static_cast<std::size_t>(at_build.id[static_cast<std::size_t>(i)])]; };
  std::sort(order.begin(), order.end(), [&](int a, int b) { return global(a) < global(b); });
  halo_.permute(order);
  owned_.assign(order.size(), 0);
  std::vector<int> from(order.size());  // whole-system index of each stored particle
  std::vector<int> local_of(p_.size(), -1);
  for (std::size_t i = 0; i < order.size(); ++i) {
    owned_[i] = order[i] < static_cast<int>(owned) ? 1 : 0;
    from[i] = global(order[i]);
    local_of[static_cast<std::size_t>(from[i])] = static_cast<int>(i);
  }
  // The state now (every column) from the whole system; the list and history restricted to this rank.
  Particles local = p_;
  local.permute(from);  // the first from.size() rows: this rank's particles, in order
  local.resize(from.size());
  ListAssembly rows(built);
  for (std::size_t i = 0; i < from.size(); ++i) {
    const auto g = static_cast<std::size_t>(from[i]);
    rows.begin_row(built.x0[g], built.y0[g], built.z0[g]);
    for (int k = built.offset[g]; k < built.offset[g + 1]; ++k) {
      const auto e = static_cast<std::size_t>(k);
      const int j = local_of[static_cast<std::size_t>(built.index[e])];
      if (j < 0) {
        if (owned_[i])
          throw std::logic_error("DemSimulation::distribute_restored: particle id " + std::to_string(local.id[i]) +
                                 " has a listed partner beyond the ghost layer");
        continue;  // two ghosts: their pair is another rank's
      }
      rows.entry(j, history_.hx[e], history_.hy[e], history_.hz[e]);
    }
    rows.end_row();
  }
  p_ = std::move(local);
  rows.install(list_, history_);
  build_grid_ = CanonicalGrid::of(box_.view(), n_total_, max_cutoff_ + skin_);
  ++layout_generation_;
  if (pass_ == PairPass::half) index_half_pass();
}

}  // namespace debris
