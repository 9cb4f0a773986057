// Carving and labelling a system in debris_dem's input (the adhesive-wear junction of paper A, section 4):
// removal by region and labels against brute-force expectations, labels kept per id through steps,
// re-sorting, checkpoint and restart, and in the dump and trajectory; bad removals through the real
// executable exit 2 naming the key and write nothing.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/io/hdf5_file.hpp"
#include "core/io/lammps_data.hpp"
#include "scenarios/common/dem/dem_input.hpp"
#include "scenarios/common/dem/dem_simulation.hpp"
#include "tests/cli_helpers.hpp"

namespace debris {
namespace {

namespace fs = std::filesystem;

// fcc, spacing 100: cells of 141.42, box 848.5 x 565.7 x 565.7, periodic in x and z, y normal; 384 particles.
// The carving takes the layer y in [200, 300) except a cylinder of radius 150 along y: two slabs joined by
// a junction. Labels paint the slabs, then the junction and the walls over them (later entries override).
std::string carved_input(const std::string& out_dir, long steps = 20) {
  return std::string(debris::test::kTable4MaterialYaml) + R"(particles:
  lattice:
    kind: fcc
    spacing: 100
    diameter: 100
    cells: [6, 4, 4]
box:
  periodic: [true, false, true]
remove:
  - difference:
      - {block: {y: [200, 300]}}
      - {cylinder: {axis: y, centre: [424.26, 0, 282.84], radius: 150}}
labels:
  - {name: bottom, region: {block: {y: [-inf, 250]}}}
  - {name: top, region: {block: {y: [250, inf]}}}
  - {name: junction, region: {cylinder: {axis: y, centre: [424.26, 0, 282.84], radius: 150, extent: [200, 300]}}}
  - {name: bottom_wall, region: {y: [-inf, 80]}}
  - {name: top_wall, region: {block: {y: [500, inf]}}}
groups:
  - {name: base, motion: frozen, region: {block: {y: [-inf, 80]}}}
run:
  steps: )" + std::to_string(steps) + R"(
  time_step_fraction: 0.1
output:
  directory: )" + out_dir + R"(
  thermo_every: 10
  dump_every: 10
  checkpoint_every: 10
)";
}

// The same lattice, uncarved and unlabelled.
DemRunConfig uncarved() {
  std::string text = carved_input("unused");
  const auto cut = [&](const std::string& from, const std::string& to) {
    text.erase(text.find(from), text.find(to) - text.find(from));
  };
  cut("remove:", "groups:");
  return read_dem_input_text(text, "uncarved", "");
}

int expected_label(double x, double y, double z) {
  int label = 0;
  if (y < 250) label = 1;
  if (y >= 250) label = 2;
  if (y >= 200 && y < 300 && (x - 424.26) * (x - 424.26) + (z - 282.84) * (z - 282.84) <= 150.0 * 150.0) label = 3;
  if (y < 80) label = 4;
  if (y >= 500) label = 5;
  return label;
}

const std::vector<std::string> kNames = {"bottom", "top", "junction", "bottom_wall", "top_wall"};

std::map<std::int64_t, int> labels_by_id(const Particles& p) {
  std::map<std::int64_t, int> m;
  for (std::size_t i = 0; i < p.size(); ++i) m[p.id[i]] = p.label[i];
  return m;
}

TEST(Carve, RemovalAndLabelsMatchBruteForce) {
  const DemRunConfig all = uncarved();
  const DemRunConfig cfg = read_dem_input_text(carved_input("unused"), "carved", "");
  const Particles& p0 = all.particles;
  const Particles& p = cfg.particles;
  std::map<std::int64_t, std::size_t> index;
  for (std::size_t i = 0; i < p.size(); ++i) index[p.id[i]] = i;
  std::size_t removed = 0, in_junction = 0;
  for (std::size_t i = 0; i < p0.size(); ++i) {
    const double x = p0.x[i], y = p0.y[i], z = p0.z[i];
    const bool in_cyl = (x - 424.26) * (x - 424.26) + (z - 282.84) * (z - 282.84) <= 150.0 * 150.0;
    const bool gone = y >= 200 && y < 300 && !in_cyl;
    removed += gone ? 1 : 0;
    EXPECT_EQ(index.count(p0.id[i]), gone ? 0u : 1u) << "id " << p0.id[i];
    if (gone) continue;
    const std::size_t k = index[p0.id[i]];
    EXPECT_EQ(p.x[k], x);  // every column carried, in the same order
    EXPECT_EQ(p.radius[k], p0.radius[i]);
    EXPECT_EQ(p.label[k], expected_label(x, y, z)) << "id " << p0.id[i] << " at y " << y;
    in_junction += p.label[k] == 3 ? 1 : 0;
  }
  EXPECT_EQ(p.size() + removed, p0.size());
  EXPECT_GT(removed, 10u);  // a layer of 48 minus the junction's share
  EXPECT_GT(in_junction, 2u);
  EXPECT_TRUE(std::is_sorted(p.id.begin(), p.id.end()));  // removal keeps the order
  EXPECT_EQ(p.label_names, kNames);
  for (int l : all.particles.label) EXPECT_EQ(l, 0);  // no labels key: every particle unlabelled
  EXPECT_TRUE(all.particles.label_names.empty());
  // The group's new region form selects the same particles as the bottom wall label.
  for (std::size_t i = 0; i < p.size(); ++i) EXPECT_EQ(p.group[i] == 0, p.label[i] == 4) << i;
}

// A LAMMPS data file has no labels: its particles are unlabelled (0) unless `labels` gives them one.
TEST(Carve, DataFileParticlesAreUnlabelledUnlessLabelled) {
  const fs::path d = test::fresh_directory("debris_carve_data");
  DemRunConfig all = uncarved();
  all.particles.set_mass_from_density(1.0);  // the data file stores densities
  write_lammps_data((d / "lattice.data").string(), all.box, all.particles);
  std::string text = carved_input("unused");
  const auto a = text.find("  lattice:"), b = text.find("box:");
  text.replace(a, b - a, "  lammps_data: lattice.data\n");
  const DemRunConfig labelled = read_dem_input_text(text, "data", d.string());
  const DemRunConfig carved = read_dem_input_text(carved_input("unused"), "carved", "");
  EXPECT_EQ(labels_by_id(labelled.particles), labels_by_id(carved.particles));
  EXPECT_EQ(labelled.particles.label_names, kNames);
  text.erase(text.find("labels:"), text.find("groups:") - text.find("labels:"));
  const DemRunConfig plain = read_dem_input_text(text, "data", d.string());
  EXPECT_EQ(plain.particles.size(), carved.particles.size());
  for (int l : plain.particles.label) EXPECT_EQ(l, 0);
  EXPECT_TRUE(plain.particles.label_names.empty());
}

TEST(Carve, RemoveIfKeepsEveryColumnOfTheRest) {
  Particles p;
  for (int i = 0; i < 6; ++i) {
    p.add(10 + i, 1 + i % 2, i, 2 * i, 3 * i, 0.5);
    p.label[static_cast<std::size_t>(i)] = 7 - i;
    p.wz[static_cast<std::size_t>(i)] = 0.25 * i;
    p.iy[static_cast<std::size_t>(i)] = -i;
  }
  EXPECT_EQ(p.remove_if({1, 0, 0, 1, 1, 0}), 3u);
  ASSERT_EQ(p.size(), 3u);
  EXPECT_EQ(p.id, (std::vector<std::int64_t>{11, 12, 15}));
  EXPECT_EQ(p.label, (std::vector<int>{6, 5, 2}));
  EXPECT_EQ(p.wz, (std::vector<double>{0.25, 0.5, 1.25}));
  EXPECT_EQ(p.iy, (std::vector<int>{-1, -2, -5}));
  EXPECT_EQ(p.type, (std::vector<int>{2, 1, 2}));
  EXPECT_EQ(p.remove_if({0, 0, 0}), 0u);
  EXPECT_EQ(p.size(), 3u);
}

TEST(Carve, LabelsSurviveStepsResortCheckpointAndRestart) {
  const fs::path d = test::fresh_directory("debris_carve_restart");
  DemRunConfig cfg = read_dem_input_text(carved_input((d / "out").string()), "carved", "");
  const std::map<std::int64_t, int> want = labels_by_id(cfg.particles);
  DemSimulation sim(cfg.box, std::move(cfg.particles), std::move(cfg.groups), cfg.settings);
  EXPECT_EQ(sim.particles().label_names, kNames);
  sim.run(15);
  sim.rebuild_neighbors();  // re-sorts by cell
  EXPECT_EQ(labels_by_id(sim.particles()), want);
  const std::string ckpt = (d / "checkpoint.h5").string();
  sim.write_checkpoint(ckpt, "echo");
  DemSimulation back = DemSimulation::from_checkpoint(ckpt);
  EXPECT_EQ(back.particles().label_names, kNames);
  EXPECT_EQ(back.particles().label, sim.particles().label);  // same storage order
  // Reversed storage order, then more steps and the sort by cell again.
  std::vector<int> order(back.particles().size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(order.size() - 1 - i);
  back.reorder(order);
  EXPECT_EQ(labels_by_id(back.particles()), want);
  back.run(10);
  back.rebuild_neighbors();
  EXPECT_EQ(labels_by_id(back.particles()), want);
  EXPECT_EQ(back.health_check(), "");
}

// ---------------------------------------------------------------- through debris_dem

test::CommandResult run_dem(const std::string& args) { return test::run_command(DEBRIS_DEM_EXECUTABLE, args); }

using debris::test::replace;

/// id -> value of `column` in the last frame of a LAMMPS dump.
std::map<std::int64_t, double> last_frame_column(const fs::path& dump, const std::string& column) {
  std::ifstream in(dump);
  std::map<std::int64_t, double> out;
  std::size_t id_col = 0, col = 0;
  bool in_atoms = false;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("ITEM: ATOMS", 0) == 0) {
      std::istringstream h(line.substr(12));
      std::vector<std::string> names;
      for (std::string t; h >> t;) names.push_back(t);
      id_col = static_cast<std::size_t>(std::find(names.begin(), names.end(), "id") - names.begin());
      col = static_cast<std::size_t>(std::find(names.begin(), names.end(), column) - names.begin());
      EXPECT_LT(col, names.size()) << "no column " << column << " in " << line;
      out.clear();
      in_atoms = true;
    } else if (line.rfind("ITEM:", 0) == 0) {
      in_atoms = false;
    } else if (in_atoms) {
      std::istringstream r(line);
      std::vector<double> v;
      for (double x; r >> x;) v.push_back(x);
      if (v.size() > std::max(id_col, col)) out[static_cast<std::int64_t>(v[id_col])] = v[col];
    }
  }
  return out;
}

TEST(CarveCli, LabelsAppearInDumpTrajectoryAndRestart) {
  const fs::path d = test::fresh_directory("debris_carve_cli");
  const fs::path out = d / "out";
  const std::string input = test::write_text_file(d, "carved.yaml", carved_input(out.string()));
  const test::CommandResult r = run_dem("-i " + input);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const DemRunConfig cfg = read_dem_input_text(carved_input(out.string()), "carved", "");
  const std::map<std::int64_t, int> want = labels_by_id(cfg.particles);
  std::map<std::int64_t, double> want_d(want.begin(), want.end());
  EXPECT_EQ(last_frame_column(out / "dump.lammpstrj", "mol"), want_d);
  // Image counts and angular velocities are columns too, equal to the checkpoint's at the last step.
  const DemSimulation end = DemSimulation::from_checkpoint((out / "checkpoint.h5").string());
  EXPECT_EQ(end.particles().label_names, kNames);
  EXPECT_EQ(labels_by_id(end.particles()), want);
  const auto wz = last_frame_column(out / "dump.lammpstrj", "omegaz");
  const auto ix = last_frame_column(out / "dump.lammpstrj", "ix");
  for (std::size_t i = 0; i < end.particles().size(); ++i) {
    EXPECT_EQ(wz.at(end.particles().id[i]), end.particles().wz[i]);
    EXPECT_EQ(ix.at(end.particles().id[i]), end.particles().ix[i]);
  }
  {
    h5::File f((out / "trajectory.h5").string(), h5::File::Mode::read_only);
    const std::string last = "frames/" + std::to_string(f.open_group("frames").children().size() - 1) + "/";
    const auto ids = f.read<std::int64_t>(last + "id").values;
    const auto labels = f.read<std::int32_t>(last + "label").values;
    ASSERT_EQ(ids.size(), want.size());
    for (std::size_t r2 = 0; r2 < ids.size(); ++r2) EXPECT_EQ(labels[r2], want.at(ids[r2])) << ids[r2];
    EXPECT_EQ(f.read_strings(last + "label_names"), kNames);
  }
  // A restart (more steps) keeps them: the checkpoint carries the labels, not the input.
  const std::string more = test::write_text_file(d, "more.yaml", replace(carved_input(out.string()), "steps: 20", "steps: 30"));
  const test::CommandResult r2 = run_dem("-i " + more + " --restart " + (out / "checkpoint.h5").string());
  ASSERT_EQ(r2.exit_code, 0) << r2.output;
  EXPECT_EQ(last_frame_column(out / "dump.restart20.lammpstrj", "mol"), want_d);
  EXPECT_EQ(labels_by_id(DemSimulation::from_checkpoint((out / "checkpoint.h5").string()).particles()), want);
}

class CarveCliBad : public ::testing::Test {
 protected:
  // Exit 2, every piece of `mention` in the message, and no output directory made.
  void expect_rejected(const std::string& from, const std::string& to, const std::vector<std::string>& mention) {
    // One directory per test: ctest -j runs these tests in parallel processes.
    const fs::path d = test::fresh_directory(std::string("debris_carve_bad_") +
                                             ::testing::UnitTest::GetInstance()->current_test_info()->name());
    const fs::path out = d / "out";
    const std::string yaml = replace(carved_input(out.string()), from, to);
    const test::CommandResult r = run_dem("-i " + test::write_text_file(d, "bad.yaml", yaml));
    EXPECT_EQ(r.exit_code, 2) << r.output;
    for (const std::string& m : mention) EXPECT_NE(r.output.find(m), std::string::npos) << "no '" << m << "' in:\n" << r.output;
    EXPECT_FALSE(fs::exists(out)) << "a bad input wrote " << out;
  }
};

const std::string kRemoval = R"(remove:
  - difference:
      - {block: {y: [200, 300]}}
      - {cylinder: {axis: y, centre: [424.26, 0, 282.84], radius: 150}}
)";

TEST_F(CarveCliBad, CylinderLargerThanTheBox) {
  // Diameter 600 > the z length 565.7 across a y axis.
  expect_rejected("radius: 150}}\n", "radius: 300}}\n",
                  {"remove[0].difference[1].cylinder.radius", "300", "larger than the box", "z length"});
}

TEST_F(CarveCliBad, RegionRemovingNothing) {
  expect_rejected(kRemoval, "remove:\n  - {block: {y: [2000, 3000]}}\n",
                  {"remove[0]", "block y [2000, 3000]", "removes no particle"});
  // The second of two entries finds nothing left in a region the first emptied.
  expect_rejected(kRemoval, "remove:\n  - {block: {y: [200, 300]}}\n  - {block: {y: [210, 290]}}\n",
                  {"remove[1]", "removes no particle"});
}

TEST_F(CarveCliBad, RemovalLeavingNothing) {
  expect_rejected(kRemoval, "remove: {block: {x: [-inf, inf]}}\n", {"'remove'", "leaves no particle"});
}

TEST_F(CarveCliBad, LabelWithNoParticleOrRepeatedName) {
  expect_rejected("name: top_wall, region: {block: {y: [500, inf]}}", "name: top_wall, region: {block: {y: [5000, inf]}}",
                  {"labels[4].name", "top_wall", "holds no particle"});
  expect_rejected("name: top_wall,", "name: top,", {"labels[4].name", "top", "already used"});
}

}  // namespace
}  // namespace debris
