#pragma once
// The two settings that make an HDF5 file one file of all ranks (MPI-IO), kept here because only core/comm
// knows MPI. core/io/hdf5_file calls them for a file opened with FileOptions::all_ranks; HDF5 then wants
// every call that changes the file's structure (create, link, attribute, close) made by every rank with
// the same arguments, while the values of a dataset may come from some ranks only (write_rows()).
#include <cstdint>

namespace debris::comm {

/// Sets the file access property list `fapl` (an hid_t) to MPI-IO on all ranks of the run and returns true;
/// false in a serial build or a run of one rank, where the file is opened as usual (nothing to share).
/// std::runtime_error if HDF5 refuses.
bool hdf5_access_on_all_ranks(std::int64_t fapl);

/// Sets the transfer property list `dxpl` (an hid_t) to collective MPI-IO: every rank takes part in each
/// write, those without values with an empty selection. False where hdf5_access_on_all_ranks() is;
/// std::runtime_error if HDF5 refuses.
bool hdf5_collective_transfer(std::int64_t dxpl);

}  // namespace debris::comm
