#pragma once
// PeriDEM node frames in HDF5 with an XDMF sidecar, the pair ParaView opens (File > Open the .xmf). Layout
// of <stem>.h5 (the nodes of a PeriDEM run never change in number or order, so what does not change is
// written once):
//   /nodes/id            N int64     permanent node ids, rows in node order
//   /nodes/grain         N int32     index of the node's grain or wall
//   /nodes/volume        N double    nodal volume of eq 31 (area in 2D)
//   /grains/name         names of the grains and walls;  /grains/kind  int32 (0 particle, 1 wall)
//   /frames/<k>/position N x 3 double
//              /velocity N x 3 double
//              /force    N x 3 double
//              /damage   N double    Z of eq 14 (max |s| / s_0 over the node's bonds)
//              /broken_fraction N double  fraction of the node's bonds that are broken
//   attributes of /frames/<k>: step (int64), time (double)
// <stem>.xmf lists every frame as one grid of a temporal collection, each with the attributes id, grain,
// volume, damage, broken_fraction, velocity and force, referring to "<stem>.h5:/..." relative to the .xmf.
//
// A killed run leaves both files readable, as core/io/trajectory_writer.hpp explains and by the same
// means: the .h5 is open only inside write_frame, each frame is built as an unlinked group, flushed, then
// linked (two-step commit), and the .xmf is rewritten (to .tmp, renamed) only after the .h5 is closed.
//
// A run cut among MPI ranks writes one file together (all_ranks): every rank makes the writer and each
// frame's call with its share of the nodes (NodeFrameShare: its own nodes and their rows), each writes its
// rows (collective parallel HDF5), and rank 0 the .xmf. The file is the one a single process writes.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace debris {

class PdNodes;
struct PdGrains;

/// A process's share of a node frame.
struct NodeFrameShare {
  std::vector<int> which;          // indices of its nodes in its PdNodes, in increasing id
  std::vector<std::int64_t> rows;  // their rows in the frame (where their id stands among all ids)
  std::size_t total = 0;           // nodes in the frame, on all ranks

  /// The whole frame held by one process: every node, in its index order (ids increase with it), rows 0, 1, ...
  static NodeFrameShare all_of(const PdNodes& nodes);
};

class NodeTrajectoryWriter {
 public:
  /// Creates <dir>/<stem>.h5 and <dir>/<stem>.xmf (truncating both; no frame yet) and writes the static
  /// node and grain data. InputError ("output") if they cannot be created or `stem` holds ':' or '/'.
  NodeTrajectoryWriter(const std::string& dir, const std::string& stem, const PdNodes& nodes, const PdGrains& grains,
                       const std::vector<std::string>& grain_names);
  /// The same, of the whole system's grains (`grain_kinds`, `grain_names`: one per grain and wall there) and
  /// this process's `share` of the nodes; `all_ranks`: every rank of an MPI run makes the writer together,
  /// `nodes.grain` then naming the whole system's grains through `grain_ids` (PdGrains::id of each grain held).
  NodeTrajectoryWriter(const std::string& dir, const std::string& stem, const PdNodes& nodes,
                       const NodeFrameShare& share, const std::vector<int>& grain_ids,
                       const std::vector<int>& grain_kinds, const std::vector<std::string>& grain_names, bool all_ranks);

  /// Appends frame frames() from the nodes' current positions, velocities, forces and damage column, and
  /// `broken_fraction` (one per node), then rewrites the .xmf. std::invalid_argument if the node count
  /// changed; std::runtime_error (naming file and object) if HDF5 fails.
  void write_frame(long step, double time, const PdNodes& nodes, const std::vector<double>& broken_fraction);
  /// The same, every rank of a writer of all ranks together: each its `share` of the nodes it holds.
  void write_frame(long step, double time, const PdNodes& nodes, const NodeFrameShare& share,
                   const std::vector<double>& broken_fraction);

  long frames() const { return static_cast<long>(frames_.size()); }
  const std::string& h5_path() const { return h5_path_; }
  const std::string& xmf_path() const { return xmf_path_; }

 private:
  struct Frame {
    long step;
    double time;
  };
  void write_xmf() const;

  std::string h5_name_, h5_path_, xmf_path_;
  std::size_t nodes_ = 0;
  std::vector<Frame> frames_;
  bool all_ranks_ = false;
};

}  // namespace debris
