#pragma once
// Peridynamic bonds (paper B, section 2.1 and eq 33): node j is bonded to node i when both belong to the
// same grain and |x0_j - x0_i| < horizon in the reference configuration. Built once, stored as compressed
// rows from both ends (row i lists every partner j, row j lists i), so the bond passes write only to the
// row's own node, with no atomics, on host threads and on a GPU alike. A bond breaks irreversibly
// (eq 10); `broken` is kept per stored entry and both ends of a bond always agree.
// Offload builds: every array is an exec::DeviceVector; build() fills the host copies, to_device(bonds)
// sends them, and the bond passes change `broken` on the device only (to_host(bonds.broken) before the host
// reads it).
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/exec.hpp"

namespace debris {

class PdNodes;
struct PdGrains;

class BondList {
 public:
  exec::DeviceVector<int> offset;              // size nodes() + 1: bonds of i are [offset[i], offset[i+1])
  exec::DeviceVector<int> partner;             // j of each entry, ascending within a row
  exec::DeviceVector<double> length0;          // reference length |x0_j - x0_i| of each entry
  exec::DeviceVector<unsigned char> broken;    // 1 once broken, never healed
  /// Each entry's weight in the bond sums, J(x0 / horizon) V_j (lps_bond_weight): written by
  /// pd_weighted_volume_pass in the reference state (build() leaves it empty; the bond sweeps require it).
  exec::DeviceVector<double> weight;

  /// Scratch of the bond passes (kernels/peridem/pd_bond_passes.cpp), sized by them: the node factors P_i, Q_i of
  /// lps_node_factors, interleaved, written from theta before every force sweep (by pd_bond_step's dilatation
  /// sweep, or by pd_bond_force_pass itself). Not bond data: nothing reads it across calls, and copies or
  /// checkpoints need not keep it. Mutable because the passes read the bonds as const.
  mutable exec::DeviceVector<double> node_factors;
  /// Scratch of pd_bond_step in host builds on CPUs with AVX2: |y| of every entry, from its dilatation sweep,
  /// for its force sweep (kernels/peridem/pd_bond_passes_avx2.cpp). Sized there; empty otherwise.
  mutable exec::DeviceVector<double> bond_length;

  std::size_t nodes() const { return offset.empty() ? 0 : offset.size() - 1; }
  std::size_t entries() const { return partner.size(); }

  /// True when i and j are joined by a bond that is not broken (false when they were never bonded).
  bool intact(int i, int j) const {
    const auto begin = partner.begin() + offset[i], end = partner.begin() + offset[i + 1];
    const auto it = std::lower_bound(begin, end, j);
    return it != end && *it == j && !broken[static_cast<std::size_t>(it - partner.begin())];
  }

  /// Bonds of every particle grain (walls get none) with the horizon of each grain
  /// (`horizon_of_grain[g]`), from the reference positions x0, y0, z0: j is a partner of i when both are
  /// nodes of one particle grain, j != i and |x0_j - x0_i| < horizon (strict, as eq 33 sums). Searched per
  /// grain through a CellList of edge >= horizon. Throws InputError when a grain's node range lies outside
  /// the nodes, a particle grain's horizon is not finite and > 0, or two nodes of a grain coincide.
  static BondList build(const PdNodes& nodes, const PdGrains& grains, const std::vector<double>& horizon_of_grain);
};

/// Transfer points for the bond data (offset, partner, length0, broken, weight; not the scratch): no-ops in
/// host builds.
inline void to_host(const BondList& b) {
  exec::to_host(b.offset);
  exec::to_host(b.partner);
  exec::to_host(b.length0);
  exec::to_host(b.broken);
  exec::to_host(b.weight);
}
inline void to_device(const BondList& b) {
  exec::to_device(b.offset);
  exec::to_device(b.partner);
  exec::to_device(b.length0);
  exec::to_device(b.broken);
  exec::to_device(b.weight);
}

}  // namespace debris
