#pragma once
#include <string>

namespace debris::fuzz {

/// Cuts the checksum trailer (core/io/hdf5_seal.hpp) off a sealed HDF5 file, leaving the file as HDF5 wrote it.
void strip_seal(const std::string& path);

/// Copies the HDF5 file `seed` to `out` and applies the edits `program` encodes (tests/fuzz/hdf5_mutation.cpp):
/// datasets and attributes deleted, resized, reshaped, retyped, or given awkward values.
/// The first byte of the program says whether the result is sealed again (even) or left unsealed (odd, as
/// checkpoints written before seals existed), so that both of the loaders' paths are fuzzed.
void mutate_hdf5(const std::string& seed, const std::string& out, const std::string& program);

}  // namespace debris::fuzz
