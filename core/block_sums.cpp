#include "core/block_sums.hpp"

namespace debris {

double* BlockPartials::reserve(std::size_t n) {
  // The allocator enters a new buffer on the device and deletes the old one (offload builds).
  if (v_.size() < n) v_.resize(n);
  return v_.data();
}

void BlockPartials::to_host(std::size_t n) const { exec::to_host(v_, n); }

void BlockPartials::add_up(int blocks, int k, double* out) const {
  for (int q = 0; q < k; ++q) out[q] = 0.0;
  for (int b = 0; b < blocks; ++b) {
    const double* s = v_.data() + static_cast<std::size_t>(k) * static_cast<std::size_t>(b);
    for (int q = 0; q < k; ++q) out[q] += s[q];
  }
}

}  // namespace debris
