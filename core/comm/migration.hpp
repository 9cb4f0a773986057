#pragma once
// Particles move to the rank that owns their position (shared/design/scale-mpi.md, section 3): at a rebuild,
// after the box wrapped them, every owned particle outside this rank's subdomain is sent to the next rank
// along the axis it left by, one axis after the other (x, y, z), with its pair rows, so a particle that
// crossed a corner reaches the diagonal rank in two hops. A particle moves at most skin/2 between rebuilds,
// less than half a subdomain, so it never needs to go farther than the next rank along an axis.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/comm/decomposition.hpp"
#include "core/particles.hpp"

namespace debris::comm {

/// State kept per pair that travels with a particle: owned particle i's rows are [offset[i], offset[i+1]),
/// each a partner's permanent id and kValues doubles (the tangential spring of the cohesive model).
struct PairRows {
  static constexpr int kValues = 3;
  std::vector<std::size_t> offset{0};
  std::vector<std::int64_t> partner;
  std::vector<double> value;  // kValues per row

  std::size_t rows_of(std::size_t i) const { return offset[i + 1] - offset[i]; }
  /// Keeps the rows of the particles with remove[i] == 0, in order.
  void remove_if(const std::vector<char>& remove);
};

/// What one exchange moved.
struct ExchangeCount {
  std::size_t sent = 0, received = 0;
};

/// Moves every particle of `p` (owned particles only: ghosts dropped first) that this rank does not own to
/// its owner, with its rows when `rows` is given (rows->offset must have p.size() + 1 entries). Collective.
/// Throws std::runtime_error naming the particle if one moved farther than the next rank. Only the rank
/// that finds it throws, and the others would wait for its messages: a caller that can meet it (a run that
/// blew up) must stop every rank (comm::abort), as the health check will.
ExchangeCount exchange(const Decomposition& d, const Box& box, Particles& p, PairRows* rows = nullptr);

/// Start of a run where every rank holds all particles: keeps those this rank owns, in their order.
void keep_owned(const Decomposition& d, const Box& box, Particles& p);

}  // namespace debris::comm
