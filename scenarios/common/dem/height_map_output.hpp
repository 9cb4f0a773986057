#pragma once
// The worn faces' height maps, one pair per census sample, in an HDF5 file a user opens with h5py for their own
// analysis (surfaces_heights.h5):
//   attributes of /: normal_axis, axis_a, axis_b (0-2 for x-z), spacing (2 doubles, m), origin (2 doubles, m)
//   /samples/<k>/bottom, /samples/<k>/top   n_a x n_b double, m along the normal (row i along a, column j along b)
//   attributes of /samples/<k>: step (int64), time (s), slide (m)
// Each sample opens the file, writes and closes it, so between samples it is never open. A run continued from a
// checkpoint keeps the samples its census had then and drops any written after (a chunk killed past its last
// checkpoint), copying them into a fresh file that replaces the old one: a chunked run writes the maps of one.
#include <string>

#include "core/rough/height_field.hpp"

namespace debris {

class HeightMapWriter {
 public:
  /// `path` created (truncating), or with `keep` >= 0: its first `keep` samples kept, the rest dropped
  /// (std::runtime_error naming the file if it holds fewer).
  HeightMapWriter(std::string path, long keep = -1);
  void append(long step, double time, double slide, const HeightField& bottom, const HeightField& top);
  long samples() const { return samples_; }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  long samples_ = 0;
};

}  // namespace debris
