// Device residency, tested where it can fail: in the hostdevice build (clang's OpenMP offload to the host
// CPU as a separate device) a kernel reads the device's copy of every array, so a missing to_device or
// to_host gives a stale value. These tests skip in host builds and on GCC's host fallback (nvptx build
// without a GPU), where target regions share the host's memory.
//  - a canary that fails unless the device really has its own memory;
//  - the residency check aborts on an array that was never entered;
//  - a DEM run on the device equals the same run on the initial device (host fallback, shared memory, where
//    no transfer can be missing), and so does the debris_dem executable's output (thermo rows, dump frames)
//    through the runner's transfer points.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "core/exec.hpp"
#include "scenarios/common/dem_simulation.hpp"
#include "tests/cli_helpers.hpp"
#include "tests/dem_samples.hpp"

namespace debris {
namespace {

namespace fs = std::filesystem;

bool separate_memory_build() { return std::string(exec::offload_kind()) == "hostdevice"; }

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
  if (!separate_memory_build()) GTEST_SKIP() << "only the hostdevice build has a device with its own memory";
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
  if (!separate_memory_build()) GTEST_SKIP() << "the residency check is compiled into hostdevice builds";
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
  if (!separate_memory_build()) GTEST_SKIP() << "needs a device with its own memory";
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

// The executable: thermo rows, dump frames and the checkpoint come from the device's state through the
// runner's transfer points; the same input on the initial device (OMP_DEFAULT_DEVICE) must give the same files.
TEST(DeviceResidency, DemExecutableOutputEqualsHostFallback) {
  if (!separate_memory_build()) GTEST_SKIP() << "needs a device with its own memory";
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
  EXPECT_NE(dev.output.find("separate-memory device"), std::string::npos) << dev.output;
  const test::CommandResult host = test::run_command(
      "OMP_DEFAULT_DEVICE=" + std::to_string(exec::initial_device()) + " " + exe, "-i " + input("host"));
  ASSERT_EQ(host.exit_code, 0) << host.output;
  EXPECT_EQ(host.output.find("separate-memory device"), std::string::npos) << host.output;
  for (const char* file : {"thermo.csv", "dump.lammpstrj"}) {
    const std::string a = test::slurp(d / "device" / file), b = test::slurp(d / "host" / file);
    EXPECT_FALSE(a.empty()) << file;
    EXPECT_EQ(a, b) << file << " differs between the device run and host fallback";
  }
  // Restarts from checkpoints written from the device's state: DemCliRestart and DemRestart, which the
  // hostdevice stage of .ci/run also runs.
}

}  // namespace
}  // namespace debris
