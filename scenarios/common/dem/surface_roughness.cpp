#include "scenarios/common/dem/surface_roughness.hpp"

#include <cmath>
#include <limits>
#include <numbers>

namespace debris {

FaceRoughness measure_face(const HeightField& face, double shortest, double longest) {
  FaceRoughness r;
  r.mean_height = face.mean();
  r.rms_height = face.rms_height();
  const double two_pi = 2 * std::numbers::pi;
  r.rms_slope = spectral_rms_slope(face, two_pi / shortest * (1 + 1e-9));
  r.psd = fit_hurst_from_psd(power_spectrum(face), two_pi / longest, two_pi / shortest);
  // The correlation at separation r probes wavelengths of about 2 r.
  r.hhcf = fit_hurst_from_hhcf(height_height_correlation(face, 0, 0.5), shortest / 2, longest / 2);
  return r;
}

std::vector<std::string> face_columns(const std::string& name) {
  std::vector<std::string> c;
  for (const char* s : {"_mean_height", "_rms_height", "_rms_slope", "_hurst", "_hurst_error", "_hurst_hhcf"})
    c.push_back(name + s);
  return c;
}

std::vector<double> face_values(const FaceRoughness& r) {
  // An exponent that could not be fitted (a flat face) is NaN in the CSV: blank cells would shift columns.
  const double nan = std::numeric_limits<double>::quiet_NaN();
  return {r.mean_height,
          r.rms_height,
          r.rms_slope,
          r.psd.defined ? r.psd.hurst : nan,
          r.psd.defined ? r.psd.error : nan,
          r.hhcf.defined ? r.hhcf.hurst : nan};
}

}  // namespace debris
