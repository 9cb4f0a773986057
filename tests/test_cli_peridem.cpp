// debris_peridem from the command line: each bad input ends with exit 2 and a message naming the key and the
// value, before anything is written (an earlier thermo CSV in the output directory survives); a good input
// writes its thermo CSV and an HDF5 node trajectory that reads back through the HDF5 C API with the values
// the input set; --restart continues bit for bit; a blown-up run stops with exit 3 naming the step and the
// node and keeps its last good checkpoint; the default inputs parse and the two-particle drop bounces.
#include <gtest/gtest.h>
#include <hdf5.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "core/error.hpp"
#include "scenarios/common/peridem/peridem_input.hpp"
#include "scenarios/common/peridem/peridem_simulation.hpp"
#include "tests/cli_helpers.hpp"

namespace {

namespace fs = std::filesystem;

using Result = debris::test::CommandResult;

Result run_peridem(const std::string& args) { return debris::test::run_command(DEBRIS_PERIDEM_EXECUTABLE, args); }

fs::path scratch(const std::string& name) { return debris::test::fresh_directory("debris_peridem_cli_" + name); }

// Two discs (R = 1 mm, Gmsh size 0.3 mm) above a wall; the top one falls at 10 m/s onto the bottom one,
// which rests on the wall. 60 steps: they have not met yet (they meet near step 150).
std::string small_input(const std::string& out_dir) {
  return R"(dimension: 2
materials:
  M1:
    density: 1200 kg/m^3
    bulk_modulus: 0.0216 GPa
    shear_modulus: 0.01296 GPa
    fracture_energy: 50 J/m^2
    horizon: 0.6 mm
shapes:
  disc:
    type: circle
    radius: 1 mm
    mesh_size: 0.3 mm
  floor:
    type: rectangle
    lo: [-2 mm, -0.6 mm, 0]
    hi: [2 mm, 0, 0]
    mesh_size: 0.3 mm
grains:
  - name: bottom
    shape: disc
    material: M1
    centre: [0, 1.18 mm, 0]
  - name: top
    shape: disc
    material: M1
    centre: [0, 3.5 mm, 0]
    radius: 1 mm
    velocity: [0, -10 m/s, 0]
walls:
  - name: floor
    shape: floor
    material: M1
contact:
  restitution: 0.95
gravity: [0, -10 m/s^2, 0]
run:
  time_step: 0.1 us
  steps: 60
output:
  directory: )" +
         out_dir + R"(
  thermo_every: 20
  trajectory_every: 20
)";
}

using debris::test::replace;

using debris::test::write;

using debris::test::slurp;

std::vector<double> csv_row(const std::string& line) {
  std::vector<double> v;
  std::stringstream ss(line);
  for (std::string cell; std::getline(ss, cell, ',');) v.push_back(std::stod(cell));
  return v;
}

std::string last_line(const std::string& text) {
  const std::size_t end = text.find_last_not_of('\n');
  return text.substr(text.rfind('\n', end) + 1, end - text.rfind('\n', end));
}

// ---- the HDF5 C API, independent of core/io/hdf5_file.hpp ----

struct H5Data {
  std::vector<hsize_t> dims;
  std::vector<double> values;
};

H5Data read_h5(hid_t file, const std::string& name, hid_t mem_type = H5T_NATIVE_DOUBLE) {
  H5Data d;
  const hid_t set = H5Dopen2(file, name.c_str(), H5P_DEFAULT);
  EXPECT_GE(set, 0) << name;
  if (set < 0) return d;
  const hid_t space = H5Dget_space(set);
  d.dims.resize(static_cast<std::size_t>(H5Sget_simple_extent_ndims(space)));
  H5Sget_simple_extent_dims(space, d.dims.data(), nullptr);
  std::size_t n = 1;
  for (hsize_t k : d.dims) n *= k;
  if (mem_type == H5T_NATIVE_DOUBLE) {
    d.values.resize(n);
    EXPECT_GE(H5Dread(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, d.values.data()), 0) << name;
  } else {
    std::vector<long long> ints(n);
    EXPECT_GE(H5Dread(set, H5T_NATIVE_LLONG, H5S_ALL, H5S_ALL, H5P_DEFAULT, ints.data()), 0) << name;
    d.values.assign(ints.begin(), ints.end());
  }
  H5Sclose(space);
  H5Dclose(set);
  return d;
}


class PeridemCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir = scratch(::testing::UnitTest::GetInstance()->current_test_info()->name());
    out = dir / "out";
    // A good run first: its results must survive every bad run pointed at the same directory.
    const Result ok = run_peridem("-i " + write(dir, "good.yaml", small_input(out.string())).string());
    ASSERT_EQ(ok.exit_code, 0) << ok.output;
    good_output = ok.output;
    thermo_before = slurp(out / "thermo.csv");
    ASSERT_FALSE(thermo_before.empty());
  }
  void expect_rejected(const std::string& yaml, const std::vector<std::string>& must_mention) {
    const Result r = run_peridem("-i " + write(dir, "bad.yaml", yaml).string());
    EXPECT_EQ(r.exit_code, 2) << r.output;
    for (const std::string& m : must_mention)
      EXPECT_NE(r.output.find(m), std::string::npos) << "no '" << m << "' in:\n" << r.output;
    EXPECT_EQ(slurp(out / "thermo.csv"), thermo_before) << "a bad input overwrote earlier results";
  }
  fs::path dir, out;
  std::string thermo_before, good_output;
};

TEST_F(PeridemCli, GoodInputWritesThermoAndTheTimePerPass) {
  EXPECT_EQ(thermo_before.substr(0, thermo_before.find('\n')),
            "step,time,kinetic_energy,bond_energy,contact_energy,max_damage,broken_bonds,contact_pairs,floor_fx,"
            "floor_fy,bottom_x,bottom_y,bottom_vx,bottom_vy,bottom_kinetic_energy,bottom_damage,bottom_broken_bonds,"
            "top_x,top_y,top_vx,top_vy,top_kinetic_energy,top_damage,top_broken_bonds");
  // Rows at steps 0, 20, 40, 60; the top grain falls freely (60 steps are before the contact).
  const std::vector<double> first = csv_row(thermo_before.substr(thermo_before.find('\n') + 1));
  const std::vector<double> last = csv_row(last_line(thermo_before));
  ASSERT_EQ(last.size(), 24u);
  EXPECT_EQ(last[0], 60);
  EXPECT_NEAR(last[1], 6e-6, 1e-18);
  // top_y falls freely: eq 32 is exact for a constant force, y = y0 - v0 t - g t^2 / 2.
  EXPECT_NEAR(last[18] - first[18], -10.0 * 6e-6 - 0.5 * 10.0 * 36e-12, 1e-15);
  EXPECT_NEAR(first[20], -10.0, 1e-12);                // top_vy as given
  EXPECT_EQ(first[14], 0.0);                           // bottom_kinetic_energy: at rest
  EXPECT_NEAR(first[21], first[2], 1e-15 * first[2]);  // the top grain holds all the kinetic energy
  EXPECT_EQ(last[6], 0);                               // no broken bond
  EXPECT_EQ(last[7], 0);                               // no contact yet
  for (const char* pass : {"integration", "neighbours", "bonds", "contact", "output", "M node-steps/s"})
    EXPECT_NE(good_output.find(pass), std::string::npos) << pass;
}

// The node trajectory through the HDF5 C API: the frames the .xmf lists, each N x 3, the static node data,
// and values the input set exactly (the top grain's initial velocity, the wall at rest, node volumes > 0).
TEST_F(PeridemCli, TrajectoryReadsBackThroughTheHdf5CApi) {
  ASSERT_EQ(debris::test::count_xmf_frames(out / "trajectory.xmf"), 4u);
  const std::string xmf = slurp(out / "trajectory.xmf");
  for (const char* a : {"Name=\"damage\"", "Name=\"grain\"", "Name=\"velocity\"", "Name=\"volume\"", "Name=\"id\""})
    EXPECT_NE(xmf.find(a), std::string::npos) << a;
  const hid_t f = H5Fopen((out / "trajectory.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  const H5Data grain = read_h5(f, "/nodes/grain", H5T_NATIVE_LLONG);
  const H5Data id = read_h5(f, "/nodes/id", H5T_NATIVE_LLONG);
  const H5Data volume = read_h5(f, "/nodes/volume");
  const std::size_t n = grain.values.size();
  ASSERT_GT(n, 100u);
  EXPECT_EQ(id.values.size(), n);
  for (std::size_t i = 0; i < n; ++i) {
    EXPECT_EQ(id.values[i], static_cast<double>(i + 1));
    EXPECT_GT(volume.values[i], 0.0);
  }
  for (int k = 0; k < 4; ++k) {
    const std::string frame = "/frames/" + std::to_string(k) + "/";
    const H5Data pos = read_h5(f, frame + "position");
    ASSERT_EQ(pos.dims, (std::vector<hsize_t>{n, 3}));
    const H5Data vel = read_h5(f, frame + "velocity");
    const H5Data damage = read_h5(f, frame + "damage");
    ASSERT_EQ(damage.values.size(), n);
    for (std::size_t i = 0; i < n; ++i) {
      EXPECT_EQ(pos.values[3 * i + 2], 0.0);                                        // 2D
      EXPECT_LT(damage.values[i], 1e-6);                                            // free flight: no stretch
      if (k == 0 && grain.values[i] == 1) EXPECT_EQ(vel.values[3 * i + 1], -10.0);  // top grain, as given
      if (grain.values[i] == 2) EXPECT_EQ(vel.values[3 * i + 1], 0.0);              // the wall
    }
  }
  EXPECT_EQ(H5Lexists(f, "/frames/4", H5P_DEFAULT), 0) << "only the listed frames";
  H5Fclose(f);
}

TEST_F(PeridemCli, UnknownKey) {
  expect_rejected(replace(small_input(out.string()), "restitution: 0.95", "restitution: 0.95\n  restitutoin: 0.9"),
                  {"contact.restitutoin", "unknown key", "line"});
}

TEST_F(PeridemCli, NegativeRadius) {
  expect_rejected(
      replace(small_input(out.string()), "    radius: 1 mm\n    velocity", "    radius: -1 mm\n    velocity"),
      {"grains[1].radius", "-0.001"});
}

TEST_F(PeridemCli, MissingMeshFile) {
  expect_rejected(replace(small_input(out.string()), R"(    type: circle
    radius: 1 mm
    mesh_size: 0.3 mm)",
                          "    type: mesh_file\n    file: no_such_mesh.msh\n    reference_radius: 1 mm"),
                  {"shapes.disc.file", "no_such_mesh.msh", "no such mesh file"});
}

TEST_F(PeridemCli, WrongUnit) {
  expect_rejected(replace(small_input(out.string()), "horizon: 0.6 mm", "horizon: 0.6 GPa"),
                  {"materials.M1.horizon", "0.6 GPa", "line"});
}

TEST_F(PeridemCli, RestitutionAboveOne) {
  expect_rejected(replace(small_input(out.string()), "restitution: 0.95", "restitution: 1.5"),
                  {"contact.restitution", "1.5", "(0, 1]"});
}

TEST_F(PeridemCli, PenetrationLimitOutOfRange) {
  expect_rejected(replace(small_input(out.string()), "time_step: 0.1 us", "time_step: 0.1 us\n  penetration_limit: 0"),
                  {"run.penetration_limit", "0", "(0, 1]"});
}

TEST_F(PeridemCli, UnknownBondBreakingRule) {
  expect_rejected(replace(small_input(out.string()), "horizon: 0.6 mm", "horizon: 0.6 mm\n    bond_breaking: sometimes"),
                  {"bond_breaking", "sometimes", "tension_and_compression"});
}

TEST_F(PeridemCli, GrainPlacedIntoAWallKeepsEarlierResults) {
  expect_rejected(replace(small_input(out.string()), "centre: [0, 1.18 mm, 0]", "centre: [0, 0.95 mm, 0]"),
                  {"grains.bottom", "wall 'floor'"});
}

TEST_F(PeridemCli, TimeStepAboveTheStableOne) {
  expect_rejected(replace(small_input(out.string()), "time_step: 0.1 us", "time_step: 1 us"),
                  {"run.time_step", "1e-06", "stable step", "allow_unstable_time_step"});
}

// Eq 33 bonds a node to its grain's nodes within the horizon: a disc of R = 1 mm meshed at 5 mm (or 0.8 mm)
// with a 0.6 mm horizon is a cloud of unbonded nodes. Refused, naming the shape's mesh size, the horizon and
// their ratio (0.6 / 5 = 0.12, 0.6 / 0.8 = 0.75).
TEST_F(PeridemCli, GrainMeshedAsCoarseAsItsHorizonHasUnbondedNodes) {
  for (const auto& [size, ratio] : {std::pair{"5 mm", "horizon / h = 0.12"}, std::pair{"0.8 mm", "horizon / h = 0.75"}})
    expect_rejected(replace(small_input(out.string()), "    radius: 1 mm\n    mesh_size: 0.3 mm",
                            std::string("    radius: 1 mm\n    mesh_size: ") + size),
                    {"'shapes.disc.mesh_size'", "without a bond", "materials.M1.horizon = 0.0006 m", ratio});
}

// Horizon / mesh size = 0.6 / 0.4 = 1.5: every node has a partner, so the run goes on, with a warning that
// names the ratio. The good input (0.6 / 0.3 = 2) has none.
TEST_F(PeridemCli, HorizonBelowTwiceTheMeshSizeWarns) {
  EXPECT_FALSE(debris::test::contains(good_output, "warning")) << good_output;
  const Result r = run_peridem(
      "-i " + write(dir, "coarse.yaml",
                    replace(replace(small_input((dir / "coarse").string()), "centre: [0, 1.18 mm, 0]", "centre: [0, 1.3 mm, 0]"),
                            "    radius: 1 mm\n    mesh_size: 0.3 mm",
                            "    radius: 1 mm\n    mesh_size: 0.4 mm"))
                  .string());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(debris::test::contains(r.output, "warning: shapes.disc.mesh_size = 0.0004 m")) << r.output;
  EXPECT_TRUE(debris::test::contains(r.output, "horizon / h = 1.5 is below 2")) << r.output;
}

TEST_F(PeridemCli, UnknownShapeAndMaterialNames) {
  expect_rejected(
      replace(small_input(out.string()), "    shape: floor\n    material: M1", "    shape: flor\n    material: M1"),
      {"walls[0].shape", "'flor'", "disc, floor"});
  expect_rejected(
      replace(small_input(out.string()), "    shape: floor\n    material: M1", "    shape: floor\n    material: M3"),
      {"walls[0].material", "'M3'"});
}

TEST_F(PeridemCli, StepsAndFinalTimeTogether) {
  expect_rejected(replace(small_input(out.string()), "  steps: 60", "  steps: 60\n  final_time: 1 ms"), {"run.steps"});
}

TEST_F(PeridemCli, MalformedYaml) {
  expect_rejected(replace(small_input(out.string()), "    horizon: 0.6 mm", "    horizon: [0.6 mm"), {"line"});
}

TEST(PeridemCliHelp, HelpListsOptionsAndNoInputIsExitTwo) {
  const Result r = run_peridem("--help");
  EXPECT_EQ(r.exit_code, 0);
  for (const char* opt : {"--input", "--output", "--threads", "--restart"})
    EXPECT_NE(r.output.find(opt), std::string::npos) << opt;
  EXPECT_EQ(run_peridem("").exit_code, 2);
}

// 2N steps in one run equal N steps, then --restart to 2N: the same thermo table and the same last frame,
// with bonds broken before the checkpoint (the discs meet at 10 m/s from step ~500).
TEST(PeridemCliRestart, RestartContinuesBitForBit) {
  const fs::path d = scratch("restart");
  std::string yaml = replace(small_input((d / "full").string()), "steps: 60", "steps: 1200");
  yaml = replace(yaml, "  thermo_every: 20\n  trajectory_every: 20", "  thermo_every: 50\n  trajectory_every: 600");
  const fs::path full = write(d, "full.yaml", yaml);
  const fs::path half =
      write(d, "half.yaml",
            replace(replace(yaml, "steps: 1200", "steps: 600"), (d / "full").string(), (d / "split").string()));
  ASSERT_EQ(run_peridem("-i " + full.string()).exit_code, 0);
  ASSERT_EQ(run_peridem("-i " + half.string()).exit_code, 0);
  const std::vector<double> at_checkpoint = csv_row(last_line(slurp(d / "split" / "thermo.csv")));
  ASSERT_GT(at_checkpoint[6], 0) << "the test needs bonds broken before the checkpoint";
  const Result r = run_peridem("--restart " + (d / "split" / "checkpoint.h5").string() + " -i " + full.string() +
                               " -o " + (d / "split").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("restarting from"), std::string::npos);
  EXPECT_EQ(slurp(d / "full" / "thermo.csv"), slurp(d / "split" / "thermo.csv"));
  const hid_t a = H5Fopen((d / "full" / "trajectory.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const hid_t b = H5Fopen((d / "split" / "trajectory.restart600.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(a, 0);
  ASSERT_GE(b, 0);
  for (const char* q : {"position", "velocity", "force", "damage", "broken_fraction"})
    EXPECT_EQ(read_h5(a, std::string("/frames/2/") + q).values, read_h5(b, std::string("/frames/1/") + q).values) << q;
  H5Fclose(a);
  H5Fclose(b);
  // Without -i the checkpoint's own input (1200 steps) is used: nothing is left to run. An input asking for
  // fewer steps than already done is an input error.
  const Result again =
      run_peridem("--restart " + (d / "split" / "checkpoint.h5").string() + " -o " + (d / "again").string());
  EXPECT_EQ(again.exit_code, 0) << again.output;
  EXPECT_NE(again.output.find("at step 1200"), std::string::npos) << again.output;
  const Result back = run_peridem("--restart " + (d / "split" / "checkpoint.h5").string() + " -i " + half.string() +
                                  " -o " + (d / "back").string());
  EXPECT_EQ(back.exit_code, 2) << back.output;
  EXPECT_NE(back.output.find("run.steps"), std::string::npos) << back.output;
  // A restart's -i that changes the system or its physics: the checkpoint's continue, and one line says so;
  // the run restarted above with the same system said nothing.
  EXPECT_EQ(r.output.find("ignored at restart"), std::string::npos) << r.output;
  std::string edited = replace(yaml, "fracture_energy: 50 J/m^2", "fracture_energy: 80 J/m^2");
  edited = replace(edited, "time_step: 0.1 us", "time_step: 0.05 us");
  edited = replace(edited, "steps: 1200", "steps: 1300");
  const Result changed = run_peridem("--restart " + (d / "split" / "checkpoint.h5").string() + " -i " +
                                     write(d, "edited.yaml", edited).string() + " -o " + (d / "edited").string());
  EXPECT_EQ(changed.exit_code, 0) << changed.output;
  EXPECT_NE(changed.output.find("ignored at restart: materials, run.time_step"), std::string::npos) << changed.output;
}

// A run far above the stable step blows up: it stops at a check with a message naming the step and the
// node, exits 3, and the checkpoint left behind is the last good state.
TEST(PeridemCliRestart, UnstableRunStopsAndKeepsTheLastGoodCheckpoint) {
  const fs::path d = scratch("unstable");
  std::string yaml = replace(small_input((d / "out").string()), "time_step: 0.1 us",
                             "time_step: 0.5 us\n  allow_unstable_time_step: true");
  yaml = replace(yaml, "steps: 60", "steps: 3000");
  yaml = replace(yaml, "  thermo_every: 20", "  thermo_every: 5\n  checkpoint_every: 5");
  const Result r = run_peridem("-i " + write(d, "bad.yaml", yaml).string());
  EXPECT_EQ(r.exit_code, 3) << r.output;
  for (const char* m : {"stopped:", "step ", "node ", "last good checkpoint"})
    EXPECT_NE(r.output.find(m), std::string::npos) << m << " in:\n" << r.output;
  debris::PeridemSimulation back = debris::PeridemSimulation::from_checkpoint((d / "out" / "checkpoint.h5").string());
  EXPECT_EQ(back.health_check(), "");
  EXPECT_EQ(back.explosion_check(), "");
  EXPECT_GT(back.step_count(), 0);
}

// A grain placed into a wall (here 0.05 mm into the floor) is refused at set-up, naming both, with exit 2
// and nothing written: run as it was, it left at 16 m/s with nearly all its bonds broken.
TEST(PeridemCliSetUp, GrainPlacedIntoAWallIsRefused) {
  const fs::path d = scratch("into_wall");
  const std::string yaml = replace(small_input((d / "out").string()), "centre: [0, 1.18 mm, 0]", "centre: [0, 0.95 mm, 0]");
  const Result r = run_peridem("-i " + write(d, "into_wall.yaml", yaml).string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  for (const char* m : {"grains.bottom", "wall 'floor'", "contact radius"})
    EXPECT_NE(r.output.find(m), std::string::npos) << m << " in:\n" << r.output;
  EXPECT_FALSE(fs::exists(d / "out" / "thermo.csv"));
}

// Grains placed into each other are refused at set-up with exit 2, naming both, before anything is
// written: a repeated row of a particle list (both discs at one place) and discs 1.5 mm apart (radius 1 mm:
// 0.5 mm deep, past half the contact radius). Run as they were, two discs 0.53 R_c deep left at 7.3 m/s
// instead of 0.1, with two thirds of their bonds broken.
TEST(PeridemCliSetUp, GrainsPlacedIntoEachOtherAreRefused) {
  const fs::path d = scratch("into_each_other");
  for (const std::string centre : {"centre: [0, 1.18 mm, 0]", "centre: [0, 2.68 mm, 0]"}) {
    const std::string yaml = replace(small_input((d / "out").string()), "centre: [0, 3.5 mm, 0]", centre);
    const Result r = run_peridem("-i " + write(d, "overlap.yaml", yaml).string());
    EXPECT_EQ(r.exit_code, 2) << centre << "\n" << r.output;
    for (const char* m : {"input error: 'grains'", "of 'bottom'", "of 'top'", "start inside each other"})
      EXPECT_NE(r.output.find(m), std::string::npos) << m << " in:\n" << r.output;
    EXPECT_FALSE(fs::exists(d / "out" / "thermo.csv")) << centre;
    EXPECT_FALSE(fs::exists(d / "out" / "trajectory.h5")) << centre;
  }
}

// The penetration check runs every step: a 500 m/s impact is stopped at the same step whether thermo rows
// (and the full health check) come every 20 steps or only at the end; it passed with exit 0 at 2,000.
TEST(PeridemCliRestart, PenetrationIsCheckedEveryStepWhateverThermoEvery) {
  const fs::path d = scratch("penetration_every_step");
  std::string stopped_at[2];
  int k = 0;
  for (const char* every : {"20", "2000"}) {
    std::string yaml = replace(small_input((d / every).string()), "velocity: [0, -10 m/s, 0]", "velocity: [0, -500 m/s, 0]");
    yaml = replace(yaml, "steps: 60", "steps: 2000");
    yaml = replace(yaml, "  thermo_every: 20\n  trajectory_every: 20", std::string("  thermo_every: ") + every);
    const Result r = run_peridem("-i " + write(d, std::string("fast") + every + ".yaml", yaml).string());
    EXPECT_EQ(r.exit_code, 3) << every << "\n" << r.output;
    for (const char* m : {"stopped: step ", "'bottom'", "passing through"})
      EXPECT_NE(r.output.find(m), std::string::npos) << m << " in:\n" << r.output;
    const auto at = r.output.find("stopped: step ");
    if (at != std::string::npos) stopped_at[k] = r.output.substr(at, r.output.find(':', at + 14) - at);
    ++k;
  }
  EXPECT_FALSE(stopped_at[0].empty());
  EXPECT_EQ(stopped_at[0], stopped_at[1]);
  // The gap of 0.32 mm closes at 500 m/s in 6.4 steps of 0.1 us; the top disc drives the bottom one into the
  // floor within tens of steps, and the stop comes then, not at a multiple of thermo_every.
  if (!stopped_at[0].empty()) {
    const long step = std::stol(stopped_at[0].substr(14));
    EXPECT_LT(step, 200) << stopped_at[0];
    EXPECT_NE(step % 20, 0) << stopped_at[0];
  }
}

// A grain passing through another (contact springs a million times too soft for a 10 m/s impact) stops
// the run at the next check with exit 3, naming the two grains, and the checkpoint left is the last good one.
TEST(PeridemCliRestart, DeepPenetrationStopsTheRun) {
  const fs::path d = scratch("penetration");
  std::string yaml = replace(small_input((d / "out").string()), "restitution: 0.95", "restitution: 0.95\n  stiffness_factor: 1e-6");
  yaml = replace(yaml, "steps: 60", "steps: 1500");
  yaml = replace(yaml, "  thermo_every: 20", "  thermo_every: 20\n  checkpoint_every: 20");
  const Result r = run_peridem("-i " + write(d, "soft.yaml", yaml).string());
  EXPECT_EQ(r.exit_code, 3) << r.output;
  for (const char* m : {"stopped:", "'bottom'", "'top'", "penetration_limit 0.5", "passing through", "last good checkpoint"})
    EXPECT_NE(r.output.find(m), std::string::npos) << m << " in:\n" << r.output;
  debris::PeridemSimulation back = debris::PeridemSimulation::from_checkpoint((d / "out" / "checkpoint.h5").string());
  EXPECT_EQ(back.penetration_check(0.5), "");
  EXPECT_GT(back.step_count(), 100);  // they meet near step 150
  // penetration_limit 1 never fires: the same run goes to its end.
  yaml = replace(yaml, "time_step: 0.1 us", "time_step: 0.1 us\n  penetration_limit: 1");
  yaml = replace(yaml, "steps: 1500", "steps: 400");
  const Result off = run_peridem("-i " + write(d, "soft_off.yaml", yaml).string());
  EXPECT_EQ(off.exit_code, 0) << off.output;
}

// The default inputs: every key of each is known and sound; the compressive decks load the paper's own
// meshes and particle lists (node counts of data/README.md); the two-particle drop bounces.
TEST(PeridemCliDefaults, DefaultInputsLoad) {
  const fs::path d = scratch("defaults");
  const std::string src = std::string(DEBRIS_SOURCE_DIR) + "/scenarios/peridem/";
  debris::PeridemInputOptions settings_only;
  settings_only.build_system = false;
  for (const char* f : {"two_particle.yaml", "impact_wall_m1.yaml", "impact_wall_m2_top.yaml", "compressive_small.yaml",
                        "compressive_n500.yaml", "noncircular_concave.yaml", "noncircular_hexagon.yaml",
                        "noncircular_wall.yaml", "compression_small.yaml", "compression_small_authors.yaml",
                        "compression_n500.yaml", "compression_n500_authors.yaml",
                        "compression_n500_from_pack.yaml", "compression_n500_authors_from_pack.yaml"}) {
    SCOPED_TRACE(f);
    EXPECT_NO_THROW(debris::read_peridem_input(src + f, settings_only));
  }
  // The full compression: free fall, a damped settle, then the press with the damping off.
  const debris::PeridemRunConfig staged = debris::read_peridem_input(src + "compression_n500.yaml", settings_only);
  ASSERT_EQ(staged.stage_changes.size(), 3u);
  EXPECT_FALSE(staged.stage_changes[0].global_damping.has_value());
  EXPECT_EQ(staged.stage_changes[1].global_damping, 200.0);
  EXPECT_EQ(staged.stage_changes[2].global_damping, 0.0);
  debris::PeridemInputOptions build;
  build.output_directory = d.string();
  const debris::PeridemRunConfig n500 = debris::read_peridem_input(src + "compressive_n500.yaml", build);
  EXPECT_EQ(n500.nodes.size(), 62994u);
  EXPECT_EQ(n500.grains.size(), 504u);
  EXPECT_EQ(n500.steps, 100);
  EXPECT_EQ(n500.grains.wall_vy[503], -0.06);
  const debris::PeridemRunConfig small = debris::read_peridem_input(src + "compressive_small.yaml", build);
  EXPECT_EQ(small.grains.size(), 17u);
  EXPECT_EQ(small.steps, 20000);
  EXPECT_EQ(small.contact.front().restitution, 1.0);
}

TEST(PeridemCliDefaults, TwoParticleDropBounces) {
  const fs::path d = scratch("two_particle");
  const Result r = run_peridem("-i " + std::string(DEBRIS_SOURCE_DIR) + "/scenarios/peridem/two_particle.yaml -o " +
                               d.string() + " --threads 1");  // 246 nodes: one thread is the fastest
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string thermo = slurp(d / "thermo.csv");
  const std::vector<double> last = csv_row(last_line(thermo));
  const std::vector<double> first = csv_row(thermo.substr(thermo.find('\n') + 1));
  ASSERT_EQ(last.size(), 22u);
  EXPECT_NEAR(first[18], -0.1264911, 1e-12);  // top_vy as given
  // The top grain starts 0.2 mm above the contact at the speed of a 0.8 mm fall: H0 = 1 mm (eq 37). At the
  // end it has left the contact (no node pair within R_c) and flies ballistically, so its rebound height is
  // H1 = gap + vy^2 / 2g, with the gap from its centre's rise. C_R = sqrt(H1 / H0) must be Table 2's 0.946
  // for test 2 (epsilon = 0.95) within the table's 0.01, without a broken bond.
  const double g = 10.0, h0 = 1e-3, gap0 = 0.2e-3;
  EXPECT_EQ(last[7], 0) << "still in contact at the end";
  const double gap = gap0 + (last[16] - last[9]) - (first[16] - first[9]);
  const double h1 = gap + last[18] * last[18] / (2 * g);
  const double c_r = std::sqrt(h1 / h0);
  std::printf("[ info ] default two-particle drop: rebound height %.4g mm, C_R = %.4f (Table 2 test 2: 0.946)\n",
              h1 * 1e3, c_r);
  EXPECT_GT(last[18], 0) << "rising";
  EXPECT_NEAR(c_r, 0.946, 0.01);
  EXPECT_EQ(last[6], 0);
}

}  // namespace
