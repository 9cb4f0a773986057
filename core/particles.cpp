#include "core/particles.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <type_traits>

#include "core/error.hpp"
#include "core/unique_ids.hpp"

namespace debris {

void Particles::resize(std::size_t n) {
  for_each_column([n](const char*, auto& col) { col.resize(n); });
}

std::size_t Particles::add(std::int64_t pid, int ptype, double px, double py, double pz, double r) {
  const std::size_t i = size();
  resize(i + 1);
  id[i] = pid;
  type[i] = ptype;
  group[i] = -1;
  x[i] = px;
  y[i] = py;
  z[i] = pz;
  radius[i] = r;
  return i;
}

void Particles::permute(const std::vector<int>& order) {
  for_each_column([&order](const char*, auto& col) {
    auto copy = col;
    for (std::size_t i = 0; i < order.size(); ++i) col[i] = copy[static_cast<std::size_t>(order[i])];
  });
}

#if defined(DEBRIS_OFFLOAD_TARGET)
namespace {
// A named function, not the visiting lambda: clang 19 crashes on a target region inside a generic lambda.
template <class Column>
void gather_on_device(Column& col, const int* __restrict o, int n) {
  Column out(col.size());
  auto* __restrict dst = out.data();
  const auto* __restrict src = col.data();
  DEBRIS_RESIDENT(dst, src, o);
  DEBRIS_KERNEL
  for (int i = 0; i < n; ++i) dst[i] = src[o[i]];
  col.swap(out);  // the buffers swap, and their mappings with them
}
}  // namespace
#endif

void Particles::permute_resident(const std::vector<int>& order) {
#if defined(DEBRIS_OFFLOAD_TARGET)
  exec::DeviceVector<int> ord(order.begin(), order.end());
  exec::to_device(ord);
  permute_resident(ord);
#else
  permute(order);
#endif
}

#if defined(DEBRIS_OFFLOAD_TARGET)
void Particles::permute_resident(const exec::DeviceVector<int>& order) {
  // On the device: each column gathered into a scratch column, whose buffer then swaps in.
  const int n = static_cast<int>(order.size());
  const int* o = order.data();
  for_each_column([n, o](const char*, auto& col) { gather_on_device(col, o, n); });
}
#endif

void to_host(const Particles& p) {
  p.for_each_column([](const char*, const auto& col) { exec::to_host(col); });
}

void to_device(const Particles& p) {
  p.for_each_column([](const char*, const auto& col) { exec::to_device(col); });
}

std::size_t Particles::remove_if(const std::vector<char>& remove) {
  const std::size_t n = size();
  std::size_t kept = 0;
  for (std::size_t i = 0; i < n; ++i) kept += remove[i] ? 0 : 1;
  if (kept == n) return 0;
  // In place: each column is compacted front to back (the write index never passes the read index).
  for_each_column([&remove, n](const char*, auto& col) {
    std::size_t w = 0;
    for (std::size_t i = 0; i < n; ++i)
      if (!remove[i]) col[w++] = col[i];
    col.resize(w);
  });
  return n - kept;
}

std::int64_t Particles::max_id() const {
  return id.empty() ? -1 : *std::max_element(id.begin(), id.end());
}

void Particles::check_column(const std::string& name, const std::string& key) const {
  const auto which = [this](std::size_t i) {
    return " (particle id " + std::to_string(id[i]) + " at index " + std::to_string(i) + ")";
  };
  if (name == "id") {
    require_unique_ids(id, key, "particle");
    return;
  }
  bool found = false;
  for_each_column([&](const char* n, const auto& col) {
    if (found || name != n) return;
    found = true;
    using T = std::decay_t<decltype(col[0])>;
    for (std::size_t i = 0; i < col.size(); ++i) {
      const T v = col[i];
      if constexpr (std::is_floating_point_v<T>) {
        // Mass, inertia and radius divide (accelerations, eq 6's stiffness): zero or negative is no particle.
        const bool positive = name == "radius" || name == "mass" || name == "inertia";
        if (!std::isfinite(v)) throw input_error(key, format_value(v), "must be finite" + which(i));
        if (positive && !(v > 0)) throw input_error(key, format_value(v), "must be > 0" + which(i));
      } else if (name == "type" && v < 1) {
        throw input_error(key, std::to_string(v), "types must be >= 1, as in LAMMPS" + which(i));
      } else if (name == "group" && v < -1) {
        throw input_error(key, std::to_string(v), "must be a group's index, or -1 for no group" + which(i));
      } else if (name == "label" && (v < 0 || static_cast<std::size_t>(v) > label_names.size())) {
        throw input_error(key, std::to_string(v),
                          (label_names.empty() ? std::string("must be 0: this system names no labels")
                                               : "must be 0 (none) or 1 to " + std::to_string(label_names.size()) +
                                                     " (a label's number)") +
                              which(i));
      }
    }
  });
  if (!found) throw input_error(key, name, "no such particle column");
}

void Particles::set_mass_from_density(double density) {
  for (std::size_t i = 0; i < size(); ++i) {
    const double r = radius[i];
    mass[i] = density * 4.0 / 3.0 * std::numbers::pi * r * r * r;
    inertia[i] = 0.4 * mass[i] * r * r;
  }
}

}  // namespace debris
