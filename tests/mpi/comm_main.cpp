// GoogleTest main for the tests of core/comm, run under mpirun (label mpi) in an MPI build and as one
// process on the serial build's stub. Every rank runs every test; rank 0 prints the usual report, the other
// ranks print only their failures, each line prefixed with the rank. The exit status is the same on every
// rank (a failure anywhere fails all), so mpirun and ctest see it whichever rank failed.
#include <gtest/gtest.h>

#include <cstdint>
#include <iostream>
#include <string>

#include "core/comm/communicator.hpp"

namespace {
class RankFailurePrinter : public ::testing::EmptyTestEventListener {
 public:
  explicit RankFailurePrinter(int rank) : rank_(rank) {}
  void OnTestPartResult(const ::testing::TestPartResult& r) override {
    if (!r.failed()) return;
    // One write per failure, so the ranks' reports do not interleave mid-line.
    const std::string text = "[rank " + std::to_string(rank_) + "] " + (r.file_name() ? r.file_name() : "?") + ":" +
                             std::to_string(r.line_number()) + ": failure\n" + r.summary() + "\n";
    std::cerr << text << std::flush;
  }

 private:
  int rank_;
};
}  // namespace

int main(int argc, char** argv) {
  // Before MPI starts, a program is one process: what debris_patch, debris_amorphous and the Python module,
  // which never start MPI, see in an MPI build (MPI itself refuses MPI_Comm_size before MPI_Init).
  if (debris::comm::rank() != 0 || debris::comm::size() != 1) {
    std::cerr << "comm::rank() / size() before MPI starts: not 0 / 1" << std::endl;
    return 1;
  }
  debris::comm::Session mpi(&argc, &argv);
  ::testing::InitGoogleTest(&argc, argv);
  const int rank = debris::comm::rank();
  if (rank != 0) {
    auto& listeners = ::testing::UnitTest::GetInstance()->listeners();
    delete listeners.Release(listeners.default_result_printer());
    listeners.Append(new RankFailurePrinter(rank));
  } else {
    std::cout << "core/comm tests: " << debris::comm::describe() << std::endl;
  }
  std::int64_t failed = RUN_ALL_TESTS() != 0 ? 1 : 0;
  debris::comm::allreduce_sum(&failed, 1);
  if (rank == 0 && failed)
    std::cerr << failed << " of " << debris::comm::size() << " ranks had failures (their [rank r] lines above)" << std::endl;
  return failed ? 1 : 0;
}
