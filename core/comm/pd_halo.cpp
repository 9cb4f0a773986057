#include "core/comm/pd_halo.hpp"

#include <algorithm>
#include <array>
#include <map>
#include <numeric>
#include <stdexcept>
#include <string>
#include <type_traits>

#include "core/comm/communicator.hpp"
#include "core/comm/pack.hpp"

namespace debris::comm {

namespace {

// Tags of the swaps: axis and direction (apart from the particle halo's and the migrations').
int tag_of(int axis, int dir) { return 500 + 2 * axis + (dir > 0 ? 1 : 0); }

// What borders() sends of a ghost's grain: the grain's columns but its node range.
struct GrainRecord {
  int kind = 0, material = 0;
  std::array<double, 10> value{};
};
constexpr std::array<exec::DeviceVector<double> PdGrains::*, 10> kGrainDoubles{
    &PdGrains::volume, &PdGrains::cx,  &PdGrains::cy,      &PdGrains::cz,      &PdGrains::cvx,
    &PdGrains::cvy,    &PdGrains::cvz, &PdGrains::wall_vx, &PdGrains::wall_vy, &PdGrains::wall_vz};

GrainRecord record_of(const PdGrains& g, std::size_t k) {
  GrainRecord r;
  r.kind = g.kind[k];
  r.material = g.material[k];
  for (std::size_t c = 0; c < kGrainDoubles.size(); ++c) r.value[c] = (g.*kGrainDoubles[c])[k];
  return r;
}

void store_record(PdGrains& g, std::size_t k, const GrainRecord& r) {
  g.kind[k] = r.kind;
  g.material[k] = r.material;
  for (std::size_t c = 0; c < kGrainDoubles.size(); ++c) (g.*kGrainDoubles[c])[k] = r.value[c];
}

// What forward() sends: a node's position and velocity, a grain's centre, mean velocity and mass.
constexpr std::size_t kNodeFields = 6, kGrainFields = 7;

// A swap as borders() makes it, in the indices of the moment (before the final sort).
struct PendingSwap {
  int to = -1, from = -1, tag = 0;
  std::vector<int> send_nodes;
  std::vector<std::int64_t> send_keys;  // grains of the sent nodes, by the id of their first node
  std::size_t first = 0, count = 0;     // received nodes
  std::vector<std::int64_t> recv_keys;
};

}  // namespace

void PdHalo::borders(const Decomposition& d, const Box& box, double width, GrainStore s) {
  for (int a = 0; a < 3; ++a)
    if (box.periodic(a)) throw std::logic_error("PdHalo: a PeriDEM domain has no periodic axes");
  const std::size_t n_owned = s.nodes.size(), g_owned = s.grains.size();
  // Grains are known by the id of their first node (a grain's ids are consecutive, from one process's store).
  std::vector<std::int64_t> owned_key(g_owned);
  for (std::size_t g = 0; g < g_owned; ++g) {
    owned_key[g] = s.nodes.id[static_cast<std::size_t>(s.grains.node_begin[g])];
    if (g > 0 && owned_key[g] <= owned_key[g - 1])
      throw std::logic_error("PdHalo: a rank's grains are not in increasing id");
  }
  std::vector<std::int64_t> node_key(n_owned);
  for (std::size_t i = 0; i < n_owned; ++i) node_key[i] = owned_key[static_cast<std::size_t>(s.nodes.grain[i])];
  std::map<std::int64_t, GrainRecord> ghost_grain;
  const auto record_of_key = [&](std::int64_t key) {
    const auto it = std::lower_bound(owned_key.begin(), owned_key.end(), key);
    if (it != owned_key.end() && *it == key) return record_of(s.grains, static_cast<std::size_t>(it - owned_key.begin()));
    return ghost_grain.at(key);
  };

  std::vector<PendingSwap> pending;
  for (int a = 0; a < 3; ++a) {
    if (d.grid()[a] == 1) continue;
    // Both directions scan the same nodes: the owned ones and the ghosts of earlier axes.
    const std::size_t scan = s.nodes.size();
    const double lo = d.sub_lo(box, a), hi = d.sub_hi(box, a);
    for (const int dir : {-1, +1}) {
      PendingSwap p;
      p.to = d.neighbour(box, a, dir);
      p.from = d.neighbour(box, a, -dir);
      p.tag = tag_of(a, dir);
      const double* c = position(s.nodes, a);
      if (p.to >= 0)
        for (std::size_t i = 0; i < scan; ++i)
          if (dir < 0 ? c[i] < lo + width : c[i] >= hi - width) p.send_nodes.push_back(static_cast<int>(i));
      for (const int i : p.send_nodes) p.send_keys.push_back(node_key[static_cast<std::size_t>(i)]);
      std::sort(p.send_keys.begin(), p.send_keys.end());
      p.send_keys.erase(std::unique(p.send_keys.begin(), p.send_keys.end()), p.send_keys.end());

      std::vector<char> out, in;
      if (p.to >= 0) {
        pack_records(s.nodes, p.send_nodes, out);
        for (const int i : p.send_nodes) pack_value(node_key[static_cast<std::size_t>(i)], out);
        pack_value(static_cast<std::int64_t>(p.send_keys.size()), out);
        for (const std::int64_t key : p.send_keys) {
          pack_value(key, out);
          pack_value(record_of_key(key), out);
        }
      }
      sendrecv(out, p.to, in, p.from, p.tag);
      p.first = s.nodes.size();
      if (!in.empty()) {
        Unpacker u(in);
        p.count = u.records(s.nodes).second;
        for (std::size_t k = 0; k < p.count; ++k) node_key.push_back(u.value<std::int64_t>());
        const auto grains = static_cast<std::size_t>(u.value<std::int64_t>());
        for (std::size_t k = 0; k < grains; ++k) {
          const auto key = u.value<std::int64_t>();
          ghost_grain[key] = u.value<GrainRecord>();
          p.recv_keys.push_back(key);
        }
        if (!u.done()) throw std::logic_error("PdHalo: a ghost message longer than its contents");
      }
      pending.push_back(std::move(p));
    }
  }

  // Owned nodes and ghosts together in increasing id; grains in increasing key.
  const std::size_t n = s.nodes.size();
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    return s.nodes.id[static_cast<std::size_t>(a)] < s.nodes.id[static_cast<std::size_t>(b)];
  });
  std::vector<int> now(n);
  for (std::size_t i = 0; i < n; ++i) now[static_cast<std::size_t>(order[i])] = static_cast<int>(i);
  s.nodes.for_each_column([&](const char*, auto& col) {
    using T = typename std::decay_t<decltype(col)>::value_type;
    const std::vector<T> old(col.begin(), col.end());
    for (std::size_t i = 0; i < n; ++i) col[i] = old[static_cast<std::size_t>(order[i])];
  });
  for (std::size_t i = 1; i < n; ++i)
    if (s.nodes.id[i] == s.nodes.id[i - 1])
      throw std::logic_error("PdHalo: node " + std::to_string(s.nodes.id[i]) + " arrived twice");

  std::vector<std::int64_t> keys(owned_key);
  for (const auto& [key, r] : ghost_grain) keys.push_back(key);
  std::sort(keys.begin(), keys.end());
  const auto grain_of_key = [&](std::int64_t key) {
    return static_cast<int>(std::lower_bound(keys.begin(), keys.end(), key) - keys.begin());
  };
  const PdGrains old_grains = s.grains;
  const std::size_t ng = keys.size();
  s.grains.resize(ng);
  owned_grain_.assign(ng, 0);
  for (std::size_t g = 0; g < ng; ++g) {
    const auto it = std::lower_bound(owned_key.begin(), owned_key.end(), keys[g]);
    if (it != owned_key.end() && *it == keys[g]) {
      store_record(s.grains, g, record_of(old_grains, static_cast<std::size_t>(it - owned_key.begin())));
      owned_grain_[g] = 1;
    } else {
      store_record(s.grains, g, ghost_grain.at(keys[g]));
    }
    s.grains.node_begin[g] = s.grains.node_end[g] = -1;
  }
  owned_node_.assign(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const auto was = static_cast<std::size_t>(order[i]);
    const int g = grain_of_key(node_key[was]);
    const auto ug = static_cast<std::size_t>(g);
    s.nodes.grain[i] = g;
    owned_node_[i] = was < n_owned ? 1 : 0;
    if (s.grains.node_begin[ug] < 0) s.grains.node_begin[ug] = static_cast<int>(i);
    if (s.grains.node_end[ug] >= 0 && s.grains.node_end[ug] != static_cast<int>(i))
      throw std::logic_error("PdHalo: the nodes of a grain do not have consecutive ids");
    s.grains.node_end[ug] = static_cast<int>(i) + 1;
  }
  ghost_nodes_ = n - n_owned;

  // Bond rows follow their nodes; ghosts have none.
  BondList old_bonds = std::move(s.bonds);
  s.bonds = BondList{};
  s.bonds.offset.assign(n + 1, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const auto was = static_cast<std::size_t>(order[i]);
    if (was < n_owned)
      for (int e = old_bonds.offset[was]; e < old_bonds.offset[was + 1]; ++e) {
        const auto ue = static_cast<std::size_t>(e);
        s.bonds.partner.push_back(now[static_cast<std::size_t>(old_bonds.partner[ue])]);
        s.bonds.length0.push_back(old_bonds.length0[ue]);
        s.bonds.broken.push_back(old_bonds.broken[ue]);
      }
    s.bonds.offset[i + 1] = static_cast<int>(s.bonds.partner.size());
  }

  swaps_.clear();
  for (const PendingSwap& p : pending) {
    Swap w;
    w.to = p.to;
    w.from = p.from;
    w.tag = p.tag;
    for (const int i : p.send_nodes) w.send_nodes.push_back(now[static_cast<std::size_t>(i)]);
    for (const std::int64_t key : p.send_keys) w.send_grains.push_back(grain_of_key(key));
    for (std::size_t k = 0; k < p.count; ++k) w.recv_nodes.push_back(now[p.first + k]);
    for (const std::int64_t key : p.recv_keys) w.recv_grains.push_back(grain_of_key(key));
    swaps_.push_back(std::move(w));
  }
}

void PdHalo::forward(PdNodes& nodes, PdGrains& grains, std::vector<double>& grain_mass) const {
  if (nodes.size() != owned_node_.size() || grains.size() != owned_grain_.size() || grain_mass.size() != grains.size())
    throw std::logic_error("PdHalo::forward: the nodes or grains changed since borders()");
  const std::array<exec::DeviceVector<double>*, kNodeFields> node_columns{&nodes.x,  &nodes.y,  &nodes.z,
                                                                           &nodes.vx, &nodes.vy, &nodes.vz};
  const std::array<exec::DeviceVector<double>*, kGrainFields - 1> grain_columns{&grains.cx,  &grains.cy,  &grains.cz,
                                                                                &grains.cvx, &grains.cvy, &grains.cvz};
  for (const Swap& s : swaps_) {
    // Sizes are fixed between builds on both sides: one message each way, no size exchange.
    out_.resize(kNodeFields * s.send_nodes.size() + kGrainFields * s.send_grains.size());
    in_.resize(kNodeFields * s.recv_nodes.size() + kGrainFields * s.recv_grains.size());
    double* o = out_.data();
    for (const auto* col : node_columns)
      for (const int i : s.send_nodes) *o++ = (*col)[static_cast<std::size_t>(i)];
    for (const auto* col : grain_columns)
      for (const int g : s.send_grains) *o++ = (*col)[static_cast<std::size_t>(g)];
    for (const int g : s.send_grains) *o++ = grain_mass[static_cast<std::size_t>(g)];
    sendrecv_sized(reinterpret_cast<const char*>(out_.data()), out_.size() * sizeof(double), s.to,
                   reinterpret_cast<char*>(in_.data()), in_.size() * sizeof(double), s.from, s.tag);
    const double* in = in_.data();
    for (auto* col : node_columns)
      for (const int i : s.recv_nodes) (*col)[static_cast<std::size_t>(i)] = *in++;
    for (auto* col : grain_columns)
      for (const int g : s.recv_grains) (*col)[static_cast<std::size_t>(g)] = *in++;
    for (const int g : s.recv_grains) grain_mass[static_cast<std::size_t>(g)] = *in++;
  }
}

void PdHalo::forward_counts(int* count) const {
  for (const Swap& s : swaps_) {
    iout_.clear();
    for (const int i : s.send_nodes) iout_.push_back(count[i]);
    iin_.resize(s.recv_nodes.size());
    sendrecv_sized(reinterpret_cast<const char*>(iout_.data()), iout_.size() * sizeof(int), s.to,
                   reinterpret_cast<char*>(iin_.data()), iin_.size() * sizeof(int), s.from, s.tag);
    for (std::size_t k = 0; k < s.recv_nodes.size(); ++k) count[s.recv_nodes[k]] = iin_[k];
  }
}

std::size_t PdHalo::forward_bytes() const {
  std::size_t n = 0;
  for (const Swap& s : swaps_)
    n += (kNodeFields * s.send_nodes.size() + kGrainFields * s.send_grains.size()) * sizeof(double);
  return n;
}

}  // namespace debris::comm
