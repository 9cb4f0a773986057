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
#include <cstddef>
#include <string>
#include <vector>

namespace debris {

class PdNodes;
struct PdGrains;

class NodeTrajectoryWriter {
 public:
  /// Creates <dir>/<stem>.h5 and <dir>/<stem>.xmf (truncating both; no frame yet) and writes the static
  /// node and grain data. InputError ("output") if they cannot be created or `stem` holds ':' or '/'.
  NodeTrajectoryWriter(const std::string& dir, const std::string& stem, const PdNodes& nodes, const PdGrains& grains,
                       const std::vector<std::string>& grain_names);

  /// Appends frame frames() from the nodes' current positions, velocities, forces and damage column, and
  /// `broken_fraction` (one per node), then rewrites the .xmf. std::invalid_argument if the node count
  /// changed; std::runtime_error (naming file and object) if HDF5 fails.
  void write_frame(long step, double time, const PdNodes& nodes, const std::vector<double>& broken_fraction);

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
};

}  // namespace debris
