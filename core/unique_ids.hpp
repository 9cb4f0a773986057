#pragma once
// Permanent ids of particles or nodes: every one >= 0 and no two alike (restarts, dumps and contact histories
// find a particle by its id). One check for set-up and for edits of any store.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <numeric>
#include <string>
#include <vector>

#include "core/error.hpp"

namespace debris {

/// InputError naming `key` for the first negative id or the first repeated one, with the indices involved
/// (`noun`: "particle", "node").
template <class Ids>
void require_unique_ids(const Ids& id, const std::string& key, const std::string& noun) {
  std::vector<std::size_t> order(id.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(),
            [&id](std::size_t a, std::size_t b) { return id[a] < id[b] || (id[a] == id[b] && a < b); });
  if (!order.empty() && id[order.front()] < 0)
    throw input_error(key, std::to_string(id[order.front()]),
                      "ids must be >= 0 (" + noun + " id " + std::to_string(id[order.front()]) + " at index " +
                          std::to_string(order.front()) + ")");
  for (std::size_t k = 1; k < order.size(); ++k)
    if (id[order[k]] == id[order[k - 1]])
      throw input_error(key, std::to_string(id[order[k]]),
                        "ids must be unique: " + noun + " id " + std::to_string(id[order[k]]) + " at index " +
                            std::to_string(order[k - 1]) + " and at index " + std::to_string(order[k]));
}

}  // namespace debris
