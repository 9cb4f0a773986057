#include "core/block_sums.hpp"

#include <vector>

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

std::int64_t* ExactPartials::reserve(std::size_t n) {
  const std::size_t words = n * static_cast<std::size_t>(comm::kExactWords);
  if (v_.size() < words) v_.resize(words);
  return v_.data();
}

void ExactPartials::to_host(std::size_t n) const { exec::to_host(v_, n * static_cast<std::size_t>(comm::kExactWords)); }

void ExactPartials::add_up(int blocks, int k, comm::ExactSum* out) const {
  for (int q = 0; q < k; ++q) {
    out[q] = comm::ExactSum{};
    add_up_one(blocks, k, q, out[q]);
  }
}

void ExactPartials::add_up(int blocks, int k, double* out) const {
  for (int q = 0; q < k; ++q) {  // one quantity at a time: no allocation in a step
    comm::ExactSum sum;
    add_up_one(blocks, k, q, sum);
    out[q] = sum.value();
  }
}

void ExactPartials::add_up(int blocks, int k, double* out, bool across_ranks) const {
  if (!across_ranks) return add_up(blocks, k, out);
  std::vector<comm::ExactSum> sums(static_cast<std::size_t>(k));
  add_up(blocks, k, sums.data());
  comm::allreduce(sums.data(), k);
  for (int q = 0; q < k; ++q) out[q] = sums[static_cast<std::size_t>(q)].value();
}

void ExactPartials::add_up_one(int blocks, int k, int q, comm::ExactSum& sum) const {
  for (int b = 0; b < blocks; ++b)
    sum += comm::ExactSum(v_.data() + (static_cast<std::size_t>(b) * static_cast<std::size_t>(k) +
                                       static_cast<std::size_t>(q)) * static_cast<std::size_t>(comm::kExactWords));
}

}  // namespace debris
