// A rough surface against the installed package (core/rough links FFTW through debris::fftw): a 64 x 64
// self-affine field scaled to 1 nm rms; its rms height is exact to round-off and its edges meet (periodic).
#include <cmath>
#include <iostream>

#include "core/rough/self_affine_surface.hpp"

int main() {
  using namespace debris;
  SelfAffineSpec spec;
  spec.hurst = 0.7;
  spec.rms_height = 1e-9;
  spec.cutoff_wavelength = 4e-9;
  const HeightField f = generate_self_affine(spec, 1, 0, 0, 64e-9, 64e-9, 64, 64);
  const double seam = std::abs(f.height(0, 10e-9) - f.height(64e-9, 10e-9));
  std::cout << "rms height " << f.rms_height() << " m, seam " << seam << " m\n";
  return std::abs(f.rms_height() - 1e-9) < 1e-21 && seam < 1e-21 ? 0 : 1;
}
