// Google Benchmark suite of the PeriDEM passes on the paper's 502-particle compressive test (paper B,
// section 4.4), built by debris_peridem's own input reader (read_peridem_input) from the shipped input
// scenarios/peridem/compressive_n500.yaml, so the benchmark runs the system `debris_peridem -i` runs: the
// PeriDEM code's deck data/compressive_n500 (366 circles and 136 hexagons from particle_locations_0.csv,
// the U-shaped container and the top plate as meshed walls, the plate moving down at 0.06 m/s), 62,994
// nodes; materials, contact, gravity and time step as that input gives them.
//
//   BM_PdBondPasses        pd_bond_step: break (eq 11) + dilatation (eq 34) + force (eq 33)   items = nodes
//   BM_PdContactPass       pd_contact_pass: node pairs (eqs 16-20) + grain centres + damping (eqs 26-30)
//   BM_PdContactListBuild  PdContactList::build (cells, full rows with self-contact, grain-pair slots)
//   BM_PdPenetrationCheck  the runner's every-step penetration check (a max reduction over the contact list)
//   BM_PdStep              PeridemSimulation::step(): integrate, list check/rebuild, forces, everything
//   BM_PdStepTiled         the same on the input's system tiled k x k times side by side (each tile its own
//                          grains, container and lid, 1 mm apart): k = 2 by default (251,976 nodes);
//                          DEBRIS_PD_TILES=k1,k2,... chooses (bench/gpu_check.sh: 4 and 8, i.e. 1.0 M and
//                          4.0 M nodes, the device goal's "several million")
//
// items_per_second is node-steps per second (one item = one node through the pass once). Arguments:
// threads (exec::set_threads); for the contact benchmarks also packed (below). Real time throughout
// (OpenMP workers are not the benchmark thread).
//
// Initial state. The input's grains start at rest, their bounding circles 0.11 mm apart at the closest (no
// node pair is closer than R_c = 0.12 mm) and the lowest ones 0.5 mm above the container's floor; falling
// together under g = 10 m/s^2, they reach it after 10 ms, 100,000 steps of 0.1 us, which a benchmark cannot
// wait for. The fixture runs kWarmUpSteps steps (the input's and the deck's 100) and measures that state as is
// (packed = 0): no node pair touches and the contact rows are nearly empty, so the contact benchmarks also
// run on a jammed packing of the deck's circles (packed = 1, packed_system below) where each inner grain
// touches its six neighbours. The counters say which is which: touching_pairs, contact_entries_per_node.
//
// Input file: $DEBRIS_PERIDEM_INPUT if set, else the source tree's scenarios/peridem/compressive_n500.yaml.
#include <benchmark/benchmark.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <map>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "bench/bench_env.hpp"
#include "bench/pd_tiles.hpp"
#include "core/bond_list.hpp"
#include "core/error.hpp"
#include "core/exec.hpp"
#include "core/pd_contact_list.hpp"
#include "core/pd_nodes.hpp"
#include "kernels/peridem/pd_bond_passes.hpp"
#include "kernels/peridem/pd_contact.hpp"
#include "scenarios/common/peridem/peridem_input.hpp"
#include "scenarios/common/peridem/peridem_simulation.hpp"

#ifndef DEBRIS_SOURCE_DIR
#define DEBRIS_SOURCE_DIR "."
#endif

namespace debris {
namespace {

constexpr long kWarmUpSteps = 100;

// ---------------------------------------------------------------------------------------------------------
// The input, read as debris_peridem reads it.

std::string input_file() {
  const char* env = std::getenv("DEBRIS_PERIDEM_INPUT");
  return env ? std::string(env) : std::string(DEBRIS_SOURCE_DIR) + "/scenarios/peridem/compressive_n500.yaml";
}

/// The PeriDEM deck's own K_n of zones 1-1 (eq 36 as the authors' code computed it), which debris computes
/// itself: the counter kn_over_deck compares the two.
double deck_kn() {
  const std::string deck = std::string(DEBRIS_SOURCE_DIR) + "/scenarios/peridem/data/compressive_n500/input_0.yaml";
  return YAML::LoadFile(deck)["Contact"]["Zone_11"]["Kn"].as<double>();
}

// ---------------------------------------------------------------------------------------------------------
// The systems: the engine (BM_PdStep keeps stepping the deck's) and a snapshot of it for the pass benchmarks.

struct PdSystem {
  std::unique_ptr<PeridemSimulation> sim;
  PdNodes nodes;
  PdGrains grains;
  BondList bonds;
  PdContactList list, built;
  PdContactWork work;
  PdLpsTable lps;
  PdContactTable table;
  PdDamping damping = PdDamping::grain_centres;
  double dt = 0, cutoff = 0, skin = 0;
  long touching = 0;
};

void take_snapshot(PdSystem& s) {
  const PeridemSimulation& sim = *s.sim;
  if (!sim.health_check().empty()) throw std::runtime_error(sim.health_check());
  s.nodes = sim.nodes();
  s.grains = sim.grains();
  s.bonds = sim.bonds();
  s.list = sim.contacts();
  s.table = sim.contact_table();
  s.lps.clear();
  for (const PdMaterial& m : sim.materials()) s.lps.push_back(PdLpsConstants::from(m));
  s.damping = sim.settings().damping;
  s.dt = sim.dt();
  s.cutoff = s.list.cutoff();
  s.skin = s.list.skin();
  s.touching = sim.touching_pairs();
  // Offload builds: a copy's device buffers start empty, and the pass benchmarks run on these copies; the
  // contact list is built again from them, on the device (a build at the snapshot's positions, which
  // BM_PdContactListBuild compares it with). No-ops in host builds.
  to_device(s.nodes);
  to_device(s.grains);
  to_device(s.bonds);
  exec::to_device(s.lps);
  exec::to_device(s.table.pairs);
  if constexpr (exec::offload_build()) s.list.build(s.nodes, s.grains, s.bonds, s.cutoff, s.skin);
}

/// The input's system as it runs (k x k tiles of it for k > 1): kWarmUpSteps steps after set-up.
PdSystem& deck_system(int tiles_per_side = 1) {
  static std::map<int, std::unique_ptr<PdSystem>> cache;
  auto& cached = cache[tiles_per_side];
  if (cached) return *cached;
  auto s = std::make_unique<PdSystem>();
  PeridemRunConfig cfg = read_peridem_input(input_file());
  tile_pd_system(cfg, tiles_per_side, tiles_per_side);
  s->sim = std::make_unique<PeridemSimulation>(std::move(cfg.nodes), std::move(cfg.grains), cfg.materials,
                                               cfg.contact, cfg.settings);
  s->sim->run(kWarmUpSteps);
  take_snapshot(*s);
  cached = std::move(s);
  return *cached;
}

/// A debris_peridem input for grains of the compressive input's circle mesh (its material M1, contact and
/// gravity, no walls), listed one by one.
std::string circles_input(const std::vector<Vec3>& centres, const std::vector<double>& rotations) {
  const std::string data = std::string(DEBRIS_SOURCE_DIR) + "/scenarios/peridem/data/compressive_n500";
  std::string text = R"(dimension: 2
materials:
  M1: {density: 1200 kg/m^3, bulk_modulus: 0.0216 GPa, shear_modulus: 0.01296 GPa, fracture_energy: 50 J/m^2,
       horizon: 0.6 mm}
shapes:
  circle: {type: mesh_file, file: )" + data + R"(/mesh_particle_1_0.msh, reference_radius: 1 mm}
contact: {contact_radius_factor: 0.95, restitution: 0.95, damping_factor: 100, friction: 0, damping: grain_centres}
gravity: [0, -10 m/s^2, 0]
run: {time_step: 0.1 us, steps: 1}
grains:
)";
  std::ostringstream grains;
  grains.precision(17);
  for (std::size_t g = 0; g < centres.size(); ++g)
    grains << "  - {shape: circle, material: M1, radius: 1 mm, centre: [" << centres[g].x << " m, " << centres[g].y
           << " m, 0 m], rotation: " << rotations[g] << "}\n";
  return text + grains.str();
}

/// A jammed packing for the contact benchmarks (the input's own state has no touching pair): 500 circles of
/// its circle mesh at R = R_ref on a triangular lattice, random orientations, neighbouring circles R_c / 2
/// apart, so that every grain touches its six neighbours through a few node pairs each. A snapshot at set-up
/// (no steps: the overlaps are not in equilibrium).
PdSystem& packed_system() {
  static std::unique_ptr<PdSystem> cached;
  if (cached) return *cached;
  auto s = std::make_unique<PdSystem>();
  const double radius = 1e-3;
  const PeridemRunConfig one = read_peridem_input_text(circles_input({Vec3{}}, {0.0}), "packed circle", "");
  const double rc = one.contact[0].contact_radius_factor * pd_mesh_size(one.nodes, one.grains);  // R_c (eq 35)
  const double spacing = 2.0 * radius + 0.5 * rc;
  std::mt19937_64 rng(20261123);
  std::uniform_real_distribution<double> angle(0.0, 6.283185307179586);
  std::vector<Vec3> centres;
  std::vector<double> rotations;
  for (int iy = 0; iy < 20; ++iy)
    for (int ix = 0; ix < 25; ++ix) {
      centres.push_back(Vec3{(ix + 0.5 * (iy % 2)) * spacing, iy * spacing * 0.8660254037844386, 0.0});
      rotations.push_back(angle(rng));
    }
  PeridemRunConfig cfg = read_peridem_input_text(circles_input(centres, rotations), "packed circles", "");
  s->sim = std::make_unique<PeridemSimulation>(std::move(cfg.nodes), std::move(cfg.grains), cfg.materials,
                                               cfg.contact, cfg.settings);
  take_snapshot(*s);
  cached = std::move(s);
  return *cached;
}

PdSystem& system_for(benchmark::State& state) { return state.range(0) == 0 ? deck_system() : packed_system(); }

double node_bytes(const PdNodes& nodes) {
  // Every column of PdNodes, per node.
  double b = 0;
  PdNodes& mutable_nodes = const_cast<PdNodes&>(nodes);
  mutable_nodes.for_each_column([&](const char*, auto& column) { b += sizeof(column[0]); });
  return b;
}

// The bond list (with each entry's weight J V_j) and the passes' scratch (node_factors, and bond_length where
// pd_bond_step keeps |y|).
double bond_bytes(const BondList& bonds) {
  return static_cast<double>(sizeof(int) * (bonds.offset.capacity() + bonds.partner.capacity()) +
                             sizeof(double) * (bonds.length0.capacity() + bonds.weight.capacity() +
                                               bonds.node_factors.capacity() + bonds.bond_length.capacity()) +
                             bonds.broken.capacity());
}

void set_counters(benchmark::State& state, const PdSystem& s, bool with_bonds, bool with_contacts) {
  const double n = static_cast<double>(s.nodes.size());
  double bytes = node_bytes(s.nodes);
  state.counters["B_nodes"] = bytes;
  if (with_bonds) {
    state.counters["B_bonds"] = bond_bytes(s.bonds) / n;
    bytes += bond_bytes(s.bonds) / n;
  }
  if (with_contacts) {
    state.counters["B_contacts"] = static_cast<double>(s.list.bytes()) / n;
    bytes += static_cast<double>(s.list.bytes()) / n;
  }
  state.counters["bytes_per_node"] = bytes;
  state.counters["nodes"] = n;
  state.counters["bond_entries_per_node"] = static_cast<double>(s.bonds.entries()) / n;
  state.counters["contact_entries_per_node"] = static_cast<double>(s.list.entries()) / n;
  state.counters["touching_pairs"] = static_cast<double>(s.touching);
}

void BM_PdBondPasses(benchmark::State& state) {
  exec::set_threads(static_cast<int>(state.range(0)));
  PdSystem& s = deck_system();
  for (auto _ : state) {
    pd_bond_step(s.lps, s.grains, s.bonds, s.nodes);
    benchmark::DoNotOptimize(s.nodes.fx.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * static_cast<long long>(s.nodes.size()));
  set_counters(state, s, true, false);
}

void BM_PdContactPass(benchmark::State& state) {
  exec::set_threads(static_cast<int>(state.range(1)));
  PdSystem& s = system_for(state);
  for (auto _ : state) {
    pd_contact_pass(s.table, s.damping, s.nodes, s.grains, s.list, s.work, s.dt);
    benchmark::DoNotOptimize(s.nodes.fx.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * static_cast<long long>(s.nodes.size()));
  state.counters["pairs/s"] =
      benchmark::Counter(static_cast<double>(state.iterations()) * s.list.entries(), benchmark::Counter::kIsRate);
  set_counters(state, s, false, true);
}

// The penetration check the runner makes after every step (pd_deepest_penetration, a max reduction over the
// contact list), beside the contact pass over the same list: its cost per step.
void BM_PdPenetrationCheck(benchmark::State& state) {
  exec::set_threads(static_cast<int>(state.range(1)));
  PdSystem& s = system_for(state);
  double deepest = 0;
  for (auto _ : state) {
    deepest = pd_deepest_penetration(s.table, s.nodes, s.grains, s.list);
    benchmark::DoNotOptimize(deepest);
  }
  state.SetItemsProcessed(state.iterations() * static_cast<long long>(s.nodes.size()));
  state.counters["deepest"] = deepest;
  set_counters(state, s, false, true);
}

void BM_PdContactListBuild(benchmark::State& state) {
  exec::set_threads(static_cast<int>(state.range(1)));
  PdSystem& s = system_for(state);
  for (auto _ : state) {
    s.built.build(s.nodes, s.grains, s.bonds, s.cutoff, s.skin);
    benchmark::DoNotOptimize(s.built.index().data());
    benchmark::ClobberMemory();
  }
  if (s.built.entries() != s.list.entries()) state.SkipWithError("the rebuilt list differs from the snapshot's");
  state.SetItemsProcessed(state.iterations() * static_cast<long long>(s.nodes.size()));
  set_counters(state, s, true, true);
}

/// Steps s's engine for the benchmark's iterations and sets the counters both step benchmarks report.
void time_steps(benchmark::State& state, PdSystem& s) {
  PeridemSimulation& sim = *s.sim;
  const long rebuilds0 = sim.contact_rebuilds(), steps0 = sim.step_count();
  exec::reset_transfer_stats();
  const auto t0 = std::chrono::steady_clock::now();
  for (auto _ : state) sim.step();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const exec::TransferStats moved = exec::transfer_stats();
  const long steps = sim.step_count() - steps0;
  // node_count(), not nodes().size(): the non-const nodes() would mark the host copy edited, and the next
  // run's first step would send every column to the device (offload builds).
  state.SetItemsProcessed(state.iterations() * static_cast<long long>(sim.node_count()));
  // Host <-> device transfers inside the timed steps (offload builds; zero in host builds).
  state.counters["transfer_bytes_per_step"] =
      (moved.to_host_bytes + moved.to_device_bytes) / static_cast<double>(steps > 0 ? steps : 1);
  state.counters["transfer_share"] = seconds > 0 ? (moved.to_host_seconds + moved.to_device_seconds) / seconds : 0.0;
  state.counters["rebuilds_per_1k_steps"] =
      1000.0 * static_cast<double>(sim.contact_rebuilds() - rebuilds0) / static_cast<double>(steps > 0 ? steps : 1);
  state.counters["steps_since_setup"] = static_cast<double>(sim.step_count());
  state.counters["broken_bonds"] = static_cast<double>(sim.broken_bonds());
  state.counters["dt_over_stable"] = sim.dt() / sim.stable_time_step();
  state.counters["kn_over_deck"] = sim.contact_table().pair(0, 0).k_n / deck_kn();
  if (!sim.health_check().empty()) state.SkipWithError("the simulation blew up");
  set_counters(state, s, true, true);
}

void BM_PdStep(benchmark::State& state) {
  exec::set_threads(static_cast<int>(state.range(0)));
  time_steps(state, deck_system());
}

void BM_PdStepTiled(benchmark::State& state) {
  exec::set_threads(static_cast<int>(state.range(1)));
  PdSystem& s = deck_system(static_cast<int>(state.range(0)));
  time_steps(state, s);
  state.counters["tiles"] = static_cast<double>(state.range(0) * state.range(0));
}

void pd_args(benchmark::internal::Benchmark* b) {
  b->ArgNames({"threads"});
  for (int t : {1, 2}) b->Args({t});
  b->UseRealTime();
  b->Unit(benchmark::kMillisecond);
}

// Tiles per side: 2 (4 tiles, 251,976 nodes) unless DEBRIS_PD_TILES=k1,k2,... says otherwise.
void tiled_args(benchmark::internal::Benchmark* b) {
  const std::vector<int> sides = env_int_list("DEBRIS_PD_TILES", 1, 64, {2}, "tiles per side");
  b->ArgNames({"tiles_per_side", "threads"});
  for (int k : sides)
    for (int t : {1, 2}) b->Args({k, t});
  b->UseRealTime();
  b->Unit(benchmark::kMillisecond);
}

// state 0: the deck after its warm-up; 1: the jammed packing.
void contact_args(benchmark::internal::Benchmark* b) {
  b->ArgNames({"packed", "threads"});
  for (int packed : {0, 1})
    for (int t : {1, 2}) b->Args({packed, t});
  b->UseRealTime();
  b->Unit(benchmark::kMillisecond);
}

BENCHMARK(BM_PdBondPasses)->Apply(pd_args);
BENCHMARK(BM_PdContactPass)->Apply(contact_args);
BENCHMARK(BM_PdPenetrationCheck)->Apply(contact_args);
BENCHMARK(BM_PdContactListBuild)->Apply(contact_args);
BENCHMARK(BM_PdStep)->Apply(pd_args);
BENCHMARK(BM_PdStepTiled)->Apply(tiled_args);

}  // namespace
}  // namespace debris
