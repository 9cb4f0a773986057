#pragma once
// The `material:` block of the cohesive-DEM inputs (debris_dem, debris_patch, debris_amorphous): one reader
// of the keys of paper A's Table 1 (E, nu, tensile and shear strength, surface energy, restitution,
// density) and the coarse-graining `scaling`, so every executable accepts the same keys with the same units
// and the same messages.

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
/// `poisson_and_scaling`.
void document_cohesive_material(KeyReference& ref, const std::string& section, const CohesiveMaterial* defaults,
                                bool poisson_and_scaling = true);

/// The shortest decimal text that reads back as exactly `v` ("0.15", "73000000000"), for literal defaults.
std::string shortest_text(double v);

}  // namespace debris
