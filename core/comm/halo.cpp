#include "core/comm/halo.hpp"

#include <array>
#include <stdexcept>

#include "core/comm/communicator.hpp"
#include "core/comm/pack.hpp"

namespace debris::comm {

namespace {
// Tags of the swaps: axis and direction, so two messages between the same two ranks never meet.
int tag_of(int axis, int dir) { return 100 + 2 * axis + (dir > 0 ? 1 : 0); }
}  // namespace

void Halo::borders(const Decomposition& d, const Box& box, double width, Particles& p, std::size_t n_owned) {
  p.resize(n_owned);
  owned_ = n_owned;
  swaps_.clear();
  shift_.clear();
  ghost_index_.clear();
  const auto shift_of = [&](std::size_t i) {
    return i < owned_ ? std::array<std::int8_t, 3>{0, 0, 0} : shift_[i - owned_];
  };
  for (int a = 0; a < 3; ++a) {
    if (d.grid()[a] == 1) continue;
    // Both directions scan the same particles: the owned ones and the ghosts of earlier axes (those of
    // this axis stand outside the subdomain, beyond the face they came through).
    const std::size_t scan = p.size();
    const double lo = d.sub_lo(box, a), hi = d.sub_hi(box, a);
    for (const int dir : {-1, +1}) {
      Swap s;
      s.axis = a;
      s.to = d.neighbour(box, a, dir);
      s.from = d.neighbour(box, a, -dir);
      s.tag = tag_of(a, dir);
      const double* c = position(p, a);
      if (s.to >= 0)
        for (std::size_t i = 0; i < scan; ++i)
          if (dir < 0 ? c[i] < lo + width : c[i] >= hi - width) s.send.push_back(static_cast<int>(i));
      // Across a periodic face the receiver sees the particle one box length away: +L below the first
      // subdomain's face (the last subdomain receives it), -L above the last one's.
      std::int8_t wrap = 0;
      if (dir < 0 && d.coord()[a] == 0) wrap = +1;
      if (dir > 0 && d.coord()[a] == d.grid()[a] - 1) wrap = -1;

      std::vector<char> out, in;
      pack_records(p, s.send, out);
      for (const int i : s.send) {
        auto sh = shift_of(static_cast<std::size_t>(i));
        sh[a] = static_cast<std::int8_t>(sh[a] + wrap);
        out.insert(out.end(), sh.begin(), sh.end());
      }
      sendrecv(out, s.to, in, s.from, s.tag);

      s.first = p.size();
      if (!in.empty()) {
        Unpacker u(in);
        s.count = u.records(p).second;
        for (std::size_t k = 0; k < s.count; ++k) {
          std::array<std::int8_t, 3> sh{};
          for (auto& v : sh) v = u.value<std::int8_t>();
          shift_.push_back(sh);
          ghost_index_.push_back(static_cast<int>(s.first + k));
        }
      }
      swaps_.push_back(std::move(s));
    }
  }
}

namespace {
// What forward() sends: x, v and omega.
constexpr int kForwardFields = 9;
std::array<exec::DeviceVector<double>*, kForwardFields> forwarded(Particles& p) {
  return {&p.x, &p.y, &p.z, &p.vx, &p.vy, &p.vz, &p.wx, &p.wy, &p.wz};
}
}  // namespace

void Halo::forward(Particles& p) const {
  if (p.size() != owned_ + shift_.size()) throw std::logic_error("Halo::forward: the particles changed since borders()");
  constexpr int kFields = kForwardFields;
  const auto columns = forwarded(p);
  for (const Swap& s : swaps_) {
    // Sizes are fixed between rebuilds on both sides: one message each way, no size exchange.
    out_.resize(kFields * s.send.size());
    in_.resize(kFields * s.count);
    double* o = out_.data();
    for (const auto* col : columns)
      for (const int i : s.send) *o++ = (*col)[static_cast<std::size_t>(i)];
    sendrecv_sized(reinterpret_cast<const char*>(out_.data()), out_.size() * sizeof(double), s.to,
                   reinterpret_cast<char*>(in_.data()), in_.size() * sizeof(double), s.from, s.tag);
    const double* in = in_.data();
    const int* slot = ghost_index_.data() + (s.first - owned_);
    for (auto* col : columns)
      for (std::size_t k = 0; k < s.count; ++k) (*col)[static_cast<std::size_t>(slot[k])] = *in++;
  }
}

void Halo::forward_values(std::vector<double>& column) const {
  if (column.size() != owned_ + shift_.size()) throw std::logic_error("Halo::forward_values: not one value per particle");
  std::vector<double> out, in;
  for (const Swap& s : swaps_) {
    out.clear();
    for (const int i : s.send) out.push_back(column[static_cast<std::size_t>(i)]);
    in.resize(s.count);
    sendrecv_sized(reinterpret_cast<const char*>(out.data()), out.size() * sizeof(double), s.to,
                   reinterpret_cast<char*>(in.data()), in.size() * sizeof(double), s.from, s.tag);
    const int* slot = ghost_index_.data() + (s.first - owned_);
    for (std::size_t k = 0; k < s.count; ++k) column[static_cast<std::size_t>(slot[k])] = in[k];
  }
}

void Halo::permute(const std::vector<int>& order) {
  if (order.size() != owned_ + shift_.size()) throw std::logic_error("Halo::permute: not an order of all particles");
  std::vector<int> now(order.size());
  for (std::size_t i = 0; i < order.size(); ++i) now[static_cast<std::size_t>(order[i])] = static_cast<int>(i);
  for (Swap& s : swaps_)
    for (int& i : s.send) i = now[static_cast<std::size_t>(i)];
  for (int& i : ghost_index_) i = now[static_cast<std::size_t>(i)];
}

std::size_t Halo::forward_bytes() const {
  std::size_t n = 0;
  for (const Swap& s : swaps_) n += s.send.size() * kForwardFields * sizeof(double);
  return n;
}

}  // namespace debris::comm
