// HDF5 trajectories with an XDMF sidecar: the RAII wrapper round-trips every type and names what failed,
// frames read back exactly and sorted by id, the .xmf lists each frame with relative references, and a
// run killed with SIGKILL leaves an .h5 in which every frame the .xmf lists can be read.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <regex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "core/error.hpp"
#include "core/io/hdf5_file.hpp"
#include "core/io/trajectory_writer.hpp"
#include "tests/cli_helpers.hpp"

namespace debris {
namespace {

namespace fs = std::filesystem;

/// A fresh empty directory under the test temp dir.
std::string fresh_dir(const std::string& name) { return debris::test::fresh_directory(name).string(); }

using debris::test::slurp;

// ---------------------------------------------------------------- the RAII wrapper on its own

TEST(TrajectoryHdf5, RoundTripsEveryType) {
  const std::string path = fresh_dir("debris_h5_roundtrip") + "/a.h5";
  const double tiny = std::numeric_limits<double>::denorm_min();
  const std::vector<double> d1 = {1.0 / 3.0, -0.0, 6.02214076e23, tiny, -1e-300};
  const std::vector<double> d2 = {1, 2, 3, 4, 5, 6.5};  // 2 x 3
  const std::vector<std::int32_t> i32 = {std::numeric_limits<std::int32_t>::min(), -1, 0, 7,
                                         std::numeric_limits<std::int32_t>::max()};
  const std::vector<std::int64_t> i64 = {std::numeric_limits<std::int64_t>::min(), 0, 1LL << 40,
                                         std::numeric_limits<std::int64_t>::max()};
  const std::string echo = "material:\n  youngs_modulus: 73 GPa  # \xce\xbc and \"quotes\"\n";
  {
    h5::File f(path, h5::File::Mode::create);
    f.write("d1", d1);
    f.write("particles/d2", d2, 2, 3);  // parent group made on the way
    f.write("particles/i32", i32);
    f.write("particles/i64", i64);
    f.write("empty", std::vector<double>{});
    f.write_scalar("dt", 1.5e-15);
    f.write_scalar<std::int64_t>("step", 123456789012LL);
    f.write_string("input", echo);
    f.write_string("blank", "");
    f.write_strings("names", {"bottom", "", "top wall"});
    h5::Group g = f.open_group("particles");
    g.set_attribute("count", std::int64_t{5});
    g.set_attribute("time", 2.5e-12);
    g.set_attribute("periodic", std::vector<std::int32_t>{1, 0, 1});
    g.set_attribute("time", 3.5e-12);  // replacing an attribute is allowed
    f.set_string_attribute("version", "debris 0.1.0");
  }
  const h5::File f(path, h5::File::Mode::read_only);
  const h5::Array<double> a1 = f.read<double>("d1");
  EXPECT_EQ(a1.shape, (h5::Shape{5}));
  ASSERT_EQ(a1.values.size(), d1.size());
  for (std::size_t i = 0; i < d1.size(); ++i) {
    EXPECT_EQ(a1.values[i], d1[i]) << i;
    EXPECT_EQ(std::signbit(a1.values[i]), std::signbit(d1[i])) << i;  // -0.0 stays negative
  }
  const h5::Array<double> a2 = f.read<double>("/particles/d2");
  EXPECT_EQ(a2.shape, (h5::Shape{2, 3}));
  EXPECT_EQ(a2.values, d2);
  EXPECT_EQ(f.read<std::int32_t>("particles/i32").values, i32);
  EXPECT_EQ(f.read<std::int64_t>("particles/i64").values, i64);
  EXPECT_EQ(f.read<std::int64_t>("particles/i32").values,
            std::vector<std::int64_t>(i32.begin(), i32.end()));  // widening is lossless, so allowed
  const h5::Array<double> empty = f.read<double>("empty");
  EXPECT_EQ(empty.shape, (h5::Shape{0}));
  EXPECT_TRUE(empty.values.empty());
  EXPECT_EQ(f.read<double>("dt").shape, h5::Shape{});
  EXPECT_EQ(f.read_scalar<double>("dt"), 1.5e-15);
  EXPECT_EQ(f.read_scalar<std::int64_t>("step"), 123456789012LL);
  EXPECT_EQ(f.read_string("input"), echo);
  EXPECT_EQ(f.read_string("blank"), "");
  EXPECT_EQ(f.read_strings("names"), (std::vector<std::string>{"bottom", "", "top wall"}));
  const h5::Group g = f.open_group("particles");
  EXPECT_EQ(g.object_path(), "/particles");
  EXPECT_EQ(g.attribute<std::int64_t>("count"), 5);
  EXPECT_EQ(g.attribute<double>("time"), 3.5e-12);
  EXPECT_EQ(g.attribute_array<std::int32_t>("periodic"), (std::vector<std::int32_t>{1, 0, 1}));
  EXPECT_EQ(f.string_attribute("version"), "debris 0.1.0");
  EXPECT_TRUE(g.has_attribute("count"));
  EXPECT_FALSE(g.has_attribute("mass"));
  EXPECT_EQ(g.children(), (std::vector<std::string>{"d2", "i32", "i64"}));
  EXPECT_EQ(f.children(), (std::vector<std::string>{"blank", "d1", "dt", "empty", "input", "names", "particles", "step"}));
  EXPECT_TRUE(f.has("particles/i64"));
  EXPECT_TRUE(f.has("/particles"));
  EXPECT_FALSE(f.has("particles/x"));
  EXPECT_FALSE(f.has("nothing/below/here"));  // a missing parent is "no", not an error
}

TEST(TrajectoryHdf5, MissingFileErrorNamesTheFile) {
  const std::string path = fresh_dir("debris_h5_missing") + "/not_there.h5";
  ::testing::internal::CaptureStderr();
  try {
    h5::File f(path, h5::File::Mode::read_only);
    FAIL() << "opened " << path;
  } catch (const std::runtime_error& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("'" + path + "'"), std::string::npos) << msg;
    EXPECT_NE(msg.find("open for reading"), std::string::npos) << msg;
    EXPECT_NE(msg.find("No such file or directory"), std::string::npos) << msg;
  }
  EXPECT_EQ(::testing::internal::GetCapturedStderr(), "");  // HDF5's own stack printing is off
}

TEST(TrajectoryHdf5, ErrorsNameTheObjectAndRefuseLossyReads) {
  const std::string path = fresh_dir("debris_h5_errors") + "/e.h5";
  {
    h5::File f(path, h5::File::Mode::create);
    f.write("frames/0/id", std::vector<std::int64_t>{1, 2});
    f.write("frames/0/radius", std::vector<double>{0.5, 0.25});
    EXPECT_THROW(f.write("frames/0/id", std::vector<std::int64_t>{3}), std::runtime_error);  // exists
    EXPECT_THROW(f.write("bad", std::vector<double>{1, 2, 3}, 2, 2), std::invalid_argument);
  }
  ::testing::internal::CaptureStderr();
  const h5::File f(path, h5::File::Mode::read_only);
  auto message_of = [](auto&& action) -> std::string {
    try {
      action();
    } catch (const std::runtime_error& e) {
      return e.what();
    }
    return "(no exception)";
  };
  const std::string missing = message_of([&] { f.read<double>("frames/0/position"); });
  EXPECT_NE(missing.find("'/frames/0/position'"), std::string::npos) << missing;
  EXPECT_NE(missing.find("'" + path + "'"), std::string::npos) << missing;
  const std::string narrowing = message_of([&] { f.read<std::int32_t>("frames/0/id"); });
  EXPECT_NE(narrowing.find("8-byte integer"), std::string::npos) << narrowing;
  EXPECT_NE(narrowing.find("int32"), std::string::npos) << narrowing;
  const std::string float_as_int = message_of([&] { f.read<std::int64_t>("frames/0/radius"); });
  EXPECT_NE(float_as_int.find("8-byte float"), std::string::npos) << float_as_int;
  const std::string not_text = message_of([&] { f.read_string("frames/0/radius"); });
  EXPECT_NE(not_text.find("not as text"), std::string::npos) << not_text;
  const std::string not_one = message_of([&] { f.read_scalar<double>("frames/0/radius"); });
  EXPECT_NE(not_one.find("holds 2 values"), std::string::npos) << not_one;
  const std::string no_attr = message_of([&] { f.open_group("frames").attribute<double>("time"); });
  EXPECT_NE(no_attr.find("attribute 'time'"), std::string::npos) << no_attr;
  EXPECT_NE(no_attr.find("'/frames'"), std::string::npos) << no_attr;
  EXPECT_EQ(::testing::internal::GetCapturedStderr(), "");

  h5::File ro(path, h5::File::Mode::read_only);
  const std::string read_only = message_of([&] { ro.write("x", std::vector<double>{1}); });
  EXPECT_NE(read_only.find("cannot create dataset '/x'"), std::string::npos) << read_only;
}

TEST(TrajectoryHdf5, CloseRefusesWhileAnObjectIsOpenAndHandlesMove) {
  const std::string path = fresh_dir("debris_h5_close") + "/c.h5";
  h5::File f(path, h5::File::Mode::create);
  std::optional<h5::Group> g(f.create_group("g"));
  h5::Group moved = std::move(*g);
  EXPECT_LT(g->id(), 0);  // the moved-from handle owns nothing
  moved.write("v", std::vector<double>{4.0});
  EXPECT_THROW(f.close(), std::logic_error);  // `moved` would keep the file open behind our back
  g.reset();
  { h5::Group gone = std::move(moved); }
  f.close();
  f.close();  // closing twice is harmless
  EXPECT_EQ(h5::File(path, h5::File::Mode::read_only).read_scalar<double>("g/v"), 4.0);
  h5::File rw(path, h5::File::Mode::read_write);
  rw.write("w", std::vector<std::int32_t>{9});
  rw.close();
  const h5::File ro(path, h5::File::Mode::read_only);
  EXPECT_EQ(ro.read<std::int32_t>("w").values, std::vector<std::int32_t>{9});
  EXPECT_EQ(ro.read<double>("g/v").values, std::vector<double>{4.0});
}

TEST(TrajectoryHdf5, UnlinkedGroupAppearsOnlyWhenLinked) {
  const std::string path = fresh_dir("debris_h5_unlinked") + "/u.h5";
  {
    h5::File f(path, h5::File::Mode::create, {.group_leaf_k = 64});
    h5::Group index = f.create_group("frames", {.reserved_name_bytes = 4096});
    h5::Group g = f.create_unlinked_group({.small = true});
    g.write("x", std::vector<double>{1.5, 2.5});
    g.set_attribute("step", std::int64_t{7});
    f.flush();
    EXPECT_TRUE(index.children().empty());  // written, flushed, but not reachable yet
    index.link(g, "0");
    EXPECT_EQ(index.children(), std::vector<std::string>{"0"});
  }
  const h5::File f(path, h5::File::Mode::read_only);
  EXPECT_EQ(f.read<double>("frames/0/x").values, (std::vector<double>{1.5, 2.5}));
  EXPECT_EQ(f.open_group("frames/0").attribute<std::int64_t>("step"), 7);
}

// write_rows on one process (tests/mpi writes one dataset from several ranks): every row, in order, or a
// named error before anything is created.
TEST(TrajectoryHdf5, WriteRowsTakesEveryRowInOrderOrSaysWhy) {
  const std::string path = fresh_dir("debris_h5_rows") + "/r.h5";
  h5::File f(path, h5::File::Mode::create);
  const std::vector<std::int64_t> rows{0, 1, 2};
  f.write_rows<double>("xyz", std::vector<double>{0, 1, 2, 10, 11, 12, 20, 21, 22}, rows, {3, 3});
  f.write_rows<std::int32_t>("k", std::vector<std::int32_t>{7, 8, 9}, rows, {3});
  f.write_rows<double>("none", std::vector<double>{}, std::vector<std::int64_t>{}, {0, 3});
  EXPECT_EQ(f.read<double>("xyz").values, (std::vector<double>{0, 1, 2, 10, 11, 12, 20, 21, 22}));
  EXPECT_EQ(f.read<double>("xyz").shape, (h5::Shape{3, 3}));
  EXPECT_EQ(f.read<std::int32_t>("k").values, (std::vector<std::int32_t>{7, 8, 9}));
  EXPECT_EQ(f.read<double>("none").shape, (h5::Shape{0, 3}));

  const std::vector<double> two_rows{1, 2, 3, 4, 5, 6};
  auto expect_error = [&](const char* name, std::vector<std::int64_t> rows, h5::Shape shape, const std::string& text) {
    std::string what = "no error";
    try {
      f.write_rows<double>(name, two_rows, rows, shape);
    } catch (const std::exception& e) {
      what = e.what();
    }
    EXPECT_NE(what.find(text), std::string::npos) << what;
  };
  expect_error("a", {1, 0}, {2, 3}, "row 0 is out of order");
  expect_error("b", {0, 2}, {2, 3}, "row 2 is out of order or beyond the 2 rows");
  expect_error("c", {0}, {2, 3}, "6 values are not 1 rows of 3");
  expect_error("d", {0, 1}, {3, 3}, "2 rows given for 3");
  expect_error("e", {0, 1}, {}, "a scalar has no rows");
  for (const char* name : {"a", "b", "c", "d", "e"}) EXPECT_FALSE(f.has(name)) << name;
}

TEST(TrajectoryHdf5, WriterWithoutLockingOpensAFileAReaderHolds) {
  const std::string path = fresh_dir("debris_h5_lock") + "/l.h5";
  h5::File(path, h5::File::Mode::create).write("a", std::vector<double>{1});
  int ready[2], done[2];
  ASSERT_EQ(pipe(ready), 0);
  ASSERT_EQ(pipe(done), 0);
  const pid_t reader = fork();
  ASSERT_GE(reader, 0);
  if (reader == 0) {  // holds the file open for reading, as a viewer would
    char c = 0;
    try {
      const h5::File f(path, h5::File::Mode::read_only);
      if (write(ready[1], "r", 1) != 1 || read(done[0], &c, 1) != 1) _exit(2);
    } catch (...) {
      _exit(3);
    }
    _exit(0);
  }
  char c = 0;
  ASSERT_EQ(read(ready[0], &c, 1), 1);
  try {
    h5::File locked(path, h5::File::Mode::read_write);
    ADD_FAILURE() << "HDF5's lock did not stop a writer; the test no longer shows why file_locking=false exists";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("open for writing"), std::string::npos) << e.what();
  }
  {
    h5::File unlocked(path, h5::File::Mode::read_write, {.file_locking = false});
    unlocked.write("b", std::vector<double>{2});
    unlocked.close();
  }
  ASSERT_EQ(write(done[1], "d", 1), 1);
  int status = 0;
  ASSERT_EQ(waitpid(reader, &status, 0), reader);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << status;
  for (int fd : {ready[0], ready[1], done[0], done[1]}) close(fd);
  EXPECT_EQ(h5::File(path, h5::File::Mode::read_only).read<double>("b").values, std::vector<double>{2});
}

// ---------------------------------------------------------------- the trajectory writer

/// Four particles stored out of id order (ids 30, 4, 17, 9), values that need all 17 digits.
Particles sample(int frame) {
  Particles p;
  const double s = 1.0 + 0.1 * frame;
  p.add(30, 2, 0.1 * s, 0.2, 0.3, 1.0 / 3.0);
  p.add(4, 1, -1.0 / 7.0, 2.5 * s, 1e-9, 0.5);
  p.add(17, 1, 3.0, 2.0 / 3.0, -0.0 * s, 0.25);
  p.add(9, 3, 1.5, -2.25, 4.0 * s, 0.125);
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double k = static_cast<double>(i + 1);
    p.vx[i] = 0.1 * k * s, p.vy[i] = -1e-300, p.vz[i] = 7.0;
    p.fx[i] = 1.0 / 9.0, p.fy[i] = -2.0 * k, p.fz[i] = 6.02214076e23 * s;
    p.group[i] = static_cast<int>(i % 3) - 1;  // -1, 0, 1, -1
    p.wx[i] = -k / 11.0 * s, p.wy[i] = 2.5e12, p.wz[i] = -0.0;
    p.ix[i] = static_cast<int>(i) - 2, p.iy[i] = frame, p.iz[i] = 1000 * static_cast<int>(i);
    p.label[i] = static_cast<int>(i % 3);  // 0 (unlabelled), 1, 2, 0
  }
  p.label_names = {"bottom slab", "junction"};
  if (frame == 2) {  // N changes: one more particle, with the smallest id
    p.add(1, 2, 9.0, 8.0, 7.0, 0.75);
    p.vx[4] = 1.0, p.fz[4] = -3.0, p.group[4] = 1, p.wy[4] = 4.0, p.ix[4] = -7, p.label[4] = 2;
  }
  return p;
}

const Box kBox({-1, 0, -2.5}, {10, 1.0 / 3.0, 2.5}, {true, false, true});
const std::vector<long> kSteps = {0, 1000, 2000};
const std::vector<double> kTimes = {0.0, 2.5e-12, 1.0 / 3.0 * 1e-11};

std::string write_sample_trajectory(const std::string& name) {
  const std::string dir = fresh_dir(name);
  TrajectoryWriter w(dir, "run", {"bottom", "top"});
  EXPECT_EQ(w.frames(), 0);
  for (int k = 0; k < 3; ++k) w.write_frame(kSteps[k], kTimes[k], kBox, sample(k));
  EXPECT_EQ(w.frames(), 3);
  EXPECT_EQ(w.h5_path(), dir + "/run.h5");
  EXPECT_EQ(w.xmf_path(), dir + "/run.xmf");
  return dir;
}

TEST(TrajectoryWriter, FramesReadBackExactlySortedById) {
  const std::string dir = write_sample_trajectory("debris_traj_frames");
  const h5::File f(dir + "/run.h5", h5::File::Mode::read_only);
  EXPECT_EQ(f.read_strings("group_names"), (std::vector<std::string>{"bottom", "top"}));
  EXPECT_EQ(f.open_group("frames").children(), (std::vector<std::string>{"0", "1", "2"}));
  for (int k = 0; k < 3; ++k) {
    SCOPED_TRACE("frame " + std::to_string(k));
    const Particles p = sample(k);
    // Memory index of each row: ids 4, 9, 17, 30 (and id 1 first in the last frame).
    const std::vector<std::size_t> order = k == 2 ? std::vector<std::size_t>{4, 1, 3, 2, 0}
                                                  : std::vector<std::size_t>{1, 3, 2, 0};
    const std::size_t n = order.size();
    const h5::Group g = f.open_group("frames/" + std::to_string(k));
    EXPECT_EQ(g.attribute<std::int64_t>("step"), kSteps[k]);
    EXPECT_EQ(g.attribute<double>("time"), kTimes[k]);
    EXPECT_EQ(g.attribute_array<double>("box_lo"), (std::vector<double>{-1, 0, -2.5}));
    EXPECT_EQ(g.attribute_array<double>("box_hi"), (std::vector<double>{10, 1.0 / 3.0, 2.5}));
    EXPECT_EQ(g.attribute_array<std::int32_t>("periodic"), (std::vector<std::int32_t>{1, 0, 1}));

    const h5::Array<double> pos = g.read<double>("position"), vel = g.read<double>("velocity"),
                            frc = g.read<double>("force"), rad = g.read<double>("radius");
    const h5::Array<std::int64_t> id = g.read<std::int64_t>("id");
    const h5::Array<std::int32_t> type = g.read<std::int32_t>("type"), group = g.read<std::int32_t>("group");
    const h5::Array<double> omega = g.read<double>("angular_velocity");
    const h5::Array<std::int32_t> image = g.read<std::int32_t>("image"), label = g.read<std::int32_t>("label");
    EXPECT_EQ(g.read_strings("label_names"), p.label_names);
    EXPECT_EQ(omega.shape, (h5::Shape{n, 3}));
    EXPECT_EQ(image.shape, (h5::Shape{n, 3}));
    EXPECT_EQ(label.shape, (h5::Shape{n}));
    EXPECT_EQ(pos.shape, (h5::Shape{n, 3}));
    EXPECT_EQ(vel.shape, (h5::Shape{n, 3}));
    EXPECT_EQ(frc.shape, (h5::Shape{n, 3}));
    EXPECT_EQ(rad.shape, (h5::Shape{n}));
    EXPECT_EQ(id.shape, (h5::Shape{n}));
    EXPECT_EQ(type.shape, (h5::Shape{n}));
    EXPECT_EQ(group.shape, (h5::Shape{n}));
    for (std::size_t r = 0; r < n; ++r) {
      const std::size_t i = order[r];
      EXPECT_EQ(id.values[r], p.id[i]) << r;
      EXPECT_EQ(type.values[r], p.type[i]) << r;
      EXPECT_EQ(group.values[r], p.group[i]) << r;
      EXPECT_EQ(rad.values[r], p.radius[i]) << r;
      EXPECT_EQ((std::vector<double>(pos.values.begin() + 3 * r, pos.values.begin() + 3 * r + 3)),
                (std::vector<double>{p.x[i], p.y[i], p.z[i]})) << r;
      EXPECT_EQ((std::vector<double>(vel.values.begin() + 3 * r, vel.values.begin() + 3 * r + 3)),
                (std::vector<double>{p.vx[i], p.vy[i], p.vz[i]})) << r;
      EXPECT_EQ((std::vector<double>(frc.values.begin() + 3 * r, frc.values.begin() + 3 * r + 3)),
                (std::vector<double>{p.fx[i], p.fy[i], p.fz[i]})) << r;
      EXPECT_EQ((std::vector<double>(omega.values.begin() + 3 * r, omega.values.begin() + 3 * r + 3)),
                (std::vector<double>{p.wx[i], p.wy[i], p.wz[i]})) << r;
      EXPECT_EQ((std::vector<std::int32_t>(image.values.begin() + 3 * r, image.values.begin() + 3 * r + 3)),
                (std::vector<std::int32_t>{p.ix[i], p.iy[i], p.iz[i]})) << r;
      EXPECT_EQ(label.values[r], p.label[i]) << r;
      if (r > 0) EXPECT_LT(id.values[r - 1], id.values[r]);
    }
  }
  // Spot values written out by hand, independent of sample(): frame 0, row 0 is id 4.
  const h5::Group g0 = f.open_group("frames/0");
  EXPECT_EQ(g0.read<std::int64_t>("id").values, (std::vector<std::int64_t>{4, 9, 17, 30}));
  EXPECT_EQ(g0.read<std::int32_t>("type").values, (std::vector<std::int32_t>{1, 3, 1, 2}));
  EXPECT_EQ(g0.read<std::int32_t>("group").values, (std::vector<std::int32_t>{0, -1, 1, -1}));
  EXPECT_EQ(g0.read<double>("radius").values, (std::vector<double>{0.5, 0.125, 0.25, 1.0 / 3.0}));
  EXPECT_EQ(g0.read<std::int32_t>("label").values, (std::vector<std::int32_t>{1, 0, 2, 0}));
  EXPECT_EQ(g0.read<std::int32_t>("image").values, (std::vector<std::int32_t>{-1, 0, 1000, 1, 0, 3000, 0, 0, 2000, -2, 0, 0}));
  EXPECT_EQ(g0.read_strings("label_names"), (std::vector<std::string>{"bottom slab", "junction"}));
  const std::vector<double> p0 = g0.read<double>("position").values;
  EXPECT_EQ((std::vector<double>(p0.begin(), p0.begin() + 3)), (std::vector<double>{-1.0 / 7.0, 2.5, 1e-9}));
  EXPECT_EQ(f.read<std::int64_t>("frames/2/id").values, (std::vector<std::int64_t>{1, 4, 9, 17, 30}));
}

TEST(TrajectoryWriter, XmfListsEveryFrameWithRelativeReferences) {
  const std::string dir = write_sample_trajectory("debris_traj_xmf");
  EXPECT_FALSE(fs::exists(dir + "/run.xmf.tmp"));
  const std::string x = slurp(dir + "/run.xmf");
  EXPECT_NE(x.find("<Grid Name=\"particles\" GridType=\"Collection\" CollectionType=\"Temporal\">"), std::string::npos) << x;

  // Split the text into the grids of the collection.
  const std::regex grid_re("<Grid Name=\"step (\\d+)\" GridType=\"Uniform\">([\\s\\S]*?)</Grid>");
  std::vector<std::smatch> grids;
  for (auto it = std::sregex_iterator(x.begin(), x.end(), grid_re); it != std::sregex_iterator(); ++it) grids.push_back(*it);
  ASSERT_EQ(grids.size(), 3u) << x;
  for (std::size_t k = 0; k < 3; ++k) {
    SCOPED_TRACE("grid " + std::to_string(k));
    const std::string body = grids[k][2].str();
    EXPECT_EQ(std::stol(grids[k][1].str()), kSteps[k]);
    std::smatch m;
    ASSERT_TRUE(std::regex_search(body, m, std::regex("<Time Value=\"([^\"]+)\"/>")));
    EXPECT_EQ(std::strtod(m[1].str().c_str(), nullptr), kTimes[k]);  // round-trips exactly
    const std::string n = k == 2 ? "5" : "4";
    EXPECT_NE(body.find("<Topology TopologyType=\"Polyvertex\" NumberOfElements=\"" + n + "\"/>"), std::string::npos);
    EXPECT_NE(body.find("<Geometry GeometryType=\"XYZ\">"), std::string::npos);
    const std::string frame = "run.h5:/frames/" + std::to_string(k) + "/";
    EXPECT_NE(body.find("<DataItem Dimensions=\"" + n + " 3\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">" +
                        frame + "position</DataItem>"),
              std::string::npos)
        << body;
    for (const char* s : {"id", "type", "radius", "group", "label"}) {
      EXPECT_NE(body.find(std::string("<Attribute Name=\"") + s + "\" AttributeType=\"Scalar\" Center=\"Node\">"),
                std::string::npos) << s;
      EXPECT_NE(body.find("Dimensions=\"" + n + "\""), std::string::npos) << s;
      EXPECT_NE(body.find(">" + frame + s + "</DataItem>"), std::string::npos) << s;
    }
    for (const char* v : {"velocity", "force", "angular_velocity"}) {
      EXPECT_NE(body.find(std::string("<Attribute Name=\"") + v + "\" AttributeType=\"Vector\" Center=\"Node\">"),
                std::string::npos) << v;
      EXPECT_NE(body.find("<DataItem Dimensions=\"" + n + " 3\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">" +
                          frame + v + "</DataItem>"),
                std::string::npos) << v;
    }
    EXPECT_NE(body.find("NumberType=\"Int\" Precision=\"8\" Format=\"HDF\">" + frame + "id<"), std::string::npos);
    EXPECT_NE(body.find("<Attribute Name=\"image\" AttributeType=\"Vector\" Center=\"Node\">"), std::string::npos);
    EXPECT_NE(body.find("<DataItem Dimensions=\"" + n + " 3\" NumberType=\"Int\" Precision=\"4\" Format=\"HDF\">" +
                        frame + "image</DataItem>"),
              std::string::npos) << body;
  }
  // Every reference is the bare file name: no directory part, relative to the .xmf.
  const std::regex ref_re(">([^<>]*):/frames/");
  int refs = 0;
  for (auto it = std::sregex_iterator(x.begin(), x.end(), ref_re); it != std::sregex_iterator(); ++it, ++refs) {
    EXPECT_EQ((*it)[1].str(), "run.h5");
  }
  EXPECT_EQ(refs, 3 * 12);
}

TEST(TrajectoryWriter, NewWriterTruncatesAndListsNoFrame) {
  const std::string dir = write_sample_trajectory("debris_traj_truncate");
  TrajectoryWriter again(dir, "run", {});
  const std::string x = slurp(dir + "/run.xmf");
  EXPECT_EQ(x.find("<Time"), std::string::npos) << x;
  EXPECT_NE(x.find("CollectionType=\"Temporal\""), std::string::npos);
  const h5::File f(dir + "/run.h5", h5::File::Mode::read_only);
  EXPECT_TRUE(f.open_group("frames").children().empty());
  EXPECT_TRUE(f.read_strings("group_names").empty());
}

TEST(TrajectoryWriter, BadOutputIsAnOutputErrorAndUnnamedGroupIsRefused) {
  const std::string dir = fresh_dir("debris_traj_bad");
  try {
    TrajectoryWriter w(dir + "/no_such_subdir", "run", {});
    FAIL() << "created a trajectory in a missing directory";
  } catch (const OutputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("output error"), std::string::npos) << msg;
    EXPECT_NE(msg.find(dir + "/no_such_subdir/run.h5"), std::string::npos) << msg;
  }
  EXPECT_THROW(TrajectoryWriter(dir, "a:b", {}), InputError);
  EXPECT_THROW(TrajectoryWriter(dir, "", {}), InputError);
  TrajectoryWriter w(dir, "groups", {"only"});
  Particles p = sample(0);  // uses groups -1, 0 and 1; only 0 is named
  EXPECT_THROW(w.write_frame(0, 0.0, kBox, p), std::invalid_argument);
  EXPECT_EQ(w.frames(), 0);
  p.group[2] = 0;
  w.write_frame(0, 0.0, kBox, p);
  EXPECT_EQ(w.frames(), 1);
}

// ---------------------------------------------------------------- a run killed between or inside frames

/// What the child of the killed-run test writes in frame k: n(k) particles, ids shuffled in memory.
std::size_t killed_n(long k) { return 40 + static_cast<std::size_t>(k % 5) * 7; }
Particles killed_frame(long k) {
  Particles p;
  const std::size_t n = killed_n(k);
  for (std::size_t i = 0; i < n; ++i) {
    const auto id = static_cast<std::int64_t>((i * 13) % n) + 1;  // 13 is coprime to every n(k)
    const double d = static_cast<double>(id);
    p.add(id, 1 + static_cast<int>(id % 3), d + 0.001 * static_cast<double>(k), -d / 3.0, 0.5, 0.1 + d / 1024.0);
    p.vx[i] = static_cast<double>(k);
  }
  return p;
}


/// Forks a writer that loops over frames, kills it `delay` after it has listed `listed` frames, and
/// checks that every frame its .xmf lists reads back from the .h5.
void kill_and_check(const std::string& dir, std::chrono::microseconds delay, int listed) {
  const std::string xmf = dir + "/run.xmf";
  const pid_t child = fork();
  ASSERT_GE(child, 0) << "fork failed";
  if (child == 0) {  // never return into the test framework from here
    try {
      TrajectoryWriter w(dir, "run", {});
      for (long k = 0; k < 1000000; ++k) w.write_frame(k, 0.5 * static_cast<double>(k), kBox, killed_frame(k));
    } catch (...) {
      _exit(3);
    }
    _exit(0);
  }
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while ((!fs::exists(xmf) || debris::test::count_xmf_frames(xmf) < listed) && std::chrono::steady_clock::now() < give_up) {
    std::this_thread::sleep_for(std::chrono::microseconds(200));
  }
  std::this_thread::sleep_for(delay);
  kill(child, SIGKILL);
  int status = 0;
  ASSERT_EQ(waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL) << "the writer ended by itself, status " << status;

  const int frames = debris::test::count_xmf_frames(xmf);
  ASSERT_GE(frames, listed);
  const h5::File f(dir + "/run.h5", h5::File::Mode::read_only);
  for (long k = 0; k < frames; ++k) {
    SCOPED_TRACE("frame " + std::to_string(k) + " of " + std::to_string(frames));
    const std::size_t n = killed_n(k);
    const h5::Group g = f.open_group("frames/" + std::to_string(k));
    EXPECT_EQ(g.attribute<std::int64_t>("step"), k);
    EXPECT_EQ(g.attribute<double>("time"), 0.5 * static_cast<double>(k));
    const std::vector<std::int64_t> id = g.read<std::int64_t>("id").values;
    const std::vector<double> pos = g.read<double>("position").values;
    const std::vector<double> rad = g.read<double>("radius").values;
    const std::vector<double> vel = g.read<double>("velocity").values;
    ASSERT_EQ(id.size(), n);
    ASSERT_EQ(pos.size(), 3 * n);
    for (std::size_t r = 0; r < n; ++r) {
      const double d = static_cast<double>(r + 1);
      ASSERT_EQ(id[r], static_cast<std::int64_t>(r + 1));
      ASSERT_EQ(pos[3 * r], d + 0.001 * static_cast<double>(k));
      ASSERT_EQ(pos[3 * r + 1], -d / 3.0);
      ASSERT_EQ(rad[r], 0.1 + d / 1024.0);
      ASSERT_EQ(vel[3 * r], static_cast<double>(k));
    }
    EXPECT_EQ(g.read<std::int32_t>("type").values.size(), n);
    EXPECT_EQ(g.read<std::int32_t>("group").values, std::vector<std::int32_t>(n, -1));
    EXPECT_EQ(g.read<double>("force").values.size(), 3 * n);
  }
}

TEST(TrajectoryKilledRun, EveryFrameTheXmfListsIsReadable) {
  // Kills land at different points of a frame (a few ms each here): right after the .xmf changed, and
  // then every 250 us for 6 ms. A kill inside HDF5's close once left a file shorter than its
  // superblock said, which HDF5 refuses to open; that window is a few syscalls wide, so many rounds.
  for (int round = 0; round <= 24; ++round) {
    const auto delay = std::chrono::microseconds(250 * round);
    SCOPED_TRACE("kill " + std::to_string(delay.count()) + " us after the second frame was listed");
    kill_and_check(fresh_dir("debris_traj_killed_" + std::to_string(round)), delay, 2);
    if (HasFatalFailure()) return;
  }
}

}  // namespace
}  // namespace debris
