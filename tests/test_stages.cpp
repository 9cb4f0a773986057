// Staged runs through the shared runner (scenarios/common/run/runner.hpp, stages.hpp), for both executables:
// each stage's changes act from its first step (a group driven at a new velocity moves exactly v dt per
// step; a wall placed and set moving is where it was put and moves at its velocity), a run split by
// --restart inside a stage or exactly at a stage boundary equals the uninterrupted run bit for bit, and
// bad stages (unknown group or wall, a wall placed onto a grain, a zero length, run.steps past the end)
// are named errors with exit 2 that write nothing.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "core/io/hdf5_file.hpp"
#include "tests/cli_helpers.hpp"

namespace {

namespace fs = std::filesystem;
using debris::test::CommandResult;
using debris::test::slurp;
using debris::test::write_text_file;

CommandResult run_dem(const std::string& args) { return debris::test::run_command(DEBRIS_DEM_EXECUTABLE, args); }
CommandResult run_peridem(const std::string& args) {
  return debris::test::run_command(DEBRIS_PERIDEM_EXECUTABLE, args);
}

using debris::test::replace;

std::vector<std::vector<double>> csv_rows(const std::string& text) {
  std::vector<std::vector<double>> rows;
  std::stringstream in(text);
  std::string line;
  std::getline(in, line);  // header
  while (std::getline(in, line)) {
    std::vector<double> row;
    std::stringstream ss(line);
    for (std::string cell; std::getline(ss, cell, ',');) row.push_back(std::stod(cell));
    rows.push_back(row);
  }
  return rows;
}

std::vector<std::string> csv_header(const std::string& text) {
  std::vector<std::string> cols;
  std::stringstream ss(text.substr(0, text.find('\n')));
  for (std::string cell; std::getline(ss, cell, ',');) cols.push_back(cell);
  return cols;
}

std::size_t column(const std::vector<std::string>& cols, const std::string& name) {
  for (std::size_t k = 0; k < cols.size(); ++k)
    if (cols[k] == name) return k;
  ADD_FAILURE() << "no column " << name;
  return 0;
}

std::string last_frame(const fs::path& dump) {
  const std::string t = slurp(dump);
  return t.substr(t.rfind("ITEM: TIMESTEP"));
}

// ---- debris_dem ----------------------------------------------------------------------------------------

// An HCP slab (Table 4 material in reduced units, as the default input) between a frozen bottom and a
// loaded top wall: settle with damping, slide the top wall at a prescribed velocity, then release it under
// half the load with the adhesion switched off.
std::string dem_staged_input(const std::string& out_dir) {
  return std::string(debris::test::kTable4MaterialYaml) + R"(particles:
  lattice:
    kind: hcp
    hcp_c_axis: y
    spacing: 100
    diameter: 100
    size_spread: 0.05
    displacement: 3
    cells: [4, 4, 3]
box:
  periodic: [true, false, true]
groups:
  - name: bottom
    region: {y: [-inf, 170]}
    motion: frozen
  - name: top
    region: {y: [480, inf]}
    motion: force
    stress: [0, -0.01, 0]
stages:
  - name: settle
    steps: 40
    global_damping: 0.5
  - name: slide
    steps: 50
    global_damping: 0
    groups:
      - {name: top, motion: velocity, velocity: [0.001, 0, 0]}
  - name: release
    steps: 30
    adhesive: false
    groups:
      - {name: top, motion: force, stress: [0, -0.005, 0]}
run:
  time_step_fraction: 0.1
output:
  directory: )" + out_dir + R"(
  thermo_every: 10
  dump_every: 30
)";
}

TEST(StagedRun, DemStagesActAtTheirStartAndRestartBitForBitInsideAndAtABoundary) {
  const fs::path d = debris::test::fresh_directory("debris_stages_dem");
  const std::string full = dem_staged_input((d / "full").string());
  const std::string full_path = write_text_file(d, "full.yaml", full);
  const CommandResult whole = run_dem("-i " + full_path);
  ASSERT_EQ(whole.exit_code, 0) << whole.output;
  EXPECT_NE(whole.output.find("stage 1 'slide' starts at step 40"), std::string::npos) << whole.output;
  EXPECT_NE(whole.output.find("stage 2 'release' starts at step 90"), std::string::npos) << whole.output;

  // The slide stage: the top wall moves at exactly 0.001 along x from step 40 to 90 (its thermo displacement
  // grows by v dt per step).
  const std::string thermo = slurp(d / "full" / "thermo.csv");
  const auto cols = csv_header(thermo);
  const auto rows = csv_rows(thermo);
  ASSERT_EQ(rows.size(), 13u);  // steps 0, 10, ..., 120
  const std::size_t dx = column(cols, "top_dx"), time = column(cols, "time");
  const double dt = rows[1][time] / 10.0;
  EXPECT_NEAR(rows[9][dx] - rows[4][dx], 0.001 * 50 * dt, 1e-12 * 0.001 * 50 * dt);

  // Split inside the slide stage (step 60) and exactly at the release boundary (step 90).
  for (const long split : {60L, 90L}) {
    const std::string tag = "split" + std::to_string(split);
    std::string part = replace(full, (d / "full").string(), (d / tag).string());
    part = replace(part, "run:\n", "run:\n  steps: " + std::to_string(split) + "\n");
    ASSERT_EQ(run_dem("-i " + write_text_file(d, tag + ".yaml", part)).exit_code, 0);
    const CommandResult rest =
        run_dem("--restart " + (d / tag / "checkpoint.h5").string() + " -i " + full_path + " -o " + (d / tag).string());
    ASSERT_EQ(rest.exit_code, 0) << rest.output;
    EXPECT_EQ(slurp(d / "full" / "thermo.csv"), slurp(d / tag / "thermo.csv")) << tag;
    EXPECT_EQ(last_frame(d / "full" / "dump.lammpstrj"),
              last_frame(d / tag / ("dump.restart" + std::to_string(split) + ".lammpstrj")))
        << tag;
  }
}

TEST(StagedRun, DemBadStagesAreNamedErrorsThatWriteNothing) {
  const fs::path d = debris::test::fresh_directory("debris_stages_dem_bad");
  const std::string good = dem_staged_input((d / "out").string());
  struct Case {
    std::string from, to, must_mention;
  };
  const std::vector<Case> cases{
      {"      - {name: top, motion: velocity", "      - {name: lid, motion: velocity", "stages[1].groups[0].name"},
      {"    steps: 40\n", "    steps: 0\n", "stages[0].steps"},
      {"    steps: 40\n", "    steps: 40\n    duration: 1\n", "stages[0].steps"},
      {"run:\n", "run:\n  steps: 121\n", "run.steps"},
      {"    adhesive: false", "    adhesive: maybe", "stages[2].adhesive"},
      {"    global_damping: 0.5", "    global_damping: -1", "stages[0].global_damping"},
      {"    global_damping: 0\n", "    global_dampin: 0\n", "global_dampin"},
  };
  for (const Case& c : cases) {
    const CommandResult r = run_dem("-i " + write_text_file(d, "bad.yaml", replace(good, c.from, c.to)));
    EXPECT_EQ(r.exit_code, 2) << c.to << "\n" << r.output;
    EXPECT_NE(r.output.find(c.must_mention), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(d / "out")) << "a bad input wrote output: " << c.to;
  }
}

// ---- debris_peridem ------------------------------------------------------------------------------------

// Two discs above a floor (as the command-line test's input) and a lid out of the way; the top disc falls
// at 10 m/s. Stage 'press' places the lid's lower edge at `lid_at` and moves it down at 5 m/s.
std::string peridem_staged_input(const std::string& out_dir, const std::string& lid_at = "4.8 mm") {
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
  lid:
    type: rectangle
    lo: [-2 mm, 8 mm, 0]
    hi: [2 mm, 8.6 mm, 0]
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
    velocity: [0, -10 m/s, 0]
walls:
  - name: floor
    shape: floor
    material: M1
  - name: lid
    shape: lid
    material: M1
contact:
  restitution: 0.95
gravity: [0, -10 m/s^2, 0]
stages:
  - name: fall
    steps: 100
  - name: press
    steps: 100
    walls:
      - {name: lid, place: {y_min: )" + lid_at + R"(}, velocity: [0, -5 m/s, 0]}
    gravity: [0, -20 m/s^2, 0]
run:
  time_step: 0.1 us
output:
  directory: )" + out_dir + R"(
  thermo_every: 25
  trajectory_every: 50
)";
}

TEST(StagedRun, PeridemWallPlacedAndMovedAtAStageRestartsBitForBit) {
  const fs::path d = debris::test::fresh_directory("debris_stages_peridem");
  const std::string full = peridem_staged_input((d / "full").string());
  const std::string full_path = write_text_file(d, "full.yaml", full);
  const CommandResult whole = run_peridem("-i " + full_path);
  ASSERT_EQ(whole.exit_code, 0) << whole.output;
  EXPECT_NE(whole.output.find("stage 1 'press' starts at step 100"), std::string::npos) << whole.output;

  // The lid: its lowest node at 4.8 mm when placed, then 100 steps at -5 m/s of 0.1 us: 4.75 mm at the end.
  {
    debris::h5::File f((d / "full" / "trajectory.h5").string(), debris::h5::File::Mode::read_only);
    const auto grain = f.read<std::int32_t>("nodes/grain").values;
    const auto kind = f.read<std::int32_t>("grains/kind").values;
    const auto pos = f.read<double>("frames/4/position").values;  // step 200
    double lid_min = 1e9, floor_min = 1e9;
    for (std::size_t i = 0; i < grain.size(); ++i) {
      if (kind[static_cast<std::size_t>(grain[i])] != 1) continue;
      double& m = grain[i] == 3 ? lid_min : floor_min;
      m = std::min(m, pos[3 * i + 1]);
    }
    EXPECT_NEAR(lid_min, 4.8e-3 - 100 * 5.0 * 1e-7, 1e-15);
    EXPECT_NEAR(floor_min, -0.6e-3, 1e-15);  // the floor stays
  }
  // Gravity doubled from step 100: the top disc's centre falls freely until the discs meet (near step 150),
  // so at step 125 its velocity has picked up g dt per step of each stage.
  const std::string thermo = slurp(d / "full" / "thermo.csv");
  const auto cols = csv_header(thermo);
  const auto rows = csv_rows(thermo);
  const std::size_t vy = column(cols, "top_vy");
  ASSERT_GE(rows.size(), 6u);
  EXPECT_NEAR(rows[5][vy] - rows[4][vy], -20.0 * 25 * 1e-7, 1e-9) << "step 100 to 125";
  EXPECT_NEAR(rows[4][vy] - rows[3][vy], -10.0 * 25 * 1e-7, 1e-9) << "step 75 to 100";

  for (const long split : {150L, 100L}) {
    const std::string tag = "split" + std::to_string(split);
    std::string part = replace(full, (d / "full").string(), (d / tag).string());
    part = replace(part, "run:\n", "run:\n  steps: " + std::to_string(split) + "\n");
    ASSERT_EQ(run_peridem("-i " + write_text_file(d, tag + ".yaml", part)).exit_code, 0);
    const CommandResult rest = run_peridem("--restart " + (d / tag / "checkpoint.h5").string() + " -i " + full_path +
                                           " -o " + (d / tag).string());
    ASSERT_EQ(rest.exit_code, 0) << rest.output;
    EXPECT_EQ(thermo, slurp(d / tag / "thermo.csv")) << tag;
  }
}

TEST(StagedRun, PeridemBadStagesAreNamedErrors) {
  const fs::path d = debris::test::fresh_directory("debris_stages_peridem_bad");
  // A lid placed onto the top disc (its top is near 4.4 mm at step 100) stops the run when the stage begins,
  // naming the wall and the grain.
  const CommandResult onto =
      run_peridem("-i " + write_text_file(d, "onto.yaml", peridem_staged_input((d / "onto").string(), "4.3 mm")));
  EXPECT_EQ(onto.exit_code, 2) << onto.output;
  EXPECT_NE(onto.output.find("lid"), std::string::npos) << onto.output;
  EXPECT_NE(onto.output.find("'top'"), std::string::npos) << onto.output;

  const std::string good = peridem_staged_input((d / "out").string());
  struct Case {
    std::string from, to, must_mention;
  };
  const std::vector<Case> cases{
      {"{name: lid, place", "{name: roof, place", "stages[1].walls[0].name"},
      {"place: {y_min: 4.8 mm}", "place: {y_low: 4.8 mm}", "stages[1].walls[0].place"},
      {"place: {y_min: 4.8 mm}", "place: {y_min: 4.8 mm}, move_by: [0, 1 mm, 0]", "place"},
      {"    steps: 100\n    walls", "    duration: 0.001 us\n    walls", "stages[1].duration"},
      {"run:\n", "run:\n  steps: 500\n", "run.steps"},
  };
  for (const Case& c : cases) {
    const CommandResult r = run_peridem("-i " + write_text_file(d, "bad.yaml", replace(good, c.from, c.to)));
    EXPECT_EQ(r.exit_code, 2) << c.to << "\n" << r.output;
    EXPECT_NE(r.output.find(c.must_mention), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(d / "out" / "thermo.csv")) << "a bad input wrote output: " << c.to;
  }
}

// A settle stage's global viscous damping (F -= c m v on the particle nodes): a lone disc coasting at v0
// keeps v0 exactly through the first stage, then loses the factor (1 - c dt) every step of the damped one
// (pd_viscous_damping); a run split inside the damped stage restarts bit for bit (the rate is in the
// checkpoint); bad rates are named errors that write nothing.
std::string peridem_damped_input(const std::string& out_dir, const std::string& rate = "20000 s^-1") {
  return R"(dimension: 2
materials:
  M1: {density: 1200 kg/m^3, bulk_modulus: 0.0216 GPa, shear_modulus: 0.01296 GPa, fracture_energy: 50 J/m^2,
       horizon: 0.6 mm}
shapes:
  disc: {type: circle, radius: 1 mm, mesh_size: 0.3 mm}
grains:
  - {name: disc, shape: disc, material: M1, centre: [0, 0, 0], velocity: [0.5 m/s, -1 m/s, 0]}
stages:
  - {name: coast, steps: 100}
  - {name: settle, steps: 100, global_damping: )" + rate + R"(}
run:
  time_step: 0.1 us
output:
  directory: )" + out_dir + R"(
  thermo_every: 50
)";
}

TEST(StagedRun, PeridemGlobalDampingStageDecaysAsItsRecurrenceAndRestartsBitForBit) {
  const fs::path d = debris::test::fresh_directory("debris_stages_peridem_damping");
  const std::string full = peridem_damped_input((d / "full").string());
  const std::string full_path = write_text_file(d, "full.yaml", full);
  const CommandResult whole = run_peridem("-i " + full_path);
  ASSERT_EQ(whole.exit_code, 0) << whole.output;
  EXPECT_NE(whole.output.find("global damping 20000 1/s"), std::string::npos) << whole.output;
  const std::string thermo = slurp(d / "full" / "thermo.csv");
  const auto cols = csv_header(thermo);
  const auto rows = csv_rows(thermo);
  ASSERT_EQ(rows.size(), 5u);  // steps 0, 50, ..., 200
  const std::size_t vx = column(cols, "disc_vx"), vy = column(cols, "disc_vy");
  const double c_dt = 20000.0 * 1e-7;
  for (std::size_t r = 0; r < rows.size(); ++r) {
    const int damped_steps = std::max(0, 50 * static_cast<int>(r) - 100);
    const double factor = std::pow(1.0 - c_dt, damped_steps);
    EXPECT_NEAR(rows[r][vx], 0.5 * factor, 1e-9) << "row " << r;
    EXPECT_NEAR(rows[r][vy], -1.0 * factor, 1e-9) << "row " << r;
  }
  EXPECT_LT(rows[4][vx], 0.5 * 0.82);  // (1 - 2e-3)^100 = 0.8186: the damping acted

  std::string part = replace(full, (d / "full").string(), (d / "split").string());
  part = replace(part, "run:\n", "run:\n  steps: 150\n");
  ASSERT_EQ(run_peridem("-i " + write_text_file(d, "split.yaml", part)).exit_code, 0);
  const CommandResult rest = run_peridem("--restart " + (d / "split" / "checkpoint.h5").string() + " -i " +
                                         full_path + " -o " + (d / "split").string());
  ASSERT_EQ(rest.exit_code, 0) << rest.output;
  EXPECT_EQ(thermo, slurp(d / "split" / "thermo.csv"));

  for (const std::string& bad : {std::string("-5 s^-1"), std::string("1e7 s^-1"), std::string("100 m")}) {
    const CommandResult r =
        run_peridem("-i " + write_text_file(d, "bad.yaml", peridem_damped_input((d / "out").string(), bad)));
    EXPECT_EQ(r.exit_code, 2) << bad << "\n" << r.output;
    EXPECT_NE(r.output.find("stages[1].global_damping"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(d / "out" / "thermo.csv")) << "a bad input wrote output: " << bad;
  }
}

// run.overlap_limit: a sample that starts with overlaps deeper than the default limit (0.5 r_min) is refused
// at set-up (exit 2, nothing written: the step-0 state is checked before any file); `auto` (the deepest
// initial overlap + one smallest radius) lets it run; a non-positive limit is a named error.
TEST(StagedRun, DemOverlapLimitSetting) {
  const fs::path d = debris::test::fresh_directory("debris_stages_overlap");
  std::string squeezed = replace(dem_staged_input((d / "out").string()), "    diameter: 100", "    diameter: 160");
  squeezed = replace(squeezed, "cells: [4, 4, 3]", "cells: [6, 4, 4]");  // periodic sides above 2 cutoffs
  const CommandResult fixed = run_dem("-i " + write_text_file(d, "fixed.yaml", squeezed));
  EXPECT_EQ(fixed.exit_code, 2) << fixed.output;
  // Diameter 160 at spacing 100: neighbours overlap by 60 (radii 77-79 with the lattice's size spread).
  EXPECT_NE(fixed.output.find("too deep an overlap at step 0"), std::string::npos) << fixed.output;
  EXPECT_FALSE(fs::exists(d / "out")) << "a refused set-up wrote output";
  const CommandResult automatic = run_dem(
      "-i " + write_text_file(d, "auto.yaml", replace(squeezed, "run:\n", "run:\n  steps: 20\n  overlap_limit: auto\n")));
  EXPECT_EQ(automatic.exit_code, 0) << automatic.output;
  EXPECT_NE(automatic.output.find("(auto: the deepest initial overlap + 1)"), std::string::npos) << automatic.output;
  fs::remove_all(d / "out");
  const CommandResult bad =
      run_dem("-i " + write_text_file(d, "bad.yaml", replace(squeezed, "run:\n", "run:\n  overlap_limit: 0\n")));
  EXPECT_EQ(bad.exit_code, 2) << bad.output;
  EXPECT_NE(bad.output.find("run.overlap_limit"), std::string::npos) << bad.output;
  EXPECT_FALSE(fs::exists(d / "out"));
}

}  // namespace
