#include "core/exec.hpp"

#include "core/thread_tuner.hpp"

#include <omp.h>

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

bool kernels_run_on_device() {
#if defined(DEBRIS_OFFLOAD_NVPTX)
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
  os << "debris: " << (offload_build() ? "offload build (nvptx)" : "host build") << ", kernels run on ";
  if (kernels_run_on_device())
    os << "GPU (device " << omp_get_default_device() << " of " << omp_get_num_devices() << ")";
  else
    os << "host threads (" << threads() << ")";
  return os.str();
}

#if defined(DEBRIS_OFFLOAD_NVPTX)
namespace {
const char* bytes_of(const void* p) { return static_cast<const char*>(p); }
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
  (void)c;  // used only inside the pragma, which -Wunused-variable does not see
  DEBRIS_PRAGMA(omp target exit data map(release : c[0 : bytes]))
}
void update_device(const void* p, std::size_t bytes) {
  if (!p || bytes == 0) return;
  const char* c = bytes_of(p);
  (void)c;  // used only inside the pragma, which -Wunused-variable does not see
  DEBRIS_PRAGMA(omp target update to(c[0 : bytes]))
}
void update_host(const void* p, std::size_t bytes) {
  if (!p || bytes == 0) return;
  const char* c = bytes_of(p);
  (void)c;  // used only inside the pragma, which -Wunused-variable does not see
  DEBRIS_PRAGMA(omp target update from(c[0 : bytes]))
}
#else
void device_enter(const void*, std::size_t) {}
void device_exit(const void*, std::size_t) {}
void update_device(const void*, std::size_t) {}
void update_host(const void*, std::size_t) {}
#endif

}  // namespace debris::exec
