#pragma once
// The ghost layer of a rank of a PeriDEM run (shared/design/scale-mpi.md, section 5): copies of the
// nodes of other ranks' grains that lie within the ghost width of this rank's subdomain, each with a record
// of its grain (kind, material, centre, velocity, mass), so that the contact list of every owned node holds
// all its partners, and the damping between grain centres (eqs 26-30) finds the centre of every grain its
// own grains touch. Bonds never cross ranks (a grain is owned whole), so ghosts carry none.
//
// borders() (at a list build) sends, as core/comm/halo does for particles, along each cut axis in turn the
// nodes within the width of each face (owned, and ghosts of earlier axes), then stores owned and ghost nodes
// together in increasing id, and their grains (whole owned grains, pieces of walls, and ghost grains holding
// only their ghost nodes) in increasing PdGrains::id: the order one process stores the whole system in, restricted
// to what this rank holds. The contact list's rows are ascending in the node index, so an owned node's row
// lists its partners in the order one process lists them, and every force sum adds the same terms in the
// same order on any rank count.
//
// An owned grain's nodes reach past the subdomain by up to the grain's own extent, so the width a caller
// asks for is the largest grain extent plus the contact reach (contact radius + skin).
//
// A PeriDEM domain has no periodic axes (walls bound it): the decomposition's box is never periodic here.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/comm/decomposition.hpp"
#include "core/comm/grain_migration.hpp"

namespace debris::comm {

class PdHalo {
 public:
  /// `s` holds this rank's own nodes only, in one process's order (as grain_migration leaves them). Adds the
  /// ghost nodes and grains and stores everything in that order (see above); ghost nodes get empty bond rows.
  /// std::logic_error if the box is periodic.
  void borders(const Decomposition& d, const Box& box, double width, GrainStore s);

  /// Positions and velocities of every sent node, and centre, mean velocity and mass of every sent grain,
  /// again into the same ghost slots (every step). `grain_mass`: one value per grain held.
  void forward(PdNodes& nodes, PdGrains& grains, exec::DeviceVector<double>& grain_mass) const;
  /// One integer per node from its owner to its ghosts (the contact rows' lengths).
  void forward_counts(int* count) const;

  /// Before borders(): the store holds `nodes` nodes in `grains` grains, all this rank's own (no ghosts).
  void set_owned(std::size_t nodes, std::size_t grains) {
    owned_node_.assign(nodes, 1);
    owned_grain_.assign(grains, 1);
    swaps_.clear();
  }
  /// Per node held: 1 for the rank's own nodes, 0 for ghosts.
  const std::vector<unsigned char>& owned_nodes() const { return owned_node_; }
  /// Per grain held: 1 for the rank's own grains, 0 for ghost grains.
  const std::vector<unsigned char>& owned_grains() const { return owned_grain_; }
  std::size_t ghost_nodes() const { return ghost_nodes_; }
  /// Bytes this rank sends in one forward() and one forward_counts().
  std::size_t forward_bytes() const;

 private:
  struct Swap {
    int to = -1, from = -1, tag = 0;
    std::vector<int> send_nodes, send_grains;  // indices after borders()
    std::vector<int> recv_nodes, recv_grains;  // where the received values go
  };
  std::vector<Swap> swaps_;
  std::vector<unsigned char> owned_node_, owned_grain_;
  std::size_t ghost_nodes_ = 0;
  mutable std::vector<double> out_, in_;  // forward()'s buffers, kept: no allocation in a step
  mutable std::vector<int> iout_, iin_;
};

}  // namespace debris::comm
