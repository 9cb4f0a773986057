#pragma once
// The `material:` block of the cohesive-DEM inputs (debris_dem, debris_patch, debris_amorphous): one reader
// of the keys of paper A's Table 1 (E, nu, tensile and shear strength, surface energy, restitution,
// density) and the coarse-graining `scaling`, so every executable accepts the same keys with the same units
// and the same messages.

#include <string>
#include <vector>

#include "core/io/input.hpp"
#include "kernels/dem/cohesive_material.hpp"

namespace debris {

struct CohesiveMaterialKeys {
  bool required = false;          // every physical key must be given (debris_dem); otherwise a key left out
                                  // keeps its value in `defaults`
  bool poisson_and_scaling = true;  // false: the caller reads them (debris_patch takes lists of them, a sweep)
};

/// Reads the keys present in `m` over `defaults`; validates the result (unless the caller still has to
/// read poisson_ratio and scaling, which validation depends on).
CohesiveMaterial read_cohesive_material(const InputNode& m, CohesiveMaterial defaults,
                                        CohesiveMaterialKeys keys = {});

/// Describes the keys read_cohesive_material() reads under `section` ("material"): required ones when
/// `defaults` is null, else with its values as the defaults. poisson_ratio and scaling only with
/// `poisson_and_scaling`. The section itself is required, or, for a reader that may go without it,
/// `when_absent` says what then holds ("optional: Table 4").
void document_cohesive_material(KeyReference& ref, const std::string& section, const CohesiveMaterial* defaults,
                                bool poisson_and_scaling = true, const std::string& when_absent = "");

/// A named set of defaults an input picks with `preset:` (debris_amorphous, debris_calibrate).
struct CohesiveMaterialPreset {
  std::string name;  // "table4"
  CohesiveMaterial values;
  std::string source;  // where its values come from ("A Table 4")
};

/// The presets `material.preset` (debris_amorphous) and `target.preset` (debris_calibrate) offer: table4
/// (paper A's Table 4, no units), then silica (Table 5, SI).
const std::vector<CohesiveMaterialPreset>& cohesive_material_presets();

/// As above, for a reader that first reads `preset` (a choice of `presets`' names, the first the default)
/// and takes the chosen preset's values as the defaults: described as `preset`, then each key with its
/// default per preset (one literal default where all presets agree).
void document_cohesive_material(KeyReference& ref, const std::string& section,
                                const std::vector<CohesiveMaterialPreset>& presets, bool poisson_and_scaling = true,
                                const std::string& when_absent = "");

/// The shortest decimal text that reads back as exactly `v` ("0.15", "1e-14"; a whole number as its digits,
/// "73000000000"), for literal defaults.
std::string shortest_text(double v);

}  // namespace debris
