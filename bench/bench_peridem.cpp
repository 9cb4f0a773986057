// Google Benchmark suite of the PeriDEM passes on the paper's 502-particle compressive test (paper B,
// section 4.4), loaded from its own PeriDEM deck scenarios/peridem/data/compressive_n500/input_0.yaml:
// 366 circles and 136 hexagons (meshes mesh_particle_{1,2}_0.msh, R_ref = the zones' Parameters[0],
// placed from particle_locations_0.csv), the U-shaped container and the top plate as meshed walls (placed
// as is; the plate moves at the deck's linear Displacement_BC rate), 62,994 nodes; materials, contact,
// gravity and time step (Final_Time / Time_Steps) from the deck. The deck's 2D PDState is run with debris's
// plane-strain constants (kernels/peridem/pd_material.hpp); its Kn equals eq 36, which debris computes itself.
//
//   BM_PdBondPasses        pd_bond_step: break (eq 11) + dilatation (eq 34) + force (eq 33)   items = nodes
//   BM_PdContactPass       pd_contact_pass: node pairs (eqs 16-20) + grain centres + damping (eqs 26-30)
//   BM_PdContactListBuild  PdContactList::build (cells, full rows with self-contact, grain-pair slots)
//   BM_PdPenetrationCheck  the runner's every-step penetration check (a max reduction over the contact list)
//   BM_PdStep              PeridemSimulation::step(): integrate, list check/rebuild, forces, everything
//   BM_PdStepTiled         the same on the deck tiled k x k times side by side (each tile its own grains,
//                          container and lid, 1 mm apart): k = 2 by default (251,976 nodes);
//                          DEBRIS_PD_TILES=k1,k2,... chooses (bench/gpu_check.sh: 4 and 8, i.e. 1.0 M and
//                          4.0 M nodes, the device goal's "several million")
//
// items_per_second is node-steps per second (one item = one node through the pass once). Arguments:
// threads (exec::set_threads); for the contact benchmarks also packed (below). Real time throughout
// (OpenMP workers are not the benchmark thread).
//
// Initial state. The deck's grains start at rest, their bounding circles 0.11 mm apart at the closest (no
// node pair is closer than R_c = 0.12 mm) and the lowest ones 0.5 mm above the container's floor; falling
// together under g = 10 m/s^2, they reach it after 10 ms, 100,000 steps of 0.1 us, which a benchmark cannot
// wait for. The fixture runs kWarmUpSteps steps (the deck's own 100) and measures that state as is
// (packed = 0): no node pair touches and the contact rows are nearly empty, so the contact benchmarks also
// run on a jammed packing of the deck's circles (packed = 1, packed_system below) where each inner grain
// touches its six neighbours. The counters say which is which: touching_pairs, contact_entries_per_node.
//
// Data directory: $DEBRIS_PERIDEM_DECK if set, else the source tree's copy.
#include <benchmark/benchmark.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "bench/bench_env.hpp"
#include "core/bond_list.hpp"
#include "core/error.hpp"
#include "core/exec.hpp"
#include "scenarios/common/peridem/grain_placement.hpp"
#include "core/io/gmsh_msh.hpp"
#include "core/io/grain_csv.hpp"
#include "core/pd_contact_list.hpp"
#include "core/pd_nodes.hpp"
#include "kernels/peridem/pd_bond_passes.hpp"
#include "kernels/peridem/pd_contact.hpp"
#include "scenarios/common/peridem/peridem_simulation.hpp"

#ifndef DEBRIS_SOURCE_DIR
#define DEBRIS_SOURCE_DIR "."
#endif

namespace debris {
namespace {

constexpr long kWarmUpSteps = 100;

// ---------------------------------------------------------------------------------------------------------
// The PeriDEM deck (only what the compressive decks use; anything else is an InputError naming the key).

YAML::Node need(const YAML::Node& parent, const std::string& key, const std::string& path) {
  const YAML::Node n = parent[key];
  if (!n) throw input_error(path + "." + key, "(missing)", "the PeriDEM deck must give it");
  return n;
}

double need_double(const YAML::Node& parent, const std::string& key, const std::string& path) {
  return need(parent, key, path).as<double>();
}

struct PeridemDeck {
  PdNodes nodes;
  PdGrains grains;
  std::vector<PdMaterial> materials;       // one per zone
  std::vector<PdContactSettings> contact;  // zones x zones
  PeridemSettings settings;
  double deck_kn = 0;  // the deck's Kn of Zone_11 (eq 36 as PeriDEM computed it)
  long deck_steps = 0;
  std::vector<ReferenceGrain> references;  // the particle zones' reference grains
};

/// The deck, or with tiles_per_side = k > 1 the deck k x k times side by side: every tile the deck's grains
/// and walls shifted by whole multiples of its extent plus 1 mm, the walls' prescribed motion repeated.
PeridemDeck load_peridem_deck(const std::string& dir, int tiles_per_side = 1) {
  const std::string file = dir + "/input_0.yaml";
  const YAML::Node deck = YAML::LoadFile(file);
  PeridemDeck d;
  const YAML::Node model = need(deck, "Model", file);
  const int dimension = need(model, "Dimension", "Model").as<int>();
  const double final_time = need_double(model, "Final_Time", "Model");
  d.deck_steps = need(model, "Time_Steps", "Model").as<long>();
  d.settings.time_step = final_time / static_cast<double>(d.deck_steps);
  const int zones = need(need(deck, "Zone", file), "Zones", "Zone").as<int>();

  // Materials per zone (PDState, linear influence function).
  const YAML::Node mat = need(deck, "Material", file);
  for (int z = 1; z <= zones; ++z) {
    const std::string key = "Zone_" + std::to_string(z);
    const YAML::Node m = need(mat, key, "Material");
    const std::string type = need(m, "Type", "Material." + key).as<std::string>();
    if (type != "PDState") throw input_error("Material." + key + ".Type", type, "only PDState is supported");
    PdMaterial pm;
    pm.density = need_double(m, "Density", "Material." + key);
    pm.bulk_modulus = need_double(m, "K", "Material." + key);
    pm.shear_modulus = need_double(m, "G", "Material." + key);
    pm.fracture_energy = need_double(m, "Gc", "Material." + key);
    pm.horizon = need_double(m, "Horizon", "Material." + key);
    pm.dimension = dimension;
    d.materials.push_back(pm);
  }

  // Contact per zone pair (Zone_ab, a <= b), symmetric.
  const YAML::Node con = need(deck, "Contact", file);
  d.contact.resize(static_cast<std::size_t>(zones * zones));
  for (int a = 1; a <= zones; ++a)
    for (int b = a; b <= zones; ++b) {
      const std::string key = "Zone_" + std::to_string(a) + std::to_string(b);
      const YAML::Node c = need(con, key, "Contact");
      const std::string path = "Contact." + key;
      PdContactSettings s;
      s.contact_radius_factor = need_double(c, "Contact_Radius_Factor", path);
      s.restitution = need_double(c, "Epsilon", path);
      s.damping_factor = need_double(c, "Beta_n_Factor", path);
      s.stiffness_factor = need_double(c, "Kn_Factor", path);
      s.friction = need(c, "Friction_On", path).as<bool>() ? need_double(c, "Friction_Coeff", path) : 0.0;
      if (a == 1 && b == 1) d.deck_kn = need_double(c, "Kn", path);
      d.contact[static_cast<std::size_t>((a - 1) * zones + (b - 1))] = s;
      d.contact[static_cast<std::size_t>((b - 1) * zones + (a - 1))] = s;
    }

  // Zones: particle zones get a reference mesh (R_ref = Parameters[0]), wall zones are meshes placed as is.
  const YAML::Node zone = need(deck, "Zone", file), particle = need(deck, "Particle", file);
  const YAML::Node mesh = need(deck, "Mesh", file);
  std::vector<ReferenceGrain> references;
  std::vector<int> wall_zones;
  for (int z = 1; z <= zones; ++z) {
    const std::string key = "Zone_" + std::to_string(z);
    const bool is_wall = need(need(zone, key, "Zone"), "Is_Wall", "Zone." + key).as<bool>();
    std::string mesh_file = need(need(mesh, key, "Mesh"), "File", "Mesh." + key).as<std::string>();
    while (!mesh_file.empty() && mesh_file.back() == ' ') mesh_file.pop_back();
    if (is_wall) {
      wall_zones.push_back(z);
      continue;
    }
    if (static_cast<int>(references.size()) != z - 1)
      throw input_error("Zone." + key + ".Is_Wall", "false", "particle zones must come before wall zones");
    const double r_ref = need(need(particle, key, "Particle"), "Parameters", "Particle." + key)[0].as<double>();
    references.push_back(make_reference_grain(read_gmsh_msh(dir + "/" + mesh_file), r_ref, z - 1, "Mesh." + key));
  }
  const YAML::Node gen = need(deck, "Particle_Generation", file);
  const std::vector<GrainRecord> records =
      read_grain_csv(dir + "/" + need(gen, "From_File", "Particle_Generation").as<std::string>());
  std::vector<SimplexMesh> walls;
  for (int z : wall_zones) {
    const std::string key = "Zone_" + std::to_string(z);
    std::string mesh_file = mesh[key]["File"].as<std::string>();
    while (!mesh_file.empty() && mesh_file.back() == ' ') mesh_file.pop_back();
    walls.push_back(read_gmsh_msh(dir + "/" + mesh_file));
  }
  // The tile pitch: the deck's extent (grains' bounding circles and wall nodes) plus 1 mm, far beyond the
  // contact cutoff, so tiles never touch.
  Vec3 lo{1e300, 1e300, 0}, hi{-1e300, -1e300, 0};
  auto extend = [&](double x, double y, double r) {
    lo.x = std::min(lo.x, x - r), lo.y = std::min(lo.y, y - r), hi.x = std::max(hi.x, x + r), hi.y = std::max(hi.y, y + r);
  };
  for (const GrainRecord& g : records) extend(g.x, g.y, g.radius);
  for (const SimplexMesh& w : walls)
    for (const Vec3& v : w.nodes) extend(v.x, v.y, 0.0);
  const double pitch_x = hi.x - lo.x + 1e-3, pitch_y = hi.y - lo.y + 1e-3;
  const int tiles = tiles_per_side * tiles_per_side;
  std::vector<GrainRecord> all;
  all.reserve(records.size() * static_cast<std::size_t>(tiles));
  for (int t = 0; t < tiles; ++t)
    for (GrainRecord g : records) {
      g.x += (t % tiles_per_side) * pitch_x, g.y += (t / tiles_per_side) * pitch_y;
      all.push_back(g);
    }
  place_grains(references, all, d.nodes, d.grains);
  d.references = references;
  const int particle_grains = static_cast<int>(d.grains.size());
  for (int t = 0; t < tiles; ++t)
    for (std::size_t w = 0; w < walls.size(); ++w) {
      SimplexMesh m = walls[w];
      for (Vec3& v : m.nodes) v.x += (t % tiles_per_side) * pitch_x, v.y += (t / tiles_per_side) * pitch_y;
      const std::string key = "Zone_" + std::to_string(wall_zones[w]);
      append_wall(m, wall_zones[w] - 1, d.nodes, d.grains, "Mesh." + key);
    }
  // The deck's grain index of wall w is records.size() + w; tile t's copy is particle_grains + t walls + w.
  const int deck_particles = static_cast<int>(records.size()), deck_walls = static_cast<int>(walls.size());

  // Gravity and the walls' prescribed motion (Displacement_BC: zero displacement, or linear in time u = a t,
  // a velocity a along the listed directions 1, 2, 3).
  const YAML::Node g = need(need(deck, "Force_BC", file), "Gravity", "Force_BC");
  d.settings.gravity = Vec3{g[0].as<double>(), g[1].as<double>(), g[2].as<double>()};
  const YAML::Node bc = need(deck, "Displacement_BC", file);
  const int sets = need(bc, "Sets", "Displacement_BC").as<int>();
  for (int s = 1; s <= sets; ++s) {
    const std::string path = "Displacement_BC.Set_" + std::to_string(s);
    const YAML::Node set = need(bc, "Set_" + std::to_string(s), "Displacement_BC");
    const bool zero = set["Zero_Displacement"] && set["Zero_Displacement"].as<bool>();
    double rate = 0.0;
    if (!zero) {
      const std::string type =
          need(need(set, "Time_Function", path), "Type", path + ".Time_Function").as<std::string>();
      if (type != "linear") throw input_error(path + ".Time_Function.Type", type, "only linear (or zero) is supported");
      rate = need(set["Time_Function"], "Parameters", path + ".Time_Function")[0].as<double>();
    }
    for (const YAML::Node& id : need(set, "Particle_List", path)) {
      const int gi = id.as<int>();
      if (gi < deck_particles || gi >= deck_particles + deck_walls)
        throw input_error(path + ".Particle_List", std::to_string(gi), "only walls may be prescribed here");
      for (const YAML::Node& dir_node : need(set, "Direction", path)) {
        const int axis = dir_node.as<int>();
        if (axis < 1 || axis > 3) throw input_error(path + ".Direction", std::to_string(axis), "must be 1, 2 or 3");
        auto& v = axis == 1 ? d.grains.wall_vx : axis == 2 ? d.grains.wall_vy : d.grains.wall_vz;
        for (int t = 0; t < tiles; ++t)
          v[static_cast<std::size_t>(particle_grains + t * deck_walls + (gi - deck_particles))] = rate;
      }
    }
  }
  d.settings.damping = PdDamping::grain_centres;  // the paper's choice (eqs 26-30)
  return d;
}

std::string deck_dir() {
  const char* env = std::getenv("DEBRIS_PERIDEM_DECK");
  return env ? std::string(env) : std::string(DEBRIS_SOURCE_DIR) + "/scenarios/peridem/data/compressive_n500";
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
  double deck_kn = 0;
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

/// The deck as it runs (k x k tiles of it for k > 1): kWarmUpSteps steps after set-up.
PdSystem& deck_system(int tiles_per_side = 1) {
  static std::map<int, std::unique_ptr<PdSystem>> cache;
  auto& cached = cache[tiles_per_side];
  if (cached) return *cached;
  auto s = std::make_unique<PdSystem>();
  PeridemDeck d = load_peridem_deck(deck_dir(), tiles_per_side);
  s->deck_kn = d.deck_kn;
  s->sim =
      std::make_unique<PeridemSimulation>(std::move(d.nodes), std::move(d.grains), d.materials, d.contact, d.settings);
  s->sim->run(kWarmUpSteps);
  take_snapshot(*s);
  cached = std::move(s);
  return *cached;
}

/// A jammed packing for the contact benchmarks (the deck's own state has no touching pair): 500 circles of
/// the deck's zone 1 mesh at R = R_ref on a triangular lattice, random orientations, neighbouring circles
/// R_c / 2 apart, so that every grain touches its six neighbours through a few node pairs each. The deck's
/// materials and contact settings; a snapshot at set-up (no steps: the overlaps are not in equilibrium).
PdSystem& packed_system() {
  static std::unique_ptr<PdSystem> cached;
  if (cached) return *cached;
  auto s = std::make_unique<PdSystem>();
  PeridemDeck d = load_peridem_deck(deck_dir());
  s->deck_kn = d.deck_kn;
  const ReferenceGrain& ref = d.references.at(0);
  PdNodes one;
  PdGrains one_grain;
  place_grain(ref, GrainRecord{0, 0.0, 0.0, 0.0, ref.radius, 0.0}, one, one_grain);
  const double rc = d.contact[0].contact_radius_factor * pd_mesh_size(one, one_grain);  // R_c = factor h (eq 35)
  const double spacing = 2.0 * ref.radius + 0.5 * rc;
  std::mt19937_64 rng(20261123);
  std::uniform_real_distribution<double> angle(0.0, 6.283185307179586);
  std::vector<GrainRecord> records;
  for (int iy = 0; iy < 20; ++iy)
    for (int ix = 0; ix < 25; ++ix)
      records.push_back(GrainRecord{0, (ix + 0.5 * (iy % 2)) * spacing, iy * spacing * 0.8660254037844386, 0.0,
                                    ref.radius, angle(rng)});
  PdNodes nodes;
  PdGrains grains;
  place_grains({ref}, records, nodes, grains);
  s->sim = std::make_unique<PeridemSimulation>(std::move(nodes), std::move(grains), d.materials, d.contact, d.settings);
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

// The bond list with the passes' scratch (node_factors).
double bond_bytes(const BondList& bonds) {
  return static_cast<double>(sizeof(int) * (bonds.offset.capacity() + bonds.partner.capacity()) +
                             sizeof(double) * (bonds.length0.capacity() + bonds.node_factors.capacity()) +
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
  state.counters["kn_over_deck"] = sim.contact_table().pair(0, 0).k_n / s.deck_kn;
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
