#pragma once
// How much memory a run may take, and the check made before a system of N particles, nodes, bonds or pairs
// is allocated: a system too large for the machine is bad input with a message saying how much it needs
// and how much there is, not a std::bad_alloc (or the kernel's out-of-memory killer) after minutes.
#include <string>

namespace debris {

struct MemoryBudget {
  double bytes = 0;  // what this process may still allocate
  std::string source;  // what limits it: "MemAvailable of /proc/meminfo", "RLIMIT_AS (ulimit -v)", ...
};

/// The smaller of the memory the kernel reports available (MemAvailable, or the physical pages where
/// /proc/meminfo is missing) and what the address-space limit RLIMIT_AS leaves this process, if one is set.
MemoryBudget memory_budget();

/// InputError for `key` = `value` when `items` of `bytes_per_item` each exceed memory_budget():
/// "... 3.2e+10 particles need about 30 TiB (1000 bytes each); this machine has 21 GiB available (MemAvailable
/// of /proc/meminfo)". `item` names one item ("particle").
void check_memory(const std::string& key, const std::string& value, double items, double bytes_per_item,
                  const std::string& item);

/// "21.5 GiB", "980 MiB": bytes in binary units for messages.
std::string format_bytes(double bytes);

}  // namespace debris
