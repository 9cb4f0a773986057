#pragma once
// core/exec: the only place in debris that knows about OpenMP.
//
// A kernel is a canonical `for (int i = 0; i < n; ++i)` loop preceded by one of the macros below.
// Host builds (DEBRIS_OFFLOAD=none) expand them to `omp parallel for schedule(static)` and contain no
// target construct at all: GCC 12's host fallback starts an OS thread per target region (45-440 us),
// which would drown a step made of many small passes (shared/notes/openmp-offload.md).
// Offload builds (DEBRIS_OFFLOAD=nvptx or hostdevice) expand them to `omp target teams distribute parallel
// for`. Kernels never map anything: every array they touch is a DeviceVector, whose allocator enters its
// buffer on the device when it is allocated and deletes it when it is freed, so the mapping lives exactly
// as long as the buffer (no path leaks or double-frees one). The host copy is refreshed only at named
// transfer points, exec::to_host(v) and exec::to_device(v) (grep for them to list every transfer of a run).
// In a host build DeviceVector<T> is std::vector<T> and the transfers are empty inline functions.
//
// Residency check: DEBRIS_RESIDENT(a, b, ...) before a kernel names the arrays it reads or writes; in
// hostdevice builds (and with -DDEBRIS_CHECK_RESIDENCY) it aborts naming the kernel's file and line if one
// of them is not on the device. clang's host device would otherwise run such a kernel on the host's memory
// without complaint, and a GPU would fault or read garbage.
//
// Rules for code inside a kernel: raw pointers copied into locals before the loop, plain Vec3, no Eigen,
// no virtual call, no allocation, no exception.

#include <algorithm>
#include <cstddef>
#include <memory>
#include <type_traits>
#include <string>
#include <vector>

#define DEBRIS_PRAGMA(x) _Pragma(#x)

#if defined(DEBRIS_OFFLOAD_NVPTX) || defined(DEBRIS_OFFLOAD_HOSTDEVICE)
#define DEBRIS_OFFLOAD_TARGET 1
#endif
#if defined(DEBRIS_OFFLOAD_HOSTDEVICE) && !defined(DEBRIS_CHECK_RESIDENCY)
#define DEBRIS_CHECK_RESIDENCY 1
#endif

#if defined(DEBRIS_OFFLOAD_TARGET)
#define DEBRIS_KERNEL DEBRIS_PRAGMA(omp target teams distribute parallel for)
#define DEBRIS_KERNEL_SUM(v) DEBRIS_PRAGMA(omp target teams distribute parallel for reduction(+ : v) map(tofrom : v))
#define DEBRIS_KERNEL_SUM2(a, b) \
  DEBRIS_PRAGMA(omp target teams distribute parallel for reduction(+ : a, b) map(tofrom : a, b))
#define DEBRIS_KERNEL_SUM3(a, b, c) \
  DEBRIS_PRAGMA(omp target teams distribute parallel for reduction(+ : a, b, c) map(tofrom : a, b, c))
#define DEBRIS_KERNEL_MAX(v) DEBRIS_PRAGMA(omp target teams distribute parallel for reduction(max : v) map(tofrom : v))
#define DEBRIS_KERNEL_MIN(v) DEBRIS_PRAGMA(omp target teams distribute parallel for reduction(min : v) map(tofrom : v))
#define DEBRIS_KERNEL_MINMAX3(l0, l1, l2, h0, h1, h2)                                                         \
  DEBRIS_PRAGMA(omp target teams distribute parallel for reduction(min : l0, l1, l2) reduction(max : h0, h1, h2) \
                    map(tofrom : l0, l1, l2, h0, h1, h2))
#define DEBRIS_DECLARE_TARGET DEBRIS_PRAGMA(omp declare target)
#define DEBRIS_END_DECLARE_TARGET DEBRIS_PRAGMA(omp end declare target)
#else
#define DEBRIS_KERNEL DEBRIS_PRAGMA(omp parallel for schedule(static))
#define DEBRIS_KERNEL_SUM(v) DEBRIS_PRAGMA(omp parallel for schedule(static) reduction(+ : v))
#define DEBRIS_KERNEL_SUM2(a, b) DEBRIS_PRAGMA(omp parallel for schedule(static) reduction(+ : a, b))
#define DEBRIS_KERNEL_SUM3(a, b, c) DEBRIS_PRAGMA(omp parallel for schedule(static) reduction(+ : a, b, c))
#define DEBRIS_KERNEL_MAX(v) DEBRIS_PRAGMA(omp parallel for simd schedule(static) reduction(max : v))
#define DEBRIS_KERNEL_MIN(v) DEBRIS_PRAGMA(omp parallel for schedule(static) reduction(min : v))
#define DEBRIS_KERNEL_MINMAX3(l0, l1, l2, h0, h1, h2) \
  DEBRIS_PRAGMA(omp parallel for schedule(static) reduction(min : l0, l1, l2) reduction(max : h0, h1, h2))
#define DEBRIS_DECLARE_TARGET
#define DEBRIS_END_DECLARE_TARGET
#endif

// Host-only parallel regions for passes that need a per-thread buffer (the half-list contact pass). Never
// used in an offload build (mixing host parallel regions with target regions oversubscribes the cores).
#define DEBRIS_HOST_PARALLEL DEBRIS_PRAGMA(omp parallel)
#define DEBRIS_HOST_FOR DEBRIS_PRAGMA(omp for schedule(static))
// A vector loop (host and device): no dependence between iterations.
#define DEBRIS_SIMD DEBRIS_PRAGMA(omp simd)
// A host vector loop whose body calls an inlined per-pair law (no dependence between iterations either).
// Not omp simd: GCC lowers omp simd before it inlines, and turns each struct the law takes or returns into
// a per-lane array, which stops the loop from vectorising.
#if defined(__clang__)
#define DEBRIS_HOST_VECTOR_LOOP DEBRIS_PRAGMA(clang loop vectorize(assume_safety))
#else
#define DEBRIS_HOST_VECTOR_LOOP DEBRIS_PRAGMA(GCC ivdep)
#endif

// A real scatter (rare: pair passes use full lists and write only to i).
#define DEBRIS_ATOMIC_ADD(target, value) \
  DEBRIS_PRAGMA(omp atomic update)       \
  target += (value)

namespace debris::exec {

/// True in builds compiled with DEBRIS_OFFLOAD=nvptx or hostdevice.
constexpr bool offload_build() {
#if defined(DEBRIS_OFFLOAD_TARGET)
  return true;
#else
  return false;
#endif
}

/// "none", "nvptx" or "hostdevice".
const char* offload_kind();

/// Number of host threads kernels use (host builds) or that host fallback uses.
void set_threads(int n);
int threads();

/// Inside a DEBRIS_HOST_PARALLEL region: this thread's index and the team's size (0 and 1 outside one).
int team_rank();
int team_size();

/// Runs a tiny target region and reports whether it executed on a GPU. Always false in host builds.
bool kernels_run_on_device();

/// One line for the start of every run: build kind, where kernels run, thread count.
std::string startup_report();

// Device residency. No-ops in host builds (and harmless on GCC's host fallback, which shares memory).
void device_enter(const void* p, std::size_t bytes);   // map(to): allocate on the device and copy
void device_exit(const void* p, std::size_t bytes);    // map(release)
void device_alloc(const void* p, std::size_t bytes);   // map(alloc): allocate, no copy
void device_free(const void* p, std::size_t bytes);    // map(delete): whatever the reference count
void update_device(const void* p, std::size_t bytes);  // host -> device after a host-side change
void update_host(const void* p, std::size_t bytes);    // device -> host before output or analysis
/// True when p is mapped on the default device (always true in host builds and on the initial device).
bool is_present(const void* p);

/// The device number of the host itself (host fallback: target regions share the host's memory), and the
/// default device kernels and transfers go to. Tests run a model on both to compare them in one process;
/// everything a run allocates must be created and freed under the same default device.
int initial_device();
int default_device();
void set_default_device(int device);

/// Transfers counted since the last reset (offload builds; all zero in host builds): calls, bytes and the
/// wall time spent in them, per direction.
struct TransferStats {
  long to_host_calls = 0, to_device_calls = 0;
  double to_host_bytes = 0, to_device_bytes = 0;
  double to_host_seconds = 0, to_device_seconds = 0;
};
TransferStats transfer_stats();
void reset_transfer_stats();

#if defined(DEBRIS_OFFLOAD_TARGET)
/// An allocator whose buffers exist on the device for exactly their lifetime: allocate enters the new
/// buffer (no copy: its contents are written afterwards, on the host then to_device, or by a kernel),
/// deallocate deletes it. A std::vector with it re-enters its storage whenever it reallocates.
template <class T>
struct DeviceAllocator {
  using value_type = T;
  DeviceAllocator() = default;
  template <class U>
  DeviceAllocator(const DeviceAllocator<U>&) noexcept {}
  T* allocate(std::size_t n) {
    T* p = std::allocator<T>().allocate(n);
    device_alloc(p, n * sizeof(T));
    return p;
  }
  void deallocate(T* p, std::size_t n) noexcept {
    device_free(p, n * sizeof(T));
    std::allocator<T>().deallocate(p, n);
  }
  template <class U>
  bool operator==(const DeviceAllocator<U>&) const noexcept {
    return true;
  }
};
template <class T>
using DeviceVector = std::vector<T, DeviceAllocator<T>>;
/// A device-resident column equals a plain vector with the same elements (tests, checkpoints).
template <class T, class A>
  requires(!std::is_same_v<A, DeviceAllocator<T>>)
bool operator==(const std::vector<T, DeviceAllocator<T>>& a, const std::vector<T, A>& b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin());
}

/// Named transfer points: the whole of v (its size, not its capacity), device -> host or host -> device.
template <class T, class A>
void to_host(const std::vector<T, A>& v) {
  update_host(v.data(), v.size() * sizeof(T));
}
template <class T, class A>
void to_device(const std::vector<T, A>& v) {
  update_device(v.data(), v.size() * sizeof(T));
}
/// The first `count` elements only.
template <class T, class A>
void to_host(const std::vector<T, A>& v, std::size_t count) {
  update_host(v.data(), count * sizeof(T));
}
#else
template <class T>
using DeviceVector = std::vector<T>;
template <class T, class A>
inline void to_host(const std::vector<T, A>&) {}
template <class T, class A>
inline void to_device(const std::vector<T, A>&) {}
template <class T, class A>
inline void to_host(const std::vector<T, A>&, std::size_t) {}
#endif

/// A host array a kernel reads (a caller's mask, say): the array itself in host builds; in offload builds a
/// copy of it in `scratch`, sent to the device for this call.
template <class T>
const T* on_device(const T* host, std::size_t n, DeviceVector<T>& scratch) {
  if constexpr (!offload_build()) {
    return host;
  } else {
    if (!host) return nullptr;
    scratch.assign(host, host + n);
    to_device(scratch);
    return scratch.data();
  }
}

/// How many blocks a row kernel hands its `rows` out in: host builds block rows of about
/// `entries_per_block` list entries each (one dispatched call per block, equal work per thread although
/// rows differ in length); offload builds one row per iteration.
constexpr int row_blocks(int rows, long long entries, int entries_per_block) {
  if constexpr (offload_build()) {
    return rows;
  } else {
    const long long b = entries / entries_per_block;
    return rows == 0 ? 0 : (b < 1 ? 1 : static_cast<int>(b));
  }
}

/// Aborts with file, line and the argument's name when a non-null pointer is not on the device.
void check_resident(const char* file, int line, const char* names, const void* const* ptrs, int n);
template <class... P>
inline void check_resident_args(const char* file, int line, const char* names, const P*... ptrs) {
  const void* list[] = {static_cast<const void*>(ptrs)...};
  check_resident(file, line, names, list, static_cast<int>(sizeof...(P)));
}

}  // namespace debris::exec

// Function versions for x86 hosts (target_clones): the function is compiled for x86-64 and x86-64-v3 (AVX2
// + FMA), the HOST_ONLY form also for x86-64-v4 (AVX-512), and the loader picks the best the machine runs,
// so the default build runs anywhere and still uses wide vectors where they exist.
//   DEBRIS_CLONES: for code that offload builds also call inside target regions, where function clones do
//     not exist; empty there.
//   DEBRIS_HOST_ONLY_CLONES: for host passes that never run on a device; in every build.
#if defined(DEBRIS_OFFLOAD_TARGET)
#define DEBRIS_CLONES
#else
#define DEBRIS_CLONES __attribute__((target_clones("default", "arch=x86-64-v3")))
#endif
#define DEBRIS_HOST_ONLY_CLONES __attribute__((target_clones("default", "arch=x86-64-v3", "arch=x86-64-v4")))
// For a per-pair law called from a cloned loop: GCC makes the clones after early inlining, and its later
// inliner will not put a function built for x86-64 into an x86-64-v3 clone, so a law too large for early
// inlining would stay an out-of-line call there (no vector loop, and no FMA: different bits).
#define DEBRIS_ALWAYS_INLINE inline __attribute__((always_inline))

#if defined(DEBRIS_CHECK_RESIDENCY)
#define DEBRIS_RESIDENT(...) ::debris::exec::check_resident_args(__FILE__, __LINE__, #__VA_ARGS__, __VA_ARGS__)
#else
#define DEBRIS_RESIDENT(...) ((void)0)
#endif
