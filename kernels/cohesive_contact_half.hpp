#pragma once
// The cohesive contact pass for host threads: eqs 2-5 over a half neighbour list (each pair evaluated once,
// its reaction written to j), with the per-pair constants of CohesivePairTable. Half the pair work of the
// full-list pass (kernels/cohesive_contact.hpp), which stays the GPU path and the reference this one is
// tested against. Each thread writes j's share into its own buffer (thread 0 into the particle arrays), so no
// atomics are needed; the buffers are added afterwards in a fixed order, so a run is reproducible bit for bit
// for a given thread count, and differs between thread counts only by round-off.
#include <vector>

#include "core/box.hpp"
#include "kernels/cohesive_pair_force.hpp"
#include "kernels/cohesive_pair_table.hpp"

namespace debris {

class Particles;
class NeighborList;
class ContactHistory;

/// Force and torque buffers of threads 1.. (thread 0 writes into the particle arrays).
struct ThreadForceBuffers {
  std::vector<double> data;  // (threads - 1) x 6 x n
  int threads = 1;
  int n = 0;
  std::size_t bytes() const { return sizeof(double) * data.capacity(); }
};

/// Adds the pair forces and torques to f and t. `list` must be a half list; the history is per pair, as
/// seen from the row's particle.
void cohesive_contact_pass_half(const CohesivePairTable& table, const CohesiveOptions& opt, const BoxView& box,
                                Particles& p, const NeighborList& list, ContactHistory& history, double dt,
                                int update_history, ThreadForceBuffers& buffers);

}  // namespace debris
