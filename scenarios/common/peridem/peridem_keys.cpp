#include "scenarios/common/peridem/peridem_keys.hpp"

namespace debris {

const KeyReference& peridem_keys() {
  static const KeyReference ref = [] {
    KeyReference r("debris_peridem");
    return r;
  }();
  return ref;
}

const ColumnTable& peridem_thermo_table() {
  static const ColumnTable t{
      "thermo.csv",
      "One row every `output.thermo_every` steps (and at the last step), in SI units. Walls are the rigid "
      "walls of `walls:`; the per-grain columns are written when the run has at most `output.grain_columns` "
      "grains.",
      {
          {"step", "-", "time step number, counted from the start of the run", ""},
          {"time", "s", "simulated time", ""},
          {"kinetic_energy", "J", "kinetic energy of all nodes", ""},
          {"bond_energy", "J", "peridynamic strain energy of the grains' bonds", ""},
          {"contact_energy", "J", "energy stored in the node-to-node and node-to-wall contact springs", ""},
          {"max_damage", "-", "largest damage Z of a node (paper B eq 14)", ""},
          {"broken_bonds", "-", "bonds broken so far", ""},
          {"contact_pairs", "-", "node pairs closer than the contact radius R_c, each counted once", ""},
          {"<wall>_fx", "N", "x component of the total contact force on the wall", ""},
          {"<wall>_fy", "N", "y component of that force", ""},
          {"<wall>_fz", "N", "z component of that force", "3D"},
          {"<grain>_x", "m", "x of the grain's centre of mass", "per grain"},
          {"<grain>_y", "m", "y of the grain's centre of mass", "per grain"},
          {"<grain>_z", "m", "z of the grain's centre of mass", "3D per grain"},
          {"<grain>_vx", "m/s", "x velocity of the grain's centre of mass", "per grain"},
          {"<grain>_vy", "m/s", "y velocity of the grain's centre of mass", "per grain"},
          {"<grain>_vz", "m/s", "z velocity of the grain's centre of mass", "3D per grain"},
          {"<grain>_kinetic_energy", "J", "the grain's kinetic energy", "per grain"},
          {"<grain>_damage", "-", "largest damage Z of the grain's nodes", "per grain"},
          {"<grain>_broken_bonds", "-", "bonds broken in the grain", "per grain"},
      }};
  return t;
}

std::vector<ColumnTable> peridem_output_columns() { return {peridem_thermo_table()}; }

}  // namespace debris
