#include "core/comm/grain_migration.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <numeric>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/comm/communicator.hpp"
#include "core/comm/pack.hpp"

namespace debris::comm {

namespace {

int tag_of(int axis, int dir) { return 300 + 2 * axis + (dir > 0 ? 1 : 0); }


bool is_wall(const PdGrains& g, std::size_t k) { return g.kind[k] == static_cast<int>(PdGrainKind::wall); }

// Appends a piece of grain g: its record and the nodes `rows` (all of a particle grain, in order; any of a
// wall's), with their bond rows, partners counted from rows.front() (a particle grain's bonds stay within it;
// walls have none).
void pack_piece(const GrainStore& s, std::size_t g, const std::vector<int>& rows, std::vector<char>& out) {
  pack_value(GrainRecord::of(s.grains, g), out);
  pack_records(s.nodes, rows, out);
  const int base = rows.empty() ? 0 : rows.front();
  const bool bonded = !s.bonds.offset.empty();
  // The bond weights (pd_weighted_volume_pass) travel when the store has them.
  const bool weighted = bonded && !s.bonds.partner.empty() && s.bonds.weight.size() == s.bonds.partner.size();
  pack_value(static_cast<unsigned char>(weighted), out);
  for (const int i : rows) {
    const auto u = static_cast<std::size_t>(i);
    const int first = bonded ? s.bonds.offset[u] : 0, last = bonded ? s.bonds.offset[u + 1] : 0;
    pack_value(static_cast<std::int32_t>(last - first), out);
    for (int e = first; e < last; ++e) {
      const auto ue = static_cast<std::size_t>(e);
      pack_value(static_cast<std::int32_t>(s.bonds.partner[ue] - base), out);
      pack_value(s.bonds.length0[ue], out);
      pack_value(s.bonds.broken[ue], out);
      if (weighted) pack_value(s.bonds.weight[ue], out);
    }
  }
}

// Appends the pieces of a message, each as a grain of its own (pieces of one wall are merged by
// sort_store); returns how many.
std::size_t unpack_pieces(const std::vector<char>& in, GrainStore s) {
  if (in.empty()) return 0;
  Unpacker u(in);
  const auto n = static_cast<std::size_t>(u.value<std::int64_t>());
  if (s.bonds.offset.empty()) s.bonds.offset.assign(s.nodes.size() + 1, 0);
  for (std::size_t a = 0; a < n; ++a) {
    const std::size_t k = s.grains.size();
    s.grains.resize(k + 1);
    u.value<GrainRecord>().store(s.grains, k);
    const auto [first, count] = u.records(s.nodes);
    s.grains.node_begin[k] = static_cast<int>(first);
    s.grains.node_end[k] = static_cast<int>(first + count);
    const bool weighted = u.value<unsigned char>() != 0;
    for (std::size_t i = first; i < first + count; ++i) {
      s.nodes.grain[i] = static_cast<int>(k);
      const auto bonds = static_cast<std::size_t>(u.value<std::int32_t>());
      for (std::size_t e = 0; e < bonds; ++e) {
        s.bonds.partner.push_back(static_cast<int>(first) + u.value<std::int32_t>());
        s.bonds.length0.push_back(u.value<double>());
        s.bonds.broken.push_back(u.value<unsigned char>());
        if (weighted) s.bonds.weight.push_back(u.value<double>());
      }
      s.bonds.offset.push_back(static_cast<int>(s.bonds.partner.size()));
    }
  }
  if (!u.done()) throw std::logic_error("comm: a grain message longer than its grains");
  // Weights from every piece or from none (a piece without them leaves the store without them).
  if (s.bonds.weight.size() != s.bonds.partner.size()) s.bonds.weight.clear();
  return n;
}

double node_at_of(const GrainStore& s, int axis, int i) { return position(s.nodes, axis)[i]; }

// The whole system's identity of the grain of node i: its id.
int grain_id_of(const GrainStore& s, std::size_t i) {
  return s.grains.id[static_cast<std::size_t>(s.nodes.grain[i])];
}

// The record's columns, in its order.
constexpr std::array<exec::DeviceVector<int> PdGrains::*, 3> kIntColumns{&PdGrains::kind, &PdGrains::material,
                                                                         &PdGrains::id};
constexpr std::array<exec::DeviceVector<double> PdGrains::*, 10> kDoubleColumns{
    &PdGrains::volume, &PdGrains::cx,  &PdGrains::cy,      &PdGrains::cz,      &PdGrains::cvx,
    &PdGrains::cvy,    &PdGrains::cvz, &PdGrains::wall_vx, &PdGrains::wall_vy, &PdGrains::wall_vz};

}  // namespace

GrainRecord GrainRecord::of(const PdGrains& g, std::size_t k) {
  GrainRecord r;
  for (std::size_t c = 0; c < kIntColumns.size(); ++c) r.ints[c] = (g.*kIntColumns[c])[k];
  for (std::size_t c = 0; c < kDoubleColumns.size(); ++c) r.doubles[c] = (g.*kDoubleColumns[c])[k];
  return r;
}

void GrainRecord::store(PdGrains& g, std::size_t k) const {
  for (std::size_t c = 0; c < kIntColumns.size(); ++c) (g.*kIntColumns[c])[k] = ints[c];
  for (std::size_t c = 0; c < kDoubleColumns.size(); ++c) (g.*kDoubleColumns[c])[k] = doubles[c];
}

std::vector<int> sort_store(GrainStore s) {
  const std::size_t n = s.nodes.size();
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    return s.nodes.id[static_cast<std::size_t>(a)] < s.nodes.id[static_cast<std::size_t>(b)];
  });
  std::vector<int> now(n);
  for (std::size_t i = 0; i < n; ++i) now[static_cast<std::size_t>(order[i])] = static_cast<int>(i);

  // Grains: one per id among the nodes, in increasing id; a grain's record from the first grain of its id.
  std::vector<int> ids(n), record_of;
  for (std::size_t i = 0; i < n; ++i) ids[i] = grain_id_of(s, i);
  std::vector<int> grain_ids(ids);
  std::sort(grain_ids.begin(), grain_ids.end());
  grain_ids.erase(std::unique(grain_ids.begin(), grain_ids.end()), grain_ids.end());
  const auto index_of = [&](int id) {
    return static_cast<int>(std::lower_bound(grain_ids.begin(), grain_ids.end(), id) - grain_ids.begin());
  };
  record_of.assign(grain_ids.size(), -1);
  for (std::size_t g = s.grains.size(); g-- > 0;) {  // backwards: the first grain of an id wins
    const auto it = std::lower_bound(grain_ids.begin(), grain_ids.end(), s.grains.id[g]);
    if (it != grain_ids.end() && *it == s.grains.id[g]) record_of[static_cast<std::size_t>(it - grain_ids.begin())] = static_cast<int>(g);
  }
  const PdGrains old = s.grains;
  s.grains.resize(grain_ids.size());
  for (std::size_t g = 0; g < grain_ids.size(); ++g) {
    const auto from = static_cast<std::size_t>(record_of[g]);
    GrainRecord::of(old, from).store(s.grains, g);
    s.grains.node_begin[g] = s.grains.node_end[g] = -1;
  }

  s.nodes.for_each_column([&](const char*, auto& col) {
    using T = typename std::decay_t<decltype(col)>::value_type;
    const std::vector<T> was(col.begin(), col.end());
    for (std::size_t i = 0; i < n; ++i) col[i] = was[static_cast<std::size_t>(order[i])];
  });
  for (std::size_t i = 0; i < n; ++i) {
    if (i > 0 && s.nodes.id[i] == s.nodes.id[i - 1])
      throw std::logic_error("comm: node " + std::to_string(s.nodes.id[i]) + " is held twice");
    const int g = index_of(ids[static_cast<std::size_t>(order[i])]);
    const auto ug = static_cast<std::size_t>(g);
    s.nodes.grain[i] = g;
    if (s.grains.node_begin[ug] < 0) s.grains.node_begin[ug] = static_cast<int>(i);
    if (s.grains.node_end[ug] >= 0 && s.grains.node_end[ug] != static_cast<int>(i))
      throw std::logic_error("comm: the nodes of grain " + std::to_string(grain_ids[ug]) + " do not have consecutive ids");
    s.grains.node_end[ug] = static_cast<int>(i) + 1;
  }

  // Bond rows follow their nodes.
  const BondList was = std::move(s.bonds);
  s.bonds = BondList{};
  s.bonds.offset.assign(n + 1, 0);
  const bool bonded = was.offset.size() == n + 1;
  const bool weighted = !was.partner.empty() && was.weight.size() == was.partner.size();
  for (std::size_t i = 0; i < n; ++i) {
    const auto from = static_cast<std::size_t>(order[i]);
    if (bonded)
      for (int e = was.offset[from]; e < was.offset[from + 1]; ++e) {
        const auto ue = static_cast<std::size_t>(e);
        s.bonds.partner.push_back(now[static_cast<std::size_t>(was.partner[ue])]);
        s.bonds.length0.push_back(was.length0[ue]);
        s.bonds.broken.push_back(was.broken[ue]);
        if (weighted) s.bonds.weight.push_back(was.weight[ue]);
      }
    s.bonds.offset[i + 1] = static_cast<int>(s.bonds.partner.size());
  }
  return order;
}

namespace {
// The pieces of `s` made of the nodes flagged in `keep`, as one message (the count of pieces first).
std::vector<char> pack_kept(const GrainStore& s, const std::vector<unsigned char>& keep) {
  if (keep.size() != s.nodes.size()) throw std::logic_error("comm: one flag per node is needed");
  std::vector<char> message(sizeof(std::int64_t));  // the count of pieces, written last
  std::int64_t pieces = 0;
  for (std::size_t g = 0; g < s.grains.size(); ++g) {
    std::vector<int> rows;
    for (int i = s.grains.node_begin[g]; i < s.grains.node_end[g]; ++i)
      if (keep[static_cast<std::size_t>(i)]) rows.push_back(i);
    if (rows.empty()) continue;
    if (!is_wall(s.grains, g) && static_cast<int>(rows.size()) != s.grains.node_end[g] - s.grains.node_begin[g])
      throw std::logic_error("comm: a particle grain is kept whole or not at all");
    pack_piece(s, g, rows, message);
    ++pieces;
  }
  std::memcpy(message.data(), &pieces, sizeof pieces);
  return message;
}

void clear(GrainStore s) {
  s.nodes.resize(0);
  s.grains.resize(0);
  s.bonds = BondList{};
  s.bonds.offset.assign(1, 0);
}
}  // namespace

void keep_nodes(GrainStore s, const std::vector<unsigned char>& keep) {
  const std::vector<char> message = pack_kept(s, keep);
  clear(s);
  unpack_pieces(message, s);
  sort_store(s);
}

void gather_to_root(const GrainStore& s, const std::vector<unsigned char>& owned, GrainStore whole) {
  const std::vector<std::vector<char>> all = gather_to_root(pack_kept(s, owned));
  clear(whole);
  for (const std::vector<char>& message : all) unpack_pieces(message, whole);  // none but on rank 0
  if (!all.empty()) sort_store(whole);
}

void select_grains(GrainStore s, const std::vector<int>& which) {
  std::vector<unsigned char> keep(s.nodes.size(), 0);
  for (const int g : which)
    for (int i = s.grains.node_begin[static_cast<std::size_t>(g)]; i < s.grains.node_end[static_cast<std::size_t>(g)]; ++i)
      keep[static_cast<std::size_t>(i)] = 1;
  keep_nodes(s, keep);
}

void keep_owned_grains(const Decomposition& d, const Box& box, GrainStore s) {
  std::vector<unsigned char> keep(s.nodes.size(), 0);
  for (std::size_t g = 0; g < s.grains.size(); ++g)
    for (int i = s.grains.node_begin[g]; i < s.grains.node_end[g]; ++i) {
      const auto u = static_cast<std::size_t>(i);
      keep[u] = is_wall(s.grains, g) ? d.owner(box, s.nodes.x[u], s.nodes.y[u], s.nodes.z[u]) == d.rank()
                                     : d.owner(box, s.grains.cx[g], s.grains.cy[g], s.grains.cz[g]) == d.rank();
    }
  keep_nodes(s, keep);
}

GrainExchangeCount exchange_grains(const Decomposition& d, const Box& box, GrainStore s) {
  GrainExchangeCount count;
  for (int a = 0; a < 3; ++a) {
    if (d.grid()[a] == 1) continue;
    const int mine = d.coord()[a];
    const auto& centre = a == 0 ? s.grains.cx : (a == 1 ? s.grains.cy : s.grains.cz);
    const double* node_at = position(s.nodes, a);
    // Where each node goes: a particle grain's nodes with its centre, a wall's each by its own position.
    std::vector<int> step(s.nodes.size(), 0);
    for (std::size_t g = 0; g < s.grains.size(); ++g) {
      const bool wall = is_wall(s.grains, g);
      const int grain_step = wall ? 0 : d.step_along(box, a, centre[g]);
      for (int i = s.grains.node_begin[g]; i < s.grains.node_end[g]; ++i) {
        const auto u = static_cast<std::size_t>(i);
        step[u] = wall ? d.step_along(box, a, node_at[u]) : grain_step;
        if (step[u] == Decomposition::kTooFar)
          throw std::runtime_error((wall ? "wall node " + std::to_string(s.nodes.id[u])
                                         : "the grain of node " + std::to_string(s.nodes.id[static_cast<std::size_t>(s.grains.node_begin[g])])) +
                                   " moved past the next rank along " + std::string(1, "xyz"[a]) +
                                   " between two list builds (at " + std::to_string(wall ? node_at[u] : centre[g]) + ")");
      }
    }
    // Each message: the count of pieces (written last), then the pieces.
    std::vector<char> out_below(sizeof(std::int64_t)), out_above(sizeof(std::int64_t)), in;
    std::int64_t pieces_below = 0, pieces_above = 0;
    std::vector<unsigned char> keep(s.nodes.size(), 1);
    for (std::size_t g = 0; g < s.grains.size(); ++g) {
      std::vector<int> below, above;
      for (int i = s.grains.node_begin[g]; i < s.grains.node_end[g]; ++i) {
        const int st = step[static_cast<std::size_t>(i)];
        if (st != 0) keep[static_cast<std::size_t>(i)] = 0;
        if (st < 0) below.push_back(i);
        if (st > 0) above.push_back(i);
      }
      if (!below.empty()) pack_piece(s, g, below, out_below), ++pieces_below;
      if (!above.empty()) pack_piece(s, g, above, out_above), ++pieces_above;
      if (!is_wall(s.grains, g)) count.sent += !below.empty() || !above.empty() ? 1 : 0;
    }
    std::memcpy(out_below.data(), &pieces_below, sizeof pieces_below);
    std::memcpy(out_above.data(), &pieces_above, sizeof pieces_above);
    keep_nodes(s, keep);
    for (const int dir : {-1, +1}) {
      sendrecv(dir < 0 ? out_below : out_above, d.neighbour(box, a, dir), in, d.neighbour(box, a, -dir), tag_of(a, dir));
      const std::size_t before = s.grains.size();
      unpack_pieces(in, s);
      for (std::size_t g = before; g < s.grains.size(); ++g) {
        const bool wall = is_wall(s.grains, g);
        if (!wall) ++count.received;
        for (int i = s.grains.node_begin[g]; i < s.grains.node_end[g] && (wall || i == s.grains.node_begin[g]); ++i)
          if (d.index_along(box, a, wall ? node_at_of(s, a, i) : centre[g]) != mine)
            throw std::runtime_error("the grain of node " + std::to_string(s.nodes.id[static_cast<std::size_t>(i)]) +
                                     " arrived on a rank that does not own it");
      }
    }
    sort_store(s);
  }
  return count;
}

}  // namespace debris::comm
