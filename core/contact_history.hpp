#pragma once
// Per-contact state stored beside the neighbour entries (one Vec3 per entry of a full list: the
// tangential spring of the cohesive model). When the list is rebuilt, or the particles are re-sorted,
// every pair still in the list gets its state back by the pair of permanent ids, whatever its indices
// became: pairs in tension included (the author's LAMMPS version loses those at every rebuild).
#include <cstdint>
#include <vector>

#include "core/exec.hpp"

namespace debris {

class Particles;
class NeighborList;
namespace comm {
struct PairRows;
}

class ContactHistory {
 public:
  exec::DeviceVector<double> hx, hy, hz;  // one value per neighbour entry (offload builds: on the device)

  /// Sizes the state for a freshly built list, all zero.
  void reset(const NeighborList& list);

  /// Remembers who is paired with whom (by permanent id) before a rebuild or re-sort.
  void remember(const Particles& p, const NeighborList& list);

  /// After the rebuild: looks up each new entry (id_i, id_j) in the remembered rows and copies its state.
  void carry_over(const Particles& p, const NeighborList& list);

  /// A run cut among ranks (core/comm): the state of every listed pair that has an end with keep[i] != 0,
  /// seen from that end: one row per kept particle, in storage order, listing (partner id, state seen from
  /// the particle). A pair of two kept particles is in both their rows (opposite signs), so each end can
  /// take it to whichever rank will own it. Host copies.
  void rows_seen_from(const Particles& p, const NeighborList& list, const unsigned char* keep,
                      comm::PairRows& rows) const;
  /// In place of remember(), for a run cut among ranks: `rows` (as rows_seen_from() gave them, after
  /// migration) belong to the particles now stored at `stored_at[k]` (row k) and name their partners by id.
  /// Only the particles stored here can be partners in the next list, so the rows are looked up by storage
  /// index: memory O(particles here), not O(largest id in the system). carry_over() then finds a pair in
  /// the row of either end.
  void remember_rows(const Particles& p, const comm::PairRows& rows, const std::vector<int>& stored_at);

  /// Transfer points (offload builds): the state, device -> host (checkpoints, analysis) or host -> device.
  void to_host() const;
  void to_device() const;

  std::size_t bytes() const { return 3 * sizeof(double) * hx.capacity(); }

 private:
  exec::DeviceVector<int> old_offset_;
  exec::DeviceVector<std::int64_t> old_partner_;
  exec::DeviceVector<int> old_row_of_id_;
  exec::DeviceVector<double> old_hx_, old_hy_, old_hz_;
  bool by_index_ = false;  // remember_rows(): old rows keyed by storage index, not by id
};

}  // namespace debris
