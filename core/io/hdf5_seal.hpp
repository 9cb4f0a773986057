#pragma once
// Checksums for HDF5 files that must not be trusted blindly (checkpoints): after the file is written and
// closed, seal() appends a trailer beyond HDF5's end of file (HDF5 ignores bytes past its end-of-address,
// so h5py, h5dump and ParaView read the file as before) that holds
//
//   - for every dataset whose values lie in one contiguous stretch of the file, its path, offset, length
//     and a 64-bit checksum of those bytes;
//   - a checksum of the whole HDF5 part (object headers, names, attributes and values alike);
//   - a fixed 48-byte footer with the HDF5 length, the table's checksum and its own, and a magic word.
//
// verify_seal() checks all of it before HDF5 parses a byte, so a changed byte anywhere is an error that
// names the file and, where the byte lies in a dataset's values, the dataset; HDF5 never reads a damaged
// structure (which can crash it). The checksum is our own (four 64-bit multiply-rotate lanes): any change
// confined to one 8-byte word always changes it, other changes miss with odds of about 2^-64.
#include <cstddef>
#include <cstdint>
#include <string>

namespace debris::h5 {

/// A streaming 64-bit checksum of a byte sequence.
class Checksum {
 public:
  void update(const void* data, std::size_t bytes);
  std::uint64_t finish() const;

 private:
  std::uint64_t lane_[4] = {0x243f6a8885a308d3ull, 0x13198a2e03707344ull, 0xa4093822299f31d0ull, 0x082efa98ec4e6c89ull};
  unsigned char pending_[32] = {};
  std::size_t pending_bytes_ = 0;
  std::uint64_t total_ = 0;
};

/// Appends the checksum trailer to the closed HDF5 file at `path` and syncs it to disk. std::runtime_error
/// (naming the file) if it cannot be read or written.
void seal(const std::string& path);

/// Whether `path` ends in a seal (false: an unsealed file, e.g. written before seals existed, or not one
/// of ours). If it has one, checks it: std::runtime_error naming the file and the damaged dataset (or
/// the HDF5 structure, or the trailer) when any byte differs from what was sealed.
bool verify_seal(const std::string& path);

}  // namespace debris::h5
