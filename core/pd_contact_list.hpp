#pragma once
// Contact candidates between PeriDEM nodes (paper B, sections 2.2 and 3.2), as a full Verlet list in
// compressed rows built on the CURRENT positions: j is in row i (and i in row j) when
// |z_i - z_j| < cutoff + skin and the pair may touch:
//   - nodes of two different grains, unless both are wall nodes (walls never touch walls);
//   - nodes of one particle grain that no intact bond joins: the self-contact that stops a broken grain
//     from interpenetrating itself (section 3.2, "Prevention of self-penetration").
// Rows are built in two kernel passes (count, prefix sum, fill) over a cell list, so they are the same for
// any thread count; the counting pass keeps the first partners of each row, so that the fill searches again
// only for long rows. The domain is bounded (no periodic axes): the cells cover the nodes' bounding box.
// Rows are ascending. The list stays valid until some node has moved skin/2; a bond that breaks adds its
// pair in place (add_broken_bonds).
//
// Grain-pair slots, for the damping between grain centres (eqs 26-30): the force between two grains is
// one force per pair of grains in contact, however many node pairs touch. A slot is (owner particle grain
// p, partner) with partner a grain q != p or, when q is a wall, one wall node (section 3.2 treats every wall
// node as a grain of its own); it lists the node pairs of the Verlet list behind it. The slots of a grain
// are contiguous, so the damping pass is O(N): one pass over slots, one over grains, one over nodes.
//
// Offload builds: every array is an exec::DeviceVector. The searches, the copy of the build positions, the
// in-place additions, the cell counting sort (CellList), the prefix sums and the grain-pair slots run on the
// device: a build or an addition moves only scalars (the scans' totals, the bounding box) between host and
// device. The host copies of the rows and slots are current after to_host().
#include <cstddef>
#include <vector>

#include "core/cell_list.hpp"
#include "core/exec.hpp"

namespace debris {

class PdNodes;
struct PdGrains;
class BondList;

class PdContactList {
 public:
  /// Builds the rows and the grain-pair slots. cutoff: the largest contact radius (> 0), skin >= 0.
  /// bonds: the grains' bond list, or an empty BondList when there are no bonds.
  /// Throws InputError ("pd_contact.cutoff", "pd_contact.skin") for bad values, std::invalid_argument when
  /// the grains, nodes and bonds do not fit together.
  void build(const PdNodes& nodes, const PdGrains& grains, const BondList& bonds, double cutoff, double skin);

  /// True when never built, the node count changed, a rebuild was requested, or some node moved more than
  /// skin/2 since the build.
  bool needs_rebuild(const PdNodes& nodes) const;
  /// Forces a full rebuild at the next needs_rebuild().
  void request_rebuild() { stale_ = true; }
  /// After bonds broke: their two nodes may now touch (self-contact). Adds every broken bond that lies within
  /// cutoff + skin at the build positions and is not in the list yet, in place; the list is then exactly the
  /// one a build at those positions with the current broken flags gives (rows ascending), at a small part of
  /// a rebuild's cost. Only bonds broken since the build or the last call are looked at (a flag per bond
  /// entry), so the cost does not grow with the bonds broken before. The grain-pair slots are unchanged
  /// (self-contact pairs have none). Returns the pairs added (entries, each pair counted from both ends).
  long add_broken_bonds(const BondList& bonds);

  /// Transfer point (offload builds): the rows, the slots and the build positions, device -> host, for the
  /// host's readers (checks, diagnostics, checkpoints, the wall reactions' exact sums).
  void to_host() const;

  int rows() const { return rows_; }
  const exec::DeviceVector<int>& offset() const { return offset_; }  // size rows() + 1
  const exec::DeviceVector<int>& index() const { return index_; }    // partner j of each entry
  /// Node positions at the last build (what a checkpoint saves to rebuild this list exactly).
  const exec::DeviceVector<double>& x_at_build() const { return x0_; }
  const exec::DeviceVector<double>& y_at_build() const { return y0_; }
  const exec::DeviceVector<double>& z_at_build() const { return z0_; }
  int entries() const { return entries_; }  // kept on the host: no transfer
  double cutoff() const { return cutoff_; }
  double skin() const { return skin_; }
  const CellList& cells() const { return cells_; }

  // Grain-pair slots.
  int slots() const { return static_cast<int>(slot_owner_.size()); }
  const exec::DeviceVector<int>& grain_slot_offset() const { return grain_slot_offset_; }    // size grains + 1
  const exec::DeviceVector<int>& slot_owner() const { return slot_owner_; }                  // particle grain p
  const exec::DeviceVector<int>& slot_partner_grain() const { return slot_partner_grain_; }  // grain q (maybe a wall)
  const exec::DeviceVector<int>& slot_partner_node() const { return slot_partner_node_; }    // wall node, or -1
  const exec::DeviceVector<int>& slot_pair_offset() const { return slot_pair_offset_; }      // size slots() + 1
  const exec::DeviceVector<int>& slot_pair_i() const { return slot_pair_i_; }                // node of p
  const exec::DeviceVector<int>& slot_pair_j() const { return slot_pair_j_; }                // node of the partner
  /// Slots whose partner is wall node j: wall_slot()[wall_slot_offset()[j] .. wall_slot_offset()[j+1]).
  const exec::DeviceVector<int>& wall_slot_offset() const { return wall_slot_offset_; }  // size rows() + 1
  const exec::DeviceVector<int>& wall_slot() const { return wall_slot_; }

  std::size_t bytes() const;

 private:
  void build_slots(const PdNodes& nodes, const PdGrains& grains);

  CellList cells_;
  exec::DeviceVector<int> offset_, index_;
  exec::DeviceVector<int> added_, spare_index_;  // add_broken_bonds: new entries per row (prefix sum), merged rows
  // Per bond entry: 1 when its bond was broken at the build or has been looked at by add_broken_bonds since.
  // The list holds every broken bond within reach whose flag is set; a broken bond with the flag clear is new.
  exec::DeviceVector<unsigned char> handled_;
  exec::DeviceVector<double> x0_, y0_, z0_;  // positions at the last build
  int rows_ = 0, entries_ = 0;
  double cutoff_ = 0, skin_ = 0;
  bool built_ = false, stale_ = false;

  exec::DeviceVector<int> grain_slot_offset_, slot_owner_, slot_partner_grain_, slot_partner_node_;
  exec::DeviceVector<int> slot_pair_offset_, slot_pair_i_, slot_pair_j_;
  exec::DeviceVector<int> wall_slot_offset_, wall_slot_;
  // build_slots' scratch, kept between builds: each grain's first cross-grain pair, each pair's partner key
  // (grain q, or grains + wall node), the wall-slot fill's cursors.
  exec::DeviceVector<int> grain_pair_offset_, wall_cursor_;
  exec::DeviceVector<long long> slot_key_;
  // The first kRowBuffer partners of every row, found by the counting pass of a build (kept between builds).
  static constexpr int kRowBuffer = 8;
  exec::DeviceVector<int> row_buffer_;
  exec::DeviceVector<long long> scan_scratch_;  // the offsets' prefix sum
};

}  // namespace debris
