#pragma once
// Where the work goes: the energy each mechanism takes out of a DEM run, accumulated per particle, exactly.
//
// Semi-implicit Euler (eq 1: v' = v + F dt / m, x' = x + v' dt) changes a particle's kinetic energy by
//
//     m |v'|^2 / 2 - m |v|^2 / 2 = F . (v + v') / 2 dt                      (and T . (w + w') / 2 dt)
//
// exactly. So when every part of F does its work with the step's mean velocity vb = (v + v') / 2, the parts
// add up to the change of kinetic energy to round-off, and each mechanism's share is exact:
//   normal damping (eq 2, -c_N v_N n)          D_normal     = -sum F_dn . vb dt
//   tangential damping (eq 2, -c_T v_T)        D_tangential = -sum (F_dt . vb + T_dt . wb) dt
//   global damping (F = -c v, free particles)  D_global     = -sum F_g . vb dt
//   the drives (frozen, velocity and force groups: whatever sets a member's velocity other than its own force)
//                                              W_drive      = sum over members (dKE_i - (F_i . vb + T_i . wb) dt)
//   sliding (eq 4: the spring cut back to F'_mT) D_sliding  = F'_mT times the length cut from dT, plus the
//                                              whole spring energy of a pair that lets go of it
// The conservative rest (eq 3's spring and softening, the tangential spring) does work -dPE plus the
// integrator's error, which is what the balance W_in = dKE + dPE + sum D + residual leaves as its residual.
//
// Per particle, each pair's dissipation at the velocities the force was evaluated with (c_N v_N^2 dt,
// c_T |v_T|^2 dt, >= 0) goes half to each end; the difference between that and the exact share above is
// each particle's own -(F_d . (vb - v) + T_d . (wb - w)) dt, which needs only its own damping force. So the
// columns are the pairs' dissipation split between their particles, and their sums are exact.
//
// When: the force pass gives each particle its pairs' parts (PairEnergyOut); fold_energy() turns them into
// the `pending_*` columns, the shares of the integration to come (vb and wb are known once F is: the next
// kick and integration are predicted exactly as they run); commit_energy() adds them to the cumulative
// columns when that integration runs. A force evaluation after an edit or a stage change (no step between)
// replaces the pending shares. Sliding happens in the pass itself (the history is cut there): it goes into
// its column at once. Every column is a particle column, so re-sorting, migration between ranks and
// checkpoints carry it, and the sums (energy_totals) are exact: the same bits on any thread or rank count.
#include <vector>

#include "core/block_sums.hpp"
#include "core/exec.hpp"
#include "core/groups.hpp"
#include "kernels/dem/cohesive_pair_force.hpp"

namespace debris {

class Particles;

/// The force pass's per-particle sums (kPairEnergyColumns per particle, contiguous), sized with the particles.
struct PairEnergyBuffers {
  exec::DeviceVector<double> rows;
  exec::DeviceVector<double> group_next;  // each group's velocity after the next kick (fold_energy's, kept)
  void resize(std::size_t n);
  PairEnergyOut out();
  std::size_t bytes() const;
};

/// After a force evaluation (forces final: pairs, reactions, global damping with coefficient `damping`):
/// sets the pending columns from the pass's sums `pair` for the integration to come (each group's velocity
/// after the next kick, as kick_rigid_groups() will set it, kept in pair.group_next), and adds the pass's
/// sliding to dissipated_sliding.
void fold_energy(Particles& p, PairEnergyBuffers& pair, const Groups& groups, Groups::View view, double damping,
                 double dt);

/// At the start of a step: the pending shares into the cumulative columns (then zero).
void commit_energy(Particles& p);

/// The cumulative columns summed over the system (exact sums; `scope` as for particle_totals).
struct EnergyTotals {
  double dissipated_normal = 0, dissipated_tangential = 0, dissipated_sliding = 0, dissipated_global = 0;
  double tangential_work = 0;
  std::vector<double> drive_work;  // per group (0 for free groups)
  double dissipated() const { return dissipated_normal + dissipated_tangential + dissipated_sliding + dissipated_global; }
};
EnergyTotals energy_totals(const Particles& p, int groups, SumScope scope = {});

/// Where a run stands: W_in = (KE - KE_0) + (PE - PE_0) + sum of D + residual.
struct EnergyBalance {
  double kinetic = 0, elastic = 0;    // now (translation + rotation; eq 3's potential + tangential springs)
  double kinetic0 = 0, elastic0 = 0;  // at the start of the run
  double stage_work = 0;              // what stages did at once: velocities set, the pair law switched
  EnergyTotals totals;
  double drive_work() const {
    double w = 0;
    for (double g : totals.drive_work) w += g;
    return w;
  }
  double work_in() const { return drive_work() + stage_work; }
  double residual() const {
    return work_in() - (kinetic - kinetic0) - (elastic - elastic0) - totals.dissipated();
  }
};

}  // namespace debris
