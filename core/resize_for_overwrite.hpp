#pragma once
// Sizing of per-pair arrays that are rebuilt from scratch (neighbour list, per-pair tables): std::vector's
// resize keeps the old contents and, when it grows, at least doubles the capacity, so a list that grew by
// 1% at a rebuild would copy itself and then hold twice the memory it needs.
#include <cstddef>
#include <vector>

namespace debris {

/// Makes v hold n elements whose values are to be overwritten: contents are not kept, and the capacity is
/// exactly n when it has to grow.
template <class T, class A>
void resize_for_overwrite(std::vector<T, A>& v, std::size_t n) {
  if (v.capacity() < n) {
    std::vector<T, A>().swap(v);
    v.reserve(n);
  }
  v.resize(n);
}

}  // namespace debris
