#pragma once
// core/comm/communicator: the only place in debris that knows MPI (as core/exec is the only place that knows
// OpenMP). Everything here acts on all ranks of the run (MPI_COMM_WORLD). A serial build (DEBRIS_MPI off)
// compiles the same functions as a one-rank stub, so every caller is written once: rank() is 0, size() is 1,
// a reduction returns its own input and a message to rank 0 comes back to the sender.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace debris::comm {

/// True in builds configured with DEBRIS_MPI=ON.
constexpr bool mpi_build() {
#if defined(DEBRIS_MPI)
  return true;
#else
  return false;
#endif
}

/// Starts MPI for the life of the object (MPI_Init_thread, funnelled: only the main thread calls MPI) and
/// ends it (MPI_Finalize) when it goes. Nothing happens in a serial build, or when MPI was already started.
class Session {
 public:
  Session(int* argc, char*** argv);
  ~Session();
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;

 private:
  bool owns_ = false;
};

/// This process's rank and the run's rank count: 0 and 1 where MPI was never started (a program without a
/// Session, or a serial build).
int rank();
int size();

/// How many processes the MPI launcher (mpirun, mpiexec, srun) started together with this one, and this
/// one's place among them, read from the launcher's environment (Open MPI, MPICH/Hydra, PMIx, Slurm):
/// 1 and 0 when not started by one. A serial build reads these to refuse a run that mpirun started many
/// times over: each copy would run the whole input and write the same files.
int launched_processes();
int launched_rank();
/// "Open MPI v4.1.4, 4 ranks" or "serial build (no MPI)": for the run's first line.
std::string describe();

void barrier();
/// Ends every rank of the run with `status` (after a rank alone found an error the others cannot see).
[[noreturn]] void abort(int status);

/// In-place sums over all ranks of n 64-bit integers: exact, so the same in any order (core/comm/exact_sum).
void allreduce_sum(std::int64_t* v, int n);
/// In-place maxima and minima over all ranks (exact in any order as well).
void allreduce_max(double* v, int n);
void allreduce_min(double* v, int n);

/// The text of the lowest rank whose `mine` is not empty, on every rank (empty when none has one): an
/// error that one rank found (an input error, a failed health check), reported the same by all so that all
/// stop the same way. Collective.
std::string first_message(const std::string& mine);

/// Every rank's `mine`, on rank 0 in rank order (other ranks get an empty list). Collective.
std::vector<std::vector<char>> gather_to_root(const std::vector<char>& mine);
/// Every rank's `mine`, on every rank, in rank order. Collective.
std::vector<std::vector<char>> gather_to_all(const std::vector<char>& mine);

/// Sends `out` to rank `to` and receives what rank `from` sends to this rank with the same tag (sizes
/// travel first, so the receiver need not know them). A rank of -1 means none (nothing is sent, or `in`
/// comes back empty); to == from == rank() copies `out` into `in`.
void sendrecv(const std::vector<char>& out, int to, std::vector<char>& in, int from, int tag);

/// The same when both sides know the sizes (a halo's forward(): fixed lists between rebuilds): one message
/// each way, into `in_bytes` bytes at `in`.
void sendrecv_sized(const char* out, std::size_t out_bytes, int to, char* in, std::size_t in_bytes, int from, int tag);

}  // namespace debris::comm
