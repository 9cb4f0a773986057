// The PeriDEM step cut among ranks (scenarios/common/peridem/peridem_ranks.cpp) against one
// process: every rank also runs the whole system alone, and every node a rank owns must have the same bits
// (position, velocity, force, dilatation) as that node in the one-process run, and the diagnostics (energies,
// momentum, damage, broken bonds, touching pairs) and the walls' reactions the same bits, after the set-up and every 150 steps in which grains fly across the cuts, collide with
// each other and with walls that cross every cut, break bonds and rub with friction.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "core/comm/communicator.hpp"
#include "core/error.hpp"
#include "core/exec.hpp"
#include "scenarios/common/peridem/peridem_simulation.hpp"
#include "tests/mpi/rank_grids.hpp"

namespace debris {
namespace {

constexpr double kMm = 1e-3;
// The whole field drifts (m/s), so that grains cross the cuts, and many of them: about 6 mm in the 600 steps
// of a test, a subdomain's width at 4 ranks along x.
const Vec3 kDrift{20, -8, 8};

// Spheres of radius 1 mm meshed on a cubic lattice of h = 0.4 mm (33 nodes each), centres on a 3 mm grid of
// nx x ny x nz with a random jitter, random velocities up to `speed` (m/s) beside the drift, and the first two grains of
// the first row thrown at each other at `impact` m/s, and the third torn apart: the halves of its nodes
// given +-tear m/s along x (bonds break). Gentle enough that no fragment flies far from its grain's centre:
// a grain's extent sets the ghost width, and at 4 ranks along x a subdomain is 6 mm wide. M1 (paper B, Table 1) with
// friction, node-pair restitution 0.8, and gravity.
PeridemSimulation make_field(int nx, int ny, int nz, double speed, double impact, double tear, double fracture_energy, double dt, bool walls, PdDamping damping,
                             std::uint64_t seed = 7) {
  const double h = 0.4 * kMm;
  PdNodes nodes;
  PdGrains grains;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::int64_t id = 0;
  int g = 0;
  for (int c = 0; c < nz; ++c)
    for (int b = 0; b < ny; ++b)
      for (int a = 0; a < nx; ++a, ++g) {
        const Vec3 centre{3 * kMm * a + 0.3 * kMm * u(rng), 3 * kMm * b + 0.3 * kMm * u(rng),
                          3 * kMm * c + 0.3 * kMm * u(rng)};
        Vec3 v{speed * u(rng), speed * u(rng), speed * u(rng)};
        if (g == 0) v = {impact, 0, 0};
        if (g == 1) v = {-impact, 0, 0};
        v += kDrift;
        grains.resize(static_cast<std::size_t>(g) + 1);
        grains.node_begin[g] = static_cast<int>(nodes.size());
        for (int k = -2; k <= 2; ++k)
          for (int j = -2; j <= 2; ++j)
            for (int i = -2; i <= 2; ++i) {
              if (i * i + j * j + k * k > 4) continue;
              const std::size_t n = nodes.add(id++, g, centre.x + i * h, centre.y + j * h, centre.z + k * h, h * h * h);
              nodes.vx[n] = v.x, nodes.vy[n] = v.y, nodes.vz[n] = v.z;
              if (g == 2) nodes.vx[n] += i > 0 ? tear : (i < 0 ? -tear : 0.0);  // torn apart
            }
        grains.node_end[g] = static_cast<int>(nodes.size());
        grains.kind[g] = static_cast<int>(PdGrainKind::particle);
        grains.material[g] = 0;
      }
  // Walls: a floor rising at 5 m/s under the field and a fixed side wall across the drift along x, planes of
  // nodes h apart; they cross every cut, so each rank holds pieces of them.
  const auto add_wall = [&](Vec3 origin, Vec3 du, Vec3 dv, int nu, int nv, Vec3 velocity) {
    grains.resize(static_cast<std::size_t>(g) + 1);
    grains.node_begin[g] = static_cast<int>(nodes.size());
    for (int b = 0; b < nv; ++b)
      for (int a = 0; a < nu; ++a) {
        const Vec3 p = origin + (a * h) * du + (b * h) * dv;
        const std::size_t n = nodes.add(id++, g, p.x, p.y, p.z, h * h * h);
        nodes.vx[n] = velocity.x, nodes.vy[n] = velocity.y, nodes.vz[n] = velocity.z;
      }
    grains.node_end[g] = static_cast<int>(nodes.size());
    grains.kind[g] = static_cast<int>(PdGrainKind::wall);
    grains.wall_vx[g] = velocity.x, grains.wall_vy[g] = velocity.y, grains.wall_vz[g] = velocity.z;
    ++g;
  };
  if (walls) {
    add_wall({-2 * kMm, -2.2 * kMm, -2 * kMm}, {1, 0, 0}, {0, 0, 1}, 70, 3 * nz * 2 + 10, {0, 5, 0});
    add_wall({3 * kMm * nx - 1.0 * kMm, -2 * kMm, -2 * kMm}, {0, 1, 0}, {0, 0, 1}, 3 * ny * 2 + 10, 3 * nz * 2 + 10, {0, 0, 0});
  }
  PdMaterial m = peridem_material_m1(3);
  m.horizon = 1.5 * h;
  m.fracture_energy = fracture_energy;  // J/m^2 (M1: 50)
  PdContactSettings contact;
  contact.restitution = 0.8;
  contact.friction = 0.5;
  PeridemSettings settings;
  settings.time_step = dt;
  settings.gravity = {0, -9.81, 0};
  settings.damping = damping;
  return PeridemSimulation(std::move(nodes), std::move(grains), {m}, {contact}, settings);
}

// Every node this rank owns against the same node of the one-process run (ids are the one-process indices),
// bit for bit; every node owned by exactly one rank.
void expect_owned_nodes_equal(const PeridemSimulation& ranks, const PeridemSimulation& one, const std::string& where) {
  const PdNodes& a = ranks.nodes();
  const PdNodes& b = one.nodes();
  std::int64_t owned = 0;
  int wrong = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (!ranks.owned_nodes()[i]) continue;
    ++owned;
    const auto k = static_cast<std::size_t>(a.id[i]);
    const double mine[10] = {a.x[i], a.y[i], a.z[i], a.vx[i], a.vy[i], a.vz[i], a.fx[i], a.fy[i], a.fz[i], a.theta[i]};
    const double theirs[10] = {b.x[k], b.y[k], b.z[k], b.vx[k], b.vy[k], b.vz[k], b.fx[k], b.fy[k], b.fz[k], b.theta[k]};
    for (int c = 0; c < 10; ++c)
      if (mine[c] != theirs[c] && ++wrong <= 3)
        ADD_FAILURE() << where << ": node " << a.id[i] << " column " << c << " (x y z vx vy vz fx fy fz theta): "
                      << mine[c] << " on ranks, " << theirs[c] << " as one process";
  }
  EXPECT_EQ(wrong, 0) << where;
  comm::allreduce_sum(&owned, 1);
  EXPECT_EQ(owned, static_cast<std::int64_t>(one.node_count())) << where;
}

std::string grid_name(const std::array<int, 3>& g) {
  return std::to_string(g[0]) + "x" + std::to_string(g[1]) + "x" + std::to_string(g[2]);
}

void run_against_one_process(PdDamping damping, double speed, double impact, double tear, double fracture_energy,
                             double dt, bool walls, long min_migrations) {
  for (const auto& grid : test::grids_for(comm::size())) {
    SCOPED_TRACE("grid " + grid_name(grid));
    PeridemSimulation one = make_field(8, 5, 5, speed, impact, tear, fracture_energy, dt, walls, damping);
    PeridemSimulation ranks = make_field(8, 5, 5, speed, impact, tear, fracture_energy, dt, walls, damping);
    ranks.distribute(grid);
    ASSERT_TRUE(ranks.distributed());
    expect_owned_nodes_equal(ranks, one, "after the set-up");
    for (int round = 1; round <= 4; ++round) {
      one.run(150);
      ranks.run(150);
      expect_owned_nodes_equal(ranks, one, "step " + std::to_string(one.step_count()));
      const PeridemDiagnostics a = ranks.diagnostics(), b = one.diagnostics();
      const std::string at = " at step " + std::to_string(one.step_count());
      EXPECT_EQ(a.kinetic_energy, b.kinetic_energy) << at;
      EXPECT_EQ(a.bond_energy, b.bond_energy) << at;
      EXPECT_EQ(a.contact_energy, b.contact_energy) << at;
      EXPECT_EQ(a.max_damage, b.max_damage) << at;
      EXPECT_EQ(a.broken_bonds, b.broken_bonds) << at;
      EXPECT_EQ(a.contact_pairs, b.contact_pairs) << at;
      EXPECT_EQ(a.momentum.x, b.momentum.x) << at;
      EXPECT_EQ(a.momentum.y, b.momentum.y) << at;
      EXPECT_EQ(a.momentum.z, b.momentum.z) << at;
      const std::vector<Vec3> mine = ranks.wall_reactions(), whole = one.wall_reactions();
      ASSERT_EQ(mine.size(), whole.size());
      for (std::size_t w = 0; w < whole.size(); ++w) {
        EXPECT_EQ(mine[w].x, whole[w].x) << "reaction of grain " << w << " at step " << one.step_count();
        EXPECT_EQ(mine[w].y, whole[w].y) << "reaction of grain " << w << " at step " << one.step_count();
        EXPECT_EQ(mine[w].z, whole[w].z) << "reaction of grain " << w << " at step " << one.step_count();
      }
      if (::testing::Test::HasFailure()) return;
    }
    // The run did what it is for: grains crossed the cuts, bonds broke, the list was rebuilt alike.
    std::int64_t broken = ranks.broken_bonds(), migrated = ranks.times().grains_migrated;
    comm::allreduce_sum(&broken, 1);
    comm::allreduce_sum(&migrated, 1);
    EXPECT_EQ(broken, one.broken_bonds());
    if (tear > 0) EXPECT_GT(one.broken_bonds(), 0);
    if (comm::rank() == 0)
      std::printf("[ info ] PeriDEM %s: %ld bonds broken, %ld list builds, %lld grains moved between ranks\n",
                  grid_name(grid).c_str(), one.broken_bonds(), one.contact_rebuilds(), static_cast<long long>(migrated));
    EXPECT_EQ(ranks.contact_rebuilds(), one.contact_rebuilds());
    if (comm::size() > 1) EXPECT_GE(migrated, min_migrations) << "grains crossing the cuts";
  }
}

// The paper's damping, with walls: the floor rises into the falling field, the side wall stops its drift.
TEST(DistributedPeridem, GrainsAndWallsWithCentreDampingHaveTheOneProcessBits) {
  if (exec::offload_build()) GTEST_SKIP() << "a run cut among ranks runs on host threads so far";
  run_against_one_process(PdDamping::grain_centres, 4.0, 6.0, 3.0, 2.0, 5e-7, true, 15);
}

TEST(DistributedPeridem, NodePairDampingHasTheOneProcessBits) {
  if (exec::offload_build()) GTEST_SKIP() << "a run cut among ranks runs on host threads so far";
  // The node-pair dashpots (eqs 21-25) shake the grains apart at 5e-7 s, a third of the stable step of the
  // springs alone (which leaves the dashpots out): 50 bonds broke without any tear; none at 2e-7 s. Without
  // walls: against them the grains shatter (3,388 bonds) and reach farther past their subdomain than three
  // ranks along y allow.
  run_against_one_process(PdDamping::node_pairs, 4.0, 6.0, 3.0, 2.0, 2e-7, false, 1);
}

// A grain torn apart whose halves fly off far: its reach grows past half a subdomain, and every rank stops
// at the same step with the same RunStop (the runner's exit 3, the run continuing on fewer ranks from its
// checkpoint), none alone.
TEST(DistributedPeridem, AGrainGrownTooLargeForTheRanksStopsEveryRankAlike) {
  if (exec::offload_build()) GTEST_SKIP() << "a run cut among ranks runs on host threads so far";
  if (comm::size() < 2) GTEST_SKIP() << "one rank holds every grain";
  PeridemSimulation ranks = make_field(8, 5, 5, 0.0, 0.0, 100.0, 0.01, 5e-7, false, PdDamping::grain_centres);
  ranks.distribute({comm::size(), 1, 1});
  std::string stop;
  long at = -1;
  for (int s = 0; s < 2000 && stop.empty(); ++s) {
    try {
      ranks.step();
    } catch (const RunStop& e) {
      stop = e.what();
      at = ranks.step_count();
    }
  }
  ASSERT_FALSE(stop.empty()) << "the torn grain never outgrew the ranks";
  EXPECT_NE(stop.find("'mpirun -np' = " + std::to_string(comm::size())), std::string::npos) << stop;
  EXPECT_NE(stop.find("continue on fewer ranks"), std::string::npos) << stop;
  EXPECT_EQ(comm::first_message(stop), stop) << "every rank says the same";
  double first = static_cast<double>(at), last = first;
  comm::allreduce_min(&first, 1);
  comm::allreduce_max(&last, 1);
  EXPECT_EQ(first, last) << "every rank stops at the same step";
  if (comm::rank() == 0) std::printf("[ info ] stopped at step %ld: %s\n", at, stop.c_str());
}

}  // namespace
}  // namespace debris
