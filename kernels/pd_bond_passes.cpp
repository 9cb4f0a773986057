#include "kernels/pd_bond_passes.hpp"

#include <cmath>
#include <string>

#include "core/bond_list.hpp"
#include "core/error.hpp"
#include "core/exec.hpp"
#include "core/pd_nodes.hpp"
#include "core/vec3.hpp"
#include "kernels/lps_bond_force.hpp"

namespace debris {

namespace {

// Host-side check before a kernel indexes `lps` through grains.material: every particle grain that owns
// nodes must name a material of the table (walls own no bonds and are never looked up).
void check_tables(const std::vector<PdLpsConstants>& lps, const PdGrains& grains, const BondList& bonds,
                  const PdNodes& nodes) {
  if (bonds.nodes() != nodes.size())
    throw input_error("bond list", std::to_string(bonds.nodes()) + " rows",
                      "must have one row per node (" + std::to_string(nodes.size()) + " nodes): rebuild it");
  for (std::size_t g = 0; g < grains.size(); ++g) {
    if (grains.kind[g] != static_cast<int>(PdGrainKind::particle)) continue;
    if (grains.node_begin[g] == grains.node_end[g]) continue;
    const int mat = grains.material[g];
    if (mat < 0 || static_cast<std::size_t>(mat) >= lps.size())
      throw input_error("grain " + std::to_string(g) + " material", std::to_string(mat),
                        "must index the material table (" + std::to_string(lps.size()) + " materials)");
  }
}

// Raw pointers of everything the kernels read, copied into locals before each loop.
struct BondView {
  int n;
  const int* offset;
  const int* partner;
  const double* length0;
  const int* grain;
  const int* material;
  const PdLpsConstants* lps;
};

BondView view(const std::vector<PdLpsConstants>& lps, const PdGrains& grains, const BondList& bonds,
              const PdNodes& nodes) {
  check_tables(lps, grains, bonds, nodes);
  return BondView{static_cast<int>(nodes.size()),
                  bonds.offset.data(),
                  bonds.partner.data(),
                  bonds.length0.data(),
                  nodes.grain.data(),
                  grains.material.data(),
                  lps.data()};
}

}  // namespace

void pd_weighted_volume_pass(const std::vector<PdLpsConstants>& lps, const PdGrains& grains, const BondList& bonds,
                             PdNodes& nodes) {
  const BondView b = view(lps, grains, bonds, nodes);
  const int n = b.n;
  const int* __restrict offset = b.offset, * __restrict partner = b.partner;
  const int* __restrict grain = b.grain, * __restrict material = b.material;
  const double* __restrict length0 = b.length0;
  const PdLpsConstants* __restrict table = b.lps;
  const double* __restrict volume = nodes.volume.data();
  double* __restrict m = nodes.weighted_volume.data();
  DEBRIS_KERNEL
  for (int i = 0; i < n; ++i) {
    double sum = 0.0;
    if (offset[i] < offset[i + 1]) {
      const double horizon = table[material[grain[i]]].horizon;
      for (int k = offset[i]; k < offset[i + 1]; ++k) {
        const double x = length0[k];
        sum += lps_weighted_volume_term(lps_influence(x / horizon), x, volume[partner[k]]);
      }
    }
    m[i] = sum;
  }
}

long pd_break_bonds_pass(const std::vector<PdLpsConstants>& lps, const PdGrains& grains, BondList& bonds,
                         const PdNodes& nodes) {
  const BondView b = view(lps, grains, bonds, nodes);
  const int n = b.n;
  const int* __restrict offset = b.offset, * __restrict partner = b.partner;
  const int* __restrict grain = b.grain, * __restrict material = b.material;
  const double* __restrict length0 = b.length0;
  const PdLpsConstants* __restrict table = b.lps;
  unsigned char* __restrict broken = bonds.broken.data();
  const double* __restrict x = nodes.x.data(), * __restrict y = nodes.y.data(), * __restrict z = nodes.z.data();
  long entries = 0;
  DEBRIS_KERNEL_SUM(entries)
  for (int i = 0; i < n; ++i) {
    if (offset[i] == offset[i + 1]) continue;
    const double s0 = table[material[grain[i]]].critical_stretch;
    const Vec3 yi{x[i], y[i], z[i]};
    for (int k = offset[i]; k < offset[i + 1]; ++k) {
      if (broken[k]) continue;
      const int j = partner[k];
      const double s = lps_stretch(norm(Vec3{x[j], y[j], z[j]} - yi), length0[k]);
      if (lps_bond_breaks(s, s0)) {
        broken[k] = 1;
        ++entries;
      }
    }
  }
  return entries / 2;  // both ends broke: one bond, two entries
}

void pd_dilatation_pass(const std::vector<PdLpsConstants>& lps, const PdGrains& grains, const BondList& bonds,
                        PdNodes& nodes) {
  const BondView b = view(lps, grains, bonds, nodes);
  const int n = b.n;
  const int* __restrict offset = b.offset, * __restrict partner = b.partner;
  const int* __restrict grain = b.grain, * __restrict material = b.material;
  const double* __restrict length0 = b.length0;
  const PdLpsConstants* __restrict table = b.lps;
  const unsigned char* __restrict broken = bonds.broken.data();
  const double* __restrict x = nodes.x.data(), * __restrict y = nodes.y.data(), * __restrict z = nodes.z.data();
  const double* __restrict volume = nodes.volume.data(), * __restrict m = nodes.weighted_volume.data();
  double* __restrict theta = nodes.theta.data();
  DEBRIS_KERNEL
  for (int i = 0; i < n; ++i) {
    if (offset[i] == offset[i + 1]) {
      theta[i] = 0.0;
      continue;
    }
    const PdLpsConstants c = table[material[grain[i]]];
    const Vec3 yi{x[i], y[i], z[i]};
    double sum = 0.0;
    for (int k = offset[i]; k < offset[i + 1]; ++k) {
      if (broken[k]) continue;  // h = 0 (eq 13)
      const int j = partner[k];
      const double x0 = length0[k];
      const double e = norm(Vec3{x[j], y[j], z[j]} - yi) - x0;
      sum += lps_dilatation_term(lps_influence(x0 / c.horizon), x0, e, volume[j]);
    }
    theta[i] = lps_dilatation(c, sum, m[i]);
  }
}

void pd_bond_force_pass(const std::vector<PdLpsConstants>& lps, const PdGrains& grains, const BondList& bonds,
                        PdNodes& nodes) {
  const BondView b = view(lps, grains, bonds, nodes);
  const int n = b.n;
  const int* __restrict offset = b.offset, * __restrict partner = b.partner;
  const int* __restrict grain = b.grain, * __restrict material = b.material;
  const double* __restrict length0 = b.length0;
  const PdLpsConstants* __restrict table = b.lps;
  const unsigned char* __restrict broken = bonds.broken.data();
  const double* __restrict x = nodes.x.data(), * __restrict y = nodes.y.data(), * __restrict z = nodes.z.data();
  const double* __restrict volume = nodes.volume.data(), * __restrict m = nodes.weighted_volume.data();
  const double* __restrict theta = nodes.theta.data();
  double* __restrict fx = nodes.fx.data(), * __restrict fy = nodes.fy.data(), * __restrict fz = nodes.fz.data();
  DEBRIS_KERNEL
  for (int i = 0; i < n; ++i) {
    if (offset[i] == offset[i + 1]) continue;
    const PdLpsConstants c = table[material[grain[i]]];
    const Vec3 yi{x[i], y[i], z[i]};
    const double theta_i = theta[i], m_i = m[i];
    Vec3 F{};
    for (int k = offset[i]; k < offset[i + 1]; ++k) {
      if (broken[k]) continue;  // h = 0 (eq 12)
      const int j = partner[k];
      F += lps_bond_force(c, Vec3{x[j], y[j], z[j]} - yi, length0[k], volume[j], theta_i, m_i, theta[j], m[j]);
    }
    // Eq 33 is a force density; the node carries V_i of it.
    fx[i] += volume[i] * F.x;
    fy[i] += volume[i] * F.y;
    fz[i] += volume[i] * F.z;
  }
}

long pd_bond_step(const std::vector<PdLpsConstants>& lps, const PdGrains& grains, BondList& bonds, PdNodes& nodes) {
  const long broke = pd_break_bonds_pass(lps, grains, bonds, nodes);
  pd_dilatation_pass(lps, grains, bonds, nodes);
  pd_bond_force_pass(lps, grains, bonds, nodes);
  return broke;
}

void pd_damage_pass(const std::vector<PdLpsConstants>& lps, const PdGrains& grains, const BondList& bonds,
                    PdNodes& nodes, double* broken_fraction) {
  const BondView b = view(lps, grains, bonds, nodes);
  const int n = b.n;
  const int* __restrict offset = b.offset, * __restrict partner = b.partner;
  const int* __restrict grain = b.grain, * __restrict material = b.material;
  const double* __restrict length0 = b.length0;
  const PdLpsConstants* __restrict table = b.lps;
  const unsigned char* __restrict broken = bonds.broken.data();
  const double* __restrict x = nodes.x.data(), * __restrict y = nodes.y.data(), * __restrict z = nodes.z.data();
  double* __restrict damage = nodes.damage.data();
  double* __restrict fraction = broken_fraction;
  DEBRIS_KERNEL
  for (int i = 0; i < n; ++i) {
    double z_max = 0.0;
    int n_broken = 0;
    if (offset[i] < offset[i + 1]) {
      const double s0 = table[material[grain[i]]].critical_stretch;
      const Vec3 yi{x[i], y[i], z[i]};
      for (int k = offset[i]; k < offset[i + 1]; ++k) {
        const int j = partner[k];
        const double s = std::fabs(lps_stretch(norm(Vec3{x[j], y[j], z[j]} - yi), length0[k]));
        z_max = s > z_max ? s : z_max;
        n_broken += broken[k];
      }
      z_max /= s0;  // 0 when s_0 is infinite
    }
    damage[i] = z_max;
    if (fraction) {
      const int count = offset[i + 1] - offset[i];
      fraction[i] = count > 0 ? static_cast<double>(n_broken) / count : 0.0;
    }
  }
}

namespace {

DEBRIS_DECLARE_TARGET
// W_i of the LPS (pd_material.hpp), from the theta column.
inline double node_energy_density(int i, const int* offset, const int* partner, const double* length0,
                                  const unsigned char* broken, const PdLpsConstants& c, const double* x,
                                  const double* y, const double* z, const double* volume, const double* m,
                                  const double* theta) {
  const Vec3 yi{x[i], y[i], z[i]};
  const double theta_i = theta[i];
  double w = lps_dilatation_energy(c, theta_i), m_intact = 0.0;
  for (int k = offset[i]; k < offset[i + 1]; ++k) {
    if (broken[k]) continue;
    const int j = partner[k];
    const double x0 = length0[k], J = lps_influence(x0 / c.horizon);
    const double e = norm(Vec3{x[j], y[j], z[j]} - yi) - x0;
    w += lps_deviatoric_energy_term(c, J, x0, e, theta_i, m[i], volume[j]);
    m_intact += lps_weighted_volume_term(J, x0, volume[j]);
  }
  return w + lps_broken_bond_energy(c, theta_i, m[i], m_intact);
}
DEBRIS_END_DECLARE_TARGET

}  // namespace

void pd_energy_density_pass(const std::vector<PdLpsConstants>& lps, const PdGrains& grains, const BondList& bonds,
                            const PdNodes& nodes, double* energy_density) {
  const BondView b = view(lps, grains, bonds, nodes);
  const int n = b.n;
  const int *offset = b.offset, *partner = b.partner, *grain = b.grain, *material = b.material;
  const double* length0 = b.length0;
  const PdLpsConstants* table = b.lps;
  const unsigned char* broken = bonds.broken.data();
  const double *x = nodes.x.data(), *y = nodes.y.data(), *z = nodes.z.data();
  const double *volume = nodes.volume.data(), *m = nodes.weighted_volume.data(), *theta = nodes.theta.data();
  double* __restrict out = energy_density;
  DEBRIS_KERNEL
  for (int i = 0; i < n; ++i) {
    out[i] = offset[i] == offset[i + 1] ? 0.0
                                        : node_energy_density(i, offset, partner, length0, broken,
                                                              table[material[grain[i]]], x, y, z, volume, m, theta);
  }
}

double pd_elastic_energy(const std::vector<PdLpsConstants>& lps, const PdGrains& grains, const BondList& bonds,
                         const PdNodes& nodes) {
  const BondView b = view(lps, grains, bonds, nodes);
  const int n = b.n;
  const int *offset = b.offset, *partner = b.partner, *grain = b.grain, *material = b.material;
  const double* length0 = b.length0;
  const PdLpsConstants* table = b.lps;
  const unsigned char* broken = bonds.broken.data();
  const double *x = nodes.x.data(), *y = nodes.y.data(), *z = nodes.z.data();
  const double *volume = nodes.volume.data(), *m = nodes.weighted_volume.data(), *theta = nodes.theta.data();
  double energy = 0.0;
  DEBRIS_KERNEL_SUM(energy)
  for (int i = 0; i < n; ++i) {
    if (offset[i] == offset[i + 1]) continue;
    energy += volume[i] * node_energy_density(i, offset, partner, length0, broken, table[material[grain[i]]], x, y, z,
                                              volume, m, theta);
  }
  return energy;
}

}  // namespace debris
