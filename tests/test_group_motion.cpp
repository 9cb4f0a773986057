// Force groups with a per-axis velocity (the adhesive-wear junction's top wall: x driven, z held, y free
// under a normal load): reading `velocity: [v, free, 0]` with read_group_motion, the errors it gives, the
// load held by the free axis while the prescribed axes keep their velocity bit for bit, and the mask
// surviving a checkpoint.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

#include "core/error.hpp"
#include "core/io/hdf5_file.hpp"
#include "core/io/input.hpp"
#include "scenarios/common/dem/dem_input.hpp"
#include "scenarios/common/dem/dem_simulation.hpp"
#include "tests/cli_helpers.hpp"

namespace debris {
namespace {

namespace fs = std::filesystem;

const Box kBox({0, 0, 0}, {2e-9, 6e-9, 3e-9}, {true, false, true});

// The first group of `groups: [...]`, read from `yaml` (one group's keys).
Group motion_of(const std::string& group_yaml, Group g = Group{}) {
  const InputNode root = InputNode::load_string("groups:\n  - " + group_yaml + "\n", "test.yaml");
  read_group_motion(root.list("groups")[0], kBox, g);
  return g;
}

std::string error_of(const std::string& group_yaml) {
  try {
    motion_of(group_yaml);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(GroupMotion, PerAxisVelocityUnderStress) {
  const Group g = motion_of("{motion: force, velocity: [10 m/s, free, 0], stress: [0, -100 MPa, 0]}");
  EXPECT_EQ(g.motion, GroupMotion::force);
  EXPECT_EQ(g.prescribed, (std::array<bool, 3>{true, false, true}));
  EXPECT_EQ(g.velocity.x, 10.0);
  EXPECT_EQ(g.velocity.y, 0.0);
  EXPECT_EQ(g.velocity.z, 0.0);
  EXPECT_DOUBLE_EQ(g.external_force.y, -1e8 * 2e-9 * 3e-9);  // stress times the x-z area
  EXPECT_EQ(g.external_force.x, 0.0);
  EXPECT_EQ(g.external_force.z, 0.0);
}

TEST(GroupMotion, InitialVelocityStartsTheFreeAxes) {
  const Group g = motion_of("{motion: force, velocity: [10 m/s, free, 0], force: [0, -1 nN, 0],"
                            " initial_velocity: [10 m/s, -2 m/s, 0]}");
  EXPECT_EQ(g.velocity.x, 10.0);
  EXPECT_EQ(g.velocity.y, -2.0);
  EXPECT_EQ(g.external_force.y, -1e-9);
  // Without a velocity key every axis is free, as before.
  const Group all_free = motion_of("{motion: force, force: [1 nN, 0, 0], initial_velocity: [1 m/s, 2 m/s, 3 m/s]}");
  EXPECT_EQ(all_free.prescribed, (std::array<bool, 3>{false, false, false}));
  EXPECT_EQ(all_free.velocity.z, 3.0);
}

TEST(GroupMotion, EveryMotionFieldIsReset) {
  Group old{"top", GroupMotion::force, {1, 2, 3}, {4, 5, 6}};
  old.prescribed = {true, true, false};
  old.count = 7;
  old.mass = 8;
  old.displacement = {9, 9, 9};
  // A stage's node with motion keys only (no name, no region), read from the root of its document.
  const InputNode stage = InputNode::load_string("motion: frozen\n", "stage.yaml");
  read_group_motion(stage, kBox, old);
  stage.reject_unknown_keys();
  EXPECT_EQ(old.motion, GroupMotion::frozen);
  EXPECT_EQ(old.velocity.x, 0.0);
  EXPECT_EQ(old.external_force.y, 0.0);
  EXPECT_EQ(old.prescribed, (std::array<bool, 3>{false, false, false}));
  // Name, membership and measured values are not motion.
  EXPECT_EQ(old.name, "top");
  EXPECT_EQ(old.count, 7);
  EXPECT_EQ(old.mass, 8.0);
  EXPECT_EQ(old.displacement.x, 9.0);
  // An empty node is a free group.
  read_group_motion(InputNode::load_string("{}", "empty.yaml"), kBox, old);
  EXPECT_EQ(old.motion, GroupMotion::free);
  // Errors of a root-level node name the bare key, and leave the group as it was.
  read_group_motion(InputNode::load_string("{motion: velocity, velocity: [1, 2, 3]}", "v.yaml"), kBox, old);
  try {
    read_group_motion(InputNode::load_string("{motion: force, velocity: [1, free, 0], force: [2, 0, 0]}", "s.yaml"),
                      kBox, old);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("'force' = [2, 0, 0]"), std::string::npos) << e.what();
  }
  EXPECT_EQ(old.motion, GroupMotion::velocity);
  EXPECT_EQ(old.velocity.y, 2.0);
  EXPECT_EQ(old.prescribed, (std::array<bool, 3>{false, false, false}));
}

TEST(GroupMotion, LoadOnAPrescribedAxisIsAnInputError) {
  const std::string s = error_of("{motion: force, velocity: [10 m/s, free, 0], stress: [5 MPa, -100 MPa, 0]}");
  EXPECT_NE(s.find("'groups[0].stress' = [5 MPa, -100 MPa, 0]"), std::string::npos) << s;
  EXPECT_NE(s.find("x velocity is prescribed"), std::string::npos) << s;
  const std::string f = error_of("{motion: force, velocity: [free, free, 0 m/s], force: [0, -1 nN, 2 nN]}");
  EXPECT_NE(f.find("'groups[0].force' = [0, -1 nN, 2 nN]"), std::string::npos) << f;
  EXPECT_NE(f.find("z velocity is prescribed"), std::string::npos) << f;
}

TEST(GroupMotion, OtherBadPerAxisInputs) {
  const std::string conflict =
      error_of("{motion: force, velocity: [10 m/s, free, 0], force: [0, -1, 0], initial_velocity: [3 m/s, 0, 0]}");
  EXPECT_NE(conflict.find("'groups[0].initial_velocity' = [3 m/s, 0, 0]"), std::string::npos) << conflict;
  const std::string in_velocity_group = error_of("{motion: velocity, velocity: [10 m/s, free, 0]}");
  EXPECT_NE(in_velocity_group.find("'groups[0].velocity' = [10 m/s, free, 0]"), std::string::npos) << in_velocity_group;
  EXPECT_NE(in_velocity_group.find("motion: force"), std::string::npos) << in_velocity_group;
  const std::string two = error_of("{motion: force, velocity: [10 m/s, free], force: [0, -1, 0]}");
  EXPECT_NE(two.find("'groups[0].velocity' = 2 values"), std::string::npos) << two;
  const std::string word = error_of("{motion: force, velocity: [fast, free, 0], force: [0, -1, 0]}");
  EXPECT_NE(word.find("groups[0].velocity[0]"), std::string::npos) << word;
  EXPECT_NE(word.find("fast"), std::string::npos) << word;
}

// A cohesive HCP slab (Table 4 material, no units) between a frozen bottom wall and a top wall driven
// along x at `vx`, held along z and loaded along y by `stress` over the x-z area.
std::string slab_input(double vx, double stress) {
  return std::string(debris::test::kTable4MaterialYaml) + R"(particles:
  lattice:
    kind: hcp
    hcp_c_axis: y
    spacing: 100
    diameter: 100
    cells: [6, 6, 4]
box:
  periodic: [true, false, true]
groups:
  - name: bottom
    region: {y: [-inf, 170]}
    motion: frozen
  - name: top
    region: {y: [800, inf]}
    motion: force
    velocity: [)" + format_value(vx) + R"(, free, 0]
    stress: [0, )" + format_value(-stress) + R"(, 0]
run:
  steps: 0
  time_step_fraction: 0.1
  global_damping: 0.2
)";
}

DemSimulation slab(double vx, double stress) {
  DemRunConfig cfg = read_dem_input_text(slab_input(vx, stress), "slab.yaml", "");
  return DemSimulation(cfg.box, std::move(cfg.particles), std::move(cfg.groups), cfg.settings);
}

TEST(GroupMotion, PerAxisDriveHoldsTheLoadAndKeepsTheVelocity) {
  const double vx = 2e-4, stress = 0.01;
  DemSimulation sim = slab(vx, stress);
  const Group& top = sim.groups().list[1];
  ASSERT_EQ(top.count * 6, static_cast<long>(sim.particles().size())) << "top wall: two of twelve layers";
  const double area = sim.box().length(0) * sim.box().length(2);
  EXPECT_DOUBLE_EQ(top.external_force.y, -stress * area);

  auto expect_exact_drive = [&] {
    ASSERT_EQ(top.velocity.x, vx);
    ASSERT_EQ(top.velocity.z, 0.0);
    const Particles& p = sim.particles();
    for (std::size_t i = 0; i < p.size(); ++i) {
      if (p.group[i] != 1) continue;
      ASSERT_EQ(p.vx[i], vx) << "member " << p.id[i];
      ASSERT_EQ(p.vz[i], 0.0) << "member " << p.id[i];
    }
  };
  const long settle = 3000, window = 2000;
  for (long s = 0; s < settle; ++s) {
    sim.step();
    if (s % 500 == 0) expect_exact_drive();
  }
  double sum = 0.0;
  for (long s = 0; s < window; ++s) {
    sim.step();
    sum += top.reaction.y;
  }
  expect_exact_drive();
  const double mean = sum / static_cast<double>(window);
  EXPECT_NEAR(mean, stress * area, 0.01 * stress * area) << "mean normal reaction over " << window << " steps";
  // The wall slid at the prescribed speed and sank into the slab under the load.
  const double t = static_cast<double>(settle + window) * sim.dt();
  EXPECT_NEAR(top.displacement.x, vx * t, 1e-9 * vx * t);
  EXPECT_EQ(top.displacement.z, 0.0);
  EXPECT_LT(top.displacement.y, 0.0);
  // It also measured the friction the drive overcomes (the x reaction is not kicked, but reported).
  EXPECT_NE(top.reaction.x, 0.0);
}

TEST(GroupMotion, CheckpointKeepsTheMaskAndContinuesBitForBit) {
  const long n = 200;
  DemSimulation straight = slab(2e-4, 0.01);
  straight.run(2 * n);
  DemSimulation first = slab(2e-4, 0.01);
  first.run(n);
  const fs::path ckpt = fs::path(::testing::TempDir()) / "debris_group_mask.h5";
  first.write_checkpoint(ckpt.string(), "echo");
  DemSimulation resumed = DemSimulation::from_checkpoint(ckpt.string());
  EXPECT_EQ(resumed.groups().list[1].prescribed, (std::array<bool, 3>{true, false, true}));
  EXPECT_EQ(resumed.groups().list[0].prescribed, (std::array<bool, 3>{false, false, false}));
  resumed.run(n);
  const Particles &a = straight.particles(), &b = resumed.particles();
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(a.x[i], b.x[i]);
    ASSERT_EQ(a.y[i], b.y[i]);
    ASSERT_EQ(a.vx[i], b.vx[i]);
  }
  EXPECT_EQ(straight.groups().list[1].velocity.y, resumed.groups().list[1].velocity.y);
  EXPECT_EQ(straight.groups().list[1].reaction.x, resumed.groups().list[1].reaction.x);
}

// A file of the former format (before groups/prescribed, and before seals) is refused before it is read.
TEST(GroupMotion, CheckpointOfTheFormerFormatIsRefused) {
  const fs::path old = fs::path(::testing::TempDir()) / "debris_group_old_format.h5";
  {
    h5::File f(old.string(), h5::File::Mode::create);
    f.set_attribute<std::int64_t>("format_version", 1);  // before groups/prescribed
    f.write_string("input", "");
    f.close();
  }
  try {
    DemSimulation::from_checkpoint(old.string());
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("checksums are missing"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(old.string()), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace debris
