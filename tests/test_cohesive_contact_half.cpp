// The host half-list contact pass (kernels/dem/cohesive_contact_half.hpp) against the full-list pass, over
// hundreds of sheared steps with damping, sliding and breaking, with size classes, and through the virial
// stress that reads the history each pass keeps. Both call the one pair law (cohesive_pair_force); they
// differ in what they sum and in what order.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <random>
#include <vector>

#include "core/contact_history.hpp"
#include "core/exec.hpp"
#include "core/lattice.hpp"
#include "core/neighbor_list.hpp"
#include "kernels/dem/cohesive_contact.hpp"
#include "kernels/dem/cohesive_contact_half.hpp"
#include "scenarios/common/dem/dem_simulation.hpp"
#include "tests/dem_sheared_sample.hpp"

namespace debris {
namespace {

using test::fcc_spec;
using test::run_sheared;
using test::shear_walls;
using test::Snapshot;
using test::table4;

// The host half-list pass and the full-list reference pass are the same physics: forces, torques and
// velocities agree to round-off after hundreds of sheared steps with damping, sliding and breaking.
TEST(DemEngine, HalfListPassEqualsFullListPass) {
  Lattice lat = make_lattice(fcc_spec({4, 3, 3}, 0.04, 1.0));
  Box box(lat.box.lo(), lat.box.hi(), {true, false, true});
  const Snapshot full = run_sheared(lat.particles, box, 400, 2, PairPass::full);
  const Snapshot half = run_sheared(lat.particles, box, 400, 2, PairPass::half);
  double fmax = 0, tmax = 0, vmax = 0;
  for (const auto& [id, v] : full.by_id) {
    fmax = std::max({fmax, std::abs(v[0]), std::abs(v[1]), std::abs(v[2])});
    tmax = std::max({tmax, std::abs(v[3]), std::abs(v[4]), std::abs(v[5])});
    vmax = std::max({vmax, std::abs(v[6]), std::abs(v[7]), std::abs(v[8])});
  }
  ASSERT_GT(tmax, 0.0);
  for (const auto& [id, vf] : full.by_id) {
    const auto& vh = half.by_id.at(id);
    for (int k = 0; k < 3; ++k) ASSERT_NEAR(vf[k], vh[k], 1e-9 * fmax) << "force, id " << id;
    for (int k = 3; k < 6; ++k) ASSERT_NEAR(vf[k], vh[k], 1e-9 * tmax) << "torque, id " << id;
    for (int k = 6; k < 9; ++k) ASSERT_NEAR(vf[k], vh[k], 1e-9 * vmax) << "velocity, id " << id;
  }
}

// The same two checks on a sample wide enough for size classes in the neighbour search (every third
// particle between the walls shrunk to d = 45: size ratio 2.3): bit for bit on 1 and 2 threads, and the
// half-list pass equal to the full-list pass.
TEST(DemEngine, SizeClassesSameOnOneAndTwoThreadsAndHalfEqualsFull) {
  Lattice lat = make_lattice(fcc_spec({4, 3, 3}, 0.04, 1.0));
  Box box(lat.box.lo(), lat.box.hi(), {true, false, true});
  Particles& p = lat.particles;
  for (std::size_t i = 0; i < p.size(); i += 3)
    if (p.y[i] > box.lo().y + 80 && p.y[i] < box.hi().y - 80) p.radius[i] = 22.5;
  const Snapshot one = run_sheared(p, box, 400, 1, PairPass::half);
  const Snapshot two = run_sheared(p, box, 400, 2, PairPass::half);
  const Snapshot full = run_sheared(p, box, 400, 2, PairPass::full);
  double vmax = 0;
  for (const auto& [id, v] : full.by_id) vmax = std::max({vmax, std::abs(v[6]), std::abs(v[7]), std::abs(v[8])});
  ASSERT_GT(vmax, 0.0);
  for (const auto& [id, va] : one.by_id) {
    for (int k = 0; k < 9; ++k) ASSERT_EQ(va[k], two.by_id.at(id)[k]) << "id " << id << " component " << k;
    for (int k = 6; k < 9; ++k) ASSERT_NEAR(va[k], full.by_id.at(id)[k], 1e-9 * vmax) << "velocity, id " << id;
  }
}

// The virial stress reads the history as the pass in use keeps it: from a half list (each pair once, both
// ends credited) it equals the one from a full list, over all particles and over a selected slab.
TEST(DemEngine, VirialStressIsTheSameFromHalfAndFullLists) {
  Lattice lat = make_lattice(fcc_spec({4, 3, 3}, 0.04, 1.0));
  Box box(lat.box.lo(), lat.box.hi(), {true, false, true});
  exec::set_threads(2);
  std::array<StressTensor, 2> all, slab;
  const PairPass passes[2] = {PairPass::full, PairPass::half};
  for (int k = 0; k < 2; ++k) {
    Particles p = lat.particles;
    const Groups g = shear_walls(p, box, {0.02, 0, 0});
    DemSettings s;
    s.material = table4(0.9);
    s.global_damping = 0.05;
    s.pair_pass = passes[k];
    DemSimulation sim(box, std::move(p), g, s);
    sim.run(400);
    ASSERT_EQ(sim.pair_pass(), passes[k]);
    const Particles& q = sim.particles();
    std::vector<int> mid(q.size());
    const double yc = 0.5 * (box.lo().y + box.hi().y);
    for (std::size_t i = 0; i < q.size(); ++i) mid[i] = std::abs(q.y[i] - yc) < 100 ? 1 : 0;
    all[k] = sim.virial_stress(nullptr, 1.0);
    slab[k] = sim.virial_stress(mid.data(), 1.0);
    // Fixed-order sums: the same bits on one thread (the amorphous relaxation feeds this into the box).
    exec::set_threads(1);
    const StressTensor one = sim.virial_stress(mid.data(), 1.0);
    exec::set_threads(2);
    EXPECT_EQ(one.xx, slab[k].xx);
    EXPECT_EQ(one.xy, slab[k].xy);
    EXPECT_EQ(one.yz, slab[k].yz);
  }
  for (const auto* t : {&all, &slab}) {
    const StressTensor &f = (*t)[0], &h = (*t)[1];
    const double scale = std::max({std::abs(f.xx), std::abs(f.yy), std::abs(f.zz), std::abs(f.xy)});
    ASSERT_GT(std::abs(f.xy), 0.0);  // the shear is really there
    for (auto m : {&StressTensor::xx, &StressTensor::yy, &StressTensor::zz, &StressTensor::xy, &StressTensor::xz,
                   &StressTensor::yz})
      EXPECT_NEAR(f.*m, h.*m, 1e-9 * scale);
  }
}

// The pass on its own, on 1, 2, 3, 5 and 8 threads, by parts and with every share filed, with the particles
// stored in lattice order (each part's tail a layer) and shuffled (partners anywhere in the rows: tails that
// reach several parts ahead and hold most pairs): the same forces and torques bit for bit over five passes in
// a row (the springs carried from one to the next); and equal to the full-list pass.
TEST(DemEngine, HalfPassSameBitsOnAnyThreadCountAndParticleOrder) {
  if (exec::offload_build())
    GTEST_SKIP() << "the half pass on host arrays, called directly (the engine's own tests cover offload builds)";
  Lattice lat = make_lattice(fcc_spec({6, 5, 5}, 0.04, 1.0));
  const Box box(lat.box.lo(), lat.box.hi(), {true, false, true});
  const CohesiveMaterial material = table4(0.9);
  const CohesiveCoefficients coef = CohesiveCoefficients::from(material);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-0.02, 0.02);
  Particles base = lat.particles;
  base.set_mass_from_density(material.density);
  for (std::size_t i = 0; i < base.size(); ++i) base.vx[i] = u(rng), base.vy[i] = u(rng), base.wz[i] = u(rng);
  const double dt = 0.1 * stability_limits(coef, base).dt_c;
  const double r_max = *std::max_element(base.radius.begin(), base.radius.end());
  const double max_cutoff = CohesiveCutoff{coef}(r_max, r_max), skin = 0.1 * max_cutoff;
  std::vector<int> shuffled(base.size());
  std::iota(shuffled.begin(), shuffled.end(), 0);
  std::shuffle(shuffled.begin(), shuffled.end(), rng);
  const int saved = exec::threads();
  for (const bool shuffle : {false, true}) {
    Particles p0 = base;
    if (shuffle) p0.permute(shuffled);
    // Five passes (the springs carried from one to the next), on `threads` threads.
    auto run = [&](int threads, PairPass pass, HalfPassPath path = HalfPassPath::automatic) {
      exec::set_threads(threads);
      Particles p = p0;
      NeighborList list;
      list.build(box.view(), p, CohesiveCutoff{coef}, max_cutoff, skin,
                 pass == PairPass::half ? NeighborKind::half : NeighborKind::full);
      ContactHistory history;
      history.reset(list);
      CohesivePairTable table;
      table.build(coef, p, list);
      HalfPassScratch scratch;
      scratch.path = path;
      scratch.index(list);
      for (int step = 0; step < 5; ++step) {
        if (pass == PairPass::half) {
          cohesive_contact_pass_half(table, CohesiveOptions{}, box.view(), p, list, history, dt, 1, scratch);
        } else {
          zero_forces(p);
          cohesive_contact_pass(coef, CohesiveOptions{}, box.view(), p, list, history, dt, 1);
        }
        for (std::size_t i = 0; i < p.size(); ++i) p.x[i] += dt * p.vx[i], p.y[i] += dt * p.vy[i];  // the springs load
      }
      return p;
    };
    const Particles one = run(1, PairPass::half);
    const Particles full = run(1, PairPass::full);
    double fmax = 0;
    for (std::size_t i = 0; i < one.size(); ++i) fmax = std::max({fmax, std::abs(one.fx[i]), std::abs(one.fy[i])});
    ASSERT_GT(fmax, 0.0);
    for (std::size_t i = 0; i < one.size(); ++i) {
      ASSERT_NEAR(one.fx[i], full.fx[i], 1e-9 * fmax) << "i " << i;
      ASSERT_NEAR(one.fy[i], full.fy[i], 1e-9 * fmax) << "i " << i;
      ASSERT_NEAR(one.fz[i], full.fz[i], 1e-9 * fmax) << "i " << i;
    }
    for (const int threads : {2, 3, 5, 8})
      for (const HalfPassPath path : {HalfPassPath::parts, HalfPassPath::filed}) {
        const Particles many = run(threads, PairPass::half, path);
        for (std::size_t i = 0; i < one.size(); ++i) {
          for (const auto c :
               {&Particles::fx, &Particles::fy, &Particles::fz, &Particles::tx, &Particles::ty, &Particles::tz})
            ASSERT_EQ((one.*c)[i], (many.*c)[i]) << threads << " threads, shuffled " << shuffle << ", path "
                                                 << static_cast<int>(path) << ", particle " << i;
        }
      }
  }
  exec::set_threads(saved);
}

}  // namespace
}  // namespace debris
