// Checkpoint and restart: N + N steps equals N steps, checkpoint, restart, N steps, bit for bit on the host,
// for both contact passes; a checkpoint is written atomically (a run killed while writing checkpoints
// always leaves a complete one).
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <random>

#include "core/error.hpp"
#include "core/lattice.hpp"
#include "scenarios/common/dem_simulation.hpp"

namespace debris {
namespace {

namespace fs = std::filesystem;

// wide: every third free particle shrunk to d = 45 (size ratio 2.3), so the neighbour search uses size
// classes and the default skin follows the mean radius.
DemSimulation sheared_system(PairPass pass, bool wide = false) {
  LatticeSpec l;
  l.kind = LatticeKind::hcp;
  l.spacing = 100;
  l.diameter = 100;
  l.size_spread = 0.04;
  l.displacement = 1.0;
  l.cells = {5, 4, 2};
  Lattice lat = make_lattice(l);
  Box box(lat.box.lo(), lat.box.hi(), {true, false, true});
  Particles p = lat.particles;
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<double> u(-0.01, 0.01);
  for (std::size_t i = 0; i < p.size(); ++i) p.vx[i] = u(rng), p.vy[i] = u(rng), p.wz[i] = u(rng) / 50;
  Groups g;
  Group top{"top", GroupMotion::force};
  top.external_force = {20.0, -50.0, 0.0};  // a sheared, loaded wall: its rigid velocity is state too
  Group bottom{"bottom", GroupMotion::frozen};
  Group probe{"probe", GroupMotion::free};
  const int gt = g.add(top), gb = g.add(bottom), gp = g.add(probe);
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p.y[i] > box.hi().y - 90) p.group[i] = gt;
    else if (p.y[i] < box.lo().y + 90) p.group[i] = gb;
    else if (p.x[i] < 200) p.group[i] = gp;
    if (wide && p.group[i] < 0 && i % 3 == 0) p.radius[i] = 22.5;
  }
  DemSettings s;
  s.material = table4_material();
  s.material.restitution = 0.9;
  s.time_step_fraction = 0.1;
  s.global_damping = 0.02;
  s.skin = wide ? 0.0 : 0.5;  // small: many rebuilds on both sides of the checkpoint
  s.pair_pass = pass;
  return DemSimulation(box, p, g, s);
}

void expect_identical(DemSimulation& a, DemSimulation& b) {
  EXPECT_EQ(a.step_count(), b.step_count());
  EXPECT_EQ(a.time(), b.time());
  Particles& pa = a.particles();
  Particles& pb = b.particles();
  ASSERT_EQ(pa.size(), pb.size());
  // Same storage order too (the restart keeps the list and the order it was built for).
  pa.for_each_column([&](const char* name, auto& col) {
    bool found = false;
    pb.for_each_column([&](const char* other, auto& col_b) {
      if (std::string(name) != other) return;
      found = true;
      if constexpr (std::is_same_v<std::decay_t<decltype(col)>, std::decay_t<decltype(col_b)>>) {
        for (std::size_t i = 0; i < col.size(); ++i) ASSERT_EQ(col[i], col_b[i]) << name << "[" << i << "]";
      }
    });
    EXPECT_TRUE(found);
  });
  EXPECT_EQ(a.history().hx, b.history().hx);
  EXPECT_EQ(a.history().hy, b.history().hy);
  for (std::size_t g = 0; g < a.groups().size(); ++g) {
    EXPECT_EQ(a.groups().list[g].velocity.x, b.groups().list[g].velocity.x);
    EXPECT_EQ(a.groups().list[g].displacement.y, b.groups().list[g].displacement.y);
    EXPECT_EQ(a.groups().list[g].reaction.x, b.groups().list[g].reaction.x);
  }
}

void expect_restart_bit_for_bit(PairPass pass, bool wide = false) {
  const long n = 300;
  DemSimulation straight = sheared_system(pass, wide);
  straight.run(2 * n);
  if (wide) EXPECT_GT(straight.neighbors().size_classes().count, 1);
  DemSimulation first = sheared_system(pass, wide);
  first.run(n);
  // One file per test: ctest -j runs the two passes' tests in parallel processes.
  const fs::path ckpt = fs::path(::testing::TempDir()) /
                        ("debris_restart_" + std::string(pass == PairPass::half ? "half" : "full") +
                         (wide ? "_wide" : "") + ".h5");
  first.write_checkpoint(ckpt.string(), "run: {steps: 600}\n");
  std::string echo;
  DemSimulation resumed = DemSimulation::from_checkpoint(ckpt.string(), &echo);
  EXPECT_EQ(echo, "run: {steps: 600}\n");
  EXPECT_EQ(resumed.step_count(), n);
  resumed.run(n);
  ASSERT_GT(straight.times().rebuilds, 3) << "the test needs rebuilds on both sides of the checkpoint";
  expect_identical(straight, resumed);
  // The state moved: this is not a system at rest.
  EXPECT_GT(std::abs(straight.groups().list[0].displacement.x), 1e-3);
}

TEST(DemRestart, BitForBitHalfListPass) { expect_restart_bit_for_bit(PairPass::half); }
TEST(DemRestart, BitForBitFullListPass) { expect_restart_bit_for_bit(PairPass::full); }
TEST(DemRestart, BitForBitWithSizeClasses) { expect_restart_bit_for_bit(PairPass::half, true); }

TEST(DemRestart, MissingCheckpointIsAnInputError) {
  try {
    DemSimulation::from_checkpoint("/nonexistent/ckpt.h5");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/ckpt.h5"), std::string::npos);
  }
}

// A child writes checkpoints in a loop and is killed at a random moment, many times: the checkpoint file
// is always complete and loads (the write goes to .tmp and is renamed only when closed).
TEST(DemRestart, KilledWhileWritingLeavesAWholeCheckpoint) {
  const fs::path ckpt = fs::path(::testing::TempDir()) / "debris_killed.h5";
  DemSimulation sim = sheared_system(PairPass::half);
  sim.write_checkpoint(ckpt.string(), "first");
  for (int attempt = 0; attempt < 5; ++attempt) {
    const pid_t child = fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
      for (;;) sim.write_checkpoint(ckpt.string(), "again");
    }
    usleep(20000 + 13000 * attempt);
    kill(child, SIGKILL);
    int status = 0;
    waitpid(child, &status, 0);
    std::string echo;
    DemSimulation back = DemSimulation::from_checkpoint(ckpt.string(), &echo);
    EXPECT_TRUE(echo == "first" || echo == "again") << echo;
    EXPECT_EQ(back.particles().size(), sim.particles().size());
  }
}

}  // namespace
}  // namespace debris
