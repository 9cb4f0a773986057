#pragma once
// What the two executables' checkpoints share around their contents: writing through `path`.tmp, sealed
// with checksums (core/io/hdf5_seal.hpp) and synced before it is renamed over the previous checkpoint;
// reading only sealed files, after the seal is checked; and one error for whatever is wrong with a checkpoint.
//
// Every problem with a checkpoint given to --restart is bad input (InputError, exit 2) naming the file and
// what is wrong, never a crash or a run from a state that is not the one written: a changed byte fails
// the seal (naming the dataset it falls in), a file without a seal is refused, and what a sealed file holds is checked
// (sizes agree, indices in range, ids unique, enumerations known) before anything uses it. A checkpoint
// that cannot be written is an OutputError (exit 3); the previous one is left as it was.
#include <filesystem>
#include <new>
#include <utility>
#include <string>

#include "core/comm/communicator.hpp"
#include "core/error.hpp"
#include "core/io/hdf5_seal.hpp"

namespace debris {

/// "input error: 'restart' = <path>: is not a sound checkpoint: <what>".
inline InputError unsound_checkpoint(const std::string& path, const std::string& what) {
  return input_error("restart", path, "is not a sound checkpoint: " + what);
}

/// Throws unsound_checkpoint(path, what) unless `ok`.
inline void check_checkpoint(bool ok, const std::string& path, const std::string& what) {
  if (!ok) throw unsound_checkpoint(path, what);
}

/// Checks that `path` exists, is sealed and its seal holds, then returns read(), turning what escapes it into
/// an InputError naming the file. `kind` ("debris_dem") is for the messages.
///
/// A file without a seal is refused before HDF5 parses a byte of it: libhdf5 does not survive every damaged
/// file (the readers' fuzzer found a heap overflow in libhdf5 1.10.8 on a mutated unsealed checkpoint), and
/// without checksums nothing can tell a damaged file from a sound one. Checkpoints from before seals (DEM
/// format 2, PeriDEM format 1, written before 2026-12-01) are refused with them.
template <class Read>
auto read_checkpoint_file(const std::string& path, const std::string& kind, Read&& read) {
  if (!std::filesystem::exists(path)) throw input_error("restart", path, "no such checkpoint file");
  bool sealed = false;
  try {
    sealed = h5::verify_seal(path);
  } catch (const std::exception& e) {
    throw InputError("input error: 'restart': " + std::string(e.what()) +
                     "; restart from an earlier checkpoint, or run again from the input");
  }
  if (!sealed)
    throw input_error("restart", path,
                      "is not a " + kind +
                          " checkpoint debris can trust: its checksums are missing. It is another kind of file, a "
                          "checkpoint whose end was cut off, or one written by a debris from before checkpoints "
                          "were sealed (2026-12-01); only sealed files are read, so that no damaged file reaches "
                          "the HDF5 library");
  try {
    return read();
  } catch (const InputError&) {
    throw;
  } catch (const std::bad_alloc&) {
    throw unsound_checkpoint(path, "its sizes do not fit in memory");
  } catch (const std::exception& e) {
    throw input_error("restart", path, "cannot be read as a " + kind + " checkpoint: " + e.what());
  }
}

/// Calls write(tmp) to write the checkpoint's HDF5 file `path`.tmp and close it, seals it, and renames it
/// over `path`. On any failure the temporary file is removed, `path` is untouched, and an OutputError
/// names it. `all_ranks`: every rank of a run cut among ranks calls this and write(tmp) (which writes one
/// file together); rank 0 alone seals and renames, once every rank has closed the file.
template <class Write>
void write_checkpoint_file(const std::string& path, bool all_ranks, Write&& write) {
  const bool root = !all_ranks || comm::rank() == 0;
  const std::string tmp = path + ".tmp";
  try {
    write(tmp);
    if (root) h5::seal(tmp);
  } catch (const std::exception& e) {
    std::error_code ignored;
    if (root) std::filesystem::remove(tmp, ignored);
    throw output_error(path, std::string("cannot write the checkpoint (the previous one is kept): ") + e.what());
  }
  if (!root) return;
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::filesystem::remove(tmp, ec);
    throw output_error(path, "cannot rename " + tmp + " onto it (the previous checkpoint is kept): " + ec.message());
  }
}

/// One process writes the checkpoint.
template <class Write>
void write_checkpoint_file(const std::string& path, Write&& write) {
  write_checkpoint_file(path, false, std::forward<Write>(write));
}

}  // namespace debris
