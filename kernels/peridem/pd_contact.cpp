#include "kernels/peridem/pd_contact.hpp"

#include <cmath>
#include <stdexcept>

#include "core/comm/exact_sum.hpp"
#include "core/exec.hpp"
#include "core/pd_contact_list.hpp"
#include "core/pd_nodes.hpp"
#include "kernels/peridem/pd_contact_force.hpp"

namespace debris {

namespace {

void check_sizes(const PdContactTable& table, const PdNodes& nodes, const PdGrains& grains, const PdContactList& list) {
  if (list.rows() != static_cast<int>(nodes.size()))
    throw std::logic_error("pd contact: the contact list was built for another set of nodes");
  if (static_cast<int>(list.grain_slot_offset().size()) != static_cast<int>(grains.size()) + 1)
    throw std::logic_error("pd contact: the contact list was built for another set of grains");
  for (int m : grains.material)
    if (m < 0 || m >= table.materials) throw std::logic_error("pd contact: a grain's material is not in the table");
  if (list.cutoff() < table.max_contact_radius())
    throw std::logic_error("pd contact: the contact list's cutoff is below the largest contact radius");
}

}  // namespace

void pd_grain_centres(const PdNodes& nodes, PdGrains& grains, PdContactWork& work) {
  const int ng = static_cast<int>(grains.size());
  work.grain_volume.resize(static_cast<std::size_t>(ng));
  work.grain_mass.resize(static_cast<std::size_t>(ng));
  const int* __restrict begin = grains.node_begin.data(), *__restrict end = grains.node_end.data();
  const double* __restrict x = nodes.x.data(), *__restrict y = nodes.y.data(), *__restrict z = nodes.z.data();
  const double* __restrict vx = nodes.vx.data(), *__restrict vy = nodes.vy.data(), *__restrict vz = nodes.vz.data();
  const double* __restrict volume = nodes.volume.data(), *__restrict mass = nodes.mass.data();
  double* __restrict cx = grains.cx.data(), *__restrict cy = grains.cy.data(), *__restrict cz = grains.cz.data();
  double* __restrict cvx = grains.cvx.data(), *__restrict cvy = grains.cvy.data(), *__restrict cvz = grains.cvz.data();
  double* __restrict g_vol = work.grain_volume.data(), *__restrict g_mass = work.grain_mass.data();
  DEBRIS_RESIDENT(begin, end, x, y, z, vx, vy, vz, volume, mass, cx, cy, cz, cvx, cvy, cvz, g_vol, g_mass);
  DEBRIS_KERNEL
  for (int g = 0; g < ng; ++g) {
    double v = 0.0, m = 0.0;
    Vec3 c{}, u{};
    for (int i = begin[g]; i < end[g]; ++i) {
      const double w = volume[i];
      v += w;
      m += mass[i];
      c += w * Vec3{x[i], y[i], z[i]};
      u += w * Vec3{vx[i], vy[i], vz[i]};
    }
    const double inv = v > 0.0 ? 1.0 / v : 0.0;
    cx[g] = inv * c.x;
    cy[g] = inv * c.y;
    cz[g] = inv * c.z;
    cvx[g] = inv * u.x;
    cvy[g] = inv * u.y;
    cvz[g] = inv * u.z;
    g_vol[g] = v;
    g_mass[g] = m;
  }
}

namespace {

// The node pairs of pd_contact_pass. kGivenCounts: the length of each partner's row comes from
// work.row_count (a rank's ghosts, whose rows here are partial) instead of the list's offsets.
template <bool kGivenCounts>
void node_pair_forces(const PdContactTable& table, PdDamping damping, PdNodes& nodes, const PdGrains& grains,
                      const PdContactList& list, const PdContactWork& work, double dt) {
  const int n = list.rows();
  const int* __restrict offset = list.offset().data();
  const int* __restrict index = list.index().data();
  const double* __restrict x = nodes.x.data(), *__restrict y = nodes.y.data(), *__restrict z = nodes.z.data();
  const double* __restrict vx = nodes.vx.data(), *__restrict vy = nodes.vy.data(), *__restrict vz = nodes.vz.data();
  const double* __restrict volume = nodes.volume.data(), *__restrict mass = nodes.mass.data();
  double* __restrict fx = nodes.fx.data(), *__restrict fy = nodes.fy.data(), *__restrict fz = nodes.fz.data();
  const int* __restrict grain = nodes.grain.data();
  const int* __restrict material = grains.material.data(), *__restrict kind = grains.kind.data();
  const PdContactParams* __restrict pairs = table.pairs.data();
  const int nm = table.materials;
  const int node_damping = damping == PdDamping::node_pairs ? 1 : 0;
  const int wall = static_cast<int>(PdGrainKind::wall);

  // Node pairs: eqs 16-20, and eqs 21-25 with node damping. Each pair is evaluated from both ends with
  // the same operations on negated differences, so the two ends get exactly opposite forces.
  const int* __restrict row_count = kGivenCounts ? work.row_count.data() : offset;
  DEBRIS_RESIDENT(offset, index, x, y, z, vx, vy, vz, volume, mass, fx, fy, fz, grain, material, kind, pairs, row_count);
  DEBRIS_KERNEL
  for (int i = 0; i < n; ++i) {
    if (offset[i + 1] == offset[i]) continue;
    const int count = kGivenCounts ? row_count[i] : offset[i + 1] - offset[i];
    const int gi = grain[i];
    const int mat_i = material[gi] * nm;
    const int rigid_i = kind[gi] == wall;
    const Vec3 zi{x[i], y[i], z[i]}, vi{vx[i], vy[i], vz[i]};
    const double vol_i = volume[i], mass_i = mass[i];
    const double share_i = mass_i / static_cast<double>(count);
    Vec3 f{};
    for (int k = offset[i]; k < offset[i + 1]; ++k) {
      const int j = index[k];
      const int gj = grain[j];
      const int rigid_j = kind[gj] == wall;
      const int count_j = kGivenCounts ? row_count[j] : offset[j + 1] - offset[j];
      const double share_j = mass[j] / static_cast<double>(count_j);
      const double stick = pd_stick_mass(share_i, rigid_i, share_j, rigid_j);
      const double m_eq = pd_damping_mass(mass_i, rigid_i, mass[j], rigid_j);
      const PdContactPairResult r = pd_contact_pair_force(pairs[mat_i + material[gj]], Vec3{x[j], y[j], z[j]} - zi,
                                                          Vec3{vx[j], vy[j], vz[j]} - vi, vol_i, volume[j], m_eq,
                                                          stick, dt, gi == gj, node_damping);
      f += r.force;
    }
    fx[i] += f.x;
    fy[i] += f.y;
    fz[i] += f.z;
  }
}

}  // namespace

void pd_node_pair_forces(const PdContactTable& table, PdDamping damping, PdNodes& nodes, const PdGrains& grains,
                         const PdContactList& list, const PdContactWork& work, double dt) {
  check_sizes(table, nodes, grains, list);
  if (work.row_count.empty()) return node_pair_forces<false>(table, damping, nodes, grains, list, work, dt);
  if (work.row_count.size() != nodes.size())
    throw std::logic_error("pd contact: one given row count per node is needed");
  node_pair_forces<true>(table, damping, nodes, grains, list, work, dt);
}

void pd_contact_pass(const PdContactTable& table, PdDamping damping, PdNodes& nodes, PdGrains& grains,
                     const PdContactList& list, PdContactWork& work, double dt) {
  pd_node_pair_forces(table, damping, nodes, grains, list, work, dt);
  if (damping != PdDamping::grain_centres) return;
  pd_grain_centres(nodes, grains, work);
  pd_centre_damping(table, nodes, grains, list, work);
}

void pd_centre_damping(const PdContactTable& table, PdNodes& nodes, const PdGrains& grains, const PdContactList& list,
                       PdContactWork& work) {
  pd_centre_slot_forces(table, nodes, grains, list, work);
  pd_centre_damping_spread(table, nodes, grains, list, work);
}

void pd_centre_slot_forces(const PdContactTable& table, const PdNodes& nodes, const PdGrains& grains,
                           const PdContactList& list, PdContactWork& work) {
  // Damping between grain centres, eqs 26-30: the force of each grain-pair slot.
  check_sizes(table, nodes, grains, list);
  const double* __restrict x = nodes.x.data(), *__restrict y = nodes.y.data(), *__restrict z = nodes.z.data();
  const double* __restrict vx = nodes.vx.data(), *__restrict vy = nodes.vy.data(), *__restrict vz = nodes.vz.data();
  const int* __restrict material = grains.material.data();
  const PdContactParams* __restrict pairs = table.pairs.data();
  const int nm = table.materials;
  const int ns = list.slots(), ng = static_cast<int>(grains.size());
  for (auto* v : {&work.slot_fx, &work.slot_fy, &work.slot_fz}) v->resize(static_cast<std::size_t>(ns));
  const int* __restrict owner = list.slot_owner().data(), *__restrict partner = list.slot_partner_grain().data();
  const int* __restrict partner_node = list.slot_partner_node().data();
  const int* __restrict pair_offset = list.slot_pair_offset().data();
  const int* __restrict pair_i = list.slot_pair_i().data(), *__restrict pair_j = list.slot_pair_j().data();
  // Not __restrict: with centre nodes they are pointed at the work arrays written just below.
  const double *cx = grains.cx.data(), *cy = grains.cy.data(), *cz = grains.cz.data();
  const double *cvx = grains.cvx.data(), *cvy = grains.cvy.data(), *cvz = grains.cvz.data();
  if (!work.centre_node.empty()) {
    // The centre node's position and velocity stand for the grain's centre in eqs 26-29.
    if (static_cast<int>(work.centre_node.size()) != ng)
      throw std::logic_error("pd contact: one centre node per grain is needed");
    for (auto* v : {&work.node_cx, &work.node_cy, &work.node_cz, &work.node_cvx, &work.node_cvy, &work.node_cvz})
      v->resize(static_cast<std::size_t>(ng));
    const int* __restrict centre = work.centre_node.data();
    double* __restrict ncx = work.node_cx.data(), *__restrict ncy = work.node_cy.data();
    double* __restrict ncz = work.node_cz.data(), *__restrict ncvx = work.node_cvx.data();
    double* __restrict ncvy = work.node_cvy.data(), *__restrict ncvz = work.node_cvz.data();
    DEBRIS_RESIDENT(centre, x, y, z, vx, vy, vz, ncx, ncy, ncz, ncvx, ncvy, ncvz);
    DEBRIS_KERNEL
    for (int p = 0; p < ng; ++p) {
      const int c = centre[p];
      ncx[p] = x[c];
      ncy[p] = y[c];
      ncz[p] = z[c];
      ncvx[p] = vx[c];
      ncvy[p] = vy[c];
      ncvz[p] = vz[c];
    }
    cx = ncx;
    cy = ncy;
    cz = ncz;
    cvx = ncvx;
    cvy = ncvy;
    cvz = ncvz;
  }
  const double* __restrict g_mass = work.grain_mass.data();
  double* __restrict sfx = work.slot_fx.data(), *__restrict sfy = work.slot_fy.data();
  double* __restrict sfz = work.slot_fz.data();

  // Which slots are in contact (dist(Omega_p, Omega_p') < R_c, or the onset factor times it).
  work.slot_touching.resize(static_cast<std::size_t>(ns));
  int* __restrict touching = work.slot_touching.data();
  DEBRIS_RESIDENT(owner, partner, pair_offset, pair_i, pair_j, material, pairs, x, y, z, touching);
  DEBRIS_KERNEL
  for (int s = 0; s < ns; ++s) {
    const int p = owner[s], q = partner[s];
    const PdContactParams& pp = pairs[material[p] * nm + material[q]];
    const double rc2 = pp.damping_onset * pp.damping_onset;
    int t = 0;
    for (int e = pair_offset[s]; e < pair_offset[s + 1] && !t; ++e) {
      const int i = pair_i[e], j = pair_j[e];
      const double dx = x[j] - x[i], dy = y[j] - y[i], dz = z[j] - z[i];
      t = dx * dx + dy * dy + dz * dz < rc2;
    }
    touching[s] = t;
  }

  // One force per grain pair in contact. A wall is one body of infinite mass (m_eq = 2 m_p, eq 29's limit)
  // met at every wall node in contact: each of its k touching wall-node slots carries 1/k of the force
  // toward its node, so the grain feels one wall force however finely the wall is meshed, as it feels one
  // force from a grain. (PeriDEM's demModel.cpp instead adds a full force per touching wall node with
  // m_eq = m_p; that damps a grain resting on k wall nodes k/sqrt(2) times harder than a grain hitting a
  // very heavy grain.)
  const int* __restrict grain_slot = list.grain_slot_offset().data();
  DEBRIS_RESIDENT(owner, partner, partner_node, touching, material, pairs, cx, cy, cz, cvx, cvy, cvz, x, y, z, vx, vy,
                  vz, grain_slot, g_mass, sfx, sfy, sfz);
  DEBRIS_KERNEL
  for (int s = 0; s < ns; ++s) {
    const int p = owner[s], q = partner[s], jn = partner_node[s];
    Vec3 g{};
    if (touching[s]) {
      const PdContactParams& pp = pairs[material[p] * nm + material[q]];
      const Vec3 zp{cx[p], cy[p], cz[p]}, vp{cvx[p], cvy[p], cvz[p]};
      if (jn >= 0) {
        int k = 0;
        for (int r = grain_slot[p]; r < grain_slot[p + 1]; ++r) k += touching[r] && partner[r] == q;
        g = (1.0 / static_cast<double>(k)) *
            pd_centre_damping_force(pp, Vec3{x[jn], y[jn], z[jn]} - zp, Vec3{vx[jn], vy[jn], vz[jn]} - vp,
                                    pd_damping_mass(g_mass[p], 0, 0.0, 1));
      } else {
        g = pd_centre_damping_force(pp, Vec3{cx[q], cy[q], cz[q]} - zp, Vec3{cvx[q], cvy[q], cvz[q]} - vp,
                                    pd_equivalent_mass(g_mass[p], g_mass[q]));
      }
    }
    sfx[s] = g.x;
    sfy[s] = g.y;
    sfz[s] = g.z;
  }

}

void pd_centre_damping_spread(const PdContactTable& table, PdNodes& nodes, const PdGrains& grains,
                              const PdContactList& list, PdContactWork& work) {
  // Eqs 29-30: the slot forces summed per grain and spread over its nodes; a wall node takes the opposite.
  check_sizes(table, nodes, grains, list);
  const int n = list.rows(), ng = static_cast<int>(grains.size());
  const int* __restrict grain = nodes.grain.data();
  const int* __restrict kind = grains.kind.data();
  const double* __restrict volume = nodes.volume.data();
  double* __restrict fx = nodes.fx.data(), *__restrict fy = nodes.fy.data(), *__restrict fz = nodes.fz.data();
  const int wall = static_cast<int>(PdGrainKind::wall);
  const int* __restrict grain_slot = list.grain_slot_offset().data();
  const double* __restrict g_vol = work.grain_volume.data();
  const double* __restrict sfx = work.slot_fx.data(), *__restrict sfy = work.slot_fy.data();
  const double* __restrict sfz = work.slot_fz.data();
  for (auto* v : {&work.grain_fx, &work.grain_fy, &work.grain_fz}) v->resize(static_cast<std::size_t>(ng));
  double* __restrict gfx = work.grain_fx.data(), *__restrict gfy = work.grain_fy.data();
  double* __restrict gfz = work.grain_fz.data();
  DEBRIS_RESIDENT(grain_slot, sfx, sfy, sfz, gfx, gfy, gfz);
  DEBRIS_KERNEL
  for (int p = 0; p < ng; ++p) {
    Vec3 g{};
    for (int s = grain_slot[p]; s < grain_slot[p + 1]; ++s) g += Vec3{sfx[s], sfy[s], sfz[s]};
    gfx[p] = g.x;
    gfy[p] = g.y;
    gfz[p] = g.z;
  }

  // Eq 30: every node of p gets V_i / |Omega_p| of the grain force; a wall node the opposite of its slots.
  const int* __restrict wall_offset = list.wall_slot_offset().data(), *__restrict wall_slot = list.wall_slot().data();
  DEBRIS_RESIDENT(grain, kind, wall_offset, wall_slot, sfx, sfy, sfz, volume, g_vol, gfx, gfy, gfz, fx, fy, fz);
  DEBRIS_KERNEL
  for (int i = 0; i < n; ++i) {
    const int gi = grain[i];
    Vec3 f{};
    if (kind[gi] == wall) {
      for (int k = wall_offset[i]; k < wall_offset[i + 1]; ++k) {
        const int s = wall_slot[k];
        f -= Vec3{sfx[s], sfy[s], sfz[s]};
      }
    } else {
      f = (volume[i] / g_vol[gi]) * Vec3{gfx[gi], gfy[gi], gfz[gi]};
    }
    fx[i] += f.x;
    fy[i] += f.y;
    fz[i] += f.z;
  }
}

void pd_wall_reaction_sums(const PdContactTable& table, PdDamping damping, const PdNodes& nodes, const PdGrains& grains,
                           const PdContactList& list, const PdContactWork& work, double dt, const unsigned char* owned_node,
                           const unsigned char* owned_grain, std::vector<comm::ExactSum>& sums) {
  check_sizes(table, nodes, grains, list);
  const int n = list.rows();
  const auto& offset = list.offset();
  const auto& index = list.index();
  const int wall = static_cast<int>(PdGrainKind::wall);
  const int node_damping = damping == PdDamping::node_pairs ? 1 : 0;
  const bool given = !work.row_count.empty();
  const auto count_of = [&](int i) { return given ? work.row_count[static_cast<std::size_t>(i)] : offset[i + 1] - offset[i]; };
  const auto add = [&](int g, Vec3 f) {
    const auto at = 3 * static_cast<std::size_t>(grains.id[static_cast<std::size_t>(g)]);
    if (at + 3 > sums.size()) throw std::logic_error("pd_wall_reaction_sums: a grain id beyond the sums");
    sums[at].add(f.x);
    sums[at + 1].add(f.y);
    sums[at + 2].add(f.z);
  };
  // The node pairs, as pd_node_pair_forces evaluates them from the particle's end.
  for (int i = 0; i < n; ++i) {
    const int gi = nodes.grain[i];
    if ((owned_node && !owned_node[i]) || grains.kind[gi] == wall || offset[i + 1] == offset[i]) continue;
    const int mat_i = grains.material[gi] * table.materials;
    const Vec3 zi{nodes.x[i], nodes.y[i], nodes.z[i]}, vi{nodes.vx[i], nodes.vy[i], nodes.vz[i]};
    const double share_i = nodes.mass[i] / static_cast<double>(count_of(i));
    for (int k = offset[i]; k < offset[i + 1]; ++k) {
      const int j = index[k];
      const int gj = nodes.grain[j];
      if (grains.kind[gj] != wall) continue;
      const double share_j = nodes.mass[j] / static_cast<double>(count_of(j));
      const double stick = pd_stick_mass(share_i, 0, share_j, 1);
      const double m_eq = pd_damping_mass(nodes.mass[i], 0, nodes.mass[j], 1);
      const PdContactPairResult r = pd_contact_pair_force(
          table.pairs[static_cast<std::size_t>(mat_i + grains.material[gj])], Vec3{nodes.x[j], nodes.y[j], nodes.z[j]} - zi,
          Vec3{nodes.vx[j], nodes.vy[j], nodes.vz[j]} - vi, nodes.volume[i], nodes.volume[j], m_eq, stick, dt, false,
          node_damping);
      add(gj, -r.force);
    }
  }
  if (damping != PdDamping::grain_centres) return;
  // The centre damping: a wall node takes the opposite of each slot toward it (pd_centre_damping).
  for (int s = 0; s < list.slots(); ++s) {
    const int p = list.slot_owner()[s];
    if (list.slot_partner_node()[s] < 0 || (owned_grain && !owned_grain[p])) continue;
    add(list.slot_partner_grain()[s], Vec3{-work.slot_fx[static_cast<std::size_t>(s)], -work.slot_fy[static_cast<std::size_t>(s)],
                                           -work.slot_fz[static_cast<std::size_t>(s)]});
  }
}

void pd_wall_reactions(const PdNodes& nodes, const PdGrains& grains, exec::DeviceVector<Vec3>& reaction) {
  const int ng = static_cast<int>(grains.size());
  reaction.resize(static_cast<std::size_t>(ng));
  const int* __restrict begin = grains.node_begin.data(), *__restrict end = grains.node_end.data();
  const int* __restrict kind = grains.kind.data();
  const double* __restrict fx = nodes.fx.data(), *__restrict fy = nodes.fy.data(), *__restrict fz = nodes.fz.data();
  Vec3* __restrict out = reaction.data();
  const int wall = static_cast<int>(PdGrainKind::wall);
  DEBRIS_RESIDENT(begin, end, kind, fx, fy, fz, out);
  DEBRIS_KERNEL
  for (int g = 0; g < ng; ++g) {
    Vec3 r{};
    if (kind[g] == wall)
      for (int i = begin[g]; i < end[g]; ++i) r += Vec3{fx[i], fy[i], fz[i]};
    out[g] = r;
  }
}

double pd_contact_elastic_energy(const PdContactTable& table, const PdNodes& nodes, const PdGrains& grains,
                                 const PdContactList& list) {
  exec::DeviceVector<double> rows(static_cast<std::size_t>(list.rows()));
  pd_contact_energy_rows(table, nodes, grains, list, rows.data());
  exec::to_host(rows);
  comm::ExactSum sum;  // any order, the same bits
  for (const double e : rows) sum.add(e);
  return sum.value();
}

void pd_contact_energy_rows(const PdContactTable& table, const PdNodes& nodes, const PdGrains& grains,
                            const PdContactList& list, double* row_energy) {
  check_sizes(table, nodes, grains, list);
  const int n = list.rows();
  const int* offset = list.offset().data();
  const int* index = list.index().data();
  const double *x = nodes.x.data(), *y = nodes.y.data(), *z = nodes.z.data();
  const double* volume = nodes.volume.data();
  const int* grain = nodes.grain.data();
  const int* material = grains.material.data();
  const PdContactParams* pairs = table.pairs.data();
  const int nm = table.materials;
  DEBRIS_RESIDENT(offset, index, x, y, z, volume, grain, material, pairs, row_energy);
  DEBRIS_KERNEL
  for (int i = 0; i < n; ++i) {
    double energy = 0.0;
    for (int k = offset[i]; k < offset[i + 1]; ++k) {
      const int j = index[k];
      const double d = norm(Vec3{x[j] - x[i], y[j] - y[i], z[j] - z[i]});
      energy += 0.5 * pd_contact_energy(pairs[material[grain[i]] * nm + material[grain[j]]], d, volume[i], volume[j]);
    }
    row_energy[i] = energy;
  }
}

long pd_touching_pairs(const PdContactTable& table, const PdNodes& nodes, const PdGrains& grains,
                       const PdContactList& list) {
  check_sizes(table, nodes, grains, list);
  const int n = list.rows();
  const int* offset = list.offset().data();
  const int* index = list.index().data();
  const double *x = nodes.x.data(), *y = nodes.y.data(), *z = nodes.z.data();
  const int* grain = nodes.grain.data();
  const int* material = grains.material.data();
  const PdContactParams* pairs = table.pairs.data();
  const int nm = table.materials;
  long touching = 0;
  DEBRIS_RESIDENT(offset, index, x, y, z, grain, material, pairs);
  DEBRIS_KERNEL_SUM(touching)
  for (int i = 0; i < n; ++i) {
    for (int k = offset[i]; k < offset[i + 1]; ++k) {
      const int j = index[k];
      if (j <= i) continue;  // a full list holds each pair twice
      const double rc = pairs[material[grain[i]] * nm + material[grain[j]]].r_c;
      const double dx = x[j] - x[i], dy = y[j] - y[i], dz = z[j] - z[i];
      touching += std::sqrt(dx * dx + dy * dy + dz * dz) < rc ? 1 : 0;
    }
  }
  return touching;
}

double pd_deepest_penetration(const PdContactTable& table, const PdNodes& nodes, const PdGrains& grains,
                              const PdContactList& list) {
  check_sizes(table, nodes, grains, list);
  const int n = list.rows();
  const int* offset = list.offset().data();
  const int* index = list.index().data();
  const double *x = nodes.x.data(), *y = nodes.y.data(), *z = nodes.z.data();
  const int* grain = nodes.grain.data();
  const int* material = grains.material.data();
  const PdContactParams* pairs = table.pairs.data();
  const int nm = table.materials;
  double deepest = 0.0;
  DEBRIS_RESIDENT(offset, index, x, y, z, grain, material, pairs);
  DEBRIS_KERNEL_MAX(deepest)
  for (int i = 0; i < n; ++i) {
    for (int k = offset[i]; k < offset[i + 1]; ++k) {
      const int j = index[k];
      if (grain[j] == grain[i]) continue;  // self-contact inside a broken grain is not a pair of bodies
      const double rc = pairs[material[grain[i]] * nm + material[grain[j]]].r_c;
      const double dx = x[j] - x[i], dy = y[j] - y[i], dz = z[j] - z[i];
      const double depth = (rc - std::sqrt(dx * dx + dy * dy + dz * dz)) / rc;
      deepest = depth > deepest ? depth : deepest;
    }
  }
  return deepest;
}

}  // namespace debris
