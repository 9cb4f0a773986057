#include "scenarios/common/peridem/peridem_simulation.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>
#include <tuple>
#include <utility>

#include "core/comm/communicator.hpp"
#include "core/error.hpp"
#include "core/exec.hpp"
#include "core/pass_timer.hpp"
#include "core/thread_tuner.hpp"
#include "kernels/peridem/pd_bond_passes.hpp"
#include "kernels/peridem/pd_integrate.hpp"
#include "kernels/peridem/pd_stable_step.hpp"

namespace debris {

namespace {

bool is_particle(const PdGrains& g, int k) { return g.kind[k] == static_cast<int>(PdGrainKind::particle); }

// The bounding box of nodes [b, e) (b < e): lo, hi.
std::pair<Vec3, Vec3> node_bounds(const PdNodes& n, std::size_t b, std::size_t e) {
  Vec3 lo{n.x[b], n.y[b], n.z[b]}, hi = lo;
  for (std::size_t i = b; i < e; ++i) {
    lo = {std::min(lo.x, n.x[i]), std::min(lo.y, n.y[i]), std::min(lo.z, n.z[i])};
    hi = {std::max(hi.x, n.x[i]), std::max(hi.y, n.y[i]), std::max(hi.z, n.z[i])};
  }
  return {lo, hi};
}


}  // namespace

double pd_mesh_size(const PdNodes& nodes, const PdGrains& grains) {
  double h = std::numeric_limits<double>::infinity();
  for (std::size_t g = 0; g < grains.size(); ++g) {
    const int b = grains.node_begin[g], e = grains.node_end[g];
    if (e - b < 2) continue;
    // Sweep along x: for each node, scan the nodes after it in x while their x gap is below the best h.
    std::vector<int> order(static_cast<std::size_t>(e - b));
    for (int i = b; i < e; ++i) order[static_cast<std::size_t>(i - b)] = i;
    std::sort(order.begin(), order.end(), [&](int p, int q) { return nodes.x0[p] < nodes.x0[q]; });
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t a = 0; a < order.size(); ++a) {
      const int i = order[a];
      for (std::size_t c = a + 1; c < order.size(); ++c) {
        const int j = order[c];
        const double dx = nodes.x0[j] - nodes.x0[i];
        if (dx >= best) break;
        const double d = std::sqrt(dx * dx + (nodes.y0[j] - nodes.y0[i]) * (nodes.y0[j] - nodes.y0[i]) +
                                   (nodes.z0[j] - nodes.z0[i]) * (nodes.z0[j] - nodes.z0[i]));
        if (d > 0) best = std::min(best, d);
      }
    }
    h = std::min(h, best);
  }
  return h;
}

PeridemSimulation::PeridemSimulation(PdNodes nodes, PdGrains grains, std::vector<PdMaterial> materials,
                                     std::vector<PdContactSettings> contact, PeridemSettings settings,
                                     std::vector<std::string> names)
    : nodes_(std::move(nodes)),
      grains_(std::move(grains)),
      materials_(std::move(materials)),
      settings_(settings),
      contact_settings_(contact) {
  if (materials_.empty()) throw input_error("materials", "(none)", "at least one material is needed");
  if (nodes_.size() == 0) throw input_error("grains", "(none)", "no nodes to simulate");
  if (!(settings_.time_step > 0) || !std::isfinite(settings_.time_step))
    throw input_error("run.time_step", format_value(settings_.time_step), "must be > 0");
  if (!(settings_.skin >= 0)) throw input_error("run.skin", format_value(settings_.skin), "must be >= 0");
  check_global_damping(settings_.global_damping, settings_.time_step, "run.global_damping");
  lps_.clear();
  for (std::size_t m = 0; m < materials_.size(); ++m) {
    const std::string prefix = "materials[" + std::to_string(m) + "]";
    lps_.push_back(PdLpsConstants::from(materials_[m], prefix.c_str()));
  }
  for (std::size_t g = 0; g < grains_.size(); ++g) {
    grains_.id[g] = static_cast<int>(g);
    const int mat = grains_.material[g];
    if (mat < 0 || static_cast<std::size_t>(mat) >= materials_.size())
      throw input_error("grains[" + std::to_string(g) + "].material", std::to_string(mat),
                        "must name one of the " + std::to_string(materials_.size()) + " materials");
    for (int i = grains_.node_begin[g]; i < grains_.node_end[g]; ++i) {
      if (!(nodes_.volume[i] > 0))
        throw input_error("node " + std::to_string(nodes_.id[i]) + " volume", format_value(nodes_.volume[i]),
                          "must be > 0");
      nodes_.mass[i] = materials_[static_cast<std::size_t>(mat)].density * nodes_.volume[i];
    }
  }
  set_placed_box();
  mesh_size_ = pd_mesh_size(nodes_, grains_);
  if (!std::isfinite(mesh_size_))
    throw input_error("grains", "(single nodes)", "every grain and wall needs at least two nodes (eq 35)");
  if (contact.size() == 1)
    table_ = pd_contact_table(materials_, contact.front(), mesh_size_);
  else
    table_ = pd_contact_table(materials_, contact, mesh_size_);

  std::vector<double> horizon(grains_.size());
  for (std::size_t g = 0; g < grains_.size(); ++g)
    horizon[g] = materials_[static_cast<std::size_t>(grains_.material[g])].horizon;
  bonds_ = BondList::build(nodes_, grains_, horizon);
  // A particle grain's node with no bond never feels its grain (eq 33). The input reader names the shape's
  // mesh size when that is the cause; this holds for systems built any other way.
  for (std::size_t g = 0; g < grains_.size(); ++g) {
    if (!is_particle(grains_, static_cast<int>(g))) continue;
    for (int i = grains_.node_begin[g]; i < grains_.node_end[g]; ++i)
      if (bonds_.offset[static_cast<std::size_t>(i) + 1] == bonds_.offset[static_cast<std::size_t>(i)]) {
        const std::string grain = g < names.size() ? names[g] : "grain" + std::to_string(g);
        throw input_error("horizon", format_value(horizon[g]) + " m",
                          "leaves node " + std::to_string(nodes_.id[i]) + " of grain '" + grain + "' (material " +
                              std::to_string(grains_.material[g]) + ") without a bond (eq 33: no node of its grain "
                              "within the horizon; the system's mesh size h = " + format_value(mesh_size_) +
                              " m, horizon / h = " + format_value(horizon[g] / mesh_size_) +
                              "); mesh the grain finer or widen the horizon: horizon / h of 2 or more");
      }
  }
  // Everything the kernels read goes to the device once (offload builds): nodes and grains as placed (the
  // host copies count as edited since construction), bonds, the LPS table (the contact table sent itself).
  state_to_device();
  to_device(bonds_);
  exec::to_device(lps_);
  pd_weighted_volume_pass(lps_, grains_, bonds_, nodes_);
  exec::to_host(nodes_.weighted_volume);  // the host copy complete (the power iteration copies the nodes)
  exec::to_host(bonds_.weight);           // and the bond weights' (to_device(bonds) sends them again)

  // The stable step of eq 32 for these bonds and contacts (kernels/peridem/pd_stable_step.hpp).
  stable_dt_ = pd_stable_time_step(nodes_, grains_, bonds_, lps_, materials_, table_, mesh_size_);
  if (settings_.time_step > stable_dt_ && !settings_.allow_unstable_time_step)
    throw input_error("run.time_step", format_value(settings_.time_step),
                      "is above the stable step " + format_value(stable_dt_) +
                          " s of eq 32 for these bonds and contacts (set run.allow_unstable_time_step: true to insist)");

  if (settings_.damping_centre_node) {
    // Each grain's centre node: the node nearest its volume-weighted centre now (for a PeriDEM circle mesh,
    // the embedded centre point).
    state_to_device();
    pd_grain_centres(nodes_, grains_, work_);
    for (const auto* c : {&grains_.cx, &grains_.cy, &grains_.cz}) exec::to_host(*c);  // computed on the device
    work_.centre_node.assign(grains_.size(), 0);
    for (std::size_t g = 0; g < grains_.size(); ++g) {
      double best = std::numeric_limits<double>::infinity();
      for (int i = grains_.node_begin[g]; i < grains_.node_end[g]; ++i) {
        const double dx = nodes_.x[i] - grains_.cx[g], dy = nodes_.y[i] - grains_.cy[g];
        const double dz = nodes_.z[i] - grains_.cz[g];
        const double d2 = dx * dx + dy * dy + dz * dz;
        if (d2 < best) {
          best = d2;
          work_.centre_node[g] = i;
        }
      }
    }
    exec::to_device(work_.centre_node);
  }
  skin_ = settings_.skin > 0 ? settings_.skin : table_.max_contact_radius();
  for (std::size_t g = 0; g < grains_.size(); ++g)
    grain_names_.push_back((is_particle(grains_, static_cast<int>(g)) ? "grain" : "wall") + std::to_string(g));
  if (!names.empty()) set_grain_names(std::move(names));
  rebuild_contacts();
  refuse_grains_in_walls();
  compute_forces();
}

// Every particle-wall node pair within R_c is in the contact list just built (cutoff R_c + skin).
template <class Visit>
void PeridemSimulation::for_each_listed_pair(Visit visit) const {
  nodes_to_host();  // the positions and the list's rows
  pairs_to_host();
  const auto& off = list_.offset();
  const auto& idx = list_.index();
  for (int i = 0; i < list_.rows(); ++i)
    for (int k = off[i]; k < off[i + 1]; ++k) {
      const int j = idx[k];
      if (j <= i) continue;
      const double rc = table_.pair(grains_.material[nodes_.grain[i]], grains_.material[nodes_.grain[j]]).r_c;
      const double dx = nodes_.x[j] - nodes_.x[i], dy = nodes_.y[j] - nodes_.y[i], dz = nodes_.z[j] - nodes_.z[i];
      if (!visit(i, j, std::sqrt(dx * dx + dy * dy + dz * dz), rc)) return;
    }
}

void PeridemSimulation::refuse_grains_in_walls() const {
  for_each_listed_pair([&](int a, int b, double dist, double rc) {
    if (dist >= rc || is_particle(grains_, nodes_.grain[a]) == is_particle(grains_, nodes_.grain[b])) return true;
    const int i = is_particle(grains_, nodes_.grain[a]) ? a : b, j = i == a ? b : a;  // grain node, wall node
    const int gi = nodes_.grain[i], gj = nodes_.grain[j];
    throw input_error("grains." + grain_names_[static_cast<std::size_t>(gi)],
                      "placed on wall '" + grain_names_[static_cast<std::size_t>(gj)] + "'",
                      "its node " + std::to_string(nodes_.id[i]) + " at (" + format_value(nodes_.x[i]) + ", " +
                          format_value(nodes_.y[i]) + ", " + format_value(nodes_.z[i]) + ") m is " +
                          format_value(dist) + " m from wall node " + std::to_string(nodes_.id[j]) +
                          ", within the contact radius " + format_value(rc) +
                          " m: the grain would be thrown out of the wall at once; move it clear of the wall");
  });
}

// Only the columns the step's kernels write come back (the weighted volume, written once at set-up, came
// back then); the others change on the host only.
void PeridemSimulation::nodes_to_host() const {
  if constexpr (exec::offload_build()) {
    if (nodes_stale_)
      for (const auto* c : {&nodes_.x, &nodes_.y, &nodes_.z, &nodes_.vx, &nodes_.vy, &nodes_.vz, &nodes_.fx, &nodes_.fy,
                            &nodes_.fz, &nodes_.theta, &nodes_.damage})
        exec::to_host(*c);
    nodes_stale_ = false;
  }
}

void PeridemSimulation::grains_to_host() const {
  if constexpr (exec::offload_build()) {
    if (grains_stale_)
      for (const auto* c : {&grains_.cx, &grains_.cy, &grains_.cz, &grains_.cvx, &grains_.cvy, &grains_.cvz})
        exec::to_host(*c);
    grains_stale_ = false;
  }
}

void PeridemSimulation::pairs_to_host() const {
  if constexpr (exec::offload_build()) {
    if (pairs_stale_) {
      exec::to_host(bonds_.broken);
      list_.to_host();
    }
    pairs_stale_ = false;
  }
}

void PeridemSimulation::state_to_device() const {
  if constexpr (exec::offload_build()) {
    if (nodes_edited_) to_device(nodes_);
    if (grains_edited_) to_device(grains_);
    nodes_edited_ = grains_edited_ = false;
  }
}

void PeridemSimulation::rebuild_contacts() {
  const PassTimer timer(times_.neighbours);
  state_to_device();
  list_.build(nodes_, grains_, bonds_, table_.max_contact_radius(), skin_);
  device_changed(pairs_changed);
  ++rebuilds_;
  ++times_.rebuilds;
}

void PeridemSimulation::compute_forces() {
  state_to_device();
  device_changed(nodes_changed | grains_changed | pairs_changed);  // forces and theta; grain centres; bonds, list
  {
    const PassTimer timer(times_.other);  // body forces: gravity, the optional global damping
    pd_weight_forces(nodes_, grains_, settings_.gravity);
    if (settings_.global_damping > 0) pd_viscous_damping(nodes_, grains_, settings_.global_damping);
  }
  long broke = 0;
  {
    const PassTimer timer(times_.bonds);  // eqs 11 (break), 34 (dilatation), 33 (force)
    broke = pd_bond_step(lps_, grains_, bonds_, nodes_);
  }
  // Both callers hand over a list that is fresh for these positions (just built, or checked by step()), so
  // only a broken bond makes it stale here: its two nodes may now touch (self-contact). The list takes
  // their pairs in place (a full rebuild here cost 13-18 ms against an 11 ms step on the 502-grain deck).
  if (broke > 0) {
    const PassTimer timer(times_.neighbours);
    broken_total_ += broke;
    list_.add_broken_bonds(bonds_);
    ++times_.self_contact_updates;
  }
  if (distributed_) share_row_counts();  // a rank's broken bonds lengthen its rows: its ghosts elsewhere learn it
  const PassTimer timer(times_.contact);  // eqs 16-30
  if (!distributed_) return pd_contact_pass(table_, settings_.damping, nodes_, grains_, list_, work_, settings_.time_step);
  // The grain centres (the ghosts' from their owners) are current since refresh_ghosts().
  pd_node_pair_forces(table_, settings_.damping, nodes_, grains_, list_, work_, settings_.time_step);
  if (settings_.damping == PdDamping::grain_centres) pd_centre_damping(table_, nodes_, grains_, list_, work_);
}

void PeridemSimulation::step() {
  const exec::TunedStep tuned;  // times the step for the thread tuner, when the count is tuned
  {
    const PassTimer timer(times_.integration);  // eq 32
    state_to_device();
    device_changed(nodes_changed);
    pd_integrate(nodes_, grains_, settings_.time_step, step_ == 0);
  }
  ++step_;
  time_ += settings_.time_step;
  if (!distributed_) {
    if (list_.needs_rebuild(nodes_)) rebuild_contacts();
    return compute_forces();
  }
  // Ghosts first, so that every rank judges the list by the positions one process has (a ghost drifts as
  // its owner); the build is then one decision of all ranks.
  refresh_ghosts();
  double rebuild = list_.needs_rebuild(nodes_) ? 1.0 : 0.0;
  comm::allreduce_max(&rebuild, 1);
  if (rebuild > 0) rebuild_distributed();
  compute_forces();
}

void PeridemSimulation::set_grain_names(std::vector<std::string> names) {
  if (names.size() != grains_.size())
    throw input_error("grain names", std::to_string(names.size()),
                      "need one per grain and wall, " + std::to_string(grains_.size()));
  grain_names_ = std::move(names);
}

void PeridemSimulation::refresh_damage(double* broken_fraction) {
  state_to_device();
  device_changed(nodes_changed);
  // Offload builds: the fractions are written on the device, into scratch, and copied out.
  double* fraction = broken_fraction;
  if constexpr (exec::offload_build()) {
    if (broken_fraction) {
      broken_fraction_.resize(nodes_.size());
      fraction = broken_fraction_.data();
    }
  }
  pd_damage_pass(lps_, grains_, bonds_, nodes_, fraction);
  if constexpr (exec::offload_build()) {
    if (broken_fraction) {
      exec::to_host(broken_fraction_);
      std::copy(broken_fraction_.begin(), broken_fraction_.end(), broken_fraction);
    }
  }
}

std::string PeridemSimulation::local_explosion_check(std::int64_t* node_id) const {
  nodes_to_host();  // (the grains' kinds are constant: always current on the host)
  const double reach = table_.max_contact_radius();
  const double dt = settings_.time_step;
  for (std::size_t i = 0; i < nodes_.size(); ++i) {
    if (!is_particle(grains_, nodes_.grain[i]) || !owns_node(i)) continue;
    const double v = std::sqrt(nodes_.vx[i] * nodes_.vx[i] + nodes_.vy[i] * nodes_.vy[i] + nodes_.vz[i] * nodes_.vz[i]);
    if (v * dt > reach) {
      std::ostringstream os;
      os << "step " << step_ << ": node " << nodes_.id[i] << " (grain " << grains_.id[static_cast<std::size_t>(nodes_.grain[i])] << ") moves " << v * dt
         << " m in one step at speed " << v << " m/s, more than the contact radius " << reach
         << " m: the run has blown up (is the time step above the stable " << stable_dt_ << " s?)";
      *node_id = nodes_.id[i];
      return os.str();
    }
  }
  return {};
}

void PeridemSimulation::run(long steps) {
  for (long s = 0; s < steps; ++s) step();
}

void PeridemSimulation::refresh_grain_centres() {
  state_to_device();
  device_changed(grains_changed);
  pd_grain_centres(nodes_, grains_, work_);
}

std::vector<Vec3> PeridemSimulation::wall_reactions() const {
  // Exact sums of the forces the walls take (pd_wall_reaction_sums): the same bits on any rank count.
  nodes_to_host();
  pairs_to_host();
  for (const auto* v : {&work_.slot_fx, &work_.slot_fy, &work_.slot_fz}) exec::to_host(*v);  // the last pass's
  const std::size_t grains = distributed_ ? static_cast<std::size_t>(grain_count_) : grains_.size();
  std::vector<comm::ExactSum> sums(3 * grains);
  pd_wall_reaction_sums(table_, settings_.damping, nodes_, grains_, list_, work_, settings_.time_step,
                        distributed_ ? halo_.owned_nodes().data() : nullptr,
                        distributed_ ? halo_.owned_grains().data() : nullptr, sums);
  if (distributed_) comm::allreduce(sums.data(), static_cast<int>(sums.size()));
  std::vector<Vec3> reaction(grains);
  for (std::size_t g = 0; g < grains; ++g)
    reaction[g] = {sums[3 * g].value(), sums[3 * g + 1].value(), sums[3 * g + 2].value()};
  return reaction;
}

int PeridemSimulation::local_grain(int g) const {
  if (!distributed_) return g;
  const auto it = std::lower_bound(grains_.id.begin(), grains_.id.end(), g);
  return it != grains_.id.end() && *it == g ? static_cast<int>(it - grains_.id.begin()) : -1;
}

void PeridemSimulation::set_grain_velocity(int whole_g, Vec3 v) {
  const int g = local_grain(whole_g);
  if (g < 0) return;  // held by other ranks
  nodes();  // current on the host, and marked as edited
  for (int i = grains_.node_begin[g]; i < grains_.node_end[g]; ++i) {
    nodes_.vx[i] = nodes_.fixed[i] & 1 ? 0.0 : v.x;
    nodes_.vy[i] = nodes_.fixed[i] & 2 ? 0.0 : v.y;
    nodes_.vz[i] = nodes_.fixed[i] & 4 ? 0.0 : v.z;
  }
}

void PeridemSimulation::set_wall_velocity(int whole_g, Vec3 v) {
  const int g = local_grain(whole_g);
  if (g < 0) return;  // held by other ranks
  nodes();  // current on the host, and marked as edited
  grains();
  const std::size_t k = static_cast<std::size_t>(g);
  grains_.wall_vx[k] = v.x;
  grains_.wall_vy[k] = v.y;
  grains_.wall_vz[k] = v.z;
  for (int i = grains_.node_begin[k]; i < grains_.node_end[k]; ++i) {
    nodes_.vx[i] = v.x;
    nodes_.vy[i] = v.y;
    nodes_.vz[i] = v.z;
  }
}

void PeridemSimulation::move_wall(int whole_g, Vec3 d) {
  const int g = local_grain(whole_g);
  // A rank cut from the others checks the pieces of the wall it holds against the grains it holds (ghosts
  // included), and all ranks stop alike when one finds a grain in the way.
  std::string problem;
  if (g >= 0) problem = move_held_wall(g, d);
  if (distributed_) problem = comm::first_message(problem);
  if (!problem.empty()) {
    const std::string wall = static_cast<std::size_t>(whole_g) < grain_names_.size()
                                 ? grain_names_[static_cast<std::size_t>(whole_g)]
                                 : "wall" + std::to_string(whole_g);
    throw input_error("walls." + wall,
                      "moved by (" + format_value(d.x) + ", " + format_value(d.y) + ", " + format_value(d.z) + ") m",
                      problem);
  }
}

std::string PeridemSimulation::move_held_wall(int g, Vec3 d) {
  nodes();  // current on the host, and marked as edited
  const std::size_t k = static_cast<std::size_t>(g);
  const int b = grains_.node_begin[k], e = grains_.node_end[k];
  for (int i = b; i < e; ++i) {
    nodes_.x[i] += d.x;
    nodes_.y[i] += d.y;
    nodes_.z[i] += d.z;
    nodes_.x0[i] += d.x;  // a wall has no bonds: its reference moves with it
    nodes_.y0[i] += d.y;
    nodes_.z0[i] += d.z;
  }
  // Refuse a wall that lands on the grains: the wall's bounding box grown by the largest contact radius
  // first (cheap), then node by node against the wall's nodes.
  const double reach = table_.max_contact_radius();
  const auto [lo, hi] = node_bounds(nodes_, static_cast<std::size_t>(b), static_cast<std::size_t>(e));
  const int wall_material = grains_.material[k];
  for (std::size_t j = 0; j < nodes_.size(); ++j) {
    const int gj = nodes_.grain[j];
    if (!is_particle(grains_, gj)) continue;
    if (nodes_.x[j] < lo.x - reach || nodes_.x[j] > hi.x + reach || nodes_.y[j] < lo.y - reach ||
        nodes_.y[j] > hi.y + reach || nodes_.z[j] < lo.z - reach || nodes_.z[j] > hi.z + reach)
      continue;
    const double rc = table_.pair(grains_.material[gj], wall_material).r_c;
    for (int i = b; i < e; ++i) {
      const double dx = nodes_.x[j] - nodes_.x[i], dy = nodes_.y[j] - nodes_.y[i], dz = nodes_.z[j] - nodes_.z[i];
      const double dist = std::sqrt(dx * dx + dy * dy + dz * dz);
      if (dist < rc) {
        const int whole_gj = grains_.id[static_cast<std::size_t>(gj)];
        const std::string grain = static_cast<std::size_t>(whole_gj) < grain_names_.size()
                                      ? grain_names_[static_cast<std::size_t>(whole_gj)]
                                      : "grain" + std::to_string(whole_gj);
        return "at step " + std::to_string(step_) + " it would lie on grain '" + grain + "' (node " +
               std::to_string(nodes_.id[j]) + " is " + format_value(dist) +
               " m from a wall node, within the contact radius " + format_value(rc) + " m)";
      }
    }
  }
  return {};
}

void PeridemSimulation::set_gravity(Vec3 g) { settings_.gravity = g; }

void PeridemSimulation::check_global_damping(double c, double dt, const std::string& key) {
  if (!(c >= 0) || !(c * dt < 1))
    throw input_error(key, format_value(c),
                      "must be a rate >= 0 with rate * run.time_step < 1 (time step " + format_value(dt) +
                          " s), e.g. '100 s^-1' (0: none)");
}

void PeridemSimulation::set_global_damping(double c) {
  check_global_damping(c, settings_.time_step, "global_damping");
  settings_.global_damping = c;
}

void PeridemSimulation::set_placed_box() { std::tie(placed_lo_, placed_hi_) = node_bounds(nodes_, 0, nodes_.size()); }

void PeridemSimulation::recompute_forces() {
  if (distributed_) {
    // A stage moved walls or set velocities on their owners: the ghosts learn it, then the list is built
    // as one process builds it here (walls that crossed a cut move to their new owner).
    refresh_ghosts();
    rebuild_distributed();
  } else {
    rebuild_contacts();
  }
  compute_forces();
}

PeridemDiagnostics PeridemSimulation::diagnostics() {
  PeridemDiagnostics d;
  const std::size_t n = nodes_.size();
  // The per-node passes first (on the device in offload builds), then the host adds them up exactly over
  // the nodes this rank owns (comm::ExactSum): the same bits on any rank count and storage order.
  state_to_device();
  bond_density_.resize(n);
  row_energy_.resize(n);
  pd_energy_density_pass(lps_, grains_, bonds_, nodes_, bond_density_.data());
  pd_contact_energy_rows(table_, nodes_, grains_, list_, row_energy_.data());
  exec::to_host(bond_density_);
  exec::to_host(row_energy_);
  refresh_damage();
  d.contact_pairs = touching_pairs();
  nodes_to_host();  // (the grains' kinds are constant: always current on the host)
  enum { kinetic, px, py, pz, bond, contact, kSums };
  comm::ExactSum sum[kSums];
  for (std::size_t i = 0; i < n; ++i) {
    if (!owns_node(i)) continue;
    sum[bond].add(nodes_.volume[i] * bond_density_[i]);
    sum[contact].add(row_energy_[i]);
    d.max_damage = std::max(d.max_damage, nodes_.damage[i]);
    if (!is_particle(grains_, nodes_.grain[i])) continue;
    const double m = nodes_.mass[i];
    sum[kinetic].add(0.5 * m * (nodes_.vx[i] * nodes_.vx[i] + nodes_.vy[i] * nodes_.vy[i] + nodes_.vz[i] * nodes_.vz[i]));
    sum[px].add(m * nodes_.vx[i]);
    sum[py].add(m * nodes_.vy[i]);
    sum[pz].add(m * nodes_.vz[i]);
  }
  std::int64_t broken = broken_total_;
  if (distributed_) {
    comm::allreduce(sum, kSums);
    comm::allreduce_max(&d.max_damage, 1);
    comm::allreduce_sum(&broken, 1);
  }
  d.kinetic_energy = sum[kinetic].value();
  d.momentum = {sum[px].value(), sum[py].value(), sum[pz].value()};
  d.bond_energy = sum[bond].value();
  d.contact_energy = sum[contact].value();
  d.broken_bonds = broken;
  return d;
}

long PeridemSimulation::touching_pairs() const {
  state_to_device();
  if (!distributed_) return pd_touching_pairs(table_, nodes_, grains_, list_);
  // Each pair once over all ranks: in the row of its owned node of lower index (ids order both ranks alike).
  std::int64_t touching = 0;
  for_each_listed_pair([&](int i, int, double dist, double rc) {
    touching += halo_.owned_nodes()[static_cast<std::size_t>(i)] && dist < rc ? 1 : 0;
    return true;
  });
  comm::allreduce_sum(&touching, 1);
  return static_cast<long>(touching);
}

double PeridemSimulation::deepest_penetration() const {
  state_to_device();
  return pd_deepest_penetration(table_, nodes_, grains_, list_);
}

std::string PeridemSimulation::local_penetration_check(double limit, std::int64_t* node_id) const {
  // The reduction first (on the device in offload builds); the pair is looked for only when one is too deep.
  if (!(deepest_penetration() > limit)) return {};
  std::string problem;
  for_each_listed_pair([&](int i, int j, double dist, double rc) {
    if (!owns_node(static_cast<std::size_t>(i))) return true;  // the pair is in its owner's row (ids order alike)
    const int gi = grains_.id[static_cast<std::size_t>(nodes_.grain[i])],
              gj = grains_.id[static_cast<std::size_t>(nodes_.grain[j])];
    // Self-contact inside a broken grain is not a pair of bodies.
    if (gj == gi || rc - dist <= limit * rc) return true;
    std::ostringstream os;
    os << "step " << step_ << ": node " << nodes_.id[i] << " of '" << grain_names_[static_cast<std::size_t>(gi)]
       << "' and node " << nodes_.id[j] << " of '" << grain_names_[static_cast<std::size_t>(gj)] << "' are " << dist
       << " m apart, " << (rc - dist) / rc << " of the contact radius " << rc << " m deep (run.penetration_limit "
       << limit << ")"
       << (step_ == 0 ? " as placed: the two bodies start inside each other (a repeated row of the particle list, or "
                        "grains placed closer than R_c apart)"
                      : ": one body is passing through the other (a time step too large for the speeds, or a "
                        "stiffness too small for the load)");
    problem = os.str();
    *node_id = nodes_.id[i];
    return false;
  });
  return problem;
}

std::string PeridemSimulation::local_health_check(std::int64_t* node_id) const {
  nodes_to_host();
  for (std::size_t i = 0; i < nodes_.size(); ++i) {
    if (!owns_node(i)) continue;  // a ghost's values are its owner's, checked there
    const double v[9] = {nodes_.x[i], nodes_.y[i], nodes_.z[i], nodes_.vx[i], nodes_.vy[i],
                         nodes_.vz[i], nodes_.fx[i], nodes_.fy[i], nodes_.fz[i]};
    for (double c : v)
      if (!std::isfinite(c)) {
        std::ostringstream os;
        os << "step " << step_ << ": node " << nodes_.id[i] << " (grain " << grains_.id[static_cast<std::size_t>(nodes_.grain[i])]
           << ") has a non-finite position, velocity or force: position (" << nodes_.x[i] << ", " << nodes_.y[i]
           << ", " << nodes_.z[i] << "), velocity (" << nodes_.vx[i] << ", " << nodes_.vy[i] << ", "
           << nodes_.vz[i] << ")";
        *node_id = nodes_.id[i];
        return os.str();
      }
  }
  return {};
}

std::string PeridemSimulation::summary() const {
  std::ostringstream os;
  long particles = 0, walls = 0;
  for (std::size_t g = 0; g < grains_.size(); ++g) (is_particle(grains_, static_cast<int>(g)) ? particles : walls)++;
  os << nodes_.size() << " nodes in " << particles << " grains and " << walls << " walls; " << bonds_.entries() / 2
     << " bonds; mesh size h = " << mesh_size_ << " m (eq 35), contact radius R_c = " << table_.pair(0, 0).r_c
     << " m, K_n = " << table_.pair(0, 0).k_n << " (eq 36); dt = " << settings_.time_step
     << " s, stable step " << stable_dt_ << " s (" << settings_.time_step / stable_dt_ << " of it); damping "
     << (settings_.damping == PdDamping::grain_centres ? "between grain centres (eqs 26-30)"
                                                        : "between nodes (eqs 21-25)");
  if (settings_.global_damping > 0) os << "; global viscous damping " << settings_.global_damping << " 1/s";
  return os.str();
}

}  // namespace debris
