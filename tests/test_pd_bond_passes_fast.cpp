// The optimised paths of the PeriDEM passes against plain references: the bond passes (vector loops over
// padded rows, per-node force factors, break + dilatation fused in pd_bond_step, rows handed out in blocks
// of equal work) against the pure bond functions of kernels/peridem/lps_bond_force.hpp summed node by node, and
// against the separate passes and another thread count; the contact list's buffered rows against a
// brute-force pair search, with rows longer than the buffer.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "core/bond_list.hpp"
#include "core/exec.hpp"
#include "core/pd_contact_list.hpp"
#include "core/pd_nodes.hpp"
#include "kernels/peridem/lps_bond_force.hpp"
#include "kernels/peridem/pd_bond_passes.hpp"
#include "kernels/peridem/pd_material.hpp"
#include "tests/pd_bond_breaking_reference.hpp"
#include "tests/pd_on_device.hpp"

namespace debris {
namespace {

struct System {
  PdNodes nodes;
  PdGrains grains;
  PdLpsTable lps;
  std::vector<double> horizon;  // per grain
  BondList bonds;

  int begin_grain(PdGrainKind kind, int material, double eps) {
    const int g = static_cast<int>(grains.size());
    grains.resize(static_cast<std::size_t>(g) + 1);
    grains.node_begin[g] = grains.node_end[g] = static_cast<int>(nodes.size());
    grains.kind[g] = static_cast<int>(kind);
    grains.material[g] = material;
    horizon.push_back(eps);
    return g;
  }
  // nx * ny * nz nodes at spacing h from corner o (nz = 1: a 2D grid), volume h^d.
  void add_grid(PdGrainKind kind, int material, double eps, Vec3 o, int nx, int ny, int nz, double h) {
    const int g = begin_grain(kind, material, eps);
    const double volume = nz == 1 ? h * h : h * h * h;
    for (int c = 0; c < nz; ++c)
      for (int b = 0; b < ny; ++b)
        for (int a = 0; a < nx; ++a) {
          const auto id = static_cast<std::int64_t>(nodes.size());
          nodes.add(id, g, o.x + a * h, o.y + b * h, o.z + c * h, volume);
        }
    grains.node_end[g] = static_cast<int>(nodes.size());
  }
};

/// Four grains: a 2D grid, a wall, a 3D grid whose interior rows (about 137 bonds) are longer than a
/// staging round of the passes, and a grain of two nodes; materials M1 in 2D and in 3D (horizon 0.6 mm),
/// whose bonds break in compression too when `in_compression` (the PeriDEM code's rule).
System make_system(bool in_compression = false) {
  System s;
  PdMaterial m2 = peridem_material_m1(2), m3 = peridem_material_m1(3);
  m2.break_in_compression = m3.break_in_compression = in_compression ? 1 : 0;
  s.lps = {PdLpsConstants::from(m2), PdLpsConstants::from(m3)};
  const double eps = m2.horizon, h = eps / 3.2;
  s.add_grid(PdGrainKind::particle, 0, eps, {0, 0, 0}, 13, 11, 1, h);
  s.add_grid(PdGrainKind::wall, 0, eps, {0, -3 * h, 0}, 15, 2, 1, h);
  s.add_grid(PdGrainKind::particle, 1, eps, {20 * h, 0, 0}, 7, 7, 7, h);
  s.add_grid(PdGrainKind::particle, 0, eps, {0, 20 * h, 0}, 2, 1, 1, h);
  s.bonds = BondList::build(s.nodes, s.grains, s.horizon);
  test::pd_weighted_volume_pass(s.lps, s.grains, s.bonds, s.nodes);
  return s;
}

/// Random displacements of 0.4 s_0 h, a band of the 2D grid pulled past s_0 (and with `squeeze`, another
/// pushed past -s_0), 10% of the bonds broken beforehand, and one bond of the 3D grid crushed to zero length.
void deform(System& s, std::uint64_t seed, bool squeeze = false) {
  const double s0 = s.lps[0].critical_stretch, h = s.lps[0].horizon / 3.2;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (std::size_t i = 0; i < s.nodes.size(); ++i) {
    const bool flat = s.grains.material[s.nodes.grain[i]] == 0;
    s.nodes.x[i] = s.nodes.x0[i] + 0.4 * s0 * h * u(rng) + 1.3 * s0 * std::max(0.0, s.nodes.x0[i] - 6 * h) +
                   (squeeze ? 1.3 * s0 * std::max(0.0, 3 * h - s.nodes.x0[i]) : 0.0);
    s.nodes.y[i] = s.nodes.y0[i] + 0.4 * s0 * h * u(rng);
    s.nodes.z[i] = s.nodes.z0[i] + (flat ? 0.0 : 0.4 * s0 * h * u(rng));
  }
  const int first3d = s.grains.node_begin[2];
  s.nodes.x[first3d + 1] = s.nodes.x[first3d];
  s.nodes.y[first3d + 1] = s.nodes.y[first3d];
  s.nodes.z[first3d + 1] = s.nodes.z[first3d];
  std::bernoulli_distribution pick(0.1);
  BondList& b = s.bonds;
  for (int i = 0; i < static_cast<int>(b.nodes()); ++i)
    for (int k = b.offset[i]; k < b.offset[i + 1]; ++k) {
      const int j = b.partner[k];
      if (i < j && pick(rng))
        for (int e = b.offset[j]; e < b.offset[j + 1]; ++e)
          if (b.partner[e] == i) b.broken[k] = b.broken[e] = 1;
    }
  std::fill(s.nodes.fx.begin(), s.nodes.fx.end(), 0.0);
  std::fill(s.nodes.fy.begin(), s.nodes.fy.end(), 0.0);
  std::fill(s.nodes.fz.begin(), s.nodes.fz.end(), 0.0);
}

Vec3 position(const System& s, int i) { return {s.nodes.x[i], s.nodes.y[i], s.nodes.z[i]}; }
const PdLpsConstants& constants(const System& s, int i) {
  return s.lps[static_cast<std::size_t>(s.grains.material[s.nodes.grain[i]])];
}

/// Theta (eq 34) and the force (eq 33) from the pure functions over the bonds intact now, against the
/// passes' theta and forces (forces zeroed before the step); returns the zero-length bond entries seen.
int expect_pure_bond_functions(const System& s) {
  const BondList& b = s.bonds;
  const int n = static_cast<int>(s.nodes.size());
  std::vector<double> theta(static_cast<std::size_t>(n), 0.0);
  for (int i = 0; i < n; ++i) {
    if (b.offset[i] == b.offset[i + 1]) continue;
    const PdLpsConstants& c = constants(s, i);
    double sum = 0.0;
    for (int k = b.offset[i]; k < b.offset[i + 1]; ++k) {
      if (b.broken[k]) continue;
      const int j = b.partner[k];
      const double x0 = b.length0[k], e = norm(position(s, j) - position(s, i)) - x0;
      sum += lps_dilatation_term(lps_bond_weight(lps_influence(x0 / c.horizon), s.nodes.volume[j]), x0, e);
    }
    theta[i] = lps_dilatation(c, sum, s.nodes.weighted_volume[i]);
  }
  double theta_max = 0.0;
  for (double t : theta) theta_max = std::max(theta_max, std::fabs(t));
  EXPECT_GT(theta_max, 0.0);
  int checked = 0, zero_length = 0;
  for (int i = 0; i < n; ++i) {
    EXPECT_NEAR(s.nodes.theta[i], theta[i], 1e-13 * theta_max) << "node " << i;
    const PdLpsConstants& c = constants(s, i);
    Vec3 f{};
    double scale = 0.0;
    for (int k = b.offset[i]; k < b.offset[i + 1]; ++k) {
      if (b.broken[k]) continue;
      const int j = b.partner[k];
      const Vec3 y = position(s, j) - position(s, i);
      zero_length += norm(y) == 0.0;
      const Vec3 t = lps_bond_force(c, y, b.length0[k], s.nodes.volume[j], theta[i], s.nodes.weighted_volume[i],
                                    theta[j], s.nodes.weighted_volume[j]);
      f += t;
      scale += norm(t);
    }
    f = s.nodes.volume[i] * f;
    scale *= s.nodes.volume[i];
    const Vec3 got{s.nodes.fx[i], s.nodes.fy[i], s.nodes.fz[i]};
    EXPECT_LE(norm(got - f), 1e-13 * scale + 1e-300) << "node " << i;
    checked += scale > 0.0;
  }
  EXPECT_GT(checked, n / 2);
  return zero_length;
}

TEST(PdBondPassesFast, StepEqualsThePureBondFunctionsSummedPerNode) {
  System s = make_system();
  deform(s, 7);
  const exec::DeviceVector<unsigned char> broken_before = s.bonds.broken;
  const long broke = test::pd_bond_step(s.lps, s.grains, s.bonds, s.nodes);
  const BondList& b = s.bonds;
  const int n = static_cast<int>(s.nodes.size());

  // Eq 11: exactly the intact entries whose stretch reached s_0 broke; both ends agree.
  long newly = 0;
  for (int i = 0; i < n; ++i)
    for (int k = b.offset[i]; k < b.offset[i + 1]; ++k) {
      const double stretch = lps_stretch(norm(position(s, b.partner[k]) - position(s, i)), b.length0[k]);
      const bool expect = broken_before[k] || lps_bond_breaks(stretch, constants(s, i).critical_stretch);
      ASSERT_EQ(b.broken[k], expect ? 1 : 0) << "entry " << k;
      newly += broken_before[k] ? 0 : b.broken[k];
    }
  EXPECT_GT(broke, 0);
  EXPECT_EQ(2 * broke, newly);

  EXPECT_EQ(expect_pure_bond_functions(s), 2) << "the crushed bond, seen from both ends, gives no force and no NaN";
}

struct Snapshot {
  exec::DeviceVector<double> theta, fx, fy, fz;
  exec::DeviceVector<unsigned char> broken;
  long broke = 0;
  bool operator==(const Snapshot&) const = default;
};

Snapshot snapshot(const System& s, long broke) {
  return {s.nodes.theta, s.nodes.fx, s.nodes.fy, s.nodes.fz, s.bonds.broken, broke};
}

/// Whether pd_bond_step must run its AVX2 sweeps here: a host build on an x86-64 CPU with AVX2 and FMA
/// (kernels/peridem/pd_bond_passes_avx2.cpp).
bool avx2_sweeps_expected() {
#if defined(__x86_64__)
  return !exec::offload_build() && __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
#else
  return false;
#endif
}

/// Which sweeps the pd_bond_step calls since `before` ran, "AVX2" or "portable", said on the test's output
/// and in its XML report; fails if they were not the ones this build and CPU must run (AVX2 where
/// avx2_sweeps_expected), or if any call ran the other ones.
std::string sweeps_ran_since(const PdBondStepCounts& before, long long calls) {
  const PdBondStepCounts after = pd_bond_step_counts();
  const long long avx2 = after.avx2 - before.avx2, portable = after.portable - before.portable;
  EXPECT_EQ(avx2 + portable, calls) << "pd_bond_step calls counted";
  const std::string ran = avx2 == calls ? "AVX2" : portable == calls ? "portable" : "mixed";
  ::testing::Test::RecordProperty("pd_bond_step_sweeps", ran);
  std::cout << "[ sweeps   ] pd_bond_step ran the " << ran << " sweeps (" << avx2 << " AVX2, " << portable
            << " portable calls); this CPU and build " << (avx2_sweeps_expected() ? "run" : "do not run")
            << " the AVX2 ones\n";
  if (avx2_sweeps_expected())
    EXPECT_EQ(avx2, calls) << "an x86-64 CPU with AVX2 and FMA: pd_bond_step must run the AVX2 sweeps";
  else
    EXPECT_EQ(portable, calls) << "no AVX2 sweeps in this build or on this CPU: pd_bond_step must run the portable "
                                  "ones";
  return ran;
}

// On CPUs with AVX2 pd_bond_step runs its own sweeps (intrinsics), the separate passes the compiler's vector
// loops: equal bits, for either breaking rule. The test says which sweeps pd_bond_step ran, and fails on such a
// CPU if they were not the AVX2 ones (else it would compare the portable sweeps with themselves).
class PdBondPassesFastRule : public ::testing::TestWithParam<bool> {};

TEST_P(PdBondPassesFastRule, FusedStepEqualsTheSeparatePassesBitForBitOnAnyThreadCount) {
  const bool in_compression = GetParam();
  const int saved = exec::threads();
  exec::set_threads(1);
  System fused = make_system(in_compression), separate = make_system(in_compression), two = make_system(in_compression);
  for (System* s : {&fused, &separate, &two}) deform(*s, 11, in_compression);
  const PdBondStepCounts before = pd_bond_step_counts();
  const Snapshot a = snapshot(fused, test::pd_bond_step(fused.lps, fused.grains, fused.bonds, fused.nodes));
  const long broke = test::break_bonds_reference(separate.lps, separate.grains, separate.bonds, separate.nodes);
  test::pd_dilatation_pass(separate.lps, separate.grains, separate.bonds, separate.nodes);
  test::pd_bond_force_pass(separate.lps, separate.grains, separate.bonds, separate.nodes);
  const Snapshot b = snapshot(separate, broke);
  exec::set_threads(2);
  const Snapshot c = snapshot(two, test::pd_bond_step(two.lps, two.grains, two.bonds, two.nodes));
  exec::set_threads(saved);
  const std::string sweeps = sweeps_ran_since(before, 2);
  EXPECT_GT(a.broke, 0);
  EXPECT_TRUE(a == b) << "pd_bond_step (" << sweeps << " sweeps) differs from break + dilatation + force";
  EXPECT_TRUE(a == c) << "pd_bond_step (" << sweeps << " sweeps) differs between 1 and 2 threads";
  // Under the compression rule, bonds shortened past s_0 broke too (none would under eq 11 alone).
  long compressed = 0;
  const BondList& bonds = fused.bonds;
  for (int i = 0; i < static_cast<int>(bonds.nodes()); ++i)
    for (int k = bonds.offset[i]; k < bonds.offset[i + 1]; ++k)
      compressed += bonds.broken[k] && lps_stretch(norm(position(fused, bonds.partner[k]) - position(fused, i)),
                                                   bonds.length0[k]) <= -fused.lps[0].critical_stretch;
  if (in_compression)
    EXPECT_GT(compressed, 0);
  else
    EXPECT_EQ(compressed, 0);
}
INSTANTIATE_TEST_SUITE_P(BreakingRule, PdBondPassesFastRule, ::testing::Values(false, true),
                         [](const ::testing::TestParamInfo<bool>& info) {
                           return info.param ? std::string("InCompressionToo") : std::string("TensionOnly");
                         });

/// make_system's grains and ten more 2D grids after them: 71,816 bond entries in 14 grains, so the sweeps'
/// 17 blocks of about 4,096 entries (cut anywhere in a grain) fall on every kind of grain, and blocks of
/// whole grains would be many too (make_system's are four grains, the 3D one 28,254 entries).
System make_many_grains() {
  System s = make_system();
  const double eps = s.lps[0].horizon, h = eps / 3.2;
  for (int g = 0; g < 10; ++g) s.add_grid(PdGrainKind::particle, 0, eps, {(40 + 15 * g) * h, 0, 0}, 13, 11, 1, h);
  s.bonds = BondList::build(s.nodes, s.grains, s.horizon);
  test::pd_weighted_volume_pass(s.lps, s.grains, s.bonds, s.nodes);
  return s;
}

// Many blocks, one and two threads: each node's sums must not depend on which block or thread sweeps its row.
// (A sweep that takes each bond once, from its lower node, must cut its blocks between grains only: cut
// inside a grain, such a sweep fails this test.)
TEST(PdBondPassesFast, ManyGrainsStepEqualsThePureFunctionsAndIsTheSameOnTwoThreads) {
  const int saved = exec::threads();
  exec::set_threads(1);
  System one = make_many_grains(), two = make_many_grains();
  ASSERT_GT(one.bonds.entries(), 60000u);
  for (System* s : {&one, &two}) deform(*s, 13);
  const long broke = test::pd_bond_step(one.lps, one.grains, one.bonds, one.nodes);
  exec::set_threads(2);
  const Snapshot b = snapshot(two, test::pd_bond_step(two.lps, two.grains, two.bonds, two.nodes));
  exec::set_threads(saved);
  EXPECT_GT(broke, 0);
  EXPECT_EQ(expect_pure_bond_functions(one), 2);
  EXPECT_TRUE(snapshot(one, broke) == b) << "pd_bond_step differs between 1 and 2 threads";
}

/// The 2D grains of make_system and the wall, every node at z = 0 but the wall's, at wall_z: the wall has no
/// bonds, so wall_z changes nothing of the physics, only whether the nodes lie in one plane.
System make_flat_system(double wall_z) {
  System s;
  const PdMaterial m2 = peridem_material_m1(2);
  s.lps = {PdLpsConstants::from(m2)};
  const double eps = m2.horizon, h = eps / 3.2;
  s.add_grid(PdGrainKind::particle, 0, eps, {0, 0, 0}, 13, 11, 1, h);
  s.add_grid(PdGrainKind::wall, 0, eps, {0, -3 * h, wall_z}, 15, 2, 1, h);
  s.add_grid(PdGrainKind::particle, 0, eps, {0, 20 * h, 0}, 2, 1, 1, h);  // deform() crushes its bond
  s.bonds = BondList::build(s.nodes, s.grains, s.horizon);
  test::pd_weighted_volume_pass(s.lps, s.grains, s.bonds, s.nodes);
  return s;
}

TEST(PdBondPassesFast, PlanarSweepsEqualThe3DSweepsBitForBit) {
  System flat = make_flat_system(0.0), lifted = make_flat_system(1e-3);
  for (System* s : {&flat, &lifted}) deform(*s, 5);
  for (System* s : {&flat, &lifted}) to_device(s->nodes);
  ASSERT_TRUE(pd_nodes_in_one_plane(flat.nodes));
  ASSERT_FALSE(pd_nodes_in_one_plane(lifted.nodes)) << "the lifted wall puts the nodes in two planes";
  const Snapshot a = snapshot(flat, test::pd_bond_step(flat.lps, flat.grains, flat.bonds, flat.nodes));
  const Snapshot b = snapshot(lifted, test::pd_bond_step(lifted.lps, lifted.grains, lifted.bonds, lifted.nodes));
  EXPECT_GT(a.broke, 0);
  EXPECT_TRUE(a == b) << "the planar sweeps differ from the 3D ones";  // == on doubles: fz 0 and -0 agree
  double theta_max = 0.0, f_max = 0.0;
  for (std::size_t i = 0; i < flat.nodes.size(); ++i) {
    theta_max = std::max(theta_max, std::fabs(a.theta[i]));
    f_max = std::max(f_max, std::hypot(a.fx[i], a.fy[i]));
    EXPECT_EQ(a.fz[i], 0.0) << "node " << i;
    EXPECT_TRUE(std::isfinite(a.fx[i]) && std::isfinite(a.fy[i])) << "node " << i;
  }
  EXPECT_GT(theta_max, 0.0);
  EXPECT_GT(f_max, 0.0);
}

TEST(PdBondPassesFast, OnePlaneMeansTheSameFiniteZ) {
  System s = make_flat_system(0.0);
  const auto check = [&s] {
    to_device(s.nodes);
    return pd_nodes_in_one_plane(s.nodes);
  };
  for (double& z : s.nodes.z) z = 2.5e-3;  // any plane z = const
  EXPECT_TRUE(check());
  s.nodes.z[3] = std::nextafter(2.5e-3, 1.0);
  EXPECT_FALSE(check());
  s.nodes.z[3] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(check()) << "a NaN z takes the 3D sweeps";
  for (double& z : s.nodes.z) z = 2.5e-3;
  s.nodes.z[0] = std::numeric_limits<double>::quiet_NaN();  // the node the others are compared with
  EXPECT_FALSE(check());
  for (double& z : s.nodes.z) z = 0.0;
  s.nodes.z[5] = std::numeric_limits<double>::denorm_min();  // the smallest difference there is
  EXPECT_FALSE(check());
  for (double& z : s.nodes.z) z = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(check());
}

// The portable kernels hold no back-end code: a CPU-specific variant of a pass (intrinsics, target
// attributes, CPU checks) lives in a file named for its back end (pd_bond_passes_avx2.cpp), which only the
// builds of that back end compile and pd_bond_step chooses at one point.
TEST(PdBondPassesLayout, PortableKernelFilesHoldNoBackEndCode) {
  const std::filesystem::path kernels = std::filesystem::path(DEBRIS_SOURCE_DIR) / "kernels";
  const std::vector<std::string> back_end_file_suffixes = {"_avx2", "_avx512", "_neon", "_sve"};
  const std::vector<std::string> back_end_code = {"__attribute__", "immintrin", "x86intrin", "_mm256_", "_mm512_",
                                                  "_mm_", "__m256", "__m128", "__x86_64__", "__AVX",
                                                  "__builtin_cpu_supports", "pragma GCC target", "__aarch64__"};
  const auto read = [](const std::filesystem::path& p) {
    std::ifstream in(p);
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
  };
  int portable = 0;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(kernels)) {
    const std::filesystem::path& p = entry.path();
    if (p.extension() != ".cpp" && p.extension() != ".hpp") continue;
    const std::string stem = p.stem().string();
    const bool back_end = std::any_of(back_end_file_suffixes.begin(), back_end_file_suffixes.end(),
                                      [&](const std::string& s) { return stem.ends_with(s); });
    if (back_end) continue;
    ++portable;
    const std::string text = read(p);
    for (const std::string& code : back_end_code)
      EXPECT_EQ(text.find(code), std::string::npos) << p.string() << " holds back-end code: " << code;
  }
  EXPECT_GT(portable, 10);
  const std::string avx2 = read(kernels / "peridem" / "pd_bond_passes_avx2.cpp");
  EXPECT_NE(avx2.find("_mm256_"), std::string::npos) << "the AVX2 sweeps live in pd_bond_passes_avx2.cpp";
}

// ---------------------------------------------------------------------------------------------------------
// Contact list: rows of about 20 partners (more than the build keeps from its counting pass).

TEST(PdContactListFast, LongRowsMatchBruteForceOnAnyThreadCount) {
  System s;
  const double h = 1.0;
  s.add_grid(PdGrainKind::particle, 0, 1.5, {0, 0, 0}, 9, 9, 1, h);
  s.add_grid(PdGrainKind::wall, 0, 1.5, {-2, -2.2, 0}, 14, 2, 1, h);
  s.add_grid(PdGrainKind::wall, 0, 1.5, {-2, -4.2, 0}, 14, 2, 1, h);  // walls never touch walls
  s.add_grid(PdGrainKind::particle, 0, 1.5, {9.6, 0.3, 0}, 5, 5, 1, h);
  s.bonds = BondList::build(s.nodes, s.grains, s.horizon);
  // Break a few bonds: their two nodes become self-contact candidates.
  for (int k = 0; k < static_cast<int>(s.bonds.entries()); k += 7) {
    const int i =
        static_cast<int>(std::upper_bound(s.bonds.offset.begin(), s.bonds.offset.end(), k) - s.bonds.offset.begin()) -
        1;
    const int j = s.bonds.partner[k];
    for (int e = s.bonds.offset[j]; e < s.bonds.offset[j + 1]; ++e)
      if (s.bonds.partner[e] == i) s.bonds.broken[k] = s.bonds.broken[e] = 1;
  }
  const double cutoff = 2.0, skin = 0.5, reach = cutoff + skin;
  const int n = static_cast<int>(s.nodes.size());
  std::vector<std::vector<int>> expect(static_cast<std::size_t>(n));
  std::size_t longest = 0;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      if (j == i || norm(position(s, j) - position(s, i)) >= reach) continue;
      const int gi = s.nodes.grain[i], gj = s.nodes.grain[j];
      const bool walls = s.grains.kind[gi] == 1 && s.grains.kind[gj] == 1;
      if (walls || (gi == gj && s.bonds.intact(i, j))) continue;
      expect[static_cast<std::size_t>(i)].push_back(j);
    }
    longest = std::max(longest, expect[static_cast<std::size_t>(i)].size());
  }
  ASSERT_GT(longest, 12u) << "rows must outgrow the build's buffer";
  const int saved = exec::threads();
  exec::DeviceVector<int> index_one;
  for (const int threads : {1, 2}) {
    exec::set_threads(threads);
    PdContactList list;
    test::build_list(list, s.nodes, s.grains, s.bonds, cutoff, skin);
    ASSERT_EQ(list.rows(), n);
    for (int i = 0; i < n; ++i) {
      std::vector<int> row(list.index().begin() + list.offset()[i], list.index().begin() + list.offset()[i + 1]);
      std::sort(row.begin(), row.end());
      EXPECT_EQ(row, expect[static_cast<std::size_t>(i)]) << threads << " threads, node " << i;
    }
    if (threads == 1)
      index_one = list.index();
    else
      EXPECT_EQ(list.index(), index_one) << "rows in the same order with 1 and 2 threads";
  }
  exec::set_threads(saved);
}

}  // namespace
}  // namespace debris
