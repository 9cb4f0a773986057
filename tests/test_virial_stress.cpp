// The average virial stress (kernels/dem/virial_stress) against exact references: one pair in closed form
// (normal law of eq 3, tangential spring and damping of eq 2), the kinetic part of free particles, and the
// strain derivative of the elastic energy of strained HCP lattices (periodic, and a free cluster for shear
// strains). Then the HCP patch-test geometry of paper section 3.1: 12 interacting neighbours from
// d0 = 0.6 d_c up, and the elastic constants of the affinely strained lattice (appendix A.2.2).
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>
#include <vector>

#include "core/box.hpp"
#include "core/contact_history.hpp"
#include "core/lattice.hpp"
#include "core/neighbor_list.hpp"
#include "core/particles.hpp"
#include "kernels/dem/cohesive_contact.hpp"
#include "kernels/dem/cohesive_material.hpp"
#include "kernels/dem/cohesive_pair_force.hpp"
#include "kernels/dem/virial_stress.hpp"

namespace debris {
namespace {

// Table 4 (d_min = 30, d_c = 150) with the Poisson ratio varied as in section 3.1, and no damping unless asked.
CohesiveMaterial table4(double nu = 0.15, double s = 0.0, double eta = 1.0) {
  CohesiveMaterial m = table4_material(s);
  m.poisson_ratio = nu;
  m.restitution = eta;
  return m;
}

// Particles with masses, a full list over them and a zero history for that list. Offload builds: made on
// the host and sent to the device, as a simulation does; the list's rows are also copied back, since the
// tests read them. A test that changes the particles or the history on the host sends them again
// (to_device) before a kernel reads them; a copied System's columns are new device buffers and are sent
// too.
struct System {
  Box box;
  Particles p;
  NeighborList list;
  ContactHistory history;
};

void build_list(System& s, const CohesiveCoefficients& c, double skin) {
  double r_max = 0;
  for (double r : s.p.radius) r_max = std::max(r_max, r);
  const CohesiveCutoff cutoff{c};
  s.list.build(s.box.view(), s.p, cutoff, cutoff(r_max, r_max), skin, NeighborKind::full);
  s.list.to_host();
  s.history.reset(s.list);
  s.history.to_host();
}

System make_system(Box box, Particles p, const CohesiveCoefficients& c, double skin) {
  System s{box, std::move(p), {}, {}};
  s.p.set_mass_from_density(1.0);
  to_device(s.p);
  build_list(s, c, skin);
  return s;
}

// Equal-radius HCP lattice, nearest neighbours touching (spacing = diameter = d0).
Lattice hcp(double d0, std::array<int, 3> cells, int c_axis = 1) {
  LatticeSpec spec;
  spec.kind = LatticeKind::hcp;
  spec.spacing = d0;
  spec.diameter = d0;
  spec.cells = cells;
  spec.hcp_c_axis = c_axis;
  return make_lattice(spec);
}

double comp(const StressTensor& s, int a, int b) {
  if (a > b) std::swap(a, b);
  if (a == b) return a == 0 ? s.xx : (a == 1 ? s.yy : s.zz);
  return a == 0 ? (b == 1 ? s.xy : s.xz) : s.yz;
}
double comp(Vec3 v, int a) { return a == 0 ? v.x : (a == 1 ? v.y : v.z); }

// ---------------------------------------------------------------------------------------------------------
// One pair and free particles, in closed form.

// Two touching-size particles (r = 50) along y, pulled or pushed to dN: sigma_yy = (d F_N) / V with
// d = 100 + dN and F_N of eq 3 (positive in tension), every other component zero.
TEST(VirialStress, PairAlongYIsDistanceTimesNormalForceOverVolume) {
  const CohesiveMaterial m = table4();
  const CohesiveCoefficients c = CohesiveCoefficients::from(m);
  const double volume = 1e6;
  for (double dn : {-5.0, 10.0, 25.0, 31.0}) {  // compression, elastic, softening, beyond delta_f = 30
    Particles p;
    p.add(1, 1, 0, 0, 0, 50);
    p.add(2, 1, 0, 100 + dn, 0, 50);
    System s = make_system(Box({-500, -500, -500}, {500, 500, 500}, {false, false, false}), p, c, 5.0);
    ASSERT_EQ(s.list.entries(), 2) << "the pair must be in the list (skin) for the dN > delta_f case to mean anything";
    const CohesivePairParams pp = cohesive_pair_params(c, 50, 50, s.p.mass[0], s.p.mass[1]);
    ASSERT_DOUBLE_EQ(pp.delta_e, 20.0);
    ASSERT_DOUBLE_EQ(pp.delta_f, 30.0);
    double f_n = 0;  // eq 3
    if (dn <= pp.delta_e) f_n = pp.k_n * dn;
    else if (dn <= pp.delta_f) f_n = -pp.k_n * pp.delta_e / (pp.delta_f - pp.delta_e) * (dn - pp.delta_f);
    const StressTensor st = virial_stress(c, CohesiveOptions{}, s.box.view(), s.p, s.list, s.history, nullptr, volume);
    const double expected = (100 + dn) * f_n / volume;
    EXPECT_NEAR(st.yy, expected, 1e-14 * std::abs(pp.k_n * 100 * 30 / volume)) << "dN " << dn;
    if (dn > 0 && dn <= pp.delta_f) EXPECT_GT(st.yy, 0.0) << "tension must be positive";
    if (dn < 0) EXPECT_LT(st.yy, 0.0) << "compression must be negative";
    if (dn > pp.delta_f) EXPECT_EQ(st.yy, 0.0);
    for (double v : {st.xx, st.zz, st.xy, st.xz, st.yz}) EXPECT_EQ(v, 0.0);
  }
}

// An oblique pair with a stored tangential spring, damping (eta < 1), velocities and spins: the virial is
// -(r_ij (x) F_ij + sum m v v) / V with F_ij the whole force of eq 2, history not advanced. The antisymmetric
// part of r (x) F is the pair torque (moment arms adding up to |r_ij|), as the header says.
TEST(VirialStress, ObliquePairIncludesTangentialSpringAndDamping) {
  const CohesiveCoefficients c = CohesiveCoefficients::from(table4(0.15, 0.0, 0.8));
  const Vec3 n{1.0 / 3.0, 2.0 / 3.0, 2.0 / 3.0};
  const double d = 100 + 8;  // elastic tension
  Particles p;
  p.add(1, 1, 0, 0, 0, 50);
  p.add(2, 1, -d * n.x, -d * n.y, -d * n.z, 50);  // n points from j (id 2) to i (id 1), as in eq 2
  System s = make_system(Box({-500, -500, -500}, {500, 500, 500}, {false, false, false}), p, c, 5.0);
  s.p.vx = {0.011, -0.004};
  s.p.vy = {-0.007, 0.009};
  s.p.vz = {0.003, 0.006};
  s.p.wx = {2e-4, -1e-4};
  s.p.wy = {-3e-4, 5e-5};
  s.p.wz = {1e-4, 2e-4};
  to_device(s.p);
  const Vec3 t1{2.0 / 3.0, 1.0 / 3.0, -2.0 / 3.0}, t2 = cross(n, t1);  // tangent plane of n
  const Vec3 h = 2.0 * t1 - 1.5 * t2;                                  // below the cap of eq 5
  ASSERT_EQ(s.list.entries(), 2);
  s.history.hx = {h.x, -h.x};  // row of i holds h, row of j the same spring seen from j
  s.history.hy = {h.y, -h.y};
  s.history.hz = {h.z, -h.z};
  s.history.to_device();
  const auto hx0 = s.history.hx;

  const double volume = 3e5;
  const StressTensor st = virial_stress(c, CohesiveOptions{}, s.box.view(), s.p, s.list, s.history, nullptr, volume);

  const Particles& q = s.p;
  const CohesivePairParams pp = cohesive_pair_params(c, 50, 50, q.mass[0], q.mass[1]);
  const CohesivePair pair{d * n, 50, 50, pp.delta_f, pp.c_n,
                          Vec3{q.vx[0], q.vy[0], q.vz[0]} - Vec3{q.vx[1], q.vy[1], q.vz[1]},
                          {q.wx[0], q.wy[0], q.wz[0]}, {q.wx[1], q.wy[1], q.wz[1]}, h, 1};
  const CohesivePairResult pr = cohesive_pair_force(c, CohesiveOptions{}, pair, 0.0, 0);
  const Vec3 r = d * n, f = pr.force;
  // The tangential and damping parts are a sizeable share of the force, so leaving them out would show.
  const Vec3 f_normal_only = -(pp.k_n * 8.0) * n;
  ASSERT_GT(norm(f - f_normal_only), 0.1 * norm(f));
  double expected[3][3];
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) {
      double kin = 0;
      for (int i = 0; i < 2; ++i) {
        const Vec3 v{q.vx[i], q.vy[i], q.vz[i]};
        kin += q.mass[i] * comp(v, a) * comp(v, b);
      }
      expected[a][b] = -(comp(r, a) * comp(f, b) + kin) / volume;
    }
  const double scale = norm(r) * norm(f) / volume;
  EXPECT_NEAR(st.xx, expected[0][0], 1e-13 * scale);
  EXPECT_NEAR(st.yy, expected[1][1], 1e-13 * scale);
  EXPECT_NEAR(st.zz, expected[2][2], 1e-13 * scale);
  EXPECT_NEAR(st.xy, expected[0][1], 1e-13 * scale);  // LAMMPS order: r_x F_y
  EXPECT_NEAR(st.xz, expected[0][2], 1e-13 * scale);
  EXPECT_NEAR(st.yz, expected[1][2], 1e-13 * scale);
  s.history.to_host();
  EXPECT_EQ(s.history.hx, hx0);

  // Pair torques from the contact pass: W_yz - W_zy = T_x over the whole sample, and so on.
  Particles torqued = s.p;
  ContactHistory hist = s.history;
  to_device(torqued);
  hist.to_device();
  cohesive_contact_pass(c, CohesiveOptions{}, s.box.view(), torqued, s.list, hist, 0.0, 0);
  to_host(torqued);
  const double tx = torqued.tx[0] + torqued.tx[1], ty = torqued.ty[0] + torqued.ty[1],
               tz = torqued.tz[0] + torqued.tz[1];
  ASSERT_GT(std::abs(tx) + std::abs(ty) + std::abs(tz), 1e-3 * norm(r) * norm(f));
  const double kin_xy = expected[0][1] + r.x * f.y / volume;  // the symmetric kinetic part, alone
  const double kin_xz = expected[0][2] + r.x * f.z / volume;
  const double kin_yz = expected[1][2] + r.y * f.z / volume;
  const double w_zy = -r.z * f.y / volume + kin_yz, w_zx = -r.z * f.x / volume + kin_xz,
               w_yx = -r.y * f.x / volume + kin_xy;
  EXPECT_NEAR((st.yz - w_zy) * volume, tx, 1e-12 * norm(r) * norm(f));
  EXPECT_NEAR((w_zx - st.xz) * volume, ty, 1e-12 * norm(r) * norm(f));
  EXPECT_NEAR((st.xy - w_yx) * volume, tz, 1e-12 * norm(r) * norm(f));
}

// Particles out of each other's reach: only -m v v, summed over the selected ones.
TEST(VirialStress, KineticPartOfFreeParticles) {
  const CohesiveCoefficients c = CohesiveCoefficients::from(table4());
  Particles p;
  p.add(1, 1, 0, 0, 0, 50);
  p.add(2, 1, 300, 0, 0, 40);
  p.add(3, 1, 0, 0, 300, 60);
  System s = make_system(Box({-500, -500, -500}, {500, 500, 500}, {false, false, false}), p, c, 5.0);
  s.p.vx = {0.3, -0.1, 0.2};
  s.p.vy = {-0.2, 0.4, 0.1};
  s.p.vz = {0.1, 0.05, -0.3};
  to_device(s.p);
  const double volume = 7e6;
  const std::vector<int> mask = {1, 0, 1};
  for (const int* sel : {static_cast<const int*>(nullptr), mask.data()}) {
    double e[3][3] = {};
    for (int i = 0; i < 3; ++i) {
      if (sel && !sel[i]) continue;
      const Vec3 v{s.p.vx[i], s.p.vy[i], s.p.vz[i]};
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) e[a][b] -= s.p.mass[i] * comp(v, a) * comp(v, b) / volume;
    }
    const StressTensor st = virial_stress(c, CohesiveOptions{}, s.box.view(), s.p, s.list, s.history, sel, volume);
    for (int a = 0; a < 3; ++a)
      for (int b = a; b < 3; ++b) EXPECT_NEAR(comp(st, a, b), e[a][b], 1e-15 * std::abs(e[0][0]));
    EXPECT_LT(st.xx, 0.0);  // motion pushes outward, like a gas pressure
    const StressTensor none = virial_stress(c, CohesiveOptions{}, s.box.view(), s.p, s.list, s.history, sel, volume, false);
    for (int a = 0; a < 3; ++a)
      for (int b = a; b < 3; ++b) EXPECT_EQ(comp(none, a, b), 0.0);
  }
}

// ---------------------------------------------------------------------------------------------------------
// The virial as the strain derivative of the elastic energy.
//
// For a strain increment e applied to the current positions, x -> (I + e) x, of a periodic sample (or a whole
// free cluster) whose forces derive from a pair potential U, dU/de_ab = -sum_pairs F_ij,a r_ij,b exactly, so
// sigma_ab V = dU/de_ab with V the current volume. This needs forces that are the gradient of U of the
// positions alone: the normal law of eq 3. The tangential spring is not such a force: its history is the
// integral of the relative tangential motion along the path (an affine normal strain already moves inclined
// pairs tangentially), so U would not be a function of the strain. Energy and virial are therefore both
// taken with options.tangential = 0; the tangential part is checked in closed form above and against the
// analytic elastic constants below.

// Elastic energy of eq 3 over all pairs (diagnostics from a freshly built list).
double normal_energy(const CohesiveCoefficients& c, Box box, Particles p) {
  System s = make_system(box, std::move(p), c, 1.0);
  CohesiveOptions normal_only;
  normal_only.tangential = 0;
  return cohesive_diagnostics(c, normal_only, s.box.view(), s.p, s.list, s.history).elastic_energy;
}

// Reference lattice stretched by factors (1 + e_a) along the axes, box with it (Box::deform).
std::pair<Box, Particles> stretched(const Lattice& lat, std::array<bool, 3> periodic, Vec3 stretch) {
  Box box(lat.box.lo(), lat.box.hi(), periodic);
  Particles p = lat.particles;
  const Vec3 len = box.length();
  box.deform(box.lo(), box.lo() + Vec3{len.x * stretch.x, len.y * stretch.y, len.z * stretch.z}, p);
  return {box, p};
}

TEST(VirialStress, EqualsStrainDerivativeOfEnergyInPeriodicHcp) {
  const CohesiveCoefficients c = CohesiveCoefficients::from(table4());  // d = 100: d_min < d < d_c
  const Lattice lat = hcp(100, {3, 2, 2});                                 // 300 x 327 x 346, 48 particles
  const std::array<bool, 3> periodic{true, true, true};
  CohesiveOptions normal_only;
  normal_only.tangential = 0;
  const double h = 1e-5;  // central differences: truncation ~h^2, round-off ~1e-16 |U| / h
  struct State {
    Vec3 strain;
    const char* name;
    bool softening;  // every interacting pair in delta_e < dN <= delta_f
  };
  const State states[] = {{{0, 1e-3, 0}, "tension along c", false},
                          {{0, -1e-3, 0}, "compression along c", false},
                          {{2e-3, -1e-3, 5e-4}, "mixed normal strains", false},
                          {{0.21, 0.21, 0.21}, "dilation into the softening branch (dN = 21)", true}};
  for (const State& st : states) {
    const Vec3 f{1 + st.strain.x, 1 + st.strain.y, 1 + st.strain.z};
    auto [box, p] = stretched(lat, periodic, f);
    System s = make_system(box, p, c, 1.0);
    const StressTensor sigma = virial_stress(c, normal_only, s.box.view(), s.p, s.list, s.history, nullptr,
                                             s.box.volume());
    // The regime the state claims to be in.
    const CohesivePairParams pp = cohesive_pair_params(c, 50, 50, s.p.mass[0], s.p.mass[0]);
    long interacting = 0, softening = 0;
    for (int i = 0; i < s.list.rows(); ++i)
      for (int k = s.list.offset()[i]; k < s.list.offset()[i + 1]; ++k) {
        const int j = s.list.index()[k];
        const Vec3 dx = minimum_image(s.box.view(), Vec3{s.p.x[i] - s.p.x[j], s.p.y[i] - s.p.y[j], s.p.z[i] - s.p.z[j]});
        const double dn = norm(dx) - 100;
        interacting += dn <= pp.delta_f;
        softening += dn > pp.delta_e && dn <= pp.delta_f;
      }
    EXPECT_EQ(interacting, 12 * static_cast<long>(s.p.size())) << st.name;
    if (st.softening) EXPECT_EQ(softening, interacting) << st.name;

    double largest = 0;
    for (int a = 0; a < 3; ++a) largest = std::max(largest, std::abs(comp(sigma, a, a)));
    for (int a = 0; a < 3; ++a) {
      Vec3 fp = f, fm = f;
      (a == 0 ? fp.x : a == 1 ? fp.y : fp.z) *= 1 + h;
      (a == 0 ? fm.x : a == 1 ? fm.y : fm.z) *= 1 - h;
      auto [bp, pp_] = stretched(lat, periodic, fp);
      auto [bm, pm] = stretched(lat, periodic, fm);
      const double du = (normal_energy(c, bp, pp_) - normal_energy(c, bm, pm)) / (2 * h);
      const double sv = comp(sigma, a, a) * s.box.volume();
      ASSERT_GT(std::abs(du), 1e-3 * largest * s.box.volume()) << st.name << " axis " << a;
      EXPECT_NEAR(sv, du, 1e-6 * std::abs(du)) << st.name << " axis " << a;
    }
    // Strains along the orthohexagonal axes keep the lattice's mirror symmetries: no shear stress.
    for (double v : {sigma.xy, sigma.xz, sigma.yz}) EXPECT_LT(std::abs(v), 1e-12 * largest) << st.name;
    if (st.strain.y > 0 && st.strain.x == 0) EXPECT_GT(sigma.yy, 0.0) << "stretched along y: sigma_yy > 0";
    if (st.strain.y < 0 && st.strain.x == 0) EXPECT_LT(sigma.yy, 0.0);

    // Every site of a homogeneously strained HCP lattice is equivalent (A and B layers are exchanged by an
    // inversion centre, which leaves a stress unchanged): one particle with its share V/N of the volume
    // measures the same stress, whichever layer it is in. This exercises the selection mask.
    std::vector<int> one(s.p.size(), 0);
    for (std::size_t i : {std::size_t{0}, std::size_t{2}}) {  // basis sites 0 (layer A) and 2 (layer B)
      std::fill(one.begin(), one.end(), 0);
      one[i] = 1;
      const StressTensor si = virial_stress(c, normal_only, s.box.view(), s.p, s.list, s.history, one.data(),
                                            s.box.volume() / static_cast<double>(s.p.size()));
      for (int a = 0; a < 3; ++a)
        for (int b = a; b < 3; ++b) EXPECT_NEAR(comp(si, a, b), comp(sigma, a, b), 1e-10 * largest) << st.name;
    }
  }
}

// Shear strains cannot be applied to an orthogonal periodic box, but the identity holds exactly for a whole
// free cluster too (the sum runs over all its pairs): a general symmetric strain, all six components.
TEST(VirialStress, EqualsStrainDerivativeOfEnergyInAShearedCluster) {
  const CohesiveCoefficients c = CohesiveCoefficients::from(table4());
  const Lattice lat = hcp(100, {2, 2, 2});
  CohesiveOptions normal_only;
  normal_only.tangential = 0;
  const double eps[3][3] = {{1e-3, 4e-4, -2e-4}, {4e-4, -5e-4, 3e-4}, {-2e-4, 3e-4, 2e-4}};
  const Box box(lat.box.lo() - Vec3{300, 300, 300}, lat.box.hi() + Vec3{300, 300, 300}, {false, false, false});
  const Vec3 centre = 0.5 * (lat.box.lo() + lat.box.hi());
  // Positions (I + de)(I + eps) X about the centre, for a symmetric increment de.
  auto strained = [&](const double de[3][3]) {
    Particles p = lat.particles;
    for (std::size_t i = 0; i < p.size(); ++i) {
      const double x0[3] = {p.x[i] - centre.x, p.y[i] - centre.y, p.z[i] - centre.z};
      double x1[3], x2[3];
      for (int a = 0; a < 3; ++a) x1[a] = x0[a] + eps[a][0] * x0[0] + eps[a][1] * x0[1] + eps[a][2] * x0[2];
      for (int a = 0; a < 3; ++a) x2[a] = x1[a] + de[a][0] * x1[0] + de[a][1] * x1[1] + de[a][2] * x1[2];
      p.x[i] = centre.x + x2[0];
      p.y[i] = centre.y + x2[1];
      p.z[i] = centre.z + x2[2];
    }
    return p;
  };
  const double zero[3][3] = {};
  System s = make_system(box, strained(zero), c, 1.0);
  const double volume = lat.box.volume();  // any volume: the identity is sigma V = dU/de
  const StressTensor sigma = virial_stress(c, normal_only, s.box.view(), s.p, s.list, s.history, nullptr, volume);
  const double h = 1e-5;
  double largest = 0;
  for (int a = 0; a < 3; ++a)
    for (int b = a; b < 3; ++b) largest = std::max(largest, std::abs(comp(sigma, a, b)));
  for (int a = 0; a < 3; ++a)
    for (int b = a; b < 3; ++b) {
      double dp[3][3] = {}, dm[3][3] = {};
      dp[a][b] = dp[b][a] = a == b ? h : 0.5 * h;  // symmetric unit increment: dU/dh = -sum r_a F_b
      dm[a][b] = dm[b][a] = -dp[a][b];
      const double du = (normal_energy(c, box, strained(dp)) - normal_energy(c, box, strained(dm))) / (2 * h);
      ASSERT_GT(std::abs(du), 1e-2 * largest * volume) << a << b;
      EXPECT_NEAR(comp(sigma, a, b) * volume, du, 1e-6 * std::abs(du)) << "component " << a << b;
    }
}

// ---------------------------------------------------------------------------------------------------------
// HCP patch-test geometry (paper section 3.1).

// Interacting neighbours of each particle of a periodic HCP lattice with spacing = diameter = d0.
std::vector<int> interacting_neighbours(const CohesiveCoefficients& c, double d0, double* max_abs_dn) {
  const Lattice lat = hcp(d0, {4, 3, 2});  // every axis longer than 2 (cutoff + skin)
  System s = make_system(Box(lat.box.lo(), lat.box.hi(), {true, true, true}), lat.particles, c, 0.05 * d0);
  const double delta_f = cohesive_delta_f(c, d0);
  std::vector<int> count(s.p.size(), 0);
  *max_abs_dn = 0;
  for (int i = 0; i < s.list.rows(); ++i)
    for (int k = s.list.offset()[i]; k < s.list.offset()[i + 1]; ++k) {
      const int j = s.list.index()[k];
      const Vec3 dx = minimum_image(s.box.view(), Vec3{s.p.x[i] - s.p.x[j], s.p.y[i] - s.p.y[j], s.p.z[i] - s.p.z[j]});
      const double dn = norm(dx) - d0;
      if (dn <= delta_f) {
        ++count[i];
        *max_abs_dn = std::max(*max_abs_dn, std::abs(dn));
      }
    }
  // The engine's own count (each pair once) agrees.
  const long pairs = cohesive_diagnostics(c, CohesiveOptions{}, s.box.view(), s.p, s.list, s.history).interacting_pairs;
  long sum = 0;
  for (int n : count) sum += n;
  EXPECT_EQ(2 * pairs, sum);
  return count;
}

// Nearest neighbours touch (dN = 0); the second shell, 6 at d0 sqrt 2, has dN = 0.414 d0, beyond delta_f when
// d0 >= 0.6 d_c: delta_f = 30 = 0.2 d_c below d_c (eq 10), and at most delta_e = 0.2 d0 above it (s = 0.5
// makes it smaller still, delta_f < delta_e). So exactly the 12 nearest interact, as section 3 needs for a
// fixed coordination number. Below about 0.48 d_c the second shell joins in: 18 at 0.45 d_c.
TEST(HcpPatch, TwelveInteractingNeighboursFromSixTenthsOfTheCriticalDiameter) {
  for (double s : {0.0, 0.5}) {
    const CohesiveCoefficients c = CohesiveCoefficients::from(table4(0.15, s));
    ASSERT_DOUBLE_EQ(c.d_c, 150.0);
    for (double ratio : {0.6, 1.0, 2.0}) {
      const double d0 = ratio * c.d_c;
      double max_dn = 0;
      const std::vector<int> count = interacting_neighbours(c, d0, &max_dn);
      for (std::size_t i = 0; i < count.size(); ++i) ASSERT_EQ(count[i], 12) << "s " << s << " d0 " << d0 << " i " << i;
      EXPECT_LT(max_dn, 1e-10 * d0) << "nearest neighbours must touch";
      if (ratio > 1 && s > 0) EXPECT_LT(cohesive_delta_f(c, d0), d0 * c.strain_e);  // delta_f < delta_e here
    }
    double max_dn = 0;
    for (int n : interacting_neighbours(c, 0.45 * c.d_c, &max_dn)) ASSERT_EQ(n, 18) << "s " << s;
  }
}

// ---------------------------------------------------------------------------------------------------------
// Elastic constants of the affinely strained HCP lattice (appendix A.2.2).
//
// Under a small strain eps, each pair's relative displacement is u = eps r_ij, and its energy is that of
// eq A.55, U = 1/2 k_N (u.n)^2 + 1/2 k_T |u - (u.n) n|^2 (tangential spring = affine tangential motion).
// With |r_ij| = a = 2r, the stiffness per particle volume V = a^3 / sqrt 2 (eq A.58) is
//
//   C_abcd = 1/(sqrt(2) a) sum_12 [ (k_N - k_T) n_a n_b n_c n_d + k_T sym(delta_ac n_b n_d) ].
//
// The first shell of HCP (and FCC) has sum_12 n n = 4 I exactly (6 in-plane directions at 60 degrees give
// 3 I_plane; the 6 out of plane have n_c^2 = 2/3 and in-plane parts of length^2 1/3 in two triangles).
// At nu = 0, eqs 15-16 give A_N = A_T = sqrt(2) r^2, so k_N = k_T = sqrt(2) a E / 4 (eq 7-8 with r_i + r_j = a)
// and the fourth-moment term drops out: C_abcd = E sym(delta_ac delta_bd), i.e. lambda = 0 and mu = E / 2:
// exactly Young's modulus E and Poisson's ratio 0, in every direction. For nu > 0 the fourth moment of the
// 12 HCP directions is not isotropic (sum n_c^4 = 8/3 along the c axis, 5/2 in the close-packed plane, while
// the 4 pi average behind eqs A.56-A.61 gives 12/5), which is why the lattice tests of the paper deviate
// more as nu grows (Figs A.4, A.5).

using Voigt6 = Eigen::Matrix<double, 6, 6>;
constexpr int kVoigt[6][2] = {{0, 0}, {1, 1}, {2, 2}, {1, 2}, {0, 2}, {0, 1}};

// Symmetric strain tensor of a unit Voigt strain (engineering shear: eps_ab = 1/2 for a shear column).
void unit_strain(int col, double eps[3][3]) {
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) eps[a][b] = 0;
  const int a = kVoigt[col][0], b = kVoigt[col][1];
  eps[a][b] = eps[b][a] = a == b ? 1.0 : 0.5;
}

struct AffineLattice {
  Lattice lat;
  System s;
  CohesivePairParams pp;
};

AffineLattice affine_lattice(const CohesiveCoefficients& c, int c_axis) {
  Lattice lat = hcp(100, {3, 2, 2}, c_axis);  // 300 along the first in-plane axis, 346 and 327 along the others
  System s = make_system(Box(lat.box.lo(), lat.box.hi(), {true, true, true}), lat.particles, c, 1.0);
  const CohesivePairParams pp = cohesive_pair_params(c, 50, 50, s.p.mass[0], s.p.mass[0]);
  return {std::move(lat), std::move(s), pp};
}

// The virial of the linearised pair forces F_ij = -[k_N (u.n) n + k_T (u - (u.n) n)], u = eps r_ij, over the
// interacting pairs (the 12 nearest); `force` (optional) receives the net force on each particle.
Eigen::Matrix3d linear_virial(const AffineLattice& al, const double eps[3][3], std::vector<Vec3>* force = nullptr) {
  const System& s = al.s;
  Eigen::Matrix3d w = Eigen::Matrix3d::Zero();
  if (force) force->assign(s.p.size(), Vec3{});
  for (int i = 0; i < s.list.rows(); ++i)
    for (int k = s.list.offset()[i]; k < s.list.offset()[i + 1]; ++k) {
      const int j = s.list.index()[k];
      const Vec3 r = minimum_image(s.box.view(), Vec3{s.p.x[i] - s.p.x[j], s.p.y[i] - s.p.y[j], s.p.z[i] - s.p.z[j]});
      if (norm(r) - 100 > al.pp.delta_f) continue;
      const Vec3 n = (1.0 / norm(r)) * r;
      const Vec3 u{eps[0][0] * r.x + eps[0][1] * r.y + eps[0][2] * r.z, eps[1][0] * r.x + eps[1][1] * r.y + eps[1][2] * r.z,
                   eps[2][0] * r.x + eps[2][1] * r.y + eps[2][2] * r.z};
      const Vec3 un = dot(u, n) * n;
      const Vec3 f = -(al.pp.k_n * un + al.pp.k_t * (u - un));
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) w(a, b) -= 0.5 * comp(r, a) * comp(f, b);
      if (force) (*force)[i] += f;
    }
  return 0.5 * (w + w.transpose()) / al.s.box.volume();
}

// Eq A.55 summed over the interacting pairs (each met twice in the full list).
double affine_energy(const AffineLattice& al, const double eps[3][3]) {
  const System& s = al.s;
  double u_sum = 0;
  for (int i = 0; i < s.list.rows(); ++i)
    for (int k = s.list.offset()[i]; k < s.list.offset()[i + 1]; ++k) {
      const int j = s.list.index()[k];
      const Vec3 r = minimum_image(s.box.view(), Vec3{s.p.x[i] - s.p.x[j], s.p.y[i] - s.p.y[j], s.p.z[i] - s.p.z[j]});
      if (norm(r) - 100 > al.pp.delta_f) continue;
      const Vec3 n = (1.0 / norm(r)) * r;
      const Vec3 u{eps[0][0] * r.x + eps[0][1] * r.y + eps[0][2] * r.z, eps[1][0] * r.x + eps[1][1] * r.y + eps[1][2] * r.z,
                   eps[2][0] * r.x + eps[2][1] * r.y + eps[2][2] * r.z};
      const double un = dot(u, n);
      u_sum += 0.5 * (0.5 * al.pp.k_n * un * un + 0.5 * al.pp.k_t * norm2(u - un * n));
    }
  return u_sum;
}

// C_IJ = d sigma_I / d e_J from the linearised virial (exact: the forces are linear in eps).
Voigt6 affine_stiffness(const AffineLattice& al) {
  Voigt6 c;
  for (int col = 0; col < 6; ++col) {
    double eps[3][3];
    unit_strain(col, eps);
    const Eigen::Matrix3d sigma = linear_virial(al, eps);
    for (int row = 0; row < 6; ++row) c(row, col) = sigma(kVoigt[row][0], kVoigt[row][1]);
  }
  return c;
}

TEST(HcpPatchAnalytic, NuZeroGivesExactlyYoungsModulusAndZeroPoissonRatio) {
  const CohesiveCoefficients coef = CohesiveCoefficients::from(table4(0.0));
  for (int c_axis : {1, 2}) {
    const AffineLattice al = affine_lattice(coef, c_axis);
    ASSERT_DOUBLE_EQ(al.pp.k_n, al.pp.k_t);  // eqs 15-16 at nu = 0

    // The linearised virial is the strain derivative of the eq A.55 energy (a quadratic form: central
    // differences are exact up to round-off).
    const double e0[3][3] = {{2e-3, 1e-3, -4e-4}, {1e-3, -3e-3, 6e-4}, {-4e-4, 6e-4, 1e-3}};
    const Eigen::Matrix3d sigma0 = linear_virial(al, e0);
    for (int a = 0; a < 3; ++a)
      for (int b = a; b < 3; ++b) {
        double ep[3][3], em[3][3];
        for (int x = 0; x < 3; ++x)
          for (int y = 0; y < 3; ++y) ep[x][y] = em[x][y] = e0[x][y];
        const double h = 1e-4, step = a == b ? h : 0.5 * h;
        ep[a][b] += step;
        em[a][b] -= step;
        if (a != b) {
          ep[b][a] += step;
          em[b][a] -= step;
        }
        const double du = (affine_energy(al, ep) - affine_energy(al, em)) / (2 * h) / al.s.box.volume();
        EXPECT_NEAR(sigma0(a, b), du, 1e-9 * sigma0.norm()) << a << b;
      }

    // C = E sym(delta delta): diag(1, 1, 1, 1/2, 1/2, 1/2) in Voigt form, nothing else.
    const Voigt6 c = affine_stiffness(al);
    for (int i = 0; i < 6; ++i)
      for (int j = 0; j < 6; ++j) EXPECT_NEAR(c(i, j), i != j ? 0.0 : (i < 3 ? 1.0 : 0.5), 1e-12) << i << j;

    // Uniaxial stress along the c axis and in the close-packed plane: E = 1, nu = 0.
    const Voigt6 s = c.inverse();
    for (int a = 0; a < 3; ++a) {
      EXPECT_NEAR(1.0 / s(a, a), 1.0, 1e-12) << "E along axis " << a << " (c axis " << c_axis << ")";
      for (int b = 0; b < 3; ++b)
        if (b != a) EXPECT_NEAR(-s(b, a) / s(a, a), 0.0, 1e-12) << "nu_" << a << b;
    }

    // No internal relaxation: the affinely strained lattice is in equilibrium particle by particle (sum_12 of
    // eps r_ij = eps sum_12 r_ij = 0 when k_N = k_T), so the affine constants are those a relaxed patch test
    // would measure.
    std::vector<Vec3> force;
    linear_virial(al, e0, &force);
    const double pair_scale = al.pp.k_n * 100 * 3e-3;
    for (const Vec3& f : force) EXPECT_LT(norm(f), 1e-12 * pair_scale);
  }
}

// The real pass on the real pair law: positions strained along an axis through the box, every tangential
// history set to the affine tangential displacement, forces of eq 2 as the engine computes them. Central
// differences of its virial give the normal block of C: the one above, E = 1 and nu = 0.
TEST(HcpPatchAnalytic, VirialOfThePairLawReproducesTheAffineStiffness) {
  const CohesiveCoefficients coef = CohesiveCoefficients::from(table4(0.0));
  const AffineLattice al = affine_lattice(coef, 1);
  const double h = 1e-5;
  Eigen::Matrix3d normal_block;
  for (int a = 0; a < 3; ++a) {
    StressTensor sig[2];
    for (int sign = 0; sign < 2; ++sign) {
      const double e = sign == 0 ? h : -h;
      System s = al.s;  // same list and entry order as the reference lattice
      const Vec3 len = s.box.length();
      Vec3 hi = s.box.lo() + len;
      (a == 0 ? hi.x : a == 1 ? hi.y : hi.z) = comp(s.box.lo(), a) + comp(len, a) * (1 + e);
      s.box.deform(s.box.lo(), hi, s.p);
      for (int i = 0; i < s.list.rows(); ++i)
        for (int k = s.list.offset()[i]; k < s.list.offset()[i + 1]; ++k) {
          const int j = s.list.index()[k];
          const Particles& p0 = al.s.p;
          const Vec3 r = minimum_image(al.s.box.view(), Vec3{p0.x[i] - p0.x[j], p0.y[i] - p0.y[j], p0.z[i] - p0.z[j]});
          const Vec3 n = (1.0 / norm(r)) * r;
          Vec3 u{};
          (a == 0 ? u.x : a == 1 ? u.y : u.z) = e * comp(r, a);
          const Vec3 ut = u - dot(u, n) * n;
          s.history.hx[k] = ut.x;
          s.history.hy[k] = ut.y;
          s.history.hz[k] = ut.z;
        }
      to_device(s.p);
      s.list.to_device();
      s.history.to_device();
      sig[sign] = virial_stress(coef, CohesiveOptions{}, s.box.view(), s.p, s.list, s.history, nullptr, s.box.volume());
    }
    for (int b = 0; b < 3; ++b) normal_block(b, a) = (comp(sig[0], b, b) - comp(sig[1], b, b)) / (2 * h);
    EXPECT_LT(std::abs(sig[0].xy) + std::abs(sig[0].xz) + std::abs(sig[0].yz), 1e-9 * h);
  }
  const Voigt6 c = affine_stiffness(al);
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) EXPECT_NEAR(normal_block(a, b), c(a, b), 1e-8) << a << b;
  const Eigen::Matrix3d s = normal_block.inverse();
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(1.0 / s(a, a), 1.0, 1e-8) << "E along axis " << a;
    for (int b = 0; b < 3; ++b)
      if (b != a) EXPECT_NEAR(-s(b, a) / s(a, a), 0.0, 1e-8);
  }
}

// At nu = 1/4 (k_T = 0) the affine constants are E/2 times the fourth moment of the 12 HCP directions:
// c axis 8/3, close-packed plane 5/2, in-plane cross term 5/6, plane-c cross term 2/3, instead of the 12/5
// and 4/5 of the isotropic average (eqs A.60-A.61: C_11 = 6/5 E, C_12 = 2/5 E). The lattice is transversely
// isotropic about c. And since an HCP site has no inversion centre (its third moment sum_12 n n n is not
// zero), the affine state is not in equilibrium once k_N != k_T: layers A and B are pushed opposite ways, so
// a relaxed patch test is softer than these affine constants.
TEST(HcpPatchAnalytic, QuarterPoissonRatioShowsTheHcpFourthMoment) {
  const CohesiveCoefficients coef = CohesiveCoefficients::from(table4(0.25));
  const AffineLattice al = affine_lattice(coef, 1);  // c axis y; close-packed plane x-z
  ASSERT_EQ(al.pp.k_t, 0.0);
  const Voigt6 c = affine_stiffness(al);
  const double tol = 1e-12;
  EXPECT_NEAR(c(0, 0), 0.5 * 5.0 / 2.0, tol);  // xx, in plane
  EXPECT_NEAR(c(2, 2), 0.5 * 5.0 / 2.0, tol);  // zz, in plane
  EXPECT_NEAR(c(1, 1), 0.5 * 8.0 / 3.0, tol);  // yy, c axis
  EXPECT_NEAR(c(0, 2), 0.5 * 5.0 / 6.0, tol);  // xz, both in plane
  EXPECT_NEAR(c(0, 1), 0.5 * 2.0 / 3.0, tol);  // xy, plane and c
  EXPECT_NEAR(c(1, 2), 0.5 * 2.0 / 3.0, tol);
  EXPECT_NEAR(c(3, 3), 0.5 * 2.0 / 3.0, tol);  // yz shear (involves c)
  EXPECT_NEAR(c(4, 4), 0.5 * 5.0 / 6.0, tol);  // xz shear, in plane = (C_xx - C_xz) / 2
  EXPECT_NEAR(c(5, 5), 0.5 * 2.0 / 3.0, tol);  // xy shear (involves c)
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j)
      if ((i < 3) != (j < 3) || (i >= 3 && i != j)) EXPECT_NEAR(c(i, j), 0.0, tol) << i << j;

  // An in-plane strain along z pushes the layers apart along z: an internal force the affine state does
  // not balance (it vanishes at nu = 0 above).
  double ezz[3][3] = {};
  ezz[2][2] = 1e-3;
  std::vector<Vec3> force;
  linear_virial(al, ezz, &force);
  EXPECT_GT(std::abs(force[0].z), 1e-2 * al.pp.k_n * 100 * 1e-3);
  EXPECT_NEAR(force[0].z + force[2].z, 0.0, 1e-12 * al.pp.k_n);  // layers A and B pushed opposite ways
}

}  // namespace
}  // namespace debris
