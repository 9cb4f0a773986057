// PeriDEM checkpoint and restart: N + N steps equals N steps, checkpoint, restart, N steps, bit for bit on
// the host, with bonds broken before the checkpoint and contact-list rebuilds on both sides of it; the
// checkpoint is written atomically (a run killed while writing checkpoints always leaves a whole one), and a
// run killed while writing node frames leaves an .xmf whose every frame reads back from the .h5.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "core/error.hpp"
#include "core/exec.hpp"
#include "core/io/hdf5_file.hpp"
#include "core/io/node_trajectory_writer.hpp"
#include "scenarios/common/peridem/peridem_input.hpp"
#include "scenarios/common/peridem/peridem_simulation.hpp"
#include "tests/cli_helpers.hpp"
#include "tests/pd_state_equality.hpp"

namespace debris {
namespace {

namespace fs = std::filesystem;

fs::path scratch(const std::string& name) { return debris::test::fresh_directory("debris_peridem_restart_" + name); }

// A fast impact that cracks both grains within a few hundred steps: a disc of R = 1 mm resting on a wall
// is hit at 10 m/s by a disc of R = 1.5 mm that starts just beyond the contact radius. Coarse meshes
// (Gmsh size 0.3 mm) and node-pair damping (the other damping of section 2.3, so both are checkpointed).
std::string impact_yaml(const std::string& damping) {
  return R"(dimension: 2
materials:
  M1: {density: 1200 kg/m^3, bulk_modulus: 0.0216 GPa, shear_modulus: 0.01296 GPa, fracture_energy: 50 J/m^2, horizon: 0.6 mm}
shapes:
  small: {type: circle, radius: 1 mm, mesh_size: 0.3 mm}
  large: {type: circle, radius: 1.5 mm, mesh_size: 0.3 mm}
  floor: {type: rectangle, lo: [-3 mm, -0.6 mm, 0], hi: [3 mm, 0, 0], mesh_size: 0.3 mm}
grains:
  - {name: bottom, shape: small, material: M1, centre: [0, 1.18 mm, 0]}
  - {name: top, shape: large, material: M1, centre: [0.1 mm, 3.86 mm, 0], rotation: 0.3, velocity: [0, -10 m/s, 0]}
walls:
  - {name: floor, shape: floor, material: M1}
contact: {restitution: 0.9, friction: 0.3, damping: )" +
         damping + R"(}
gravity: [0, -10 m/s^2, 0]
run: {time_step: 0.1 us, steps: 1000, skin: 0.05 mm}
)";
}

PeridemSimulation make(const std::string& damping, const fs::path& dir) {
  PeridemInputOptions o;
  o.output_directory = dir.string();
  PeridemRunConfig cfg = read_peridem_input_text(impact_yaml(damping), "impact.yaml", "", o);
  PeridemSimulation sim(std::move(cfg.nodes), std::move(cfg.grains), cfg.materials, cfg.contact, cfg.settings);
  sim.set_grain_names(cfg.grain_names);
  return sim;
}


void expect_restart_bit_for_bit(const std::string& damping) {
  const fs::path dir = scratch(damping);
  const long n = 500;
  PeridemSimulation straight = make(damping, dir);
  straight.run(2 * n);
  PeridemSimulation first = make(damping, dir);
  first.run(n);
  ASSERT_GT(first.broken_bonds(), 0) << "the test needs bonds broken before the checkpoint";
  const long rebuilds_at_checkpoint = first.contact_rebuilds();
  const fs::path ckpt = dir / "checkpoint.h5";
  first.write_checkpoint(ckpt.string(), "run: {steps: 1000}\n");
  std::string echo;
  PeridemSimulation resumed = PeridemSimulation::from_checkpoint(ckpt.string(), &echo);
  EXPECT_EQ(echo, "run: {steps: 1000}\n");
  EXPECT_EQ(resumed.step_count(), n);
  EXPECT_EQ(resumed.stable_time_step(), first.stable_time_step());
  resumed.run(n);
  ASSERT_GT(straight.contact_rebuilds(), rebuilds_at_checkpoint + 3) << "the test needs rebuilds after the checkpoint";
  ASSERT_GT(straight.broken_bonds(), first.broken_bonds()) << "and bonds breaking after it";
  test::expect_same_pd_state(straight, resumed);
}

// The thread tuner (core/thread_tuner.hpp) changes the thread count between steps while a run goes on: a run
// whose count changes every few steps is bit for bit the run on one thread, bonds breaking and lists rebuilt.
TEST(PeridemThreads, CountChangedBetweenStepsGivesTheSameBits) {
  const int saved = exec::threads();
  const fs::path dir = scratch("threads");
  exec::set_threads(1);
  PeridemSimulation fixed = make("node_pairs", dir);
  fixed.run(600);
  PeridemSimulation changing = make("node_pairs", dir);
  for (long k = 0; k < 600; ++k) {
    exec::set_threads(1 + static_cast<int>((k / 7) % 2));
    changing.step();
  }
  exec::set_threads(saved);
  ASSERT_GT(fixed.broken_bonds(), 0);
  ASSERT_GT(fixed.contact_rebuilds(), 2);
  test::expect_same_pd_state(fixed, changing);
}

TEST(PeridemRestart, BitForBitWithBrokenBondsGrainCentreDamping) { expect_restart_bit_for_bit("grain_centres"); }
TEST(PeridemRestart, BitForBitWithBrokenBondsNodePairDamping) { expect_restart_bit_for_bit("node_pairs"); }

TEST(PeridemRestart, MissingOrForeignCheckpointIsAnInputError) {
  try {
    PeridemSimulation::from_checkpoint("/nonexistent/ckpt.h5");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/ckpt.h5"), std::string::npos);
  }
  const fs::path other = scratch("foreign") / "other.h5";
  {
    h5::File f(other.string(), h5::File::Mode::create);
    f.set_attribute<std::int64_t>("format_version", 1);
    f.write_string("input", "");
    f.close();
  }
  try {
    PeridemSimulation::from_checkpoint(other.string());
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("not a debris_peridem checkpoint"), std::string::npos) << e.what();
  }
}

// A child writes checkpoints in a loop and is killed at a random moment, several times: the checkpoint file
// is always whole and loads (written to .tmp, renamed when closed).
TEST(PeridemRestart, KilledWhileWritingLeavesAWholeCheckpoint) {
  const fs::path dir = scratch("killed");
  const fs::path ckpt = dir / "checkpoint.h5";
  PeridemSimulation sim = make("grain_centres", dir);
  sim.run(5);
  sim.write_checkpoint(ckpt.string(), "first");
  for (int attempt = 0; attempt < 4; ++attempt) {
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
    PeridemSimulation back = PeridemSimulation::from_checkpoint(ckpt.string(), &echo);
    EXPECT_TRUE(echo == "first" || echo == "again") << echo;
    EXPECT_EQ(back.nodes().size(), sim.nodes().size());
    EXPECT_EQ(back.step_count(), 5);
  }
}

// ---- the node trajectory of a killed run ----

/// Frame k of the killed writer: 60 nodes in two grains, positions and damage that encode k.
void killed_frame(long k, PdNodes& n) {
  for (std::size_t i = 0; i < n.size(); ++i) {
    const double d = static_cast<double>(i + 1);
    n.x[i] = d + 0.001 * static_cast<double>(k);
    n.y[i] = -d / 3.0;
    n.vx[i] = static_cast<double>(k);
    n.damage[i] = d / 64.0 + static_cast<double>(k);
  }
}


// A child writes frames in a loop and is killed at different moments after its second frame was listed:
// every frame its .xmf lists reads back whole (the writer commits a frame in two steps, then the .xmf).
TEST(PeridemRestart, KilledTrajectoryWriterLeavesEveryListedFrameReadable) {
  PdNodes nodes;
  PdGrains grains;
  grains.resize(2);
  for (int i = 0; i < 60; ++i) nodes.add(i + 1, i < 30 ? 0 : 1, 0.0, 0.0, 0.0, 1e-8);
  grains.node_begin = {0, 30};
  grains.node_end = {30, 60};
  grains.kind = {0, 1};
  int round = 0;
  for (const auto delay :
       {std::chrono::microseconds(0), std::chrono::microseconds(700), std::chrono::microseconds(2300)}) {
    SCOPED_TRACE("kill " + std::to_string(delay.count()) + " us after the second frame was listed");
    const fs::path dir = scratch("killed_trajectory_" + std::to_string(round++));
    const fs::path xmf = dir / "nodes.xmf";
    const pid_t child = fork();
    ASSERT_GE(child, 0);
    if (child == 0) {  // never return into the test framework from here
      try {
        NodeTrajectoryWriter w(dir.string(), "nodes", nodes, grains, {"grain", "wall"});
        const std::vector<double> fraction(nodes.size(), 0.25);
        for (long k = 0; k < 1000000; ++k) {
          killed_frame(k, nodes);
          w.write_frame(k, 0.5 * static_cast<double>(k), nodes, fraction);
        }
      } catch (...) {
        _exit(3);
      }
      _exit(0);
    }
    const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(30);
    while ((!fs::exists(xmf) || debris::test::count_xmf_frames(xmf) < 2) && std::chrono::steady_clock::now() < give_up)
      std::this_thread::sleep_for(std::chrono::microseconds(200));
    std::this_thread::sleep_for(delay);
    kill(child, SIGKILL);
    int status = 0;
    ASSERT_EQ(waitpid(child, &status, 0), child);
    ASSERT_TRUE(WIFSIGNALED(status)) << "the writer ended by itself, status " << status;
    const int frames = debris::test::count_xmf_frames(xmf);
    ASSERT_GE(frames, 2);
    const h5::File f((dir / "nodes.h5").string(), h5::File::Mode::read_only);
    EXPECT_EQ(f.read<std::int64_t>("nodes/id").values.size(), 60u);
    EXPECT_EQ(f.read_strings("grains/name"), (std::vector<std::string>{"grain", "wall"}));
    for (long k = 0; k < frames; ++k) {
      SCOPED_TRACE("frame " + std::to_string(k));
      const h5::Group g = f.open_group("frames/" + std::to_string(k));
      EXPECT_EQ(g.attribute<std::int64_t>("step"), k);
      const std::vector<double> pos = g.read<double>("position").values;
      const std::vector<double> damage = g.read<double>("damage").values;
      ASSERT_EQ(pos.size(), 180u);
      ASSERT_EQ(damage.size(), 60u);
      for (std::size_t i = 0; i < 60; ++i) {
        ASSERT_EQ(pos[3 * i], static_cast<double>(i + 1) + 0.001 * static_cast<double>(k));
        ASSERT_EQ(damage[i], static_cast<double>(i + 1) / 64.0 + static_cast<double>(k));
      }
      EXPECT_EQ(g.read<double>("broken_fraction").values, std::vector<double>(60, 0.25));
    }
  }
}

}  // namespace
}  // namespace debris
