#include "scenarios/common/dem/cohesive_material_input.hpp"

namespace debris {

CohesiveMaterial read_cohesive_material(const InputNode& m, CohesiveMaterial mat, CohesiveMaterialKeys keys) {
  const auto read = [&](const char* key, units::Dimension dim, double& value) {
    value = keys.required ? m.quantity(key, dim) : m.quantity(key, dim, value);
  };
  read("youngs_modulus", units::pressure, mat.youngs_modulus);
  read("tensile_strength", units::pressure, mat.tensile_strength);
  read("shear_strength", units::pressure, mat.shear_strength);
  read("surface_energy", units::surface_energy, mat.surface_energy);
  read("restitution", units::dimensionless, mat.restitution);
  read("density", units::density, mat.density);
  if (keys.poisson_and_scaling) {
    read("poisson_ratio", units::dimensionless, mat.poisson_ratio);
    mat.scaling = m.quantity("scaling", units::dimensionless, mat.scaling);  // 0 (none) unless given
    mat.validate("material");
  }
  return mat;
}

}  // namespace debris
