#pragma once
// The PeriDEM passes for kernel tests that build and edit their nodes, grains and bonds on the host: each
// wrapper sends every input to the device, runs the pass there and brings its outputs back (core/exec.hpp's
// named transfer points; all no-ops in host builds, where this is the pass itself). Output pointers the
// tests hold on the host (damage fractions, energy densities, wall reactions) go through device scratch.
// Engine-level tests use PeridemSimulation, which keeps the state on the device and transfers it itself.
#include <algorithm>
#include <cstddef>
#include <vector>

#include "core/bond_list.hpp"
#include "core/exec.hpp"
#include "core/pd_contact_list.hpp"
#include "core/pd_nodes.hpp"
#include "kernels/peridem/pd_bond_passes.hpp"
#include "kernels/peridem/pd_contact.hpp"
#include "kernels/peridem/pd_integrate.hpp"

namespace debris::test {

inline void send(const PdLpsTable& lps, const PdGrains& grains, const BondList& bonds, const PdNodes& nodes) {
  exec::to_device(lps);
  to_device(grains);
  to_device(bonds);
  to_device(nodes);
}

inline void pd_weighted_volume_pass(const PdLpsTable& lps, const PdGrains& grains, BondList& bonds, PdNodes& nodes) {
  send(lps, grains, bonds, nodes);
  debris::pd_weighted_volume_pass(lps, grains, bonds, nodes);
  to_host(nodes);
  exec::to_host(bonds.weight);
}

inline void pd_dilatation_pass(const PdLpsTable& lps, const PdGrains& grains, const BondList& bonds, PdNodes& nodes) {
  send(lps, grains, bonds, nodes);
  debris::pd_dilatation_pass(lps, grains, bonds, nodes);
  to_host(nodes);
}

inline void pd_bond_force_pass(const PdLpsTable& lps, const PdGrains& grains, const BondList& bonds, PdNodes& nodes) {
  send(lps, grains, bonds, nodes);
  debris::pd_bond_force_pass(lps, grains, bonds, nodes);
  to_host(nodes);
}

inline long pd_bond_step(const PdLpsTable& lps, const PdGrains& grains, BondList& bonds, PdNodes& nodes) {
  send(lps, grains, bonds, nodes);
  const long broke = debris::pd_bond_step(lps, grains, bonds, nodes);
  to_host(nodes);
  exec::to_host(bonds.broken);
  return broke;
}

inline void pd_damage_pass(const PdLpsTable& lps, const PdGrains& grains, const BondList& bonds, PdNodes& nodes,
                           double* broken_fraction = nullptr) {
  send(lps, grains, bonds, nodes);
  exec::DeviceVector<double> fraction(broken_fraction ? nodes.size() : 0);
  debris::pd_damage_pass(lps, grains, bonds, nodes, broken_fraction ? fraction.data() : nullptr);
  to_host(nodes);
  exec::to_host(fraction);
  std::copy(fraction.begin(), fraction.end(), broken_fraction);
}

inline void pd_energy_density_pass(const PdLpsTable& lps, const PdGrains& grains, const BondList& bonds,
                                   const PdNodes& nodes, double* energy_density) {
  send(lps, grains, bonds, nodes);
  exec::DeviceVector<double> w(nodes.size());
  debris::pd_energy_density_pass(lps, grains, bonds, nodes, w.data());
  exec::to_host(w);
  std::copy(w.begin(), w.end(), energy_density);
}

inline double pd_elastic_energy(const PdLpsTable& lps, const PdGrains& grains, const BondList& bonds,
                                const PdNodes& nodes) {
  send(lps, grains, bonds, nodes);
  return debris::pd_elastic_energy(lps, grains, bonds, nodes);
}

inline void pd_zero_forces(PdNodes& nodes) {
  to_device(nodes);
  debris::pd_zero_forces(nodes);
  to_host(nodes);
}

inline void pd_weight_forces(PdNodes& nodes, const PdGrains& grains, Vec3 g) {
  to_device(nodes);
  to_device(grains);
  debris::pd_weight_forces(nodes, grains, g);
  to_host(nodes);
}

inline void pd_viscous_damping(PdNodes& nodes, const PdGrains& grains, double c) {
  to_device(nodes);
  to_device(grains);
  debris::pd_viscous_damping(nodes, grains, c);
  to_host(nodes);
}

inline void pd_integrate(PdNodes& nodes, const PdGrains& grains, double dt, bool first_step = false) {
  to_device(nodes);
  to_device(grains);
  debris::pd_integrate(nodes, grains, dt, first_step);
  to_host(nodes);
}

inline void pd_grain_centres(const PdNodes& nodes, PdGrains& grains, PdContactWork& work) {
  to_device(nodes);
  to_device(grains);
  debris::pd_grain_centres(nodes, grains, work);
  to_host(grains);
}

inline void pd_contact_pass(const PdContactTable& table, PdDamping damping, PdNodes& nodes, PdGrains& grains,
                            const PdContactList& list, PdContactWork& work, double dt) {
  exec::to_device(table.pairs);
  to_device(nodes);
  to_device(grains);
  debris::pd_contact_pass(table, damping, nodes, grains, list, work, dt);
  to_host(nodes);
  to_host(grains);
}

inline void pd_wall_reactions(const PdNodes& nodes, const PdGrains& grains, std::vector<Vec3>& reaction) {
  to_device(nodes);
  to_device(grains);
  exec::DeviceVector<Vec3> r;
  debris::pd_wall_reactions(nodes, grains, r);
  exec::to_host(r);
  reaction.assign(r.begin(), r.end());
}

inline double pd_contact_elastic_energy(const PdContactTable& table, const PdNodes& nodes, const PdGrains& grains,
                                        const PdContactList& list) {
  exec::to_device(table.pairs);
  to_device(nodes);
  to_device(grains);
  return debris::pd_contact_elastic_energy(table, nodes, grains, list);
}

// The contact list's own kernels.
inline void build_list(PdContactList& list, const PdNodes& nodes, const PdGrains& grains, const BondList& bonds,
                       double cutoff, double skin) {
  to_device(nodes);
  to_device(grains);
  to_device(bonds);
  list.build(nodes, grains, bonds, cutoff, skin);
  list.to_host();
}

inline bool needs_rebuild(const PdContactList& list, const PdNodes& nodes) {
  to_device(nodes);
  return list.needs_rebuild(nodes);
}

inline long add_broken_bonds(PdContactList& list, const BondList& bonds) {
  to_device(bonds);
  const long added = list.add_broken_bonds(bonds);
  list.to_host();
  return added;
}

}  // namespace debris::test
