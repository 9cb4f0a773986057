#pragma once
// Eq 11 on its own, for the tests: a plain host loop over the bond list, written from the paper (and the
// PeriDEM code's compression rule where a material asks for it), as the reference the fused production pass
// pd_bond_step (break + dilatation + force in one sweep) is checked against.
#include <cmath>

#include "core/bond_list.hpp"
#include "core/pd_nodes.hpp"
#include "core/vec3.hpp"
#include "kernels/peridem/lps_bond_force.hpp"
#include "kernels/peridem/pd_material.hpp"

namespace debris::test {

/// Marks as broken every intact bond whose stretch |y_j - y_i| / |x_j - x_i| - 1 is >= s_0 (or |s| >= s_0),
/// on the host copies. Returns the bonds (not entries) that broke.
inline long break_bonds_reference(const PdLpsTable& lps, const PdGrains& grains, BondList& bonds,
                                  const PdNodes& nodes) {
  long entries = 0;
  for (int i = 0; i + 1 < static_cast<int>(bonds.offset.size()); ++i) {
    if (bonds.offset[i] == bonds.offset[i + 1]) continue;
    const PdLpsConstants& c = lps[static_cast<std::size_t>(grains.material[nodes.grain[i]])];
    for (int k = bonds.offset[i]; k < bonds.offset[i + 1]; ++k) {
      if (bonds.broken[k]) continue;
      const int j = bonds.partner[k];
      const double length = norm(Vec3{nodes.x[j] - nodes.x[i], nodes.y[j] - nodes.y[i], nodes.z[j] - nodes.z[i]});
      if (lps_bond_breaks(lps_stretch(length, bonds.length0[k]), c.critical_stretch, c.break_in_compression > 0.0)) {
        bonds.broken[k] = 1;
        ++entries;
      }
    }
  }
  return entries / 2;  // both ends broke: one bond, two entries
}

}  // namespace debris::test
