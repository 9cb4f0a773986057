// The wear census of a sliding interface (scenarios/common/dem/surface_census.hpp), against answers known
// without the census:
//   - two blocks of frictionless-like, non-adhesive spheres (strengths 1000 times below the load) sliding on
//     each other: nothing wears, every particle stays with its body, the friction coefficient is small and
//     the contact area is the contact pairs' A_N of paper A eqs 14-15;
//   - walls with balls set moving between them by hand: the balls at half the wall's speed are the third body,
//     one cluster each, and a ball labelled with the bottom body but moving with the top wall is transfer;
//   - the sheared junction of paper A (D = 20 nm, d0 = 6 nm): every particle in exactly one of bottom, top and
//     third body at every sample, wear once sheared;
//   - a hand-built state: a cluster touching no driven member is detached, one hanging from the top driven
//     group attached to it, and once the lid is lowered onto it, bridging; counts and volumes exact (4/3 pi r^3
//     sums), every particle counted once; the tangential work of each third-body cluster from tangential_work
//     columns set by hand (less their values when the particles joined), the V_d(W_t) fit through them, and
//     the contact tangential work as the accounting's sum; NaN and a reason with the accounting off;
//   - surfaces.csv the same bits on 1 and 2 threads; bad `surfaces:` input is exit 2 naming the key, nothing
//     written. (A chunked run's census: WearJunctionRestart; the rolling junction's: WearJunctionRolling.)
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/io/text_format.hpp"
#include "core/lattice.hpp"
#include "kernels/dem/cohesive_material.hpp"
#include "scenarios/common/dem/dem_run.hpp"
#include "scenarios/common/dem/dem_simulation.hpp"
#include "scenarios/common/dem/surface_census.hpp"
#include "tests/cli_helpers.hpp"

namespace debris {
namespace {

namespace fs = std::filesystem;
constexpr double kPi = 3.14159265358979323846;

double sphere_volume(double r) { return 4.0 / 3.0 * kPi * r * r * r; }

// Rows as the files write them (NaN, with the accounting off, compares equal as text).
std::string csv_text(const std::vector<std::vector<double>>& rows) {
  std::string t;
  for (const std::vector<double>& row : rows) {
    for (double v : row) {
      append_number(t, v);
      t += ',';
    }
    t += '\n';
  }
  return t;
}

// ---- two blocks sliding on a frictionless-like interface ---------------------------------------------------

// Two HCP blocks (close-packed planes x-z, periodic in x and z): the bottom one of spacing 100 (6 x 2 x 6
// cells, 288 particles, its lowest layer frozen), the top one of spacing 120 (5 x 2 x 5 cells, 200 particles,
// its highest layer driven: x at `speed`, y under `pressure`), the same period along x and z. Their 6:5
// spacings make the interface incommensurate, so the only plane that can slide without climbing over a row
// is the interface. Material: Table 4's stiffness with tensile and shear strength and surface energy far
// below the load (1e-6 against a pressure of 1e-3): a pair's adhesion and tangential cap are about 1/1000 of
// the force each contact carries.
struct TwoBlocks {
  Box box;
  Particles particles;
  Groups groups;
  double pressure = 1e-3;
  double area = 0;
};

TwoBlocks two_blocks() {
  LatticeSpec b;
  b.kind = LatticeKind::hcp;
  b.spacing = b.diameter = 100;
  b.cells = {6, 2, 6};
  LatticeSpec t = b;
  t.spacing = t.diameter = 120;
  t.cells = {5, 2, 5};
  Lattice bottom = make_lattice(b), top = make_lattice(t);
  TwoBlocks s;
  Particles& p = bottom.particles;
  const auto [b_lo, b_hi] = std::minmax_element(p.y.begin(), p.y.end());
  const double bottom_low = *b_lo, bottom_high = *b_hi;
  const Particles& q = top.particles;
  const double top_low = *std::min_element(q.y.begin(), q.y.end());
  const double shift = bottom_high + 110 - top_low;  // the interface layers touching: r + r' = 50 + 60
  p.label_names = {"lower", "upper", "floor", "slider"};
  for (std::size_t i = 0; i < p.size(); ++i) p.label[i] = 1;
  for (std::size_t i = 0; i < q.size(); ++i) {
    const std::size_t k = p.add(q.id[i] + 1000, 1, q.x[i], q.y[i] + shift, q.z[i], q.radius[i]);
    p.label[k] = 2;
  }
  double top_high = -1e300;
  for (std::size_t i = 0; i < p.size(); ++i) top_high = std::max(top_high, p.y[i]);
  const Vec3 lo = bottom.box.lo(), hi = bottom.box.hi();
  s.box = Box(Vec3{lo.x, bottom_low - 100, lo.z}, Vec3{hi.x, top_high + 200, hi.z}, {true, false, true});
  EXPECT_NEAR(top.box.hi().x - top.box.lo().x, hi.x - lo.x, 1e-9);  // the same period
  EXPECT_NEAR(top.box.hi().z - top.box.lo().z, hi.z - lo.z, 1e-9);
  s.area = (hi.x - lo.x) * (hi.z - lo.z);
  Group floor{"floor", GroupMotion::frozen};
  Group slider{"slider", GroupMotion::force};
  slider.prescribed = {true, false, true};
  slider.external_force = {0, -s.pressure * s.area, 0};
  const int g_floor = s.groups.add(floor), g_slider = s.groups.add(slider);
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p.y[i] < bottom_low + 10) p.group[i] = g_floor, p.label[i] = 3;
    if (p.y[i] > top_high - 10) p.group[i] = g_slider, p.label[i] = 4;
  }
  s.particles = std::move(p);
  return s;
}

DemSettings frictionless_settings() {
  DemSettings s;
  s.material = table4_material();
  s.material.tensile_strength = 1e-6;
  s.material.shear_strength = 1e-6;
  s.material.surface_energy = 1e-12;
  s.material.restitution = 0.9;
  s.time_step_fraction = 0.1;
  s.global_damping = 0.1;  // while settling
  return s;
}

SurfaceSettings block_census(double window) {
  SurfaceSettings c;
  c.every = 100;
  c.bottom.labels = {"lower", "floor"};
  c.bottom.driven = "floor";
  c.top.labels = {"upper"};  // the slider joins through `driven`
  c.top.driven = "slider";
  c.window = window;
  return c;
}

TEST(SurfaceCensus, FrictionlessInterfaceSlidesWithoutWear) {
  TwoBlocks s = two_blocks();
  const double load = s.pressure * s.area;
  DemSimulation sim(s.box, std::move(s.particles), std::move(s.groups), frictionless_settings());
  // Settle under the load (damped), then slide slowly (0.2% of the wave speed) without global damping, which
  // would drag the whole top block: 6,000 steps, about 1.3 top periods.
  const double speed = 0.002, dt = sim.dt();
  SurfaceCensus census(block_census(3000 * dt), sim);
  census.sample(sim);
  for (long step = 1; step <= 6500; ++step) {
    if (step == 501) {
      sim.groups().list[1].velocity.x = speed;
      sim.set_global_damping(0);
      sim.recompute_forces();
    }
    sim.step();
    if (step % 100 == 0) census.sample(sim);
  }
  const double slid = census.samples().back().slide;
  EXPECT_NEAR(slid, 6000 * dt * speed, 1e-9 * slid);
  // Nothing wears: at every sample each particle is in the body it started in.
  long classified = 0;
  for (const SurfaceSample& x : census.samples()) {
    EXPECT_EQ(x.wear_volume, 0.0) << "step " << x.step;
    EXPECT_EQ(x.third_particles, 0) << "step " << x.step;
    EXPECT_EQ(x.bottom_particles, 288) << "step " << x.step;
    EXPECT_EQ(x.top_particles, 200) << "step " << x.step;
    EXPECT_EQ(x.clusters, 0);
    classified += x.classified;
  }
  // f classifies from a relative slide of one smallest radius (50) on.
  EXPECT_GT(classified, 30);
  // The interface carries the load on contact pairs of a bottom (r = 50) and a top (r = 60) particle, each
  // with A_N = sqrt(2) r_eff^2 / (1 - 2 nu), r_eff = 50 (eqs 14-15).
  const SurfaceSample& last = census.samples().back();
  EXPECT_GT(last.contact_pairs, 0);
  EXPECT_NEAR(last.contact_area, last.contact_pairs * std::sqrt(2.0) * 2500 / (1 - 2 * 0.15), 1e-9 * last.contact_area);
  // Friction: what resists the slide is the pairs' tangential cap (1/1000 of a contact's load), the
  // incommensurate interface's corrugation, which averages out, and the pairs' damping of the vibration it
  // excites: the mean |tangential| / |normal| reaction over the slide is far below a dry contact's 0.1-1 (the
  // geometric friction of two commensurate sphere layers is about 0.3), and so is the drive's work over
  // load x slide.
  double mu = 0;
  long sliding = 0;
  for (const SurfaceSample& x : census.samples())
    if (x.slide > 50) {
      mu += x.friction_coefficient;
      ++sliding;
    }
  ASSERT_GT(sliding, 30);
  EXPECT_LT(mu / sliding, 0.05) << "mean friction coefficient";
  EXPECT_GT(last.tangential_work, 0.0);
  EXPECT_LT(last.tangential_work, 0.05 * load * slid);
  EXPECT_NEAR(last.normal_force, load, 0.2 * load);  // the reaction balances the load, give or take vibration
}

// ---- balls set moving by hand between two walls -------------------------------------------------------------

// An FCC lattice (spacing = diameter = 100) in an 8 x 14 x 8 cell box, periodic in x and z: a bottom wall
// (y < 150, frozen) and a top wall (y > y_max - 150, at `speed` along x), and three balls out of the walls'
// and each other's reach: A (radius 230) and B (radius 200) labelled `debris` (neither body) and C (radius
// 160) labelled `flake` (the bottom body's). Everything else is removed.
struct Balls {
  Box box;
  Particles particles;
  Groups groups;
};

Balls balls() {
  LatticeSpec spec;
  spec.kind = LatticeKind::fcc;
  spec.spacing = spec.diameter = 100;
  spec.cells = {8, 14, 8};
  Lattice lat = make_lattice(spec);
  Balls s;
  s.box = Box(lat.box.lo(), lat.box.hi(), {true, false, true});
  Particles& p = lat.particles;
  const double y_hi = lat.box.hi().y;
  p.label_names = {"base", "lid", "debris", "flake"};
  Group bottom{"base", GroupMotion::frozen};
  Group top{"lid", GroupMotion::velocity, Vec3{0.01, 0, 0}};
  s.groups.add(bottom);
  s.groups.add(top);
  struct Ball {
    Vec3 centre;
    double radius;
    int label;
  };
  const Ball list[] = {{{280, 700, 280}, 230, 3}, {{280, 1000, 850}, 200, 3}, {{700, 1350, 280}, 160, 4}};
  std::vector<char> remove(p.size(), 0);
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Vec3 x{p.x[i], p.y[i], p.z[i]};
    if (x.y < 150) {
      p.group[i] = 0, p.label[i] = 1;
      continue;
    }
    if (x.y > y_hi - 150) {
      p.group[i] = 1, p.label[i] = 2;
      continue;
    }
    remove[i] = 1;
    for (const Ball& b : list)
      if (norm(minimum_image(s.box.view(), x - b.centre)) < b.radius) remove[i] = 0, p.label[i] = b.label;
  }
  p.remove_if(remove);
  s.particles = std::move(p);
  return s;
}

TEST(SurfaceCensus, BallsMovingWithNeitherWallAreTheThirdBody) {
  Balls s = balls();
  DemSettings settings;
  settings.material = table4_material();
  settings.material.restitution = 1.0;
  settings.time_step_fraction = 0.1;
  DemSimulation sim(s.box, std::move(s.particles), std::move(s.groups), settings);
  // Which particle is which, and the balls' velocities: A and B at half the wall's speed (f = 1/2), C at the
  // wall's (f = 1); no spin.
  Particles& p = sim.particles();
  const double v = 0.01;
  std::vector<std::int64_t> a, b, c;
  long base = 0, lid = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p.label[i] == 1) ++base;
    if (p.label[i] == 2) ++lid;
    if (p.label[i] == 3) (p.z[i] < 565 ? a : b).push_back(p.id[i]);
    if (p.label[i] == 4) c.push_back(p.id[i]);
    if (p.label[i] >= 3) p.vx[i] = p.label[i] == 3 ? 0.5 * v : v;
  }
  sim.recompute_forces();
  ASSERT_GT(a.size(), b.size());
  ASSERT_GT(b.size(), 4u);
  ASSERT_GT(c.size(), 4u);
  const double r = 50, vp = sphere_volume(r);  // every particle has radius 50
  const double vol_a = static_cast<double>(a.size()) * vp, vol_b = static_cast<double>(b.size()) * vp,
               vol_c = static_cast<double>(c.size()) * vp;

  SurfaceSettings cs;
  cs.every = 100;
  cs.bottom.labels = {"base", "flake"};
  cs.bottom.driven = "base";
  cs.top.labels = {"lid"};
  cs.top.driven = "lid";
  cs.window = 600 * sim.dt();
  SurfaceCensus census(cs, sim);
  census.sample(sim);
  // Before any motion: each particle in the body it starts in, the debris balls (neither) in the third body.
  const SurfaceSample& first = census.samples().front();
  EXPECT_FALSE(first.classified);
  EXPECT_EQ(first.third_particles, static_cast<long>(a.size() + b.size()));
  EXPECT_EQ(first.bottom_particles, base + static_cast<long>(c.size()));
  EXPECT_EQ(first.to_top_volume, 0.0);
  for (long step = 1; step <= 1200; ++step) {
    sim.step();
    if (step % 100 == 0) census.sample(sim);
  }
  const SurfaceSample& last = census.samples().back();
  ASSERT_TRUE(last.classified);
  EXPECT_NEAR(last.window_time, 600 * sim.dt(), 1e-9 * last.window_time);
  // A and B: the third body, one cluster each; C: transferred to the top body.
  EXPECT_EQ(last.third_particles, static_cast<long>(a.size() + b.size()));
  EXPECT_NEAR(last.third_volume, vol_a + vol_b, 1e-12 * (vol_a + vol_b));
  EXPECT_EQ(last.clusters, 2);
  EXPECT_EQ(last.largest_particles, static_cast<long>(a.size()));
  EXPECT_NEAR(last.largest_volume, vol_a, 1e-12 * vol_a);
  EXPECT_NEAR(last.largest_diameter, std::cbrt(6 * vol_a / kPi), 1e-12 * last.largest_diameter);
  EXPECT_EQ(last.largest_from_neither, 1.0);
  EXPECT_EQ(last.bottom_particles, base);
  EXPECT_EQ(last.top_particles, lid + static_cast<long>(c.size()));
  EXPECT_NEAR(last.to_top_volume, vol_c, 1e-12 * vol_c);
  EXPECT_EQ(last.to_bottom_volume, 0.0);
  EXPECT_NEAR(last.wear_volume, vol_a + vol_b + vol_c, 1e-12 * (vol_a + vol_b + vol_c));
  EXPECT_EQ(last.contact_pairs, 0);  // the walls are apart, C touches nothing
  // By the graph, all three balls are detached (C too: f has it moving with the lid, but it touches
  // nothing), and the walls are their driven groups' alone.
  EXPECT_EQ(last.detached_particles, static_cast<long>(a.size() + b.size() + c.size()));
  EXPECT_EQ(last.detached_clusters, 3);
  EXPECT_NEAR(last.detached_volume, vol_a + vol_b + vol_c, 1e-12 * (vol_a + vol_b + vol_c));
  EXPECT_NEAR(last.largest_detached_volume, vol_a, 1e-12 * vol_a);
  EXPECT_EQ(last.attached_bottom_particles, base);
  EXPECT_EQ(last.attached_top_particles, lid);
  EXPECT_EQ(last.bridging_particles, 0);
  EXPECT_EQ(last.bridging_clusters, 0);
  // The third body's clusters as wear particles, largest first; no accounting here: W_t is NaN.
  ASSERT_EQ(last.debris.size(), 2u);
  EXPECT_EQ(last.debris[0].rank, 1);
  EXPECT_EQ(last.debris[0].particles, static_cast<long>(a.size()));
  EXPECT_EQ(last.debris[1].particles, static_cast<long>(b.size()));
  EXPECT_TRUE(std::isnan(last.debris[0].tangential_work));
  EXPECT_TRUE(std::isnan(last.contact_tangential_work));
  EXPECT_NE(census.report().find("the energy accounting is off"), std::string::npos) << census.report();
  for (std::int64_t id : a) EXPECT_EQ(census.state_of(id), SurfaceState::third);
  for (std::int64_t id : c) EXPECT_EQ(census.state_of(id), SurfaceState::top);
  // The histogram (default bins: edges 100 x 2^((k - 1/2) / 3), a cluster of n particles of diameter 100 in
  // bin round(log2 n)): one cluster in A's bin and one in B's.
  std::map<long, double> expected;
  expected[std::lround(std::log2(static_cast<double>(a.size())))] += 1;
  expected[std::lround(std::log2(static_cast<double>(b.size())))] += 1;
  const std::vector<double>& edges = census.bin_edges();
  EXPECT_NEAR(edges[0], 100 * std::exp2(-0.5 / 3), 1e-9);
  for (const std::vector<double>& row : census.histogram_rows(last)) {
    const long bin = static_cast<long>(row[2]);
    EXPECT_EQ(row[5], expected.count(bin) ? expected[bin] : 0.0) << "bin " << bin;
    EXPECT_NEAR(row[3], 100 * std::exp2((bin - 0.5) / 3), 1e-9 * row[3]);
  }
  // The state handed to a checkpoint restores a census that goes on as the original.
  SurfaceCensus copy(cs, sim);
  copy.restore(census.state(), "test");
  for (long step = 1201; step <= 1500; ++step) {
    sim.step();
    if (step % 100 == 0) {
      census.sample(sim);
      copy.sample(sim);
    }
  }
  ASSERT_EQ(copy.samples().size(), census.samples().size());
  for (std::size_t k = 0; k < census.samples().size(); ++k) {
    EXPECT_EQ(csv_text({SurfaceCensus::row(copy.samples()[k])}), csv_text({SurfaceCensus::row(census.samples()[k])}))
        << "sample " << k;
    EXPECT_EQ(csv_text(SurfaceCensus::debris_rows(copy.samples()[k])),
              csv_text(SurfaceCensus::debris_rows(census.samples()[k])))
        << "sample " << k;
  }
  SurfaceCensusState broken = census.state();
  broken.history_id.pop_back();
  EXPECT_THROW(copy.restore(broken, "test"), InputError);
  broken = census.state();
  broken.debris.pop_back();
  EXPECT_THROW(copy.restore(broken, "test"), InputError);
  broken = census.state();
  broken.debris_count.pop_back();
  EXPECT_THROW(copy.restore(broken, "test"), InputError);
  broken = census.state();
  broken.joined_value.push_back(1.0);
  EXPECT_THROW(copy.restore(broken, "test"), InputError);
}

// ---- a hand-built state: detached, attached, bridging; tangential work per cluster --------------------------

// In a box of 3000 (no periodic axis): a floor of three particles (r = 50, group `floor`, touching in a row)
// with one more (`lower`, the bottom body's label) standing on it; a lid of three (group `lid`) at height
// `lid_y`; a cluster D of three particles (r = 40, 50, 60, label `debris`: neither body) touching each other
// and nothing else; and a cluster T of two (r = 45, 55, label `debris`) hanging from the lid's third
// particle. Touching is at a distance of r_i + r_j, in interaction range (eq 10's delta_f above it); the
// test checks every other pair is out of range.
struct HandBuilt {
  Box box;
  Particles particles;
  Groups groups;
  std::vector<std::int64_t> d, t;  // the ids of clusters D and T
};

HandBuilt hand_built(double lid_y) {
  HandBuilt h;
  h.box = Box(Vec3{0, 0, 0}, Vec3{3000, 3000, 3000}, {false, false, false});
  Particles& p = h.particles;
  p.label_names = {"lower", "upper", "debris"};
  const int floor = h.groups.add(Group{"floor", GroupMotion::frozen});
  const int lid = h.groups.add(Group{"lid", GroupMotion::velocity, Vec3{0, 0, 0}});
  std::int64_t id = 1;
  auto put = [&](double x, double y, double r, int label, int group) {
    const std::size_t i = p.add(id++, 1, x, y, 500, r);
    p.label[i] = label;
    p.group[i] = group;
    return p.id[i];
  };
  for (double x : {100.0, 200.0, 300.0}) put(x, 100, 50, 0, floor);
  put(100, 200, 50, 1, -1);  // `lower`, on the floor's first particle
  for (double x : {100.0, 200.0, 300.0}) put(x, lid_y, 50, 0, lid);
  h.d.push_back(put(1500, 1500, 40, 3, -1));
  h.d.push_back(put(1500 + 90, 1500, 50, 3, -1));
  h.d.push_back(put(1500 + 90 + 110, 1500, 60, 3, -1));
  h.t.push_back(put(300, lid_y - 95, 45, 3, -1));
  h.t.push_back(put(300, lid_y - 95 - 100, 55, 3, -1));
  return h;
}

SurfaceSettings hand_built_census() {
  SurfaceSettings c;
  c.every = 1;
  c.bottom.labels = {"lower"};
  c.bottom.driven = "floor";
  c.top.labels = {"upper"};  // no particle carries it: the lid joins through `driven`
  c.top.driven = "lid";
  c.window = 1;
  return c;
}

// Every pair of the hand-built state is in range exactly when the test says it touches.
void expect_pairs_in_range(const DemSimulation& sim, long touching) {
  const Particles& p = sim.particles();
  const CohesiveCutoff range{sim.coefficients()};
  long in_range = 0;
  for (std::size_t i = 0; i < p.size(); ++i)
    for (std::size_t j = i + 1; j < p.size(); ++j) {
      const double d = norm(Vec3{p.x[i] - p.x[j], p.y[i] - p.y[j], p.z[i] - p.z[j]});
      const double touch = p.radius[i] + p.radius[j];
      if (d < range(p.radius[i], p.radius[j])) {
        ++in_range;
        EXPECT_NEAR(d, touch, 1e-9 * touch) << "ids " << p.id[i] << ", " << p.id[j];
      }
    }
  EXPECT_EQ(in_range, touching);
}

TEST(SurfaceCensus, GraphTellsDetachedFromAttachedAndBridging) {
  const double v_d = sphere_volume(40) + sphere_volume(50) + sphere_volume(60);  // cluster D
  const double v_t = sphere_volume(45) + sphere_volume(55);                      // cluster T
  DemSettings settings;
  settings.material = table4_material();
  settings.time_step_fraction = 0.1;
  {
    HandBuilt h = hand_built(2500);
    DemSimulation sim(h.box, std::move(h.particles), std::move(h.groups), settings);
    // Floor 2 pairs + lower 1, lid 2 + T's 2 (lid-T and T-T), D's 2.
    expect_pairs_in_range(sim, 9);
    SurfaceCensus census(hand_built_census(), sim);
    const SurfaceSample& s = census.sample(sim);
    EXPECT_EQ(s.detached_particles, 3);
    EXPECT_EQ(s.detached_clusters, 1);
    EXPECT_NEAR(s.detached_volume, v_d, 1e-15 * v_d);
    EXPECT_NEAR(s.largest_detached_volume, v_d, 1e-15 * v_d);
    EXPECT_EQ(s.attached_bottom_particles, 4);  // the floor and `lower`
    EXPECT_EQ(s.attached_top_particles, 5);     // the lid and T
    EXPECT_EQ(s.bridging_particles, 0);
    EXPECT_EQ(s.bridging_clusters, 0);
    EXPECT_EQ(s.attached_bottom_particles + s.attached_top_particles + s.bridging_particles + s.detached_particles, 12);
    // By f (nothing moved: each in the body it starts in), D and T are both third body: two clusters.
    EXPECT_EQ(s.third_particles, 5);
    EXPECT_EQ(s.clusters, 2);
    ASSERT_EQ(s.debris.size(), 2u);
    EXPECT_NEAR(s.debris[0].volume, v_d, 1e-15 * v_d);  // D is the larger
    EXPECT_NEAR(s.debris[1].volume, v_t, 1e-15 * v_t);
    EXPECT_NEAR(s.debris[1].diameter, std::cbrt(6 * v_t / kPi), 1e-15 * s.debris[1].diameter);
    EXPECT_EQ(s.debris[1].from_neither, 1.0);
  }
  {
    // The lid lowered until T rests on the floor's third particle: one component holds both driven groups.
    HandBuilt h = hand_built(100 + 105 + 100 + 95);
    DemSimulation sim(h.box, std::move(h.particles), std::move(h.groups), settings);
    expect_pairs_in_range(sim, 10);
    SurfaceCensus census(hand_built_census(), sim);
    const SurfaceSample& s = census.sample(sim);
    EXPECT_EQ(s.bridging_particles, 9);  // floor, lower, lid, T
    EXPECT_EQ(s.bridging_clusters, 1);
    EXPECT_EQ(s.attached_bottom_particles, 0);
    EXPECT_EQ(s.attached_top_particles, 0);
    EXPECT_EQ(s.detached_particles, 3);
    EXPECT_NEAR(s.detached_volume, v_d, 1e-15 * v_d);
    EXPECT_NE(census.report().find("the interface still bridges: 9 particles in 1 cluster"), std::string::npos)
        << census.report();
  }
}

TEST(SurfaceCensus, TangentialWorkPerClusterFromTheColumns) {
  DemSettings settings;
  settings.material = table4_material();
  settings.time_step_fraction = 0.1;
  settings.energy_accounting = true;
  HandBuilt h = hand_built(2500);
  const std::vector<std::int64_t> d = h.d, t = h.t;
  DemSimulation sim(h.box, std::move(h.particles), std::move(h.groups), settings);
  auto set_work = [&](std::int64_t id, double w) {
    Particles& p = sim.particles();
    for (std::size_t i = 0; i < p.size(); ++i)
      if (p.id[i] == id) p.tangential_work[i] = w;
  };
  // Before the first sample, where the five third-body particles join the third body: their columns then
  // are what the clusters' W_t starts from (dyadic values: every sum below is exact).
  set_work(d[0], 0.5);
  set_work(d[1], 0.25);
  set_work(d[2], 0.125);
  set_work(t[0], 1.0);
  set_work(t[1], 2.0);
  set_work(1, 64.0);  // a floor particle: counts in the system's total, in no cluster
  SurfaceCensus census(hand_built_census(), sim);
  const SurfaceSample& first = census.sample(sim);
  EXPECT_EQ(first.contact_tangential_work, 0.5 + 0.25 + 0.125 + 1.0 + 2.0 + 64.0);
  ASSERT_EQ(first.debris.size(), 2u);
  EXPECT_EQ(first.debris[0].tangential_work, 0.0);
  EXPECT_EQ(first.debris[1].tangential_work, 0.0);
  // Work done on them since: D 1 + 2 + 4 = 7, T 0.5 + 1.5 = 2.
  set_work(d[0], 1.5);
  set_work(d[1], 2.25);
  set_work(d[2], 4.125);
  set_work(t[0], 1.5);
  set_work(t[1], 3.5);
  const SurfaceSample& second = census.sample(sim);
  ASSERT_EQ(second.debris.size(), 2u);
  EXPECT_EQ(second.debris[0].tangential_work, 7.0);  // D, the larger
  EXPECT_EQ(second.debris[1].tangential_work, 2.0);  // T
  EXPECT_EQ(second.contact_tangential_work, 1.5 + 2.25 + 4.125 + 1.5 + 3.5 + 64.0);
  // The rows of surfaces_debris.csv: step, slide, rank, particles, volume, diameter, W_t, shares.
  const std::vector<std::vector<double>> rows = SurfaceCensus::debris_rows(second);
  ASSERT_EQ(rows.size(), 2u);
  ASSERT_EQ(rows[1].size(), SurfaceCensus::debris_columns().size());
  EXPECT_EQ(rows[1][2], 2.0);
  EXPECT_EQ(rows[1][3], 2.0);
  EXPECT_EQ(rows[1][6], 2.0);
  EXPECT_EQ(rows[1][9], 1.0);
  // Two clusters: the power law through both points.
  const double v_d = second.debris[0].volume, v_t = second.debris[1].volume;
  const PowerFit fit = census.debris_fit();
  ASSERT_TRUE(fit.made);
  EXPECT_EQ(fit.points, 2);
  EXPECT_NEAR(fit.exponent, std::log(v_d / v_t) / std::log(7.0 / 2.0), 1e-12);
  EXPECT_NEAR(fit.prefactor, v_t / std::pow(2.0, fit.exponent), 1e-9 * fit.prefactor);
  EXPECT_NE(census.report().find("V_d = "), std::string::npos) << census.report();
  // The census's state carries the records of when each joined: a copy goes on as the original.
  SurfaceCensus copy(hand_built_census(), sim);
  copy.restore(census.state(), "test");
  set_work(t[1], 4.5);
  EXPECT_EQ(census.sample(sim).debris[1].tangential_work, 3.0);
  EXPECT_EQ(copy.sample(sim).debris[1].tangential_work, 3.0);
}

TEST(SurfaceCensus, TangentialWorkAndPowerLawFit) {
  // A reaction of -2 (against the slide) over a displacement 0 -> 3: the drive does 6; the bottom group held
  // still does nothing; a trapezoid of reactions -1 and -3 over the same 3 does 6 too.
  EXPECT_EQ(tangential_work_increment(-2, -2, 0, 3, 5, 7, 1, 1), 6.0);
  EXPECT_EQ(tangential_work_increment(-1, -3, 0, 3, 0, 0, 0, 0), 6.0);
  EXPECT_EQ(tangential_work_increment(0, 0, 0, 0, -1, -1, 0, -2), -2.0);  // the bottom one driven backwards
  // V = 3 W^1.5 exactly, with points at V = 0 or W = 0 left out.
  std::vector<double> w{0, 1, 2, 4, 8, 5}, v{0, 3, 3 * std::pow(2, 1.5), 3 * 8, 3 * std::pow(8, 1.5), 0};
  const PowerFit fit = fit_power_law(w, v);
  ASSERT_TRUE(fit.made);
  EXPECT_EQ(fit.points, 4);
  EXPECT_NEAR(fit.exponent, 1.5, 1e-12);
  EXPECT_NEAR(fit.prefactor, 3, 1e-12);
  EXPECT_FALSE(fit_power_law({1, 1}, {2, 3}).made);  // one W: no slope
}

// ---- the sheared junction of paper A -------------------------------------------------------------------------

std::string junction_input(const fs::path& dir, const std::string& slide, const std::string& name) {
  std::string text = test::slurp(fs::path(DEBRIS_SOURCE_DIR) / "scenarios" / "wear" / "junction_D20_d0_6nm.yaml");
  text = test::replace(text, "lammps_data: data/",
                       "lammps_data: " + std::string(DEBRIS_SOURCE_DIR) + "/scenarios/wear/data/");
  text = test::replace(text, "duration: 10.0 ns", "duration: " + slide);
  return test::write_text_file(dir, name, text);
}

// D = 20 nm at d0 = 6 nm, 4 ns of its slide (52,500 steps, a few seconds), run as debris_dem runs it. The
// junction bonds the top body (its label is the top body's) to the bottom one, so sliding shears it: part
// of it ends with neither body or with the bottom one, and the wear volume is above zero from then on. At
// every sample every particle is in exactly one of bottom, top and third body.
TEST(SurfaceCensus, ShearedJunctionWearsAndConservesEveryParticle) {
  const fs::path d = test::fresh_directory("debris_census_junction");
  RunOptions opt;
  opt.input = junction_input(d, "4.0 ns", "junction.yaml");
  opt.output = (d / "out").string();
  opt.threads = 1;
  debris::Run run(prepare_dem_run(opt), "census", opt, WallClock::now());
  ASSERT_EQ(run.start(), 0);
  while (!run.done()) ASSERT_EQ(run.advance(10000), 0);
  const SurfaceCensus* census = dem_surface_census(run.model());
  ASSERT_NE(census, nullptr);
  const Particles& p = dem_simulation(run.model()).particles();
  const long n = static_cast<long>(p.size());
  double total = 0;
  for (std::size_t i = 0; i < p.size(); ++i) total += sphere_volume(p.radius[i]);
  ASSERT_EQ(census->samples().size(), 52500u / 625 + 1);
  for (const SurfaceSample& x : census->samples()) {
    EXPECT_EQ(x.bottom_particles + x.top_particles + x.third_particles, n) << "step " << x.step;
    // By the graph too: attached to either body, bridging or detached, every particle once.
    EXPECT_EQ(x.attached_bottom_particles + x.attached_top_particles + x.bridging_particles + x.detached_particles, n)
        << "step " << x.step;
    EXPECT_LE(x.largest_detached_volume, x.detached_volume);
    EXPECT_EQ(static_cast<long>(x.debris.size()), x.clusters) << "step " << x.step;
    long in_clusters = 0;
    for (const SurfaceDebris& c : x.debris) in_clusters += c.particles;
    EXPECT_EQ(in_clusters, x.third_particles) << "step " << x.step;
    EXPECT_NEAR(x.bottom_volume + x.top_volume + x.third_volume, total, 1e-12 * total) << "step " << x.step;
    EXPECT_NEAR(x.wear_volume, x.third_volume + x.to_bottom_volume + x.to_top_volume, 1e-12 * total);
    if (x.slide >= 20e-9) EXPECT_GT(x.wear_volume, 0.0) << "step " << x.step;  // a whole window of sliding
  }
  // Before sliding, the contact between the bodies is the junction's foot on the bottom body: its pairs'
  // A_N add up to about the junction's cross-section pi (D/2)^2 (eqs 14-15 make A_N a particle's share of it).
  const SurfaceSample& first = census->samples().front();
  EXPECT_EQ(first.wear_volume, 0.0);
  EXPECT_GT(first.contact_area, 0.5 * kPi * 1e-16);
  EXPECT_LT(first.contact_area, 2.0 * kPi * 1e-16);
  // The junction still joins the bodies at the first sample: one component holds both walls.
  EXPECT_EQ(first.bridging_clusters, 1);
  // The contact tangential work is the accounting's own sum (debris_dem runs with it on).
  const DemSimulation& sim = dem_simulation(run.model());
  ASSERT_TRUE(census->energy_accounting());
  EXPECT_EQ(census->samples().back().contact_tangential_work, sim.energy_totals().tangential_work);
  EXPECT_GT(census->samples().back().contact_tangential_work, 0.0);
  ASSERT_EQ(run.finish(), 0);
  // The file holds the samples, row for row.
  const test::NumberTable csv = test::read_number_table(d / "out" / "surfaces.csv");
  ASSERT_EQ(csv.rows.size(), census->samples().size());
  // (A face's Hurst exponent is NaN where the box holds too few wavelengths to fit: NaN reads back as NaN.)
  for (std::size_t k = 0; k < csv.rows.size(); ++k)
    EXPECT_THAT(csv.rows[k], testing::Pointwise(testing::NanSensitiveDoubleEq(), SurfaceCensus::row(census->samples()[k])));
  EXPECT_EQ(test::read_csv_rows(d / "out" / "surfaces_histogram.csv").size(),
            census->samples().size() * (census->bin_edges().size() - 1));
  const test::NumberTable debris = test::read_number_table(d / "out" / "surfaces_debris.csv");
  EXPECT_EQ(debris.columns, SurfaceCensus::debris_columns());
  std::vector<std::vector<double>> expected;
  for (const SurfaceSample& x : census->samples())
    for (const std::vector<double>& row : SurfaceCensus::debris_rows(x)) expected.push_back(row);
  EXPECT_EQ(debris.rows, expected);
  EXPECT_GT(debris.rows.size(), 0u);
}

// The census reads the system in id order: surfaces.csv and its histogram are the same bytes on 1 and 2
// threads (the D = 20 nm, d0 = 6 nm junction, 2.5 ns of its slide: the window fills).
TEST(SurfaceCensus, SameFilesOnOneAndTwoThreads) {
  const fs::path d = test::fresh_directory("debris_census_threads");
  const std::string input = junction_input(d, "2.5 ns", "junction.yaml");
  for (const char* threads : {"1", "2"}) {
    const test::CommandResult r = test::run_command(
        DEBRIS_DEM_EXECUTABLE, "-i " + input + " -o " + (d / threads).string() + " --threads " + threads);
    ASSERT_EQ(r.exit_code, 0) << r.output;
  }
  for (const char* file : {"surfaces.csv", "surfaces_histogram.csv", "surfaces_debris.csv"}) {
    const std::string one = test::slurp(d / "1" / file);
    EXPECT_GT(one.size(), 1000u) << file;
    EXPECT_EQ(one, test::slurp(d / "2" / file)) << file;
  }
}

// Bad `surfaces:` input: exit 2 naming the key and the value, before anything is written.
TEST(SurfaceCensus, BadInputIsANamedErrorAndWritesNothing) {
  const fs::path d = test::fresh_directory("debris_census_bad");
  const std::string good = test::slurp(fs::path(junction_input(d, "10.0 ns", "good.yaml")));
  struct Bad {
    std::string from, to, key, value;
  };
  const std::string bottom = "bottom: {label: [bottom, bottom_wall], driven: bottom_wall}";
  const std::string top = "top: {label: [top, junction, top_wall], driven: top_wall}";
  const std::vector<Bad> cases{
      {bottom, "bottom: {label: [bottom, floor], driven: bottom_wall}", "surfaces.bottom.label", "floor"},
      {top, "top: {group: slab, driven: top_wall}", "surfaces.top.group", "slab"},
      {top, "top: {label: [top, junction], driven: lid}", "surfaces.top.driven", "lid"},
      {top, "top: {label: [bottom, junction], driven: top_wall}", "surfaces.top.label", "bottom"},
      {top, "top: {label: [top, junction], driven: bottom_wall}", "surfaces.top.driven", "bottom_wall"},
      {top, "top: {label: top, group: top_wall, driven: top_wall}", "surfaces.top", "label and group"},
      {"  sliding_axis: x\n  normal_axis: y\n  window: 2 ns                 # f",
       "  sliding_axis: w\n  normal_axis: y\n  window: 2 ns                 # f", "surfaces.sliding_axis", "w"},
      {"  sliding_axis: x\n  normal_axis: y\n  window: 2 ns                 # f",
       "  sliding_axis: x\n  normal_axis: x\n  window: 2 ns                 # f", "surfaces.normal_axis", "x"},
      {"window: 2 ns                 # f over", "window: 12 ns                 # f over", "surfaces.window", "1.2e-08"},
      {"every: 625                   # steps: 0.05 ns\n  bottom: {", "every: 0\n  bottom: {", "surfaces.every", "0"},
      {"every: 625                   # steps: 0.05 ns\n  bottom: {", "every: -625\n  bottom: {", "surfaces.every",
       "-625"},
  };
  for (const Bad& b : cases) {
    const std::string input = test::write_text_file(d, "bad.yaml", test::replace(good, b.from, b.to));
    const test::CommandResult r =
        test::run_command(DEBRIS_DEM_EXECUTABLE, "-i " + input + " -o " + (d / "out").string());
    EXPECT_EQ(r.exit_code, 2) << b.to << "\n" << r.output;
    EXPECT_NE(r.output.find("'" + b.key + "'"), std::string::npos) << b.key << " not in\n" << r.output;
    EXPECT_NE(r.output.find(b.value), std::string::npos) << b.value << " not in\n" << r.output;
    EXPECT_FALSE(fs::exists(d / "out")) << b.to;
  }
}

}  // namespace
}  // namespace debris
