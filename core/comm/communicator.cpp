#include "core/comm/communicator.hpp"

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <initializer_list>
#include <stdexcept>

#if defined(DEBRIS_MPI)
#include <mpi.h>
#endif

namespace debris::comm {

namespace {
// The first of the launcher variables that is set, as a positive count (or rank); `fallback` otherwise.
int launcher_value(std::initializer_list<const char*> names, int fallback) {
  for (const char* name : names)
    if (const char* v = std::getenv(name); v && *v) {
      char* end = nullptr;
      const long n = std::strtol(v, &end, 10);
      if (end && *end == '\0' && n >= 0 && n < (1L << 30)) return static_cast<int>(n);
    }
  return fallback;
}
}  // namespace

int launched_processes() {
  return std::max(1, launcher_value({"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_SIZE", "SLURM_NTASKS"}, 1));
}
int launched_rank() { return launcher_value({"OMPI_COMM_WORLD_RANK", "PMI_RANK", "PMIX_RANK", "SLURM_PROCID"}, 0); }

#if defined(DEBRIS_MPI)

namespace {
// MPI's errors are fatal by default (MPI_ERRORS_ARE_FATAL), so a return code never needs checking here.
// (Open MPI's MPI_COMM_WORLD is an address cast, not a constant expression: hence a macro.)
#define kWorld MPI_COMM_WORLD

int count_of(std::size_t n) {
  if (n > static_cast<std::size_t>(INT32_MAX)) throw std::runtime_error("comm: a message over 2 GiB");
  return static_cast<int>(n);
}
}  // namespace

Session::Session(int* argc, char*** argv) {
  int started = 0;
  MPI_Initialized(&started);
  if (started) return;
  int provided = 0;
  MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided);
  owns_ = true;
}

Session::~Session() {
  if (!owns_) return;
  int ended = 0;
  MPI_Finalized(&ended);
  if (!ended) MPI_Finalize();
}

// A program that never started MPI (no Session: debris_patch, the Python module) is one process.
bool running() {
  int started = 0, ended = 0;
  MPI_Initialized(&started);
  MPI_Finalized(&ended);
  return started && !ended;
}

int rank() {
  if (!running()) return 0;
  int r = 0;
  MPI_Comm_rank(kWorld, &r);
  return r;
}

int size() {
  if (!running()) return 1;
  int s = 1;
  MPI_Comm_size(kWorld, &s);
  return s;
}

std::string describe() {
  char version[MPI_MAX_LIBRARY_VERSION_STRING];
  int len = 0;
  MPI_Get_library_version(version, &len);
  std::string v(version, static_cast<std::size_t>(len));
  if (const auto cut = v.find_first_of(",\n"); cut != std::string::npos) v.resize(cut);
  const int n = size();
  return v + ", " + std::to_string(n) + (n == 1 ? " rank" : " ranks");
}

void barrier() { MPI_Barrier(kWorld); }

void abort(int status) {
  MPI_Abort(kWorld, status);
  std::exit(status);
}

void allreduce_sum(std::int64_t* v, int n) { MPI_Allreduce(MPI_IN_PLACE, v, n, MPI_INT64_T, MPI_SUM, kWorld); }
void allreduce_max(double* v, int n) { MPI_Allreduce(MPI_IN_PLACE, v, n, MPI_DOUBLE, MPI_MAX, kWorld); }
void allreduce_min(double* v, int n) { MPI_Allreduce(MPI_IN_PLACE, v, n, MPI_DOUBLE, MPI_MIN, kWorld); }

std::string first_message(const std::string& mine) {
  const int n = size();
  int root = mine.empty() ? n : rank();
  MPI_Allreduce(MPI_IN_PLACE, &root, 1, MPI_INT, MPI_MIN, kWorld);
  if (root == n) return {};
  std::int64_t length = static_cast<std::int64_t>(mine.size());
  MPI_Bcast(&length, 1, MPI_INT64_T, root, kWorld);
  std::string text = rank() == root ? mine : std::string(static_cast<std::size_t>(length), ' ');
  MPI_Bcast(text.data(), count_of(text.size()), MPI_CHAR, root, kWorld);
  return text;
}

namespace {
// Where each rank's bytes go in a gathered buffer: counts and displacements for MPI_(All)Gatherv.
struct Layout {
  std::vector<int> counts, displs;
  std::size_t total = 0;
  explicit Layout(const std::vector<std::int64_t>& sizes) {
    for (const std::int64_t b : sizes) {
      counts.push_back(count_of(static_cast<std::size_t>(b)));
      displs.push_back(count_of(total));
      total += static_cast<std::size_t>(b);
    }
  }
  /// The gathered buffer cut back into each rank's bytes.
  std::vector<std::vector<char>> split(const std::vector<char>& all) const {
    std::vector<std::vector<char>> out;
    for (std::size_t r = 0; r < counts.size(); ++r) out.emplace_back(all.begin() + displs[r], all.begin() + displs[r] + counts[r]);
    return out;
  }
};
}  // namespace

std::vector<std::vector<char>> gather_to_root(const std::vector<char>& mine) {
  const int n = size(), me = rank();
  std::int64_t bytes = static_cast<std::int64_t>(mine.size());
  std::vector<std::int64_t> sizes(me == 0 ? static_cast<std::size_t>(n) : 0);
  MPI_Gather(&bytes, 1, MPI_INT64_T, sizes.data(), 1, MPI_INT64_T, 0, kWorld);
  const Layout at(sizes);  // empty on the other ranks
  std::vector<char> all(at.total);
  MPI_Gatherv(mine.data(), count_of(mine.size()), MPI_BYTE, all.data(), at.counts.data(), at.displs.data(), MPI_BYTE, 0,
              kWorld);
  return at.split(all);
}

std::vector<std::vector<char>> gather_to_all(const std::vector<char>& mine) {
  std::int64_t bytes = static_cast<std::int64_t>(mine.size());
  std::vector<std::int64_t> sizes(static_cast<std::size_t>(size()));
  MPI_Allgather(&bytes, 1, MPI_INT64_T, sizes.data(), 1, MPI_INT64_T, kWorld);
  const Layout at(sizes);
  std::vector<char> all(at.total);
  MPI_Allgatherv(mine.data(), count_of(mine.size()), MPI_BYTE, all.data(), at.counts.data(), at.displs.data(), MPI_BYTE,
                 kWorld);
  return at.split(all);
}

void sendrecv(const std::vector<char>& out, int to, std::vector<char>& in, int from, int tag) {
  if (to < 0) to = MPI_PROC_NULL;
  if (from < 0) from = MPI_PROC_NULL;
  std::int64_t out_size = static_cast<std::int64_t>(out.size()), in_size = 0;
  MPI_Sendrecv(&out_size, 1, MPI_INT64_T, to, tag, &in_size, 1, MPI_INT64_T, from, tag, kWorld, MPI_STATUS_IGNORE);
  in.resize(static_cast<std::size_t>(in_size));
  MPI_Sendrecv(out.data(), count_of(out.size()), MPI_BYTE, to, tag, in.data(), count_of(in.size()), MPI_BYTE, from,
               tag, kWorld, MPI_STATUS_IGNORE);
}

void sendrecv_sized(const char* out, std::size_t out_bytes, int to, char* in, std::size_t in_bytes, int from, int tag) {
  MPI_Sendrecv(out, count_of(out_bytes), MPI_BYTE, to < 0 ? MPI_PROC_NULL : to, tag, in, count_of(in_bytes), MPI_BYTE,
               from < 0 ? MPI_PROC_NULL : from, tag, kWorld, MPI_STATUS_IGNORE);
}

#else  // the one-rank stub of a serial build

Session::Session(int*, char***) {}
Session::~Session() = default;
int rank() { return 0; }
int size() { return 1; }
std::string describe() { return "serial build (no MPI)"; }
void barrier() {}
void abort(int status) { std::exit(status); }
void allreduce_sum(std::int64_t*, int) {}
void allreduce_max(double*, int) {}
void allreduce_min(double*, int) {}
std::string first_message(const std::string& mine) { return mine; }
std::vector<std::vector<char>> gather_to_root(const std::vector<char>& mine) { return {mine}; }
std::vector<std::vector<char>> gather_to_all(const std::vector<char>& mine) { return {mine}; }

void sendrecv(const std::vector<char>& out, int to, std::vector<char>& in, int from, int) {
  if (to > 0 || from > 0) throw std::logic_error("comm: a serial build has rank 0 only");
  if (from < 0) {
    in.clear();
    return;
  }
  in = out;
}

void sendrecv_sized(const char* out, std::size_t out_bytes, int to, char* in, std::size_t in_bytes, int from, int) {
  if (to > 0 || from > 0) throw std::logic_error("comm: a serial build has rank 0 only");
  if (from == 0 && to == 0) std::memcpy(in, out, std::min(out_bytes, in_bytes));
}

#endif

}  // namespace debris::comm
