#include "scenarios/common/dem/dem_keys.hpp"

#include "scenarios/common/dem/cohesive_material_input.hpp"
#include "scenarios/common/dem/wear_analysis.hpp"

namespace debris {

const KeyReference& dem_keys() {
  static const KeyReference ref = [] {
    KeyReference r("debris_dem");
    document_cohesive_material(r, "material", nullptr);
    return r;
  }();
  return ref;
}

const ColumnTable& dem_thermo_table() {
  static const ColumnTable t{
      "thermo.csv",
      "One row every `output.thermo_every` steps (and at the last step); SI, or the input's own units when it "
      "gives none.",
      {
          {"step", "-", "time step number, counted from the start of the run", ""},
          {"time", "s", "simulated time", ""},
          {"kinetic_energy", "J", "translational plus rotational kinetic energy of all particles", ""},
          {"elastic_energy", "J",
           "energy stored in the pair springs: the potential of the normal force (paper A eq 3) plus the "
           "tangential springs",
           ""},
          {"max_overlap", "m", "largest interpenetration of an interacting pair (0 when none overlaps)", ""},
          {"interacting_pairs", "-", "pairs within their interaction distance delta_f", ""},
          {"<group>_fx", "N", "x component of the group's reaction: the sum of the pair forces on its members", ""},
          {"<group>_fy", "N", "y component of the group's reaction", ""},
          {"<group>_fz", "N", "z component of the group's reaction", ""},
          {"<group>_dx", "m", "x displacement of the group's centre of mass since the start of the run", ""},
          {"<group>_dy", "m", "y displacement of the group's centre of mass", ""},
          {"<group>_dz", "m", "z displacement of the group's centre of mass", ""},
      }};
  return t;
}

std::vector<ColumnTable> dem_output_columns() { return {dem_thermo_table(), WearAnalysis::table()}; }

}  // namespace debris
