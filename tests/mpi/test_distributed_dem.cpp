// The cohesive DEM step cut among ranks (DemSimulation on a decomposition) gives the one-process run's bits:
// at every thermo row (kinetic energy, momentum, elastic energy, pairs, deepest overlap, the groups'
// reactions, displacements and velocities, the number of rebuilds) and in the final state of every particle.
// Every rank also runs the whole system alone (settings.distribute = false) as the reference, and compares.
// The cases: a sheared cohesive sample with rebuilds and particles crossing ranks (their pair history
// migrating with them), and a stress test that rebuilds, and so migrates, at every step.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <array>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <map>
#include <random>
#include <string>
#include <vector>

#include <unistd.h>

#include "core/comm/communicator.hpp"
#include "core/lattice.hpp"
#include "scenarios/common/dem/dem_simulation.hpp"
#include "tests/mpi/cohesive_block.hpp"
#include "tests/mpi/rank_grids.hpp"

namespace debris::comm {
namespace {

using test::grids_for;

struct Sample {
  Box box;
  Particles particles;
  Groups groups;
  DemSettings settings;
};

// A cohesive block, periodic along x and z, between a frozen floor and a lid that slides along x and z
// under a load along y (the adhesive-wear junction's drive, in miniature), with a thermal kick. Without
// walls (`walls` false): periodic on every axis, every particle drifting along (1, 0.8, 0.6) at
// `slide_per_step` a step, so that particles cross every cut.
Sample sheared_sample(double slide_per_step, double kick, bool walls = true) {
  // 3,072 particles: 4 ranks fit along x, 3 along y or z.
  const Lattice lat = test::cohesive_block({12, 8, 8}, 5);
  Sample s;
  s.box = Box(lat.box.lo(), lat.box.hi(), {true, !walls, true});
  s.particles = lat.particles;
  s.settings.material = table4_material(0.0);
  s.settings.material.restitution = 0.9;
  s.settings.time_step_fraction = 0.1;
  s.settings.global_damping = 0.02;
  s.settings.energy_accounting = true;  // its sums too are compared bit for bit
  const CohesiveCoefficients coef = CohesiveCoefficients::from(s.settings.material);
  Particles probe = s.particles;
  probe.set_mass_from_density(s.settings.material.density);
  const double dt = 0.1 * stability_limits(coef, probe).dt_c;
  const double m = probe.mass[0];
  const CohesivePairParams pp = cohesive_pair_params(coef, 50, 50, m, m);

  const double y_lo = s.box.lo().y, y_hi = s.box.hi().y;
  Group floor;
  floor.name = "floor";
  floor.motion = GroupMotion::frozen;
  Group lid;
  lid.name = "lid";
  lid.motion = GroupMotion::force;
  lid.velocity = {slide_per_step / dt, 0, 0.5 * slide_per_step / dt};
  lid.prescribed = {true, false, true};
  long lid_count = 0;
  for (std::size_t i = 0; i < s.particles.size(); ++i) lid_count += s.particles.y[i] > y_hi - 120;
  lid.external_force = {0, -0.002 * pp.k_n * 100.0 * static_cast<double>(lid_count) / 12, 0};
  const int gf = walls ? s.groups.add(floor) : -1, gl = walls ? s.groups.add(lid) : -1;
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (std::size_t i = 0; i < s.particles.size(); ++i) {
    if (s.particles.y[i] < y_lo + 120) s.particles.group[i] = gf;
    if (s.particles.y[i] > y_hi - 120) s.particles.group[i] = gl;
    const double drift = walls ? 0.0 : slide_per_step / dt;
    s.particles.vx[i] = drift + kick * u(rng) / dt;
    s.particles.vy[i] = 0.8 * drift + kick * u(rng) / dt;
    s.particles.vz[i] = 0.6 * drift + kick * u(rng) / dt;
    s.particles.wx[i] = 0.01 * kick * u(rng) / dt, s.particles.wy[i] = 0.01 * kick * u(rng) / dt;
  }
  return s;
}

// One thermo row, as a list of doubles compared bit for bit (with the virial stress the stress-driven box
// of the amorphous relaxation reads).
std::vector<double> thermo_row(const DemSimulation& sim) {
  const ParticleTotals t = sim.totals();
  const CohesiveDiagnostics d = sim.diagnostics();
  std::vector<double> row = {static_cast<double>(sim.step_count()), sim.time(), t.kinetic_energy, t.momentum.x,
                             t.momentum.y, t.momentum.z, d.elastic_energy, d.max_overlap,
                             static_cast<double>(d.interacting_pairs), static_cast<double>(sim.times().rebuilds)};
  for (const Group& g : sim.groups().list)
    for (const Vec3& v : {g.reaction, g.displacement, g.velocity}) row.insert(row.end(), {v.x, v.y, v.z});
  // The virial stress of the whole box, and of the particles of even id (a selection) without m v v.
  const Vec3 extent = sim.box().hi() - sim.box().lo();
  const double volume = extent.x * extent.y * extent.z;
  const StressTensor all = sim.virial_stress(nullptr, volume);
  const Particles& p = sim.particles();
  std::vector<int> even(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) even[i] = p.id[i] % 2 == 0;
  const StressTensor part = sim.virial_stress(even.data(), volume / 2, false);
  for (const StressTensor& t : {all, part}) row.insert(row.end(), {t.xx, t.yy, t.zz, t.xy, t.xz, t.yz});
  // The energy accounting's sums: each mechanism, each group's drive, the residual.
  if (sim.settings().energy_accounting) {
    const EnergyBalance b = sim.energy_balance(d);
    row.insert(row.end(), {b.totals.dissipated_normal, b.totals.dissipated_tangential, b.totals.dissipated_sliding,
                           b.totals.dissipated_global, b.totals.tangential_work, b.residual()});
    row.insert(row.end(), b.totals.drive_work.begin(), b.totals.drive_work.end());
  }
  return row;
}

bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

using State = std::array<double, 15>;
State state_of(const Particles& p, std::size_t i) {
  return {p.x[i], p.y[i], p.z[i], p.vx[i], p.vy[i], p.vz[i], p.wx[i], p.wy[i], p.wz[i],
          p.fx[i], p.fy[i], p.fz[i], p.tx[i], p.ty[i], p.tz[i]};
}

// Runs `steps` steps (a rebuild forced after each when `rebuild_every_step`), a thermo row every `every`.
std::vector<std::vector<double>> run(DemSimulation& sim, int steps, int every, bool rebuild_every_step) {
  std::vector<std::vector<double>> rows{thermo_row(sim)};
  for (int s = 1; s <= steps; ++s) {
    sim.step();
    if (rebuild_every_step) {
      sim.rebuild_neighbors();
      sim.recompute_forces();
    }
    if (s % every == 0) rows.push_back(thermo_row(sim));
  }
  return rows;
}

// `crossing_axes`: the axes along which particles must have crossed a cut, on every grid that cuts one.
void expect_serial_bits(const Sample& sample, int steps, int every, bool rebuild_every_step, long min_rebuilds,
                        std::array<bool, 3> crossing_axes) {
  Sample alone = sample;
  alone.settings.distribute = false;
  DemSimulation serial(alone.box, alone.particles, alone.groups, alone.settings);
  const auto want = run(serial, steps, every, rebuild_every_step);
  ASSERT_GE(serial.times().rebuilds, min_rebuilds) << "the test must rebuild";
  std::map<std::int64_t, State> final_state;
  for (std::size_t i = 0; i < serial.particles().size(); ++i) final_state[serial.particles().id[i]] = state_of(serial.particles(), i);

  for (const auto g : grids_for(size())) {
    Sample cut = sample;
    cut.settings.rank_grid = g;
    DemSimulation sim(cut.box, cut.particles, cut.groups, cut.settings);
    const std::string where = sim.decomposition().describe() + ", rank " + std::to_string(rank());
    EXPECT_EQ(sim.distributed(), size() > 1) << where;
    const auto got = run(sim, steps, every, rebuild_every_step);
    ASSERT_EQ(got.size(), want.size());
    for (std::size_t r = 0; r < want.size(); ++r)
      if (!same_bits(got[r], want[r])) {
        ADD_FAILURE() << "thermo row " << r << " (step " << want[r][0] << ") differs, " << where;
        for (std::size_t c = 0; c < want[r].size(); ++c)
          if (got[r][c] != want[r][c]) std::printf("  column %zu: %.17g vs %.17g\n", c, got[r][c], want[r][c]);
        break;
      }
    const Particles& p = sim.particles();
    long mismatches = 0;
    std::int64_t owned = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
      if (sim.distributed() && !sim.owned_mask()[i]) continue;
      ++owned;
      if (state_of(p, i) != final_state.at(p.id[i]) && mismatches++ < 3)
        ADD_FAILURE() << "particle " << p.id[i] << " differs from the serial run at the end, " << where;
    }
    EXPECT_EQ(mismatches, 0) << where;
    std::int64_t counts[2] = {owned, sim.times().migrated};
    allreduce_sum(counts, 2);
    EXPECT_EQ(counts[0], static_cast<std::int64_t>(sample.particles.size())) << "every particle owned once, " << where;
    bool must_cross = false;
    for (int a = 0; a < 3; ++a) must_cross = must_cross || (crossing_axes[a] && g[a] > 1);
    if (must_cross) EXPECT_GT(counts[1], 0) << "particles must cross ranks, " << where;
    if (rank() == 0)
      std::printf("[ distributed ] %s: %ld rebuilds, %lld migrations, halo %zu B per step on rank 0\n",
                  sim.decomposition().describe().c_str(), sim.times().rebuilds, static_cast<long long>(counts[1]),
                  sim.halo().forward_bytes());
  }
}

TEST(DistributedDem, ShearedCohesiveSampleHasTheSerialBitsAtEveryThermoRow) {
  if (exec::offload_build()) GTEST_SKIP() << "a run cut among ranks runs on host threads so far";
  // The lid slides 0.3 length units a step along x: 600 (half the box) in 2,000 steps, across every cut
  // along x (and along z at half that speed); the sample shears and tears under it.
  expect_serial_bits(sheared_sample(0.3, 0.05), 2000, 100, false, 20, {true, false, true});
}

TEST(DistributedDem, MigrationAtEveryStepKeepsTheSerialBits) {
  if (exec::offload_build()) GTEST_SKIP() << "a run cut among ranks runs on host threads so far";
  // A hot block drifting along (1, 0.8, 0.6) 1 length unit a step, rebuilt after every step: particles
  // cross cuts along every axis, their pair state travelling with them each time.
  expect_serial_bits(sheared_sample(1.0, 0.3, false), 150, 10, true, 150, {true, true, true});
}

// Every column, the list as built and the history of two one-process simulations, bit for bit.
bool same_system(const DemSimulation& a, const DemSimulation& b) {
  bool same = a.step_count() == b.step_count() && a.time() == b.time() && a.particles().size() == b.particles().size();
  std::vector<std::vector<char>> bytes_a, bytes_b;
  auto bytes = [](const Particles& p, std::vector<std::vector<char>>& out) {
    p.for_each_column([&](const char*, const auto& col) {
      const char* c = reinterpret_cast<const char*>(col.data());
      out.emplace_back(c, c + col.size() * sizeof(col[0]));
    });
  };
  bytes(a.particles(), bytes_a);
  bytes(b.particles(), bytes_b);
  const NeighborList::Saved la = a.neighbors().save(), lb = b.neighbors().save();
  auto vec = [](const auto& v) { return std::vector<double>(v.begin(), v.end()); };
  return same && bytes_a == bytes_b && la.offset == lb.offset && la.index == lb.index && la.x0 == lb.x0 &&
         la.y0 == lb.y0 && la.z0 == lb.z0 && vec(a.history().hx) == vec(b.history().hx) &&
         vec(a.history().hy) == vec(b.history().hy) && vec(a.history().hz) == vec(b.history().hz);
}

TEST(DistributedDem, CheckpointsRestartOnAnyRankCountBitForBit) {
  if (exec::offload_build()) GTEST_SKIP() << "a run cut among ranks runs on host threads so far";
  const Sample sample = sheared_sample(0.3, 0.05);
  const int half = 300, every = 50;
  namespace fs = std::filesystem;
  const std::string dir = first_message(
      rank() == 0 ? (fs::temp_directory_path() / ("debris_mpi_checkpoints_" + std::to_string(::getpid()))).string() : "");
  if (rank() == 0) fs::create_directories(dir);
  const std::string serial_file = dir + "/serial.h5", cut_file = dir + "/cut.h5";

  // The reference: one process, 2 x 300 steps, a checkpoint at 300 (rank 0 writes it).
  Sample alone = sample;
  alone.settings.distribute = false;
  DemSimulation serial(alone.box, alone.particles, alone.groups, alone.settings);
  auto want = run(serial, half, every, false);
  if (rank() == 0) serial.write_checkpoint(serial_file, "");
  const auto second_half = run(serial, half, every, false);
  want.insert(want.end(), second_half.begin() + 1, second_half.end());
  barrier();
  auto expect_rows = [&](const std::vector<std::vector<double>>& got, std::size_t first, const std::string& where) {
    for (std::size_t r = 0; r < got.size(); ++r) {
      // Column 9 counts rebuilds since the set-up: a restarted run counts afresh.
      std::vector<double> a = got[r], b = want[first + r];
      a[9] = b[9] = 0;
      if (same_bits(a, b)) continue;
      ADD_FAILURE() << "thermo row " << first + r << " differs, " << where;
      for (std::size_t c = 0; c < a.size(); ++c)
        if (a[c] != b[c]) std::printf("  column %zu: %.17g vs %.17g\n", c, a[c], b[c]);
      break;
    }
  };

  for (const auto g : grids_for(size())) {
    const std::string grid = std::to_string(g[0]) + "x" + std::to_string(g[1]) + "x" + std::to_string(g[2]);
    // P ranks write a checkpoint at 300 (each rank its own rows, parallel HDF5) and go on: the file holds
    // what one process writes.
    Sample cut = sample;
    cut.settings.rank_grid = g;
    DemSimulation sim(cut.box, cut.particles, cut.groups, cut.settings);
    run(sim, half, every, false);
    sim.write_checkpoint(cut_file, "");
    barrier();
    const DemSimulation from_cut = DemSimulation::from_checkpoint(cut_file, nullptr, {}, {false, {0, 0, 0}});
    const DemSimulation from_serial = DemSimulation::from_checkpoint(serial_file, nullptr, {}, {false, {0, 0, 0}});
    EXPECT_TRUE(same_system(from_cut, from_serial)) << "the checkpoint of " << grid << " ranks is not the one-process one";
    expect_rows(run(sim, half, every, false), half / every, "uninterrupted on " + grid);

    // P -> 1: one process continues the P ranks' checkpoint.
    DemSimulation one = DemSimulation::from_checkpoint(cut_file, nullptr, {}, {false, {0, 0, 0}});
    expect_rows(run(one, half, every, false), half / every, "restarted on 1 rank from " + grid);
    // 1 -> P: P ranks continue the one-process checkpoint.
    DemSimulation many = DemSimulation::from_checkpoint(serial_file, nullptr, {}, {true, g});
    EXPECT_EQ(many.distributed(), size() > 1);
    expect_rows(run(many, half, every, false), half / every, "restarted on " + grid + " from 1 rank");
    barrier();  // before rank 0 overwrites the file
  }
  barrier();
  if (rank() == 0) fs::remove_all(dir);
}

// The amorphous relaxation's moving box (scenarios/common/dem/amorphous_sample.cpp, phase 2): every n steps
// the virial stress of the whole box (exact, across ranks) sets a strain of each box length, and the box
// deforms, carrying every particle (owned and ghosts alike, the same bits) and the cut planes (stored as
// box fractions). A block packed 2% too tight grows toward zero stress.
std::vector<std::vector<double>> run_moving_box(DemSimulation& sim, int checks, int n) {
  std::vector<std::vector<double>> rows;
  const double gain = 1e-3;  // strain per unit of (stress / the stress scale of the first check)
  double scale = 0;
  for (int c = 0; c < checks; ++c) {
    const Vec3 len = sim.box().length();
    const StressTensor s = sim.virial_stress(nullptr, len.x * len.y * len.z, false);
    if (c == 0) scale = std::max({std::fabs(s.xx), std::fabs(s.yy), std::fabs(s.zz)});
    std::vector<double> row = thermo_row(sim);
    row.insert(row.end(), {len.x, len.y, len.z});
    rows.push_back(row);
    const double sig[3] = {s.xx, s.yy, s.zz};
    const double now[3] = {len.x, len.y, len.z};
    double next[3];
    for (int a = 0; a < 3; ++a) next[a] = now[a] * (1.0 - std::clamp(gain * sig[a] / scale, -1e-3, 1e-3));
    const Vec3 lo = sim.box().lo();
    sim.box().deform(lo, lo + Vec3{next[0], next[1], next[2]}, sim.particles());
    sim.run(n);
  }
  return rows;
}

TEST(DistributedDem, MovingBoxOfTheAmorphousRelaxationHasTheSerialBits) {
  if (exec::offload_build()) GTEST_SKIP() << "a run cut among ranks runs on host threads so far";
  // The block drifts along (1, 0.8, 0.6), 0.5 length units a step at first, under a global damping light
  // enough (0.02) that every layer crosses a cut on every axis; the drift leaves the virial unchanged.
  Sample sample = sheared_sample(0.5, 0.02, false);
  const Vec3 lo = sample.box.lo(), hi = sample.box.hi();
  sample.box.deform(lo, lo + 0.98 * (hi - lo), sample.particles);  // packed tight: the block pushes out
  sample.settings.global_damping = 0.02;
  Sample alone = sample;
  alone.settings.distribute = false;
  DemSimulation serial(alone.box, alone.particles, alone.groups, alone.settings);
  const auto want = run_moving_box(serial, 40, 20);
  ASSERT_GT(serial.box().length().x, (hi - lo).x * 0.98 * 1.005) << "the box must grow";
  ASSERT_GT(serial.times().rebuilds, 3) << "the box's growth must rebuild the list";
  if (rank() == 0)
    std::printf("[ distributed ] moving box: x length %.6g -> %.6g, %ld rebuilds\n", 0.98 * (hi - lo).x,
                serial.box().length().x, serial.times().rebuilds);
  for (const auto g : grids_for(size())) {
    Sample cut = sample;
    cut.settings.rank_grid = g;
    DemSimulation sim(cut.box, cut.particles, cut.groups, cut.settings);
    const auto got = run_moving_box(sim, 40, 20);
    const std::string where = sim.decomposition().describe() + ", rank " + std::to_string(rank());
    for (std::size_t r = 0; r < want.size(); ++r)
      if (!same_bits(got[r], want[r])) {
        ADD_FAILURE() << "check " << r << " differs, " << where;
        break;
      }
    // Particles crossed the cuts, which the box carries along: their migration is part of what matched.
    const std::int64_t crossed = sim.migrated_in_all();
    if (size() > 1) EXPECT_GT(crossed, 0) << "particles must cross a cut, " << where;
    if (rank() == 0) std::printf("[ distributed ] moving box on %s: %lld particles crossed a cut\n",
                                 sim.decomposition().describe().c_str(), static_cast<long long>(crossed));
  }
}

}  // namespace
}  // namespace debris::comm
