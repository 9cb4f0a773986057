// Google Benchmark of one patch test (Pham-Ba & Molinari section 3, scenarios/patch/patch_test.hpp): the
// elastic test (confined compression under a stress of 0.01 on the top wall, damping 0.2 c_c, time step
// 0.1 dt_c, run to equilibrium) on a small HCP lattice: Table 4 material at nu = 0.15, d0 = 0.6 d_c, c axis
// along the load, 10 x 10 x 3 d0 (the engine raises W to what its neighbour list needs), walls 1.5 d0.
//
//   BM_PatchElastic   run_elastic_test() from set-up to convergence   items = particle-steps
//
// Argument: threads (debris::exec::set_threads). The sample is built once (not timed); each iteration runs
// the whole test, simulation set-up, stress measurements and stopping rule included. Counters: particles,
// steps (the same on every iteration).
#include <benchmark/benchmark.h>

#include "core/exec.hpp"
#include "scenarios/patch/patch_test.hpp"

namespace debris {
namespace {

CohesiveMaterial bench_material() {
  CohesiveMaterial m = table4_material(0.0);
  m.poisson_ratio = 0.15;
  return m;
}

void BM_PatchElastic(benchmark::State& state) {
  exec::set_threads(static_cast<int>(state.range(0)));
  const CohesiveMaterial m = bench_material();
  HcpSampleSpec spec;
  spec.d0 = 0.6 * m.critical_diameter();
  spec.c_axis = 1;
  spec.length = 10;
  spec.thickness = 3;
  const PatchSample sample = make_hcp_sample(spec, m);
  const ElasticSettings settings;
  long steps = 0;
  double particle_steps = 0;
  for (auto _ : state) {
    const ElasticResult r = run_elastic_test(sample, m, settings);
    steps = r.steps;
    particle_steps += static_cast<double>(r.steps) * static_cast<double>(sample.particles.size());
    benchmark::DoNotOptimize(r.moduli.E);
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(particle_steps));
  state.counters["particles"] = static_cast<double>(sample.particles.size());
  state.counters["steps"] = static_cast<double>(steps);
}

BENCHMARK(BM_PatchElastic)->Arg(1)->Arg(2)->UseRealTime()->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace debris
