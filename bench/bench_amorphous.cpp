// Google Benchmark of the amorphous-sample relaxation (Pham-Ba & Molinari section 3.2,
// scenarios/common/dem/amorphous_sample.hpp), phase 2: adhesive normal force, no tangential force, damping
// 0.02 c_c, the periodic box moved every 10 steps from the average virial stress, run until the normal
// stresses are below 1e-14 E. The system is the small sample of the tests' kind: Table 4 material, d0 =
// 0.6 d_c (so delta_f = d0 / 3, the longest relative interaction range of the paper's sweep), diameters
// in [0.75, 1.25] d0, 10 x 10 x 4 d0, about 550 particles, seed 1.
//
//   BM_AmorphousPhase2   relax_phase2() from the end of phase 1 to convergence   items = particle-steps
//
// Argument: threads (debris::exec::set_threads). The inserted sample and its phase 1 are made once and
// kept (not timed); each iteration builds a simulation from that state (not timed) and runs the whole of
// phase 2 (timed, stress measurements and box updates included). Counters: particles, phase2_steps (the
// same every iteration on one thread count; across thread counts it may differ by round-off).
#include <benchmark/benchmark.h>

#include <memory>

#include "core/exec.hpp"
#include "scenarios/common/dem/amorphous_sample.hpp"
#include "scenarios/common/dem/dem_simulation.hpp"

namespace debris {
namespace {

AmorphousSpec bench_spec() {
  AmorphousSpec s;
  s.d0 = 0.6;
  s.length = 10;
  s.width = 4;
  s.seed = 1;
  return s;
}

DemSettings bench_settings(const AmorphousSpec& spec) {
  DemSettings set;
  set.material = spec.material;
  set.time_step_fraction = spec.time_step_fraction;
  set.skin = spec.skin();
  return set;
}

/// The state at the end of phase 1, made on first use with the current thread count.
struct Phase1State {
  Box box;
  Particles particles;
};

const Phase1State& phase1_state() {
  static std::unique_ptr<Phase1State> state;
  if (!state) {
    const AmorphousSpec spec = bench_spec();
    InsertedSpheres ins = insert_random_spheres(spec);
    DemSimulation sim(ins.box, std::move(ins.particles), Groups{}, bench_settings(spec));
    relax_phase1(sim, spec);
    state = std::make_unique<Phase1State>(Phase1State{sim.box(), sim.particles()});
  }
  return *state;
}

void BM_AmorphousPhase2(benchmark::State& state) {
  exec::set_threads(static_cast<int>(state.range(0)));
  const AmorphousSpec spec = bench_spec();
  const Phase1State& start = phase1_state();
  long steps = 0;
  double particle_steps = 0;
  for (auto _ : state) {
    state.PauseTiming();
    DemSimulation sim(start.box, start.particles, Groups{}, bench_settings(spec));
    state.ResumeTiming();
    steps = relax_phase2(sim, spec);
    particle_steps += static_cast<double>(steps) * static_cast<double>(start.particles.size());
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(particle_steps));
  state.counters["particles"] = static_cast<double>(start.particles.size());
  state.counters["phase2_steps"] = static_cast<double>(steps);
}

BENCHMARK(BM_AmorphousPhase2)->Arg(1)->Arg(2)->UseRealTime()->Unit(benchmark::kSecond);

}  // namespace
}  // namespace debris
