// Parallel HDF5 output: one dataset written by every rank, each its own rows (collective), and the trajectory
// of a run cut among ranks, which must be the file one process writes, row for row, bit for bit.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "core/comm/communicator.hpp"
#include "core/io/hdf5_file.hpp"
#include "core/io/trajectory_writer.hpp"
#include "scenarios/common/dem/dem_simulation.hpp"
#include "tests/mpi/cohesive_block.hpp"
#include "tests/mpi/rank_grids.hpp"

namespace debris::comm {
namespace {

namespace fs = std::filesystem;

// A directory every rank knows (rank 0 names and makes it).
std::string shared_directory(const std::string& stem) {
  const std::string dir = first_message(
      rank() == 0 ? (fs::temp_directory_path() / (stem + "_" + std::to_string(::getpid()))).string() : "");
  if (rank() == 0) fs::create_directories(dir);
  barrier();
  return dir;
}

// The value stored in row r, column c: exact in a double, different in every row and column.
double value_at(std::int64_t r, int c) { return 1000.0 * static_cast<double>(r) + c + 0.25; }

TEST(ParallelHdf5, EveryRankWritesItsOwnRowsOfOneDataset) {
  const std::string dir = shared_directory("debris_mpi_rows");
  const std::string path = dir + "/rows.h5";
  // Rows dealt in runs of 1 to 3 (blocks of consecutive rows and single rows); from 3 ranks up, the last
  // rank holds none and still takes part in every collective write.
  const std::int64_t total = 101;
  const int dealers = size() >= 3 ? size() - 1 : size();
  std::vector<std::int64_t> mine;
  std::vector<double> xyz;
  std::vector<std::int32_t> tag;
  for (std::int64_t r = 0; r < total; ++r)
    if ((r / (1 + r % 3)) % dealers == rank()) {
      mine.push_back(r);
      for (int c = 0; c < 3; ++c) xyz.push_back(value_at(r, c));
      tag.push_back(static_cast<std::int32_t>(7 * r));
    }
  {
    h5::File f(path, h5::File::Mode::create, {.all_ranks = true});
    EXPECT_EQ(f.on_all_ranks(), size() > 1);
    {
      h5::Group g = f.create_group("frame");
      g.write_rows<double>("xyz", xyz, mine, {static_cast<std::size_t>(total), 3});
      g.write_rows<std::int32_t>("tag", tag, mine, {static_cast<std::size_t>(total)});
      // Whole-dataset writes and attributes: every rank calls alike, rank 0's values are stored (a string's
      // length is its type, so it too must be every rank's alike).
      g.write("whole", std::vector<double>{static_cast<double>(rank()), 2.0});
      g.write_strings("names", {"rank " + std::to_string(rank() % 10), "b"});
      g.set_attribute("step", std::int64_t{42});
    }
    f.flush();
    f.close();
  }
  barrier();
  const h5::File f(path, h5::File::Mode::read_only);
  const auto xyz_read = f.read<double>("frame/xyz");
  ASSERT_EQ(xyz_read.shape, (h5::Shape{static_cast<std::size_t>(total), 3}));
  const auto tag_read = f.read<std::int32_t>("frame/tag").values;
  for (std::int64_t r = 0; r < total; ++r) {
    for (int c = 0; c < 3; ++c) EXPECT_EQ(xyz_read.values[static_cast<std::size_t>(3 * r + c)], value_at(r, c)) << r;
    EXPECT_EQ(tag_read[static_cast<std::size_t>(r)], 7 * r);
  }
  EXPECT_EQ(f.read<double>("frame/whole").values, (std::vector<double>{0.0, 2.0}));
  EXPECT_EQ(f.open_group("frame").read_strings("names"), (std::vector<std::string>{"rank 0", "b"}));
  EXPECT_EQ(f.open_group("frame").attribute<std::int64_t>("step"), 42);
  barrier();
  if (rank() == 0) fs::remove_all(dir);
}

// Every dataset and attribute of the two trajectory files, compared value for value (bits).
void expect_same_trajectory(const std::string& a_path, const std::string& b_path, long frames) {
  const h5::File a(a_path, h5::File::Mode::read_only), b(b_path, h5::File::Mode::read_only);
  EXPECT_EQ(a.read_strings("group_names"), b.read_strings("group_names"));
  ASSERT_EQ(a.open_group("frames").children().size(), static_cast<std::size_t>(frames));
  ASSERT_EQ(b.open_group("frames").children().size(), static_cast<std::size_t>(frames));
  for (long k = 0; k < frames; ++k) {
    const std::string frame = "frames/" + std::to_string(k) + "/";
    for (const char* name : {"position", "radius", "velocity", "force", "angular_velocity"}) {
      const auto x = a.read<double>(frame + name), y = b.read<double>(frame + name);
      EXPECT_EQ(x.shape, y.shape) << frame << name;
      EXPECT_TRUE(x.values.size() == y.values.size() &&
                  std::memcmp(x.values.data(), y.values.data(), x.values.size() * sizeof(double)) == 0)
          << frame << name << " differs";
    }
    EXPECT_EQ(a.read<std::int64_t>(frame + "id").values, b.read<std::int64_t>(frame + "id").values) << frame;
    for (const char* name : {"type", "group", "image", "label"})
      EXPECT_EQ(a.read<std::int32_t>(frame + name).values, b.read<std::int32_t>(frame + name).values) << frame << name;
    const h5::Group ga = a.open_group(frame), gb = b.open_group(frame);
    EXPECT_EQ(ga.attribute<std::int64_t>("step"), gb.attribute<std::int64_t>("step"));
    EXPECT_EQ(ga.attribute<double>("time"), gb.attribute<double>("time"));
    EXPECT_EQ(ga.attribute_array<double>("box_lo"), gb.attribute_array<double>("box_lo"));
    EXPECT_EQ(ga.attribute_array<double>("box_hi"), gb.attribute_array<double>("box_hi"));
  }
}

// A block sliding through the periodic box (particles cross every cut and wrap), its trajectory written by
// one process and by every rank count's grids. `gaps`: ids 3 apart and shuffled, so a frame's row is found
// in the table of all ids rather than as id - first id.
void trajectory_of_ranks_is_the_serial_one(bool gaps) {
  if (exec::offload_build()) GTEST_SKIP() << "a run cut among ranks runs on host threads so far";
  const Lattice lat = test::cohesive_block({12, 8, 8}, 7);
  Particles particles = lat.particles;
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  DemSettings settings;
  settings.material = table4_material(0.0);
  settings.time_step_fraction = 0.1;
  // Length units a step: 72, 58 and 43 in all along x, y and z, past the 35 from a layer of the block to
  // the next cut (a quarter of a cell), so every cut is crossed.
  const double slide = 0.6;
  Particles probe = particles;
  probe.set_mass_from_density(settings.material.density);
  const double dt = 0.1 * stability_limits(CohesiveCoefficients::from(settings.material), probe).dt_c;
  std::vector<std::int64_t> ids(particles.size());
  for (std::size_t i = 0; i < ids.size(); ++i) ids[i] = gaps ? 5 + 3 * static_cast<std::int64_t>(i) : particles.id[i];
  if (gaps) std::shuffle(ids.begin(), ids.end(), rng);
  for (std::size_t i = 0; i < particles.size(); ++i) {
    particles.id[i] = ids[i];
    particles.vx[i] = (slide + 0.05 * u(rng)) / dt;
    particles.vy[i] = (0.8 * slide + 0.05 * u(rng)) / dt;
    particles.vz[i] = (0.6 * slide + 0.05 * u(rng)) / dt;
  }
  const Box box(lat.box.lo(), lat.box.hi(), {true, true, true});
  const std::string dir = shared_directory(gaps ? "debris_mpi_trajectory_gaps" : "debris_mpi_trajectory");
  const int steps = 120, every = 40;
  // Every rank steps (a serial run on each: its calls stay alike), rank 0 alone writes the serial file.
  auto frames = [&](DemSimulation& sim, TrajectoryWriter* out, bool share) {
    for (int s = 0; s <= steps; ++s) {
      if (s > 0) sim.step();
      if (s % every != 0 || !out) continue;
      if (share) out->write_frame(sim.step_count(), sim.time(), sim.box(), sim.particles(), sim.frame_share());
      else out->write_frame(sim.step_count(), sim.time(), sim.box(), sim.particles());
    }
  };
  DemSettings alone = settings;
  alone.distribute = false;
  DemSimulation serial(box, particles, Groups{}, alone);
  std::optional<TrajectoryWriter> serial_out;
  if (rank() == 0) serial_out.emplace(dir, "serial", std::vector<std::string>{});
  frames(serial, serial_out ? &*serial_out : nullptr, false);
  for (const auto g : test::grids_for(size())) {
    const std::string grid = std::to_string(g[0]) + "x" + std::to_string(g[1]) + "x" + std::to_string(g[2]);
    DemSettings cut = settings;
    cut.rank_grid = g;
    DemSimulation sim(box, particles, Groups{}, cut);
    TrajectoryWriter out(dir, "ranks", {}, true);
    frames(sim, &out, true);
    EXPECT_GT(sim.times().rebuilds, 2) << grid;
    // The frames must hold particles that changed ranks between them.
    const std::int64_t crossed = sim.migrated_in_all();
    if (size() > 1) EXPECT_GT(crossed, 0) << "particles must cross a cut, " << grid;
    barrier();
    if (rank() == 0) {
      SCOPED_TRACE("ranks " + grid);
      expect_same_trajectory(dir + "/serial.h5", dir + "/ranks.h5", steps / every + 1);
    }
    barrier();  // before the next grid overwrites the file
  }
  if (rank() == 0) fs::remove_all(dir);
}

TEST(ParallelTrajectory, IsTheOneProcessFileRowForRow) { trajectory_of_ranks_is_the_serial_one(false); }
TEST(ParallelTrajectory, IdsWithGapsFindTheirRowsInTheTableOfIds) { trajectory_of_ranks_is_the_serial_one(true); }

}  // namespace
}  // namespace debris::comm
