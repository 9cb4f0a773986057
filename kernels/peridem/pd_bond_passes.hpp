#pragma once
// The peridynamic bond passes of paper B (sections 2.1.1 and 3.1): kernels/peridem/lps_bond_force.hpp over the
// bond list. The bond list stores every bond from both ends, so each pass writes only to the row's own node
// (and the row's own entries), with no atomics: the results are bitwise the same for any thread count.
// The force needs theta at both ends of every bond, so dilatation and force are separate passes. One step:
//
//   pd_bond_step           h of eq 11 from the current stretch, theta_i of eqs 13/34 over the intact bonds
//                          (row i breaks its own entries, then sums the intact ones), then
//                          f_i += V_i F_i, F_i of eq 33 (force density; PdNodes stores newtons)
//   pd_dilatation_pass     theta alone, and pd_bond_force_pass the force alone, for fixed bond states
//                          (the stable step of eq 32 probes the stiffness with them)
// pd_weighted_volume_pass runs once, in the reference state.
//
// How they run (kernels/peridem/pd_bond_passes.cpp): rows are handed to the threads in blocks of equal bond entries;
// within a row, a vector loop computes every entry's term into a small local array and a scalar loop sums
// them in entry order into 4 running sums (entry t into sum t mod 4), so the bits depend neither on the thread
// count nor on the vector width chosen at run time, and, since the file is built without contraction into
// FMA, not on the CPU either. The force uses t_i<xi> = J (P_i x + Q_i e) with per-node factors P, Q
// (lps_node_factors, kept in BondList::node_factors): one division per entry (1 / |y|) where eqs 7 and 33
// written out take four; each entry's J V_j is kept from the reference state (BondList::weight, written by
// pd_weighted_volume_pass), so no sweep fetches V_j or evaluates J.
// On x86-64 CPUs with AVX2 and FMA, host builds run pd_bond_step's sweeps written with AVX2 intrinsics
// (kernels/peridem/pd_bond_passes_avx2.cpp, chosen in pd_bond_step): four entries an iteration, the
// partners' columns fetched by broadcast loads and blends, every term summed in registers in the same 4-sum
// order, and |y| handed from the dilatation sweep to the force sweep (BondList::bond_length, 8 B an entry),
// which then takes no square root: the same operations in the same order as the compiler's loops, so the same
// bits (tests/test_pd_bond_passes_fast.cpp).
// When every node has the same z (a 2D deck; pd_nodes_in_one_plane) the sweeps skip z: dz = 0 exactly, so
// the bits are those of the 3D sweeps, with one column fewer to fetch per entry and a fifth less arithmetic
// (bench/README.md has the passes' rates).
//
// Per-node constants: node i belongs to grain nodes.grain[i], whose material is grains.material[g], an
// index into `lps` (PdLpsConstants::from of the scenario's material table). Wall nodes have no bonds and
// get m = theta = 0, no force and no damage.
//
// Offload builds: the passes read and write the device copies only. The node and grain columns, the bond
// list (node_factors is sized here, entered by its allocator) and the `lps` table are device-resident
// (exec::DeviceVector) and must be current there (to_device after a host-side change); `broken`, theta,
// damage and the forces are current on the host after to_host. Output pointers (broken_fraction,
// energy_density) must point into device-resident arrays too.
#include <vector>

#include "kernels/peridem/pd_material.hpp"

namespace debris {

class PdNodes;
struct PdGrains;
class BondList;

/// m_i of eq 34 over all bonds of i (broken or not: m is a property of the reference configuration), and
/// each entry's weight J V_j into bonds.weight, which the other passes read: run it after building (or
/// restoring) the bonds. Throws InputError if a particle grain's material index is outside `lps`.
void pd_weighted_volume_pass(const PdLpsTable& lps, const PdGrains& grains, BondList& bonds, PdNodes& nodes);

/// theta_i of eqs 13/34 from the current positions over the intact bonds (h = 0 for broken ones).
void pd_dilatation_pass(const PdLpsTable& lps, const PdGrains& grains, const BondList& bonds,
                        PdNodes& nodes);

/// Adds V_i F_i (eq 33 over the intact bonds) to the node force. Needs theta of every node (this step).
void pd_bond_force_pass(const PdLpsTable& lps, const PdGrains& grains, const BondList& bonds,
                        PdNodes& nodes);

/// Eq 11, then theta and the bond forces: marks as broken, for ever, every intact bond whose current stretch
/// is >= s_0 (both ends of a bond compute bitwise the same stretch, so they always agree), then computes
/// theta over the intact bonds and adds their forces. Returns the number of bonds (not entries) that broke
/// in this step: the runner rebuilds the contact list when it is > 0 (broken bonds contact).
long pd_bond_step(const PdLpsTable& lps, const PdGrains& grains, BondList& bonds, PdNodes& nodes);

/// How many pd_bond_step calls of this process ran which sweeps: the portable ones (pd_bond_passes.cpp) or
/// the same written with AVX2 intrinsics (pd_bond_passes_avx2.cpp), which x86-64 host builds run on CPUs
/// with AVX2 and FMA. The tests read it to say which sweeps they compared, and to fail on such a CPU if the
/// AVX2 sweeps did not run.
struct PdBondStepCounts {
  long long portable = 0, avx2 = 0;
};
PdBondStepCounts pd_bond_step_counts();

/// True when every node has the same finite z (a 2D deck: the inputs put its nodes at z = 0), which the bond
/// passes check on each call; they then leave z out of |y| and the force (no z component: it is exactly 0).
bool pd_nodes_in_one_plane(const PdNodes& nodes);

/// Damage Z_i (eq 14) into nodes.damage: the largest |s| / s_0 over all bonds of i, broken or not.
/// Eq 14 writes |u_j - u_i| / |x_j - x_i|, which a rigid rotation makes nonzero (a grain turned by 90 degrees
/// would read Z = 1.4 / s_0 everywhere); the authors' code (PeriDEM, DEMModel::computePeridynamicForces)
/// measures |stretch| / s_0 instead, which is what the paper's damage plots show, and so do we.
/// Optionally, `broken_fraction` (size nodes.size(), or null) receives the fraction of i's bonds that are
/// broken (0 for nodes without bonds): the usual peridynamic damage, a second diagnostic.
void pd_damage_pass(const PdLpsTable& lps, const PdGrains& grains, const BondList& bonds,
                    PdNodes& nodes, double* broken_fraction = nullptr);

/// LPS energy density W_i (header of pd_material.hpp) of every node into `energy_density` (size nodes.size(); 0
/// for nodes without bonds; pd_elastic_energy sums V_i W_i of it),
/// from the current positions and the theta column (run pd_dilatation_pass first).
void pd_energy_density_pass(const PdLpsTable& lps, const PdGrains& grains, const BondList& bonds,
                            const PdNodes& nodes, double* energy_density);

/// Elastic energy of the grains, sum_i V_i W_i (J; J/m in 2D), from the theta column (run
/// pd_dilatation_pass first). Its gradient is minus the force of pd_bond_force_pass for fixed bond states.
double pd_elastic_energy(const PdLpsTable& lps, const PdGrains& grains, const BondList& bonds,
                         const PdNodes& nodes);

}  // namespace debris
