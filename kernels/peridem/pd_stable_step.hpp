#pragma once
// The stable time step of PeriDEM's explicit scheme (paper B, eq 32: velocity Verlet is stable for
// dt < 2 / omega_max), beside the DEM's eq 6 (kernels/dem/cohesive_material.hpp, stability_limits).
// omega_max^2 is bounded by that of the linearised bonds about the reference state (a power iteration on
// M^-1 K, with a 10% margin) plus that of the stiffest contact spring two bodies can form (eq 17
// linearised). Set-up only: the power iteration runs the bond passes 200 times.
#include <vector>

#include "kernels/peridem/pd_contact_params.hpp"
#include "kernels/peridem/pd_material.hpp"

namespace debris {

class BondList;
class PdNodes;
struct PdGrains;

/// The stable step (s) for nodes at their reference positions (x0), their bonds and the contact table;
/// `mesh_size` is h of eq 35. Needs the weighted volumes (pd_weighted_volume_pass) and masses.
double pd_stable_time_step(const PdNodes& nodes, const PdGrains& grains, const BondList& bonds, const PdLpsTable& lps,
                           const std::vector<PdMaterial>& materials, const PdContactTable& table, double mesh_size);

}  // namespace debris
