#pragma once
// core/exec: the only place in debris that knows about OpenMP.
//
// A kernel is a canonical `for (int i = 0; i < n; ++i)` loop preceded by one of the macros below.
// Host builds (DEBRIS_OFFLOAD=none) expand them to `omp parallel for schedule(static)` and contain no
// target construct at all: GCC 12's host fallback starts an OS thread per target region (45-440 us),
// which would drown a step made of many small passes (shared/notes/openmp-offload.md).
// Offload builds (DEBRIS_OFFLOAD=nvptx) expand them to `omp target teams distribute parallel for`; the
// SoA columns they touch are kept resident on the device with the enter/exit/update helpers below.
//
// Rules for code inside a kernel: raw pointers copied into locals before the loop, plain Vec3, no Eigen,
// no virtual call, no allocation, no exception.

#include <cstddef>
#include <string>

#define DEBRIS_PRAGMA(x) _Pragma(#x)

#if defined(DEBRIS_OFFLOAD_NVPTX)
#define DEBRIS_KERNEL DEBRIS_PRAGMA(omp target teams distribute parallel for)
#define DEBRIS_KERNEL_SUM(v) DEBRIS_PRAGMA(omp target teams distribute parallel for reduction(+ : v) map(tofrom : v))
#define DEBRIS_KERNEL_SUM2(a, b) \
  DEBRIS_PRAGMA(omp target teams distribute parallel for reduction(+ : a, b) map(tofrom : a, b))
#define DEBRIS_KERNEL_SUM3(a, b, c) \
  DEBRIS_PRAGMA(omp target teams distribute parallel for reduction(+ : a, b, c) map(tofrom : a, b, c))
#define DEBRIS_KERNEL_MAX(v) DEBRIS_PRAGMA(omp target teams distribute parallel for reduction(max : v) map(tofrom : v))
#define DEBRIS_KERNEL_MIN(v) DEBRIS_PRAGMA(omp target teams distribute parallel for reduction(min : v) map(tofrom : v))
#define DEBRIS_DECLARE_TARGET DEBRIS_PRAGMA(omp declare target)
#define DEBRIS_END_DECLARE_TARGET DEBRIS_PRAGMA(omp end declare target)
#else
#define DEBRIS_KERNEL DEBRIS_PRAGMA(omp parallel for schedule(static))
#define DEBRIS_KERNEL_SUM(v) DEBRIS_PRAGMA(omp parallel for schedule(static) reduction(+ : v))
#define DEBRIS_KERNEL_SUM2(a, b) DEBRIS_PRAGMA(omp parallel for schedule(static) reduction(+ : a, b))
#define DEBRIS_KERNEL_SUM3(a, b, c) DEBRIS_PRAGMA(omp parallel for schedule(static) reduction(+ : a, b, c))
#define DEBRIS_KERNEL_MAX(v) DEBRIS_PRAGMA(omp parallel for simd schedule(static) reduction(max : v))
#define DEBRIS_KERNEL_MIN(v) DEBRIS_PRAGMA(omp parallel for schedule(static) reduction(min : v))
#define DEBRIS_DECLARE_TARGET
#define DEBRIS_END_DECLARE_TARGET
#endif

// Host-only parallel regions for passes that need a per-thread buffer (the half-list contact pass). Never
// used in an offload build (mixing host parallel regions with target regions oversubscribes the cores).
#define DEBRIS_HOST_PARALLEL DEBRIS_PRAGMA(omp parallel)
#define DEBRIS_HOST_FOR DEBRIS_PRAGMA(omp for schedule(static))
// A vector loop (host and device): no dependence between iterations.
#define DEBRIS_SIMD DEBRIS_PRAGMA(omp simd)

// A real scatter (rare: pair passes use full lists and write only to i).
#define DEBRIS_ATOMIC_ADD(target, value) \
  DEBRIS_PRAGMA(omp atomic update)       \
  target += (value)

namespace debris::exec {

/// True in builds compiled with DEBRIS_OFFLOAD=nvptx.
constexpr bool offload_build() {
#if defined(DEBRIS_OFFLOAD_NVPTX)
  return true;
#else
  return false;
#endif
}

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

// Device residency of SoA columns. No-ops in host builds (and harmless on host fallback).
void device_enter(const void* p, std::size_t bytes);
void device_exit(const void* p, std::size_t bytes);
void update_device(const void* p, std::size_t bytes);  // host -> device after a host-side change
void update_host(const void* p, std::size_t bytes);    // device -> host before output or analysis

}  // namespace debris::exec
