// The cohesive contact pass on P ranks gives every owned particle the serial run's force bits (the S1 test
// "step-0 forces" of shared/design/scale-mpi.md, and 40 steps after it), through the pieces the distributed
// DEM step will use: owned particles and the halo, stored together in the canonical order (global cell,
// then id), a half list over them, the unchanged half-list pass, and forward() of x, v and omega between
// steps. Each rank also runs the whole system serially as the reference, and compares bit for bit.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "core/box.hpp"
#include "core/canonical_order.hpp"
#include "core/cell_list.hpp"
#include "core/comm/communicator.hpp"
#include "core/comm/decomposition.hpp"
#include "core/comm/halo.hpp"
#include "core/comm/migration.hpp"
#include "core/contact_history.hpp"
#include "core/exec.hpp"
#include "core/groups.hpp"
#include "core/lattice.hpp"
#include "core/neighbor_list.hpp"
#include "core/particles.hpp"
#include "tests/mpi/cohesive_block.hpp"
#include "tests/mpi/rank_grids.hpp"
#include "kernels/dem/cohesive_contact_half.hpp"
#include "kernels/dem/cohesive_material.hpp"
#include "kernels/dem/cohesive_pair_table.hpp"
#include "kernels/dem/integrate.hpp"

namespace debris::comm {
namespace {

using test::grids_for;

// One system's pass state: a half list over the particles as stored, its history, pair table and scratch.
struct Pass {
  NeighborList list;
  ContactHistory history;
  CohesivePairTable table;
  HalfPassScratch scratch;
  void build(const Box& box, const CohesiveCoefficients& coef, Particles& p, double max_cutoff, double skin) {
    list.build(box.view(), p, CohesiveCutoff{coef}, max_cutoff, skin, NeighborKind::half);
    history.reset(list);
    table.build(coef, p, list);
    scratch.index(list);
  }
  void forces(const Box& box, Particles& p, double dt, int update) {
    cohesive_contact_pass_half(table, CohesiveOptions{}, box.view(), p, list, history, dt, update, scratch);
  }
};


TEST(DistributedForces, OwnedParticlesGetTheSerialBitsAtEveryStep) {
  // The host pass on host arrays: the distributed step on a device (its own packing, the full list) is the
  // sketch's step S2.
  if (exec::offload_build()) GTEST_SKIP() << "host-side halo and half-list pass; offload builds come with MPI step S2";
  // 6,912 particles: 4 subdomains of at least twice the ghost width on x.
  const Lattice lat = test::cohesive_block({12, 12, 12}, 3);
  CohesiveMaterial material = table4_material(0.0);
  material.restitution = 0.9;
  const CohesiveCoefficients coef = CohesiveCoefficients::from(material);
  for (const auto per : {std::array<bool, 3>{true, true, true}, std::array<bool, 3>{true, false, true}}) {
    const Box box(lat.box.lo(), lat.box.hi(), per);
    Particles all = lat.particles;
    all.set_mass_from_density(material.density);
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (std::size_t i = 0; i < all.size(); ++i) {  // a thermal kick: pairs in tension and compression
      all.vx[i] = 2e-4 * u(rng), all.vy[i] = 2e-4 * u(rng), all.vz[i] = 2e-4 * u(rng);
      all.wx[i] = 1e-6 * u(rng), all.wy[i] = 1e-6 * u(rng), all.wz[i] = 1e-6 * u(rng);
    }
    box.wrap(all);
    const double r_max = *std::max_element(all.radius.begin(), all.radius.end());
    const double r_min = *std::min_element(all.radius.begin(), all.radius.end());
    const double max_cutoff = CohesiveCutoff{coef}(r_max, r_max), skin = 0.2 * r_min, w = max_cutoff + skin;
    const double dt = 0.1 * stability_limits(coef, all).dt_c;
    // One grid for every rank: the whole box, the whole system's count (core/canonical_order).
    const CanonicalGrid global = CanonicalGrid::of(box.view(), static_cast<long long>(all.size()), w);
    const int steps = 40;

    // The serial run, stored canonically: forces at step 0 and after every step.
    Particles serial = all;
    serial.permute(canonical_order(global, serial));
    Pass sp;
    sp.build(box, coef, serial, max_cutoff, skin);
    sp.forces(box, serial, dt, 0);
    std::vector<std::map<std::int64_t, std::array<double, 9>>> want(steps + 1);
    const Groups::View none{};
    for (int s = 0; s <= steps; ++s) {
      if (s > 0) {
        integrate_semi_implicit_euler(serial, none, dt);
        sp.forces(box, serial, dt, 1);
      }
      for (std::size_t i = 0; i < serial.size(); ++i)
        want[static_cast<std::size_t>(s)][serial.id[i]] = {serial.x[i],  serial.y[i],  serial.z[i],
                                                            serial.vx[i], serial.vy[i], serial.vz[i],
                                                            serial.fx[i], serial.fy[i], serial.tz[i]};
    }
    double drift = 0;
    for (std::size_t i = 0; i < serial.size(); ++i) {
      const auto& a = want[0].at(serial.id[i]);
      drift = std::max(drift, std::hypot(serial.x[i] - a[0], serial.y[i] - a[1], serial.z[i] - a[2]));
    }
    ASSERT_FALSE(sp.list.needs_rebuild(box.view(), serial))
        << "the test must stay inside one list: drift " << drift << ", skin " << skin << ", dt " << dt << ", w " << w;

    for (const auto g : grids_for(size())) {
      const auto d = Decomposition::make(box, size(), rank(), w, g);
      const std::string where = d.describe() + ", periodic y " + std::to_string(per[1]) + ", rank " + std::to_string(rank());
      Particles p = all;
      keep_owned(d, box, p);
      const std::size_t owned = p.size();
      std::vector<char> is_owned;
      Halo halo;
      halo.borders(d, box, w, p, owned);
      // Owned particles and ghosts together in the canonical order; the halo follows.
      const std::vector<int> order = canonical_order(global, p);
      p.permute(order);
      halo.permute(order);
      is_owned.assign(p.size(), 0);
      for (std::size_t i = 0; i < p.size(); ++i) is_owned[i] = order[i] < static_cast<int>(owned);
      Pass dp;
      dp.build(box, coef, p, max_cutoff, skin);
      dp.forces(box, p, dt, 0);
      long mismatches = 0, compared = 0;
      for (int s = 0; s <= steps; ++s) {
        if (s > 0) {
          integrate_semi_implicit_euler(p, none, dt);  // ghosts too: forward() overwrites them next
          halo.forward(p);
          dp.forces(box, p, dt, 1);
        }
        for (std::size_t i = 0; i < p.size(); ++i) {
          if (!is_owned[i]) continue;
          const auto& ref = want[static_cast<std::size_t>(s)].at(p.id[i]);
          const std::array<double, 9> got = {p.x[i], p.y[i], p.z[i], p.vx[i], p.vy[i], p.vz[i], p.fx[i], p.fy[i], p.tz[i]};
          ++compared;
          if (got != ref && mismatches++ < 3)
            ADD_FAILURE() << "particle " << p.id[i] << " differs from the serial run at step " << s << ", " << where;
        }
      }
      EXPECT_EQ(mismatches, 0) << where;
      std::int64_t total = compared;
      allreduce_sum(&total, 1);
      EXPECT_EQ(total, static_cast<std::int64_t>(all.size()) * (steps + 1)) << where;
    }
  }
}

}  // namespace
}  // namespace debris::comm
