// Google Benchmark suite of the cohesive DEM engine on the system of the benchmarks issue: a periodic FCC
// packing (nearest-neighbour distance 100, diameters 100 +- 5%, periodic on all axes) of the paper's
// Table 4 material (E = 1, nu = 0.15, sigma_mN = 0.2, sigma_mT = 0.1, gamma = 1.5, eta = 0.95, rho = 1,
// s = 0: d_min = 30 < d < d_c = 150, delta_f = 30 inside the cutoff, 12 interacting neighbours each),
// small random velocities, dt = 0.1 dt_c, N = 4,000 / 32,000 / 256,000 particles on 1 and 2 threads (the step
// also at 1,048,576; DEBRIS_BENCH_SIZES=n1,n2,... replaces the sizes, see bench_sizes).
//
//   BM_Binning        CellList::build on the positions                        items = particles
//   BM_NeighborBuild  NeighborList::build (full, CohesiveCutoff, engine skin)   items = particles
//   BM_CohesivePass   the host pass over the half list (what the engine runs; it sets f)  items = particles, pairs/s
//   BM_CohesivePassFullList   the same over the full list (the GPU path)
//   BM_Step           DemSimulation::step(), the whole engine                   items = particle-steps
//   BM_Rebuild        DemSimulation::rebuild_neighbors(): wrap, sort by cell, build, carry the history
//                     (what a step costs extra when a particle drifted skin/2; this packing is a stable
//                     crystal and BM_Step reports how often that really happens: rebuilds_per_1k_steps)
//
//   BM_StepPolydisperse  DemSimulation::step() on the wear junction's sample: amorphous silica, log-normal
//                     diameters of mode d0 = 1.5 nm in [1.125, 7.5] nm (size ratio 6.7), 4,000-odd particles
//                     read from scenarios/wear/data/silica_d0_1.5nm.data (LAMMPS data, masses from the file), periodic
//                     in x and z, free in y, Table 5 silica with s = 0.5, dt = 0.1 dt_c, no damping, thermal
//                     velocities of 25 m/s rms (Gaussian components, seed fixed, no net momentum) so that the
//                     list is rebuilt at the rate of a real run, settled for 3,000 steps (untimed). Arguments: threads, the most size classes the
//                     neighbour search may use (1: one grid, as before), and the skin in pm (0: the engine's
//                     default, -1: 0.2 r_min, the default before). Items = particle-steps; rebuild_share = the
//                     neighbour time's share of the step; candidates_per_particle = particles in the stencils
//                     scanned per row at the last rebuild.
//
// Arguments: N (particles) and threads (debris::exec::set_threads, OpenMP). Real time throughout: the
// OpenMP workers' CPU time is not the benchmark thread's. One system per N is built on first use and kept
// (setup is not timed); BM_Step's simulation keeps stepping from call to call.
//
// Counters: bytes_per_particle = (particle columns + neighbour list with its cell list + contact history)
// / N, from Particles::bytes_per_particle() and the objects' bytes(); for BM_Step and BM_Rebuild it is the
// engine's DemSimulation::bytes_per_particle(), which also counts what its contact pass holds (B_other).
// B_* break it down per particle. entries_per_particle = entries / N of the list the benchmark uses: the
// pass benchmarks build a full list (each pair twice), the engine may keep a half list (half_list = 1).
// contacts_per_particle = interacting neighbours (dN <= delta_f) per particle. BM_Step's cell list for
// sorting (DemSimulation::sorter_) is not exposed and not counted.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <map>
#include <memory>
#include <random>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "bench/bench_env.hpp"
#include "core/cell_list.hpp"
#include "core/contact_history.hpp"
#include "core/exec.hpp"
#include "core/io/lammps_data.hpp"
#include "core/lattice.hpp"
#include "core/neighbor_list.hpp"
#include "core/particles.hpp"
#include "kernels/dem/cohesive_contact.hpp"
#include "kernels/dem/cohesive_contact_half.hpp"
#include "kernels/dem/cohesive_pair_table.hpp"
#include "kernels/dem/cohesive_material.hpp"
#include "kernels/dem/integrate.hpp"
#include "scenarios/common/dem/dem_simulation.hpp"

namespace debris {
namespace {

// Engine steps run once after set-up, untimed: the packing starts with overlaps of up to 5% of a diameter
// (size spread) and relaxes; at N = 256,000 a particle drifts skin/2 in about 13 steps and triggers one
// early rebuild. After that the crystal vibrates in place and never needs another (rebuilds_per_1k_steps
// of BM_Step reports the rate actually seen; BM_Rebuild gives the cost of one).
constexpr long kEngineWarmUpSteps = 20;
// Contact passes run on the pass benchmarks' snapshot to load its tangential springs (zero when built).
constexpr long kPassWarmUp = 3;

int cells_per_axis(int n) {
  const int c = static_cast<int>(std::lround(std::cbrt(n / 4.0)));
  if (4 * c * c * c != n) throw std::invalid_argument("bench: N must be 4 c^3 (FCC), got " + std::to_string(n));
  return c;
}

/// Memory held by the engine's data per particle, from the objects themselves.
struct Footprint {
  double particles = 0, list = 0, cells = 0, history = 0;
  double total() const { return particles + list + history; }  // list includes its cell list
};

Footprint footprint(std::size_t n, const NeighborList& list, const ContactHistory& history) {
  const double dn = static_cast<double>(n);
  Footprint f;
  f.particles = static_cast<double>(Particles::bytes_per_particle());
  f.list = static_cast<double>(list.bytes()) / dn;
  f.cells = static_cast<double>(list.cells().bytes()) / dn;
  f.history = static_cast<double>(history.bytes()) / dn;
  return f;
}

struct DemSystem {
  int n = 0;
  // The whole engine, for BM_Step and BM_Rebuild.
  std::unique_ptr<DemSimulation> sim;
  // A snapshot of the engine after the warm-up steps, for the pass benchmarks: particles sorted by cell
  // as the engine keeps them, a full neighbour list and a contact history of their own.
  Box box;
  Particles p;
  CohesiveCoefficients coef{};
  CohesiveOptions options;
  double dt = 0, max_cutoff = 0, skin = 0;
  NeighborList list;                  // full list: BM_CohesivePassFullList (the GPU path)
  ContactHistory history;
  ContactHistory history0;            // the snapshot's history, restored before every timed pass
  NeighborList half;                  // half list: BM_CohesivePass (the host path the engine runs)
  ContactHistory half_history;
  CohesivePairTable table;
  HalfPassScratch scratch;
  ContactHistory half_history0;
  CellList cells;                     // BM_Binning's output
  NeighborList built;                 // BM_NeighborBuild's output
  double contacts_per_particle = 0;  // interacting neighbours per particle in the snapshot
};

DemSystem& dem_system(int n, bool energy = true) {
  static std::map<std::pair<int, bool>, std::unique_ptr<DemSystem>> cache;
  auto& slot = cache[{n, energy}];
  if (slot) return *slot;
  auto s = std::make_unique<DemSystem>();
  s->n = n;

  LatticeSpec spec;
  spec.kind = LatticeKind::fcc;
  spec.spacing = 100;
  spec.diameter = 100;
  spec.size_spread = 0.05;
  const int c = cells_per_axis(n);
  spec.cells = {c, c, c};
  spec.seed = 1;
  Lattice lat = make_lattice(spec);
  Particles& p = lat.particles;
  std::mt19937_64 rng(12345);
  std::uniform_real_distribution<double> u(-1e-3, 1e-3);
  for (std::size_t i = 0; i < p.size(); ++i) {
    p.vx[i] = u(rng);
    p.vy[i] = u(rng);
    p.vz[i] = u(rng);
  }
  DemSettings settings;
  settings.material = table4_material();
  settings.time_step_fraction = 0.1;
  settings.global_damping = 0.0;
  settings.energy_accounting = energy;
  Box box(lat.box.lo(), lat.box.hi(), {true, true, true});
  s->sim = std::make_unique<DemSimulation>(box, std::move(p), Groups{}, settings);
  s->sim->run(kEngineWarmUpSteps);

  // The pass benchmarks get their own full list (the engine may run a half-list pass) on the engine's
  // current positions, sorted by cell as the engine keeps them, and a history advanced by a few passes so
  // that the springs are loaded as in a running simulation.
  const DemSimulation& sim = *s->sim;
  s->box = sim.box();
  s->p = sim.particles();
  to_device(s->p);  // offload builds: a copy's device buffer starts empty (no-op on the host)
  s->coef = sim.coefficients();
  s->options = sim.settings().options;
  s->dt = sim.dt();
  s->max_cutoff = sim.max_cutoff();
  s->skin = sim.skin();
  s->list.build(s->box.view(), s->p, CohesiveCutoff{s->coef}, s->max_cutoff, s->skin, NeighborKind::full);
  s->history.reset(s->list);
  for (long k = 0; k < kPassWarmUp; ++k) {
    zero_forces(s->p);
    cohesive_contact_pass(s->coef, s->options, s->box.view(), s->p, s->list, s->history, s->dt, 1);
  }
  s->history.to_host();  // the warm-up passes ran on the device in offload builds
  s->history0 = s->history;
  s->half.build(s->box.view(), s->p, CohesiveCutoff{s->coef}, s->max_cutoff, s->skin, NeighborKind::half);
  s->half_history.reset(s->half);
  s->table.build(s->coef, s->p, s->half);
  s->scratch.index(s->half);
  for (long k = 0; k < kPassWarmUp; ++k) {
    zero_forces(s->p);
    cohesive_contact_pass_half(s->table, s->options, s->box.view(), s->p, s->half, s->half_history, s->dt, 1,
                               s->scratch);
  }
  s->half_history0 = s->half_history;  // the half pass runs on the host: its history is there
  const CohesiveDiagnostics d = cohesive_diagnostics(s->coef, s->options, s->box.view(), s->p, s->list, s->history);
  s->contacts_per_particle = 2.0 * static_cast<double>(d.interacting_pairs) / n;
  slot = std::move(s);
  return *slot;
}

/// entries_per_particle: of the list the benchmark uses (the engine's may be a half list: half_list = 1).
void set_common_counters(benchmark::State& state, const DemSystem& s, const Footprint& f, const NeighborList& list,
                         bool breakdown) {
  state.counters["bytes_per_particle"] = f.total();
  state.counters["entries_per_particle"] = static_cast<double>(list.entries()) / s.n;
  state.counters["half_list"] = list.kind() == NeighborKind::half ? 1 : 0;
  state.counters["contacts_per_particle"] = s.contacts_per_particle;
  if (breakdown) {
    state.counters["B_particles"] = f.particles;
    state.counters["B_list"] = f.list;
    state.counters["B_cells"] = f.cells;
    state.counters["B_history"] = f.history;
  }
}

/// The engine's own accounting, DemSimulation::bytes_per_particle(): particles, list, history and whatever
/// else its contact pass holds (pair table, per-thread buffers: B_other).
void set_engine_counters(benchmark::State& state, const DemSystem& s, const DemSimulation& sim, bool breakdown) {
  const Footprint f = footprint(sim.particles().size(), sim.neighbors(), sim.history());
  set_common_counters(state, s, f, sim.neighbors(), breakdown);
  state.counters["bytes_per_particle"] = sim.bytes_per_particle();
  if (breakdown) state.counters["B_other"] = sim.bytes_per_particle() - f.total();
}

void BM_Binning(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  exec::set_threads(static_cast<int>(state.range(1)));
  DemSystem& s = dem_system(n);
  const BoxView box = s.box.view();
  for (auto _ : state) {
    s.cells.build(box, s.p.x.data(), s.p.y.data(), s.p.z.data(), n, s.max_cutoff + s.skin);
    benchmark::DoNotOptimize(s.cells.sorted_index().data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * n);
  set_common_counters(state, s, footprint(s.p.size(), s.list, s.history), s.list, false);
  state.counters["cells"] = s.cells.cell_count();
}

void BM_NeighborBuild(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  exec::set_threads(static_cast<int>(state.range(1)));
  DemSystem& s = dem_system(n);
  const BoxView box = s.box.view();
  const CohesiveCutoff cutoff{s.coef};
  for (auto _ : state) {
    s.built.build(box, s.p, cutoff, s.max_cutoff, s.skin, NeighborKind::full);
    benchmark::DoNotOptimize(s.built.index().data());
    benchmark::ClobberMemory();
  }
  if (s.built.entries() != s.list.entries())
    state.SkipWithError("the rebuilt list differs in size from the snapshot's");
  state.SetItemsProcessed(state.iterations() * n);
  set_common_counters(state, s, footprint(s.p.size(), s.list, s.history), s.list, false);
}

// Every timed pass starts from the same history, so it does the same work (springs would otherwise grow with
// every pass at fixed positions and end up all sliding). Copies in place: no allocation in the loop.
void restore_history(ContactHistory& h, const ContactHistory& saved) {
  std::copy(saved.hx.begin(), saved.hx.end(), h.hx.begin());
  std::copy(saved.hy.begin(), saved.hy.end(), h.hy.begin());
  std::copy(saved.hz.begin(), saved.hz.end(), h.hz.begin());
  h.to_device();  // offload builds: the passes read the device copy (no-op on the host)
}

void BM_CohesivePassFullList(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  exec::set_threads(static_cast<int>(state.range(1)));
  DemSystem& s = dem_system(n);
  const BoxView box = s.box.view();
  for (auto _ : state) {
    state.PauseTiming();
    restore_history(s.history, s.history0);
    state.ResumeTiming();
    zero_forces(s.p);
    cohesive_contact_pass(s.coef, s.options, box, s.p, s.list, s.history, s.dt, 1);
    benchmark::DoNotOptimize(s.p.fx.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * n);
  state.counters["pairs/s"] =
      benchmark::Counter(static_cast<double>(state.iterations()) * s.list.entries(), benchmark::Counter::kIsRate);
  set_common_counters(state, s, footprint(s.p.size(), s.list, s.history), s.list, true);
}

// The host contact pass the engine runs: half list, per-pair constants, two phases (vectorised pairs, then a
// per-particle gather).
void BM_CohesivePass(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  exec::set_threads(static_cast<int>(state.range(1)));
  DemSystem& s = dem_system(n);
  const BoxView box = s.box.view();
  for (auto _ : state) {
    state.PauseTiming();
    restore_history(s.half_history, s.half_history0);
    state.ResumeTiming();
    cohesive_contact_pass_half(s.table, s.options, box, s.p, s.half, s.half_history, s.dt, 1, s.scratch);  // sets f
    benchmark::DoNotOptimize(s.p.fx.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * n);
  state.counters["pairs/s"] =
      benchmark::Counter(static_cast<double>(state.iterations()) * s.half.entries(), benchmark::Counter::kIsRate);
  set_common_counters(state, s, footprint(s.p.size(), s.half, s.half_history), s.half, true);
  state.counters["B_table_scratch"] = static_cast<double>(s.table.bytes() + s.scratch.bytes()) / n;
}

void step_benchmark(benchmark::State& state, bool energy) {
  const int n = static_cast<int>(state.range(0));
  exec::set_threads(static_cast<int>(state.range(1)));
  DemSystem& s = dem_system(n, energy);
  DemSimulation& sim = *s.sim;
  const long rebuilds0 = sim.times().rebuilds;
  exec::reset_transfer_stats();
  const auto t0 = std::chrono::steady_clock::now();
  for (auto _ : state) {
    sim.step();
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const long rebuilds = sim.times().rebuilds - rebuilds0;
  state.SetItemsProcessed(state.iterations() * n);
  // Host <-> device transfers inside the timed steps (offload builds, where the aim is none between output
  // steps): bytes per step, and their share of the wall time. Zero in host builds.
  const exec::TransferStats moved = exec::transfer_stats();
  const double steps = static_cast<double>(state.iterations());
  state.counters["transfer_bytes_per_step"] = (moved.to_host_bytes + moved.to_device_bytes) / steps;
  state.counters["transfer_share"] = seconds > 0 ? (moved.to_host_seconds + moved.to_device_seconds) / seconds : 0.0;
  state.counters["rebuilds_per_1k_steps"] = 1000.0 * static_cast<double>(rebuilds) / static_cast<double>(state.iterations());
  state.counters["steps_since_setup"] = static_cast<double>(sim.step_count());
  // const: the non-const particles() would mark the host copy edited, and the next run's first step would
  // send every column to the device (offload builds).
  if (first_non_finite(std::as_const(sim).particles()) >= 0) state.SkipWithError("the simulation blew up");
  set_engine_counters(state, s, sim, true);
}

// The whole step without the energy accounting (`output.energy: false`; the regression check's subset, the
// same work as before the accounting existed), and with it, as debris_dem runs by default: the accounting's
// cost is the ratio of the two (interleave them: --benchmark_enable_random_interleaving=true
// --benchmark_repetitions=5).
void BM_Step(benchmark::State& state) { step_benchmark(state, false); }
void BM_StepWithEnergy(benchmark::State& state) { step_benchmark(state, true); }

void BM_Rebuild(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  exec::set_threads(static_cast<int>(state.range(1)));
  DemSystem& s = dem_system(n);
  DemSimulation& sim = *s.sim;
  for (auto _ : state) {
    sim.rebuild_neighbors();
  }
  state.SetItemsProcessed(state.iterations() * n);
  set_engine_counters(state, s, sim, false);
}

#ifndef DEBRIS_SOURCE_DIR
#define DEBRIS_SOURCE_DIR "."
#endif

constexpr double kThermalSpeed = 25.0;  // m/s, rms: the vibration left by carving and shearing
// Untimed steps before any variant is measured. Freed in y, the relaxed sample's faces settle for the first
// ~1,500 steps: rebuilds come every 15-25 steps at the default skin then, every ~200 after. Each variant
// starts from the same settled state, so that all are measured in the same regime.
constexpr long kPolySettleSteps = 3000;
constexpr long kPolyWarmUpSteps = 50;  // each variant's own, untimed: its tangential springs load again

/// The settled sample: the engine with default settings after kPolySettleSteps from the data file.
const DemSimulation& poly_settled() {
  static std::unique_ptr<DemSimulation> sim;
  if (sim) return *sim;
  const char* env = std::getenv("DEBRIS_POLY_SAMPLE");
  const std::string path = env ? env : std::string(DEBRIS_SOURCE_DIR) + "/scenarios/wear/data/silica_d0_1.5nm.data";
  LammpsData data = read_lammps_data(path, {true, false, true});
  Particles& p = data.particles;
  std::mt19937_64 rng(20261201);
  std::normal_distribution<double> g(0.0, kThermalSpeed / std::sqrt(3.0));
  double px = 0, py = 0, pz = 0, m = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    p.vx[i] = g(rng);
    p.vy[i] = g(rng);
    p.vz[i] = g(rng);
    px += p.mass[i] * p.vx[i];
    py += p.mass[i] * p.vy[i];
    pz += p.mass[i] * p.vz[i];
    m += p.mass[i];
  }
  for (std::size_t i = 0; i < p.size(); ++i) {
    p.vx[i] -= px / m;
    p.vy[i] -= py / m;
    p.vz[i] -= pz / m;
  }
  DemSettings settings;
  settings.material = silica_material();
  settings.masses_from_density = false;  // the sample's (scaled) masses, as the junction reads them
  settings.time_step_fraction = 0.1;
  sim = std::make_unique<DemSimulation>(data.box, std::move(p), Groups{}, settings);
  sim->run(kPolySettleSteps);
  return *sim;
}

/// The engine on the settled sample, one per (size classes, skin) and kept stepping between calls.
DemSimulation& poly_system(int classes, int skin_pm) {
  static std::map<std::pair<int, int>, std::unique_ptr<DemSimulation>> cache;
  auto& slot = cache[{classes, skin_pm}];
  if (slot) return *slot;
  const DemSimulation& base = poly_settled();
  DemSettings settings = base.settings();
  settings.size_classes = classes;
  // skin_pm: > 0 in pm, 0 the engine's default, -1 the default before size classes (0.2 r_min).
  const auto& r = base.particles().radius;
  settings.skin = skin_pm >= 0 ? skin_pm * 1e-12 : 0.2 * *std::min_element(r.begin(), r.end());
  slot = std::make_unique<DemSimulation>(base.box(), base.particles(), Groups{}, settings);
  slot->run(kPolyWarmUpSteps);
  return *slot;
}

void BM_StepPolydisperse(benchmark::State& state) {
  exec::set_threads(static_cast<int>(state.range(0)));
  DemSimulation& sim = poly_system(static_cast<int>(state.range(1)), static_cast<int>(state.range(2)));
  const int n = static_cast<int>(sim.particles().size());
  const PassTimes t0 = sim.times();
  for (auto _ : state) {
    sim.step();
  }
  const PassTimes& t1 = sim.times();
  const double total = (t1.neighbours - t0.neighbours) + (t1.contact - t0.contact) +
                       (t1.integration - t0.integration) + (t1.other - t0.other);
  state.SetItemsProcessed(state.iterations() * n);
  state.counters["N"] = n;
  state.counters["rebuilds_per_1k_steps"] =
      1000.0 * static_cast<double>(t1.rebuilds - t0.rebuilds) / static_cast<double>(state.iterations());
  state.counters["rebuild_share"] = total > 0 ? (t1.neighbours - t0.neighbours) / total : 0.0;
  state.counters["candidates_per_particle"] = static_cast<double>(sim.neighbors().candidates()) / n;
  state.counters["entries_per_particle"] = static_cast<double>(sim.neighbors().entries()) / n;
  state.counters["size_classes"] = sim.neighbors().size_classes().count;
  state.counters["skin_nm"] = sim.skin() * 1e9;
  state.counters["bytes_per_particle"] = sim.bytes_per_particle();
  // Where they go: particle columns, list (with its cells), history, and the contact pass's own (B_other).
  const Footprint f = footprint(static_cast<std::size_t>(n), sim.neighbors(), sim.history());
  state.counters["B_particles"] = f.particles;
  state.counters["B_list"] = f.list;
  state.counters["B_history"] = f.history;
  state.counters["B_other"] = sim.bytes_per_particle() - f.total();
  if (first_non_finite(std::as_const(sim).particles()) >= 0) state.SkipWithError("the simulation blew up");
}

// After (size classes, default skin) and before (one grid, skin 0.2 r_min), on 1 and 2 threads; and each
// change alone on 1 thread.
BENCHMARK(BM_StepPolydisperse)
    ->ArgNames({"threads", "classes", "skin_pm"})
    ->Args({1, SizeClasses::kMax, 0})
    ->Args({2, SizeClasses::kMax, 0})
    ->Args({1, 1, -1})
    ->Args({2, 1, -1})
    ->Args({1, SizeClasses::kMax, -1})
    ->Args({1, 1, 0})
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);

// The sizes (FCC boxes of 4 c^3 particles): N = 4,000, 32,000 and 256,000, and for the whole step also 1,048,576 (the size at which the
// cost per particle-step should still be that of 32,000). DEBRIS_BENCH_SIZES (comma-separated particle
// counts of the form 4 c^3) replaces them for every benchmark: bench/gpu_check.sh runs 256,000 to 16,384,000.
std::vector<int> bench_sizes(bool whole_step) {
  std::vector<int> sizes{4000, 32000, 256000};
  if (whole_step) sizes.push_back(1048576);  // 4 x 64^3: the FCC box holds 4 c^3 particles
  return env_int_list("DEBRIS_BENCH_SIZES", 1, 100000000, sizes, "particle counts");
}

void size_args(benchmark::internal::Benchmark* b, bool whole_step) {
  b->ArgNames({"N", "threads"});
  for (int n : bench_sizes(whole_step))
    for (int t : {1, 2}) b->Args({n, t});
  b->UseRealTime();
  b->Unit(benchmark::kMillisecond);
}
void dem_args(benchmark::internal::Benchmark* b) { size_args(b, false); }
void step_args(benchmark::internal::Benchmark* b) { size_args(b, true); }

BENCHMARK(BM_Binning)->Apply(dem_args);
BENCHMARK(BM_NeighborBuild)->Apply(dem_args);
BENCHMARK(BM_CohesivePass)->Apply(dem_args);
BENCHMARK(BM_CohesivePassFullList)->Apply(dem_args);
BENCHMARK(BM_Step)->Apply(step_args);
BENCHMARK(BM_StepWithEnergy)->Apply(step_args);
BENCHMARK(BM_Rebuild)->Apply(dem_args);

}  // namespace
}  // namespace debris
