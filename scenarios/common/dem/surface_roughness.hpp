#pragma once
// The roughness of a body's face, as the wear census measures it each sample: the face is a height field (the
// envelope of the body's spheres, core/rough/surface_envelope.hpp), and its statistics are the ones
// tribologists state roughness in: rms height, rms slope (spectral: exact for the sampled field), and the Hurst
// exponent H fitted to the radially averaged PSD over the self-affine range, with the height-height
// correlation's H beside it as a check (core/rough/surface_spectrum.hpp). The range stops above the particle
// scale: a face made of spheres of diameter d is bumpy at wavelengths near d whatever its roughness, so the
// shortest wavelength fitted is a few diameters (RoughnessSettings), and the longest half the box.
#include <string>
#include <vector>

#include "core/rough/height_field.hpp"
#include "core/rough/surface_spectrum.hpp"

namespace debris {

struct FaceRoughness {
  double mean_height = 0;  // m, along the normal
  double rms_height = 0;   // m
  double rms_slope = 0;    // spectral, over the wavelengths down to `shortest` (the particles' caps left out)
  HurstFit psd;            // H from the PSD (the figure reported), over [2 pi / longest, 2 pi / shortest]
  HurstFit hhcf;           // H from the height-height correlation along a, over [shortest, longest] / 2
};

/// The statistics of `face`, fitting wavelengths from `shortest` to `longest` (m).
FaceRoughness measure_face(const HeightField& face, double shortest, double longest);

/// The columns measure_face gives surfaces.csv for a face `name` (bottom, top): name_mean_height, ... in the
/// order face_values() returns them.
std::vector<std::string> face_columns(const std::string& name);
std::vector<double> face_values(const FaceRoughness& r);

}  // namespace debris
