// Tiling a relaxed periodic sample (particles.replicate): the tiled packing continues across every seam with the
// neighbours each particle had across the original's periodic faces, at the same distances, so the seams leave no
// trace in the packing. Checked pair by pair against a brute-force minimum-image search of the original.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <vector>

#include "core/box.hpp"
#include "core/io/lammps_data.hpp"
#include "core/particles.hpp"
#include "scenarios/common/dem/replicate_sample.hpp"

namespace debris {
namespace {

double min_image(double d, double length) { return d - length * std::round(d / length); }

// Pairs (i, j), i < j, closer than r_i + r_j + margin in a fully periodic box, with their distances.
std::vector<std::pair<std::pair<long, long>, double>> pairs_in_range(const Particles& p, const Box& box,
                                                                      double margin) {
  std::vector<std::pair<std::pair<long, long>, double>> out;
  const Vec3 len = box.length();
  for (std::size_t i = 0; i < p.size(); ++i)
    for (std::size_t j = i + 1; j < p.size(); ++j) {
      const double dx = min_image(p.x[i] - p.x[j], len.x), dy = min_image(p.y[i] - p.y[j], len.y);
      const double dz = min_image(p.z[i] - p.z[j], len.z);
      const double d = std::sqrt(dx * dx + dy * dy + dz * dz);
      if (d < p.radius[i] + p.radius[j] + margin) out.push_back({{p.id[i], p.id[j]}, d});
    }
  return out;
}

TEST(ReplicateSample, SeamsContinueThePeriodicPacking) {
  LammpsData data = read_lammps_data(DEBRIS_SOURCE_DIR "/scenarios/wear/data/silica_d0_6nm.data", {true, true, true});
  Particles original = data.particles;
  Box box = data.box;
  const std::size_t m = original.size();
  const std::int64_t step = original.max_id() + 1;
  Particles tiled = original;
  Box tiled_box = box;
  replicate_sample(tiled, tiled_box, {2, 1, 2});

  ASSERT_EQ(tiled.size(), 4 * m);
  EXPECT_DOUBLE_EQ(tiled_box.length().x, 2 * box.length().x);
  EXPECT_DOUBLE_EQ(tiled_box.length().y, box.length().y);
  EXPECT_DOUBLE_EQ(tiled_box.length().z, 2 * box.length().z);
  std::set<std::int64_t> ids(tiled.id.begin(), tiled.id.end());
  EXPECT_EQ(ids.size(), tiled.size());
  for (std::size_t i = 0; i < tiled.size(); ++i) {
    EXPECT_GE(tiled.x[i], tiled_box.lo().x);
    EXPECT_LT(tiled.x[i], tiled_box.hi().x);
    EXPECT_GE(tiled.z[i], tiled_box.lo().z);
    EXPECT_LT(tiled.z[i], tiled_box.hi().z);
  }

  // Every pair in range of the original (across its periodic faces too) appears in each of the four copies, and
  // the tiled box has no other pair: the same neighbour count per particle, the same distances.
  const double margin = 0.2 * *std::min_element(original.radius.begin(), original.radius.end());
  const auto before = pairs_in_range(original, box, margin);
  const auto after = pairs_in_range(tiled, tiled_box, margin);
  ASSERT_GT(before.size(), m);  // a dense packing: several neighbours each
  EXPECT_EQ(after.size(), 4 * before.size());
  std::vector<std::pair<std::pair<long, long>, double>> folded;  // the tiled pairs by original ids
  for (const auto& [ij, d] : after) {
    const long a = ij.first % step, b = ij.second % step;
    folded.push_back({{std::min(a, b), std::max(a, b)}, d});
  }
  std::sort(folded.begin(), folded.end());
  auto ref = before;
  for (auto& [ij, d] : ref) ij = {std::min(ij.first, ij.second), std::max(ij.first, ij.second)};
  std::sort(ref.begin(), ref.end());
  double worst = 0;
  for (std::size_t k = 0; k < folded.size(); ++k) {
    const auto& r = ref[k / 4];
    ASSERT_EQ(folded[k].first, r.first) << "pair " << k;
    worst = std::max(worst, std::abs(folded[k].second - r.second) / r.second);
  }
  EXPECT_LT(worst, 1e-12);  // the shift by whole box lengths rounds in the last bits only
}

TEST(ReplicateSample, OneCopyChangesNothing) {
  LammpsData data = read_lammps_data(DEBRIS_SOURCE_DIR "/scenarios/wear/data/silica_d0_6nm.data", {true, true, true});
  Particles p = data.particles;
  Box box = data.box;
  replicate_sample(p, box, {1, 1, 1});
  EXPECT_EQ(p.x, data.particles.x);
  EXPECT_EQ(p.ix, data.particles.ix);
  EXPECT_EQ(box.hi().x, data.box.hi().x);
}

}  // namespace
}  // namespace debris
