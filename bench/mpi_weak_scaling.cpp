// Weak scaling of the distributed contact step, on demand (not in ctest):
//   mpirun -np P build-mpi/bin/debris_mpi_weak_scaling [--per-rank 32000,256000] [--steps 50]
// Each rank holds about N particles of an FCC block P times longer in x (Table 4's material, sizes spread
// 2%, displaced), cut into P slabs (the least-surface grid for that box). One step here is what the
// distributed DEM step will run between rebuilds: integrate, forward() of the halo (x, v, omega), the
// half-list contact pass over owned particles and ghosts in the canonical order. Reports, per rank: owned
// particles, ghosts (and the slab model's count, 2 w L_y L_z n), halo bytes per step against the model's
// 72 B per ghost, particle-steps/s (owned particles x steps / wall time of the steps), the comm share of the
// step, and the cost of a rebuild's halo and canonical order against its list build. Then the same system
// through DemSimulation, the whole distributed step as debris_dem runs it (the rebuild decision of all
// ranks, migration with pair state at rebuilds, exact group and thermo sums; here with a frozen slab and a
// velocity-driven one as groups): particle-steps/s per rank and the comm pass's share.
// Without MPI (a serial build) it runs the P = 1 case.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include "bench/over_ranks.hpp"
#include "core/box.hpp"
#include "core/canonical_order.hpp"
#include "core/comm/communicator.hpp"
#include "core/comm/decomposition.hpp"
#include "core/comm/halo.hpp"
#include "core/comm/migration.hpp"
#include "core/contact_history.hpp"
#include "core/exec.hpp"
#include "core/groups.hpp"
#include "core/io/trajectory_writer.hpp"
#include "core/lattice.hpp"
#include "core/neighbor_list.hpp"
#include "kernels/dem/cohesive_contact_half.hpp"
#include "kernels/dem/cohesive_material.hpp"
#include "kernels/dem/cohesive_pair_table.hpp"
#include "kernels/dem/integrate.hpp"
#include "scenarios/common/dem/dem_simulation.hpp"

namespace {
using namespace debris;
using Clock = std::chrono::steady_clock;
double seconds(Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double>(b - a).count(); }

// About per_rank particles per rank: an FCC block of Table 4's size, `ranks` times longer in x (sizes spread
// 2%, positions displaced: every pair its own constants).
Lattice weak_scaling_block(int ranks, int per_rank) {
  const int c = std::max(3, static_cast<int>(std::lround(std::cbrt(per_rank / 4.0))));
  LatticeSpec spec;
  spec.kind = LatticeKind::fcc;
  spec.spacing = 100;
  spec.diameter = 100;
  spec.size_spread = 0.02;
  spec.displacement = 0.3;
  spec.cells = {ranks * c, c, c};
  spec.seed = 3;
  return make_lattice(spec);
}

void run(int per_rank, int steps) {
  const int ranks = comm::size();
  Lattice lat = weak_scaling_block(ranks, per_rank);
  const Box box(lat.box.lo(), lat.box.hi(), {true, true, true});
  CohesiveMaterial material = table4_material(0.0);
  material.restitution = 0.9;
  const CohesiveCoefficients coef = CohesiveCoefficients::from(material);
  Particles& all = lat.particles;
  all.set_mass_from_density(material.density);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (std::size_t i = 0; i < all.size(); ++i) all.vx[i] = 2e-4 * u(rng), all.vy[i] = 2e-4 * u(rng), all.vz[i] = 2e-4 * u(rng);
  box.wrap(all);
  const double r_max = *std::max_element(all.radius.begin(), all.radius.end());
  const double r_min = *std::min_element(all.radius.begin(), all.radius.end());
  const double max_cutoff = CohesiveCutoff{coef}(r_max, r_max), skin = 0.2 * r_min, w = max_cutoff + skin;
  const double dt = 0.1 * stability_limits(coef, all).dt_c;
  const auto n_total = static_cast<long long>(all.size());
  const auto d = comm::Decomposition::make(box, ranks, comm::rank(), w);
  Particles p = std::move(all);
  comm::keep_owned(d, box, p);
  const std::size_t owned = p.size();

  // A rebuild's distributed part: halo, canonical order; then the list build as a single rank does it.
  comm::barrier();
  const auto t0 = Clock::now();
  comm::Halo halo;
  halo.borders(d, box, w, p, owned);
  const auto t1 = Clock::now();
  const std::vector<int> order = canonical_order(CanonicalGrid::of(box.view(), n_total, w), p);
  p.permute(order);
  halo.permute(order);
  const auto t2 = Clock::now();
  NeighborList list;
  list.build(box.view(), p, CohesiveCutoff{coef}, max_cutoff, skin, NeighborKind::half);
  ContactHistory history;
  history.reset(list);
  CohesivePairTable table;
  table.build(coef, p, list);
  HalfPassScratch scratch;
  scratch.index(list);
  const auto t3 = Clock::now();
  cohesive_contact_pass_half(table, CohesiveOptions{}, box.view(), p, list, history, dt, 0, scratch);

  const Groups::View none{};
  double t_comm = 0, t_compute = 0;
  comm::barrier();
  const auto s0 = Clock::now();
  for (int s = 0; s < steps; ++s) {
    const auto a = Clock::now();
    integrate_semi_implicit_euler(p, none, dt);
    const auto b = Clock::now();
    halo.forward(p);
    const auto e = Clock::now();
    cohesive_contact_pass_half(table, CohesiveOptions{}, box.view(), p, list, history, dt, 1, scratch);
    const auto f = Clock::now();
    t_compute += seconds(a, b) + seconds(e, f);
    t_comm += seconds(b, e);
  }
  comm::barrier();
  const double wall = seconds(s0, Clock::now());

  // The slab model (a rank's two faces, width w, the lattice's number density): ghosts and 72 B each.
  const double density = static_cast<double>(n_total) / box.volume();
  const double model_ghosts = ranks > 1 ? 2.0 * w * box.length(1) * box.length(2) * density : 0.0;
  const Spread ghosts = over_ranks(static_cast<double>(halo.ghosts()));
  const Spread bytes = over_ranks(static_cast<double>(halo.forward_bytes()));
  const Spread rate = over_ranks(static_cast<double>(owned) * steps / wall);
  const Spread comm_share = over_ranks(t_comm / (t_comm + t_compute));
  const Spread halo_time = over_ranks(seconds(t0, t1)), order_time = over_ranks(seconds(t1, t2)),
               list_time = over_ranks(seconds(t2, t3));
  const Spread n_owned = over_ranks(static_cast<double>(owned));
  if (comm::rank() == 0) {
    std::printf("%d rank(s), %s, %lld particles, %d steps, %d thread(s) per rank\n", ranks, d.describe().c_str(), n_total,
                steps, exec::threads());
    std::printf("  owned per rank          %.0f (max %.0f)\n", n_owned.mean, n_owned.max);
    std::printf("  ghosts per rank         %.0f (max %.0f; slab model %.0f)\n", ghosts.mean, ghosts.max, model_ghosts);
    std::printf("  halo bytes per step     %.0f (max %.0f; model %.0f = 72 B x model ghosts)\n", bytes.mean, bytes.max,
                72.0 * model_ghosts);
    std::printf("  particle-steps/s/rank   %.3g M (slowest rank %.3g M)\n", rate.mean / 1e6, rate.min / 1e6);
    std::printf("  comm share of a step    %.1f%% (max %.1f%%)\n", 100 * comm_share.mean, 100 * comm_share.max);
    std::printf("  rebuild: halo %.2f ms, canonical order %.2f ms, list build %.2f ms (max over ranks)\n",
                1e3 * halo_time.max, 1e3 * order_time.max, 1e3 * list_time.max);
  }
}
// The whole step: DemSimulation on the same block, two slabs of it as groups (frozen, and sliding along y).
void run_engine(int per_rank, int steps) {
  const int ranks = comm::size();
  Lattice lat = weak_scaling_block(ranks, per_rank);
  const Box box(lat.box.lo(), lat.box.hi(), {true, true, true});
  DemSettings settings;
  settings.material = table4_material(0.0);
  settings.material.restitution = 0.9;
  Particles& all = lat.particles;
  Groups groups;
  Group floor, lid;
  floor.name = "floor";
  floor.motion = GroupMotion::frozen;
  lid.name = "lid";
  lid.motion = GroupMotion::velocity;
  lid.velocity = {0, 2e-3, 0};
  const int gf = groups.add(floor), gl = groups.add(lid);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double z_lo = box.lo().z, z_hi = box.hi().z;
  for (std::size_t i = 0; i < all.size(); ++i) {
    all.vx[i] = 2e-4 * u(rng), all.vy[i] = 2e-4 * u(rng), all.vz[i] = 2e-4 * u(rng);
    if (all.z[i] < z_lo + 150) all.group[i] = gf;
    if (all.z[i] > z_hi - 150) all.group[i] = gl;
  }
  DemSimulation sim(box, std::move(all), std::move(groups), settings);
  sim.run(10);  // warm
  const PassTimes before = sim.times();
  comm::barrier();
  const auto s0 = Clock::now();
  sim.run(steps);
  comm::barrier();
  const double wall = seconds(s0, Clock::now());
  const PassTimes after = sim.times();
  const double owned = static_cast<double>(sim.particle_count()) / ranks;
  const Spread rate = over_ranks(owned * steps / wall);
  const Spread comm_share = over_ranks((after.comm - before.comm) / wall);
  if (comm::rank() == 0)
    std::printf("  DemSimulation step      %.3g M particle-steps/s/rank (slowest %.3g M), comm %.1f%% (max %.1f%%), "
                "%ld rebuilds\n",
                rate.mean / 1e6, rate.min / 1e6, 100 * comm_share.mean, 100 * comm_share.max,
                after.rebuilds - before.rebuilds);

  // Output: a trajectory frame and a checkpoint, each rank writing its own rows into the one file
  // (parallel HDF5), against rank 0 writing the system gathered from the ranks (with_whole_system).
  namespace fs = std::filesystem;
  const std::string dir = comm::first_message(
      comm::rank() == 0 ? (fs::temp_directory_path() / ("debris_weak_output_" + std::to_string(::getpid()))).string() : "");
  if (comm::rank() == 0) fs::create_directories(dir);
  comm::barrier();
  auto timed = [&](const std::function<void()>& write) {
    comm::barrier();
    const auto t0 = Clock::now();
    write();
    comm::barrier();
    return seconds(t0, Clock::now());
  };
  const double frame_ranks = timed([&] {
    TrajectoryWriter out(dir, "ranks", {"floor", "lid"}, true);
    out.write_frame(sim.step_count(), sim.time(), sim.box(), sim.particles(), sim.frame_share());
  });
  const double frame_gathered = timed([&] {
    sim.with_whole_system([&](const DemSimulation& whole) {
      TrajectoryWriter out(dir, "gathered", {"floor", "lid"});
      out.write_frame(whole.step_count(), whole.time(), whole.box(), whole.particles());
    });
  });
  const double checkpoint_ranks = timed([&] { sim.write_checkpoint(dir + "/ranks.h5", ""); });
  const double checkpoint_gathered = timed([&] {
    sim.with_whole_system([&](const DemSimulation& whole) { whole.write_checkpoint(dir + "/gathered.h5", ""); });
  });
  if (comm::rank() == 0) {
    const double mb = static_cast<double>(fs::file_size(dir + "/ranks.h5")) / 1e6;
    std::printf("  output: frame %.3f s (rank 0 gathering: %.3f s), checkpoint %.3f s = %.0f MB (gathering: %.3f s)\n",
                frame_ranks, frame_gathered, checkpoint_ranks, mb, checkpoint_gathered);
    fs::remove_all(dir);
  }
}
}  // namespace

int main(int argc, char** argv) {
  debris::comm::Session mpi(&argc, &argv);
  std::vector<int> sizes{32000, 256000};
  int steps = 50;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string key = argv[i];
    if (key == "--per-rank") {
      sizes.clear();
      std::stringstream ss(argv[i + 1]);
      for (std::string item; std::getline(ss, item, ',');) sizes.push_back(std::atoi(item.c_str()));
    } else if (key == "--steps") {
      steps = std::atoi(argv[i + 1]);
    }
  }
  for (const int n : sizes) {
    run(n, steps);
    run_engine(n, steps);
  }
  return 0;
}
