#include "core/comm/migration.hpp"

#include <stdexcept>
#include <string>

#include "core/comm/communicator.hpp"
#include "core/comm/pack.hpp"

namespace debris::comm {

namespace {
int tag_of(int axis, int dir) { return 200 + 2 * axis + (dir > 0 ? 1 : 0); }

// Appends the particles `which` with their rows to a message.
void pack_leavers(const Particles& p, const PairRows* rows, const std::vector<int>& which, std::vector<char>& out) {
  pack_records(p, which, out);
  if (!rows) return;
  for (const int i : which) {
    const auto k = static_cast<std::size_t>(i);
    pack_value(static_cast<std::int64_t>(rows->rows_of(k)), out);
    for (std::size_t r = rows->offset[k]; r < rows->offset[k + 1]; ++r) {
      pack_value(rows->partner[r], out);
      for (int v = 0; v < PairRows::kValues; ++v) pack_value(rows->value[PairRows::kValues * r + v], out);
    }
  }
}

// Appends the particles of a message (and their rows) to the rank's own.
std::size_t unpack_arrivals(const std::vector<char>& in, Particles& p, PairRows* rows) {
  if (in.empty()) return 0;
  Unpacker u(in);
  const std::size_t n = u.records(p).second;
  if (rows) {
    for (std::size_t k = 0; k < n; ++k) {
      const auto count = static_cast<std::size_t>(u.value<std::int64_t>());
      for (std::size_t r = 0; r < count; ++r) {
        rows->partner.push_back(u.value<std::int64_t>());
        for (int v = 0; v < PairRows::kValues; ++v) rows->value.push_back(u.value<double>());
      }
      rows->offset.push_back(rows->partner.size());
    }
  }
  return n;
}
}  // namespace

void PairRows::remove_if(const std::vector<char>& remove) {
  std::size_t kept_rows = 0, kept = 0;
  for (std::size_t i = 0; i + 1 < offset.size(); ++i) {
    const std::size_t begin = offset[i], end = offset[i + 1];
    if (remove[i]) continue;
    for (std::size_t r = begin; r < end; ++r, ++kept_rows) {
      partner[kept_rows] = partner[r];
      for (int v = 0; v < kValues; ++v) value[kValues * kept_rows + v] = value[kValues * r + v];
    }
    offset[++kept] = kept_rows;
  }
  offset.resize(kept + 1);
  partner.resize(kept_rows);
  value.resize(kValues * kept_rows);
}

ExchangeCount exchange(const Decomposition& d, const Box& box, Particles& p, PairRows* rows) {
  if (rows && rows->offset.size() != p.size() + 1)
    throw std::logic_error("comm::exchange: pair rows for " + std::to_string(rows->offset.size() - 1) +
                           " particles, " + std::to_string(p.size()) + " given");
  ExchangeCount count;
  for (int a = 0; a < 3; ++a) {
    if (d.grid()[a] == 1) continue;
    const int mine = d.coord()[a];
    std::vector<int> to_below, to_above;
    std::vector<char> leaves(p.size(), 0);
    const double* c = position(p, a);
    for (std::size_t i = 0; i < p.size(); ++i) {
      const int step = d.step_along(box, a, c[i]);
      if (step == 0) continue;
      if (step == +1)
        to_above.push_back(static_cast<int>(i));
      else if (step == -1)
        to_below.push_back(static_cast<int>(i));
      else
        throw std::runtime_error("particle " + std::to_string(p.id[i]) + " moved past the next rank along " +
                                 std::string(1, "xyz"[a]) + " between two rebuilds (at " + std::to_string(c[i]) +
                                 ")");
      leaves[i] = 1;
    }
    std::vector<char> out_below, out_above, in;
    pack_leavers(p, rows, to_below, out_below);
    pack_leavers(p, rows, to_above, out_above);
    count.sent += to_below.size() + to_above.size();
    p.remove_if(leaves);
    if (rows) rows->remove_if(leaves);
    for (const int dir : {-1, +1}) {
      sendrecv(dir < 0 ? out_below : out_above, d.neighbour(box, a, dir), in, d.neighbour(box, a, -dir), tag_of(a, dir));
      const std::size_t before = p.size();
      count.received += unpack_arrivals(in, p, rows);
      const double* arrived = position(p, a);
      for (std::size_t i = before; i < p.size(); ++i)
        if (d.index_along(box, a, arrived[i]) != mine)
          throw std::runtime_error("particle " + std::to_string(p.id[i]) + " arrived on a rank that does not own it");
    }
  }
  return count;
}

void keep_owned(const Decomposition& d, const Box& box, Particles& p) {
  const int me = d.rank();
  std::vector<char> remove(p.size(), 0);
  for (std::size_t i = 0; i < p.size(); ++i) remove[i] = d.owner(box, p.x[i], p.y[i], p.z[i]) != me;
  p.remove_if(remove);
}

}  // namespace debris::comm
