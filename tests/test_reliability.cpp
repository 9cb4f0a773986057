// Reliability of the executables: checkpoints that detect silent corruption, exit statuses that
// mean one thing each, a full disk or a blocked output directory, systems too large for the machine, thermo
// tables that do not depend on the thread count, a split run whose thermo table equals the whole run's, and
// restarts over tables a crash cut short.
#include <gtest/gtest.h>
#include <hdf5.h>

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "core/io/hdf5_file.hpp"
#include "core/io/hdf5_seal.hpp"
#include "tests/cli_helpers.hpp"

namespace {

namespace fs = std::filesystem;
using debris::test::CommandResult;
using debris::test::run_command;
using debris::test::slurp;

CommandResult run_dem(const std::string& args) { return run_command(DEBRIS_DEM_EXECUTABLE, args); }
CommandResult run_peridem(const std::string& args) { return run_command(DEBRIS_PERIDEM_EXECUTABLE, args); }

fs::path scratch(const std::string& name) { return debris::test::fresh_directory("debris_reliability_" + name); }

using debris::test::write;

using debris::test::replace;

bool mentions(const std::string& text, const std::string& what) { return text.find(what) != std::string::npos; }

// A small debris_dem run: an FCC block of 3 x 3 x 3 cells (108 particles) with a frozen bottom group, a
// checkpoint every 10 steps.
std::string dem_input(const fs::path& out, int steps = 20, const std::string& cells = "[3, 3, 3]") {
  return std::string(debris::test::kTable4MaterialYaml) + R"(particles:
  lattice:
    kind: fcc
    spacing: 100
    diameter: 100
    cells: )" +
         cells + R"(
    size_spread: 0.05
    displacement: 3
box:
  periodic: [true, false, true]
groups:
  - name: bottom
    region: {y: [-inf, 60]}
    motion: frozen
run:
  steps: )" +
         std::to_string(steps) +
         R"(
  time_step_fraction: 0.1
output:
  directory: )" +
         out.string() +
         R"(
  thermo_every: 10
  dump_every: 10
  checkpoint_every: 10
)";
}

// A small debris_peridem run: two discs above a wall (tests/test_peridem_cli.cpp's input), `mesh` the Gmsh size.
std::string peridem_input(const fs::path& out, int steps = 60, const std::string& mesh = "0.3 mm") {
  return R"(dimension: 2
materials:
  M1: {density: 1200 kg/m^3, bulk_modulus: 0.0216 GPa, shear_modulus: 0.01296 GPa, fracture_energy: 50 J/m^2, horizon: 0.6 mm}
shapes:
  disc: {type: circle, radius: 1 mm, mesh_size: )" +
         mesh + R"(}
  floor: {type: rectangle, lo: [-2 mm, -0.6 mm, 0], hi: [2 mm, 0, 0], mesh_size: )" +
         mesh + R"(}
grains:
  - {name: bottom, shape: disc, material: M1, centre: [0, 1.18 mm, 0]}
  - {name: top, shape: disc, material: M1, centre: [0, 3.5 mm, 0], velocity: [0, -10 m/s, 0]}
walls:
  - {name: floor, shape: floor, material: M1}
contact: {restitution: 0.95}
gravity: [0, -10 m/s^2, 0]
run: {time_step: 0.1 us, steps: )" +
         std::to_string(steps) + R"(}
output:
  directory: )" +
         out.string() +
         R"(
  thermo_every: 20
  trajectory_every: 20
  checkpoint_every: 20
)";
}

std::vector<char> bytes_of(const fs::path& p) {
  const std::string s = slurp(p);
  return {s.begin(), s.end()};
}

void put_bytes(const fs::path& p, const std::vector<char>& b) {
  std::ofstream(p, std::ios::binary | std::ios::trunc).write(b.data(), static_cast<std::streamsize>(b.size()));
}

/// Offset and length of a contiguous dataset's values in an HDF5 file (the HDF5 C API, independently of
/// the seal's own table).
std::pair<std::uint64_t, std::uint64_t> dataset_extent(const fs::path& file, const std::string& name) {
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  EXPECT_GE(f, 0) << file;
  const hid_t d = H5Dopen2(f, name.c_str(), H5P_DEFAULT);
  EXPECT_GE(d, 0) << name;
  const std::pair<std::uint64_t, std::uint64_t> e{H5Dget_offset(d), H5Dget_storage_size(d)};
  H5Dclose(d);
  H5Fclose(f);
  return e;
}

// ---- the seal itself ----

TEST(Seal, AChangedByteAnywhereIsFoundAndNamed) {
  const fs::path d = scratch("seal");
  const std::string path = (d / "f.h5").string();
  {
    debris::h5::File f(path, debris::h5::File::Mode::create);
    f.write("values/x", std::vector<double>(500, 1.25));
    f.write("values/id", std::vector<std::int64_t>(300, 7));
    f.set_attribute<std::int64_t>("format_version", 1);
    f.close();
  }
  const std::uintmax_t hdf5_size = fs::file_size(path);
  EXPECT_FALSE(debris::h5::verify_seal(path)) << "an unsealed file has no seal";
  debris::h5::seal(path);
  EXPECT_GT(fs::file_size(path), hdf5_size);
  EXPECT_TRUE(debris::h5::verify_seal(path));
  {  // HDF5 still reads the sealed file: the trailer lies beyond its end of file.
    const debris::h5::File f(path, debris::h5::File::Mode::read_only);
    EXPECT_EQ(f.read<double>("values/x").values, std::vector<double>(500, 1.25));
  }
  const std::vector<char> good = bytes_of(path);
  const auto [x_at, x_len] = dataset_extent(path, "/values/x");
  ASSERT_EQ(x_len, 500u * 8u);
  // Every 5th byte of the file and the last 64 (the trailer's footer), one at a time: a bit flipped anywhere
  // is an error; inside /values/x it names it.
  int named = 0, in_x = 0;
  for (std::size_t at = 0; at < good.size(); at += at + 64 >= good.size() ? 1 : 5) {
    std::vector<char> bad = good;
    bad[at] = static_cast<char>(bad[at] ^ 0x10);
    put_bytes(path, bad);
    try {
      debris::h5::verify_seal(path);
      // A seal whose magic word was hit reads as no seal at all: the checkpoint readers then refuse a
      // format that must be sealed (tested through the executables below).
      EXPECT_GE(at, good.size() - 8) << "a changed byte at " << at << " went unnoticed";
    } catch (const std::runtime_error& e) {
      EXPECT_TRUE(mentions(e.what(), path)) << e.what();
      if (at >= x_at && at < x_at + x_len) {
        EXPECT_TRUE(mentions(e.what(), "/values/x")) << "byte " << at << ": " << e.what();
        ++named;
      }
    }
    if (at >= x_at && at < x_at + x_len) ++in_x;
  }
  EXPECT_EQ(named, in_x);
  EXPECT_EQ(in_x, 500 * 8 / 5);
  put_bytes(path, good);
  EXPECT_TRUE(debris::h5::verify_seal(path));
}

// ---- checkpoints with bytes flipped, through the executables ----

struct FlipOutcomes {
  int tried = 0, refused = 0, identical = 0, other = 0;
  std::map<std::string, int> named;  // dataset named in the message -> count
};

// Copies `checkpoint`, XORs 8 bytes at each offset in turn, and restarts from the copy: each restart must
// end with exit 2 naming the file and 'restart', or succeed with the `expected` result file; never crash.
// `datasets` are checked to be named when the flip lies in their values.
template <class Run>
FlipOutcomes flip_and_restart(const fs::path& checkpoint, const fs::path& dir,
                              const std::vector<std::uint64_t>& offsets, const std::vector<std::string>& datasets,
                              Run run, const std::string& result_file, const std::string& expected) {
  FlipOutcomes o;
  const std::vector<char> good = bytes_of(checkpoint);
  std::vector<std::pair<std::string, std::pair<std::uint64_t, std::uint64_t>>> extents;
  for (const std::string& name : datasets) extents.push_back({name, dataset_extent(checkpoint, name)});
  const fs::path copy = dir / "flipped.h5";
  for (const std::uint64_t at : offsets) {
    std::vector<char> bad = good;
    for (std::uint64_t k = at; k < at + 8 && k < bad.size(); ++k) bad[k] = static_cast<char>(bad[k] ^ 0x5a);
    put_bytes(copy, bad);
    const fs::path out = dir / "restart_out";
    fs::remove_all(out);
    const CommandResult r = run("--restart " + copy.string() + " -o " + out.string() + " --threads 1");
    ++o.tried;
    if (r.exit_code == 2) {
      ++o.refused;
      EXPECT_TRUE(mentions(r.output, "restart") && mentions(r.output, copy.string()))
          << "offset " << at << ": " << r.output;
      for (const auto& [name, e] : extents)
        if (at < e.first + e.second && at + 8 > e.first) {
          EXPECT_TRUE(mentions(r.output, name)) << "offset " << at << " lies in " << name << ": " << r.output;
          ++o.named[name];
        }
    } else if (r.exit_code == 0 && slurp(out / result_file) == expected) {
      ++o.identical;
    } else {
      ++o.other;
      ADD_FAILURE() << "offset " << at << ": exit " << r.exit_code << "\n" << r.output;
    }
  }
  return o;
}

/// `count` offsets spread evenly over [0, size - 8], and every 8th byte of the given extents.
std::vector<std::uint64_t> offsets_over(std::uint64_t size, int count,
                                        const std::vector<std::pair<std::uint64_t, std::uint64_t>>& extents) {
  std::vector<std::uint64_t> at;
  for (int k = 0; k < count; ++k) at.push_back((size - 8) * static_cast<std::uint64_t>(k) / (count - 1));
  for (const auto& [offset, length] : extents)
    for (std::uint64_t k = 0; k < length; k += std::max<std::uint64_t>(8, length / 6)) at.push_back(offset + k);
  return at;
}

TEST(CheckpointCorruption, DemRestartFromAFlippedCheckpointIsANamedInputError) {
  const fs::path d = scratch("dem_flip");
  const fs::path in = write(d, "run.yaml", dem_input(d / "out", 20));
  ASSERT_EQ(run_dem("-i " + in.string() + " --threads 1").exit_code, 0);
  const fs::path checkpoint = d / "out" / "checkpoint.h5";
  // The result of an unharmed restart to step 30, which a restart from a flipped file must equal if it runs.
  const fs::path ref = d / "ref";
  const fs::path in30 = write(d, "run30.yaml", dem_input(d / "out", 30));
  ASSERT_EQ(run_dem("--restart " + checkpoint.string() + " -i " + in30.string() + " -o " + ref.string()).exit_code, 0);
  const std::string expected = slurp(ref / "thermo.csv");
  ASSERT_FALSE(expected.empty());
  const std::vector<std::string> datasets{"/particles/x",      "/particles/id", "/neighbors/index",
                                          "/neighbors/offset", "/history/hx",   "/groups/count"};
  std::vector<std::pair<std::uint64_t, std::uint64_t>> extents;
  for (const std::string& n : datasets) extents.push_back(dataset_extent(checkpoint, n));
  const std::vector<std::uint64_t> offsets = offsets_over(fs::file_size(checkpoint), 48, extents);
  // The restarts keep the 30-step input: run.steps comes from -i, so give it.
  FlipOutcomes o = flip_and_restart(
      checkpoint, d, offsets, datasets, [&](const std::string& args) { return run_dem(args + " -i " + in30.string()); },
      "thermo.csv", expected);
  EXPECT_EQ(o.other, 0);
  EXPECT_EQ(o.refused + o.identical, o.tried);
  for (const std::string& n : datasets) EXPECT_GT(o.named[n], 0) << n;
  std::cout << "debris_dem: " << o.tried << " flipped offsets, " << o.refused << " refused (exit 2), " << o.identical
            << " identical runs\n";
}

TEST(CheckpointCorruption, PeridemRestartFromAFlippedCheckpointIsANamedInputError) {
  const fs::path d = scratch("pd_flip");
  const fs::path in = write(d, "run.yaml", peridem_input(d / "out", 40));
  ASSERT_EQ(run_peridem("-i " + in.string() + " --threads 1").exit_code, 0);
  const fs::path checkpoint = d / "out" / "checkpoint.h5";
  const fs::path ref = d / "ref";
  const fs::path in60 = write(d, "run60.yaml", peridem_input(d / "out", 60));
  ASSERT_EQ(run_peridem("--restart " + checkpoint.string() + " -i " + in60.string() + " -o " + ref.string()).exit_code,
            0);
  const std::string expected = slurp(ref / "thermo.csv");
  const std::vector<std::string> datasets{"/nodes/x", "/nodes/grain", "/grains/node_begin", "/bonds/offset",
                                          "/contact_list/x_at_build"};
  std::vector<std::pair<std::uint64_t, std::uint64_t>> extents;
  for (const std::string& n : datasets) extents.push_back(dataset_extent(checkpoint, n));
  const std::vector<std::uint64_t> offsets = offsets_over(fs::file_size(checkpoint), 48, extents);
  FlipOutcomes o = flip_and_restart(
      checkpoint, d, offsets, datasets,
      [&](const std::string& args) { return run_peridem(args + " -i " + in60.string()); }, "thermo.csv", expected);
  EXPECT_EQ(o.other, 0);
  EXPECT_EQ(o.refused + o.identical, o.tried);
  for (const std::string& n : datasets) EXPECT_GT(o.named[n], 0) << n;
  std::cout << "debris_peridem: " << o.tried << " flipped offsets, " << o.refused << " refused (exit 2), "
            << o.identical << " identical runs\n";
}

/// Cuts the seal off a checkpoint and rewrites its format_version: what a checkpoint of an older format
/// (or one whose end was lost) looks like.
void unseal(const fs::path& checkpoint, std::int64_t version) {
  std::vector<char> b = bytes_of(checkpoint);
  const hid_t f0 = H5Fopen(checkpoint.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(f0, 0);
  haddr_t eoa = 0;
  ASSERT_GE(H5Fget_eoa(f0, &eoa), 0);
  H5Fclose(f0);
  ASSERT_LT(eoa, b.size());
  b.resize(eoa);
  put_bytes(checkpoint, b);
  debris::h5::File f(checkpoint.string(), debris::h5::File::Mode::read_write);
  f.set_attribute<std::int64_t>("format_version", version);
  f.close();
}

/// Writes `value` into element `k` of an int32 dataset (format `version`), then seals the file again: a checkpoint
/// whose checksums hold but whose contents are wrong (a foreign writer, a bug).
void poke_int32(const fs::path& checkpoint, const std::string& name, std::size_t k, std::int32_t value,
                std::int64_t version) {
  unseal(checkpoint, version);
  const hid_t f = H5Fopen(checkpoint.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  const hid_t d = H5Dopen2(f, name.c_str(), H5P_DEFAULT);
  std::vector<std::int32_t> v(H5Dget_storage_size(d) / 4);
  H5Dread(d, H5T_NATIVE_INT32, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
  v.at(k) = value;
  H5Dwrite(d, H5T_NATIVE_INT32, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
  H5Dclose(d);
  H5Fclose(f);
  debris::h5::seal(checkpoint.string());
}

TEST(CheckpointCorruption, DemUnsealedFutureAndForeignFilesAndWrongContents) {
  const fs::path d = scratch("dem_formats");
  const fs::path in = write(d, "run.yaml", dem_input(d / "out", 20));
  const fs::path in30 = write(d, "run30.yaml", dem_input(d / "out", 30));
  ASSERT_EQ(run_dem("-i " + in.string()).exit_code, 0);
  const fs::path checkpoint = d / "out" / "checkpoint.h5";
  auto restart = [&](const fs::path& file, const std::string& out) {
    return run_dem("--restart " + file.string() + " -i " + in30.string() + " -o " + (d / out).string());
  };
  ASSERT_EQ(restart(checkpoint, "ref").exit_code, 0);

  // Without a seal nothing is read (HDF5 does not survive every damaged file): format 2, from before
  // seals, and format 3 whose end was lost are both refused, naming what is missing.
  CommandResult r;
  for (const std::int64_t version : {2, 3}) {
    const fs::path cut = d / ("unsealed" + std::to_string(version) + ".h5");
    fs::copy_file(checkpoint, cut);
    unseal(cut, version);
    r = restart(cut, "cut_out");
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_TRUE(mentions(r.output, "checksums are missing") && mentions(r.output, cut.string())) << r.output;
    EXPECT_FALSE(fs::exists(d / "cut_out" / "thermo.csv")) << "nothing is written";
  }
  // A format from the future.
  const fs::path future = d / "future.h5";
  fs::copy_file(checkpoint, future);
  unseal(future, 99);
  debris::h5::seal(future.string());
  r = restart(future, "future_out");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_TRUE(mentions(r.output, "format 99")) << r.output;
  // Foreign files: a trajectory, a text file (a PeriDEM checkpoint: DemAndPeridemCheckpointsAreToldApart).
  r = restart(d / "out" / "trajectory.h5", "traj_out");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_TRUE(mentions(r.output, "not a debris_dem checkpoint")) << r.output;
  r = restart(in, "text_out");
  EXPECT_EQ(r.exit_code, 2) << r.output;

  // Sealed, but wrong inside: each is found before it is used.
  struct Poke {
    std::string dataset;
    std::size_t k;
    std::int32_t value;
    std::string message;
  };
  for (const Poke& p : {Poke{"/neighbors/index", 3, 100000, "neighbors/index"},
                        Poke{"/neighbors/offset", 5, -7, "neighbors/offset"}, Poke{"/particles/group", 2, 9, "group 9"},
                        Poke{"/particles/label", 2, 4, "label 4"}, Poke{"/settings/flags", 3, 17, "pair pass"}}) {
    const fs::path bad = d / "poked.h5";
    fs::remove(bad);
    fs::copy_file(checkpoint, bad);
    poke_int32(bad, p.dataset, p.k, p.value, 3);
    r = restart(bad, "poked_out");
    EXPECT_EQ(r.exit_code, 2) << p.dataset << ": " << r.output;
    EXPECT_TRUE(mentions(r.output, p.message) && mentions(r.output, "not a sound checkpoint"))
        << p.dataset << ": " << r.output;
  }
}

// Apart from the DEM checks above so that those run in the hostdevice build too, where the PeriDEM model
// is not device-resident yet (CI stage 3 leaves out tests named Peridem).
TEST(CheckpointCorruption, DemAndPeridemCheckpointsAreToldApart) {
  const fs::path d = scratch("dem_pd_foreign");
  const fs::path in = write(d, "run.yaml", dem_input(d / "out", 20));
  ASSERT_EQ(run_dem("-i " + in.string()).exit_code, 0);
  const fs::path checkpoint = d / "out" / "checkpoint.h5";
  const fs::path pd_in = write(d, "pd.yaml", peridem_input(d / "pd", 20));
  ASSERT_EQ(run_peridem("-i " + pd_in.string()).exit_code, 0);
  const fs::path pd_checkpoint = d / "pd" / "checkpoint.h5";
  CommandResult r =
      run_dem("--restart " + pd_checkpoint.string() + " -i " + in.string() + " -o " + (d / "pd_out").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_TRUE(mentions(r.output, "not a debris_dem checkpoint")) << r.output;
  r = run_peridem("--restart " + checkpoint.string() + " -o " + (d / "dem_as_pd").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_TRUE(mentions(r.output, "not a debris_peridem checkpoint")) << r.output;
}

TEST(CheckpointCorruption, PeridemUnsealedFileAndWrongContents) {
  const fs::path d = scratch("pd_formats");
  const fs::path in = write(d, "run.yaml", peridem_input(d / "out", 20));
  const fs::path in40 = write(d, "run40.yaml", peridem_input(d / "out", 40));
  ASSERT_EQ(run_peridem("-i " + in.string()).exit_code, 0);
  const fs::path checkpoint = d / "out" / "checkpoint.h5";
  auto restart = [&](const fs::path& file, const std::string& out) {
    return run_peridem("--restart " + file.string() + " -i " + in40.string() + " -o " + (d / out).string());
  };
  ASSERT_EQ(restart(checkpoint, "ref").exit_code, 0);
  // Format 1, from before seals: refused unread.
  const fs::path old = d / "old.h5";
  fs::copy_file(checkpoint, old);
  unseal(old, 1);
  CommandResult r = restart(old, "old_out");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_TRUE(mentions(r.output, "checksums are missing")) << r.output;
  for (const auto& [dataset, message] : std::vector<std::pair<std::string, std::string>>{
           {"/nodes/grain", "names grain"}, {"/grains/node_begin", "does not fit the nodes"}}) {
    const fs::path bad = d / "poked.h5";
    fs::remove(bad);
    fs::copy_file(checkpoint, bad);
    poke_int32(bad, dataset, 1, 57, 2);
    r = restart(bad, "poked_out");
    EXPECT_EQ(r.exit_code, 2) << dataset << ": " << r.output;
    EXPECT_TRUE(mentions(r.output, message)) << dataset << ": " << r.output;
  }
}

// ---- exit statuses ----

TEST(ExitStatus, BadCommandLinesAndMissingInputsAreTwoInEveryExecutable) {
  for (const char* exe : {DEBRIS_DEM_EXECUTABLE, DEBRIS_PERIDEM_EXECUTABLE, DEBRIS_PATCH_EXECUTABLE,
                          DEBRIS_AMORPHOUS_EXECUTABLE, DEBRIS_RESTITUTION_EXECUTABLE}) {
    const CommandResult unknown = run_command(exe, "--no-such-option");
    EXPECT_EQ(unknown.exit_code, 2) << exe << ": " << unknown.output;
    const CommandResult missing = run_command(exe, "-i /nonexistent/debris_input.yaml");
    EXPECT_EQ(missing.exit_code, 2) << exe << ": " << missing.output;
    EXPECT_TRUE(mentions(missing.output, "/nonexistent/debris_input.yaml")) << exe << ": " << missing.output;
    EXPECT_EQ(run_command(exe, "--help").exit_code, 0) << exe;
  }
}

TEST(ExitStatus, AnOutputDirectoryThatCannotBeMadeIsThree) {
  const fs::path d = scratch("blocked");
  write(d, "file", "a file where the output directory should be\n");
  const fs::path out = d / "file" / "out";
  const CommandResult dem = run_dem("-i " + write(d, "dem.yaml", dem_input(out, 10)).string());
  EXPECT_EQ(dem.exit_code, 3) << dem.output;
  EXPECT_TRUE(mentions(dem.output, out.string())) << dem.output;
  const CommandResult pd = run_peridem("-i " + write(d, "pd.yaml", peridem_input(out, 10)).string());
  EXPECT_EQ(pd.exit_code, 3) << pd.output;
  EXPECT_TRUE(mentions(pd.output, out.string())) << pd.output;
}

// A file size limit (ulimit -f, with SIGXFSZ ignored so that write() fails with EFBIG as on a full disk)
// that lets the thermo table and the frames through but not a checkpoint: the restart stops with exit 3
// naming the checkpoint, and the previous checkpoint is left whole and still named as the last good one.
TEST(ExitStatus, AFullDiskStopsTheRunAndKeepsThePreviousCheckpoint) {
  const fs::path d = scratch("full_disk");
  std::string yaml = dem_input(d / "out", 20, "[6, 6, 6]");
  yaml = replace(yaml, "  dump_every: 10\n", "  dump_every: 1000\n");
  ASSERT_EQ(run_dem("-i " + write(d, "run.yaml", yaml).string()).exit_code, 0);
  const fs::path checkpoint = d / "out" / "checkpoint.h5";
  const std::string before = slurp(checkpoint);
  const std::uintmax_t limit_kib = fs::file_size(checkpoint) / 1024 - 1;
  // The first run wrote two frames (steps 0 and 20); the restart writes one of each before step 30.
  for (const char* f : {"trajectory.h5", "dump.lammpstrj", "thermo.csv"})
    ASSERT_LT(fs::file_size(d / "out" / f) / 2, limit_kib * 1024) << f << " would hit the limit first";
  const fs::path in40 = write(d, "run40.yaml", replace(yaml, "steps: 20", "steps: 40"));
  const CommandResult r = run_command("bash", "-c \"trap '' XFSZ; ulimit -f " + std::to_string(limit_kib) + "; exec " +
                                                  DEBRIS_DEM_EXECUTABLE + " --restart " + checkpoint.string() + " -i " +
                                                  in40.string() + "\"");
  EXPECT_EQ(r.exit_code, 3) << r.output;
  EXPECT_TRUE(mentions(r.output, "at step 30")) << r.output;
  EXPECT_TRUE(mentions(r.output, "cannot write the checkpoint")) << r.output;
  EXPECT_TRUE(mentions(r.output, "the last good checkpoint is " + checkpoint.string() + " (step 20)")) << r.output;
  EXPECT_EQ(slurp(checkpoint), before) << "the previous checkpoint was touched";
  EXPECT_FALSE(fs::exists(checkpoint.string() + ".tmp"));
  // It still restarts.
  EXPECT_EQ(
      run_dem("--restart " + checkpoint.string() + " -i " + in40.string() + " -o " + (d / "again").string()).exit_code,
      0);
}

// ---- resource limits ----

TEST(ResourceLimits, ALatticeTooLargeForTheMachineIsRefusedBeforeItIsBuilt) {
  const fs::path d = scratch("huge");
  CommandResult r = run_dem("-i " + write(d, "huge.yaml", dem_input(d / "out", 10, "[2000, 2000, 2000]")).string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  for (const char* m : {"particles.lattice.cells", "[2000, 2000, 2000]", "3.2e+10 particles", "available"})
    EXPECT_TRUE(mentions(r.output, m)) << m << " in " << r.output;
  EXPECT_FALSE(fs::exists(d / "out"));
  // An address-space limit (ulimit -v 1 GiB) is counted: 2 million particles fit this machine but not it.
  r = run_command("bash", "-c \"ulimit -v 1048576; exec " + std::string(DEBRIS_DEM_EXECUTABLE) + " -i " +
                              write(d, "limited.yaml", dem_input(d / "out", 10, "[80, 80, 80]")).string() + "\"");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_TRUE(mentions(r.output, "RLIMIT_AS")) << r.output;
}

// ---- thermo tables ----

/// Runs `run` with --threads 1 and 2 into two directories and returns their thermo tables.
template <class Run>
std::pair<std::string, std::string> thermo_on_1_and_2_threads(const fs::path& d, Run run) {
  EXPECT_EQ(run(d / "t1", 1).exit_code, 0);
  EXPECT_EQ(run(d / "t2", 2).exit_code, 0);
  return {slurp(d / "t1" / "thermo.csv"), slurp(d / "t2" / "thermo.csv")};
}

TEST(ThermoTable, DemIsTheSameOnOneAndTwoThreads) {
  const fs::path d = scratch("dem_threads");
  // 2,592 particles: two summation blocks of 2,048 (the tables differed before they were summed in fixed
  // blocks).
  const fs::path in = write(d, "run.yaml", dem_input(d / "unused", 40, "[6, 9, 12]"));
  const auto [one, two] = thermo_on_1_and_2_threads(d, [&](const fs::path& out, int threads) {
    return run_dem("-i " + in.string() + " -o " + out.string() + " --threads " + std::to_string(threads));
  });
  ASSERT_FALSE(one.empty());
  EXPECT_EQ(one, two);
}

TEST(ThermoTable, PeridemIsTheSameOnOneAndTwoThreads) {
  const fs::path d = scratch("pd_threads");
  // A finer mesh: 2,337 nodes, two summation blocks of 2,048 (the tables differed before they were summed in
  // fixed blocks).
  const fs::path in = write(d, "run.yaml", peridem_input(d / "unused", 20, "0.07 mm"));
  const auto [one, two] = thermo_on_1_and_2_threads(d, [&](const fs::path& out, int threads) {
    return run_peridem("-i " + in.string() + " -o " + out.string() + " --threads " + std::to_string(threads));
  });
  ASSERT_FALSE(one.empty());
  EXPECT_EQ(one, two);
}

// A run split at a step that is not a thermo step: the first part ends there and writes its last row, which
// the run in one piece does not have; the restart drops it.
TEST(ThermoTable, ASplitRunHasTheWholeRunsTable) {
  const fs::path d = scratch("split");
  {
    const fs::path whole = write(d, "whole.yaml", dem_input(d / "whole", 40));
    const fs::path half = write(d, "half.yaml", dem_input(d / "split", 25));
    ASSERT_EQ(run_dem("-i " + whole.string()).exit_code, 0);
    ASSERT_EQ(run_dem("-i " + half.string()).exit_code, 0);
    const CommandResult r = run_dem("--restart " + (d / "split" / "checkpoint.h5").string() + " -i " +
                                    write(d, "rest.yaml", dem_input(d / "split", 40)).string());
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_EQ(slurp(d / "whole" / "thermo.csv"), slurp(d / "split" / "thermo.csv"));
  }
}

// The same for PeriDEM (a test of its own: the hostdevice build leaves out tests named Peridem).
TEST(ThermoTable, APeridemSplitRunHasTheWholeRunsTable) {
  const fs::path d = scratch("pd_split_run");
  {
    const fs::path whole = write(d, "pd_whole.yaml", peridem_input(d / "pd_whole", 60));
    const fs::path half = write(d, "pd_half.yaml", peridem_input(d / "pd_split", 30));
    ASSERT_EQ(run_peridem("-i " + whole.string()).exit_code, 0);
    ASSERT_EQ(run_peridem("-i " + half.string()).exit_code, 0);
    const CommandResult r = run_peridem("--restart " + (d / "pd_split" / "checkpoint.h5").string() + " -i " +
                                        write(d, "pd_rest.yaml", peridem_input(d / "pd_split", 60)).string());
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_EQ(slurp(d / "pd_whole" / "thermo.csv"), slurp(d / "pd_split" / "thermo.csv"));
  }
}

// ---- restarts over tables a crash damaged ----

/// The step a table's row starts with (-1 for the header).
long row_step(const std::string& line) {
  return !line.empty() && std::isdigit(static_cast<unsigned char>(line[0])) ? std::stol(line) : -1;
}

/// A table's lines, each with its line break.
std::vector<std::string> table_lines(const std::string& text) {
  std::vector<std::string> lines;
  for (std::size_t at = 0; at < text.size();) {
    const std::size_t end = std::min(text.find('\n', at), text.size() - 1);
    lines.push_back(text.substr(at, end + 1 - at));
    at = end + 1;
  }
  return lines;
}

/// The header and the rows of `text` whose step passes `keep`.
template <class Keep>
std::string rows_where(const std::string& text, Keep keep) {
  std::string out;
  for (const std::string& line : table_lines(text))
    if (row_step(line) < 0 || keep(row_step(line))) out += line;
  return out;
}

/// `text` cut inside its last row, as a crash before the file was synced leaves it: the row loses the
/// second half of its characters and its line break.
std::string cut_inside_last_row(const std::string& text) {
  const std::size_t start = text.rfind('\n', text.size() - 2) + 1;
  return text.substr(0, start + (text.size() - start) / 2);
}

/// debris_dem's default input (the sheared junction with its wear analysis), `steps` long, with a thermo row
/// and a wear sample every 250 steps and a checkpoint every 1,000.
std::string dem_wear_input(long steps) {
  std::string yaml = slurp(fs::path(DEBRIS_SOURCE_DIR) / "scenarios" / "dem" / "default.yaml");
  yaml = replace(yaml, "lammps_data: ../wear/data/",
                 "lammps_data: " + std::string(DEBRIS_SOURCE_DIR) + "/scenarios/wear/data/");
  yaml = replace(yaml, "pictures: true", "pictures: false");
  yaml = replace(yaml, "  every: 625 ", "  every: 250 ");
  yaml = replace(yaml, "thermo_every: 625", "thermo_every: 250");
  yaml = replace(yaml, "checkpoint_every: 12500", "checkpoint_every: 1000");
  return replace(yaml, "run:\n", "run:\n  steps: " + std::to_string(steps) + "\n");
}

// A crash before the tables were synced leaves them cut: inside the row of the checkpoint's step, or back
// at an earlier row's end, or empty. A restart from the checkpoint at step 2,000 rewrites what the
// checkpoint holds (the thermo row of its own step, every wear sample), names the rows it cannot rebuild,
// and never keeps a row cut short; the rows it writes are those of the run that was never interrupted.
TEST(ThermoTable, ARestartOverDamagedDemTablesRewritesTheirRows) {
  const fs::path d = scratch("dem_damaged_tables");
  const fs::path whole = write(d, "whole.yaml", dem_wear_input(3000));
  ASSERT_EQ(run_dem("-i " + whole.string() + " -o " + (d / "whole").string()).exit_code, 0);
  ASSERT_EQ(run_dem("-i " + write(d, "chunk.yaml", dem_wear_input(2000)).string() + " -o " + (d / "chunk").string())
                .exit_code,
            0);
  const std::string thermo = slurp(d / "whole" / "thermo.csv"), wear = slurp(d / "whole" / "wear.csv");
  ASSERT_EQ(row_step(table_lines(slurp(d / "chunk" / "thermo.csv")).back()), 2000);
  ASSERT_EQ(row_step(table_lines(slurp(d / "chunk" / "wear.csv")).back()), 2000);
  auto restart = [&](const std::string& name, const std::function<std::string(const std::string&)>& damage) {
    const fs::path out = d / name;
    fs::copy(d / "chunk", out, fs::copy_options::recursive);
    for (const char* table : {"thermo.csv", "wear.csv"}) {
      const std::string text = damage(slurp(out / table));
      std::ofstream(out / table, std::ios::binary | std::ios::trunc) << text;
    }
    const CommandResult r =
        run_dem("--restart " + (out / "checkpoint.h5").string() + " -i " + whole.string() + " -o " + out.string());
    EXPECT_EQ(r.exit_code, 0) << r.output;
    return r.output;
  };

  // Cut inside the rows of step 2,000: both are rewritten from the checkpoint.
  std::string log = restart("torn", cut_inside_last_row);
  EXPECT_EQ(slurp(d / "torn" / "thermo.csv"), thermo);
  EXPECT_EQ(slurp(d / "torn" / "wear.csv"), wear);
  EXPECT_TRUE(mentions(log, "thermo.csv was cut short or damaged before this restart: 1 row cut short or unreadable is "
                            "dropped; the row of step 2000 is rewritten from the checkpoint."))
      << log;
  EXPECT_TRUE(mentions(log, "wear.csv was cut short or damaged")) << log;

  // Cut back to the end of the row of step 750: the thermo rows of 1,000 to 1,750 are lost and said to be;
  // the checkpoint holds every wear sample.
  log = restart("short", [](const std::string& text) { return rows_where(text, [](long s) { return s <= 750; }); });
  EXPECT_EQ(slurp(d / "short" / "thermo.csv"), rows_where(thermo, [](long s) { return s <= 750 || s >= 2000; }));
  EXPECT_EQ(slurp(d / "short" / "wear.csv"), wear);
  EXPECT_TRUE(mentions(log, "the row of step 2000 is rewritten from the checkpoint; the rows of steps 1000, 1250, "
                            "1500 and 1750 are lost"))
      << log;
  EXPECT_TRUE(mentions(log, "wear.csv was cut short or damaged before this restart: 5 rows between steps 1000 and "
                            "2000 are rewritten from the checkpoint."))
      << log;

  // Empty, as a crash can leave a file whose first write was never synced: taken as missing, not as a
  // table whose columns differ.
  log = restart("empty", [](const std::string&) { return std::string(); });
  EXPECT_EQ(slurp(d / "empty" / "thermo.csv"), rows_where(thermo, [](long s) { return s > 2000; }));
  EXPECT_EQ(slurp(d / "empty" / "wear.csv"), rows_where(wear, [](long s) { return s > 2000; }));
}

// The same for PeriDEM's thermo table (a test of its own: the hostdevice build leaves out tests named Peridem).
TEST(ThermoTable, ARestartOverADamagedPeridemTableRewritesItsRows) {
  const fs::path d = scratch("pd_damaged_table");
  const fs::path whole = write(d, "whole.yaml", peridem_input(d / "unused", 120));
  ASSERT_EQ(run_peridem("-i " + whole.string() + " -o " + (d / "whole").string()).exit_code, 0);
  ASSERT_EQ(
      run_peridem("-i " + write(d, "chunk.yaml", peridem_input(d / "unused", 80)).string() + " -o " + (d / "chunk").string())
          .exit_code,
      0);
  const std::string thermo = slurp(d / "whole" / "thermo.csv");
  ASSERT_EQ(row_step(table_lines(slurp(d / "chunk" / "thermo.csv")).back()), 80);
  auto restart = [&](const std::string& name, const std::string& text) {
    const fs::path out = d / name;
    fs::copy(d / "chunk", out, fs::copy_options::recursive);
    std::ofstream(out / "thermo.csv", std::ios::binary | std::ios::trunc) << text;
    const CommandResult r = run_peridem("--restart " + (out / "checkpoint.h5").string() + " -i " + whole.string() +
                                        " -o " + out.string());
    EXPECT_EQ(r.exit_code, 0) << r.output;
    return r.output;
  };
  const std::string chunk = slurp(d / "chunk" / "thermo.csv");
  std::string log = restart("torn", cut_inside_last_row(chunk));
  EXPECT_EQ(slurp(d / "torn" / "thermo.csv"), thermo);
  EXPECT_TRUE(mentions(log, "the row of step 80 is rewritten from the checkpoint")) << log;
  log = restart("short", rows_where(chunk, [](long s) { return s <= 20; }));
  EXPECT_EQ(slurp(d / "short" / "thermo.csv"), rows_where(thermo, [](long s) { return s <= 20 || s >= 80; }));
  EXPECT_TRUE(mentions(log, "the rows of steps 40 and 60 are lost")) << log;
  restart("empty", "");
  EXPECT_EQ(slurp(d / "empty" / "thermo.csv"), rows_where(thermo, [](long s) { return s > 80; }));
}

// A run killed while writing a checkpoint leaves checkpoint.h5.tmp beside the whole previous one: the next
// start, or restart, removes it and says so. The restart has nothing left to run, so it writes no
// checkpoint of its own (whose writing would replace the file).
template <class Run>
void expect_unfinished_checkpoint_removed(const fs::path& out, const std::string& input, Run run) {
  const fs::path tmp = out / "checkpoint.h5.tmp";
  fs::create_directories(out);
  std::ofstream(tmp, std::ios::binary) << "half a checkpoint";
  CommandResult r = run("-i " + input + " -o " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(mentions(r.output, "removed " + tmp.string() + ", a checkpoint left unfinished")) << r.output;
  const std::string checkpoint = slurp(out / "checkpoint.h5");
  std::ofstream(tmp, std::ios::binary) << "half a checkpoint";
  r = run("--restart " + (out / "checkpoint.h5").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(mentions(r.output, "removed " + tmp.string() + ", a checkpoint left unfinished")) << r.output;
  EXPECT_FALSE(fs::exists(tmp));
  EXPECT_EQ(slurp(out / "checkpoint.h5"), checkpoint);
}

TEST(Checkpoint, AnUnfinishedDemCheckpointIsRemovedAtTheNextStart) {
  const fs::path d = scratch("dem_unfinished_checkpoint");
  expect_unfinished_checkpoint_removed(d / "out", write(d, "run.yaml", dem_input(d / "unused", 20)).string(), run_dem);
}

TEST(Checkpoint, AnUnfinishedPeridemCheckpointIsRemovedAtTheNextStart) {
  const fs::path d = scratch("pd_unfinished_checkpoint");
  expect_unfinished_checkpoint_removed(d / "out", write(d, "run.yaml", peridem_input(d / "unused", 20)).string(),
                                       run_peridem);
}

}  // namespace
