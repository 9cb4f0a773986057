#pragma once
// Building blocks of the PeriDEM kernel tests (contact parameters, pair functions, contact list, contact pass,
// integration): grains built directly in PdNodes / PdGrains on small regular grids (2D: z = 0, volumes are
// areas); bonds, where needed, filled into BondList by hand; the passes through tests/pd_on_device.hpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <numbers>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "core/bond_list.hpp"
#include "core/error.hpp"
#include "core/exec.hpp"
#include "core/pd_contact_list.hpp"
#include "core/pd_nodes.hpp"
#include "kernels/peridem/pd_contact.hpp"
#include "kernels/peridem/pd_contact_force.hpp"
#include "kernels/peridem/pd_contact_params.hpp"
#include "kernels/peridem/pd_integrate.hpp"
#include "tests/pd_on_device.hpp"

namespace debris::pd_test {

struct PdSystem {
  PdNodes nodes;
  PdGrains grains;
  BondList bonds;  // empty: no bonds

  int begin_grain(PdGrainKind kind, int material = 0) {
    const int g = static_cast<int>(grains.size());
    grains.resize(static_cast<std::size_t>(g) + 1);
    grains.node_begin[g] = grains.node_end[g] = static_cast<int>(nodes.size());
    grains.kind[g] = static_cast<int>(kind);
    grains.material[g] = material;
    return g;
  }
  int add_node(Vec3 p, double volume, double density) {
    const int g = static_cast<int>(grains.size()) - 1;
    const int i = static_cast<int>(nodes.add(static_cast<std::int64_t>(nodes.size()), g, p.x, p.y, p.z, volume));
    nodes.mass[i] = density * volume;
    grains.node_end[g] = i + 1;
    grains.volume[g] += volume;
    return i;
  }
  // nx * ny nodes at spacing h from corner o, volume h^2 (2D).
  int add_block(PdGrainKind kind, Vec3 o, int nx, int ny, double h, double density, int material = 0) {
    const int g = begin_grain(kind, material);
    for (int b = 0; b < ny; ++b)
      for (int a = 0; a < nx; ++a) add_node(o + Vec3{a * h, b * h, 0.0}, h * h, density);
    return g;
  }
  // Lattice points of spacing h within radius r of c (2D).
  int add_disk(Vec3 c, double r, double h, double density, int material = 0) {
    const int g = begin_grain(PdGrainKind::particle, material);
    const int m = static_cast<int>(r / h);
    for (int b = -m; b <= m; ++b)
      for (int a = -m; a <= m; ++a)
        if (a * a + b * b <= m * m) add_node(c + Vec3{a * h, b * h, 0.0}, h * h, density);
    return g;
  }
  void set_velocity(int g, Vec3 v) {
    for (int i = grains.node_begin[g]; i < grains.node_end[g]; ++i) {
      nodes.vx[i] = v.x;
      nodes.vy[i] = v.y;
      nodes.vz[i] = v.z;
    }
  }
  Vec3 position(int i) const { return {nodes.x[i], nodes.y[i], nodes.z[i]}; }
  Vec3 velocity(int i) const { return {nodes.vx[i], nodes.vy[i], nodes.vz[i]}; }
  Vec3 force(int i) const { return {nodes.fx[i], nodes.fy[i], nodes.fz[i]}; }
  int nodes_of(int g) const { return grains.node_end[g] - grains.node_begin[g]; }
};

// Bonds by hand (BondList::build is written elsewhere): every pair of one particle grain closer than the
// horizon in the reference positions, rows ascending.
inline void bond_within(PdSystem& s, double horizon) {
  BondList& b = s.bonds;
  const int n = static_cast<int>(s.nodes.size());
  b.offset.assign(1, 0);
  b.partner.clear();
  b.length0.clear();
  b.broken.clear();
  for (int i = 0; i < n; ++i) {
    const int g = s.nodes.grain[i];
    if (s.grains.kind[g] == static_cast<int>(PdGrainKind::particle)) {
      for (int j = s.grains.node_begin[g]; j < s.grains.node_end[g]; ++j) {
        const double r =
            norm(Vec3{s.nodes.x0[j] - s.nodes.x0[i], s.nodes.y0[j] - s.nodes.y0[i], s.nodes.z0[j] - s.nodes.z0[i]});
        if (j != i && r < horizon) {
          b.partner.push_back(j);
          b.length0.push_back(r);
          b.broken.push_back(0);
        }
      }
    }
    b.offset.push_back(static_cast<int>(b.partner.size()));
  }
}

// Breaks the bond (i, j) at both ends.
inline void break_bond(BondList& b, int i, int j) {
  for (auto [a, c] : {std::pair{i, j}, std::pair{j, i}})
    for (int k = b.offset[a]; k < b.offset[a + 1]; ++k)
      if (b.partner[k] == c) b.broken[k] = 1;
}

// A linear spring along every intact bond: a stand-in for the peridynamic bond force (written elsewhere)
// that keeps the test grains together. Exactly antisymmetric, so it conserves momentum too.
inline void spring_pass(PdSystem& s, double k) {
  const BondList& b = s.bonds;
  for (int i = 0; i < static_cast<int>(s.nodes.size()); ++i) {
    Vec3 f{};
    for (int e = b.offset[i]; e < b.offset[i + 1]; ++e) {
      if (b.broken[e]) continue;
      const Vec3 d = s.position(b.partner[e]) - s.position(i);
      const double l = norm(d);
      f += (k * (l - b.length0[e]) / l) * d;
    }
    s.nodes.fx[i] += f.x;
    s.nodes.fy[i] += f.y;
    s.nodes.fz[i] += f.z;
  }
}

// A soft material in SI units for the dynamic tests: with h = 1 mm and V = 1 mm^2 per node, K_n V V is
// 18 K / (pi eps^5) 1e-12 N/m for horizon eps.
inline PdMaterial soft_material(double bulk_modulus, double horizon = 3e-3) {
  PdMaterial m;
  m.density = 1000;
  m.bulk_modulus = bulk_modulus;
  m.shear_modulus = 0.6 * bulk_modulus;
  m.fracture_energy = 1;
  m.horizon = horizon;
  m.dimension = 2;
  return m;
}

inline PdContactSettings settings(double restitution, double friction) {
  PdContactSettings s;
  s.restitution = restitution;
  s.friction = friction;
  return s;
}

// One force evaluation as a PeriDEM step makes it: rebuild if needed, weights, (springs), contact.
struct Stepper {
  PdContactTable table;
  PdDamping damping = PdDamping::grain_centres;
  double skin = 0.3e-3;
  double spring_k = 0.0;
  Vec3 gravity{};
  PdContactList list;
  PdContactWork work;
  int rebuilds = 0;

  void forces(PdSystem& s, double dt) {
    if (test::needs_rebuild(list, s.nodes)) {
      test::build_list(list, s.nodes, s.grains, s.bonds, table.max_contact_radius(), skin);
      ++rebuilds;
    }
    test::pd_weight_forces(s.nodes, s.grains, gravity);  // f = m g on particle nodes, 0 on walls
    if (spring_k > 0) spring_pass(s, spring_k);
    test::pd_contact_pass(table, damping, s.nodes, s.grains, list, work, dt);
  }
};

// Moves every particle grain as a rigid body (one velocity for all its nodes, kicked by the grain's total
// force), walls at their prescribed velocity: the test harness for rigid grains.
inline void rigid_update(PdSystem& s, double dt) {
  for (int g = 0; g < static_cast<int>(s.grains.size()); ++g) {
    const int b = s.grains.node_begin[g], e = s.grains.node_end[g];
    Vec3 v{s.grains.wall_vx[g], s.grains.wall_vy[g], s.grains.wall_vz[g]};
    if (s.grains.kind[g] == static_cast<int>(PdGrainKind::particle)) {
      Vec3 f{};
      double m = 0;
      for (int i = b; i < e; ++i) {
        f += s.force(i);
        m += s.nodes.mass[i];
      }
      v = s.velocity(b) + (dt / m) * f;
    }
    for (int i = b; i < e; ++i) {
      s.nodes.vx[i] = v.x;
      s.nodes.vy[i] = v.y;
      s.nodes.vz[i] = v.z;
      s.nodes.x[i] += dt * v.x;
      s.nodes.y[i] += dt * v.y;
      s.nodes.z[i] += dt * v.z;
    }
  }
}

inline Vec3 momentum(const PdSystem& s) {
  Vec3 p{};
  for (std::size_t i = 0; i < s.nodes.size(); ++i) p += s.nodes.mass[i] * s.velocity(static_cast<int>(i));
  return p;
}

inline Vec3 grain_force(const PdSystem& s, int g) {
  Vec3 f{};
  for (int i = s.grains.node_begin[g]; i < s.grains.node_end[g]; ++i) f += s.force(i);
  return f;
}

inline double grain_mass(const PdSystem& s, int g) {
  double m = 0;
  for (int i = s.grains.node_begin[g]; i < s.grains.node_end[g]; ++i) m += s.nodes.mass[i];
  return m;
}

inline bool same_bits(Vec3 a, Vec3 b) { return a.x == b.x && a.y == b.y && a.z == b.z; }

class ThreadGuard {
 public:
  ThreadGuard() : saved_(exec::threads()) {}
  ~ThreadGuard() { exec::set_threads(saved_); }

 private:
  int saved_;
};

// The paper's material M1 (Table 1) and its two-particle deck: horizon 0.6 mm.
inline PdMaterial material_m1() {
  PdMaterial m;
  m.density = 1200;
  m.bulk_modulus = 2.16e7;
  m.shear_modulus = 1.296e7;
  m.fracture_energy = 50;
  m.horizon = 6e-4;
  m.dimension = 2;
  return m;
}

inline void expect_input_error(const std::function<void()>& f, const std::string& key, const std::string& value) {
  try {
    f();
    ADD_FAILURE() << "no InputError for " << key;
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("'" + key + "'"), std::string::npos) << what;
    EXPECT_NE(what.find(value), std::string::npos) << what;
  }
}

}  // namespace debris::pd_test
