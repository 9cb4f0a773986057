#include "core/memory_budget.hpp"

#include <sys/resource.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "core/error.hpp"

namespace debris {

namespace {

/// A "Key:   1234 kB" line of a /proc file, in bytes; negative when absent.
double proc_kib(const char* file, const std::string& key) {
  std::ifstream in(file);
  for (std::string line; std::getline(in, line);)
    if (line.compare(0, key.size() + 1, key + ":") == 0) {
      std::istringstream s(line.substr(key.size() + 1));
      double kib = -1;
      s >> kib;
      return kib >= 0 ? 1024.0 * kib : -1.0;
    }
  return -1.0;
}

}  // namespace

MemoryBudget memory_budget() {
  MemoryBudget b;
  const double available = proc_kib("/proc/meminfo", "MemAvailable");
  if (available >= 0) {
    b.bytes = available;
    b.source = "MemAvailable of /proc/meminfo";
  } else {
    b.bytes = static_cast<double>(sysconf(_SC_PHYS_PAGES)) * static_cast<double>(sysconf(_SC_PAGESIZE));
    b.source = "physical memory";
  }
  rlimit as{};
  if (getrlimit(RLIMIT_AS, &as) == 0 && as.rlim_cur != RLIM_INFINITY) {
    const double used = proc_kib("/proc/self/status", "VmSize");
    const double left = static_cast<double>(as.rlim_cur) - (used > 0 ? used : 0.0);
    if (left < b.bytes) {
      b.bytes = left > 0 ? left : 0.0;
      b.source = "RLIMIT_AS (ulimit -v) less this process's address space";
    }
  }
  return b;
}

std::string format_bytes(double bytes) {
  const char* unit[] = {"bytes", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"};
  int k = 0;
  while (bytes >= 1024.0 && k < 6) {
    bytes /= 1024.0;
    ++k;
  }
  char buf[48];
  std::snprintf(buf, sizeof buf, k == 0 ? "%.0f %s" : "%.3g %s", bytes, unit[k]);
  return buf;
}

void check_memory(const std::string& key, const std::string& value, double items, double bytes_per_item,
                  const std::string& item) {
  const double need = items * bytes_per_item;
  const MemoryBudget b = memory_budget();
  if (need <= b.bytes) return;
  std::ostringstream what;
  what.precision(3);
  what << items << " " << item << "s need about " << format_bytes(need) << " (" << bytes_per_item << " bytes each); "
       << "this machine has " << format_bytes(b.bytes) << " available (" << b.source << "): make the system smaller";
  throw input_error(key, value, what.str());
}

}  // namespace debris
