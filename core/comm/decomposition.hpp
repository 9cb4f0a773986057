#pragma once
// How the box is cut among the ranks (shared/design/scale-mpi.md, section 2): a Px x Py x Pz grid of
// subdomains, the one with the least surface (the least halo) among the grids whose subdomains are at least
// twice the ghost width wide on every cut axis (a ghost then comes from the next rank only, never from two
// ranks over, and never twice). The cuts are stored as fractions of the box, so a box that deforms (the
// stress-driven relaxation) carries them along.
//
// Ranks are numbered x fastest: rank = (cz Py + cy) Px + cx. A subdomain is [lo, hi) on every axis; a
// coordinate on a cut plane belongs to the rank above it. On a walled axis the first and last subdomains
// reach past the box (particles may stray outside it); on a periodic axis positions are wrapped into it.
#include <array>
#include <string>
#include <vector>

#include "core/box.hpp"

namespace debris::comm {

class Decomposition {
 public:
  Decomposition() = default;  // one rank, the whole box

  /// The grid with the least surface for `ranks` ranks, or `requested` (Px, Py, Pz, product = ranks) when
  /// given non-zero. InputError (key `key`, by default the rank count mpirun starts) when no grid, or the
  /// requested one, has subdomains at least 2 `ghost_width` wide on every cut axis: the message names the
  /// box and the largest rank count along each axis.
  static Decomposition make(const Box& box, int ranks, int rank, double ghost_width,
                            std::array<int, 3> requested = {0, 0, 0}, const std::string& key = "mpirun -np");

  const std::array<int, 3>& grid() const { return grid_; }
  const std::array<int, 3>& coord() const { return coord_; }
  int ranks() const { return grid_[0] * grid_[1] * grid_[2]; }
  int rank() const { return rank_of(coord_); }
  int rank_of(std::array<int, 3> c) const { return (c[2] * grid_[1] + c[1]) * grid_[0] + c[0]; }
  std::array<int, 3> coord_of_rank(int r) const;

  /// The rank next to this one along `axis`, below (dir = -1) or above (dir = +1); across a periodic face
  /// the grid wraps around; -1 past a walled face.
  int neighbour(const Box& box, int axis, int dir) const;

  /// Cut plane i of `axis` (i = 0 .. grid[axis]): the box's lo and hi at the ends, lo + fraction * length
  /// between. Every rank computes the same bits.
  double cut(const Box& box, int axis, int i) const;
  double sub_lo(const Box& box, int axis) const { return cut(box, axis, coord_[axis]); }
  double sub_hi(const Box& box, int axis) const { return cut(box, axis, coord_[axis] + 1); }

  /// The grid index along `axis` of the subdomain that holds coordinate v (clamped to the first or last
  /// subdomain outside the box).
  int index_along(const Box& box, int axis, double v) const;
  /// The rank that owns a point.
  int owner(const Box& box, double x, double y, double z) const;
  /// Where coordinate v along `axis` sends what this rank holds at it: 0 when this rank's subdomain holds v,
  /// -1 or +1 toward the next subdomain below or above (across a periodic face too), kTooFar beyond them.
  static constexpr int kTooFar = 2;
  int step_along(const Box& box, int axis, double v) const;

  /// Largest number of subdomains along each axis that keeps them 2 ghost_width wide (1 for an axis too
  /// short for two).
  static std::array<int, 3> largest_counts(const Box& box, double ghost_width);

  /// "2 x 1 x 1 (cut along x)".
  std::string describe() const;

 private:
  std::array<int, 3> grid_{1, 1, 1};
  std::array<int, 3> coord_{0, 0, 0};
  std::array<std::vector<double>, 3> fraction_{std::vector<double>{0.0, 1.0}, std::vector<double>{0.0, 1.0},
                                               std::vector<double>{0.0, 1.0}};
};

}  // namespace debris::comm
