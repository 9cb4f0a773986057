// Rigid groups on any thread count: a force group's reaction moves it (kick_rigid_groups), so its sum must have
// the same bits whatever the number of threads. The default debris_dem input (a top wall loaded by a
// stress), enlarged to span several of the fixed summation blocks, gives bit-identical states on 1 and 2
// threads, and a checkpoint written on 2 threads and continued on 1 equals the uninterrupted run.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "core/exec.hpp"
#include "core/io/input.hpp"
#include "scenarios/common/dem/dem_input.hpp"
#include "scenarios/common/dem/dem_simulation.hpp"

namespace debris {
namespace {

namespace fs = std::filesystem;

// Sets the thread count for a scope and puts the previous one back.
struct Threads {
  int saved;
  explicit Threads(int n) : saved(exec::threads()) { exec::set_threads(n); }
  ~Threads() { exec::set_threads(saved); }
};

// scenarios/dem/hcp_wall_load.yaml with 17 x 8 x 8 HCP cells (4352 particles: two full summation blocks and a
// partial one, each wall's members spread over all three after the sort by cell).
DemSimulation default_system() {
  std::string text = read_input_file(std::string(DEBRIS_SOURCE_DIR) + "/scenarios/dem/hcp_wall_load.yaml");
  const std::string from = "cells: [10, 8, 5]";
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << "default.yaml changed: update this test";
  if (at != std::string::npos) text.replace(at, from.size(), "cells: [17, 8, 8]");
  DemRunConfig cfg = read_dem_input_text(text, "default.yaml", "");
  EXPECT_EQ(cfg.groups.list.at(1).motion, GroupMotion::force);
  return DemSimulation(cfg.box, std::move(cfg.particles), std::move(cfg.groups), cfg.settings);
}

double component(Vec3 v, int k) { return k == 0 ? v.x : (k == 1 ? v.y : v.z); }

void expect_identical(const DemSimulation& a, const DemSimulation& b) {
  ASSERT_EQ(a.step_count(), b.step_count());
  EXPECT_EQ(a.time(), b.time());
  const Particles& pa = a.particles();
  const Particles& pb = b.particles();
  ASSERT_EQ(pa.size(), pb.size());
  const_cast<Particles&>(pa).for_each_column([&](const char* name, auto& col) {
    const_cast<Particles&>(pb).for_each_column([&](const char* other, auto& col_b) {
      if (std::string(name) != other) return;
      if constexpr (std::is_same_v<std::decay_t<decltype(col)>, std::decay_t<decltype(col_b)>>) {
        for (std::size_t i = 0; i < col.size(); ++i) ASSERT_EQ(col[i], col_b[i]) << name << "[" << i << "]";
      }
    });
  });
  ASSERT_EQ(a.groups().size(), b.groups().size());
  for (std::size_t g = 0; g < a.groups().size(); ++g) {
    const Group &ga = a.groups().list[g], &gb = b.groups().list[g];
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(component(ga.reaction, k), component(gb.reaction, k)) << ga.name << " reaction " << k;
      EXPECT_EQ(component(ga.velocity, k), component(gb.velocity, k)) << ga.name << " velocity " << k;
      EXPECT_EQ(component(ga.displacement, k), component(gb.displacement, k)) << ga.name << " displacement " << k;
    }
  }
}

constexpr long kSteps = 300;  // the unfixed sums parted from step ~100 on

TEST(GroupDeterminism, ForceGroupBitIdenticalOnOneAndTwoThreads) {
  DemSimulation one = [] {
    Threads t(1);
    DemSimulation s = default_system();
    s.run(kSteps);
    return s;
  }();
  DemSimulation two = [] {
    Threads t(2);
    DemSimulation s = default_system();
    s.run(kSteps);
    return s;
  }();
  ASSERT_GT(one.particles().size(), 2u * 2048u);
  // The wall moved under its load: the test compares a state that depends on the reaction.
  EXPECT_NE(one.groups().list[1].velocity.y, 0.0);
  expect_identical(one, two);
}

TEST(GroupDeterminism, CheckpointOnTwoThreadsContinuedOnOne) {
  DemSimulation straight = [] {
    Threads t(2);
    DemSimulation s = default_system();
    s.run(2 * kSteps);
    return s;
  }();
  const fs::path ckpt = fs::path(::testing::TempDir()) / "debris_group_threads.h5";
  {
    Threads t(2);
    DemSimulation first = default_system();
    first.run(kSteps);
    first.write_checkpoint(ckpt.string(), "echo");
  }
  Threads t(1);
  DemSimulation resumed = DemSimulation::from_checkpoint(ckpt.string());
  resumed.run(kSteps);
  expect_identical(straight, resumed);
}

}  // namespace
}  // namespace debris
