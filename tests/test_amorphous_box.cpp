// Amorphous samples of any box lengths [Lx, Ly, Lz] (paper A section 4 uses 60 x 40 x 40 nm): the `box`
// key in d0 or with units, its errors, the cache key, and a tiny sample made and saved with such a box.
#include <gtest/gtest.h>

#include <filesystem>
#include <functional>
#include <string>

#include "core/error.hpp"
#include "core/exec.hpp"
#include "core/io/input.hpp"
#include "scenarios/common/dem/amorphous_sample.hpp"
#include "tests/cli_helpers.hpp"

namespace debris {
namespace {

// Table 4 (no units): d_c = 150, so d0 = 1.2 d_c = 180.
AmorphousSpec read_sample(const std::string& yaml) {
  AmorphousSpec s;
  s.d0 = 1.2;
  const InputNode n = InputNode::load_string(yaml, "test");
  read_amorphous_sample_keys(n, s);
  n.reject_unknown_keys();
  s.validate();
  return s;
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(AmorphousBox, BoxKeyInD0OrWithUnits) {
  const AmorphousSpec a = read_sample("{box: [5, 4.5, 3.6]}");
  EXPECT_FALSE(a.box_absolute);
  EXPECT_DOUBLE_EQ(a.box_length().x, 5 * 180.0);
  EXPECT_DOUBLE_EQ(a.box_length().y, 4.5 * 180.0);
  EXPECT_DOUBLE_EQ(a.box_length().z, 3.6 * 180.0);
  // "m" on a unitless material: the numbers are taken as lengths, whatever d0 is.
  AmorphousSpec b = read_sample("{box: [900 m, 810 m, 648 m]}");
  EXPECT_TRUE(b.box_absolute);
  EXPECT_EQ(b.box_length().x, 900.0);
  EXPECT_EQ(b.box_length().z, 648.0);
  b.d0 = 1.0;
  EXPECT_EQ(b.box_length().y, 810.0);  // unchanged by d0
  // The old keys still make L x L x W.
  const AmorphousSpec c = read_sample("{length: 5, width: 3.6}");
  EXPECT_DOUBLE_EQ(c.box_length().y, 5 * 180.0);
  EXPECT_DOUBLE_EQ(c.box_length().z, 3.6 * 180.0);
  // The cache key of an L x L x W spec is what it was; a box makes another one.
  EXPECT_EQ(amorphous_spec_key(c).find("box"), std::string::npos);
  EXPECT_NE(amorphous_spec_key(a), amorphous_spec_key(c));
  EXPECT_NE(amorphous_spec_key(a), amorphous_spec_key(read_sample("{box: [5, 4.5, 3.7]}")));
}

TEST(AmorphousBox, BadBoxesNameTheKey) {
  auto msg = [](const std::string& yaml) { return error_of([&] { read_sample(yaml); }); };
  EXPECT_NE(msg("{box: [5, 4.5]}").find("'sample.box' = 2 values"), std::string::npos) << msg("{box: [5, 4.5]}");
  EXPECT_NE(msg("{box: [5, 4.5 m, 4]}").find("'sample.box'"), std::string::npos);
  EXPECT_NE(msg("{box: [5, 4.5 m, 4]}").find("all three"), std::string::npos);
  EXPECT_NE(msg("{box: [5, 4, 4], width: 4}").find("'sample.box'"), std::string::npos);
  EXPECT_NE(msg("{box: [5, 4, 2]}").find("'sample.box' = [5, 4, 2]: the box is too small"), std::string::npos)
      << msg("{box: [5, 4, 2]}");
  EXPECT_NE(msg("{box: [5, -4, 4]}").find("'sample.box'"), std::string::npos);
  EXPECT_NE(msg("{box: [-5, -4, -4]}").find("'sample.box' = [-5, -4, -4]: every length must be > 0"), std::string::npos)
      << msg("{box: [-5, -4, -4]}");
  EXPECT_NE(msg("{box: [5 GPa, 4 GPa, 4 GPa]}").find("box[0]' = '5 GPa'"), std::string::npos) << msg("{box: [5 GPa, 4 GPa, 4 GPa]}");
}

TEST(AmorphousBox, TinySampleOfThreeDifferentLengths) {
  AmorphousSpec s = read_sample("{box: [5, 4.2, 3.6], seed: 3}");
  s.phase1_steps = 1000;
  s.stress_threshold = 1e-9;  // seconds, not minutes: the box rule is tested elsewhere
  const int before = exec::threads();
  exec::set_threads(1);
  const AmorphousSample a = make_amorphous_sample(s);
  exec::set_threads(before);
  EXPECT_DOUBLE_EQ(a.initial_box_length.x, 5 * 180.0);
  EXPECT_DOUBLE_EQ(a.initial_box_length.y, 4.2 * 180.0);
  EXPECT_DOUBLE_EQ(a.initial_box_length.z, 3.6 * 180.0);
  EXPECT_LT(a.final_max_stress, 1e-9);
  // The box relaxes per axis but keeps its proportions roughly: no axis moved by more than 10%.
  const Vec3 l = a.box.length();
  EXPECT_NEAR(l.x / a.initial_box_length.x, 1.0, 0.1);
  EXPECT_NEAR(l.y / a.initial_box_length.y, 1.0, 0.1);
  EXPECT_NEAR(l.z / a.initial_box_length.z, 1.0, 0.1);
  EXPECT_GT(a.particles.size(), 50u);
  for (std::size_t i = 0; i < a.particles.size(); ++i) {
    EXPECT_TRUE(a.particles.x[i] >= 0 && a.particles.x[i] < l.x) << i;
    EXPECT_TRUE(a.particles.y[i] >= 0 && a.particles.y[i] < l.y) << i;
    EXPECT_TRUE(a.particles.z[i] >= 0 && a.particles.z[i] < l.z) << i;
  }
  // Saved and read back with its box.
  const std::string stem = (test::fresh_directory("debris_amorphous_box") / "s").string();
  write_amorphous_sample(stem, a, s, "sample: {box: [5, 4.2, 3.6]}");
  const AmorphousSampleFile f = read_amorphous_sample(stem + ".h5");
  EXPECT_EQ(f.box.length().x, l.x);
  EXPECT_EQ(f.box.length().y, l.y);
  EXPECT_EQ(f.box.length().z, l.z);
  EXPECT_EQ(f.particles.size(), a.particles.size());
  EXPECT_TRUE(std::filesystem::exists(stem + ".data"));
}

}  // namespace
}  // namespace debris
