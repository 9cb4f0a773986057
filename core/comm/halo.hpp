#pragma once
// The ghost layer of a rank (shared/design/scale-mpi.md, sections 2 and 7): copies of the particles of other
// ranks that lie within the ghost width (max cutoff + skin) of this rank's subdomain, so the pair passes
// find every partner of an owned particle on this rank.
//
// borders() (at a rebuild) sends, along each cut axis in turn (x, then y, then z; below, then above), every
// particle within the width of the face to the rank across it, ghosts received along an earlier axis
// included, so edge and corner ghosts come through the face neighbours (LAMMPS's comm_brick pattern).
// The send lists are kept; forward() (every other step) resends x, v and omega over the same lists into the
// same ghost slots. Storage: owned particles first, then ghosts, in the order of the swaps.
//
// A ghost keeps its owner's coordinate bits, also across a periodic face: it records instead the image
// shift (in box lengths) at which it stands beside this subdomain, for binning only. The pair passes take
// nearest_image(x_i - x_j), which subtracts exactly one box length or nothing, as on a single rank, so a
// pair is computed from the same bits on every rank count.
//
// An axis with one subdomain is not cut: it has no ghosts, and periodic pairs across it use minimum image
// as in a serial run.
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/comm/decomposition.hpp"
#include "core/particles.hpp"

namespace debris::comm {

class Halo {
 public:
  /// Drops every particle after the first n_owned (the old ghosts) and appends the new ghost layer.
  void borders(const Decomposition& d, const Box& box, double width, Particles& p, std::size_t n_owned);
  /// x, y, z, v and omega of every sent particle again, into the same ghost slots (between rebuilds).
  void forward(Particles& p) const;
  /// One more value per particle (`column`, as long as the particles), sent from each owner to its ghosts'
  /// slots over the same lists (e.g. where each particle stands in the whole system, for a checkpoint).
  void forward_values(std::vector<double>& column) const;
  /// Follows a reordering of all the particles (owned and ghosts) after borders(): new index i holds the
  /// particle that was at order[i]. The send lists and ghost slots move with them, so forward() still fills
  /// the right slots (a rank stores owned particles and ghosts together in the canonical order).
  void permute(const std::vector<int>& order);

  std::size_t owned() const { return owned_; }
  std::size_t ghosts() const { return shift_.size(); }
  /// Image shift of ghost k along each axis, in box lengths: it stands at x + shift L beside this subdomain.
  const std::vector<std::array<std::int8_t, 3>>& shifts() const { return shift_; }
  /// Where ghost k is stored: owned() + k after borders(), wherever permute() put it since.
  const std::vector<int>& ghost_index() const { return ghost_index_; }
  /// Bytes this rank sends in one forward().
  std::size_t forward_bytes() const;

 private:
  struct Swap {
    int axis = 0, to = -1, from = -1, tag = 0;
    std::vector<int> send;          // indices of the sent particles (owned, or ghosts of an earlier axis)
    std::size_t first = 0, count = 0;  // its ghosts: ghost_index_[first - owned_ ...], how many
  };
  std::vector<Swap> swaps_;
  std::size_t owned_ = 0;
  std::vector<std::array<std::int8_t, 3>> shift_;
  std::vector<int> ghost_index_;
  mutable std::vector<double> out_, in_;  // forward()'s buffers, kept: no allocation in a step
};

}  // namespace debris::comm
