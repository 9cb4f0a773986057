#include "scenarios/common/dem/cohesive_material_input.hpp"

#include <cmath>
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
  // A whole number as its digits ("30", "73000000000"), not "3e+01" (%g's shortest).
  if (v == std::floor(v) && std::abs(v) < 1e17) {
    std::snprintf(buf, sizeof buf, "%.0f", v);
    return buf;
  }
  for (int digits = 1; digits <= 17; ++digits) {
    std::snprintf(buf, sizeof buf, "%.*g", digits, v);
    if (std::strtod(buf, nullptr) == v) break;
  }
  return buf;
}

const std::vector<CohesiveMaterialPreset>& cohesive_material_presets() {
  static const std::vector<CohesiveMaterialPreset> presets{{"table4", table4_material(), "paper A's Table 4, no units"},
                                                           {"silica", silica_material(), "paper A's Table 5, SI"}};
  return presets;
}

void document_cohesive_material(KeyReference& ref, const std::string& section, const CohesiveMaterial* defaults,
                                bool poisson_and_scaling, const std::string& when_absent) {
  std::vector<CohesiveMaterialPreset> one;
  if (defaults) one.push_back({"", *defaults, ""});
  document_cohesive_material(ref, section, one, poisson_and_scaling, when_absent);
}

void document_cohesive_material(KeyReference& ref, const std::string& section,
                                const std::vector<CohesiveMaterialPreset>& presets, bool poisson_and_scaling,
                                const std::string& when_absent) {
  KeyDoc& block = ref.key(section).is(KeyKind::section).means(
      "the target material properties of paper A's Table 3, from which every force parameter of the pair law is "
      "calibrated");
  if (!when_absent.empty()) block.fallback_is(when_absent);
  const bool named = !presets.empty() && !presets.front().name.empty();
  if (named) {
    std::vector<std::string> names;
    std::string sources;
    for (const CohesiveMaterialPreset& p : presets) {
      names.push_back(p.name);
      sources += (sources.empty() ? "" : "; ") + p.name + ": " + p.source;
    }
    ref.key(section + ".preset")
        .one_of(names)
        .fallback(names.front())
        .means("the material whose values the keys left out take (" + sources + ")");
  }
  // One literal default where every preset agrees, else each preset's value in words.
  const auto set_default = [&](KeyDoc& d, double CohesiveMaterial::*field) {
    if (presets.empty()) return;
    bool same = true;
    for (const CohesiveMaterialPreset& p : presets) same = same && p.values.*field == presets.front().values.*field;
    if (same) {
      d.fallback(shortest_text(presets.front().values.*field));
      return;
    }
    std::string text;
    for (const CohesiveMaterialPreset& p : presets) {
      text += (text.empty() ? "" : "; ") + p.name + ": " + shortest_text(p.values.*field);
    }
    d.fallback_is(text);
  };
  const auto add = [&](const std::string& name, units::Dimension dim, double CohesiveMaterial::*field) -> KeyDoc& {
    KeyDoc& d = ref.key(section + "." + name).is(KeyKind::quantity).in(dim);
    set_default(d, field);
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
  if (presets.empty()) s.fallback("0");
  else set_default(s, &CohesiveMaterial::scaling);
  s.allowed("[0, 1]")
      .means("coarse-graining exponent s for pairs larger than d_c: 0 keeps the strength, 0.5 the surface energy")
      .eq("A eqs 10, 20");
}

}  // namespace debris
