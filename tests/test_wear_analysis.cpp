// The wear analysis (scenarios/common/dem/wear_analysis.hpp) on systems whose answer is known by construction:
// a cohesive ball set rolling without slip between a fixed and a moving wall (out of their reach) is a
// third body with centre speed 1/2 of the wall's and rolling number 1; the same ball sliding without spin is
// a third body that does not roll; one cohesive block between the walls has no third body at all.
#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <vector>

#include "core/error.hpp"

#include "core/lattice.hpp"
#include "scenarios/common/dem/dem_simulation.hpp"
#include "scenarios/common/dem/wear_analysis.hpp"

namespace debris {
namespace {

constexpr double kWallSpeed = 0.01;  // Table 4 units: 1% of the wave speed sqrt(E / rho) = 1

// An FCC lattice (spacing 100) in a 7 x 14 x 7 cell box, periodic in x and z: a bottom wall (2 rows), a top
// wall (2 rows) and either a ball of radius 260 about the centre (`ball`) or the whole block between them.
struct JunctionSystem {
  Box box;
  Particles particles;
  Groups groups;
};

JunctionSystem make_system(bool ball, bool across_face = false) {
  LatticeSpec spec;
  spec.kind = LatticeKind::fcc;
  spec.spacing = 100;
  spec.diameter = 100;
  spec.cells = {7, 14, 7};
  Lattice lat = make_lattice(spec);
  JunctionSystem s;
  s.box = Box(lat.box.lo(), lat.box.hi(), {true, false, true});
  Particles& p = lat.particles;
  Vec3 c = 0.5 * (lat.box.lo() + lat.box.hi());
  if (across_face) c.x = lat.box.lo().x + 20;  // the ball straddles the periodic x face
  const double y_hi = lat.box.hi().y;
  std::vector<char> remove(p.size(), 0);
  Group bottom{"bottom", GroupMotion::frozen};
  Group top{"top", GroupMotion::velocity, Vec3{kWallSpeed, 0, 0}};
  s.groups.add(bottom);
  s.groups.add(top);
  p.label_names = {"junction"};
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Vec3 x{p.x[i], p.y[i], p.z[i]};
    if (x.y < 150) {
      p.group[i] = 0;
    } else if (x.y > y_hi - 150) {
      p.group[i] = 1;
    } else if (norm(minimum_image(s.box.view(), x - c)) < 260 || (!ball && x.y > 400 && x.y < y_hi - 400)) {
      p.label[i] = 1;  // the junction: the ball, or the middle of the block
    } else if (ball) {
      remove[i] = 1;
    }
  }
  p.remove_if(remove);
  s.particles = std::move(p);
  return s;
}

DemSettings settings() {
  DemSettings s;
  s.material = table4_material();
  s.material.restitution = 1.0;
  s.time_step_fraction = 0.1;
  return s;
}

// Sets the labelled body moving rigidly: centre velocity v_c along x, spin w about z. Positions are taken
// relative to the first member through minimum images (the ball may straddle a periodic face).
void set_body_motion(DemSimulation& sim, double v_c, double w) {
  Particles& p = sim.particles();
  const BoxView b = sim.box().view();
  std::size_t first = 0;
  while (p.label[first] != 1) ++first;
  const Vec3 anchor{p.x[first], p.y[first], p.z[first]};
  auto rel = [&](std::size_t i) { return minimum_image(b, Vec3{p.x[i], p.y[i], p.z[i]} - anchor); };
  Vec3 c{};
  double m = 0;
  for (std::size_t i = 0; i < p.size(); ++i)
    if (p.label[i] == 1) {
      c += p.mass[i] * rel(i);
      m += p.mass[i];
    }
  c = (1.0 / m) * c;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p.label[i] != 1) continue;
    const Vec3 v = Vec3{v_c, 0, 0} + cross(Vec3{0, 0, w}, rel(i) - c);
    p.vx[i] = v.x;
    p.vy[i] = v.y;
    p.vz[i] = v.z;
    p.wz[i] = w;
  }
  sim.recompute_forces();
}

// Half the body's height along y, radii included: the R of the rolling number.
double half_height(const Particles& p) {
  double lo = 1e300, hi = -1e300;
  for (std::size_t i = 0; i < p.size(); ++i)
    if (p.label[i] == 1) {
      lo = std::min(lo, p.y[i] - p.radius[i]);
      hi = std::max(hi, p.y[i] + p.radius[i]);
    }
  return 0.5 * (hi - lo);
}

WearSettings wear_settings(double dt) {
  WearSettings w;
  w.every = 100;
  w.bottom_wall = "bottom";
  w.top_wall = "top";
  w.junction_label = "junction";
  w.persistence = 300 * dt;
  w.window = 600 * dt;
  return w;
}

WearAnalysis run(DemSimulation& sim, long steps) {
  WearAnalysis wear(wear_settings(sim.dt()), sim);
  wear.sample(sim);
  for (long s = 1; s <= steps; ++s) {
    sim.step();
    if (s % 100 == 0) wear.sample(sim);
  }
  return wear;
}

TEST(WearAnalysis, BallRollingWithoutSlipIsARollingWearParticle) {
  JunctionSystem s = make_system(true);
  DemSimulation sim(s.box, std::move(s.particles), std::move(s.groups), settings());
  // Rolling without slip between a fixed floor and a roof moving at v: centre at v/2, spin -v / (2R) about
  // z (clockwise seen from +z when the roof moves to +x), so 2 R omega / v = 1 about n x s = y x x = -z.
  const double R = half_height(sim.particles());
  set_body_motion(sim, 0.5 * kWallSpeed, -kWallSpeed / (2 * R));
  const WearAnalysis wear = run(sim, 1500);
  const WearSample& last = wear.samples().back();
  EXPECT_EQ(wear.verdict(), WearVerdict::rolling) << wear.report();
  EXPECT_FALSE(last.walls_joined);
  // The ball is the whole junction; its bottom and top rows move with f < 0.1 or f > 0.9 and are left out.
  EXPECT_GT(last.third_volume, 0.9);
  EXPECT_EQ(last.third_from_junction, 1.0);
  EXPECT_NEAR(last.centre_speed, 0.5, 0.01);
  // 2R from the particles with 0.1 < f < 0.9, whose extent is 0.8 of the height to within a row of this
  // 100-particle lattice ball (17% here; less for the junctions' hundreds of amorphous particles).
  EXPECT_NEAR(last.rolling_number, 1.0, 0.2);
  EXPECT_LT(last.residual, 0.02);
  // Kinematics need a whole window (600 steps) of sliding behind a sample; the ball is a rolling third body
  // in the fit of the first such sample on, and the verdict, which needs one at every sample of its span
  // (window / 2 = 300 steps, samples 6 to 9), from sample 9 on.
  EXPECT_FALSE(wear.samples()[5].kinematics);
  EXPECT_EQ(wear.samples()[6].sample_verdict, WearVerdict::rolling);
  EXPECT_EQ(wear.samples()[8].verdict, WearVerdict::ductile);
  EXPECT_EQ(wear.detection_index(), 9);
  EXPECT_NEAR(last.mean_centre_speed, 0.5, 0.01);
  EXPECT_LT(last.mean_residual, 0.02);
  // Its bonds: every pair of the ball stayed in range, so it is one bonded cluster bonded to neither wall.
  EXPECT_NEAR(last.junction_in_third, 1.0, 1e-12);
}

// Each threshold decides at its boundary: the rolling ball is analysed once with the input's settings and,
// on the same samples, with one threshold moved just past the value measured over the verdict's span (a
// relative 1e-6 either side), which must turn the verdict to what that threshold means.
TEST(WearAnalysis, EachThresholdDecidesAtItsBoundary) {
  JunctionSystem s = make_system(true);
  DemSimulation sim(s.box, std::move(s.particles), std::move(s.groups), settings());
  const double R = half_height(sim.particles());
  set_body_motion(sim, 0.5 * kWallSpeed, -kWallSpeed / (2 * R));
  // A first pass gives the values over the span at the last sample (steps 1200-1500).
  const WearAnalysis reference = run(sim, 1500);
  const WearSample ref = reference.samples().back();
  ASSERT_EQ(ref.verdict, WearVerdict::rolling) << reference.report();
  double min_volume = 1;
  for (std::size_t k = reference.samples().size() - 4; k < reference.samples().size(); ++k)
    min_volume = std::min(min_volume, reference.samples()[k].third_volume);

  struct Case {
    const char* what;
    WearSettings settings;
    WearVerdict expected;
  };
  const double up = 1 + 1e-6, down = 1 - 1e-6;
  std::vector<Case> cases;
  auto with = [&](const char* what, auto edit, WearVerdict expected) {
    WearSettings w = wear_settings(sim.dt());
    edit(w);
    cases.push_back({what, w, expected});
  };
  with("max_residual just above", [&](WearSettings& w) { w.max_residual = ref.mean_residual * up; }, WearVerdict::rolling);
  with("max_residual just below", [&](WearSettings& w) { w.max_residual = ref.mean_residual * down; }, WearVerdict::ductile);
  with("centre_speed max just above", [&](WearSettings& w) { w.centre_speed_max = ref.mean_centre_speed * up; },
       WearVerdict::rolling);
  with("centre_speed max just below", [&](WearSettings& w) { w.centre_speed_max = ref.mean_centre_speed * down; },
       WearVerdict::detached);
  with("centre_speed min just above", [&](WearSettings& w) { w.centre_speed_min = ref.mean_centre_speed * up; },
       WearVerdict::detached);
  with("rolling_number min just below", [&](WearSettings& w) { w.rolling_number_min = ref.mean_rolling_number * down; },
       WearVerdict::rolling);
  with("rolling_number min just above", [&](WearSettings& w) { w.rolling_number_min = ref.mean_rolling_number * up; },
       WearVerdict::detached);
  with("rolling_number max just below", [&](WearSettings& w) { w.rolling_number_max = ref.mean_rolling_number * down; },
       WearVerdict::detached);
  with("min_volume_fraction at the span's least", [&](WearSettings& w) { w.min_volume_fraction = min_volume; },
       WearVerdict::rolling);
  with("min_volume_fraction just above it", [&](WearSettings& w) { w.min_volume_fraction = std::min(1.0, min_volume * up); },
       WearVerdict::ductile);
  // The span: kinematics from step 600 on, so a span reaching back to step 600 is covered, one to 500 not.
  with("verdict_span back to the first fit", [&](WearSettings& w) { w.verdict_span = 900 * sim.dt(); }, WearVerdict::rolling);
  with("verdict_span past the first fit", [&](WearSettings& w) { w.verdict_span = 1000 * sim.dt(); }, WearVerdict::ductile);

  // The same run again from the same start, every analysis sampling it.
  JunctionSystem s2 = make_system(true);
  DemSimulation again(s2.box, std::move(s2.particles), std::move(s2.groups), settings());
  set_body_motion(again, 0.5 * kWallSpeed, -kWallSpeed / (2 * R));
  std::vector<WearAnalysis> analyses;
  for (const Case& c : cases) analyses.emplace_back(c.settings, again);
  for (WearAnalysis& a : analyses) a.sample(again);
  for (long step = 1; step <= 1500; ++step) {
    again.step();
    if (step % 100 == 0)
      for (WearAnalysis& a : analyses) a.sample(again);
  }
  for (std::size_t k = 0; k < cases.size(); ++k)
    EXPECT_EQ(analyses[k].verdict(), cases[k].expected) << cases[k].what << "\n" << analyses[k].report();
}

// The state handed to a checkpoint restores an analysis that goes on exactly as the original.
TEST(WearAnalysis, RestoredStateGoesOnAsTheOriginal) {
  JunctionSystem s = make_system(true);
  DemSimulation sim(s.box, std::move(s.particles), std::move(s.groups), settings());
  const double R = half_height(sim.particles());
  set_body_motion(sim, 0.5 * kWallSpeed, -kWallSpeed / (2 * R));
  WearAnalysis original(wear_settings(sim.dt()), sim);
  original.sample(sim);
  std::optional<WearAnalysis> copy;
  for (long step = 1; step <= 1500; ++step) {
    sim.step();
    if (step % 100 != 0) continue;
    original.sample(sim);
    if (step == 800) {
      copy.emplace(wear_settings(sim.dt()), sim);
      copy->restore(original.state(), "test");
    } else if (copy) {
      copy->sample(sim);
    }
  }
  ASSERT_TRUE(copy);
  ASSERT_EQ(copy->samples().size(), original.samples().size());
  for (std::size_t k = 0; k < original.samples().size(); ++k)
    EXPECT_EQ(WearAnalysis::row(copy->samples()[k]), WearAnalysis::row(original.samples()[k])) << "sample " << k;
  EXPECT_EQ(copy->report(), original.report());
  WearState broken = original.state();
  broken.history_id.pop_back();
  EXPECT_THROW(copy->restore(broken, "test"), InputError);
}

// The same across the periodic x face: members joined through minimum images are fitted as one body.
TEST(WearAnalysis, BallRollingAcrossAPeriodicFaceIsOneBody) {
  JunctionSystem s = make_system(true, true);
  DemSimulation sim(s.box, std::move(s.particles), std::move(s.groups), settings());
  const double R = half_height(sim.particles());
  set_body_motion(sim, 0.5 * kWallSpeed, -kWallSpeed / (2 * R));
  const WearAnalysis wear = run(sim, 1500);
  const WearSample& last = wear.samples().back();
  EXPECT_EQ(wear.verdict(), WearVerdict::rolling) << wear.report();
  EXPECT_GT(last.third_volume, 0.9);
  EXPECT_NEAR(last.centre_speed, 0.5, 0.01);
  EXPECT_LT(last.residual, 0.02);
}

TEST(WearAnalysis, BallSlidingWithoutSpinIsDetachedButDoesNotRoll) {
  JunctionSystem s = make_system(true);
  DemSimulation sim(s.box, std::move(s.particles), std::move(s.groups), settings());
  set_body_motion(sim, 0.5 * kWallSpeed, 0.0);
  const WearAnalysis wear = run(sim, 1500);
  const WearSample& last = wear.samples().back();
  EXPECT_EQ(wear.verdict(), WearVerdict::detached) << wear.report();
  EXPECT_NEAR(last.centre_speed, 0.5, 0.01);
  EXPECT_NEAR(last.rolling_number, 0.0, 0.02);
  EXPECT_LT(last.residual, 0.02);
}

TEST(WearAnalysis, OneBondedBlockHasNoThirdBody) {
  JunctionSystem s = make_system(false);
  DemSimulation sim(s.box, std::move(s.particles), std::move(s.groups), settings());
  const WearAnalysis wear = run(sim, 1000);
  const WearSample& last = wear.samples().back();
  EXPECT_EQ(wear.verdict(), WearVerdict::ductile) << wear.report();
  EXPECT_TRUE(last.walls_joined);
  EXPECT_GT(last.residual, 0.3) << "a sheared layer is not a rigid body";
  EXPECT_NEAR(last.junction_in_bottom, 1.0, 1e-12);
  EXPECT_NEAR(last.junction_in_top, 1.0, 1e-12);
  EXPECT_GT(last.bonded_pairs, 6 * static_cast<long>(sim.particles().size()) / 2 - 1);  // FCC: 12 bonds each
}

}  // namespace
}  // namespace debris
