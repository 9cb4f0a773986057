#include "scenarios/common/dem/dem_simulation.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>
#include <stdexcept>

#include "core/comm/communicator.hpp"
#include "core/error.hpp"
#include "core/exec.hpp"
#include "core/pass_timer.hpp"
#include "core/thread_tuner.hpp"
#include "kernels/dem/integrate.hpp"
#include "kernels/dem/virial_stress.hpp"

namespace debris {

DemSimulation::DemSimulation(Box box, Particles particles, Groups groups, DemSettings settings)
    : box_(std::move(box)), p_(std::move(particles)), groups_(std::move(groups)), settings_(std::move(settings)) {
  setup();
}

void DemSimulation::setup() {
  coef_ = CohesiveCoefficients::from(settings_.material);
  pass_ = settings_.pair_pass != PairPass::automatic ? settings_.pair_pass
          : exec::offload_build()                    ? PairPass::full
                                                     : PairPass::half;
  if (p_.size() == 0) throw input_error("particles", "none", "the system has no particle");
  // The same checks an edit from Python meets (Particles::check_column); masses come later, from the density.
  for (const char* column : {"id", "radius", "x", "y", "z"}) p_.check_column(column, std::string("particles.") + column);
  if (settings_.masses_from_density) p_.set_mass_from_density(settings_.material.density);
  groups_.refresh_members(p_);
  // Members of frozen and rigid groups start with their group's motion, not with whatever the input said.
  for (std::size_t i = 0; i < p_.size(); ++i) {
    const int g = p_.group[i];
    if (g < 0 || groups_.list[static_cast<std::size_t>(g)].motion == GroupMotion::free) continue;
    const Vec3 v = groups_.list[static_cast<std::size_t>(g)].velocity;
    const bool frozen = groups_.list[static_cast<std::size_t>(g)].motion == GroupMotion::frozen;
    p_.vx[i] = frozen ? 0.0 : v.x;
    p_.vy[i] = frozen ? 0.0 : v.y;
    p_.vz[i] = frozen ? 0.0 : v.z;
    p_.wx[i] = p_.wy[i] = p_.wz[i] = 0.0;
  }

  // Time step against eq 6, damping against eq 21, both for the most restrictive particle.
  limits_ = stability_limits(coef_, p_);
  limit_radius_ = p_.radius[static_cast<std::size_t>(limits_.particle)];
  limit_mass_ = p_.mass[static_cast<std::size_t>(limits_.particle)];
  if (settings_.time_step > 0.0) {
    dt_ = settings_.time_step;
  } else {
    if (!(settings_.time_step_fraction > 0.0))
      throw input_error("run.time_step_fraction", format_value(settings_.time_step_fraction), "must be > 0");
    dt_ = settings_.time_step_fraction * limits_.dt_c;
  }
  if (!std::isfinite(dt_) || dt_ <= 0.0) throw input_error("run.time_step", format_value(dt_), "must be > 0");
  if (dt_ > limits_.dt_c && !settings_.allow_unstable_time_step)
    throw input_error("run.time_step", format_value(dt_),
                      "exceeds the critical time step dt_c = " + format_value(limits_.dt_c) +
                          " of eq 6 (semi-implicit Euler diverges above it); use a fraction of dt_c, or set "
                          "run.allow_unstable_time_step: true to insist");
  set_global_damping(settings_.global_damping);

  // Neighbour cutoff: delta_f grows with r_i + r_j, so the largest pair bounds it.
  const double r_max = *std::max_element(p_.radius.begin(), p_.radius.end());
  max_cutoff_ = CohesiveCutoff{coef_}(r_max, r_max);
  const double r_min = *std::min_element(p_.radius.begin(), p_.radius.end());
  // Default skin. Narrow size distributions (one size class of the neighbour search, r_max < 2 r_min)
  // keep 0.2 r_min: a larger skin there adds the second shell of a close-packed solid to the list. Wide
  // ones take 0.25 r_mean: the smallest radius says little about their typical pair. Measured on the wear
  // junction's silica (size ratio 6.6, r_min = 0.56 nm, r_mean = 1.23 nm, 25 m/s vibration, settled;
  // BM_StepPolydisperse, 1 thread, M particle-steps/s): 0.2 r_min = 0.11 nm rebuilt every 44 steps (38% of
  // the run, 7.5 M); 0.15 nm every 70 (8.7 M); 0.2 nm every 96 (9.5 M); 0.25-0.6 nm every 170-590 (10.0-10.2 M:
  // more list entries offset fewer rebuilds). 0.25 r_mean = 0.31 nm sits at the low end of that plateau.
  double r_sum = 0.0;
  for (double r : p_.radius) r_sum += r;
  const double r_mean = r_sum / static_cast<double>(p_.size());
  const bool wide = SizeClasses::of(p_.radius.data(), static_cast<int>(p_.size()), SizeClasses::kMax).count > 1;
  skin_ = settings_.skin > 0.0 ? settings_.skin : wide ? 0.25 * r_mean : 0.2 * r_min;
  if (settings_.skin < 0.0) throw input_error("run.skin", format_value(settings_.skin), "must be >= 0");
  list_.set_max_size_classes(settings_.size_classes);

  // Everything above saw the whole system, on every rank alike; from here a distributed run keeps its own.
  distributed_ = settings_.distribute && comm::size() > 1;
  n_total_ = static_cast<long long>(p_.size());
  if (distributed_) distribute();
  rebuild_neighbors();
  refuse_coincident_particles();
  compute_forces(0);
  if (settings_.energy_accounting) {  // the balance counts from here
    kinetic0_ = totals().kinetic_energy;
    elastic0_ = diagnostics().elastic_energy;
  }
}

void DemSimulation::refuse_coincident_particles() const {
  // Two particles at one place (a repeated row of a data file) have no direction between them: eq 2's
  // normal is 0 / 0. Found among the listed pairs (every pair closer than the cutoff is listed); in a
  // distributed run by the rank that holds the pair, and reported by all (the lowest such rank's message).
  particles_to_host();
  pairs_to_host();
  const BoxView b = box_.view();
  std::string found;
  for (int i = 0; i < list_.rows() && found.empty(); ++i)
    for (int k = list_.offset()[i]; k < list_.offset()[i + 1]; ++k) {
      const std::size_t a = static_cast<std::size_t>(i), c = static_cast<std::size_t>(list_.index()[k]);
      const Vec3 d = minimum_image(b, Vec3{p_.x[a] - p_.x[c], p_.y[a] - p_.y[c], p_.z[a] - p_.z[c]});
      if (norm(d) > 1e-6 * std::min(p_.radius[a], p_.radius[c])) continue;
      found = input_error("particles", "particles id " + std::to_string(p_.id[a]) + " and id " + std::to_string(p_.id[c]),
                          "both sit at (" + format_value(p_.x[a]) + ", " + format_value(p_.y[a]) + ", " +
                              format_value(p_.z[a]) + "): a repeated particle (a duplicated row of the data file?)")
                  .what();
      break;
    }
  if (distributed_) found = comm::first_message(found);
  if (!found.empty()) throw InputError(found);
}

void DemSimulation::check_global_damping(double fraction, const std::string& key) const {
  if (!(fraction >= 0.0) || !std::isfinite(fraction))
    throw input_error(key, format_value(fraction), "must be a fraction >= 0 of the critical damping c_c (eq 21)");
  if (fraction == 0.0) return;
  particles_to_host();  // the masses
  double m_min = p_.size() ? *std::min_element(p_.mass.begin(), p_.mass.end()) : HUGE_VAL;
  if (distributed_) comm::allreduce_min(&m_min, 1);  // every rank decides alike
  const double bound = m_min / (limits_.c_c * dt_);
  if (!(fraction < bound))
    throw input_error(key, format_value(fraction),
                      "must stay below " + format_value(bound) + " c_c: the damping -c v then takes less than a "
                      "particle's whole velocity in one step (c_c dt / m_min = " + format_value(1.0 / bound) +
                      ", time step " + format_value(dt_) + "; the paper's relaxations use 0.1-0.2 c_c)");
}

void DemSimulation::set_global_damping(double fraction) {
  check_global_damping(fraction, "run.global_damping");
  settings_.global_damping = fraction;
  damping_ = fraction * limits_.c_c;
}

void DemSimulation::set_options(const CohesiveOptions& options) { settings_.options = options; }

void DemSimulation::rebuild_neighbors() { rebuild(nullptr); }

void DemSimulation::reorder(const std::vector<int>& order) {
  if (order.size() != p_.size()) throw std::invalid_argument("reorder: order has the wrong size");
  rebuild(&order);
}

void DemSimulation::rebuild(const std::vector<int>* order) {
  if (distributed_) {
    if (order) throw std::logic_error("DemSimulation::reorder: a run cut among ranks keeps the canonical order");
    return rebuild_distributed();
  }
  const PassTimer timer(times_.neighbours);
  particles_to_device();
  // Offload builds: wrap, re-sort (its order and a gather per column), neighbour search and history
  // carry-over run on the device, as do the cell counting sorts, the size-class binning of polydisperse
  // systems and the row prefix sum: a build moves scalars only.
  if (list_.rows() > 0) history_.remember(p_, list_);
  box_.wrap_resident(p_);
  if (order) {
    p_.permute_resident(*order);
    ++layout_generation_;
  } else if (settings_.sort_by_cell) {
    CellList& sorter = list_.cells_until_next_build();  // list_.build() below re-bins the new order
    sorter.build(box_.view(), p_.x.data(), p_.y.data(), p_.z.data(), static_cast<int>(p_.size()),
                 max_cutoff_ + skin_);
    // By cell, then by id: the canonical order, which the positions and ids alone decide, so every
    // per-particle sum (rows in increasing index) has the same terms in the same order however the particles
    // were stored before (offload builds: computed and applied on the device).
    exec::DeviceVector<int> order;  // transient, as the gather's scratch columns are
    sorter.sort_order(p_.id.data(), order);
    p_.permute_resident(order);
    ++layout_generation_;
  }
  list_.build(box_.view(), p_, CohesiveCutoff{coef_}, max_cutoff_, skin_,
               pass_ == PairPass::half ? NeighborKind::half : NeighborKind::full);
  history_.carry_over(p_, list_);
  device_changed(particles_and_pairs_changed);
  if (pass_ == PairPass::half) index_half_pass();
  ++times_.rebuilds;
}

void DemSimulation::index_half_pass() {
  // The half-list pass runs on host threads only: in offload builds its tables come back to the host.
  table_.build(coef_, p_, list_);
  exec::to_host(table_.delta_f);
  exec::to_host(table_.c_n);
  pairs_to_host();
  scratch_.energy = settings_.energy_accounting;
  scratch_.index(list_);
}

void DemSimulation::compute_forces(int update_history) {
  const bool energy = settings_.energy_accounting;
  PairEnergyOut energy_out;
  if (energy) {
    pair_energy_.resize(p_.size());
    energy_out = pair_energy_.out();
  }
  {
    const PassTimer timer(times_.contact);  // eqs 2-5 over the neighbour list
    particles_to_device();
    if (pass_ == PairPass::half) {  // sets the forces (zeroes them itself)
      // Host threads. In offload builds (where the half pass is chosen only on request, for tests) the state
      // makes a round trip around it.
      device_changed(particles_changed);
      particles_to_host();
      pairs_to_host();
      cohesive_contact_pass_half(table_, settings_.options, box_.view(), p_, list_, history_, dt_, update_history,
                                 scratch_, energy ? &energy_out : nullptr);
      if constexpr (exec::offload_build()) {
        to_device(p_);
        history_.to_device();
        if (energy) exec::to_device(pair_energy_.rows);
      }
    } else {
      zero_forces(p_);
      cohesive_contact_pass(coef_, settings_.options, box_.view(), p_, list_, history_, dt_, update_history,
                            energy ? &energy_out : nullptr);
    }
    device_changed(update_history != 0 ? particles_and_pairs_changed : particles_changed);
  }
  const PassTimer timer(times_.other);
  groups_.measure_reactions(p_, sum_scope());
  const Groups::View view = groups_.view();
  global_damping_pass(p_, view, damping_);
  // The forces are final: what each mechanism will take from the integration they drive.
  if (energy) fold_energy(p_, pair_energy_, groups_, view, damping_, dt_);
}

void DemSimulation::recompute_forces() {
  particles_to_device();
  if (pass_ == PairPass::half) index_half_pass();
  compute_forces(0);
}

double DemSimulation::bytes_per_particle() const {
  const double n = static_cast<double>(p_.size());
  return static_cast<double>(Particles::bytes_per_particle()) +
         static_cast<double>(list_.bytes() + history_.bytes() + table_.bytes() + scratch_.bytes() + pair_energy_.bytes() +
                             owned_.capacity() + sizeof(std::int64_t) * ids_in_order_.capacity()) /
             n;
}

void DemSimulation::step() {
  const exec::TunedStep tuned;  // times the step for the thread tuner, when the count is tuned
  {
    const PassTimer timer(times_.integration);  // eq 1: kick the rigid groups and the particles, drift
    particles_to_device();
    if (settings_.energy_accounting) commit_energy(p_);  // the shares of this integration, folded with its forces
    kick_rigid_groups(groups_, dt_);
    integrate_semi_implicit_euler(p_, groups_.view(), dt_);
    device_changed(particles_changed);
    groups_.accumulate_displacements(p_, dt_, sum_scope());
    ++step_;
    time_ += dt_;
  }
  if (distributed_) {
    // The ghosts take their owners' new x, v, omega (the drift moved them with partial forces) before
    // anything reads them, the rebuild test included.
    const PassTimer timer(times_.comm);
    halo_.forward(p_);
  }
  bool rebuild = false;
  {
    const PassTimer timer(times_.neighbours);
    rebuild = list_.needs_rebuild(box_.view(), p_);
  }
  if (distributed_) {
    const PassTimer timer(times_.comm);
    double any = rebuild ? 1.0 : 0.0;  // every rank rebuilds when one must
    comm::allreduce_max(&any, 1);
    rebuild = any > 0.0;
  }
  if (rebuild) rebuild_neighbors();  // drifted past skin / 2
  compute_forces(1);                 // contact (eqs 2-5), group reactions, global damping
}

void DemSimulation::run(long steps) {
  for (long s = 0; s < steps; ++s) step();
}

CohesiveDiagnostics DemSimulation::diagnostics() const {
  particles_to_device();
  return cohesive_diagnostics(coef_, settings_.options, box_.view(), p_, list_, history_, sum_scope());
}

EnergyTotals DemSimulation::energy_totals() const {
  particles_to_device();
  return debris::energy_totals(p_, static_cast<int>(groups_.size()), sum_scope());
}

EnergyBalance DemSimulation::energy_balance(const CohesiveDiagnostics& d) const {
  EnergyBalance b;
  b.kinetic = totals().kinetic_energy;
  b.elastic = d.elastic_energy;
  b.kinetic0 = kinetic0_;
  b.elastic0 = elastic0_;
  b.stage_work = stage_work_;
  b.totals = energy_totals();
  return b;
}

double DemSimulation::energy_content() const {
  if (!settings_.energy_accounting) return 0.0;
  const EnergyBalance b = energy_balance(diagnostics());
  return b.kinetic + b.elastic + b.totals.dissipated();
}

double DemSimulation::smallest_radius() const {
  particles_to_host();  // the radii (a re-sort leaves the host's copies stale)
  // A rank may hold no particle at all (a sparse system cut among many ranks).
  double r = p_.size() ? *std::min_element(p_.radius.begin(), p_.radius.end()) : HUGE_VAL;
  if (distributed_) comm::allreduce_min(&r, 1);
  return r;
}

ParticleTotals DemSimulation::totals() const {
  particles_to_device();
  return particle_totals(p_, sum_scope());
}

StressTensor DemSimulation::virial_stress(const int* select, double volume, bool kinetic) const {
  particles_to_device();
  if (!distributed_)
    return debris::virial_stress(coef_, settings_.options, box_.view(), p_, list_, history_, select, volume, kinetic);
  // Cut among ranks: each rank counts the selected particles it owns (so each half of a pair once, on the
  // rank of its end; 2 x (r F / 2) is r F exactly) and every rank gets the sum.
  std::vector<int> mine(p_.size());
  for (std::size_t i = 0; i < p_.size(); ++i) mine[i] = owned_[i] && (!select || select[i]) ? 1 : 0;
  return debris::virial_stress(coef_, settings_.options, box_.view(), p_, list_, history_, mine.data(), volume,
                               kinetic, true);
}

std::string DemSimulation::health_check(double overlap_limit) const {
  return health_check(diagnostics(), overlap_limit);
}

std::string DemSimulation::health_check(const CohesiveDiagnostics& diag, double overlap_limit) const {
  if (!distributed_) return local_health_check(diag, overlap_limit);
  // The rank that finds a fault reports it (the lowest, when several do), and every rank gets its message.
  return comm::first_message(local_health_check(diag, overlap_limit));
}

std::string DemSimulation::local_health_check(const CohesiveDiagnostics& diag, double overlap_limit) const {
  const double r_min = smallest_radius();  // collective: before any rank returns
  particles_to_device();
  const long bad = first_non_finite(p_);
  if (bad >= 0) {
    particles_to_host();
    const std::size_t b = static_cast<std::size_t>(bad);
    std::ostringstream os;
    os << "non-finite state at step " << step_ << " on particle id " << p_.id[b] << " (x = " << p_.x[b]
       << ", v = " << p_.vx[b] << ", f = " << p_.fx[b] << ")"
       << (step_ == 0 ? ": the set-up itself is not finite" : "; is the time step stable?");
    return os.str();
  }
  if (diag.max_overlap <= overlap_limit * r_min) return {};
  // Rare: find the pair by a plain scan, on the host.
  particles_to_host();
  pairs_to_host();
  const BoxView b = box_.view();
  for (int i = 0; i < list_.rows(); ++i) {
    for (int k = list_.offset()[i]; k < list_.offset()[i + 1]; ++k) {
      const std::size_t a = static_cast<std::size_t>(i), c = static_cast<std::size_t>(list_.index()[k]);
      const Vec3 d = minimum_image(b, Vec3{p_.x[a] - p_.x[c], p_.y[a] - p_.y[c], p_.z[a] - p_.z[c]});
      const double overlap = p_.radius[a] + p_.radius[c] - norm(d);
      if (overlap > overlap_limit * std::min(p_.radius[a], p_.radius[c])) {
        std::ostringstream os;
        os << (step_ == 0 ? "too deep an overlap" : "exploding overlap") << " at step " << step_ << ": particles id " << p_.id[a] << " and id " << p_.id[c]
           << " overlap by " << overlap << " (radii " << p_.radius[a] << ", " << p_.radius[c] << ")"
           << (step_ == 0 ? ", deeper than run.overlap_limit (" + format_value(overlap_limit) +
                                " smallest radii) as placed: place them farther apart, or raise the limit (auto: the "
                                "deepest initial overlap + 1)"
                          : "; is the time step stable, or the load too large?");
        return os.str();
      }
    }
  }
  return {};
}

std::string DemSimulation::summary() const {
  // limits_.particle indexes the storage order at set-up; particles have been sorted by cell since.
  // Cut among ranks: the one recorded at set-up (a rank holds a part of the system).
  particles_to_host();
  double r = limit_radius_, m = limit_mass_;
  if (!distributed_) {
    const std::size_t i = static_cast<std::size_t>(stability_limits(coef_, p_).particle);
    r = p_.radius[i];
    m = p_.mass[i];
  }
  const CohesivePairParams pp = cohesive_pair_params(coef_, r, r, m, m);
  std::ostringstream os;
  os << std::setprecision(6);
  os << "particles " << particle_count() << ", groups " << groups_.size() << "\n"
     << "material: d_min = " << settings_.material.minimum_diameter()
     << " (eq 19), d_c = " << settings_.material.critical_diameter() << " (eq 18)\n"
     << "smallest pair (d = " << 2 * r << "): k_N = " << pp.k_n << ", k_T = " << pp.k_t
     << ", delta_e = " << pp.delta_e << ", delta_f = " << pp.delta_f << ", F_mT = " << pp.f_max_t
     << ", c_N = " << pp.c_n << ", c_T = " << pp.c_t << "\n"
     << "critical time step dt_c = " << limits_.dt_c << " (eq 6), dt = " << dt_ << " = " << dt_ / limits_.dt_c
     << " dt_c\n"
     << "critical damping c_c = " << limits_.c_c << " (eq 21), global damping c = " << damping_ << " = "
     << settings_.global_damping << " c_c\n"
     << "neighbour cutoff <= " << max_cutoff_ << " + skin " << skin_;
  return os.str();
}

}  // namespace debris
