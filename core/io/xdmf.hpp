#pragma once
// What the two HDF5 + XDMF trajectory writers (particles: trajectory_writer, PeriDEM nodes:
// node_trajectory_writer) share: the XDMF text of a temporal collection of Polyvertex frames whose data
// lives in the .h5 beside it, its atomic replacement on disk, and the HDF5 sizing that keeps frame links
// kill-safe.
#include <cstddef>
#include <string>

#include "core/io/hdf5_file.hpp"

namespace debris::xdmf {

// Linking a frame rewrites the index of /frames in place, which a kill between two writes cannot damage;
// splitting a full index leaf or moving a full heap of names can (a kill mid-way leaves pointers past the
// end of file that the superblock records). Sizing both up front makes those events rare: a leaf split every
// 256 frames after the first 512, a heap move after 8192 frames (names take 8 bytes each). The price is
// ~85 KiB rewritten per frame.
constexpr unsigned kFramesPerLeaf = 512;
constexpr std::size_t kFrameNameBytes = 8 * 8192;

/// How both writers create and reopen their .h5: no lock (a viewer may hold the file while a run appends),
/// index leaves sized as above (used at creation only), and no space a close could give back
/// (FileOptions::survives_kill).
inline h5::FileOptions frames_file_options(bool all_ranks) {
  return {.file_locking = false, .group_leaf_k = kFramesPerLeaf / 2, .all_ranks = all_ranks, .survives_kill = true};
}

/// InputError ("output") unless `stem` can name the .h5 inside the .xmf: XDMF splits "file.h5:/path" at the
/// colon, and the reference must stay relative to the .xmf.
void check_stem(const std::string& stem);

/// `s` with &, <, > and " escaped for XML.
std::string escaped(const std::string& s);

/// The opening of a document holding one temporal collection named `collection`.
std::string begin(const std::string& collection);
/// Opens one frame of `n` points at `time` whose positions are the N x 3 dataset `position_ref`
/// ("file.h5:/path", already escaped).
void begin_frame(std::string& x, long step, double time, const std::string& n, const std::string& position_ref);
/// One per-point attribute: a scalar (N) or a vector (N x 3) dataset at `ref`.
void attribute(std::string& x, const char* name, bool vector, const std::string& n, const char* number_type,
               int precision, const std::string& ref);
void end_frame(std::string& x);
void end(std::string& x);

/// Writes `text` to `path`.tmp, then renames it over `path`, so a reader (or a kill) never sees half a file.
/// `what` names the writer in errors.
void replace_file(const std::string& path, const std::string& text, const char* what);

}  // namespace debris::xdmf
