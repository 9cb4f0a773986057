// Ten lines against the installed package: two touching spheres of Table 4's material, one pulled away at
// constant speed until the cohesive bond of eq 3 lets go; prints the pair count before and after.
#include <iostream>

#include "scenarios/common/dem/dem_simulation.hpp"

int main() {
  using namespace debris;
  Particles p;
  p.add(0, 1, 0, 0, 0, 50);
  p.add(1, 1, 100, 0, 0, 50);
  Groups g;
  Group puller{"puller", GroupMotion::velocity};
  puller.velocity = {1.0, 0, 0};
  p.group[0] = g.add(Group{"base", GroupMotion::frozen});
  p.group[1] = g.add(puller);
  DemSettings s;
  s.material = table4_material(0.0);
  s.time_step = 1.0;
  DemSimulation sim(Box({-500, -500, -500}, {500, 500, 500}, {false, false, false}), p, g, s);
  const long before = sim.diagnostics().interacting_pairs;
  sim.run(200);  // 200 units apart: far beyond delta_f (30 for d = 100 < d_c)
  std::cout << "interacting pairs: " << before << " then " << sim.diagnostics().interacting_pairs << "\n";
  return before == 1 && sim.diagnostics().interacting_pairs == 0 ? 0 : 1;
}
