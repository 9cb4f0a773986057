#include "core/comm/grain_migration.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <numeric>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/comm/communicator.hpp"
#include "core/comm/pack.hpp"

namespace debris::comm {

namespace {

int tag_of(int axis, int dir) { return 300 + 2 * axis + (dir > 0 ? 1 : 0); }

// A grain's record beside its node range: what travels with it.
constexpr std::array<exec::DeviceVector<int> PdGrains::*, 2> kIntColumns{&PdGrains::kind, &PdGrains::material};
constexpr std::array<exec::DeviceVector<double> PdGrains::*, 10> kDoubleColumns{
    &PdGrains::volume, &PdGrains::cx,  &PdGrains::cy,      &PdGrains::cz,      &PdGrains::cvx,
    &PdGrains::cvy,    &PdGrains::cvz, &PdGrains::wall_vx, &PdGrains::wall_vy, &PdGrains::wall_vz};

void refuse_walls(const PdGrains& g) {
  for (std::size_t k = 0; k < g.size(); ++k)
    if (g.kind[k] == static_cast<int>(PdGrainKind::wall))
      throw std::logic_error("comm: walls are not cut among ranks yet (grain " + std::to_string(k) + " is a wall)");
}

std::int64_t first_id(const GrainStore& s, std::size_t g) {
  return s.nodes.id[static_cast<std::size_t>(s.grains.node_begin[g])];
}

// Appends grain g whole: record, nodes, bond rows with partners counted from the grain's first node.
void pack_grain(const GrainStore& s, std::size_t g, std::vector<char>& out) {
  for (const auto m : kIntColumns) pack_value((s.grains.*m)[g], out);
  for (const auto m : kDoubleColumns) pack_value((s.grains.*m)[g], out);
  const int begin = s.grains.node_begin[g], end = s.grains.node_end[g];
  std::vector<int> rows(static_cast<std::size_t>(end - begin));
  std::iota(rows.begin(), rows.end(), begin);
  pack_records(s.nodes, rows, out);
  for (const int i : rows) {
    const auto u = static_cast<std::size_t>(i);
    pack_value(static_cast<std::int32_t>(s.bonds.offset[u + 1] - s.bonds.offset[u]), out);
    for (int e = s.bonds.offset[u]; e < s.bonds.offset[u + 1]; ++e) {
      const auto ue = static_cast<std::size_t>(e);
      pack_value(static_cast<std::int32_t>(s.bonds.partner[ue] - begin), out);
      pack_value(s.bonds.length0[ue], out);
      pack_value(s.bonds.broken[ue], out);
    }
  }
}

// Appends the grains of a message to the store; returns how many.
std::size_t unpack_grains(const std::vector<char>& in, GrainStore s) {
  if (in.empty()) return 0;
  Unpacker u(in);
  const auto n = static_cast<std::size_t>(u.value<std::int64_t>());
  if (s.bonds.offset.empty()) s.bonds.offset.push_back(0);
  for (std::size_t a = 0; a < n; ++a) {
    const std::size_t k = s.grains.size();
    s.grains.resize(k + 1);
    for (const auto m : kIntColumns) (s.grains.*m)[k] = u.value<int>();
    for (const auto m : kDoubleColumns) (s.grains.*m)[k] = u.value<double>();
    const auto [first, count] = u.records(s.nodes);
    s.grains.node_begin[k] = static_cast<int>(first);
    s.grains.node_end[k] = static_cast<int>(first + count);
    for (std::size_t i = first; i < first + count; ++i) {
      s.nodes.grain[i] = static_cast<int>(k);
      const auto bonds = static_cast<std::size_t>(u.value<std::int32_t>());
      for (std::size_t e = 0; e < bonds; ++e) {
        s.bonds.partner.push_back(static_cast<int>(first) + u.value<std::int32_t>());
        s.bonds.length0.push_back(u.value<double>());
        s.bonds.broken.push_back(u.value<unsigned char>());
      }
      s.bonds.offset.push_back(static_cast<int>(s.bonds.partner.size()));
    }
  }
  if (!u.done()) throw std::logic_error("comm: a grain message longer than its grains");
  return n;
}

// Sorts grain indices by the id of their first node (one process's order).
void sort_by_first_id(const GrainStore& s, std::vector<int>& grains) {
  std::sort(grains.begin(), grains.end(), [&](int a, int b) {
    return first_id(s, static_cast<std::size_t>(a)) < first_id(s, static_cast<std::size_t>(b));
  });
}

// Puts the store's grains in that order (stored again only when they are not in it already).
void sort_grains(GrainStore s) {
  std::vector<int> order(s.grains.size());
  std::iota(order.begin(), order.end(), 0);
  sort_by_first_id(s, order);
  if (!std::is_sorted(order.begin(), order.end())) select_grains(s, order);
}

}  // namespace

void select_grains(GrainStore s, const std::vector<int>& which) {
  std::vector<char> packed;
  pack_value(static_cast<std::int64_t>(which.size()), packed);
  for (const int g : which) pack_grain(s, static_cast<std::size_t>(g), packed);
  s.nodes.resize(0);
  s.grains.resize(0);
  s.bonds.offset.assign(1, 0);
  s.bonds.partner.clear();
  s.bonds.length0.clear();
  s.bonds.broken.clear();
  unpack_grains(packed, s);
}

void keep_owned_grains(const Decomposition& d, const Box& box, GrainStore s) {
  refuse_walls(s.grains);
  std::vector<int> mine;
  for (std::size_t g = 0; g < s.grains.size(); ++g)
    if (d.owner(box, s.grains.cx[g], s.grains.cy[g], s.grains.cz[g]) == d.rank()) mine.push_back(static_cast<int>(g));
  sort_by_first_id(s, mine);
  select_grains(s, mine);
}

GrainExchangeCount exchange_grains(const Decomposition& d, const Box& box, GrainStore s) {
  refuse_walls(s.grains);
  GrainExchangeCount count;
  for (int a = 0; a < 3; ++a) {
    if (d.grid()[a] == 1) continue;
    const int mine = d.coord()[a];
    const auto& centre = a == 0 ? s.grains.cx : (a == 1 ? s.grains.cy : s.grains.cz);
    std::vector<int> stay, to_below, to_above;
    for (std::size_t g = 0; g < s.grains.size(); ++g) {
      const int step = d.step_along(box, a, centre[g]);
      const int gi = static_cast<int>(g);
      if (step == 0)
        stay.push_back(gi);
      else if (step == +1)
        to_above.push_back(gi);
      else if (step == -1)
        to_below.push_back(gi);
      else
        throw std::runtime_error("the grain of node " + std::to_string(first_id(s, g)) + " moved past the next rank along " +
                                 std::string(1, "xyz"[a]) + " between two list builds (centre at " +
                                 std::to_string(centre[g]) + ")");
    }
    std::vector<char> out_below, out_above, in;
    for (auto [list, out] : {std::pair{&to_below, &out_below}, std::pair{&to_above, &out_above}}) {
      pack_value(static_cast<std::int64_t>(list->size()), *out);
      for (const int g : *list) pack_grain(s, static_cast<std::size_t>(g), *out);
    }
    count.sent += to_below.size() + to_above.size();
    select_grains(s, stay);
    for (const int dir : {-1, +1}) {
      sendrecv(dir < 0 ? out_below : out_above, d.neighbour(box, a, dir), in, d.neighbour(box, a, -dir), tag_of(a, dir));
      const std::size_t before = s.grains.size();
      count.received += unpack_grains(in, s);
      for (std::size_t g = before; g < s.grains.size(); ++g)
        if (d.index_along(box, a, centre[g]) != mine)
          throw std::runtime_error("the grain of node " + std::to_string(first_id(s, g)) +
                                   " arrived on a rank that does not own it");
    }
  }
  sort_grains(s);
  return count;
}

}  // namespace debris::comm
