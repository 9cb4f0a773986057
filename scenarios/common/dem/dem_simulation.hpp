#pragma once
// The cohesive DEM step loop, assembled once from the passes of kernels/ (shared/DESIGN.md):
//
//   kick rigid groups -> integrate (eq 1) -> neighbours if needed (wrap, sort by cell, rebuild, carry the
//   contact history) -> zero forces -> cohesive contact (eqs 2-5) -> group reactions -> global damping
//
// Forces at step n use x_n and v_n, so the semi-implicit Euler of eq 1 is v_{n+1} = v_n + F_n/m dt,
// x_{n+1} = x_n + v_{n+1} dt.
//
// Device residency (offload builds; none of it exists in host builds): particles, neighbour list, contact
// history, group views and pair tables live on the device from setup() to destruction. The host copies are
// refreshed only where the host reads them: the accessors particles(), neighbors() and history() bring
// back what a step changed (to_host), once per change; the non-const particles() also marks the host copy
// as edited, so the next step, rebuild or force evaluation sends it to the device first (to_device).
// Checkpoints, health-check messages and summary() go through the same two points.
//
// Cut among ranks (core/comm, shared/design/scale-mpi.md; host builds): when the job has several MPI ranks,
// each rank reads the whole input, checks it and sets up the global limits (dt, skin, cutoff) exactly as one
// process would, then keeps the particles it owns. It stores them together with ghosts (copies of the
// neighbouring ranks' particles within max cutoff + skin) in the canonical order (core/canonical_order),
// so every per-particle sum of the contact pass adds the serial run's terms in the serial run's order, and
// the global sums (group reactions, thermo) are exact (core/block_sums' SumScope): the same bits as one
// process on any rank count. The step gains a comm pass: forward() of the ghosts' x, v, omega after the
// drift, or at a rebuild (decided by all ranks together) migration of owned particles with their pair
// history and a new ghost layer.
#include <array>
#include <chrono>
#include <functional>
#include <string>

#include "core/box.hpp"
#include "core/canonical_order.hpp"
#include "core/comm/decomposition.hpp"
#include "core/comm/halo.hpp"
#include "core/contact_history.hpp"
#include "core/exec.hpp"
#include "core/cell_list.hpp"
#include "core/groups.hpp"
#include "core/io/trajectory_writer.hpp"
#include "core/neighbor_list.hpp"
#include "core/particles.hpp"
#include "kernels/dem/cohesive_contact.hpp"
#include "kernels/dem/cohesive_contact_half.hpp"
#include "kernels/dem/cohesive_pair_table.hpp"
#include "kernels/dem/cohesive_material.hpp"
#include "kernels/dem/energy_accounting.hpp"
#include "kernels/dem/integrate.hpp"
#include "kernels/dem/virial_stress.hpp"

namespace debris {

namespace h5 {
class File;
}

/// Which contact pass runs: the half-list host pass (each pair once, vectorised), or the
/// full-list pass (each pair from both ends, no scatter: the GPU path and the reference).
enum class PairPass { automatic, full, half };

struct DemSettings {
  CohesiveMaterial material;
  CohesiveOptions options;
  // Time step: an absolute value (> 0) or, when time_step is 0, a fraction of the critical one (eq 6).
  double time_step = 0.0;
  double time_step_fraction = 0.1;
  bool allow_unstable_time_step = false;  // the user insists on a step above the critical one
  double global_damping = 0.0;            // fraction of the critical damping c_c of eq 21
  double skin = 0.0;                      // Verlet skin; 0 = 0.2 r_min, or 0.25 r_mean if r_max >= 2 r_min
  bool sort_by_cell = true;               // re-sort particles in memory at each rebuild (ids are kept)
  int size_classes = SizeClasses::kMax;   // neighbour search: at most this many size classes (1: one grid)
  bool masses_from_density = true;        // set m = rho 4/3 pi r^3 at set-up (false: keep the given masses)
  PairPass pair_pass = PairPass::automatic;  // automatic: half on host builds, full in offload builds
  // A job of several MPI ranks cuts the box among them, on this grid of Px x Py x Pz subdomains (0s: the
  // grid with the least cut surface). distribute = false runs the whole system on every rank instead
  // (each alone: a reference for the distributed run).
  bool distribute = true;
  std::array<int, 3> rank_grid{0, 0, 0};
  // The energy accounting (kernels/dem/energy_accounting.hpp): the per-particle columns and the balance.
  // debris_dem turns it on (`output.energy`, true by default); the patch tests, calibration and other
  // engines built in code run without it unless they ask.
  bool energy_accounting = false;
};

/// How a restart on several MPI ranks cuts the system (DemSettings::distribute and rank_grid, which a
/// checkpoint does not keep: the restart decides).
struct RestartRanks {
  bool distribute = true;
  std::array<int, 3> rank_grid{0, 0, 0};
};

/// Accumulated wall time per pass.
struct PassTimes {
  double neighbours = 0, contact = 0, integration = 0, other = 0;
  double comm = 0;    // runs cut among ranks: forward(), migration, the halo at rebuilds, global decisions
  long rebuilds = 0;
  long migrated = 0;  // particles this rank sent to another at rebuilds
};

class DemSimulation {
 public:
  DemSimulation(Box box, Particles particles, Groups groups, DemSettings settings);

  /// Validates particles and time step (InputError on bad input), builds the neighbour list and
  /// evaluates the forces at step 0. Called by the constructor.
  void setup();

  void step();
  void run(long steps);

  // State.
  const Box& box() const { return box_; }
  Box& box() { return box_; }
  /// The number of particles of the whole system, without a transfer (the progress line asks every step).
  std::size_t particle_count() const { return distributed_ ? static_cast<std::size_t>(n_total_) : p_.size(); }
  /// The host copy, current (offload builds: copied back from the device if a step changed it). Distributed
  /// runs: this rank's owned particles and ghosts, in the canonical order (owned_mask() tells them apart).
  const Particles& particles() const {
    particles_to_host();
    return p_;
  }
  /// Positions and velocities may be changed between steps; a change of radius or mass reaches the contact
  /// pass at the next neighbour rebuild or recompute_forces() (the pass keeps per-pair constants).
  /// Offload builds: the host copy is brought up to date, and sent back to the device before the next
  /// kernel (any call counts as an edit).
  Particles& particles() {
    particles_to_host();
    if constexpr (exec::offload_build()) host_edited_ = true;
    return p_;
  }
  Groups& groups() { return groups_; }
  const Groups& groups() const { return groups_; }
  const NeighborList& neighbors() const {
    pairs_to_host();
    return list_;
  }
  const ContactHistory& history() const {
    pairs_to_host();
    return history_;
  }
  const DemSettings& settings() const { return settings_; }
  const CohesiveCoefficients& coefficients() const { return coef_; }
  long step_count() const { return step_; }
  double time() const { return time_; }
  double dt() const { return dt_; }
  const StabilityLimits& limits() const { return limits_; }
  double damping_coefficient() const { return damping_; }
  double skin() const { return skin_; }
  double max_cutoff() const { return max_cutoff_; }
  const PassTimes& times() const { return times_; }
  /// Counts the changes of storage order (a re-sort by cell at a rebuild, reorder()): an index into the
  /// columns means the same particle only while this stays the same (the Python module's views check it).
  long layout_generation() const { return layout_generation_; }

  // Runs cut among ranks.
  /// True when the run is cut among ranks (several MPI ranks and settings.distribute).
  bool distributed() const { return distributed_; }
  const comm::Decomposition& decomposition() const { return decomposition_; }
  const comm::Halo& halo() const { return halo_; }
  /// Particles that crossed a cut since the set-up (each sent from one rank to another at a rebuild), summed
  /// over the ranks: collective in a run cut among ranks, 0 in one process.
  std::int64_t migrated_in_all() const;
  /// Per stored particle: 1 when this rank owns it, 0 for a ghost (distributed runs; empty otherwise).
  const std::vector<unsigned char>& owned_mask() const { return owned_; }
  /// Which stored particles a global sum counts, over which ranks (core/block_sums.hpp).
  SumScope sum_scope() const { return distributed_ ? SumScope{owned_.data(), true} : SumScope{}; }
  /// Kinetic energy, momentum and angular momentum of the whole system (every rank gets the same bits).
  ParticleTotals totals() const;
  /// The smallest radius in the whole system (collective when cut among ranks).
  double smallest_radius() const;
  /// Calls `use` with the whole system as one process running it would hold it at this step (particles in
  /// its storage order, the neighbour list as built, the contact history, groups, clock): this simulation
  /// itself on one process; cut among ranks, an image gathered on rank 0, and the other ranks do not call
  /// `use` (collective). What the LAMMPS dump and the wear analysis read.
  void with_whole_system(const std::function<void(const DemSimulation&)>& use) const;
  /// This process's share of a trajectory frame: its particles (owned ones, cut among ranks) in increasing
  /// id, and their rows in the frame, where their ids stand among all the ids of the run.
  FrameShare frame_share() const;

  /// Forces a neighbour rebuild (with re-sort and history carry-over) now, as if particles had drifted.
  void rebuild_neighbors();
  /// Stores the particles in the given order (new index i holds old index order[i]) instead of by cell,
  /// rebuilding the list and carrying the history over; ids, physics and history are unchanged.
  void reorder(const std::vector<int>& order);
  /// Re-evaluates forces at the current state without advancing the history (after host-side edits,
  /// e.g. of masses: the per-pair constants are recomputed too).
  void recompute_forces();
  /// The contact pass in use (never automatic).
  PairPass pair_pass() const { return pass_; }
  /// Bytes held per particle by particles, neighbour list (whose cell list the re-sort borrows), history, pair
  /// table, pass scratch and the id bookkeeping of runs cut among ranks: all the engine holds per particle.
  double bytes_per_particle() const;
  /// Changes the global damping fraction (relaxation phases); check_global_damping() first.
  void set_global_damping(double fraction);
  /// InputError naming `key` unless 0 <= fraction and the damping F = -fraction c_c v slows every particle
  /// by less than its own velocity in one step: fraction c_c dt / m_min < 1 (c_c of eq 21). Past it the
  /// velocity flips sign each step, and past twice it grows without bound. The one check of the run key,
  /// the stage key and the setter.
  void check_global_damping(double fraction, const std::string& key) const;
  /// Switches the pair law's adhesion and tangential parts (relaxation phases); takes effect at the next
  /// force evaluation (call recompute_forces() to apply it to the current step).
  void set_options(const CohesiveOptions& options);

  /// Elastic energy, max overlap and interacting pairs at the current state.
  CohesiveDiagnostics diagnostics() const;

  /// The energy balance since the start of the run (collective when cut among ranks; `d`: this step's
  /// diagnostics). Only with settings().energy_accounting.
  EnergyBalance energy_balance(const CohesiveDiagnostics& d) const;
  /// The energy accounting's cumulative columns summed over the whole system (exact sums: the same bits on
  /// any thread or rank count; collective when cut among ranks). Only with settings().energy_accounting.
  EnergyTotals energy_totals() const;
  /// Kinetic + elastic energy + everything dissipated so far: what a change between steps (a stage) alters
  /// by the work it does. Collective when cut among ranks.
  double energy_content() const;
  /// Adds work done on the system between steps (a stage's changes: energy_content() after minus before).
  void add_stage_work(double w) { stage_work_ += w; }

  /// Average virial stress (kernels/dem/virial_stress.hpp) of the selected particles (`select`: nullptr for all,
  /// or a per-particle mask, nonzero = counted) over `volume`, from the current forces' pair law and
  /// contact history; the state is not modified.
  StressTensor virial_stress(const int* select, double volume, bool kinetic = true) const;

  /// Empty when the state is sound; otherwise a message naming the step and the particle(s): a non-finite
  /// position, velocity or force, or an exploding overlap (deeper than `overlap_limit` times the smaller
  /// radius of the pair, which no calibrated cohesive solid reaches).
  std::string health_check(double overlap_limit = 0.5) const;
  /// The same, with diagnostics() already computed for this step.
  std::string health_check(const CohesiveDiagnostics& d, double overlap_limit = 0.5) const;

  /// Writes everything needed to continue bit for bit (particles, box, groups and their state, neighbour
  /// list, contact history, step, time, settings, and the input file's text) to `path` atomically: into
  /// `path`.tmp, closed, then renamed, so a crash mid-write leaves the previous checkpoint whole.
  /// `extra` (may be empty) writes what the run keeps beside the system (its `run` group: the health check's
  /// limit, the wear analysis's state) into the open file.
  /// Cut among ranks, every rank calls it (collective): each writes its own particles' rows and their list
  /// rows into the one file (parallel HDF5), then rank 0 adds the rest, calls `extra`, seals and renames.
  /// The file is the one a single process writes of the same run, dataset for dataset.
  void write_checkpoint(const std::string& path, const std::string& input_echo,
                        const std::function<void(h5::File&)>& extra = {}) const;
  /// Continues from a checkpoint exactly where it was written. `input_echo` receives the input text;
  /// `extra` (may be empty) reads what write_checkpoint's `extra` wrote (its errors name the file).
  /// A job of several ranks cuts the restored system among them (RestartRanks), whatever rank count wrote
  /// the checkpoint, and continues bit for bit.
  static DemSimulation from_checkpoint(const std::string& path, std::string* input_echo = nullptr,
                                       const std::function<void(const h5::File&)>& extra = {},
                                       RestartRanks ranks = {});

  /// One-paragraph summary: N, dt and dt_c, c_c, skin, cutoff, calibration of the smallest pair.
  std::string summary() const;

 private:
  struct Restored {};
  explicit DemSimulation(Restored) {}
  /// from_checkpoint() once the file is known to be a checkpoint of a format this version reads.
  static DemSimulation restore(const h5::File& f, std::string* input_echo);
  void compute_forces(int update_history);
  std::string local_health_check(const CohesiveDiagnostics& d, double overlap_limit) const;  // this rank's
  void refuse_coincident_particles() const;
  void rebuild(const std::vector<int>* order);
  void rebuild_distributed();  // rebuild() of a run cut among ranks: migration, halo, canonical order
  void distribute();           // set-up of a run cut among ranks: the decomposition, keep the owned
  void distribute_restored(std::array<int, 3> rank_grid);  // from the whole system, as at its last rebuild
  void index_half_pass();  // pair table and pass scratch of the half-list pass, after a build
  // Where this process's share of the system stands in a one-process checkpoint (write_checkpoint()).
  struct WholeRows {
    std::vector<int> owned;                 // stored particles this process writes, in storage order
    std::vector<std::int64_t> row;          // per stored particle (owned or ghost): its row in the whole system
    std::vector<std::int64_t> first_entry;  // per owned one: the row of its first list entry
    std::int64_t particles = 0, entries = 0;  // in the whole system
  };
  WholeRows whole_rows(const NeighborList::Saved& built) const;
  // Residency (offload builds; empty in host builds). The host copies of the particles, and of the list and
  // history, are current when the flags say so; host_edited_ says the device copy of the particles is not.
  void particles_to_host() const {
    if constexpr (exec::offload_build()) {
      if (!particles_on_host_) to_host(p_);
      particles_on_host_ = true;
    }
  }
  void pairs_to_host() const {
    if constexpr (exec::offload_build()) {
      if (!pairs_on_host_) {
        list_.to_host();
        history_.to_host();
      }
      pairs_on_host_ = true;
    }
  }
  void particles_to_device() const {
    if constexpr (exec::offload_build()) {
      if (host_edited_) to_device(p_);
      host_edited_ = false;
    }
  }
  // After kernels changed the device copies: of the particles alone, or of the list and history too.
  enum DeviceChange { particles_changed, particles_and_pairs_changed };
  void device_changed(DeviceChange what) const {
    if constexpr (exec::offload_build()) {
      particles_on_host_ = false;
      if (what == particles_and_pairs_changed) pairs_on_host_ = false;
    }
  }

  Box box_;
  Particles p_;
  Groups groups_;
  DemSettings settings_;
  CohesiveCoefficients coef_{};
  StabilityLimits limits_{};
  NeighborList list_;
  ContactHistory history_;
  CohesivePairTable table_;
  HalfPassScratch scratch_;
  PairEnergyBuffers pair_energy_;  // the contact pass's energy parts, with the accounting on
  double kinetic0_ = 0, elastic0_ = 0, stage_work_ = 0;  // the balance's start and the stages' work
  PairPass pass_ = PairPass::full;
  double dt_ = 0, damping_ = 0, skin_ = 0, max_cutoff_ = 0;
  long step_ = 0;
  double time_ = 0;
  long layout_generation_ = 0;
  PassTimes times_;
  bool distributed_ = false;
  comm::Decomposition decomposition_;
  comm::Halo halo_;
  std::vector<unsigned char> owned_;
  long long n_total_ = 0;
  CanonicalGrid build_grid_;  // the canonical order's grid at the last rebuild
  // Every id of the run, sorted, for frame_share() (left empty when the ids are first_id_, first_id_ + 1, ...).
  std::vector<std::int64_t> ids_in_order_;
  std::int64_t first_id_ = 0;
  void remember_ids();  // while this rank still holds every particle
  double limit_radius_ = 0, limit_mass_ = 0;  // the particle that limits dt at set-up (summary())
  mutable bool particles_on_host_ = true, pairs_on_host_ = true, host_edited_ = true;
};

}  // namespace debris
