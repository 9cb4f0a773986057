#pragma once
// The cohesive contact pass for host threads: eqs 2-5 over a half neighbour list (each pair evaluated once)
// (delta_f per pair from CohesivePairTable, the other constants of eqs 7-17 computed in the loop), in two
// phases:
//   1. over all pairs, flat: the force and both torques of pair k go to per-pair arrays. No pair writes to a
//      particle, so the loop vectorises (built for x86-64, AVX2 and AVX-512, picked at run time);
//   2. over particles: each sums its own pairs, then the pairs where it is the partner (a transposed index
//      built with the list), in a fixed order.
// No atomics, no per-thread buffers, and the sum order does not depend on the thread count, so results are
// the same bit for bit on 1 or 2 threads. Host threads only: the full-list pass (kernels/cohesive_contact.hpp)
// is the GPU path, and the reference this one is tested against.
#include <vector>

#include "core/box.hpp"
#include "kernels/cohesive_pair_force.hpp"
#include "kernels/cohesive_pair_table.hpp"

namespace debris {

class Particles;
class NeighborList;
class ContactHistory;

/// Per-pair results of phase 1 and the transposed index for phase 2, sized with the list.
struct HalfPassScratch {
  std::vector<int> row_of;     // i of each pair k
  std::vector<int> in_offset;  // pairs where particle j is the partner: in_entry[in_offset[j] .. in_offset[j+1])
  std::vector<int> in_entry;
  std::vector<double> fx, fy, fz, tix, tiy, tiz, tjx, tjy, tjz;  // force on i, torques on i and on j

  /// Rebuilds row_of and the transposed index (after every list rebuild).
  void index(const NeighborList& list);
  std::size_t bytes() const;
};

/// Adds the pair forces and torques to f and t. `list` must be a half list, `scratch` indexed for it.
void cohesive_contact_pass_half(const CohesivePairTable& table, const CohesiveOptions& opt, const BoxView& box,
                                Particles& p, const NeighborList& list, ContactHistory& history, double dt,
                                int update_history, HalfPassScratch& scratch);

}  // namespace debris
