#pragma once
// Trajectory frames in HDF5 with an XDMF sidecar, the pair ParaView opens (File > Open the .xmf; both of
// its XDMF readers work). Layout of <stem>.h5:
//   /group_names                 names of the motion groups (strings; index k is group k)
//   /frames/<k>/position         N x 3 double      rows sorted by permanent id
//              /id               N int64
//              /type, /group     N int32 (group -1 = none)
//              /radius           N double
//              /velocity, /force N x 3 double
//              /angular_velocity N x 3 double
//              /image            N x 3 int32     periodic image counts: unwrapped = position + image * box length
//              /label            N int32         body the particle started in (0 = none, k = label_names[k-1])
//              /label_names      strings         the legend of label (Particles::label_names)
//   attributes of /frames/<k>: step (int64), time (double), box_lo, box_hi (3 doubles), periodic (3 int32)
// <stem>.xmf lists every frame as one grid of a temporal collection, with the data referred to as
// "<stem>.h5:/frames/<k>/...", a path relative to the .xmf, so the pair can be moved together.
//
// A killed run leaves both files readable. Each frame opens the .h5, writes, flushes and closes it again,
// so between frames the file is never open; the .xmf is rewritten only after that close (to .xmf.tmp,
// then renamed over the old one), so it always lists exactly the frames whose data is complete on disk.
// A kill inside a frame is survived too when it falls between two system calls (the frame is committed in
// two steps, see write_frame; tested at every write of 60 frames), except in the rare frame that must
// grow the index of /frames (every 256 frames after the first 512). A kill that interrupts the kernel in
// the middle of one multi-page write can still tear that index, rarely (a few in 10^4 random kills at most).
// The file is opened without HDF5's flock, so a viewer holding it open cannot make the run fail.
//
// A run cut among MPI ranks writes one file together (all_ranks): every rank makes the writer and each
// frame's call, each writes its own particles' rows (collective parallel HDF5), and rank 0 the .xmf. The
// file is the one a single process writes of the same particles, row for row.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "core/box.hpp"
#include "core/particles.hpp"

namespace debris {

/// A process's share of a frame of particles cut among ranks.
struct FrameShare {
  std::vector<int> which;          // indices of its particles in its Particles, in increasing id
  std::vector<std::int64_t> rows;  // their rows in the frame (where their id stands among all ids)
  std::size_t total = 0;           // particles in the frame, on all ranks

  /// The whole frame held by one process: all of `p`, sorted by id, in rows 0, 1, ...
  static FrameShare all_of(const Particles& p);
};

class TrajectoryWriter {
 public:
  /// Creates <dir>/<stem>.h5 and <dir>/<stem>.xmf (truncating both; the .xmf lists no frame yet).
  /// InputError ("output") if they cannot be created or `stem` holds a character XDMF cannot refer to.
  /// `all_ranks`: every rank of an MPI run makes this writer and writes each frame together.
  TrajectoryWriter(const std::string& dir, const std::string& stem, std::vector<std::string> group_names,
                   bool all_ranks = false);

  /// Appends frame frames(): positions, ids, types, radii, velocities, forces, groups, angular velocities,
  /// image counts and labels sorted by id, then
  /// rewrites the .xmf. N may change between frames. std::runtime_error (naming file and object) if
  /// HDF5 fails; std::invalid_argument if a particle's group has no name.
  void write_frame(long step, double time, const Box& box, const Particles& p);
  /// The same, every rank of a writer of all ranks together: each rank's `share` of the particles `p` it
  /// holds (the box, step and time are every rank's alike).
  void write_frame(long step, double time, const Box& box, const Particles& p, const FrameShare& share);

  long frames() const { return static_cast<long>(frames_.size()); }
  const std::string& h5_path() const { return h5_path_; }
  const std::string& xmf_path() const { return xmf_path_; }

 private:
  struct Frame {
    long step;
    double time;
    std::size_t particles;
  };
  void write_xmf() const;

  std::string h5_name_, h5_path_, xmf_path_;
  std::vector<std::string> group_names_;
  std::vector<Frame> frames_;
  bool all_ranks_ = false;
};

}  // namespace debris
