// Weak scaling of the PeriDEM step cut among ranks (shared/design/scale-mpi.md, section 5), on demand (not in
// ctest):
//   mpirun -np P build-mpi/bin/debris_mpi_pd_weak_scaling [--steps 200] [--input FILE] [--gap MM]
// The 502-grain deck (scenarios/peridem/compressive_n500.yaml, or FILE) tiled P x 1 (bench/pd_tiles.hpp:
// each tile its own grains, container and lid, --gap mm from the next, 1 by default: beyond contact, so
// no ghosts; 0.05 puts the neighbouring containers within the contact radius and the grains near them
// within the ghost width), one tile per rank: the decomposition cuts the box along x between the tiles. After 100 warm-up steps it times --steps steps of
// PeridemSimulation::step() on every rank together and reports, per rank (min / mean / max): owned and
// ghost nodes, node-steps/s (owned nodes x steps / wall time), the comm share of the step (ghost exchanges,
// the rebuild decision, migration and ghost layer at list builds) and the halo bytes sent per step; then the
// whole step's node-steps/s summed over the ranks. Without MPI (a serial build) it runs the P = 1 case.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "bench/over_ranks.hpp"
#include "bench/pd_tiles.hpp"
#include "core/comm/communicator.hpp"
#include "core/exec.hpp"
#include "scenarios/common/peridem/peridem_input.hpp"
#include "scenarios/common/peridem/peridem_simulation.hpp"

namespace {
using namespace debris;
using Clock = std::chrono::steady_clock;

void print(const char* what, Spread s, const char* unit) {
  if (comm::rank() == 0) std::printf("  %-34s %12.4g %12.4g %12.4g %s\n", what, s.min, s.mean, s.max, unit);
}

}  // namespace

int main(int argc, char** argv) {
  comm::Session session(&argc, &argv);
  long steps = 200;
  std::string input = std::string(DEBRIS_SOURCE_DIR) + "/scenarios/peridem/compressive_n500.yaml";
  double gap_mm = 1.0;
  for (int a = 1; a + 1 < argc; a += 2) {
    const std::string key = argv[a];
    if (key == "--steps") steps = std::atol(argv[a + 1]);
    else if (key == "--input") input = argv[a + 1];
    else if (key == "--gap") gap_mm = std::atof(argv[a + 1]);
    else {
      if (comm::rank() == 0) std::fprintf(stderr, "unknown option %s (--steps N, --input FILE, --gap MM)\n", key.c_str());
      return 2;
    }
  }
  exec::set_threads(1);
  const int ranks = comm::size();
  PeridemRunConfig cfg = read_peridem_input(input);
  tile_pd_system(cfg, ranks, 1, gap_mm * 1e-3);
  PeridemSimulation sim(std::move(cfg.nodes), std::move(cfg.grains), cfg.materials, cfg.contact, cfg.settings);
  const std::size_t total_nodes = sim.node_count();
  sim.distribute();
  sim.run(100);
  const PeridemPassTimes before = sim.times();
  const long rebuilds_before = sim.contact_rebuilds();
  comm::barrier();
  const auto t0 = Clock::now();
  sim.run(steps);
  comm::barrier();
  const double wall = std::chrono::duration<double>(Clock::now() - t0).count();
  const PeridemPassTimes& after = sim.times();

  std::size_t owned = 0;
  for (const unsigned char o : sim.owned_nodes()) owned += o;
  const double comm_seconds = after.comm - before.comm;
  if (comm::rank() == 0) {
    std::printf("PeriDEM weak scaling: %d rank(s) (%s), one tile of %s each, %g mm apart, %zu nodes in all; %ld "
                "steps, %ld list builds\n",
                ranks, sim.decomposition().describe().c_str(), input.c_str(), gap_mm, total_nodes, steps,
                sim.contact_rebuilds() - rebuilds_before);
    std::printf("  %-34s %12s %12s %12s\n", "per rank", "min", "mean", "max");
  }
  print("owned nodes", over_ranks(static_cast<double>(owned)), "");
  print("ghost nodes", over_ranks(static_cast<double>(sim.ghost_nodes())), "");
  print("halo bytes sent per step", over_ranks(static_cast<double>(sim.halo_bytes_per_step())), "B");
  print("node-steps/s", over_ranks(static_cast<double>(owned) * steps / wall), "");
  print("comm share of the step", over_ranks(comm_seconds / wall), "");
  if (comm::rank() == 0)
    std::printf("  whole run: %.4g node-steps/s over %d rank(s), %.3f s for %ld steps\n",
                static_cast<double>(total_nodes) * steps / wall, ranks, wall, steps);
  return 0;
}
