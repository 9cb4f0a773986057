#include "core/exec.hpp"

#include "core/thread_tuner.hpp"

#include <omp.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <sstream>

namespace debris::exec {

void set_threads(int n) {
  if (n <= 0) return;
  stop_tuning();  // a count set by hand is kept (core/thread_tuner.hpp)
  omp_set_num_threads(n);
}

int threads() { return omp_get_max_threads(); }

int team_rank() { return omp_get_thread_num(); }
int team_size() { return omp_get_num_threads(); }

const char* offload_kind() {
#if defined(DEBRIS_OFFLOAD_NVPTX)
  return "nvptx";
#elif defined(DEBRIS_OFFLOAD_HOSTDEVICE)
  return "hostdevice";
#else
  return "none";
#endif
}

bool kernels_run_on_device() {
#if defined(DEBRIS_OFFLOAD_TARGET)
  int on_device = 0;
  // GCC 12 silently falls back to the host even under OMP_TARGET_OFFLOAD=MANDATORY, so ask the region.
  DEBRIS_PRAGMA(omp target map(from : on_device))
  { on_device = !omp_is_initial_device(); }
  return on_device != 0;
#else
  return false;
#endif
}

std::string startup_report() {
  std::ostringstream os;
  os << "debris: ";
  if (offload_build())
    os << "offload build (" << offload_kind() << ")";
  else
    os << "host build";
  os << ", kernels run on ";
  if (kernels_run_on_device())
    os << (std::string(offload_kind()) == "hostdevice" ? "the host CPU as a separate-memory device" : "GPU")
       << " (device " << omp_get_default_device() << " of " << omp_get_num_devices() << ")";
  else
    os << "host threads (" << threads() << ")";
  return os.str();
}

int initial_device() { return omp_get_initial_device(); }
int default_device() { return omp_get_default_device(); }
void set_default_device(int device) { omp_set_default_device(device); }

namespace {
TransferStats g_stats;  // host bookkeeping only (transfers are issued from the host thread)
}  // namespace

TransferStats transfer_stats() { return g_stats; }
void reset_transfer_stats() { g_stats = TransferStats{}; }

#if defined(DEBRIS_OFFLOAD_TARGET)
namespace {
const char* bytes_of(const void* p) { return static_cast<const char*>(p); }
using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }
}  // namespace
void device_enter(const void* p, std::size_t bytes) {
  if (!p || bytes == 0) return;
  const char* c = bytes_of(p);
  (void)c;  // used only inside the pragma, which -Wunused-variable does not see
  DEBRIS_PRAGMA(omp target enter data map(to : c[0 : bytes]))
}
void device_exit(const void* p, std::size_t bytes) {
  if (!p || bytes == 0) return;
  const char* c = bytes_of(p);
  (void)c;
  DEBRIS_PRAGMA(omp target exit data map(release : c[0 : bytes]))
}
void device_alloc(const void* p, std::size_t bytes) {
  if (!p || bytes == 0) return;
  const char* c = bytes_of(p);
  (void)c;
  DEBRIS_PRAGMA(omp target enter data map(alloc : c[0 : bytes]))
}
void device_free(const void* p, std::size_t bytes) {
  if (!p || bytes == 0) return;
  const char* c = bytes_of(p);
  (void)c;
  DEBRIS_PRAGMA(omp target exit data map(delete : c[0 : bytes]))
}
void update_device(const void* p, std::size_t bytes) {
  if (!p || bytes == 0) return;
  const auto t0 = Clock::now();
  const char* c = bytes_of(p);
  (void)c;
  DEBRIS_PRAGMA(omp target update to(c[0 : bytes]))
  g_stats.to_device_calls += 1;
  g_stats.to_device_bytes += static_cast<double>(bytes);
  g_stats.to_device_seconds += since(t0);
}
void update_host(const void* p, std::size_t bytes) {
  if (!p || bytes == 0) return;
  const auto t0 = Clock::now();
  const char* c = bytes_of(p);
  (void)c;
  DEBRIS_PRAGMA(omp target update from(c[0 : bytes]))
  g_stats.to_host_calls += 1;
  g_stats.to_host_bytes += static_cast<double>(bytes);
  g_stats.to_host_seconds += since(t0);
}
bool is_present(const void* p) { return !p || omp_target_is_present(p, omp_get_default_device()) != 0; }
#else
void device_enter(const void*, std::size_t) {}
void device_exit(const void*, std::size_t) {}
void device_alloc(const void*, std::size_t) {}
void device_free(const void*, std::size_t) {}
void update_device(const void*, std::size_t) {}
void update_host(const void*, std::size_t) {}
bool is_present(const void*) { return true; }
#endif

void check_resident(const char* file, int line, const char* names, const void* const* ptrs, int n) {
  for (int k = 0; k < n; ++k) {
    if (is_present(ptrs[k])) continue;
    // Name the k-th argument: the comma-separated list as written at the call.
    std::string all(names), name;
    int at = 0;
    std::size_t from = 0;
    while (at < k && from != std::string::npos) {
      from = all.find(',', from);
      if (from != std::string::npos) ++from;
      ++at;
    }
    if (from != std::string::npos) {
      const std::size_t to = all.find(',', from);
      name = all.substr(from, to == std::string::npos ? std::string::npos : to - from);
      while (!name.empty() && name.front() == ' ') name.erase(name.begin());
    }
    std::fprintf(stderr, "debris: residency check failed at %s:%d: array '%s' (%p) is not on device %d\n", file,
                 line, name.c_str(), ptrs[k], omp_get_default_device());
    std::abort();
  }
}

}  // namespace debris::exec
