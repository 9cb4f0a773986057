#pragma once
// A sheared periodic FCC block for the DEM engine tests: a frozen bottom wall, a top wall driven along x, the
// Table 4 material with eta = 0.9, run with either pair pass on a chosen thread count.
#include <array>
#include <cstdint>
#include <map>

#include "core/box.hpp"
#include "core/exec.hpp"
#include "core/groups.hpp"
#include "core/lattice.hpp"
#include "core/particles.hpp"
#include "scenarios/common/dem/dem_simulation.hpp"

namespace debris::test {

/// Table 4's material with restitution eta and scaling exponent s.
inline CohesiveMaterial table4(double eta = 0.95, double s = 0.0) {
  CohesiveMaterial m = table4_material(s);
  m.restitution = eta;
  return m;
}

// An FCC lattice of d = 100 at spacing 100 (touching), optionally with a size spread and random displacements.
inline LatticeSpec fcc_spec(std::array<int, 3> cells, double spread = 0.0, double disp = 0.0) {
  LatticeSpec l;
  l.kind = LatticeKind::fcc;
  l.spacing = 100;
  l.diameter = 100;
  l.size_spread = spread;
  l.displacement = disp;
  l.cells = cells;
  l.seed = 3;
  return l;
}

// A frozen bottom wall and a top wall driven at `velocity`, each 80 thick, on a sample spanning the box in y.
inline Groups shear_walls(Particles& p, const Box& box, Vec3 velocity) {
  Groups g;
  Group top{"top", GroupMotion::velocity};
  top.velocity = velocity;
  const int gt = g.add(top), gb = g.add(Group{"bottom", GroupMotion::frozen});
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p.y[i] > box.hi().y - 80) p.group[i] = gt;
    if (p.y[i] < box.lo().y + 80) p.group[i] = gb;
  }
  return g;
}

// Runs a sheared periodic FCC sample for `steps` and returns forces, torques and velocities by id.
struct Snapshot {
  std::map<std::int64_t, std::array<double, 9>> by_id;
};
// threads = 0: the count changes every few steps (1, then 2, ...), as the thread tuner may change it.
inline Snapshot run_sheared(Particles p, Box box, int steps, int threads, PairPass pass = PairPass::automatic) {
  exec::set_threads(threads > 0 ? threads : 1);
  const Groups g = shear_walls(p, box, {0.02, 0, 0});
  DemSettings s;
  s.material = table4(0.9);
  s.time_step_fraction = 0.1;
  s.global_damping = 0.05;
  s.pair_pass = pass;
  DemSimulation sim(box, std::move(p), g, s);
  if (threads > 0) {
    sim.run(steps);
  } else {
    for (int k = 0; k < steps; ++k) {
      exec::set_threads(1 + (k / 7) % 2);
      sim.step();
    }
  }
  Snapshot snap;
  const Particles& q = sim.particles();
  for (std::size_t i = 0; i < q.size(); ++i)
    snap.by_id[q.id[i]] = {q.fx[i], q.fy[i], q.fz[i], q.tx[i], q.ty[i], q.tz[i], q.vx[i], q.vy[i], q.vz[i]};
  exec::set_threads(2);
  return snap;
}

}  // namespace debris::test
