// comm::Halo and comm::exchange under any rank count: the ghost layer against a brute force over every
// particle (all ranks know the whole system here), ghosts with their owners' bits, forward communication,
// and migration with pair rows over many steps, also when particles cross ranks every step.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <map>
#include <random>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "core/box.hpp"
#include "core/comm/communicator.hpp"
#include "core/comm/decomposition.hpp"
#include "core/comm/halo.hpp"
#include "core/comm/migration.hpp"
#include "core/comm/pack.hpp"
#include "core/particles.hpp"
#include "tests/mpi/rank_grids.hpp"

namespace debris::comm {
namespace {

using test::grids_for;

double axis_value(Vec3 v, int a) { return a == 0 ? v.x : (a == 1 ? v.y : v.z); }

using Shift = std::array<std::int8_t, 3>;


// The bits of every column of particle i, in column order.
std::vector<std::uint64_t> column_bits(const Particles& p, std::size_t i) {
  std::vector<std::uint64_t> bits;
  p.for_each_column([&](const char*, const auto& col) {
    std::uint64_t w = 0;
    std::memcpy(&w, &col[i], sizeof(col[i]));
    bits.push_back(w);
  });
  return bits;
}

// Every column of particle i of `a` has the bits of particle j of `b`.
bool same_bits(const Particles& a, std::size_t i, const Particles& b, std::size_t j) {
  return column_bits(a, i) == column_bits(b, j);
}

// The whole system, the same on every rank: random particles, and particles exactly on every cut plane of
// `d` and on the box's faces (the periodic ones included), where ownership and wrapping are decided.
Particles make_system(const Box& box, const Decomposition& d, int n, unsigned seed) {
  Particles p;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::int64_t id = 0;
  const auto add = [&](double x, double y, double z) {
    const std::size_t i = p.add(id, 1 + static_cast<int>(id % 3), x, y, z, 0.01 + 1e-5 * static_cast<double>(id % 7));
    p.vx[i] = u(rng) - 0.5;
    p.vy[i] = u(rng) - 0.5;
    p.vz[i] = u(rng) - 0.5;
    p.wx[i] = u(rng);
    p.wy[i] = u(rng);
    p.wz[i] = u(rng);
    p.mass[i] = 1.0 + u(rng);
    p.group[i] = static_cast<int>(id % 4) - 1;
    p.label[i] = static_cast<int>(id % 2);
    ++id;
  };
  const Vec3 lo = box.lo(), len = box.length();
  for (int k = 0; k < n; ++k) add(lo.x + u(rng) * len.x, lo.y + u(rng) * len.y, lo.z + u(rng) * len.z);
  for (int a = 0; a < 3; ++a) {
    std::vector<double> planes{axis_value(lo, a), std::nextafter(axis_value(box.hi(), a), axis_value(lo, a))};
    for (int i = 1; i < d.grid()[a]; ++i) planes.push_back(d.cut(box, a, i));
    for (const double c : planes)
      for (int k = 0; k < 6; ++k) {
        double q[3] = {lo.x + u(rng) * len.x, lo.y + u(rng) * len.y, lo.z + u(rng) * len.z};
        q[a] = c;
        add(q[0], q[1], q[2]);
      }
  }
  // Corners of the box.
  add(lo.x, lo.y, lo.z);
  add(std::nextafter(box.hi().x, 0.0), std::nextafter(box.hi().y, 0.0), std::nextafter(box.hi().z, 0.0));
  return p;
}

// The ghosts rank `d.rank()` must hold: (id, shift) of every image of every particle within `w` of its
// subdomain along each cut axis, its own particles as they are excepted.
std::set<std::pair<std::int64_t, Shift>> expected_ghosts(const Box& box, const Decomposition& d, double w,
                                                         const Particles& all) {
  std::set<std::pair<std::int64_t, Shift>> want;
  for (std::size_t j = 0; j < all.size(); ++j) {
    const bool mine = d.owner(box, all.x[j], all.y[j], all.z[j]) == d.rank();
    for (int sx = -1; sx <= 1; ++sx)
      for (int sy = -1; sy <= 1; ++sy)
        for (int sz = -1; sz <= 1; ++sz) {
          const int s[3] = {sx, sy, sz};
          bool inside = true;
          for (int a = 0; a < 3 && inside; ++a) {
            const bool cut = d.grid()[a] > 1;
            if (!cut || !box.periodic(a)) inside = s[a] == 0;
            if (!inside || !cut) continue;
            const double c = position(all, a)[j] + s[a] * box.length(a);
            inside = c >= d.sub_lo(box, a) - w && c < d.sub_hi(box, a) + w;
          }
          if (!inside || (mine && sx == 0 && sy == 0 && sz == 0)) continue;
          want.insert({all.id[j], Shift{static_cast<std::int8_t>(sx), static_cast<std::int8_t>(sy),
                                        static_cast<std::int8_t>(sz)}});
        }
  }
  return want;
}

std::map<std::int64_t, std::size_t> index_by_id(const Particles& p) {
  std::map<std::int64_t, std::size_t> m;
  for (std::size_t i = 0; i < p.size(); ++i) m[p.id[i]] = i;
  return m;
}


// Periodic on all axes, on none, and on x and y with walls in z (the sheared junction's box).
std::vector<std::array<bool, 3>> periodicities() { return {{true, true, true}, {false, false, false}, {true, true, false}}; }

TEST(Halo, GhostsAreExactlyTheParticlesWithinTheWidthWithTheirOwnersBits) {
  for (const auto per : periodicities())
    for (const auto g : grids_for(size())) {
      const Box box({-0.4, 0.1, 0.0}, {2.0, 2.3, 1.9}, per);
      const double w = 0.1731;  // cut planes and faces are not a width away from another plane
      const auto d = Decomposition::make(box, size(), rank(), w, g);
      const Particles all = make_system(box, d, 3000, 17);
      Particles p = all;
      keep_owned(d, box, p);
      // Ownership: each particle on exactly one rank.
      std::int64_t owned = static_cast<std::int64_t>(p.size());
      allreduce_sum(&owned, 1);
      EXPECT_EQ(owned, static_cast<std::int64_t>(all.size()));

      Halo halo;
      halo.borders(d, box, w, p, p.size());
      const std::string where = d.describe() + ", periodic " + std::to_string(per[0]) + std::to_string(per[1]) +
                                std::to_string(per[2]) + ", rank " + std::to_string(rank());
      std::set<std::pair<std::int64_t, Shift>> got;
      const auto ref = index_by_id(all);
      for (std::size_t k = 0; k < halo.ghosts(); ++k) {
        const std::size_t i = halo.owned() + k;
        EXPECT_TRUE(got.insert({p.id[i], halo.shifts()[k]}).second) << "ghost " << p.id[i] << " twice, " << where;
        EXPECT_TRUE(same_bits(p, i, all, ref.at(p.id[i]))) << "ghost " << p.id[i] << " differs from its owner, " << where;
      }
      const auto want = expected_ghosts(box, d, w, all);
      EXPECT_EQ(got.size(), want.size()) << where;
      EXPECT_TRUE(got == want) << where;
      if (size() > 1 && d.grid() != std::array<int, 3>{1, 1, 1}) EXPECT_GT(halo.ghosts(), 0u) << where;

      // Forward: the owners change x, v and omega; the ghosts then carry the new bits, nothing else moved.
      Particles moved = all;
      for (std::size_t j = 0; j < moved.size(); ++j) {
        moved.x[j] += 1e-3 * std::sin(static_cast<double>(moved.id[j]));
        moved.vy[j] *= -3.0;
        moved.wz[j] += 0.25;
      }
      const auto in_moved = index_by_id(moved);
      for (std::size_t i = 0; i < halo.owned(); ++i) {
        const std::size_t j = in_moved.at(p.id[i]);
        p.x[i] = moved.x[j];
        p.vy[i] = moved.vy[j];
        p.wz[i] = moved.wz[j];
      }
      halo.forward(p);
      for (std::size_t i = halo.owned(); i < p.size(); ++i)
        EXPECT_TRUE(same_bits(p, i, moved, in_moved.at(p.id[i]))) << "forwarded ghost " << p.id[i] << ", " << where;
      std::int64_t bytes = static_cast<std::int64_t>(halo.forward_bytes()), ghosts = static_cast<std::int64_t>(halo.ghosts());
      allreduce_sum(&bytes, 1);
      allreduce_sum(&ghosts, 1);
      EXPECT_EQ(bytes, ghosts * 72) << "x, v and omega: 72 B per ghost";
    }
}

// The reference motion of particle `id` at `step`, the same on every rank: a displacement of up to 0.45 w
// per axis (a particle moves less than skin/2 < w between rebuilds), biased across the nearest cut plane
// when `stress` asks for migration at every step.
Vec3 displacement(std::int64_t id, int step, double w) {
  std::mt19937_64 rng(static_cast<std::uint64_t>(id) * 1000003u + static_cast<std::uint64_t>(step));
  std::uniform_real_distribution<double> u(-0.45 * w, 0.45 * w);
  return {u(rng), u(rng), u(rng)};
}

// Pair rows of a particle: its partners are the ids id +- 1..3, each with values of the unordered pair,
// as the contact history keys them (lower id first), then changed per step so stale rows are caught.
void rows_for(std::int64_t id, int step, std::vector<std::int64_t>& partner, std::vector<double>& value) {
  for (const std::int64_t off : {-3, -1, 2, 3}) {
    const std::int64_t q = id + off;
    if (q < 0) continue;
    const std::int64_t lo = std::min(id, q), hi = std::max(id, q);
    partner.push_back(q);
    value.push_back(static_cast<double>(lo) + 0.5 * step);
    value.push_back(static_cast<double>(hi) * 1e-3);
    value.push_back(std::sin(static_cast<double>(lo * 31 + hi + step)));
  }
}

void check_migration(const Box& box0, std::array<int, 3> g, int steps, bool stress) {
  Box box = box0;
  const double w = 0.1731;
  const auto d = Decomposition::make(box, size(), rank(), w, g);
  Particles all = make_system(box, d, 2000, 29);
  if (stress) {  // everyone within 0.4 w of a cut plane or a periodic face: most cross at every step
    std::mt19937_64 rng(3);
    for (std::size_t j = 0; j < all.size(); ++j) {
      const int a = static_cast<int>(j % 3);
      const int c = static_cast<int>(rng() % static_cast<std::uint64_t>(d.grid()[a] + 1));
      double* q = a == 0 ? &all.x[j] : (a == 1 ? &all.y[j] : &all.z[j]);
      const double plane = d.cut(box, a, c) + (std::uniform_real_distribution<double>(-0.4, 0.4)(rng)) * w;
      if (box.periodic(a) || (plane >= axis_value(box.lo(), a) && plane < axis_value(box.hi(), a))) *q = plane;
    }
    box.wrap(all);
  }
  Particles p = all;
  keep_owned(d, box, p);
  PairRows rows;
  for (std::size_t i = 0; i < p.size(); ++i) {
    rows_for(p.id[i], 0, rows.partner, rows.value);
    rows.offset.push_back(rows.partner.size());
  }
  std::int64_t crossings = 0;
  for (int step = 1; step <= steps; ++step) {
    // The same motion on the whole system and on this rank's share: the ghosts are dropped first, as at a
    // rebuild; the stress test turns each particle back across the plane it just crossed.
    for (Particles* q : {&all, &p})
      for (std::size_t i = 0; i < q->size(); ++i) {
        Vec3 s = displacement(q->id[i], stress ? 0 : step, w);
        if (stress && step % 2 == 0) s = -s;
        q->x[i] += s.x;
        q->y[i] += s.y;
        q->z[i] += s.z;
        q->vx[i] = step;
      }
    box.wrap(all);
    box.wrap(p);
    for (std::size_t i = 0; i < p.size(); ++i) {  // rows change per step: a stale row is caught
      std::vector<std::int64_t> part;
      std::vector<double> val;
      rows_for(p.id[i], step, part, val);
      std::copy(val.begin(), val.end(), rows.value.begin() + static_cast<long>(3 * rows.offset[i]));
    }
    const ExchangeCount moved = exchange(d, box, p, &rows);
    crossings += static_cast<std::int64_t>(moved.sent);
    // Every particle on its owner, once, with the whole system's bits and its own rows.
    std::int64_t n = static_cast<std::int64_t>(p.size());
    allreduce_sum(&n, 1);
    ASSERT_EQ(n, static_cast<std::int64_t>(all.size())) << "step " << step;
    const auto ref = index_by_id(all);
    bool all_good = true;
    for (std::size_t i = 0; i < p.size() && all_good; ++i) {
      all_good = d.owner(box, p.x[i], p.y[i], p.z[i]) == rank() && same_bits(p, i, all, ref.at(p.id[i]));
      std::vector<std::int64_t> part;
      std::vector<double> val;
      rows_for(p.id[i], step, part, val);
      all_good = all_good && rows.rows_of(i) == part.size() &&
                 std::equal(part.begin(), part.end(), rows.partner.begin() + static_cast<long>(rows.offset[i])) &&
                 std::equal(val.begin(), val.end(), rows.value.begin() + static_cast<long>(3 * rows.offset[i]));
      EXPECT_TRUE(all_good) << "particle " << p.id[i] << " at step " << step << ", rank " << rank() << ", "
                            << d.describe();
    }
  }
  allreduce_sum(&crossings, 1);
  if (size() > 1) {
    EXPECT_GT(crossings, stress ? static_cast<std::int64_t>(all.size()) / 10 * steps : 0);
    if (rank() == 0) std::cout << d.describe() << (stress ? ", stress" : "") << ": " << crossings
                               << " particles changed rank in " << steps << " steps\n";
  }
}

TEST(Migration, ParticlesAndPairRowsFollowTheirOwners) {
  for (const auto per : periodicities())
    for (const auto g : grids_for(size())) check_migration(Box({-0.4, 0.1, 0.0}, {2.0, 2.3, 1.9}, per), g, 40, false);
}

TEST(Migration, CrossingAtEveryStep) {
  for (const auto g : grids_for(size())) check_migration(Box({0, 0, 0}, {2.0, 2.0, 2.0}, {true, true, true}), g, 20, true);
}

}  // namespace
}  // namespace debris::comm
