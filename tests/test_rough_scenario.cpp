// The rough-surface scenario's reduced input (scenarios/rough/rough_small.yaml, the one CI runs): it carves, settles
// and slides with its census and height maps, and a run cut into chunks writes the same files as one piece.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

#include "cli_helpers.hpp"
#include "core/io/hdf5_file.hpp"

namespace fs = std::filesystem;
using debris::test::replace;

namespace {

std::string rough_input() {
  std::string text = debris::test::slurp(fs::path(DEBRIS_SOURCE_DIR) / "scenarios" / "rough" / "rough_small.yaml");
  return replace(text, "lammps_data: ../wear/data/",
                 "lammps_data: " + std::string(DEBRIS_SOURCE_DIR) + "/scenarios/wear/data/");
}

std::string dem(const std::string& args) {
  const debris::test::CommandResult r = debris::test::run_command(DEBRIS_DEM_EXECUTABLE, args + " --threads 1");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  return r.output;
}

TEST(RoughScenario, ReducedRunMeasuresBothFacesEverySample) {
  const fs::path d = debris::test::fresh_directory("debris_rough_small");
  const std::string input = debris::test::write_text_file(d, "rough.yaml", rough_input());
  const std::string log = dem("-i " + input + " -o " + (d / "out").string());
  const debris::test::NumberTable csv = debris::test::read_number_table(d / "out" / "surfaces.csv");
  ASSERT_GT(csv.rows.size(), 20u);
  // Both faces measured at every sample; the carved faces are rough (generated with rms 2 nm: the envelope of
  // spheres up to 7.5 nm across adds their caps) and the top face lies above the bottom one.
  for (const auto& row : csv.rows) {
    EXPECT_GT(row[csv.column("bottom_rms_height")], 1e-9);
    EXPECT_LT(row[csv.column("bottom_rms_height")], 6e-9);
    EXPECT_GT(row[csv.column("top_rms_height")], 1e-9);
    EXPECT_GT(row[csv.column("top_mean_height")], row[csv.column("bottom_mean_height")]);
    // Every particle is attached to a body, bridging or detached (the graph's partition).
    const double all = row[csv.column("attached_bottom_particles")] + row[csv.column("attached_top_particles")] +
                       row[csv.column("bridging_particles")] + row[csv.column("detached_particles")];
    EXPECT_EQ(all, row[csv.column("bottom_particles")] + row[csv.column("top_particles")] +
                       row[csv.column("third_particles")]);
  }
  // One pair of height maps per row, on the grid the census chose (a cell at most the smallest radius).
  debris::h5::File maps((d / "out" / "surfaces_heights.h5").string(), debris::h5::File::Mode::read_only);
  debris::h5::Group samples = maps.open_group("samples");
  EXPECT_EQ(samples.children().size(), csv.rows.size());
  const debris::h5::Array<double> first = samples.open_group("0").read<double>("bottom");
  ASSERT_EQ(first.shape.size(), 2u);
  EXPECT_GT(first.shape[0], 20u);
  // The balance closes.
  EXPECT_NE(log.find("energy balance"), std::string::npos) << log;
}

TEST(RoughScenario, ChunkedRunWritesTheSameCensusAndHeightMaps) {
  const fs::path d = debris::test::fresh_directory("debris_rough_chunks");
  const std::string full = rough_input();
  const std::string whole = debris::test::write_text_file(d, "whole.yaml", full);
  const std::string first =
      debris::test::write_text_file(d, "first.yaml", replace(full, "run:\n", "run:\n  steps: 4000\n"));
  const fs::path one = d / "one", chunks = d / "chunks";
  dem("-i " + whole + " -o " + one.string());
  dem("-i " + first + " -o " + chunks.string());
  const fs::path checkpoint = chunks / "checkpoint.h5", at_4000 = d / "checkpoint_4000.h5";
  fs::copy_file(checkpoint, at_4000);
  dem("--restart " + checkpoint.string() + " -i " + whole + " -o " + chunks.string());
  // As if the second chunk was killed before its last checkpoint: continuing from step 4000 again drops the maps
  // (and rows) written after it.
  fs::copy_file(at_4000, checkpoint, fs::copy_options::overwrite_existing);
  dem("--restart " + checkpoint.string() + " -i " + whole + " -o " + chunks.string());
  for (const char* file : {"thermo.csv", "surfaces.csv", "surfaces_histogram.csv", "surfaces_debris.csv"})
    EXPECT_EQ(debris::test::slurp(one / file), debris::test::slurp(chunks / file)) << file;
  debris::h5::File a((one / "surfaces_heights.h5").string(), debris::h5::File::Mode::read_only);
  debris::h5::File b((chunks / "surfaces_heights.h5").string(), debris::h5::File::Mode::read_only);
  debris::h5::Group sa = a.open_group("samples"), sb = b.open_group("samples");
  ASSERT_EQ(sa.children().size(), sb.children().size());
  for (std::size_t k = 0; k < sa.children().size(); ++k) {
    const std::string name = std::to_string(k);
    EXPECT_EQ(sa.open_group(name).attribute<std::int64_t>("step"), sb.open_group(name).attribute<std::int64_t>("step"));
    for (const char* face : {"bottom", "top"})
      EXPECT_EQ(sa.open_group(name).read<double>(face).values, sb.open_group(name).read<double>(face).values)
          << "sample " << k << " " << face;
  }
}

}  // namespace
