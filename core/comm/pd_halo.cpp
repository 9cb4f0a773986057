#include "core/comm/pd_halo.hpp"

#include <algorithm>
#include <array>
#include <map>
#include <stdexcept>
#include <string>
#include <type_traits>

#include "core/comm/communicator.hpp"
#include "core/comm/pack.hpp"

namespace debris::comm {

namespace {

// Tags of the swaps: axis and direction (apart from the particle halo's and the migrations').
int tag_of(int axis, int dir) { return 500 + 2 * axis + (dir > 0 ? 1 : 0); }

// What forward() sends: a node's position and velocity, a grain's centre, mean velocity and mass.
constexpr std::size_t kNodeFields = 6, kGrainFields = 7;

// A swap as borders() makes it, in the indices of the moment (before the final sort).
struct PendingSwap {
  int to = -1, from = -1, tag = 0;
  std::vector<int> send_nodes;
  std::vector<int> send_keys;  // grains of the sent nodes, by PdGrains::id
  std::size_t first = 0, count = 0;     // received nodes
  std::vector<int> recv_keys;
};

}  // namespace

void PdHalo::borders(const Decomposition& d, const Box& box, double width, GrainStore s) {
  for (int a = 0; a < 3; ++a)
    if (box.periodic(a)) throw std::logic_error("PdHalo: a PeriDEM domain has no periodic axes");
  const std::size_t n_owned = s.nodes.size(), g_owned = s.grains.size();
  // Grains (and pieces of walls) are known by PdGrains::id, the whole system's grain index.
  for (std::size_t g = 1; g < g_owned; ++g)
    if (s.grains.id[g] <= s.grains.id[g - 1]) throw std::logic_error("PdHalo: a rank's grains are not in increasing id");
  std::vector<int> node_key(n_owned);
  for (std::size_t i = 0; i < n_owned; ++i) node_key[i] = s.grains.id[static_cast<std::size_t>(s.nodes.grain[i])];
  std::map<int, GrainRecord> ghost_grain;
  const auto record_of_key = [&](int key) {
    const auto it = std::lower_bound(s.grains.id.begin(), s.grains.id.begin() + static_cast<std::ptrdiff_t>(g_owned), key);
    if (it != s.grains.id.begin() + static_cast<std::ptrdiff_t>(g_owned) && *it == key)
      return GrainRecord::of(s.grains, static_cast<std::size_t>(it - s.grains.id.begin()));
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
        for (const int key : p.send_keys) {
          pack_value(key, out);
          pack_value(record_of_key(key), out);
        }
      }
      sendrecv(out, p.to, in, p.from, p.tag);
      p.first = s.nodes.size();
      if (!in.empty()) {
        Unpacker u(in);
        p.count = u.records(s.nodes).second;
        for (std::size_t k = 0; k < p.count; ++k) node_key.push_back(u.value<int>());
        const auto grains = static_cast<std::size_t>(u.value<std::int64_t>());
        for (std::size_t k = 0; k < grains; ++k) {
          const int key = u.value<int>();
          ghost_grain[key] = u.value<GrainRecord>();
          p.recv_keys.push_back(key);
        }
        if (!u.done()) throw std::logic_error("PdHalo: a ghost message longer than its contents");
      }
      pending.push_back(std::move(p));
    }
  }

  // A grain record for every ghost grain id (a wall this rank holds a piece of keeps its own record: the
  // first grain of an id wins in sort_store), the ghosts pointed at them, then one process's order.
  std::map<int, int> appended;
  for (const auto& [key, r] : ghost_grain) {
    const std::size_t g = s.grains.size();
    s.grains.resize(g + 1);
    r.store(s.grains, g);  // (its id, key, included)
    appended[key] = static_cast<int>(g);
  }
  for (std::size_t i = n_owned; i < s.nodes.size(); ++i) s.nodes.grain[i] = appended.at(node_key[i]);
  if (s.bonds.offset.size() != n_owned + 1) throw std::logic_error("PdHalo: the bond rows do not fit the owned nodes");
  s.bonds.offset.resize(s.nodes.size() + 1, s.bonds.offset.back());  // ghosts: no bonds
  const std::vector<int> order = sort_store(s);
  const std::size_t n = order.size();
  std::vector<int> now(n);
  for (std::size_t i = 0; i < n; ++i) now[static_cast<std::size_t>(order[i])] = static_cast<int>(i);
  const auto grain_of_key = [&](int key) {
    const auto it = std::lower_bound(s.grains.id.begin(), s.grains.id.end(), key);
    return static_cast<int>(it - s.grains.id.begin());
  };

  owned_node_.assign(n, 0);
  owned_grain_.assign(s.grains.size(), 0);
  for (std::size_t i = 0; i < n; ++i)
    if (static_cast<std::size_t>(order[i]) < n_owned) {
      owned_node_[i] = 1;
      owned_grain_[static_cast<std::size_t>(s.nodes.grain[i])] = 1;
    }
  ghost_nodes_ = n - n_owned;

  swaps_.clear();
  for (const PendingSwap& p : pending) {
    Swap w;
    w.to = p.to;
    w.from = p.from;
    w.tag = p.tag;
    for (const int i : p.send_nodes) w.send_nodes.push_back(now[static_cast<std::size_t>(i)]);
    for (const int key : p.send_keys) w.send_grains.push_back(grain_of_key(key));
    for (std::size_t k = 0; k < p.count; ++k) w.recv_nodes.push_back(now[p.first + k]);
    for (const int key : p.recv_keys) w.recv_grains.push_back(grain_of_key(key));
    swaps_.push_back(std::move(w));
  }
}

void PdHalo::forward(PdNodes& nodes, PdGrains& grains, exec::DeviceVector<double>& grain_mass) const {
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
    n += (kNodeFields * s.send_nodes.size() + kGrainFields * s.send_grains.size()) * sizeof(double) +
         s.send_nodes.size() * sizeof(int);  // and forward_counts()
  return n;
}

}  // namespace debris::comm
