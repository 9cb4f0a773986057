// Whole PeriDEM grains on their centre's rank (core/comm/grain_migration): every grain on exactly
// one rank, the one owning its centre, with its nodes, record and bond rows bit for bit those of the whole
// system every rank also holds, after the set-up and after each of 30 rounds of motion that makes grains
// cross the cuts (and a periodic face) back and forth; storage in one process's order.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <map>
#include <random>
#include <string>
#include <type_traits>
#include <vector>

#include "core/comm/communicator.hpp"
#include "core/comm/grain_migration.hpp"
#include "tests/mpi/rank_grids.hpp"

namespace debris::comm {
namespace {

// A box 1 x 0.8 x 0.6, periodic along x only; ghost width 0.05 (every grid of tests/mpi/rank_grids fits).
Box grain_box() { return Box({0, 0, 0}, {1, 0.8, 0.6}, {true, false, false}); }
constexpr double kGhostWidth = 0.05;

struct System {
  PdNodes nodes;
  PdGrains grains;
  BondList bonds;
  GrainStore store() { return {nodes, grains, bonds}; }
};

// 60 grains of 5-15 nodes (ids consecutive from 1, grain after grain) within 0.03 of their centre; bonds
// within 0.04 (BondList::build), a fifth of them broken (both ends alike).
System make_grains() {
  System s;
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const Box box = grain_box();
  std::int64_t id = 1;
  const int count = 60;
  s.grains.resize(count);
  for (int g = 0; g < count; ++g) {
    const auto k = static_cast<std::size_t>(g);
    const Vec3 lo = box.lo(), hi = box.hi();
    const double c[3] = {lo.x + u(rng) * (hi.x - lo.x), lo.y + 0.05 + u(rng) * (hi.y - lo.y - 0.1),
                         lo.z + 0.05 + u(rng) * (hi.z - lo.z - 0.1)};
    const int n = 5 + (7 * g) % 11;
    s.grains.node_begin[k] = static_cast<int>(s.nodes.size());
    double sum[3] = {0, 0, 0};
    for (int j = 0; j < n; ++j) {
      const double p[3] = {c[0] + 0.03 * (2 * u(rng) - 1), c[1] + 0.03 * (2 * u(rng) - 1), c[2] + 0.03 * (2 * u(rng) - 1)};
      const std::size_t i = s.nodes.add(id++, g, p[0], p[1], p[2], 1e-3 * (1 + u(rng)));
      s.nodes.vx[i] = u(rng), s.nodes.vy[i] = u(rng), s.nodes.vz[i] = u(rng);
      s.nodes.fx[i] = u(rng), s.nodes.damage[i] = u(rng), s.nodes.theta[i] = u(rng);
      s.nodes.mass[i] = 2 * s.nodes.volume[i], s.nodes.weighted_volume[i] = u(rng), s.nodes.fixed[i] = j % 3;
      for (int a = 0; a < 3; ++a) sum[a] += p[a];
    }
    s.grains.node_end[k] = static_cast<int>(s.nodes.size());
    s.grains.kind[k] = static_cast<int>(PdGrainKind::particle);
    s.grains.id[k] = g;
    s.grains.material[k] = g % 2;
    s.grains.volume[k] = u(rng);
    s.grains.cx[k] = sum[0] / n, s.grains.cy[k] = sum[1] / n, s.grains.cz[k] = sum[2] / n;
    s.grains.cvx[k] = u(rng), s.grains.cvy[k] = u(rng), s.grains.cvz[k] = u(rng);
  }
  s.bonds = BondList::build(s.nodes, s.grains, std::vector<double>(count, 0.04));
  for (std::size_t i = 0; i + 1 < s.bonds.offset.size(); ++i)
    for (int e = s.bonds.offset[i]; e < s.bonds.offset[i + 1]; ++e) {
      const auto j = static_cast<std::size_t>(s.bonds.partner[static_cast<std::size_t>(e)]);
      const std::int64_t a = std::min(s.nodes.id[i], s.nodes.id[j]), b = std::max(s.nodes.id[i], s.nodes.id[j]);
      s.bonds.broken[static_cast<std::size_t>(e)] = (a * 31 + b * 17) % 5 == 0 ? 1 : 0;
    }
  // Weights as pd_weighted_volume_pass leaves them, one per entry (values that tell entries apart).
  s.bonds.weight.resize(s.bonds.entries());
  for (std::size_t e = 0; e < s.bonds.entries(); ++e)
    s.bonds.weight[e] = s.bonds.length0[e] * (1.0 + 1e-3 * s.bonds.partner[e]);
  return s;
}

// Round t's motion of a grain (by its first node's id), the same on every rank: up to 0.06 along each axis,
// back and forth, so grains cross cuts many times; y and z kept inside the walls, x wrapped (whole grain).
void move(System& s, int t) {
  const Box box = grain_box();
  for (std::size_t g = 0; g < s.grains.size(); ++g) {
    const auto begin = static_cast<std::size_t>(s.grains.node_begin[g]), end = static_cast<std::size_t>(s.grains.node_end[g]);
    const std::int64_t key = s.nodes.id[begin];
    std::mt19937_64 rng(static_cast<std::uint64_t>(key * 1000 + t));
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    double d[3] = {0.06 * u(rng), 0.06 * u(rng), 0.06 * u(rng)};
    double* c[3] = {&s.grains.cx[g], &s.grains.cy[g], &s.grains.cz[g]};
    const double lo[3] = {box.lo().x, box.lo().y, box.lo().z}, hi[3] = {box.hi().x, box.hi().y, box.hi().z};
    for (int a = 1; a < 3; ++a)
      if (*c[a] + d[a] < lo[a] + 0.04 || *c[a] + d[a] > hi[a] - 0.04) d[a] = -d[a];
    if (*c[0] + d[0] >= hi[0]) d[0] -= hi[0] - lo[0];  // the periodic face: the whole grain wraps
    if (*c[0] + d[0] < lo[0]) d[0] += hi[0] - lo[0];
    for (int a = 0; a < 3; ++a) *c[a] += d[a];
    for (std::size_t i = begin; i < end; ++i) s.nodes.x[i] += d[0], s.nodes.y[i] += d[1], s.nodes.z[i] += d[2];
  }
}

template <class V>
bool same_range(const V& a, std::size_t ab, const V& b, std::size_t bb, std::size_t n) {
  return n == 0 || std::memcmp(&a[ab], &b[bb], n * sizeof(a[0])) == 0;
}

// Every grain of `mine` is the whole system's grain of the same first node id, bit for bit; mine are sorted
// by that id and owned here; all ranks together hold each grain once. Returns a description of the first
// difference, or "".
std::string check(const Decomposition& d, System& mine, System& whole) {
  const Box box = grain_box();
  std::map<std::int64_t, std::size_t> whole_of;
  for (std::size_t g = 0; g < whole.grains.size(); ++g)
    whole_of[whole.nodes.id[static_cast<std::size_t>(whole.grains.node_begin[g])]] = g;
  std::int64_t held = static_cast<std::int64_t>(mine.grains.size());
  allreduce_sum(&held, 1);
  if (held != static_cast<std::int64_t>(whole.grains.size()))
    return std::to_string(held) + " grains on all ranks, not " + std::to_string(whole.grains.size());
  std::int64_t before = 0;
  for (std::size_t g = 0; g < mine.grains.size(); ++g) {
    const auto mb = static_cast<std::size_t>(mine.grains.node_begin[g]), me = static_cast<std::size_t>(mine.grains.node_end[g]);
    const std::int64_t key = mine.nodes.id[mb];
    const std::string which = "grain of node " + std::to_string(key);
    if (key <= before) return which + " out of order";
    before = key;
    if (d.owner(box, mine.grains.cx[g], mine.grains.cy[g], mine.grains.cz[g]) != d.rank()) return which + " not owned here";
    const std::size_t w = whole_of.at(key);
    const auto wb = static_cast<std::size_t>(whole.grains.node_begin[w]), we = static_cast<std::size_t>(whole.grains.node_end[w]);
    if (me - mb != we - wb) return which + ": node count differs";
    for (std::size_t i = mb; i < me; ++i)
      if (mine.nodes.grain[i] != static_cast<int>(g)) return which + ": a node names another grain";
    bool same = true;
    mine.nodes.for_each_column([&](const char* name, auto& col) {
      if (std::string(name) == "grain") return;
      whole.nodes.for_each_column([&](const char* other, auto& wcol) {
        if constexpr (std::is_same_v<decltype(col), decltype(wcol)>)
          if (std::string(name) == other) same = same && same_range(col, mb, wcol, wb, me - mb);
      });
    });
    if (!same) return which + ": node columns differ";
    for (const auto m : {&PdGrains::kind, &PdGrains::material, &PdGrains::id})
      if ((mine.grains.*m)[g] != (whole.grains.*m)[w]) return which + ": record differs";
    for (const auto m : {&PdGrains::volume, &PdGrains::cx, &PdGrains::cy, &PdGrains::cz, &PdGrains::cvx, &PdGrains::cvy,
                         &PdGrains::cvz, &PdGrains::wall_vx, &PdGrains::wall_vy, &PdGrains::wall_vz})
      if (std::memcmp(&(mine.grains.*m)[g], &(whole.grains.*m)[w], sizeof(double)) != 0) return which + ": record differs";
    for (std::size_t k = 0; k < me - mb; ++k) {
      const std::size_t i = mb + k, j = wb + k;
      const int n = mine.bonds.offset[i + 1] - mine.bonds.offset[i];
      if (n != whole.bonds.offset[j + 1] - whole.bonds.offset[j]) return which + ": bond count differs";
      for (int e = 0; e < n; ++e) {
        const auto a = static_cast<std::size_t>(mine.bonds.offset[i] + e), b = static_cast<std::size_t>(whole.bonds.offset[j] + e);
        if (mine.bonds.partner[a] - static_cast<int>(mb) != whole.bonds.partner[b] - static_cast<int>(wb) ||
            std::memcmp(&mine.bonds.length0[a], &whole.bonds.length0[b], sizeof(double)) != 0 ||
            mine.bonds.broken[a] != whole.bonds.broken[b] ||
            std::memcmp(&mine.bonds.weight[a], &whole.bonds.weight[b], sizeof(double)) != 0)
          return which + ": bond rows differ";
      }
    }
  }
  if (mine.bonds.offset.size() != mine.nodes.size() + 1) return "bond offsets do not match the nodes";
  if (mine.bonds.weight.size() != mine.bonds.entries()) return "the bond weights did not travel with the rows";
  return "";
}

TEST(GrainMigration, EveryGrainOnItsCentresRankWithItsNodesAndBondsAfterEveryMove) {
  for (const auto grid : test::grids_for(size())) {
    const std::string name = std::to_string(grid[0]) + "x" + std::to_string(grid[1]) + "x" + std::to_string(grid[2]);
    const Decomposition d = Decomposition::make(grain_box(), size(), rank(), kGhostWidth, grid);
    System whole = make_grains(), mine = make_grains();
    keep_owned_grains(d, grain_box(), mine.store());
    std::string problem = first_message(check(d, mine, whole));
    EXPECT_EQ(problem, "") << "set-up, " << name;
    std::int64_t moved = 0;
    for (int t = 1; t <= 30 && problem.empty(); ++t) {
      move(whole, t);
      move(mine, t);
      moved += static_cast<std::int64_t>(exchange_grains(d, grain_box(), mine.store()).sent);
      problem = first_message(check(d, mine, whole));
      EXPECT_EQ(problem, "") << "round " << t << ", " << name;
    }
    allreduce_sum(&moved, 1);
    if (size() > 1) EXPECT_GT(moved, 100) << name << ": grains must cross the cuts";
    if (rank() == 0) std::printf("[ info ] grains, %s: %lld moves between ranks in 30 rounds\n", name.c_str(),
                                 static_cast<long long>(moved));
  }
}

TEST(GrainMigration, AGrainThatJumpsPastTheNextRankIsNamed) {
  if (size() < 3) GTEST_SKIP() << "needs three ranks along y";
  // Cut along y, which is walled (along the periodic x, three ranks are all each other's neighbours).
  const Decomposition d = Decomposition::make(grain_box(), size(), rank(), kGhostWidth, {1, size(), 1});
  System mine = make_grains();
  keep_owned_grains(d, grain_box(), mine.store());
  // Rank 0 sends one of its grains two subdomains along y (the middle of rank 2's slab).
  if (rank() == 0 && mine.grains.size() > 0) {
    mine.grains.cy[0] = 2.5 * 0.8 / size();
    std::string error;
    try {
      exchange_grains(d, grain_box(), mine.store());
    } catch (const std::runtime_error& e) {
      error = e.what();
    }
    EXPECT_NE(error.find("moved past the next rank along y"), std::string::npos) << error;
  }
  // The others would wait for rank 0's messages: they do not call it (a real run aborts every rank).
}

}  // namespace
}  // namespace debris::comm
