#include "scenarios/common/dem/cohesive_material_input.hpp"

#include <cstdio>
#include <cstdlib>

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

std::string shortest_text(double v) {
  char buf[40];
  for (int digits = 1; digits <= 17; ++digits) {
    std::snprintf(buf, sizeof buf, "%.*g", digits, v);
    if (std::strtod(buf, nullptr) == v) break;
  }
  return buf;
}

void document_cohesive_material(KeyReference& ref, const std::string& section, const CohesiveMaterial* defaults,
                                bool poisson_and_scaling) {
  ref.key(section).is(KeyKind::section).means("the target material properties of paper A's Table 3, from which "
                                              "every force parameter of the pair law is calibrated");
  const auto add = [&](const std::string& name, units::Dimension dim, double CohesiveMaterial::*field) -> KeyDoc& {
    KeyDoc& d = ref.key(section + "." + name).is(KeyKind::quantity).in(dim);
    if (defaults) d.fallback(shortest_text(defaults->*field));
    return d;
  };
  add("youngs_modulus", units::pressure, &CohesiveMaterial::youngs_modulus)
      .allowed("> 0")
      .means("Young's modulus E; sets the stiffnesses k_N and k_T")
      .eq("A eqs 7-8");
  add("tensile_strength", units::pressure, &CohesiveMaterial::tensile_strength)
      .allowed("> 0")
      .means("tensile strength sigma_mN; sets the elastic limit delta_e of the normal force")
      .eq("A eqs 9, 20");
  add("shear_strength", units::pressure, &CohesiveMaterial::shear_strength)
      .allowed(">= 0")
      .means("shear strength sigma_mT: the cap of the tangential spring F_mT = A_T sigma_mT")
      .eq("A eq 11");
  add("surface_energy", units::surface_energy, &CohesiveMaterial::surface_energy)
      .allowed("> 0")
      .means("surface energy gamma: sets the fracture distance delta_f = 4 gamma / sigma_mN")
      .eq("A eq 10");
  add("restitution", units::dimensionless, &CohesiveMaterial::restitution)
      .allowed("(0, 1]")
      .means("restitution coefficient eta of a two-particle collision; sets the damping c_N and c_T")
      .eq("A eqs 12-13");
  add("density", units::density, &CohesiveMaterial::density).allowed("> 0").means("mass density rho of the particles");
  if (!poisson_and_scaling) return;
  add("poisson_ratio", units::dimensionless, &CohesiveMaterial::poisson_ratio)
      .allowed("(-1, 0.25]")
      .means("Poisson's ratio nu; sets the areas A_N and A_T (A_T < 0 above 1/4)")
      .eq("A eqs 15-16");
  KeyDoc& s = ref.key(section + ".scaling").is(KeyKind::quantity).in(units::dimensionless);
  s.fallback(shortest_text(defaults ? defaults->scaling : 0.0))
      .allowed("[0, 1]")
      .means("coarse-graining exponent s for pairs larger than d_c: 0 keeps the strength, 0.5 the surface energy")
      .eq("A eqs 10, 20");
}

}  // namespace debris
