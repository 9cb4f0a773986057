#pragma once
// PeriDEM material (paper B, Table 1 and section 2.1.1): what a user gives per material. The derived
// constants of the state-based model (eqs 9-10, plane strain in 2D) are computed from these by functions
// in kernels/pd_material.cpp.
namespace debris {

struct PdMaterial {
  double density = 0;           // rho (kg/m^3)
  double bulk_modulus = 0;      // K (Pa)
  double shear_modulus = 0;     // G (Pa)
  double fracture_energy = 0;   // G_c (J/m^2)
  double horizon = 0;           // epsilon (m)
  int dimension = 2;            // 2 (plane strain) or 3
};

}  // namespace debris
