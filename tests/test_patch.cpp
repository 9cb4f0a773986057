// Patch tests of the cohesive DEM (paper section 3) at small sizes: the elastic test recovers E and nu at
// nu = 0 in both lattice orientations and the closed-form affine constants along the c axis at nu = 0.15;
// tension at nu = 0 finds a peak (broke) in both orientations, against the target of eq 20 in the
// close-packed plane and against the uniformly stretched lattice's closed form along c; the shear peak at
// fixed height against the uniformly sheared lattice (above d_c); debris_patch's table values; a sample read
// from a LAMMPS data file gives the same result as the lattice it was written from; bad inputs end with
// messages naming the key and the value, in the library and in the debris_patch executable.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "core/error.hpp"
#include "core/exec.hpp"
#include "core/io/lammps_data.hpp"
#include "core/lattice.hpp"
#include "scenarios/patch/patch_test.hpp"
#include "tests/cli_helpers.hpp"

namespace debris {
namespace {

namespace fs = std::filesystem;

CohesiveMaterial table4(double nu, double s = 0.0) {
  CohesiveMaterial m = table4_material(s);
  m.poisson_ratio = nu;
  return m;
}

// The smallest HCP patch samples that keep an interior 1.5 d0 away from both walls (8 d0 tall).
PatchSample small_hcp(const CohesiveMaterial& m, int c_axis, double length = 8, double d0_over_dc = 0.6) {
  HcpSampleSpec spec;
  spec.d0 = d0_over_dc * m.critical_diameter();
  spec.c_axis = c_axis;
  spec.length = length;
  return make_hcp_sample(spec, m);
}

// ---------------------------------------------------------------------------------------------------------
// Closed forms.

TEST(PatchFormulas, IsotropicModuliInvertTheConfinedStiffness) {
  for (double nu : {0.0, 0.1, 0.25, -0.3}) {
    const double E = 2.5;
    const double c11 = E * (1 - nu) / ((1 + nu) * (1 - 2 * nu)), c12 = E * nu / ((1 + nu) * (1 - 2 * nu));
    const IsotropicModuli m = isotropic_from_stiffness(c11, c12);
    EXPECT_NEAR(m.E, E, 1e-14 * E) << nu;
    EXPECT_NEAR(m.nu, nu, 1e-14) << nu;
  }
}

TEST(PatchFormulas, TargetStrengthFollowsEq20AboveTheCriticalDiameter) {
  const CohesiveMaterial m = table4(0.0, 0.5);  // d_c = 150
  EXPECT_DOUBLE_EQ(target_strength(m, PatchTest::tension, 90), 0.2);
  EXPECT_DOUBLE_EQ(target_strength(m, PatchTest::tension, 150), 0.2);
  EXPECT_DOUBLE_EQ(target_strength(m, PatchTest::tension, 600), 0.2 * 0.5);  // (600 / 150)^-0.5
  EXPECT_DOUBLE_EQ(target_strength(m, PatchTest::shear, 600), 0.1 * 0.5);
  EXPECT_DOUBLE_EQ(target_strength(table4(0.0, 0.0), PatchTest::tension, 600), 0.2);
}

// ---------------------------------------------------------------------------------------------------------
// Samples.

TEST(PatchSample, HcpWallsAndGeometry) {
  const CohesiveMaterial m = table4(0.15);
  for (int c : {0, 1, 2}) {
    const PatchSample s = small_hcp(m, c, 25);
    EXPECT_TRUE(s.box.periodic(0));
    EXPECT_FALSE(s.box.periodic(1));
    EXPECT_TRUE(s.box.periodic(2));
    // Lengths within one lattice period of the requested 25 x 25 x 3 d0.
    EXPECT_NEAR(s.box.length(0) / s.d0, 25, 1.0) << c;
    EXPECT_NEAR(s.box.length(1) / s.d0, 25, 1.7) << c;
    EXPECT_NEAR(s.box.length(2) / s.d0, 3, 1.0) << c;
    long bottom = 0, top = 0, free = 0;
    for (std::size_t i = 0; i < s.particles.size(); ++i) {
      const int g = s.particles.group[i];
      const double y = s.particles.y[i];
      if (g == s.bottom) {
        ++bottom;
        EXPECT_LT(y, s.box.lo().y + 1.5 * s.d0);
      } else if (g == s.top) {
        ++top;
        EXPECT_GE(y, s.box.hi().y - 1.5 * s.d0);
      } else {
        ++free;
        EXPECT_EQ(g, -1);
        EXPECT_GT(y, s.inner_bottom);
        EXPECT_LT(y, s.inner_top);
      }
    }
    EXPECT_EQ(free, s.free_count);
    EXPECT_EQ(bottom, top) << "the lattice is symmetric about its mid-plane";
    EXPECT_GT(bottom, 0);
    EXPECT_NEAR(s.volume_per_particle, std::pow(s.d0, 3) / std::sqrt(2.0), 1e-9 * std::pow(s.d0, 3));
    EXPECT_EQ(s.groups.list[static_cast<std::size_t>(s.bottom)].motion, GroupMotion::frozen);
  }
}

TEST(PatchSample, DiameterBelowMinimumIsRejected) {
  const CohesiveMaterial m = table4(0.15);  // d_min = 30 = 0.2 d_c
  try {
    small_hcp(m, 1, 8, 0.1);
    FAIL() << "d0 = 0.1 d_c < d_min was accepted";
  } catch (const InputError& e) {
    const std::string w = e.what();
    EXPECT_NE(w.find("sample.d0"), std::string::npos) << w;
    EXPECT_NE(w.find("0.1 d_c"), std::string::npos) << w;
    EXPECT_NE(w.find("d_min"), std::string::npos) << w;
  }
  EXPECT_NO_THROW(small_hcp(m, 1, 8, 0.2));  // exactly d_min
}

// ---------------------------------------------------------------------------------------------------------
// Elastic test.

// At nu = 0 (k_N = k_T) the affinely strained HCP lattice has exactly E and nu = 0 in every direction
// (tests/test_virial_stress.cpp); the relaxed patch test must find them, in both orientations. The 1%
// compression adds geometric nonlinearity of order 1e-3.
TEST(PatchElastic, NuZeroRecoversYoungsModulusAndZeroPoissonRatioInBothOrientations) {
  const CohesiveMaterial m = table4(0.0);
  for (int c : {1, 2}) {
    const PatchSample s = small_hcp(m, c);
    const ElasticResult r = run_elastic_test(s, m, ElasticSettings{});
    std::printf("[ info ] elastic nu = 0, %s: E = %.5f, nu = %.5f (walls: E = %.5f), %ld steps, %.2f s\n",
                hcp_orientation_name(c).c_str(), r.moduli.E, r.moduli.nu, r.moduli_walls.E, r.steps, r.wall_seconds);
    EXPECT_NEAR(r.moduli.E, 1.0, 0.02) << hcp_orientation_name(c);
    EXPECT_NEAR(r.moduli.nu, 0.0, 0.02) << hcp_orientation_name(c);
    EXPECT_LT(r.eps, 0.0);
    EXPECT_NEAR(r.eps, -0.01, 0.0002);  // E = 1, stress 0.01
    // Equilibrium: the deformable part carries the applied stress (exact for c along y, where every bond
    // to a wall crosses one plane; to 1% otherwise).
    EXPECT_NEAR(r.sigma_part.yy, r.applied, (c == 1 ? 1e-5 : 1e-2) * std::abs(r.applied));
    if (c == 1)
      EXPECT_NEAR(r.eps_walls, r.eps, 1e-4 * std::abs(r.eps)) << "one wall layer: the walls give the bulk strain";
  }
}

// Along the c axis the affinely strained lattice is in equilibrium at any nu (the up and down bonds of a
// site balance), so the patch test must give the affine constants of the 12 HCP bonds:
//   C11 = 8/3 (kN - kT) + 4 kT,  C12 = 2/3 (kN - kT),  kN = E / (4 (1 - 2 nu)),  kT = kN (1 - 4 nu) / (1 + nu)
// (k_N, k_T of eqs 7-8, 15-16 over sqrt(2) a). A small load (0.1% strain) keeps geometric nonlinearity out.
TEST(PatchElastic, CAxisAlongLoadGivesTheAffineHcpConstantsAtNonzeroNu) {
  const double nu = 0.15;
  const CohesiveMaterial m = table4(nu);
  const PatchSample s = small_hcp(m, 1);
  ElasticSettings es;
  es.stress = 1e-3;
  const ElasticResult r = run_elastic_test(s, m, es);
  const double kn = 1.0 / (4 * (1 - 2 * nu)), kt = kn * (1 - 4 * nu) / (1 + nu);
  const double c11 = 8.0 / 3.0 * (kn - kt) + 4 * kt, c12 = 2.0 / 3.0 * (kn - kt);
  std::printf("[ info ] c axis along the load, nu = 0.15: C11 = %.5f (affine %.5f), C12 = %.5f (affine %.5f)\n", r.c11,
              c11, r.c12, c12);
  EXPECT_NEAR(r.c11, c11, 2e-3);
  EXPECT_NEAR(r.c12, c12, 2e-3);
  EXPECT_NEAR(r.c13, r.c12, 1e-6) << "transversely isotropic about c";
}

TEST(PatchElastic, StepLimitEndsWithAMessageNamingIt) {
  const CohesiveMaterial m = table4(0.0);
  const PatchSample s = small_hcp(m, 1);
  ElasticSettings es;
  es.max_steps = 800;  // one full window (500 steps) but not yet settled (this sample needs 1350 steps)
  try {
    run_elastic_test(s, m, es);
    FAIL() << "no equilibrium in 800 steps was accepted";
  } catch (const PatchRunError& e) {
    const std::string w = e.what();
    EXPECT_NE(w.find("elastic.max_steps = 800"), std::string::npos) << w;
    EXPECT_NE(w.find("still changed by"), std::string::npos) << w;
    EXPECT_NE(w.find("elastic.tolerance"), std::string::npos) << w;
  }
}

TEST(PatchElastic, SampleThatGivesWayIsReported) {
  const CohesiveMaterial m = table4(0.0);
  const PatchSample s = small_hcp(m, 1);
  ElasticSettings es;
  es.stress = 0.5;  // beyond the strength: the sample is crushed
  es.max_strain = 0.05;
  try {
    run_elastic_test(s, m, es);
    FAIL() << "a crushed sample gave a result";
  } catch (const PatchRunError& e) {
    EXPECT_NE(std::string(e.what()).find("elastic.max_strain = 0.05"), std::string::npos) << e.what();
  }
}

// ---------------------------------------------------------------------------------------------------------
// Strength test.

// Strength of an HCP lattice with c along y (close-packed layers parallel to the walls) deformed uniformly,
// from eqs 3-5 and 7-11 written out here. Only the 3 pairs per site between neighbouring layers carry
// sigma_yy and sigma_xy: in a layer's frame a pair is b = (rho cos phi, h, rho sin phi) with rho = a / sqrt 3,
// h = a sqrt(2/3), phi = 30, 150, 270 degrees (the B sites over an A site; core/lattice.cpp), and the
// B-over-A pairs are its mirror image in z. Virial stress per site: sigma_ab = 3 pairs sum f_a b_b / V,
// V = a^3 / sqrt 2 stretched with eps_yy; f = F_N n + F_T t (the pull that holds the upper site back).
struct HcpPairLaw {
  double a, kn, kt, de, df, fmt;
  HcpPairLaw(const CohesiveMaterial& m, double d0) : a(d0) {
    const double r = 0.5 * d0, nu = m.poisson_ratio;
    const double an = std::sqrt(2.0) * r * r / (1 - 2 * nu);                           // eq 15
    const double at = std::sqrt(2.0) * r * r * (1 - 4 * nu) / ((1 - 2 * nu) * (1 + nu));  // eq 16
    kn = an * m.youngs_modulus / d0;                                                      // eq 7
    kt = at * m.youngs_modulus / d0;                                                      // eq 8
    de = d0 * m.tensile_strength / m.youngs_modulus;                                      // eq 9
    const double dc = m.critical_diameter();
    df = d0 <= dc ? 4 * m.surface_energy / m.tensile_strength : de * std::pow(d0 / dc, -m.scaling);  // eq 10
    fmt = at * m.shear_strength;                                                          // eq 11
  }
  double normal(double dn) const {  // eq 3
    if (dn > df) return 0;
    if (dn <= de) return kn * dn;
    return -kn * de / (df - de) * (dn - df);
  }
  double cap(double dn) const { return std::min((df - dn) / df, 1.0) * fmt; }  // eq 5
  double rho() const { return a / std::sqrt(3.0); }
  double h() const { return a * std::sqrt(2.0 / 3.0); }
  double site_volume() const { return a * a * a / std::sqrt(2.0); }
};

// Tension along c, in closed form. The layers stay flat and stacked (the 3 pairs of a site are 120 degrees
// apart: their in-plane forces cancel), so the stretch is affine: b = (rho, h (1 + eps)). The tangential
// spring of eq 4 integrates the sliding velocity h eps' sin(theta) into
// dT = rho (asinh(h (1 + eps) / rho) - asinh(h / rho)), and is capped by eq 5, which only falls as dN grows.
// sigma_yy rises until the pairs reach the end of the Hookean branch, dN = min(delta_e, delta_f), and falls
// after it: that is the peak.
double c_axis_tension_peak(const CohesiveMaterial& m, double d0) {
  const HcpPairLaw p(m, d0);
  const double rho = p.rho(), h = p.h();
  const double dn = std::min(p.de, p.df), len = p.a + dn;
  const double by = std::sqrt(len * len - rho * rho), eps = by / h - 1;
  const double dt = rho * (std::asinh(by / rho) - std::asinh(h / rho));
  const double ft = std::min(p.kt * dt, p.cap(dn));
  return 3.0 / (p.site_volume() * (1 + eps)) * (p.kn * dn * by / len + ft * rho / len) * by;
}

// Shear along x at fixed height, by integration over the strain. Under shear the pairs of one layer stretch
// unevenly and pull it along z, an A layer one way and a B layer the other, so the layers zigzag: neighbouring
// layers are offset by (gamma h, h, +-w), with w at each step the offset that balances the z forces of the 3
// pairs. The tangential history follows eq 4 as the pair law does (rotated into the tangent plane keeping
// its length, then the sliding increment added, capped by eq 5). Returns the peak sigma_xy.
double c_axis_shear_peak(const CohesiveMaterial& m, double d0) {
  const HcpPairLaw p(m, d0);
  const double kPi = 3.14159265358979323846, rho = p.rho(), h = p.h();
  const double phi[3] = {kPi / 6, 5 * kPi / 6, 3 * kPi / 2};
  Vec3 hist[3] = {};
  struct Pairs {
    Vec3 force[3], hist[3];
    Vec3 b[3];
  };
  auto pairs = [&](double x, double z, double dx, double dz) {
    Pairs out{};
    for (int k = 0; k < 3; ++k) {
      const Vec3 b{rho * std::cos(phi[k]) + x, h, rho * std::sin(phi[k]) + z};
      const double len = norm(b), dn = len - p.a;
      const Vec3 n = (1.0 / len) * b;
      out.b[k] = b;
      if (dn > p.df) continue;  // broken: history reset, no force
      Vec3 hk = hist[k];
      const double h2 = norm2(hk);
      if (h2 > 0) {
        hk = hk - dot(hk, n) * n;
        if (norm2(hk) > 0) hk = std::sqrt(h2 / norm2(hk)) * hk;
      }
      const Vec3 v{dx, 0, dz};
      hk += v - dot(v, n) * n;
      const double spring = p.kt * norm(hk), cap = p.cap(dn);
      if (spring > cap) hk = (cap / spring) * hk;
      out.hist[k] = hk;
      out.force[k] = p.normal(dn) * n + p.kt * hk;
    }
    return out;
  };
  const int steps = 5000;
  const double dgamma = 1.0 / steps;
  double x = 0, z = 0, peak = 0;
  for (int i = 1; i <= steps; ++i) {
    const double dx = h * dgamma;
    auto fz = [&](double dz) {
      const Pairs q = pairs(x + dx, z + dz, dx, dz);
      return q.force[0].z + q.force[1].z + q.force[2].z;
    };
    double lo = -2 * dx, hi = 2 * dx, flo = fz(lo), fhi = fz(hi);
    for (int k = 0; k < 30 && flo * fhi > 0; ++k) {
      lo *= 2, hi *= 2;
      flo = fz(lo), fhi = fz(hi);
    }
    for (int k = 0; k < 60; ++k) {
      const double mid = 0.5 * (lo + hi), fm = fz(mid);
      if ((fm > 0) == (flo > 0)) lo = mid, flo = fm;
      else hi = mid;
    }
    const double dz = 0.5 * (lo + hi);
    const Pairs q = pairs(x + dx, z + dz, dx, dz);
    for (int k = 0; k < 3; ++k) hist[k] = q.hist[k];
    x += dx, z += dz;
    double sxy = 0;
    for (int k = 0; k < 3; ++k) sxy += q.force[k].x * q.b[k].y;
    peak = std::max(peak, sxy / p.site_volume());
  }
  return peak;
}

// Tension at nu = 0: the lattice breaks (stress down to nothing after the peak) in both orientations. The
// paper finds the tensile strength equal to the target at nu = 0; here that holds for the load in the
// close-packed plane (c along z, as LAMMPS builds hcp), while with c along the load the 6 bonds to the
// neighbouring layers turn toward the load as it stretches and the peak comes later and higher.
TEST(PatchStrength, TensionAtNuZeroBreaksNearTheTarget) {
  // ~30000 steps of ~150 particles: the cost is the per-kernel fork and barrier, which with sleeping
  // threads (ctest sets OMP_WAIT_POLICY=passive) made this test 24 s on 2 threads; on 1 thread it takes
  // a few seconds. Results do not depend on the thread count.
  const int threads = exec::threads();
  exec::set_threads(1);
  const CohesiveMaterial m = table4(0.0);
  for (int c : {2, 1}) {
    const PatchSample s = small_hcp(m, c, 6, 100.0 / 150.0);
    const StrengthResult r = run_strength_test(s, m, PatchTest::tension, StrengthSettings{});
    const double target = target_strength(m, PatchTest::tension, s.d0);
    std::printf(
        "[ info ] tension, nu = 0, d0 = 100 (0.67 d_c), %s: strength %.4f, target %.4f (ratio %.3f) at strain "
        "%.4f, %s, %ld steps, %.2f s\n",
        hcp_orientation_name(c).c_str(), r.strength, target, r.strength / target, r.strain_at_peak,
        strength_outcome_name(r.outcome), r.steps, r.wall_seconds);
    EXPECT_EQ(r.outcome, StrengthOutcome::broke) << hcp_orientation_name(c);
    EXPECT_LT(std::abs(r.final_over_peak), 0.5);
    EXPECT_GT(r.strain_at_peak, 0.5 * target / m.youngs_modulus) << "a peak from the start-up wave, not a fracture";
    ASSERT_FALSE(r.curve.empty());
    EXPECT_DOUBLE_EQ(r.curve.front().strain, 0.0);
    if (c == 2) {
      EXPECT_NEAR(r.strength / target, 1.0, 0.05) << "the paper: tensile strength = target at nu = 0";
    } else {
      // Along c the uniformly stretched lattice's peak is known in closed form (c_axis_tension_peak: 1.172
      // target here, above it because the 6 inter-layer pairs turn toward the load and their tangential
      // springs add to it). What is left is dynamics: the stress wave of the start-up and the inertia and
      // global damping of a sample pulled at 1e-5 per step, and the curve sampled every 20 steps (2e-4
      // strain): measured 0.2344 against 0.2344 here, and 1.191 against 1.1915 target on L = 10 d0 at
      // 0.6 d_c (scenarios/patch/RESULTS.md).
      const double uniform = c_axis_tension_peak(m, s.d0);
      std::printf("[ info ] c axis tension peak %.4f, uniform lattice closed form %.4f\n", r.strength, uniform);
      EXPECT_NEAR(r.strength / uniform, 1.0, 0.01);
    }
  }
  exec::set_threads(threads);
}

// Shear at fixed height with c along y above d_c (1.2 d_c, s = 0): the peak sigma_xy against the uniformly
// sheared, zigzag-balanced lattice (c_axis_shear_peak: 1.41 target; the fixed height forbids the dilation
// that shear needs, and the compressed pairs add to the tangential ones). Measured on L = 10 d0 for every
// d0 from 1.2 to 76.8 d_c: 1.410 (scenarios/patch/RESULTS.md). Below d_c the model does not hold (0.6 d_c:
// 1.08 measured, 1.57 modelled): pairs pass delta_e and soften before the peak, and the shear then localises
// in one layer interface instead of staying uniform. What limits agreement above d_c is the dynamics, as
// for tension (measured 1.410 against 1.4105 here). The run stops at 0.5 strain, past the peak (0.405).
TEST(PatchStrength, ShearPeakAtFixedHeightMatchesTheUniformLatticeAboveDc) {
  const int threads = exec::threads();
  exec::set_threads(1);
  const CohesiveMaterial m = table4(0.0);
  const PatchSample s = small_hcp(m, 1, 6, 1.2);
  StrengthSettings ss;
  ss.max_strain = 0.5;
  const StrengthResult r = run_strength_test(s, m, PatchTest::shear, ss);
  exec::set_threads(threads);
  const double target = target_strength(m, PatchTest::shear, s.d0), uniform = c_axis_shear_peak(m, s.d0);
  std::printf("[ info ] shear, fixed height, nu = 0, d0 = 1.2 d_c, c along y: peak %.4f = %.3f target at strain "
              "%.4f; uniform lattice %.4f = %.3f target; %s, %ld steps\n",
              r.strength, r.strength / target, r.strain_at_peak, uniform, uniform / target,
              strength_outcome_name(r.outcome), r.steps);
  EXPECT_NEAR(r.strength / uniform, 1.0, 0.01);
  EXPECT_NEAR(uniform / target, 1.41, 0.01);
  EXPECT_LT(r.strain_at_peak, 0.48) << "the peak must be inside the run, not its end";
}

// Shear with the top wall free along y under a normal stress: the wall keeps the prescribed shear rate
// exactly (its x kicks are cancelled), settles under the load, and the deformable part carries it.
TEST(PatchStrength, ShearWithFreeHeightKeepsTheRateAndCarriesTheNormalStress) {
  const CohesiveMaterial m = table4(0.0);
  const PatchSample s = small_hcp(m, 1);
  StrengthSettings ss;
  ss.shear_fixed_height = false;
  ss.shear_normal_stress = 0.005;
  ss.max_strain = 0.03;
  const StrengthResult r = run_strength_test(s, m, PatchTest::shear, ss);
  ASSERT_GT(r.curve.size(), 100u);
  double syy = 0, eyy = 0;
  long n = 0;
  for (const StressStrainPoint& p : r.curve) {
    EXPECT_NEAR(p.strain, ss.strain_rate * static_cast<double>(p.step), 1e-12) << p.step;
    if (p.strain < 0.5 * ss.max_strain) continue;
    syy += p.stress.yy;
    eyy += p.eps_yy;
    ++n;
  }
  syy /= static_cast<double>(n);
  eyy /= static_cast<double>(n);
  std::printf("[ info ] shear with free height, normal stress 0.005: mean sigma_yy %.5f, eps_yy %.5f\n", syy, eyy);
  EXPECT_NEAR(syy, -0.005, 0.1 * 0.005);
  EXPECT_NEAR(eyy, -0.005, 0.1 * 0.005) << "E = 1, nu = 0: confined modulus 1";
}

// ---------------------------------------------------------------------------------------------------------
// A sample from a LAMMPS data file (the amorphous samples' way in): the periodic HCP lattice written to a
// data file and walled by make_walled_sample is the same sample as make_hcp_sample's, with the same result.

TEST(PatchSample, DataFileSampleMatchesTheLattice) {
  const CohesiveMaterial m = table4(0.0);
  const PatchSample lattice = small_hcp(m, 1);
  LatticeSpec spec;
  spec.kind = LatticeKind::hcp;
  spec.spacing = spec.diameter = lattice.d0;
  spec.hcp_c_axis = 1;
  for (int a = 0; a < 3; ++a)
    spec.cells[static_cast<std::size_t>(a)] =
        static_cast<int>(std::lround(lattice.box.length(a) / (a == 0   ? lattice.d0
                                                              : a == 1 ? lattice.d0 * std::sqrt(8.0 / 3.0)
                                                                       : lattice.d0 * std::sqrt(3.0))));
  Lattice lat = make_lattice(spec);
  lat.particles.set_mass_from_density(m.density);
  const Box periodic(lat.box.lo(), lat.box.hi(), {true, true, true});
  const fs::path file = fs::path(::testing::TempDir()) / "debris_patch_lattice.data";
  write_lammps_data(file.string(), periodic, lat.particles);

  const LammpsData data = read_lammps_data(file.string(), {true, true, true});
  const PatchSample s = make_walled_sample(data.box, data.particles, 1.5, m, "sample.lammps_data", "test file");
  EXPECT_FALSE(s.masses_from_density);
  EXPECT_FALSE(s.box.periodic(1));
  EXPECT_EQ(s.free_count, lattice.free_count);
  EXPECT_DOUBLE_EQ(s.strain_height, lattice.strain_height);
  EXPECT_NEAR(s.volume_per_particle, lattice.volume_per_particle, 1e-12 * lattice.volume_per_particle);

  const ElasticResult a = run_elastic_test(lattice, m, ElasticSettings{});
  const ElasticResult b = run_elastic_test(s, m, ElasticSettings{});
  EXPECT_NEAR(b.moduli.E, a.moduli.E, 1e-9);
  EXPECT_NEAR(b.moduli.nu, a.moduli.nu, 1e-9);

  // Not periodic, or too small diameters: refused with the key.
  EXPECT_THROW(make_walled_sample(Box(lat.box.lo(), lat.box.hi(), {true, false, true}), data.particles, 1.5, m,
                                  "sample.lammps_data", "x"),
               InputError);
  CohesiveMaterial strong = m;
  strong.surface_energy = 100;  // d_min = 2000 > every diameter
  try {
    make_walled_sample(data.box, data.particles, 1.5, strong, "sample.lammps_data", "test file");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("sample.lammps_data"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("d_min"), std::string::npos) << e.what();
  }
}

// ---------------------------------------------------------------------------------------------------------
// The executable.

using Result = debris::test::CommandResult;

Result run_patch(const std::string& args) { return debris::test::run_command(DEBRIS_PATCH_EXECUTABLE, args); }

fs::path scratch(const std::string& name) { return debris::test::fresh_directory("debris_patch_" + name); }

std::string small_input() {
  return R"(test: [elastic, tension]
material:
  poisson_ratio: 0
sample:
  kind: hcp
  c_axis: y
  d0: 0.6
  length: 8
strength:
  max_strain: 0.02
output:
  plots: true
)";
}

using debris::test::replace;

Result run_input(const fs::path& dir, const std::string& yaml) {
  std::ofstream(dir / "in.yaml") << yaml;
  return run_patch("-i " + (dir / "in.yaml").string() + " -o " + (dir / "out").string() + " --threads 2");
}

using debris::test::slurp;

TEST(PatchCli, SmallSweepWritesTableCurvesAndPlots) {
  const fs::path dir = scratch("good");
  const Result r = run_input(dir, small_input());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string table = slurp(dir / "out" / "cases.csv");
  EXPECT_NE(table.find("case,test,sample,c_axis,d0_over_dc"), std::string::npos) << table;
  EXPECT_NE(table.find("\n1,elastic,hcp,y,"), std::string::npos) << table;
  EXPECT_NE(table.find("\n2,tension,hcp,y,"), std::string::npos) << table;
  const std::string curve = slurp(dir / "out" / "curves" / "case_002_tension.csv");
  EXPECT_NE(curve.find("step,strain,eps_yy,sigma_xx,sigma_yy"), std::string::npos);
  // The values. d0 = 0.6 d_c = 90 (d_c = 150, eq 18). Elastic, nu = 0, c along y: the affine HCP lattice has
  // exactly E = 1, nu = 0 (PatchElastic tests), and the 0.01 load gives eps_yy = -0.01. Tension stopped at
  // 0.02 strain, still rising: the uniformly stretched lattice carries E eps there (the closed form of
  // c_axis_tension_peak's stretch at eps = 0.02 gives 0.0199997: its nonlinearities cancel).
  const auto rows = debris::test::read_csv_rows(dir / "out" / "cases.csv");
  ASSERT_EQ(rows.size(), 2u) << table;
  const auto& elastic = rows[0];
  const auto& tension = rows[1];
  using debris::test::csv_number;
  EXPECT_EQ(elastic.at("status"), "ok") << table;
  EXPECT_DOUBLE_EQ(csv_number(elastic, "d0"), 90.0);
  EXPECT_DOUBLE_EQ(csv_number(elastic, "nu_target"), 0.0);
  EXPECT_NEAR(csv_number(elastic, "E"), 1.0, 0.02);
  EXPECT_NEAR(csv_number(elastic, "nu"), 0.0, 0.02);
  EXPECT_NEAR(csv_number(elastic, "eps_yy"), -0.01, 2e-4);
  EXPECT_NEAR(csv_number(elastic, "sigma_yy"), -0.01, 1e-4);
  EXPECT_DOUBLE_EQ(csv_number(tension, "target_strength"), 0.2);
  EXPECT_EQ(tension.at("outcome"), "max strain");
  // Measured 0.020201 at strain 0.0202 (the run's last point): E eps within 0.01%; 1% allowed.
  EXPECT_NEAR(csv_number(tension, "strength"), 1.0 * csv_number(tension, "strain_at_peak"), 0.01 * 0.02);
  EXPECT_NEAR(csv_number(tension, "strength_over_target"), csv_number(tension, "strength") / 0.2, 1e-9);
  EXPECT_NEAR(csv_number(tension, "strain_at_peak"), 0.02, 1e-3);
  EXPECT_TRUE(fs::exists(dir / "out" / "plots.gp"));
  // gnuplot draws the PNGs when it is installed, and the run says so either way.
  const bool drawn = r.output.find("plots drawn with gnuplot") != std::string::npos;
  EXPECT_TRUE(drawn || r.output.find("plots skipped") != std::string::npos) << r.output;
  if (drawn) {
    EXPECT_TRUE(fs::exists(dir / "out" / "elastic_E_deviation.png"));
    EXPECT_TRUE(fs::exists(dir / "out" / "stress_strain_tension_hcp_cy_nu0.png"));
    // The tension case stopped at max_strain 0.02, still rising: a lower bound, kept out of the strength plot.
    EXPECT_FALSE(fs::exists(dir / "out" / "tensile_strength.png"));
    EXPECT_NE(table.find("max strain"), std::string::npos);
  }
}

TEST(PatchCli, BadInputsEndWithTheKeyAndValue) {
  const fs::path dir = scratch("bad");
  struct Bad {
    std::string from, to;
    std::vector<std::string> mention;
  };
  const Bad bad[] = {
      {"  d0: 0.6", "  d0: [0.6, 0.1]", {"sample.d0", "0.1 d_c", "d_min"}},
      {"  poisson_ratio: 0", "  poisson_ratio: [0, 0.3]", {"material.poisson_ratio", "0.3", "0.25"}},
      {"  length: 8", "  length: 8\n  lenght: 9", {"sample.lenght", "unknown key"}},
      {"  c_axis: y", "  c_axis: w", {"sample.c_axis", "w"}},
      {"test: [elastic, tension]", "test: [elastic, bend]", {"test[1]", "bend"}},
      {"  max_strain: 0.02", "  max_strain: -1", {"strength.max_strain", "-1"}},
      {"  kind: hcp", "  kind: lammps_data\n  lammps_data: missing.data", {"missing.data", "no such file"}},
  };
  for (const Bad& b : bad) {
    const Result r = run_input(dir, replace(small_input(), b.from, b.to));
    EXPECT_EQ(r.exit_code, 2) << b.to << "\n" << r.output;
    for (const std::string& m : b.mention)
      EXPECT_NE(r.output.find(m), std::string::npos) << "no '" << m << "' in:\n" << r.output;
    EXPECT_FALSE(fs::exists(dir / "out" / "cases.csv")) << "bad input must not start writing results";
  }
}

TEST(PatchCli, StepLimitNeverMetEndsWithAMessageAndStatus3) {
  const fs::path dir = scratch("limit");
  const Result r = run_input(dir, replace(small_input(), "strength:", "elastic:\n  max_steps: 200\nstrength:"));
  EXPECT_EQ(r.exit_code, 3) << r.output;
  EXPECT_NE(r.output.find("elastic.max_steps = 200"), std::string::npos) << r.output;
  const std::string table = slurp(dir / "out" / "cases.csv");
  EXPECT_NE(table.find("failed: elastic test: no equilibrium"), std::string::npos) << table;
  EXPECT_NE(table.find("\n2,tension,hcp,y,"), std::string::npos) << "the other cases still run";
}

// A sweep stopped part way (here: two of four rows written, the third torn as a killed run leaves it, the
// fourth case's curve never written) and resumed: only the missing cases run, and the table (wall times
// aside) and the plots are those of the uninterrupted run, bit for bit.
TEST(PatchCli, ResumeRunsOnlyTheMissingCasesAndPlotsThemAll) {
  const fs::path dir = scratch("resume");
  const std::string input = replace(small_input(), "  poisson_ratio: 0", "  poisson_ratio: [0, 0.1]");
  std::ofstream(dir / "in.yaml") << input;
  auto patch = [&](const std::string& out, const std::string& more) {
    return run_patch("-i " + (dir / "in.yaml").string() + " -o " + (dir / out).string() + " --threads 1" + more);
  };
  const Result whole = patch("whole", "");
  ASSERT_EQ(whole.exit_code, 0) << whole.output;
  const std::string table = slurp(dir / "whole" / "cases.csv");
  std::vector<std::string> lines;
  for (std::istringstream in(table); std::getline(in, lines.emplace_back());) {
  }
  lines.pop_back();
  ASSERT_EQ(lines.size(), 5u) << table;  // header and four cases

  fs::copy(dir / "whole", dir / "stopped", fs::copy_options::recursive);
  std::ofstream(dir / "stopped" / "cases.csv", std::ios::trunc)
      << lines[0] << "\n" << lines[1] << "\n" << lines[2] << "\n" << lines[3].substr(0, 40);
  fs::remove(dir / "stopped" / "curves" / "case_004_tension.csv");
  fs::remove(dir / "stopped" / "plots.gp");
  const Result resumed = patch("stopped", " --resume");
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  EXPECT_NE(resumed.output.find("resume: 2 of 4 case(s) finished"), std::string::npos) << resumed.output;
  EXPECT_NE(resumed.output.find("line 4 of cases.csv is incomplete"), std::string::npos) << resumed.output;
  std::size_t kept = 0;
  for (std::size_t at = 0; (at = resumed.output.find("finished by an earlier run", at)) != std::string::npos; ++at)
    ++kept;
  EXPECT_EQ(kept, 2u) << resumed.output;

  EXPECT_EQ(slurp(dir / "stopped" / "plots.gp"), slurp(dir / "whole" / "plots.gp"));
  auto rows = debris::test::read_csv_rows(dir / "whole" / "cases.csv");
  auto again = debris::test::read_csv_rows(dir / "stopped" / "cases.csv");
  ASSERT_EQ(again.size(), 4u);
  for (std::size_t k = 0; k < rows.size(); ++k) {
    if (k >= 2) {  // the cases run again: the same numbers, their own wall times
      rows[k].erase("wall_seconds");
      again[k].erase("wall_seconds");
    }
    EXPECT_EQ(again[k], rows[k]) << "row " << k + 1;
  }
  EXPECT_EQ(slurp(dir / "stopped" / "curves" / "case_004_tension.csv"),
            slurp(dir / "whole" / "curves" / "case_004_tension.csv"));

  // Another input's results are not resumed (case k of one sweep is not case k of another).
  std::ofstream(dir / "in.yaml", std::ios::trunc) << replace(input, "  length: 8", "  length: 9");
  const Result other = patch("stopped", " --resume");
  EXPECT_EQ(other.exit_code, 2) << other.output;
  EXPECT_NE(other.output.find("'--resume'"), std::string::npos) << other.output;
  EXPECT_NE(other.output.find("another input"), std::string::npos) << other.output;
  EXPECT_EQ(debris::test::read_csv_rows(dir / "stopped" / "cases.csv").size(), 4u) << "nothing written is lost";
}

}  // namespace
}  // namespace debris
