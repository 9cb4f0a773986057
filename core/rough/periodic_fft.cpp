#include "core/rough/periodic_fft.hpp"

#include <fftw3.h>

#include <mutex>

namespace debris {

namespace {

// FFTW's planner and fftw_destroy_plan share global state; fftw_execute does not.
std::mutex& planner_mutex() {
  static std::mutex m;
  return m;
}

fftw_complex* as_fftw(std::complex<double>* z) { return reinterpret_cast<fftw_complex*>(z); }  // same layout

void execute_and_destroy(fftw_plan plan) {
  fftw_execute(plan);
  std::lock_guard<std::mutex> lock(planner_mutex());
  fftw_destroy_plan(plan);
}

}  // namespace

std::vector<std::complex<double>> forward_real_fft(const std::vector<double>& h, int n_a, int n_b) {
  std::vector<double> in(h);  // FFTW's planner takes a non-const array (r2c preserves it)
  std::vector<std::complex<double>> out(HalfSpectrum(n_a, n_b).size());
  fftw_plan plan;
  {
    std::lock_guard<std::mutex> lock(planner_mutex());
    plan = n_b == 1 ? fftw_plan_dft_r2c_1d(n_a, in.data(), as_fftw(out.data()), FFTW_ESTIMATE)
                    : fftw_plan_dft_r2c_2d(n_a, n_b, in.data(), as_fftw(out.data()), FFTW_ESTIMATE);
  }
  execute_and_destroy(plan);
  return out;
}

std::vector<double> inverse_real_fft(std::vector<std::complex<double>> half, int n_a, int n_b) {
  std::vector<double> out(static_cast<std::size_t>(n_a) * n_b);
  fftw_plan plan;
  {
    std::lock_guard<std::mutex> lock(planner_mutex());
    // c2r overwrites its input: `half` is this function's own copy.
    plan = n_b == 1 ? fftw_plan_dft_c2r_1d(n_a, as_fftw(half.data()), out.data(), FFTW_ESTIMATE)
                    : fftw_plan_dft_c2r_2d(n_a, n_b, as_fftw(half.data()), out.data(), FFTW_ESTIMATE);
  }
  execute_and_destroy(plan);
  return out;
}

}  // namespace debris
