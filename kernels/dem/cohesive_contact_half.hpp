#pragma once
// The cohesive contact pass for host threads: eqs 2-5 over a half neighbour list (each pair evaluated once;
// delta_f and c_N per pair from CohesivePairTable, the other constants of eqs 7-17 computed in the loop).
// The pairs go in chunks: a flat vector loop (no pair writes to a particle; built for x86-64, AVX2 and
// AVX-512, picked at run time) computes each pair's force and both torques into a small per-thread buffer;
// a scalar sweep then adds the row particle's share to a running row sum and the partner's share to the
// partner's force and torque on the spot, in increasing pair order.
// Threads: each owns a part of the rows (contiguous, about equal pairs) and sweeps it so; a part's tail rows
// (those with a partner in a later part: a slab one cutoff thick before the part's end, and the first layer
// of cells where the box is periodic along the order's slowest axis) are swept first, shared among the
// threads, and their shares kept; a later part starts from the shares it receives, in the order one thread
// would add them. Where the tails would hold many of the pairs (small or periodic systems) every partner
// share is filed at its pair's index and gathered per particle instead (the path every multi-thread pass
// took before). No atomics, and every path makes the same sums in the same order, so results are the same
// bit for bit on any number of threads. Host threads only: the full-list pass (kernels/dem/cohesive_contact.hpp) is the GPU
// path, and the reference this one is tested against; both evaluate each pair with cohesive_pair_force.
#include <vector>

#include "core/box.hpp"
#include "kernels/dem/cohesive_pair_force.hpp"
#include "kernels/dem/cohesive_pair_table.hpp"

namespace debris {

class Particles;
class NeighborList;
class ContactHistory;

/// How more than one thread sums: by parts (automatic where the tails hold at most kMostTailPairs of the
/// pairs), or with every share filed. Both give the bits one thread gives; tests choose to check both.
enum class HalfPassPath { automatic, parts, filed };

/// The rows' parts, one per thread, and the shares their tails keep, sized with the list.
struct HalfPassScratch {
  HalfPassPath path = HalfPassPath::automatic;
  static constexpr int kShareStride = 6;  // force on i (the partner gets its negative), torque on j
  // With the energy accounting on, each share also carries the pair's energy parts (PairEnergyColumns):
  // stride() doubles per share instead of kShareStride. Set before index().
  bool energy = false;
  int stride() const;
  static constexpr int kUnitPairs = 512;  // the tails' sweep is shared among threads in units of this many pairs
  int entries = -1;                       // the pairs of the list it was indexed for
  int parts = 0;                          // the thread count the parts are for
  std::vector<int> part_row;              // part t: rows part_row[t] .. part_row[t+1]
  std::vector<int> part_run;              // part t's tail runs: part_run[t] .. part_run[t+1]
  std::vector<int> run_begin, run_end;    // a tail run: rows run_begin[r] .. run_end[r]
  std::vector<int> run_pair, run_sum;     // where run r's pairs start in tail_share, its rows in tail_sum
  std::vector<int> unit_run, unit_begin, unit_end;  // the tails' sweep: rows of run unit_run[u]
  std::vector<int> thread_unit;                     // thread t's units: thread_unit[t] .. thread_unit[t+1]
  std::vector<double> tail_share;                   // stride() doubles per tail pair: the partner's share
  std::vector<double> tail_sum;                     // stride() doubles per tail row: the row's own sum
  // Where the tails would hold more than kMostTailPairs of the pairs, every share is filed instead:
  // Measured: parts win at 6% (256k) and tie at 12% (32k); at 22% (the junction's sample) they tie and at
  // 25.5% (4k) parts step in 0.301 ms against 0.323 ms filed (best of five interleaved rounds), keeping 256 B
  // per particle fewer. Thin periodic samples, with most pairs in tails, still file.
  static constexpr double kMostTailPairs = 0.30;
  static constexpr int kBlockPairs = 1024;        // the filing sweep's unit: whole rows, about this many pairs
  bool file_all = false;
  std::vector<int> block_row;            // its blocks: rows block_row[b] .. block_row[b+1]
  std::vector<int> in_offset, in_entry;  // pairs where j is the partner: in_entry[in_offset[j] ..], increasing k
  std::vector<double> filed;             // stride() doubles per pair

  /// Rebuilds the indices and parts (after every list rebuild), for exec::threads() threads.
  void index(const NeighborList& list);
  /// Parts the rows for `count` threads (the pass calls it when the thread count changed since index()).
  void partition(const NeighborList& list, int count);
  /// The filing path's blocks and transposed index (partition() calls it when it chooses that path).
  void index_filed(const NeighborList& list);
  std::size_t bytes() const;
};

/// Sets f and t to the pair forces and torques: each part's rows are zeroed by the thread that sums them, so
/// the step needs no zero_forces sweep before it (one parallel region and one pass over f, t fewer; the same
/// bits: 0 + the row's sum). `list` must be a half list, `scratch` indexed for it. `energy` (nullptr: none;
/// needs scratch.energy) is set the same way to the per-particle sums of the pairs' energy parts.
void cohesive_contact_pass_half(const CohesivePairTable& table, const CohesiveOptions& opt, const BoxView& box,
                                Particles& p, const NeighborList& list, ContactHistory& history, double dt,
                                int update_history, HalfPassScratch& scratch, const PairEnergyOut* energy = nullptr);

}  // namespace debris
