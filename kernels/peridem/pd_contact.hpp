#pragma once
// The PeriDEM contact passes (paper B, sections 2.2-2.3 and 3.2) over a PdContactList: normal force and
// friction between nodes (eqs 16-20, kernels/peridem/pd_contact_force.hpp) and one of the paper's two dampings,
// between nodes (eqs 21-25) or between grain centres (eqs 26-30, the paper's choice). Every pass writes
// only to its own row (node, slot or grain), so there are no atomics and the results are the same bits for
// any number of threads, on host threads and on a GPU.
//
// Damping between grain centres. Eq 27 is one force density at the centre of grain p per grain p' in
// contact (dist < R_c: some node pair closer than R_c), and eq 30 applies it at every node of p; times the
// nodal volume, node i of p receives V_i / |Omega_p| of the grain-pair force beta-bar delta_dot_c e, so the
// grain as a whole receives the force once, whatever the number of touching node pairs. A wall node is a
// partner of its own (section 3.2): its position and velocity stand for z_c', v_c'; the wall itself is one
// body of infinite mass (m_eq = 2 m_p), whose force is shared among its touching nodes (pd_contact.cpp).
// Passes: per-grain centres (pd_grain_centres), per-slot forces (a slot is one grain pair of the list, see
// core/pd_contact_list.hpp), per-grain sums, per-node spreading; the wall nodes take the opposite of the
// slot forces of their particle partners, so the contact forces of a step sum to zero (round-off).
//
// Notes against PeriDEM's src/model/dem/demModel.cpp: it damps grain pairs in an O(N_p^2) serial loop,
// decides contact between bounding circles (|x_c - x_c'| < R + R' + 1.01 R_c) instead of dist < R_c,
// divides by pi R^2 instead of |Omega_p|, and uses the particle mass alone as M_eq against each wall node
// in contact, one full force per node. Eq 29 with the wall node's own mass (what debris did first) left a
// grain bouncing off a wall almost undamped (C_R 0.95 for restitution 0.5); debris takes the wall as one
// body of infinite mass, so a wall damps like a very heavy grain. Because the dashpot acts along the line
// from the grain centre to the wall node, a grain sliding past a wall is also slowed by it (rate < 0 for the
// wall nodes ahead of the centre); that is the paper's model, kept as written.
#include <vector>

#include "core/comm/exact_sum.hpp"
#include "core/exec.hpp"
#include "core/vec3.hpp"
#include "kernels/peridem/pd_contact_params.hpp"

namespace debris {

class PdNodes;
struct PdGrains;
class PdContactList;

/// The two dampings of section 2.3. Restitution 1 switches either off (eq 23 gives beta = 0).
enum class PdDamping : int { node_pairs = 0, grain_centres = 1 };

/// Scratch of the contact passes, sized by them (no allocation once the sizes are stable). Device-resident
/// in offload builds; nothing reads it across calls.
struct PdContactWork {
  exec::DeviceVector<double> grain_volume, grain_mass;      // sums over each grain's nodes
  exec::DeviceVector<int> slot_touching;                    // 1 when the slot's grains are in contact
  exec::DeviceVector<double> slot_fx, slot_fy, slot_fz;     // damping force of each grain-pair slot on its owner
  exec::DeviceVector<double> grain_fx, grain_fy, grain_fz;  // total centre damping force on each grain
  // Per grain, when not empty: the centre damping takes z_c, v_c of eq 26 from this node (the authors' code
  // uses the grain's centre node, BaseParticle::getXCenter / getVCenter) instead of the volume-weighted
  // means of grains.cx .. cvz. Set by the caller, who sends it to the device; the grain centres themselves
  // stay the means.
  exec::DeviceVector<int> centre_node;
  exec::DeviceVector<double> node_cx, node_cy, node_cz, node_cvx, node_cvy, node_cvz;  // scratch for centre_node
  // When not empty (one per node): the length of each node's row of the contact list, to use in place of the
  // list's own. A rank's list holds partial rows for its ghost nodes; their owners' counts are given here
  // (the friction's stick mass of eq 20 shares a node's mass among its row, pd_contact_force.hpp).
  exec::DeviceVector<int> row_count;
};

/// Per-grain reduction: volume-weighted centre and mean velocity of every grain into grains.cx .. cvz, and
/// each grain's volume and mass (sums of V_i and m_i) into work.
void pd_grain_centres(const PdNodes& nodes, PdGrains& grains, PdContactWork& work);

/// Adds the contact forces of one step to nodes.fx .. fz: normal force (eqs 16-18), friction (eqs 19-20,
/// capped to stop but never reverse the sliding within a step), and the chosen damping. Self-contact pairs
/// (one grain, bond broken) get the normal force only (section 3.2). dt: the time step (friction cap).
/// With grain_centres, refreshes the grain centres first (pd_grain_centres).
void pd_contact_pass(const PdContactTable& table, PdDamping damping, PdNodes& nodes, PdGrains& grains,
                     const PdContactList& list, PdContactWork& work, double dt);

/// pd_contact_pass in two parts, for a caller that puts grain centres in between (a rank sets its ghost
/// grains' centres from their owners): the node pairs (eqs 16-20, and 21-25 with node damping), then, for
/// grain_centres, the damping between grain centres (eqs 26-30) from grains.cx .. cvz and work.grain_volume,
/// grain_mass as they stand (pd_grain_centres, or given). Same operations in the same order as pd_contact_pass.
void pd_node_pair_forces(const PdContactTable& table, PdDamping damping, PdNodes& nodes, const PdGrains& grains,
                         const PdContactList& list, const PdContactWork& work, double dt);
void pd_centre_damping(const PdContactTable& table, PdNodes& nodes, const PdGrains& grains, const PdContactList& list,
                       PdContactWork& work);
/// pd_centre_damping in its two parts: the force of every grain-pair slot into work.slot_fx .. fz (eqs
/// 26-29; nothing else changes: a restart recomputes them for the wall reactions), then their sums per grain
/// spread over the nodes (eqs 29-30).
void pd_centre_slot_forces(const PdContactTable& table, const PdNodes& nodes, const PdGrains& grains,
                           const PdContactList& list, PdContactWork& work);
void pd_centre_damping_spread(const PdContactTable& table, PdNodes& nodes, const PdGrains& grains,
                              const PdContactList& list, PdContactWork& work);

/// Total force on each wall grain (the sum over its nodes, in node order; particles get zero): the wall's
/// reaction. Call it after the force passes: wall nodes receive contact forces only (no bonds, no gravity).
/// Offload builds: written on the device (to_host(reaction) to read it).
void pd_wall_reactions(const PdNodes& nodes, const PdGrains& grains, exec::DeviceVector<Vec3>& reaction);

/// The wall reactions as sums that give the same bits on any rank count (core/comm/exact_sum): into
/// sums[3 grains.id[w] + axis], for every wall w, minus each force its nodes exert on the particle nodes of
/// the list's rows (those flagged in owned_node; all when null): each node pair's force (eqs 16-20, 21-25
/// with node damping; evaluated from the particle's end, the wall's end being its exact opposite) and each
/// centre damping slot of a particle grain (flagged in owned_grain) toward a wall node (eqs 26-30), one exact
/// term each. A host pass over the host copies of the nodes, the list and work (the slot forces of the last
/// pd_centre_damping), for output rows. `sums` must hold 3 per grain of the whole system.
void pd_wall_reaction_sums(const PdContactTable& table, PdDamping damping, const PdNodes& nodes, const PdGrains& grains,
                           const PdContactList& list, const PdContactWork& work, double dt, const unsigned char* owned_node,
                           const unsigned char* owned_grain, std::vector<comm::ExactSum>& sums);

/// Elastic energy stored in the contact springs, sum over pairs of 1/2 K_n delta^2 V V': the exact sum of
/// pd_contact_energy_rows.
double pd_contact_elastic_energy(const PdContactTable& table, const PdNodes& nodes, const PdGrains& grains,
                                 const PdContactList& list);

/// The contact springs' energy by row: row_energy[i] = sum over row i of 1/2 (1/2 K_n delta^2 V V'), half of
/// each pair's (the other half is in the partner's row), in row order: an owned node's value is the same on
/// any rank count, for sums that are (diagnostics of a run cut among ranks). row_energy: rows() values
/// (device-resident in offload builds).
void pd_contact_energy_rows(const PdContactTable& table, const PdNodes& nodes, const PdGrains& grains,
                            const PdContactList& list, double* row_energy);

/// Node pairs of the list closer than their contact radius R_c (each pair once; diagnostics). An integer
/// sum: the same on any thread count or device.
long pd_touching_pairs(const PdContactTable& table, const PdNodes& nodes, const PdGrains& grains,
                       const PdContactList& list);

/// The deepest penetration of two bodies: the largest (R_c - |x' - x|) / R_c over listed node pairs of two
/// different grains or walls (0 when none is within R_c). A max reduction, cheap enough for every step;
/// the health check's run.penetration_limit is compared with it.
double pd_deepest_penetration(const PdContactTable& table, const PdNodes& nodes, const PdGrains& grains,
                              const PdContactList& list);

}  // namespace debris
