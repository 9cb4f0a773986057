// Checkpoint and restart: N + N steps equals N steps, checkpoint, restart, N steps, bit for bit on the host,
// for both contact passes; a checkpoint is written atomically (a run killed while writing checkpoints
// always leaves a complete one).
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>

#include "core/error.hpp"
#include "scenarios/common/dem/dem_simulation.hpp"
#include "tests/dem_samples.hpp"

namespace debris {
namespace {

namespace fs = std::filesystem;

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
  DemSimulation straight = test::sheared_dem_system(pass, wide);
  straight.run(2 * n);
  if (wide) EXPECT_GT(straight.neighbors().size_classes().count, 1);
  DemSimulation first = test::sheared_dem_system(pass, wide);
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
  DemSimulation sim = test::sheared_dem_system(PairPass::half);
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
