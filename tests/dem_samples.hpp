#pragma once
// DEM systems that several tests build the same way (one copy, so that a change to the sample reaches
// every test that uses it).
#include <random>

#include "core/lattice.hpp"
#include "scenarios/common/dem/dem_simulation.hpp"

namespace debris::test {

/// A sheared, loaded HCP block (5 x 4 x 2 cells, periodic in x and z) with a frozen base, a rigid top under a
/// load and a free probe group: rebuilds, re-sorts, history carry-over, group sums and global damping all
/// take part. energy: the energy accounting on. wide: every third free particle shrunk to d = 45 (size ratio 2.3), so the neighbour search
/// uses size classes and the default skin follows the mean radius; otherwise a small skin (many rebuilds).
inline DemSimulation sheared_dem_system(PairPass pass = PairPass::automatic, bool wide = false, bool energy = true) {
  LatticeSpec l;
  l.kind = LatticeKind::hcp;
  l.spacing = 100;
  l.diameter = 100;
  l.size_spread = 0.04;
  l.displacement = 1.0;
  l.cells = {5, 4, 2};
  Lattice lat = make_lattice(l);
  Box box(lat.box.lo(), lat.box.hi(), {true, false, true});
  Particles p = lat.particles;
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<double> u(-0.01, 0.01);
  for (std::size_t i = 0; i < p.size(); ++i) p.vx[i] = u(rng), p.vy[i] = u(rng), p.wz[i] = u(rng) / 50;
  Groups g;
  Group top{"top", GroupMotion::force};
  top.external_force = {20.0, -50.0, 0.0};  // a sheared, loaded wall: its rigid velocity is state too
  Group bottom{"bottom", GroupMotion::frozen};
  Group probe{"probe", GroupMotion::free};
  const int gt = g.add(top), gb = g.add(bottom), gp = g.add(probe);
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p.y[i] > box.hi().y - 90) p.group[i] = gt;
    else if (p.y[i] < box.lo().y + 90) p.group[i] = gb;
    else if (p.x[i] < 200) p.group[i] = gp;
    if (wide && p.group[i] < 0 && i % 3 == 0) p.radius[i] = 22.5;
  }
  DemSettings s;
  s.material = table4_material();
  s.material.restitution = 0.9;
  s.time_step_fraction = 0.1;
  s.global_damping = 0.02;
  s.skin = wide ? 0.0 : 0.5;  // small: many rebuilds (on both sides of a checkpoint)
  s.pair_pass = pass;
  s.energy_accounting = energy;
  return DemSimulation(box, p, g, s);
}

}  // namespace debris::test
