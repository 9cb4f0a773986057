#include "core/comm/parallel_hdf5.hpp"

#include <hdf5.h>

#include <stdexcept>

#include "core/comm/communicator.hpp"

#if defined(DEBRIS_MPI)
#include <mpi.h>
#endif

namespace debris::comm {

#if defined(DEBRIS_MPI)

bool hdf5_access_on_all_ranks(std::int64_t fapl) {
  if (size() == 1) return false;
  if (H5Pset_fapl_mpio(fapl, MPI_COMM_WORLD, MPI_INFO_NULL) < 0)
    throw std::runtime_error("HDF5: cannot open files through MPI-IO (H5Pset_fapl_mpio)");
  return true;
}

bool hdf5_collective_transfer(std::int64_t dxpl) {
  if (size() == 1) return false;
  if (H5Pset_dxpl_mpio(dxpl, H5FD_MPIO_COLLECTIVE) < 0)
    throw std::runtime_error("HDF5: cannot make a collective transfer (H5Pset_dxpl_mpio)");
  return true;
}

#else

bool hdf5_access_on_all_ranks(std::int64_t) { return false; }
bool hdf5_collective_transfer(std::int64_t) { return false; }

#endif

}  // namespace debris::comm
