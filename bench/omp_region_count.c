/* Counts the OpenMP parallel regions a program starts (libgomp's GOMP_parallel entry point), for the
 * README's "parallel regions per step": each region ends at a barrier, and on a shared machine every
 * barrier can wait for a thread that lost its core. Load it beside any executable:
 *
 *   LD_PRELOAD=build/bench/libdebris_region_count.so build/bin/debris_dem -i run.yaml --threads 2
 *
 * and it prints the count at exit; run two lengths and divide the difference by the extra steps. */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <stdio.h>

static unsigned long long regions = 0;

typedef void (*gomp_parallel_fn)(void (*)(void*), void*, unsigned, unsigned);

void GOMP_parallel(void (*fn)(void*), void* data, unsigned num_threads, unsigned flags) {
  static gomp_parallel_fn real = 0;
  if (!real) real = (gomp_parallel_fn)dlsym(RTLD_NEXT, "GOMP_parallel");
  __atomic_add_fetch(&regions, 1, __ATOMIC_RELAXED);
  real(fn, data, num_threads, flags);
}

__attribute__((destructor)) static void report(void) {
  fprintf(stderr, "omp_region_count: %llu parallel regions\n", regions);
}
