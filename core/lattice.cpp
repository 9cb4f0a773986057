#include "core/lattice.hpp"

#include <climits>
#include <cmath>
#include <random>
#include <sstream>
#include <string>

#include "core/error.hpp"

namespace debris {

namespace {

// Through a stream: GCC 12 warns falsely (-Wrestrict) on chains of std::string operator+.
template <class T>
std::string triple(T a, T b, T c) {
  std::ostringstream os;
  os.precision(12);
  os << "[" << a << ", " << b << ", " << c << "]";
  return os.str();
}

void require(bool ok, const std::string& prefix, const char* key, const std::string& value, const char* valid) {
  if (!ok) throw input_error(prefix + "." + key, value, valid);
}

// U(-1, 1) from the raw 64-bit stream: std::uniform_real_distribution is not specified bit for bit,
// and a seed must give the same packing with any standard library.
double symmetric_uniform(std::mt19937_64& rng) {
  const double u = static_cast<double>(rng() >> 11) * 0x1.0p-53;  // [0, 1), 53 random bits
  return 2.0 * u - 1.0;
}

// Fractional positions of the 4 particles of one unit cell. They are shifted off the faces by the same
// amount on both sides of the period, so that a non-periodic box holds the lattice symmetrically.
struct Basis {
  double f[4][3];
};

// Conventional cubic cell: corner + three face centres.
constexpr Basis fcc_basis{{{0.25, 0.25, 0.25}, {0.75, 0.75, 0.25}, {0.75, 0.25, 0.75}, {0.25, 0.75, 0.75}}};

// Columns: first in-plane axis (period a), second in-plane axis (period a sqrt 3), c axis.
// Layer A at c = 1/4 (two particles a apart on a rectangular a x a sqrt 3 net), layer B at c = 3/4 above
// the centroids of the A triangles (offset (a/2, a sqrt 3 / 6) in the plane).
constexpr Basis hcp_basis{{{0.25, 1.0 / 6.0, 0.25},
                           {0.75, 4.0 / 6.0, 0.25},
                           {0.75, 2.0 / 6.0, 0.75},
                           {0.25, 5.0 / 6.0, 0.75}}};

double& comp(Vec3& v, int a) { return a == 0 ? v.x : (a == 1 ? v.y : v.z); }
double comp(const Vec3& v, int a) { return a == 0 ? v.x : (a == 1 ? v.y : v.z); }

// HCP axes as (first in-plane, second in-plane, c).
std::array<int, 3> hcp_axes(int c_axis) {
  std::array<int, 3> ax{};
  int k = 0;
  for (int a = 0; a < 3; ++a)
    if (a != c_axis) ax[k++] = a;
  ax[2] = c_axis;
  return ax;
}

}  // namespace

Vec3 lattice_period(const LatticeSpec& spec) {
  const double a = spec.spacing;
  if (spec.kind == LatticeKind::fcc) {
    const double edge = a * std::sqrt(2.0);
    return {edge, edge, edge};
  }
  const std::array<int, 3> ax = hcp_axes(spec.hcp_c_axis);
  Vec3 period;
  comp(period, ax[0]) = a;
  comp(period, ax[1]) = a * std::sqrt(3.0);
  comp(period, ax[2]) = a * std::sqrt(8.0 / 3.0);
  return period;
}

void validate(const LatticeSpec& s, const std::string& prefix) {
  require(std::isfinite(s.spacing) && s.spacing > 0, prefix, "spacing", format_value(s.spacing), "must be > 0");
  require(std::isfinite(s.diameter) && s.diameter > 0, prefix, "diameter", format_value(s.diameter), "must be > 0");
  require(std::isfinite(s.size_spread) && s.size_spread >= 0 && s.size_spread < 1, prefix, "size_spread",
          format_value(s.size_spread), "must be in [0, 1) (relative half-width of the diameter spread)");
  require(std::isfinite(s.displacement) && s.displacement >= 0, prefix, "displacement", format_value(s.displacement),
          "must be >= 0 (absolute amplitude)");
  const std::string cells = triple(s.cells[0], s.cells[1], s.cells[2]);
  require(s.cells[0] >= 1 && s.cells[1] >= 1 && s.cells[2] >= 1, prefix, "cells", cells, "every entry must be >= 1");
  const long long n = 4LL * s.cells[0] * s.cells[1] * s.cells[2];
  require(n <= INT_MAX, prefix, "cells", cells, "4 * cells[0] * cells[1] * cells[2] must fit in an int");
  require(s.hcp_c_axis >= 0 && s.hcp_c_axis <= 2, prefix, "hcp_c_axis", std::to_string(s.hcp_c_axis),
          "must be 0 (x), 1 (y) or 2 (z)");
  require(std::isfinite(s.origin.x) && std::isfinite(s.origin.y) && std::isfinite(s.origin.z), prefix, "origin",
          triple(s.origin.x, s.origin.y, s.origin.z), "must be finite");
}

Lattice make_lattice(const LatticeSpec& spec) {
  validate(spec);
  const Vec3 period = lattice_period(spec);
  const Basis& basis = spec.kind == LatticeKind::fcc ? fcc_basis : hcp_basis;
  // Basis column k holds the fractional coordinate along axis axes[k].
  const std::array<int, 3> axes = spec.kind == LatticeKind::fcc ? std::array<int, 3>{0, 1, 2} : hcp_axes(spec.hcp_c_axis);

  Vec3 lo = spec.origin, extent;
  for (int a = 0; a < 3; ++a) comp(extent, a) = spec.cells[a] * comp(period, a);
  Lattice out{Box(lo, lo + extent, {false, false, false}), Particles{}};

  const int n = 4 * spec.cells[0] * spec.cells[1] * spec.cells[2];
  Particles& p = out.particles;
  p.resize(static_cast<std::size_t>(n));
  std::mt19937_64 rng(spec.seed);
  int i = 0;
  for (int cz = 0; cz < spec.cells[2]; ++cz) {
    for (int cy = 0; cy < spec.cells[1]; ++cy) {
      for (int cx = 0; cx < spec.cells[0]; ++cx) {
        const int cell[3] = {cx, cy, cz};
        for (const auto& f : basis.f) {
          Vec3 r;
          for (int k = 0; k < 3; ++k) {
            const int a = axes[k];
            comp(r, a) = comp(lo, a) + (cell[a] + f[k]) * comp(period, a);
          }
          // Always four draws per particle, so that changing the spread leaves the displacements alone.
          const double d = spec.diameter * (1.0 + spec.size_spread * symmetric_uniform(rng));
          r.x += spec.displacement * symmetric_uniform(rng);
          r.y += spec.displacement * symmetric_uniform(rng);
          r.z += spec.displacement * symmetric_uniform(rng);
          p.id[i] = i + 1;  // LAMMPS numbering: ids start at 1
          p.type[i] = spec.type;
          p.group[i] = -1;
          p.x[i] = r.x;
          p.y[i] = r.y;
          p.z[i] = r.z;
          p.radius[i] = 0.5 * d;
          ++i;
        }
      }
    }
  }
  return out;
}

}  // namespace debris
