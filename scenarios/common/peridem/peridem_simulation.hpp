#pragma once
// The PeriDEM step loop (paper B), assembled once from the passes of kernels/ (shared/DESIGN.md):
//
//   integrate (eq 32) -> contact list if needed -> zero forces -> gravity -> bonds (break, theta, force:
//   eqs 10-13, 33-34) -> contact list again if a bond broke (self-contact) -> contact + damping
//   (eqs 16-30) -> wall reactions
//
// Forces at step n use x^n; eq 32 in velocity form gives v^{n+1/2} = v^{n-1/2} + dt f^n / m and
// x^{n+1} = x^n + dt v^{n+1/2} (kernels/peridem/pd_integrate.hpp). The stored velocity is half a step behind the
// positions; the first step kicks by dt/2 from the initial velocity.
//
// Device residency (offload builds; none of it exists in host builds): nodes, grains, bonds, the contact
// list, the material and contact tables and every scratch array live on the device from construction (or
// restore) to destruction, and a step transfers nothing but the scalars of its reductions (bonds broken,
// largest drift) and, on steps that break bonds or rebuild the list, the list's prefix sums and slots
// (core/pd_contact_list.hpp). The host copies are refreshed only where the host reads them, in three parts
// (nodes, grains, bonds + contact list), each once per change: the accessors nodes(), grains(), bonds() and
// contacts(), the checks, diagnostics() and checkpoints. The non-const nodes() and grains(), and the stage
// changes (walls placed or set moving, grain velocities), mark the host copies as edited, so the next kernel
// sends them first (state_to_device()).
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/bond_list.hpp"
#include "core/box.hpp"
#include "core/comm/decomposition.hpp"
#include "core/comm/pd_halo.hpp"
#include "core/exec.hpp"
#include "core/io/node_trajectory_writer.hpp"
#include "core/pd_contact_list.hpp"
#include "core/pd_nodes.hpp"
#include "core/vec3.hpp"
#include "kernels/peridem/pd_contact.hpp"
#include "kernels/peridem/pd_contact_params.hpp"
#include "kernels/peridem/pd_material.hpp"

namespace debris {

namespace h5 {
class File;
}

struct PeridemSettings {
  double time_step = 0;                   // s, > 0
  bool allow_unstable_time_step = false;  // the user insists on a step above the stable one
  Vec3 gravity{};                         // m/s^2, acts on particle nodes
  PdDamping damping = PdDamping::grain_centres;
  // grain_centres only: take each grain's centre and velocity in eqs 26-29 from its centre node (the node
  // nearest its volume-weighted centre at set-up), as the authors' code does, instead of the means of its
  // nodes. Not kept in checkpoints (a restart passes its settings again).
  bool damping_centre_node = false;
  double skin = 0;  // Verlet skin of the contact list; 0 = the contact radius R_c
  // Global viscous damping rate c (1/s): F -= c m v on every particle node, to bring a pack to rest before
  // it is loaded (a settle stage); 0 (the paper's runs) = none. Not in the paper's model.
  double global_damping = 0;
};

/// Wall-clock seconds spent in each pass since the start (or the restart).
struct PeridemPassTimes {
  double integration = 0;  // eq 32
  double neighbours = 0;   // contact list rebuilds
  double bonds = 0;        // break, dilatation, bond force
  double contact = 0;      // contact forces and damping
  double other = 0;        // zeroing forces, gravity
  long rebuilds = 0;       // contact list rebuilds in that time
  long self_contact_updates = 0;  // steps whose broken bonds were added to the list in place
  // A run cut among ranks: the ghosts' exchanges every step and the grains' migration and ghost layer at
  // list builds (the list build itself stays in `neighbours`), and the grains this rank sent to others.
  double comm = 0;
  long grains_migrated = 0;
};

/// One particle grain at one instant (output rows): its centre and mean velocity (volume-weighted), the
/// kinetic energy of its nodes, its largest damage Z (eq 14) and its broken bonds (each counted once).
struct PdGrainState {
  Vec3 centre, velocity;
  double kinetic_energy = 0, damage = 0;
  long broken_bonds = 0;
};

/// Sums over the system at one instant.
struct PeridemDiagnostics {
  double kinetic_energy = 0;  // 1/2 m v^2 over particle nodes (v half a step behind x)
  double bond_energy = 0;     // LPS elastic energy of the grains
  double contact_energy = 0;  // energy in the contact springs
  double max_damage = 0;      // largest Z of eq 14 (|s| / s_0)
  long broken_bonds = 0;      // bonds broken since the start
  long contact_pairs = 0;     // node pairs closer than R_c (each counted once)
  Vec3 momentum{};            // of the particle nodes
};

class PeridemSimulation {
 public:
  /// `nodes` and `grains` as placed (scenarios/common/peridem/grain_placement.hpp): masses are set here from the grains'
  /// materials. `contact` holds one PdContactSettings for every pair of materials (or one for all).
  /// Validates everything (InputError naming the key and value), builds the bonds, the weighted volumes,
  /// the contact list, and evaluates the forces at step 0. A particle node closer to a wall node than their
  /// contact radius R_c is an InputError naming the grain and the wall (a grain placed into a wall would be
  /// thrown out at once). `names`: one per grain and wall (messages and output columns), or empty for
  /// "grain<k>" / "wall<k>".
  PeridemSimulation(PdNodes nodes, PdGrains grains, std::vector<PdMaterial> materials,
                    std::vector<PdContactSettings> contact, PeridemSettings settings,
                    std::vector<std::string> names = {});

  void step();
  void run(long steps);

  /// Cuts the run among the MPI ranks (collective; every rank constructed the same whole system): each rank
  /// keeps the grains whose centre its subdomain holds, and from then on steps them with ghost copies of the
  /// nodes of other ranks' grains within reach (core/comm/pd_halo). Every owned node's position, velocity
  /// and force are then the bits one process computes (peridem_ranks.cpp says how). `rank_grid`: Px, Py, Pz,
  /// or zeros for the grid with the least surface. InputError ("mpirun -np") when the ranks cannot share the
  /// grains: a grain wider than a subdomain allows. The cut is made as at the contact list's last build
  /// (by the positions then), so a system restored from a checkpoint of any rank count continues with the
  /// list, and the bits, it had. Centre-node damping is refused until it is cut among ranks.
  void distribute(std::array<int, 3> rank_grid = {0, 0, 0});
  bool distributed() const { return distributed_; }
  /// Per node held: 1 for this rank's own nodes, 0 for ghost copies (empty: one process, every node its own).
  const std::vector<unsigned char>& owned_nodes() const { return halo_.owned_nodes(); }
  const comm::Decomposition& decomposition() const { return decomposition_; }
  /// Ghost nodes held (0 on one process) and the bytes this rank sends to them in a step without a build.
  std::size_t ghost_nodes() const { return distributed_ ? halo_.ghost_nodes() : 0; }
  std::size_t halo_bytes_per_step() const { return distributed_ ? halo_.forward_bytes() : 0; }

  // State. The accessors return the host copies, current (offload builds: copied back from the device if a
  // kernel changed them); the non-const ones count as an edit, sent to the device before the next kernel.
  const PdNodes& nodes() const {
    nodes_to_host();
    return nodes_;
  }
  PdNodes& nodes() {
    nodes_to_host();
    if constexpr (exec::offload_build()) nodes_edited_ = true;
    return nodes_;
  }
  const PdGrains& grains() const {
    grains_to_host();
    return grains_;
  }
  PdGrains& grains() {
    grains_to_host();
    if constexpr (exec::offload_build()) grains_edited_ = true;
    return grains_;
  }
  const BondList& bonds() const {
    pairs_to_host();
    return bonds_;
  }
  const PdContactList& contacts() const {
    pairs_to_host();
    return list_;
  }
  /// Nodes in the whole system, on every rank (no transfer: the runner asks every step).
  std::size_t node_count() const { return distributed_ ? node_total_ : nodes_.size(); }
  /// The kind of every grain and wall of the whole system (PdGrainKind), by its index there.
  std::vector<int> grain_kinds() const;
  /// Every particle grain of the whole system by its index there (walls left at zero), on every rank:
  /// collective in a run cut among ranks, where each grain's owner computes it as one process does. Reads
  /// the damage of the last diagnostics() or refresh_damage(); refreshes the grain centres.
  std::vector<PdGrainState> grain_states();
  /// The least (max = false) or greatest coordinate along `axis` of the nodes of wall g (a whole-system
  /// index), on every rank (collective in a run cut among ranks): where a stage places a wall from.
  double wall_edge(int g, int axis, bool max) const;
  /// This process's rows of a node frame (core/io/node_trajectory_writer.hpp): its own nodes, each at the
  /// row its id has among all ids, the row one process writes it in.
  NodeFrameShare frame_share() const;
  const PdContactTable& contact_table() const { return table_; }
  const std::vector<PdMaterial>& materials() const { return materials_; }
  const PeridemSettings& settings() const { return settings_; }
  long step_count() const { return step_; }
  double time() const { return time_; }
  double dt() const { return settings_.time_step; }
  /// h of eq 35: the smallest distance between two nodes of one grain or wall (reference configuration).
  double mesh_size() const { return mesh_size_; }
  /// Largest stable step of the central difference, 2 / omega_max, for the linearised bonds plus one
  /// contact spring per node (see stable_time_step in the .cpp).
  double stable_time_step() const { return stable_dt_; }
  long broken_bonds() const { return broken_total_; }
  long contact_rebuilds() const { return rebuilds_; }

  /// Grain centres and mean velocities (volume-weighted) at the current step, refreshed on demand.
  void refresh_grain_centres();
  /// Total contact force on each wall this step (zero for particles), by grain index in the whole system:
  /// every term added exactly (pd_wall_reaction_sums), so the same bits on any rank count. Collective in a
  /// run cut among ranks.
  std::vector<Vec3> wall_reactions() const;
  /// Sums as exact sums (comm::ExactSum) over the nodes: the same bits on any rank count. Collective in a
  /// run cut among ranks.
  PeridemDiagnostics diagnostics();
  /// Node pairs closer than their contact radius R_c now (each pair once; collective in a run cut among
  /// ranks).
  long touching_pairs() const;
  /// Empty when every position, velocity and force is finite; otherwise names the step and the node.
  /// This and the two checks below are collective in a run cut among ranks: every rank returns the message
  /// one process gives (the problem at the node of lowest id).
  std::string health_check() const;

  /// Sets every node of grain g to velocity v (initial conditions; before the first step).
  void set_grain_velocity(int g, Vec3 v);

  // Between steps (a stage's start). After the last of them call recompute_forces(), so the changes act on
  // this step's forces too.
  /// A wall's prescribed velocity from now on (its nodes take it at once).
  void set_wall_velocity(int g, Vec3 v);
  /// Moves wall g rigidly by d (a lid placed before it presses). InputError naming the wall and the grain
  /// if a particle node then lies closer to one of its nodes than their contact radius R_c: a wall placed
  /// into the grains would throw them out at once.
  void move_wall(int g, Vec3 d);
  void set_gravity(Vec3 g);
  /// Global viscous damping rate c (1/s) from now on, 0 to end it. InputError ("global_damping") unless
  /// check_global_damping accepts it.
  void set_global_damping(double c);
  /// InputError naming `key` unless 0 <= c and c dt < 1 (above that the explicit drag would reverse a
  /// node's velocity in one step). The one check of every place a rate is given (input, stage, setter).
  static void check_global_damping(double c, double dt, const std::string& key);
  /// Rebuilds the contact list and re-evaluates this step's forces for the state as edited.
  void recompute_forces();

  /// One paragraph: nodes, grains, bonds, h, R_c, K_n, dt against the stable step.
  std::string summary() const;

  /// Names of the grains and walls (output columns); "grain<k>" / "wall<k>" unless set.
  const std::vector<std::string>& grain_names() const { return grain_names_; }
  /// One name per grain; InputError if the count differs.
  void set_grain_names(std::vector<std::string> names);
  /// Damage Z of eq 14 into nodes().damage for the current positions (diagnostics() does this too), and
  /// optionally each node's fraction of broken bonds into `broken_fraction` (nodes().size() values).
  void refresh_damage(double* broken_fraction = nullptr);
  /// Empty unless a node pair of two bodies (two grains, or a grain and a wall) is closer than
  /// (1 - limit) R_c: a penetration far deeper than any contact force allows in a sound run (the contact
  /// spring holds pairs to a few per cent of R_c), so a grain is passing through another or through a wall.
  /// Names the step, the bodies and the nodes. limit in (0, 1]; 1 never fires.
  std::string penetration_check(double limit) const;
  /// The deepest penetration of two bodies as a fraction of R_c (pd_deepest_penetration; 0: none).
  double deepest_penetration() const;
  /// Empty unless some particle node moves farther than the contact radius R_c in one step (|v| dt > R_c):
  /// contacts would be stepped over, so the run has blown up (or its time step is far too large for the
  /// speeds). Names the step and the node.
  std::string explosion_check() const;
  /// Time per pass since construction or restart.
  const PeridemPassTimes& times() const { return times_; }

  /// Checkpoint (HDF5, scenarios/common/peridem/peridem_checkpoint.cpp): everything needed to continue bit for bit on
  /// the host, plus `input_echo` (the input file's text). Written to path.tmp, then renamed over `path`.
  /// A run cut among ranks gathers the whole system on rank 0, which writes the one-process file
  /// (collective): a restart reads it on any rank count.
  void write_checkpoint(const std::string& path, const std::string& input_echo) const;
  /// The simulation as it was when the checkpoint was written; `input_echo` receives the input's text.
  /// InputError ("restart") for a missing file or one of another format version.
  static PeridemSimulation from_checkpoint(const std::string& path, std::string* input_echo = nullptr);

 private:
  struct Restored {};
  explicit PeridemSimulation(Restored) {}
  /// from_checkpoint() once the file is known to be a checkpoint of a format this version reads.
  static PeridemSimulation restore(const h5::File& f, std::string* input_echo);
  /// The file of write_checkpoint() from these nodes, grains, bonds and the list's build positions (this
  /// object's or the whole system's gathered on rank 0) and this object's settings and counters.
  using Positions = std::array<std::vector<double>, 3>;  // x, y, z of every node
  void write_checkpoint_of(const std::string& path, const std::string& input_echo, const PdNodes& nodes,
                           const PdGrains& grains, const BondList& bonds, const Positions& at_build,
                           long broken_total) const;
  /// The nodes' positions at the contact list's last build (the list's own, host copies).
  Positions positions_at_build() const;
  void write_distributed_checkpoint(const std::string& path, const std::string& input_echo) const;
  void compute_forces();
  void rebuild_contacts();
  // A run cut among ranks (peridem_ranks.cpp): the list build that migrates grains and lays the ghosts, the
  // ghosts' positions, velocities and grain centres from their owners, and the owners' row lengths.
  void rebuild_distributed();
  void refresh_ghosts();
  void share_row_counts();
  double ghost_width() const;
  bool owns_node(std::size_t i) const { return !distributed_ || halo_.owned_nodes()[i]; }
  bool owns_grain(std::size_t g) const { return !distributed_ || halo_.owned_grains()[g]; }
  /// The index in the whole system of the node with this id (its rank among all ids).
  std::int64_t whole_index(std::int64_t id) const;
  // The checks above on this rank's own nodes (and pairs by their node of lower id): the first problem
  // in id order, and the id of its node.
  std::string local_health_check(std::int64_t* node_id) const;
  std::string local_explosion_check(std::int64_t* node_id) const;
  std::string local_penetration_check(double limit, std::int64_t* node_id) const;
  // Residency (offload builds; no-ops in host builds). *_stale_: kernels changed the device copies since the
  // host's were refreshed; *_edited_: the host copies were changed, the device's are not current (the host
  // edits nodes and grains only: bonds and the contact list are the kernels').
  void nodes_to_host() const;
  void grains_to_host() const;
  void pairs_to_host() const;  // the bonds' broken flags and the contact list
  void state_to_host() const {
    nodes_to_host();
    grains_to_host();
    pairs_to_host();
  }
  void state_to_device() const;
  // What kernels changed on the device: flags or-ed together (nodes_changed | grains_changed).
  enum DeviceChange : unsigned { nodes_changed = 1u, grains_changed = 2u, pairs_changed = 4u };
  void device_changed(unsigned what) const {
    if constexpr (exec::offload_build()) {
      nodes_stale_ = nodes_stale_ || (what & nodes_changed);
      grains_stale_ = grains_stale_ || (what & grains_changed);
      pairs_stale_ = pairs_stale_ || (what & pairs_changed);
    }
  }
  void refuse_grains_in_walls() const;
  /// The index here of grain g of the whole system (g itself on one process), -1 when not held here.
  int local_grain(int g) const;
  /// move_wall on the wall (or piece of it) held at index g: empty, or why it cannot go there.
  std::string move_held_wall(int g, Vec3 d);
  // Each pair of the contact list once (i < j), with its distance and contact radius R_c; `visit(i, j, dist,
  // rc)` returns false to stop. The set-up check, the health check and the diagnostics share it.
  template <class Visit>
  void for_each_listed_pair(Visit visit) const;

  PdNodes nodes_;
  PdGrains grains_;
  std::vector<PdMaterial> materials_;
  PdLpsTable lps_;
  PdContactTable table_;
  PeridemSettings settings_;
  BondList bonds_;
  PdContactList list_;
  PdContactWork work_;
  double mesh_size_ = 0, stable_dt_ = 0, skin_ = 0;
  long step_ = 0, broken_total_ = 0, rebuilds_ = 0;
  double time_ = 0;
  // For checkpoints: the constructor's contact settings (the node positions at the last contact list build,
  // from which a restart rebuilds the list, are the list's own).
  std::vector<PdContactSettings> contact_settings_;
  std::vector<std::string> grain_names_;
  PeridemPassTimes times_;
  // Output of a kernel the host reads (broken-bond fractions): device-resident scratch.
  mutable exec::DeviceVector<double> broken_fraction_;
  exec::DeviceVector<double> bond_density_, row_energy_;  // diagnostics(): W_i, and each row's contact energy
  mutable bool nodes_stale_ = false, grains_stale_ = false, pairs_stale_ = false;
  mutable bool nodes_edited_ = true, grains_edited_ = true;  // as constructed: on the host only
  // Cut among ranks: the decomposition of a box around the nodes at the set-up (walled on every axis), and
  // the ghost layer.
  bool distributed_ = false;
  int grain_count_ = 0;  // grains and walls of the whole system
  std::size_t node_total_ = 0;  // nodes of the whole system
  std::vector<int> whole_kinds_;  // PdGrainKind of every grain and wall of the whole system
  // The ids of the whole system's nodes in increasing order, kept only where they are not 0, 1, 2, ...
  std::vector<std::int64_t> whole_ids_;
  comm::Decomposition decomposition_;
  Box box_;
  // The nodes' bounding box as placed (kept in checkpoints): the box a run is cut in on any rank count, so a
  // restart on P ranks is cut as a fresh run on P ranks is, however the walls have moved since.
  Vec3 placed_lo_, placed_hi_;
  void set_placed_box();
  comm::PdHalo halo_;
};

/// h of eq 35 per grain, minimised: the smallest reference distance between two nodes of one grain (the
/// mesh's own spacing; nodes of different grains may be anywhere). A sweep along x, not all pairs.
double pd_mesh_size(const PdNodes& nodes, const PdGrains& grains);

}  // namespace debris
