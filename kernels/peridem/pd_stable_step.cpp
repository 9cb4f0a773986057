#include "kernels/peridem/pd_stable_step.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "core/bond_list.hpp"
#include "core/exec.hpp"
#include "core/pd_nodes.hpp"
#include "kernels/peridem/pd_bond_passes.hpp"
#include "kernels/peridem/pd_integrate.hpp"

namespace debris {

namespace {

bool is_particle(const PdGrains& g, int k) { return g.kind[k] == static_cast<int>(PdGrainKind::particle); }

// Largest eigenvalue of M^-1 K for the linearised bond forces about the reference state, by power
// iteration with the Rayleigh quotient (from below; 200 iterations bring it within a few per cent on the
// paper's grains, and the caller adds a margin). K u is evaluated as -f(x0 + a u) / a with an amplitude
// a 1e-7 of the mesh size: the bond force is smooth there and f(x0) = 0.
// Offload builds: the iterate goes to the device and the forces come back each iteration (set-up only).
double bond_lambda_max(const PdNodes& reference, const PdGrains& grains, const BondList& bonds,
                       const PdLpsTable& lps, double h, int dimension) {
  const std::size_t n = reference.size();
  if (bonds.entries() == 0) return 0.0;
  PdNodes work = reference;
  to_device(work);  // a copy holds the host columns only
  std::vector<double> u(3 * n, 0.0), ku(3 * n);
  std::mt19937_64 rng(12345);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  auto movable = [&](std::size_t i) {
    return is_particle(grains, work.grain[i]) && bonds.offset[i + 1] > bonds.offset[i] && work.mass[i] > 0;
  };
  for (std::size_t i = 0; i < n; ++i)
    if (movable(i))
      for (int c = 0; c < dimension; ++c) u[3 * i + static_cast<std::size_t>(c)] = uni(rng);
  double lambda = 0.0;
  for (int it = 0; it < 200; ++it) {
    double umax = 0.0;
    for (double v : u) umax = std::max(umax, std::abs(v));
    if (umax == 0.0) return 0.0;
    for (double& v : u) v /= umax;  // keep the iterate O(1)
    const double a = 1e-7 * h;
    for (std::size_t i = 0; i < n; ++i) {
      work.x[i] = reference.x0[i] + a * u[3 * i];
      work.y[i] = reference.y0[i] + a * u[3 * i + 1];
      work.z[i] = reference.z0[i] + a * u[3 * i + 2];
    }
    exec::to_device(work.x);
    exec::to_device(work.y);
    exec::to_device(work.z);
    pd_zero_forces(work);
    pd_dilatation_pass(lps, grains, bonds, work);
    pd_bond_force_pass(lps, grains, bonds, work);
    exec::to_host(work.fx);
    exec::to_host(work.fy);
    exec::to_host(work.fz);
    double uku = 0.0, umu = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      if (!movable(i)) continue;
      const double f[3] = {work.fx[i], work.fy[i], work.fz[i]};
      for (int c = 0; c < 3; ++c) {
        const std::size_t k = 3 * i + static_cast<std::size_t>(c);
        ku[k] = -f[c] / a;
        uku += u[k] * ku[k];
        umu += u[k] * work.mass[i] * u[k];
      }
    }
    lambda = uku / umu;
    for (std::size_t i = 0; i < n; ++i)
      for (int c = 0; c < 3; ++c) {
        const std::size_t k = 3 * i + static_cast<std::size_t>(c);
        u[k] = movable(i) && c < dimension ? ku[k] / work.mass[i] : 0.0;
      }
  }
  return lambda;
}

}  // namespace

double pd_stable_time_step(const PdNodes& nodes, const PdGrains& grains, const BondList& bonds, const PdLpsTable& lps,
                           const std::vector<PdMaterial>& materials, const PdContactTable& table, double mesh_size) {
  // Stability of eq 32: omega_max^2 of the linearised bonds (power iteration) plus that of one contact
  // spring k = K_n V_i V_j (eq 17 linearised) between the largest nodes of two bodies that can touch:
  // k (1/m_i + 1/m_j) = K_n (V_j / rho_i + V_i / rho_j) between particle nodes, K_n V_j / rho_i against a
  // wall node (a wall is rigid: infinite mass). Walls never touch walls. Both are per-node stiffnesses, so
  // the sum bounds the combination from above (Weyl), up to the power iteration's estimate, which gets a
  // 10% margin.
  int dimension = 2;
  for (const PdMaterial& m : materials) dimension = std::max(dimension, m.dimension);
  const double lambda_bonds =
      1.10 * bond_lambda_max(nodes, grains, bonds, lps, mesh_size, dimension);
  const std::size_t nm = materials.size();
  std::vector<double> vmax_particle(nm, 0.0), vmax_wall(nm, 0.0);
  for (std::size_t g = 0; g < grains.size(); ++g) {
    const std::size_t mat = static_cast<std::size_t>(grains.material[g]);
    double& v = is_particle(grains, static_cast<int>(g)) ? vmax_particle[mat] : vmax_wall[mat];
    for (int i = grains.node_begin[g]; i < grains.node_end[g]; ++i) v = std::max(v, nodes.volume[i]);
  }
  double lambda_contact = 0.0;
  for (std::size_t a = 0; a < nm; ++a) {
    if (vmax_particle[a] == 0.0) continue;  // no particle of material a
    for (std::size_t b = 0; b < nm; ++b) {
      const double kn = table.pair(static_cast<int>(a), static_cast<int>(b)).k_n;
      if (vmax_particle[b] > 0.0)
        lambda_contact = std::max(lambda_contact, kn * (vmax_particle[b] / materials[a].density +
                                                        vmax_particle[a] / materials[b].density));
      if (vmax_wall[b] > 0.0) lambda_contact = std::max(lambda_contact, kn * vmax_wall[b] / materials[a].density);
    }
  }
  return 2.0 / std::sqrt(lambda_bonds + lambda_contact);
}

}  // namespace debris
