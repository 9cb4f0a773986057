// The PeriDEM model against the installed package: two square grains of 6 x 6 nodes (0.2 mm apart, bonded
// within a 0.6 mm horizon), one at rest and one flying at 1 m/s, 3 mm apart. Before they meet, the flying
// grain moves as a rigid body: its centre travels v t exactly (to round-off) and its bonds stay intact.
#include <cmath>
#include <iostream>

#include "scenarios/common/peridem/peridem_simulation.hpp"

int main() {
  using namespace debris;
  PdNodes nodes;
  PdGrains grains;
  const double h = 0.2e-3, v = 1.0;
  for (int g = 0; g < 2; ++g) {
    grains.resize(static_cast<std::size_t>(g) + 1);
    grains.kind[g] = static_cast<int>(PdGrainKind::particle);
    grains.material[g] = 0;
    grains.node_begin[g] = static_cast<int>(nodes.size());
    for (int b = 0; b < 6; ++b)
      for (int a = 0; a < 6; ++a) {
        const std::size_t i = nodes.add(static_cast<std::int64_t>(nodes.size()), g, g * 4e-3 + a * h, b * h, 0, h * h);
        nodes.vx[i] = g == 1 ? -v : 0.0;
      }
    grains.node_end[g] = static_cast<int>(nodes.size());
    grains.volume[g] = 36 * h * h;
  }
  PdMaterial m{1200, 0.0216e9, 0.01296e9, 50, 0.6e-3, 2, 0};
  PeridemSettings s;
  s.time_step = 1e-7;
  PeridemSimulation sim(nodes, grains, {m}, {PdContactSettings{}}, s);
  const double x0 = sim.grain_states()[1].centre.x;
  sim.run(1000);  // 0.1 mm of flight, far before the 3 mm gap closes
  const double dx = sim.grain_states()[1].centre.x - x0;
  std::cout << "bonds: " << sim.bonds().entries() / 2 << ", centre moved " << dx << " m (v t = " << -v * 1e-4
            << " m)\n";
  return sim.bonds().entries() > 0 && std::abs(dx + v * 1e-4) < 1e-12 ? 0 : 1;
}
