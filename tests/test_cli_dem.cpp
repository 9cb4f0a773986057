// debris_dem from the command line: each bad input ends with a message naming the key and the value and
// exit status 2, before anything is written (earlier results in the output directory survive); the default
// input runs and writes its thermo CSV and dump.
#include <gtest/gtest.h>

#include <algorithm>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "core/comm/communicator.hpp"
#include "core/io/hdf5_file.hpp"
#include "scenarios/common/dem/dem_simulation.hpp"
#include "tests/cli_helpers.hpp"

namespace {

namespace fs = std::filesystem;

using Result = debris::test::CommandResult;

Result run_dem(const std::string& args) { return debris::test::run_command(DEBRIS_DEM_EXECUTABLE, args); }

fs::path scratch(const std::string& name) { return debris::test::fresh_directory("debris_cli_" + name); }

// A small valid input; `edit` replaces one line to make it bad.
std::string small_input(const std::string& out_dir) {
  return std::string(debris::test::kTable4MaterialYaml) + R"(particles:
  lattice:
    kind: fcc
    spacing: 100
    diameter: 100
    cells: [3, 3, 3]
box:
  periodic: [true, true, true]
run:
  steps: 20
  time_step_fraction: 0.1
output:
  directory: )" + out_dir + R"(
  thermo_every: 10
  dump_every: 10
)";
}

using debris::test::replace;

using debris::test::write;

using debris::test::slurp;

class DemCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir = scratch(::testing::UnitTest::GetInstance()->current_test_info()->name());
    out = dir / "out";
    // A good run first: its results must survive every bad run pointed at the same directory.
    const Result ok = run_dem("-i " + write(dir, "good.yaml", small_input(out.string())).string());
    ASSERT_EQ(ok.exit_code, 0) << ok.output;
    thermo_before = slurp(out / "thermo.csv");
    ASSERT_FALSE(thermo_before.empty());
  }
  void expect_rejected(const std::string& yaml, const std::vector<std::string>& must_mention) {
    const Result r = run_dem("-i " + write(dir, "bad.yaml", yaml).string());
    EXPECT_EQ(r.exit_code, 2) << r.output;
    for (const std::string& m : must_mention) EXPECT_NE(r.output.find(m), std::string::npos) << "no '" << m << "' in:\n" << r.output;
    EXPECT_EQ(slurp(out / "thermo.csv"), thermo_before) << "a bad input overwrote earlier results";
  }
  fs::path dir, out;
  std::string thermo_before;
};

TEST_F(DemCli, GoodInputWritesThermoAndDump) {
  EXPECT_NE(thermo_before.find("step,time,kinetic_energy,elastic_energy"), std::string::npos);
  const std::string dump = slurp(out / "dump.lammpstrj");
  EXPECT_NE(dump.find("ITEM: ATOMS id type x y z radius vx vy vz fx fy fz"), std::string::npos);
  EXPECT_NE(dump.find("ITEM: BOX BOUNDS pp pp pp"), std::string::npos);
}

// Started by mpirun as several processes (the launcher's environment says so): a serial build would run the
// whole input once per process, every copy writing the same files. Exit 2 on each, the first one saying why,
// nothing written. (In an MPI build the runs refuse more than one rank until they are distributed.)
TEST_F(DemCli, ManyProcessesFromASerialBuildAreRefused) {
  if (debris::comm::mpi_build()) GTEST_SKIP() << "an MPI build counts its ranks through MPI itself";
  const std::string input = write(dir, "good_again.yaml", small_input(out.string())).string();
  const Result first = debris::test::run_command("OMPI_COMM_WORLD_SIZE=4 OMPI_COMM_WORLD_RANK=0 " +
                                                     std::string(DEBRIS_DEM_EXECUTABLE), "-i " + input);
  EXPECT_EQ(first.exit_code, 2) << first.output;
  EXPECT_NE(first.output.find("'mpirun -np' = 4"), std::string::npos) << first.output;
  EXPECT_NE(first.output.find("built without MPI (DEBRIS_MPI=OFF)"), std::string::npos) << first.output;
  const Result other = debris::test::run_command("PMI_SIZE=2 PMI_RANK=1 " + std::string(DEBRIS_DEM_EXECUTABLE),
                                                 "-i " + input);
  EXPECT_EQ(other.exit_code, 2) << other.output;
  EXPECT_EQ(other.output, "") << "only the first process explains";
  EXPECT_EQ(slurp(out / "thermo.csv"), thermo_before) << "a refused run overwrote earlier results";
  // One process under a launcher (mpirun -np 1) runs as usual.
  const Result one = debris::test::run_command("OMPI_COMM_WORLD_SIZE=1 " + std::string(DEBRIS_DEM_EXECUTABLE),
                                               "-i " + input);
  EXPECT_EQ(one.exit_code, 0) << one.output;
}

TEST_F(DemCli, PoissonRatioAboveQuarter) {
  expect_rejected(replace(small_input(out.string()), "poisson_ratio: 0.15", "poisson_ratio: 0.3"),
                  {"material.poisson_ratio", "0.3", "0.25"});
}

TEST_F(DemCli, NegativeDiameter) {
  expect_rejected(replace(small_input(out.string()), "    diameter: 100", "    diameter: -100"), {"diameter", "-100"});
}

TEST_F(DemCli, NegativeRadiusInDataFile) {
  write(dir, "bad.data",
        "LAMMPS data\n\n2 atoms\n1 atom types\n0 400 xlo xhi\n0 400 ylo yhi\n0 400 zlo zhi\n\nAtoms # sphere\n\n"
        "1 1 100 1 100 100 100\n2 1 -100 1 200 100 100\n");
  std::string yaml = small_input(out.string());
  yaml = replace(yaml, R"(  lattice:
    kind: fcc
    spacing: 100
    diameter: 100
    cells: [3, 3, 3]
)", "  lammps_data: bad.data\n");
  yaml = replace(yaml, "periodic: [true, true, true]", "periodic: [false, false, false]");
  expect_rejected(yaml, {"diameter", "-100", "bad.data"});
}

// Two rows of the data file at one place (ids 1 and 2): eq 2's normal is 0 / 0. Refused at set-up, naming both.
TEST_F(DemCli, RepeatedParticleInDataFile) {
  write(dir, "twice.data",
        "LAMMPS data\n\n3 atoms\n1 atom types\n0 400 xlo xhi\n0 400 ylo yhi\n0 400 zlo zhi\n\nAtoms # sphere\n\n"
        "1 1 100 1 100 100 100\n2 1 100 1 100 100 100\n3 1 100 1 200 100 100\n");
  std::string yaml = replace(small_input(out.string()), R"(  lattice:
    kind: fcc
    spacing: 100
    diameter: 100
    cells: [3, 3, 3]
)", "  lammps_data: twice.data\n");
  yaml = replace(yaml, "periodic: [true, true, true]", "periodic: [false, false, false]");
  expect_rejected(yaml, {"'particles'", "particles id 1 and id 2", "repeated particle"});
}

// Global damping F = -c v with c = f c_c (eq 21): over one step it takes f c_c dt / m of a particle's
// velocity. For equal particles at dt = 0.1 dt_c that is 0.2 f (dt_c = sqrt(2 m / k_N), c_c = sqrt(2 k_N m)),
// so f must stay below 5, in the run and in a stage alike; 20 c_c gave NaN by step 100.
TEST_F(DemCli, GlobalDampingPastItsStableRange) {
  const std::string yaml = small_input(out.string());
  expect_rejected(replace(yaml, "time_step_fraction: 0.1", "time_step_fraction: 0.1\n  global_damping: 20"),
                  {"run.global_damping", "20", "must stay below"});
  expect_rejected(replace(yaml, "time_step_fraction: 0.1", "time_step_fraction: 0.1\n  global_damping: 5.05"),
                  {"run.global_damping", "5.05"});
  expect_rejected(yaml + "stages:\n  - {name: damped, duration: 2000, global_damping: 5.05}\n",
                  {"stages[0].global_damping", "5.05"});
  const Result below = run_dem("-i " + write(dir, "below.yaml",
                                             replace(yaml, "time_step_fraction: 0.1",
                                                     "time_step_fraction: 0.1\n  global_damping: 4.95")).string() +
                               " -o " + (dir / "below").string());
  EXPECT_EQ(below.exit_code, 0) << below.output;
}

TEST_F(DemCli, TimeStepAboveCritical) {
  expect_rejected(replace(small_input(out.string()), "time_step_fraction: 0.1", "time_step: 200"),
                  {"run.time_step", "200", "critical time step", "143.99"});
}

TEST_F(DemCli, TimeStepAboveCriticalAcceptedWhenInsisting) {
  std::string yaml = replace(small_input(out.string()), "time_step_fraction: 0.1",
                             "time_step: 150\n  allow_unstable_time_step: true");
  yaml = replace(yaml, "steps: 20", "steps: 2");
  const Result r = run_dem("-i " + write(dir, "insist.yaml", yaml).string() + " -o " + (dir / "insist").string());
  EXPECT_EQ(r.exit_code, 0) << r.output;
}

TEST_F(DemCli, MissingInputFile) {
  const Result r = run_dem("-i " + (dir / "no_such_file.yaml").string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("no_such_file.yaml"), std::string::npos) << r.output;
}

TEST_F(DemCli, MissingDataFile) {
  std::string yaml = replace(small_input(out.string()), R"(  lattice:
    kind: fcc
    spacing: 100
    diameter: 100
    cells: [3, 3, 3]
)", "  lammps_data: missing.data\n");
  // The key and the path it was looked for at, beside the input file (a copied input's usual slip).
  expect_rejected(yaml, {"'particles.lammps_data' = missing.data", "no such file",
                         (dir / "missing.data").lexically_normal().string(), "taken from the input file's folder"});
}

// A tiling count that is not a whole number >= 1 names the key and the counts.
TEST_F(DemCli, BadReplicate) {
  const std::string yaml = small_input(out.string());
  expect_rejected(replace(yaml, "    cells: [3, 3, 3]\n", "    cells: [3, 3, 3]\n  replicate: [2, 0, 1]\n"),
                  {"particles.replicate", "whole number from 1 to 1000"});
  expect_rejected(replace(yaml, "    cells: [3, 3, 3]\n", "    cells: [3, 3, 3]\n  replicate: [2, 1.5, 1]\n"),
                  {"particles.replicate", "1.5"});
  expect_rejected(replace(yaml, "    cells: [3, 3, 3]\n", "    cells: [3, 3, 3]\n  replicate: [2, 2]\n"),
                  {"particles.replicate", "three counts"});
}

// A rough surface carves by particle centres: features shorter than two particle diameters cannot be cut by
// spheres. The small input's particles are 100 across, its box 424.26 on each side.
TEST_F(DemCli, RoughSurfaceFinerThanTwoDiameters) {
  const std::string surface = "{surface: {normal: y, side: above, at: 212, self_affine: {hurst: 0.8, rms_height: 20, "
                              "cutoff_wavelength: 150, seed: 3}, grid_spacing: 20}}";
  expect_rejected(small_input(out.string()) + "remove: " + surface + "\n",
                  {"'remove.surface.self_affine.cutoff_wavelength' = 150", "shortest wavelength 150",
                   "two particle diameters (2 x 100 = 200", "cannot be carved by spheres"});
  expect_rejected(small_input(out.string()) + "labels:\n  - {name: rough, region: " + surface + "}\n",
                  {"'labels[0].region.surface.self_affine.cutoff_wavelength' = 150", "cannot be carved"});
  expect_rejected(small_input(out.string()) + "groups:\n  - {name: rough, region: " + surface + "}\n",
                  {"'groups[0].region.surface.self_affine.cutoff_wavelength' = 150", "cannot be carved"});
  // A measured map of 8 x 8 points over the box: spacing 53.03, shortest wavelength 106.07.
  std::string map;
  for (int i = 0; i < 8; ++i) map += "1 -2 3 0 -1 2 -3 0\n";
  write(dir, "fine.txt", map);
  expect_rejected(small_input(out.string()) +
                      "remove: {surface: {normal: y, side: above, at: 212, height_map: {file: fine.txt, "
                      "spacing: [53.0330085890, 53.0330085890]}}}\n",
                  {"'remove.surface.height_map.spacing' = 53.033008589", "shortest wavelength 106.066017178",
                   "2 x 100 = 200", "cannot be carved"});
}

// A map of 4 x 4 points (shortest wavelength 212.1 > 200), found beside the input: the top half goes.
TEST_F(DemCli, RoughSurfaceFromAMapBesideTheInput) {
  write(dir, "coarse.txt", "10 -5 0 5\n-10 0 5 0\n0 5 -5 10\n5 0 -10 0\n");
  const fs::path other = dir / "rough_out";
  const Result r = run_dem("-i " + write(dir, "rough.yaml", small_input(other.string()) +
                                                                "remove: {surface: {normal: y, side: above, at: 212, "
                                                                "height_map: {file: coarse.txt, spacing: [106.066017178, "
                                                                "106.066017178]}}}\n")
                                       .string());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_FALSE(slurp(other / "thermo.csv").empty()) << r.output;
}

TEST_F(DemCli, MalformedYaml) {
  expect_rejected(replace(small_input(out.string()), "  density: 1\n", "  density: [1\n"), {"line"});
}

TEST_F(DemCli, UnknownKey) {
  expect_rejected(replace(small_input(out.string()), "youngs_modulus: 1", "youngs_modulus: 1\n  youngs_modulu: 2"),
                  {"material.youngs_modulu", "unknown key"});
}

// Group members by type or id: whole numbers only (1.7 was once cut to 1 without a word).
TEST_F(DemCli, NonIntegerGroupTypeOrId) {
  const std::string groups = "groups:\n  - name: g\n    motion: frozen\n";
  expect_rejected(replace(small_input(out.string()), "run:\n", groups + "    types: [1.7]\nrun:\n"),
                  {"groups[0].types[0]", "1.7", "whole number"});
  expect_rejected(replace(small_input(out.string()), "run:\n", groups + "    ids: [3, 4.5e0]\nrun:\n"),
                  {"groups[0].ids[1]", "4.5e0", "whole number"});
}

// A group name heads thermo.csv columns: one with a comma was accepted and the run stopped (exit 3) after
// creating the output directory.
TEST_F(DemCli, GroupNameThatCannotHeadAColumn) {
  const std::string groups = "groups:\n  - name: top, bottom\n    motion: frozen\n    types: [1]\nrun:\n";
  expect_rejected(replace(small_input(out.string()), "run:\n", groups), {"groups[0].name", "top, bottom", "','"});
}

TEST_F(DemCli, WrongUnit) {
  expect_rejected(replace(small_input(out.string()), "youngs_modulus: 1", "youngs_modulus: 73 nm"),
                  {"material.youngs_modulus", "73 nm"});
}

TEST_F(DemCli, NotANumber) {
  expect_rejected(replace(small_input(out.string()), "restitution: 0.95", "restitution: high"),
                  {"material.restitution", "high"});
}

// A per-axis force group with a load on a prescribed axis: exit 2 naming the key and the value, and no
// output directory made (the earlier results elsewhere survive too).
TEST_F(DemCli, LoadOnPrescribedAxis) {
  const fs::path never = dir / "never_written";
  std::string yaml = replace(small_input(never.string()), "run:\n", R"(groups:
  - name: top
    region: {y: [300, inf]}
    motion: force
    velocity: [0.001, free, 0]
    force: [0.5, -1, 0]
run:
)");
  const Result r = run_dem("-i " + write(dir, "bad.yaml", yaml).string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  for (const char* m : {"groups[0].force", "[0.5, -1, 0]", "x velocity is prescribed"})
    EXPECT_NE(r.output.find(m), std::string::npos) << "no '" << m << "' in:\n" << r.output;
  EXPECT_FALSE(fs::exists(never)) << "a bad input made its output directory";
  EXPECT_EQ(slurp(out / "thermo.csv"), thermo_before);
  // The same group with the x load removed runs.
  const Result ok = run_dem("-i " + write(dir, "good_axes.yaml", replace(yaml, "force: [0.5, -1, 0]", "force: [0, -1, 0]")).string());
  EXPECT_EQ(ok.exit_code, 0) << ok.output;
  EXPECT_TRUE(fs::exists(never / "thermo.csv"));
}

TEST(DemCliHelp, HelpListsOptions) {
  const Result r = run_dem("--help");
  EXPECT_EQ(r.exit_code, 0);
  for (const char* opt : {"--input", "--output", "--threads"}) EXPECT_NE(r.output.find(opt), std::string::npos) << opt;
}

// The default input: the D = 10 nm, d0 = 6 nm junction of scenarios/wear with pictures. It ends with the
// verdict scenarios/wear/RESULTS.md records for it (ductile), and names its pictures in its last lines.
TEST(DemCliDefault, DefaultInputIsAShearedJunctionWithItsVerdictAndPictures) {
  const fs::path d = scratch("default");
  const Result r = run_dem("-i " + std::string(DEBRIS_SOURCE_DIR) + "/scenarios/dem/default.yaml -o " + d.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("wear: verdict ductile"), std::string::npos) << r.output;
  const std::string last_lines = r.output.substr(r.output.rfind("output written to"));
  EXPECT_NE(last_lines.find("side_view.png, tangential_force.png"), std::string::npos) << last_lines;
  for (const char* f : {"pictures.gp", "side_start.dat", "side_end.dat", "wear.csv"})
    EXPECT_TRUE(fs::is_regular_file(d / f)) << f;
  // Every particle in both side views (525 after carving, RESULTS.md), with its radius and body.
  for (const char* f : {"side_start.dat", "side_end.dat"}) {
    std::istringstream in(slurp(d / f));
    std::string line;
    int rows = 0;
    while (std::getline(in, line))
      if (!line.empty() && line[0] != '#') ++rows;
    EXPECT_EQ(rows, 525) << f;
  }
  if (std::system("command -v gnuplot > /dev/null 2>&1") == 0) {
    EXPECT_NE(r.output.find("pictures: " + (d / "side_view.png").string()), std::string::npos) << r.output;
    for (const char* f : {"side_view.png", "tangential_force.png"}) {
      EXPECT_TRUE(fs::is_regular_file(d / f)) << f;
      EXPECT_GT(fs::file_size(d / f), 10000u) << f;
    }
  } else {
    EXPECT_NE(r.output.find("pictures skipped: gnuplot not found"), std::string::npos) << r.output;
  }
}

TEST(DemCliHcpWallLoad, TopWallReachesItsEquilibriumDisplacement) {
  const fs::path d = scratch("hcp_wall_load");
  const Result r = run_dem("-i " + std::string(DEBRIS_SOURCE_DIR) + "/scenarios/dem/hcp_wall_load.yaml -o " +
                           d.string() + " --threads 2");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("critical time step"), std::string::npos);
  // The loaded top wall ends in equilibrium: its reaction balances the applied 0.01 x (1000 x 866.03).
  const std::string thermo = slurp(d / "thermo.csv");
  const std::string last = thermo.substr(thermo.rfind('\n', thermo.size() - 2) + 1);
  std::vector<double> v;
  std::stringstream ss(last);
  for (std::string cell; std::getline(ss, cell, ',');) v.push_back(std::stod(cell));
  std::vector<std::string> names;
  std::stringstream hs(thermo.substr(0, thermo.find('\n')));
  for (std::string cell; std::getline(hs, cell, ',');) names.push_back(cell);
  ASSERT_EQ(v.size(), names.size());
  auto at = [&](const std::string& name) {
    const auto it = std::find(names.begin(), names.end(), name);
    EXPECT_NE(it, names.end()) << name;
    return it == names.end() ? 0.0 : v[static_cast<std::size_t>(it - names.begin())];
  };
  const double applied = 0.01 * 1000.0 * 5 * 100 * std::sqrt(3.0);
  EXPECT_NEAR(at("top_fy"), applied, 1e-6 * applied);
  EXPECT_NEAR(at("bottom_fy"), -applied, 1e-6 * applied);
  EXPECT_LT(at("top_dy"), -5.0);  // compressed
  // The load did the work (its force times the distance it moved the wall down), and the damped settling
  // dissipated what the block did not store; the balance closes within 1% of it.
  EXPECT_GT(at("top_work"), 0.0);
  EXPECT_EQ(at("bottom_work"), 0.0);  // a frozen wall does none
  EXPECT_LT(std::abs(at("energy_residual")), 0.01 * at("work_in"));
}

std::string last_frame(const fs::path& dump) {
  const std::string t = slurp(dump);
  return t.substr(t.rfind("ITEM: TIMESTEP"));
}

// 2N steps in one run equal N steps, then --restart to 2N: same final frame and the same thermo table.
TEST(DemCliRestart, RestartContinuesBitForBit) {
  const fs::path d = scratch("restart");
  std::string yaml = replace(small_input((d / "full").string()), "steps: 20", "steps: 60");
  yaml = replace(yaml, "cells: [3, 3, 3]", "cells: [3, 3, 3]\n    size_spread: 0.05\n    displacement: 3");
  const fs::path full = write(d, "full.yaml", yaml);
  const fs::path half = write(d, "half.yaml", replace(replace(yaml, "steps: 60", "steps: 30"), (d / "full").string(),
                                                       (d / "split").string()));
  ASSERT_EQ(run_dem("-i " + full.string()).exit_code, 0);
  ASSERT_EQ(run_dem("-i " + half.string()).exit_code, 0);
  const Result r = run_dem("--restart " + (d / "split" / "checkpoint.h5").string() + " -i " + full.string() + " -o " +
                           (d / "split").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("restarting from"), std::string::npos);
  EXPECT_EQ(last_frame(d / "full" / "dump.lammpstrj"), last_frame(d / "split" / "dump.restart30.lammpstrj"));
  EXPECT_EQ(slurp(d / "full" / "thermo.csv"), slurp(d / "split" / "thermo.csv"));
  // The restarted run wrote its own checkpoint at step 60, keeping the 60-step input. Without -i that input
  // is used: nothing is left to run. An input asking for fewer steps than already done is an error.
  const Result again = run_dem("--restart " + (d / "split" / "checkpoint.h5").string() + " -o " + (d / "again").string());
  EXPECT_EQ(again.exit_code, 0) << again.output;
  EXPECT_NE(again.output.find("at step 60"), std::string::npos) << again.output;
  const fs::path shorter = write(d, "short.yaml", replace(yaml, "steps: 60", "steps: 10"));
  const Result back = run_dem("--restart " + (d / "split" / "checkpoint.h5").string() + " -i " + shorter.string());
  EXPECT_EQ(back.exit_code, 2) << back.output;
  EXPECT_NE(back.output.find("run.steps"), std::string::npos) << back.output;
}

// A restart reads only what it needs: from another directory, without -i, with the data file gone; an -i
// whose system differs (material, data file path) is read for its run keys only, and the keys the
// checkpoint overrides are named in one line. The result equals the run in one piece.
TEST(DemCliRestart, RestartsFromAnotherDirectoryWithoutTheInputOrItsDataFile) {
  const fs::path d = scratch("restart_elsewhere");
  fs::create_directories(d / "a");
  fs::create_directories(d / "b");
  fs::create_directories(d / "c");
  // Eight touching particles, a little off their cube (they start moving), in an open box.
  const std::string data =
      "LAMMPS data\n\n8 atoms\n1 atom types\n0 400 xlo xhi\n0 400 ylo yhi\n0 400 zlo zhi\n\nAtoms # sphere\n\n"
      "1 1 200 1 100 100 100\n2 1 200 1 301 100 100\n3 1 200 1 100 298 100\n4 1 200 1 300 300 103\n"
      "5 1 200 1 102 100 300\n6 1 200 1 300 99 300\n7 1 200 1 100 300 301\n8 1 200 1 297 302 300\n";
  write(d / "a", "cube.data", data);
  auto input = [&](long steps, const std::string& out_dir) {
    std::string yaml = replace(small_input(out_dir), R"(  lattice:
    kind: fcc
    spacing: 100
    diameter: 100
    cells: [3, 3, 3]
)", "  lammps_data: cube.data\n");
    yaml = replace(yaml, "periodic: [true, true, true]", "periodic: [false, false, false]");
    return replace(yaml, "steps: 20", "steps: " + std::to_string(steps));
  };
  write(d / "a", "whole.yaml", input(80, (d / "whole").string()));
  write(d / "a", "part.yaml", input(40, "out"));
  const auto in = [&](const fs::path& cwd) { return "cd " + cwd.string() + " && " + DEBRIS_DEM_EXECUTABLE; };
  for (const char* yaml : {"whole.yaml", "part.yaml"}) {
    const Result r = debris::test::run_command(in(d / "a"), std::string("-i ") + yaml);
    ASSERT_EQ(r.exit_code, 0) << r.output;
  }
  fs::rename(d / "a" / "cube.data", d / "cube.data.gone");
  const std::string checkpoint = (d / "a" / "out" / "checkpoint.h5").string();
  // Without -i: the kept input, whose 40 steps are done; nothing is read but the checkpoint.
  const Result same = debris::test::run_command(in(d / "b"), "--restart " + checkpoint);
  ASSERT_EQ(same.exit_code, 0) << same.output;
  EXPECT_NE(same.output.find("at step 40"), std::string::npos) << same.output;
  EXPECT_EQ(same.output.find("ignored at restart"), std::string::npos) << same.output;
  // With an -i for 80 steps whose data file does not exist there and whose material differs.
  write(d / "c", "more.yaml", replace(input(80, "unused"), "youngs_modulus: 1", "youngs_modulus: 2"));
  const Result more = debris::test::run_command(in(d / "b"), "--restart " + checkpoint + " -i ../c/more.yaml");
  ASSERT_EQ(more.exit_code, 0) << more.output;
  EXPECT_NE(more.output.find("ignored at restart: material (the checkpoint's"), std::string::npos) << more.output;
  // Without -o the restart continues in the checkpoint's own directory.
  EXPECT_EQ(slurp(d / "whole" / "thermo.csv"), slurp(d / "a" / "out" / "thermo.csv"));
  EXPECT_FALSE(fs::exists(d / "b" / "out"));
  EXPECT_FALSE(fs::exists(d / "c" / "unused"));
}

// A run pushed past the critical time step blows up: it stops at a health check with a message naming the
// step and the particle, exits 3, and the last good checkpoint is the one written before.
TEST(DemCliRestart, UnstableRunStopsAndKeepsTheLastGoodCheckpoint) {
  const fs::path d = scratch("unstable");
  std::string yaml = replace(small_input((d / "out").string()), "time_step_fraction: 0.1",
                             "time_step_fraction: 1.02\n  allow_unstable_time_step: true");
  yaml = replace(yaml, "steps: 20", "steps: 400");
  yaml = replace(yaml, "cells: [3, 3, 3]", "cells: [3, 3, 3]\n    displacement: 0.5");
  yaml = replace(yaml, "  thermo_every: 10", "  thermo_every: 1\n  checkpoint_every: 1");
  const Result r = run_dem("-i " + write(d, "bad.yaml", yaml).string());
  EXPECT_EQ(r.exit_code, 3) << r.output;
  EXPECT_NE(r.output.find("stopped:"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("at step"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("particle"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("last good checkpoint"), std::string::npos) << r.output;
  // The checkpoint left behind is a sound state from before the failure.
  debris::DemSimulation back = debris::DemSimulation::from_checkpoint((d / "out" / "checkpoint.h5").string());
  EXPECT_EQ(back.health_check(), "");
  EXPECT_GT(back.step_count(), 0);
}

// A run killed with SIGKILL in the middle leaves a trajectory whose every listed frame reads, and a
// checkpoint that loads.
TEST(DemCliRestart, KilledRunLeavesReadableTrajectoryAndCheckpoint) {
  const fs::path d = scratch("killed");
  std::string yaml = replace(small_input((d / "out").string()), "steps: 20", "steps: 100000000");
  yaml = replace(yaml, "cells: [3, 3, 3]", "cells: [6, 6, 6]");
  yaml = replace(yaml, "  dump_every: 10", "  dump_every: 0\n  trajectory_every: 5\n  checkpoint_every: 20");
  const fs::path input = write(d, "long.yaml", yaml);
  // Kill it once a checkpoint (written by rename, so whole when it exists) and two trajectory frames are
  // there, polling every 0.1 s for up to 300 s: a fixed sleep was too short on a loaded machine.
  const std::string ckpt = (d / "out" / "checkpoint.h5").string(), xmf_path = (d / "out" / "trajectory.xmf").string();
  const Result r = run_dem("-i " + input.string() + " > /dev/null 2>&1 & pid=$!; i=0; while [ $i -lt 3000 ]; do " +
                           "if [ -f " + ckpt + " ] && [ \"$(grep -c '<Time Value=' " + xmf_path +
                           " 2>/dev/null)\" -ge 2 ] 2>/dev/null; then echo ready; break; fi; sleep 0.1; i=$((i+1)); " +
                           "done; kill -9 $pid; wait $pid; true");
  ASSERT_NE(r.output.find("ready"), std::string::npos) << "no checkpoint and two frames within 300 s\n" << r.output;
  const std::string xmf = slurp(d / "out" / "trajectory.xmf");
  std::size_t frames = 0;
  for (auto pos = xmf.find("<Time Value="); pos != std::string::npos; pos = xmf.find("<Time Value=", pos + 1)) ++frames;
  ASSERT_GE(frames, 2u);
  debris::h5::File f((d / "out" / "trajectory.h5").string(), debris::h5::File::Mode::read_only);
  for (std::size_t k = 0; k < frames; ++k) {
    const auto pos = f.read<double>("frames/" + std::to_string(k) + "/position");
    EXPECT_EQ(pos.values.size(), 3u * 864u) << "frame " << k;
  }
  debris::DemSimulation back = debris::DemSimulation::from_checkpoint((d / "out" / "checkpoint.h5").string());
  EXPECT_EQ(back.particles().size(), 864u);
}

}  // namespace
