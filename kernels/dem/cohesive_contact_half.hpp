#pragma once
// The cohesive contact pass for host threads: eqs 2-5 over a half neighbour list (each pair evaluated once;
// delta_f and c_N per pair from CohesivePairTable, the other constants of eqs 7-17 computed in the loop), in
// two phases:
//   1. over blocks of whole rows, in chunks of pairs: a flat vector loop (no pair writes to a particle; built
//      for x86-64, AVX2 and AVX-512, picked at run time) computes each pair's force and both torques into a
//      small per-thread buffer; a scalar sweep then adds the row particle's share to its force and torque,
//      in increasing pair order, and files the partner's share (6 doubles) at the pair's index;
//   2. over particles: each adds the shares filed for it, through a transposed index built with the list,
//      in increasing pair order.
// No atomics, and the sum order does not depend on the thread count, so results are the same bit for bit
// on 1 or 2 threads. Host threads only: the full-list pass (kernels/dem/cohesive_contact.hpp) is the GPU path,
// and the reference this one is tested against; both evaluate each pair with cohesive_pair_force.
#include <vector>

#include "core/box.hpp"
#include "kernels/dem/cohesive_pair_force.hpp"
#include "kernels/dem/cohesive_pair_table.hpp"

namespace debris {

class Particles;
class NeighborList;
class ContactHistory;

/// The partners' shares filed by phase 1 for phase 2, and the indices that place them, sized with the list.
struct HalfPassScratch {
  static constexpr int kShareStride = 6;   // force on i (the partner gets its negative), torque on j
  static constexpr int kBlockPairs = 1024; // phase-1 work unit: whole rows, about this many pairs
  std::vector<int> row_of;      // i of each pair k
  std::vector<int> block_row;   // phase-1 blocks: rows block_row[b] .. block_row[b+1]
  // Only where more than one thread sums (shares_indexed); empty on one thread, which never files shares:
  std::vector<int> in_offset;   // pairs where particle j is the partner: in_entry[in_offset[j] .. in_offset[j+1])
  std::vector<int> in_entry;    // ... in increasing k
  std::vector<double> partner;  // kShareStride doubles per pair k
  bool shares_indexed = false;

  /// Rebuilds the indices (after every list rebuild); the shares' only when exec::threads() > 1.
  void index(const NeighborList& list);
  /// The shares' index and buffer (a multi-thread pass calls it when the thread count rose since index()).
  void index_shares(const NeighborList& list);
  std::size_t bytes() const;
};

/// Sets f and t to the pair forces and torques: each block of rows is zeroed by the thread that sums it, so
/// the step needs no zero_forces sweep before it (one parallel region and one pass over f, t fewer; the same
/// bits: 0 + the row's sum, as before). `list` must be a half list, `scratch` indexed for it.
void cohesive_contact_pass_half(const CohesivePairTable& table, const CohesiveOptions& opt, const BoxView& box,
                                Particles& p, const NeighborList& list, ContactHistory& history, double dt,
                                int update_history, HalfPassScratch& scratch);

}  // namespace debris
