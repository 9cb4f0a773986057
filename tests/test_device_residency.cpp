// Device residency, tested where it can fail: on a device with its own memory (the hostdevice build: clang's
// OpenMP offload to the host CPU as a separate device; or an nvptx build on a GPU) a kernel reads the
// device's copy of every array, so a missing to_device or to_host gives a stale value. These tests skip in
// host builds and on GCC's host fallback (an nvptx build without a GPU), where target regions share the
// host's memory and no transfer can be missing.
//  - a canary that fails unless the device really has its own memory;
//  - the residency check aborts on an array that was never entered;
//  - a DEM run on the device equals the same run on the initial device (host fallback, shared memory, where
//    no transfer can be missing), and so does the debris_dem executable's output (thermo rows, dump frames)
//    through the runner's transfer points;
//  - the same for PeriDEM: an impact that breaks bonds and rebuilds its contact list, run on the device and
//    on host fallback; a checkpoint written from the device's state restarts identically; and the
//    debris_peridem executable's thermo rows and trajectory frames (with a stage that places a wall and sets
//    it moving) equal host fallback's.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>
#include <type_traits>

#include "core/exec.hpp"
#include "core/io/hdf5_file.hpp"
#include "core/pd_contact_list.hpp"
#include "scenarios/common/dem/dem_simulation.hpp"
#include "scenarios/common/peridem/peridem_input.hpp"
#include "scenarios/common/peridem/peridem_simulation.hpp"
#include "tests/cli_helpers.hpp"
#include "tests/dem_samples.hpp"
#include "tests/pd_state_equality.hpp"

namespace debris {
namespace {

namespace fs = std::filesystem;

// A device with its own memory runs the kernels: the hostdevice build, or an nvptx build on a GPU.
bool device_with_own_memory() { return exec::offload_build() && exec::kernels_run_on_device(); }
constexpr const char* kNoDevice =
    "no device with its own memory here: a host build, or an offload build whose kernels fall back to the host";

// The words the startup line uses for such a device ("kernels run on GPU" or "... on the host CPU as a
// separate-memory device"), absent when they run on host threads.
std::string device_words() {
  return std::string(exec::offload_kind()) == "hostdevice" ? "separate-memory device" : "kernels run on GPU";
}

// The sum of v on the device.
double device_sum(const exec::DeviceVector<double>& v) {
  const double* a = v.data();
  const int n = static_cast<int>(v.size());
  double s = 0.0;
  DEBRIS_RESIDENT(a);
  DEBRIS_KERNEL_SUM(s)
  for (int i = 0; i < n; ++i) s += a[i];
  return s;
}

// Doubles every element on the device.
void device_double(exec::DeviceVector<double>& v) {
  double* a = v.data();
  const int n = static_cast<int>(v.size());
  DEBRIS_RESIDENT(a);
  DEBRIS_KERNEL
  for (int i = 0; i < n; ++i) a[i] *= 2.0;
}

TEST(DeviceResidency, SeparateMemoryCanary) {
  if (!device_with_own_memory()) GTEST_SKIP() << kNoDevice;
  ASSERT_TRUE(exec::kernels_run_on_device()) << "kernels fell back to the host: " << exec::startup_report();
  exec::DeviceVector<double> v(64, 1.0);
  exec::to_device(v);
  v[0] = 42.0;  // on the host only: the update is skipped on purpose
  EXPECT_EQ(device_sum(v), 64.0) << "the device saw a host write without to_device: it shares the host's memory";
  exec::to_device(v);
  EXPECT_EQ(device_sum(v), 105.0);
  device_double(v);
  EXPECT_EQ(v[1], 1.0) << "the host saw a device write without to_host";
  exec::to_host(v);
  EXPECT_EQ(v[0], 84.0);
  EXPECT_EQ(v[1], 2.0);
}

TEST(DeviceResidencyDeathTest, KernelOnAnArrayNeverEnteredAborts) {
  if (std::string(exec::offload_kind()) != "hostdevice" || !device_with_own_memory())
    GTEST_SKIP() << "the residency check (DEBRIS_CHECK_RESIDENCY) is compiled into hostdevice builds only";
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_DEATH(
      {
        std::vector<double> plain(16, 1.0);  // a plain vector: never on the device
        const double* a = plain.data();
        DEBRIS_RESIDENT(a);
      },
      "residency check failed at .*test_device_residency.cpp:[0-9]+: array 'a'");
  exec::DeviceVector<double> resident(16, 1.0);
  const double* b = resident.data();
  DEBRIS_RESIDENT(b);  // entered by its allocator: no abort
}

struct DemResult {
  Particles p;
  exec::DeviceVector<double> hx, hy, hz;
  Vec3 top_velocity, probe_displacement;
  CohesiveDiagnostics diag;
  long rebuilds = 0;
};

DemResult run_dem_model(long steps) {
  DemSimulation sim = test::sheared_dem_system();
  sim.run(steps);
  DemResult r;
  r.diag = sim.diagnostics();
  r.p = sim.particles();
  r.hx = sim.history().hx;
  r.hy = sim.history().hy;
  r.hz = sim.history().hz;
  r.top_velocity = sim.groups().list[0].velocity;
  r.probe_displacement = sim.groups().list[2].displacement;
  r.rebuilds = sim.times().rebuilds;
  return r;
}

// Runs f with the initial device (the host, shared memory) as the default device.
template <class F>
auto on_initial_device(F f) {
  const int device = exec::default_device();
  exec::set_default_device(exec::initial_device());
  auto r = f();
  exec::set_default_device(device);
  return r;
}

TEST(DeviceResidency, DemRunOnTheDeviceEqualsHostFallback) {
  if (!device_with_own_memory()) GTEST_SKIP() << kNoDevice;
  const long steps = 300;
  exec::reset_transfer_stats();
  const DemResult dev = run_dem_model(steps);
  const exec::TransferStats t = exec::transfer_stats();
  const DemResult host = on_initial_device([&] { return run_dem_model(steps); });
  ASSERT_GT(dev.rebuilds, 3) << "the run needs rebuilds (re-sort, carry-over) to test them";
  ASSERT_EQ(dev.p.size(), host.p.size());
  // The same compiler and flags for both: the same bits, storage order included.
  dev.p.for_each_column([&](const char* name, const auto& col) {
    host.p.for_each_column([&](const char* other, const auto& col_h) {
      if (std::string(name) != other) return;
      if constexpr (std::is_same_v<std::decay_t<decltype(col)>, std::decay_t<decltype(col_h)>>) {
        for (std::size_t i = 0; i < col.size(); ++i) ASSERT_EQ(col[i], col_h[i]) << name << "[" << i << "]";
      }
    });
  });
  EXPECT_EQ(dev.hx, host.hx);
  EXPECT_EQ(dev.hy, host.hy);
  EXPECT_EQ(dev.hz, host.hz);
  EXPECT_EQ(dev.top_velocity.x, host.top_velocity.x);
  EXPECT_EQ(dev.top_velocity.y, host.top_velocity.y);
  EXPECT_EQ(dev.probe_displacement.x, host.probe_displacement.x);
  EXPECT_DOUBLE_EQ(dev.diag.elastic_energy, host.diag.elastic_energy);
  EXPECT_EQ(dev.diag.max_overlap, host.diag.max_overlap);
  EXPECT_EQ(dev.diag.interacting_pairs, host.diag.interacting_pairs);
  // The state moved, and transfers happened on the device run only where named.
  EXPECT_GT(std::abs(dev.top_velocity.x), 1e-6);
  EXPECT_GT(t.to_device_calls, 0);
  std::printf("DEM %zu particles, %ld steps, %ld rebuilds: %ld transfers to the device (%.0f bytes), %ld to the host "
              "(%.0f bytes)\n",
              dev.p.size(), steps, dev.rebuilds, t.to_device_calls, t.to_device_bytes, t.to_host_calls,
              t.to_host_bytes);
}

// A DEM list build runs where the particles are: wrap, the canonical re-sort (the cell counting sort, the
// order by cell and id, the gather of every column), the neighbour search and its prefix sum, the
// history's carry-over. 60 rebuilds of the sheared block move no array through the named transfer points
// (only reductions' and scans' scalars), and the state after them equals host fallback's bit for bit.
// `wide`: a third of the free particles at 0.45 of the others' radius, two size classes, so each build also
// bins the classes and joins their grids on the device.
static void expect_dem_list_builds_move_only_scalars(bool wide) {
  const int builds = 60;
  const auto run = [&](exec::TransferStats* counted) {
    DemSimulation sim = test::sheared_dem_system(PairPass::automatic, wide);
    EXPECT_EQ(sim.neighbors().size_classes().count, wide ? 2 : 1);
    sim.run(20);
    for (int b = 0; b < builds; ++b) {
      exec::reset_transfer_stats();
      sim.rebuild_neighbors();
      if (counted) {  // the rebuild's own transfers (a step moves its group sums and views: not counted here)
        const exec::TransferStats t = exec::transfer_stats();
        counted->to_host_calls += t.to_host_calls;
        counted->to_device_calls += t.to_device_calls;
        counted->to_host_bytes += t.to_host_bytes;
        counted->to_device_bytes += t.to_device_bytes;
      }
      sim.run(2);
    }
    DemResult r;
    r.p = sim.particles();
    r.hx = sim.history().hx;
    r.rebuilds = sim.times().rebuilds;
    return r;
  };
  exec::TransferStats t;
  const DemResult dev = run(&t);
  std::printf("DEM %zu particles, %d rebuilds: %ld transfers to the device (%.0f B), %ld to the host (%.0f B)\n",
              dev.p.size(), builds, t.to_device_calls, t.to_device_bytes, t.to_host_calls, t.to_host_bytes);
  EXPECT_EQ(t.to_host_calls + t.to_device_calls, 0) << "a rebuild copies no array";
  const DemResult host = on_initial_device([&] { return run(nullptr); });
  ASSERT_GE(dev.rebuilds, builds);
  EXPECT_EQ(dev.rebuilds, host.rebuilds);
  EXPECT_EQ(dev.p.id, host.p.id) << "the same canonical order";
  EXPECT_EQ(dev.p.x, host.p.x);
  EXPECT_EQ(dev.p.vy, host.p.vy);
  EXPECT_EQ(dev.hx, host.hx);
}

TEST(DeviceResidency, DemListBuildsMoveOnlyScalars) {
  if (!device_with_own_memory()) GTEST_SKIP() << kNoDevice;
  expect_dem_list_builds_move_only_scalars(false);
}

TEST(DeviceResidency, PolydisperseDemListBuildsMoveOnlyScalars) {
  if (!device_with_own_memory()) GTEST_SKIP() << kNoDevice;
  expect_dem_list_builds_move_only_scalars(true);
}

// The executable: thermo rows, dump frames and the checkpoint come from the device's state through the
// runner's transfer points; the same input on the initial device (OMP_DEFAULT_DEVICE) must give the same files.
// Runs `exe -i input` and returns the bytes per step the runner reports between host and device (outputs
// and sampled checks left out), or -1 when the run fails or does not report them.
double transfers_per_step(const std::string& exe, const std::string& input) {
  const test::CommandResult r = test::run_command(exe, "-i " + input);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  const std::string key = "device transfers while stepping: ";
  const std::size_t at = r.output.find(key);
  EXPECT_NE(at, std::string::npos) << r.output;
  if (r.exit_code != 0 || at == std::string::npos) return -1.0;
  return std::stod(r.output.substr(at + key.size()));
}

// Through the runner, the steps of both executables on their default inputs move only scalars, block sums
// and group views between host and device, never the particle or node state (1,600 particles of 24 columns
// would be 282 KB per step; the progress line once asked for the particles' host copy every step).
TEST(DeviceResidency, ExecutableStepsMoveNoStateBetweenHostAndDevice) {
  if (!device_with_own_memory()) GTEST_SKIP() << kNoDevice;
  const fs::path d = test::fresh_directory("debris_device_transfers");
  const std::string source = DEBRIS_SOURCE_DIR;
  const std::string dem = test::replace(
      test::replace(test::slurp(fs::path(source) / "scenarios/dem/hcp_wall_load.yaml"), "steps: 4000", "steps: 600"),
      "directory: out/dem_hcp_wall_load", "directory: " + (d / "dem").string());
  ASSERT_NE(dem.find("steps: 600"), std::string::npos);
  const double dem_bytes = transfers_per_step(DEBRIS_DEM_EXECUTABLE, test::write_text_file(d, "dem.yaml", dem));
  ASSERT_GE(dem_bytes, 0.0);
  EXPECT_LT(dem_bytes, 4096.0);
  std::string pd = test::slurp(fs::path(source) / "scenarios/peridem/compressive_small.yaml");
  for (std::size_t at = pd.find("file: data/"); at != std::string::npos; at = pd.find("file: data/", at + 1))
    pd.replace(at, 11, "file: " + source + "/scenarios/peridem/data/");
  pd = test::replace(test::replace(pd, "steps: 20000", "steps: 600"), "directory: out/peridem_compressive_small",
                     "directory: " + (d / "peridem").string());
  ASSERT_NE(pd.find("steps: 600"), std::string::npos);
  ASSERT_EQ(pd.find("file: data/"), std::string::npos);
  const double pd_bytes =
      transfers_per_step(DEBRIS_PERIDEM_EXECUTABLE, test::write_text_file(d, "peridem.yaml", pd));
  ASSERT_GE(pd_bytes, 0.0);
  EXPECT_LT(pd_bytes, 4096.0);
  std::cout << "bytes per step: debris_dem " << dem_bytes << ", debris_peridem " << pd_bytes << "\n";
}

TEST(DeviceResidency, DemExecutableOutputEqualsHostFallback) {
  if (!device_with_own_memory()) GTEST_SKIP() << kNoDevice;
  const fs::path d = test::fresh_directory("debris_device_dem_cli");
  auto input = [&](const std::string& out) {
    return test::write_text_file(d, out + ".yaml", std::string(test::kTable4MaterialYaml) + R"(particles:
  lattice:
    kind: fcc
    spacing: 100
    diameter: 100
    size_spread: 0.05
    displacement: 3
    cells: [3, 3, 3]
box:
  periodic: [true, true, true]
run:
  steps: 200
  time_step_fraction: 0.1
  skin: 2
output:
  directory: )" + (d / out).string() + R"(
  thermo_every: 20
  dump_every: 50
)");
  };
  const std::string exe = DEBRIS_DEM_EXECUTABLE;
  const test::CommandResult dev = test::run_command(exe, "-i " + input("device"));
  ASSERT_EQ(dev.exit_code, 0) << dev.output;
  EXPECT_NE(dev.output.find(device_words()), std::string::npos) << dev.output;
  const test::CommandResult host = test::run_command(
      "OMP_DEFAULT_DEVICE=" + std::to_string(exec::initial_device()) + " " + exe, "-i " + input("host"));
  ASSERT_EQ(host.exit_code, 0) << host.output;
  EXPECT_EQ(host.output.find(device_words()), std::string::npos) << host.output;
  for (const char* file : {"thermo.csv", "dump.lammpstrj"}) {
    const std::string a = test::slurp(d / "device" / file), b = test::slurp(d / "host" / file);
    EXPECT_FALSE(a.empty()) << file;
    EXPECT_EQ(a, b) << file << " differs between the device run and host fallback";
  }
  // Restarts from checkpoints written from the device's state: DemCliRestart and DemRestart, which the
  // hostdevice stage of .ci/run also runs.
}


// ---- PeriDEM ----

// A fast impact that cracks both grains within a few hundred steps (tests/test_peridem_restart.cpp's, with
// grain-centre damping): a disc of R = 1 mm on a wall hit at 10 m/s by a disc of R = 1.5 mm. `extra`: more
// top-level keys (stages, output).
std::string pd_impact_yaml(const std::string& extra = "") {
  return R"(dimension: 2
materials:
  M1: {density: 1200 kg/m^3, bulk_modulus: 0.0216 GPa, shear_modulus: 0.01296 GPa, fracture_energy: 50 J/m^2, horizon: 0.6 mm}
shapes:
  small: {type: circle, radius: 1 mm, mesh_size: 0.3 mm}
  large: {type: circle, radius: 1.5 mm, mesh_size: 0.3 mm}
  floor: {type: rectangle, lo: [-3 mm, -0.6 mm, 0], hi: [3 mm, 0, 0], mesh_size: 0.3 mm}
  lid: {type: rectangle, lo: [-3 mm, 9 mm, 0], hi: [3 mm, 9.6 mm, 0], mesh_size: 0.3 mm}
grains:
  - {name: bottom, shape: small, material: M1, centre: [0, 1.18 mm, 0]}
  - {name: top, shape: large, material: M1, centre: [0.1 mm, 3.86 mm, 0], rotation: 0.3, velocity: [0, -10 m/s, 0]}
walls:
  - {name: floor, shape: floor, material: M1}
  - {name: lid, shape: lid, material: M1}
contact: {restitution: 0.9, friction: 0.3, damping: grain_centres}
gravity: [0, -10 m/s^2, 0]
)" + extra;
}

PeridemSimulation pd_impact(const fs::path& dir) {
  PeridemInputOptions o;
  o.output_directory = dir.string();
  PeridemRunConfig cfg =
      read_peridem_input_text(pd_impact_yaml("run: {time_step: 0.1 us, steps: 1000, skin: 0.05 mm}\n"), "impact.yaml",
                              "", o);
  PeridemSimulation sim(std::move(cfg.nodes), std::move(cfg.grains), cfg.materials, cfg.contact, cfg.settings);
  sim.set_grain_names(cfg.grain_names);
  return sim;
}


struct PdResult {
  PdNodes nodes;
  exec::DeviceVector<unsigned char> broken;
  exec::DeviceVector<double> cx, cvy;
  exec::DeviceVector<int> index;
  std::vector<Vec3> reactions;
  PeridemDiagnostics diag;
  long broken_bonds = 0, rebuilds = 0;
};

PdResult run_pd_model(long steps, const fs::path& dir) {
  PeridemSimulation sim = pd_impact(dir);
  sim.run(steps);
  PdResult r;
  r.diag = sim.diagnostics();
  r.reactions = sim.wall_reactions();
  r.nodes = sim.nodes();
  r.broken = sim.bonds().broken;
  r.cx = sim.grains().cx;
  r.cvy = sim.grains().cvy;
  r.index = sim.contacts().index();
  r.broken_bonds = sim.broken_bonds();
  r.rebuilds = sim.contact_rebuilds();
  return r;
}

// A contact list build runs where the nodes are, the cell list (cell of each node, counting sort), the
// offsets' prefix sum and the grain-pair slots included, so 60 builds of the impact's list move nothing
// through the named transfer points (only the scans' totals and the bounding box come back, as scalars of
// their kernels). The lists and slots equal host fallback's bit for bit.
TEST(DeviceResidency, PeridemListBuildMovesOnlyScalars) {
  if (!device_with_own_memory()) GTEST_SKIP() << kNoDevice;
  const fs::path dir = test::fresh_directory("debris_device_pd_builds");
  PeridemSimulation sim = pd_impact(dir);
  sim.run(50);
  const PdNodes& nodes = sim.nodes();
  const PdGrains& grains = sim.grains();
  const BondList& bonds = sim.bonds();
  const double cutoff = pd_mesh_size(nodes, grains), skin = 0.2 * cutoff;
  const int builds = 60;
  PdContactList list;
  exec::reset_transfer_stats();
  for (int b = 0; b < builds; ++b) list.build(nodes, grains, bonds, cutoff, skin);
  const exec::TransferStats t = exec::transfer_stats();
  std::cout << "per build: " << t.to_host_bytes / builds << " B back, " << t.to_device_bytes / builds << " B out ("
            << nodes.size() << " nodes, " << list.entries() << " entries, " << list.slots() << " slots)\n";
  EXPECT_EQ(t.to_host_calls + t.to_device_calls, 0) << "a build copies no array";
  PdContactList host;
  on_initial_device([&] {
    host.build(nodes, grains, bonds, cutoff, skin);
    return 0;
  });
  ASSERT_GT(host.slots(), 0) << "the impact must have grain-pair slots at this step to test them";
  list.to_host();
  EXPECT_EQ(list.entries(), host.entries());
  EXPECT_EQ(list.offset(), host.offset());
  EXPECT_EQ(list.index(), host.index());
  EXPECT_EQ(list.grain_slot_offset(), host.grain_slot_offset());
  EXPECT_EQ(list.slot_owner(), host.slot_owner());
  EXPECT_EQ(list.slot_partner_grain(), host.slot_partner_grain());
  EXPECT_EQ(list.slot_partner_node(), host.slot_partner_node());
  EXPECT_EQ(list.slot_pair_offset(), host.slot_pair_offset());
  EXPECT_EQ(list.slot_pair_i(), host.slot_pair_i());
  EXPECT_EQ(list.slot_pair_j(), host.slot_pair_j());
  EXPECT_EQ(list.wall_slot_offset(), host.wall_slot_offset());
  EXPECT_EQ(list.wall_slot(), host.wall_slot());
}

TEST(DeviceResidency, PeridemRunOnTheDeviceEqualsHostFallback) {
  if (!device_with_own_memory()) GTEST_SKIP() << kNoDevice;
  const fs::path dir = test::fresh_directory("debris_device_peridem_run");
  const long steps = 600;
  exec::reset_transfer_stats();
  const PdResult dev = run_pd_model(steps, dir);
  const exec::TransferStats t = exec::transfer_stats();
  const PdResult host = on_initial_device([&] { return run_pd_model(steps, dir); });
  ASSERT_GT(dev.broken_bonds, 0) << "the run must break bonds (self-contact added in place) to test it";
  ASSERT_GT(dev.rebuilds, 2) << "the run needs contact list rebuilds to test them";
  EXPECT_EQ(dev.broken_bonds, host.broken_bonds);
  EXPECT_EQ(dev.rebuilds, host.rebuilds);
  ASSERT_EQ(dev.nodes.size(), host.nodes.size());
  dev.nodes.for_each_column([&](const char* name, const auto& col) {
    host.nodes.for_each_column([&](const char* other, const auto& col_h) {
      if (std::string(name) != other) return;
      if constexpr (std::is_same_v<std::decay_t<decltype(col)>, std::decay_t<decltype(col_h)>>) {
        for (std::size_t i = 0; i < col.size(); ++i) ASSERT_EQ(col[i], col_h[i]) << name << "[" << i << "]";
      }
    });
  });
  EXPECT_EQ(dev.broken, host.broken);
  EXPECT_EQ(dev.cx, host.cx);
  EXPECT_EQ(dev.cvy, host.cvy);
  EXPECT_EQ(dev.index, host.index);
  ASSERT_EQ(dev.reactions.size(), host.reactions.size());
  for (std::size_t g = 0; g < dev.reactions.size(); ++g) {
    EXPECT_EQ(dev.reactions[g].x, host.reactions[g].x) << "grain " << g;
    EXPECT_EQ(dev.reactions[g].y, host.reactions[g].y) << "grain " << g;
  }
  // Fixed-order block sums: the same bits on the device.
  EXPECT_EQ(dev.diag.kinetic_energy, host.diag.kinetic_energy);
  EXPECT_EQ(dev.diag.bond_energy, host.diag.bond_energy);
  EXPECT_EQ(dev.diag.contact_energy, host.diag.contact_energy);
  EXPECT_EQ(dev.diag.max_damage, host.diag.max_damage);
  EXPECT_EQ(dev.diag.contact_pairs, host.diag.contact_pairs);
  EXPECT_GT(dev.diag.contact_pairs, 0);
  std::printf("PeriDEM %zu nodes, %ld steps, %ld rebuilds, %ld bonds broken: %ld transfers to the device (%.0f "
              "bytes), %ld to the host (%.0f bytes)\n",
              dev.nodes.size(), steps, dev.rebuilds, dev.broken_bonds, t.to_device_calls, t.to_device_bytes,
              t.to_host_calls, t.to_host_bytes);
}

// The checkpoint is written from the device's state (nothing read it on the host before), and the run
// restored from it on the device goes on as the run in one piece, bit for bit.
TEST(DeviceResidency, PeridemCheckpointFromTheDeviceRestartsIdentically) {
  if (!device_with_own_memory()) GTEST_SKIP() << kNoDevice;
  const fs::path dir = test::fresh_directory("debris_device_peridem_restart");
  const long n = 500;
  PeridemSimulation straight = pd_impact(dir);
  straight.run(2 * n);
  PeridemSimulation first = pd_impact(dir);
  first.run(n);
  const fs::path ckpt = dir / "checkpoint.h5";
  first.write_checkpoint(ckpt.string(), "run: {steps: 1000}\n");
  ASSERT_GT(first.broken_bonds(), 0) << "the test needs bonds broken before the checkpoint";
  PeridemSimulation resumed = PeridemSimulation::from_checkpoint(ckpt.string());
  resumed.run(n);
  ASSERT_GT(straight.contact_rebuilds(), first.contact_rebuilds()) << "the test needs rebuilds after the checkpoint";
  test::expect_same_pd_state(straight, resumed);
}

// The executable: thermo rows (energies, wall forces, per-grain centres, damage, broken bonds) and trajectory
// frames come from the device's state through the runner's transfer points, and a stage places the lid and
// sets it moving (host-side edits sent back to the device). The same input on the initial device must give
// the same rows and frames.
TEST(DeviceResidency, PeridemExecutableOutputEqualsHostFallback) {
  if (!device_with_own_memory()) GTEST_SKIP() << kNoDevice;
  const fs::path d = test::fresh_directory("debris_device_peridem_cli");
  auto input = [&](const std::string& out) {
    return test::write_text_file(d, out + ".yaml", pd_impact_yaml(R"(stages:
  - {name: fall, duration: 20 us}
  - name: press
    duration: 20 us
    walls:
      - {name: lid, place: {y_min: 5.8 mm}, velocity: [0, -5 m/s, 0]}
run: {time_step: 0.1 us, skin: 0.05 mm}
output:
  directory: )" + (d / out).string() + R"(
  thermo_every: 50
  trajectory_every: 100
)"));
  };
  const std::string exe = DEBRIS_PERIDEM_EXECUTABLE;
  const test::CommandResult dev = test::run_command(exe, "-i " + input("device"));
  ASSERT_EQ(dev.exit_code, 0) << dev.output;
  EXPECT_NE(dev.output.find(device_words()), std::string::npos) << dev.output;
  EXPECT_NE(dev.output.find("wall lid moved by"), std::string::npos) << dev.output;
  const test::CommandResult host = test::run_command(
      "OMP_DEFAULT_DEVICE=" + std::to_string(exec::initial_device()) + " " + exe, "-i " + input("host"));
  ASSERT_EQ(host.exit_code, 0) << host.output;
  EXPECT_EQ(host.output.find(device_words()), std::string::npos) << host.output;
  const std::string a = test::slurp(d / "device" / "thermo.csv"), b = test::slurp(d / "host" / "thermo.csv");
  EXPECT_FALSE(a.empty());
  EXPECT_EQ(a, b) << "thermo.csv differs between the device run and host fallback";
  const int frames = test::count_xmf_frames(d / "device" / "trajectory.xmf");
  EXPECT_EQ(frames, test::count_xmf_frames(d / "host" / "trajectory.xmf"));
  EXPECT_GE(frames, 4);
  const h5::File fd((d / "device" / "trajectory.h5").string(), h5::File::Mode::read_only);
  const h5::File fh((d / "host" / "trajectory.h5").string(), h5::File::Mode::read_only);
  for (int k = 0; k < frames; ++k) {
    SCOPED_TRACE("frame " + std::to_string(k));
    const h5::Group gd = fd.open_group("frames/" + std::to_string(k)), gh = fh.open_group("frames/" + std::to_string(k));
    EXPECT_EQ(gd.attribute<std::int64_t>("step"), gh.attribute<std::int64_t>("step"));
    for (const char* set : {"position", "velocity", "force", "damage", "broken_fraction"})
      EXPECT_EQ(gd.read<double>(set).values, gh.read<double>(set).values) << set;
  }
}

}  // namespace
}  // namespace debris
