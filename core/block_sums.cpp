#include "core/block_sums.hpp"

#include "core/exec.hpp"

namespace debris {

BlockPartials& BlockPartials::operator=(BlockPartials&& o) noexcept {
  if (this != &o) {
    release();
    v_.swap(o.v_);
  }
  return *this;
}

double* BlockPartials::reserve(std::size_t n) {
  if (v_.size() < n) {
    release();
    v_.resize(n);
    exec::device_enter(v_.data(), n * sizeof(double));
  }
  return v_.data();
}

void BlockPartials::to_host(std::size_t n) { exec::update_host(v_.data(), n * sizeof(double)); }

void BlockPartials::release() {
  if (!v_.empty()) exec::device_exit(v_.data(), v_.size() * sizeof(double));
  std::vector<double>().swap(v_);
}

}  // namespace debris
