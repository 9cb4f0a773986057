// The PeriDEM contact list (core/pd_contact_list.hpp) against a brute-force pair search, with self-contact
// across broken bonds and walls; rebuild triggers; broken bonds added in place.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "tests/pd_test_grains.hpp"

namespace debris {
namespace {

using namespace pd_test;

using Pairs = std::vector<std::pair<int, int>>;

// Random 3D system: three particle grains with bonds (a third of them broken) and two walls.
PdSystem random_system(std::uint64_t seed, double horizon) {
  PdSystem s;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const int sizes[5] = {120, 90, 110, 60, 50};
  const PdGrainKind kinds[5] = {PdGrainKind::particle, PdGrainKind::particle, PdGrainKind::wall, PdGrainKind::particle,
                                PdGrainKind::wall};
  for (int g = 0; g < 5; ++g) {
    s.begin_grain(kinds[g], g % 2);
    for (int k = 0; k < sizes[g]; ++k)
      s.add_node(Vec3{0.1 * g + 0.5 * u(rng), 0.5 * u(rng), 0.5 * u(rng)}, 1e-3, 1000.0);
  }
  bond_within(s, horizon);
  for (int i = 0; i < static_cast<int>(s.nodes.size()); ++i)
    for (int e = s.bonds.offset[i]; e < s.bonds.offset[i + 1]; ++e)
      if (s.bonds.partner[e] > i && u(rng) < 0.33) break_bond(s.bonds, i, s.bonds.partner[e]);
  return s;
}

Pairs brute_force(const PdSystem& s, double reach) {
  Pairs out;
  const int n = static_cast<int>(s.nodes.size());
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      if (i == j || norm(s.position(i) - s.position(j)) >= reach) continue;
      const int gi = s.nodes.grain[i], gj = s.nodes.grain[j];
      const bool wi = s.grains.kind[gi] == 1, wj = s.grains.kind[gj] == 1;
      if (wi && wj) continue;                                                     // never wall-wall
      if (gi == gj && !s.bonds.offset.empty() && s.bonds.intact(i, j)) continue;  // bonded: not contact
      out.emplace_back(i, j);
    }
  }
  return out;
}

Pairs listed_pairs(const PdContactList& l) {
  Pairs out;
  for (int i = 0; i < l.rows(); ++i)
    for (int k = l.offset()[i]; k < l.offset()[i + 1]; ++k) out.emplace_back(i, l.index()[k]);
  return out;
}

TEST(PdContactList, MatchesBruteForceWithSelfContactAndWalls) {
  const double cutoff = 0.06, skin = 0.02;
  const PdSystem s = random_system(3, 0.12);
  ThreadGuard guard;
  exec::set_threads(1);
  PdContactList one;
  test::build_list(one, s.nodes, s.grains, s.bonds, cutoff, skin);
  exec::set_threads(2);
  PdContactList two;
  test::build_list(two, s.nodes, s.grains, s.bonds, cutoff, skin);
  EXPECT_EQ(one.offset(), two.offset());
  EXPECT_EQ(one.index(), two.index());

  const Pairs ref = brute_force(s, cutoff + skin);
  int self = 0, bonded_close = 0;
  for (const auto& [i, j] : ref) self += s.nodes.grain[i] == s.nodes.grain[j];
  for (int i = 0; i < static_cast<int>(s.nodes.size()); ++i)
    for (int e = s.bonds.offset[i]; e < s.bonds.offset[i + 1]; ++e)
      bonded_close += !s.bonds.broken[e] && norm(s.position(i) - s.position(s.bonds.partner[e])) < cutoff + skin;
  ASSERT_GT(ref.size(), 1000u) << "the test system should have contacts";
  ASSERT_GT(self, 50) << "and self-contacts across broken bonds";
  ASSERT_GT(bonded_close, 50) << "and bonded pairs in range, which must stay out";
  Pairs got = listed_pairs(one);
  std::sort(got.begin(), got.end());
  EXPECT_TRUE(std::adjacent_find(got.begin(), got.end()) == got.end()) << "a pair listed twice";
  EXPECT_EQ(got, ref);

  // Slots: one per (particle grain, partner grain or wall node), holding exactly that pair's list entries.
  std::map<std::pair<int, long>, Pairs> expect;
  const long ng = static_cast<long>(s.grains.size());
  for (const auto& [i, j] : ref) {
    const int p = s.nodes.grain[i], q = s.nodes.grain[j];
    if (p == q || s.grains.kind[p] == 1) continue;
    expect[{p, s.grains.kind[q] == 1 ? ng + j : q}].emplace_back(i, j);
  }
  std::map<std::pair<int, long>, Pairs> slots;
  for (int p = 0; p < static_cast<int>(ng); ++p) {
    for (int sl = one.grain_slot_offset()[p]; sl < one.grain_slot_offset()[p + 1]; ++sl) {
      ASSERT_EQ(one.slot_owner()[sl], p);
      const int jn = one.slot_partner_node()[sl];
      const int q = one.slot_partner_grain()[sl];
      if (jn >= 0) {
        EXPECT_EQ(s.nodes.grain[jn], q);
        EXPECT_EQ(s.grains.kind[q], 1) << "node partners are wall nodes";
      }
      Pairs& v = slots[{p, jn >= 0 ? ng + jn : q}];
      EXPECT_TRUE(v.empty()) << "two slots for one grain pair";
      for (int e = one.slot_pair_offset()[sl]; e < one.slot_pair_offset()[sl + 1]; ++e)
        v.emplace_back(one.slot_pair_i()[e], one.slot_pair_j()[e]);
    }
  }
  for (auto& [k, v] : slots) std::sort(v.begin(), v.end());
  EXPECT_EQ(slots, expect);
  // Every wall-node slot is listed under its wall node.
  int wall_slots = 0;
  for (int j = 0; j < one.rows(); ++j)
    for (int k = one.wall_slot_offset()[j]; k < one.wall_slot_offset()[j + 1]; ++k) {
      EXPECT_EQ(one.slot_partner_node()[one.wall_slot()[k]], j);
      ++wall_slots;
    }
  EXPECT_EQ(wall_slots, static_cast<int>(std::count_if(one.slot_partner_node().begin(), one.slot_partner_node().end(),
                                                       [](int jn) { return jn >= 0; })));
  EXPECT_GT(wall_slots, 20);

  // 2D (all z = 0) with no bonds at all: every same-grain pair in range is a (self-)contact candidate.
  PdSystem flat;
  flat.add_block(PdGrainKind::particle, {0, 0, 0}, 6, 5, 1.0, 1.0);
  flat.add_block(PdGrainKind::wall, {-2, -1.1, 0}, 12, 1, 1.0, 1.0);
  flat.add_block(PdGrainKind::wall, {-2, -2.1, 0}, 12, 1, 1.0, 1.0);
  PdContactList fl;
  test::build_list(fl, flat.nodes, flat.grains, flat.bonds, 1.1, 0.2);
  Pairs fg = listed_pairs(fl);
  std::sort(fg.begin(), fg.end());
  EXPECT_EQ(fg, brute_force(flat, 1.3));
}

// The grain-pair slots in their defined order, which fixes the order of the centre damping's sums: grains
// ascending; within a grain one slot per partner key (grain q, or grains + wall node) ascending; within a
// slot its pairs in row order (i ascending, then the row's order); each wall node's slots ascending. The
// reference is that definition run serially on the list's rows (checked against a brute force above); the
// build computes the slots in kernels over grains, on any thread count (and on the device).
TEST(PdContactList, SlotsInTheirDefinedOrderOnAnyThreadCount) {
  const PdSystem s = random_system(5, 0.12);
  const double cutoff = 0.06, skin = 0.02;
  ThreadGuard guard;
  for (const int threads : {1, 2, 3}) {
    exec::set_threads(threads);
    PdContactList l;
    test::build_list(l, s.nodes, s.grains, s.bonds, cutoff, skin);
    const int ng = static_cast<int>(s.grains.size());
    std::vector<int> grain_slot{0}, owner, partner_grain, partner_node, pair_offset{0}, pair_i, pair_j;
    for (int p = 0; p < ng; ++p) {
      struct Entry {
        long key;
        int i, j;
      };
      std::vector<Entry> e;
      if (s.grains.kind[p] != 1)
        for (int i = s.grains.node_begin[p]; i < s.grains.node_end[p]; ++i)
          for (int k = l.offset()[i]; k < l.offset()[i + 1]; ++k) {
            const int j = l.index()[k], q = s.nodes.grain[j];
            if (q != p) e.push_back({s.grains.kind[q] == 1 ? long{ng} + j : long{q}, i, j});
          }
      std::stable_sort(e.begin(), e.end(), [](const Entry& a, const Entry& b) { return a.key < b.key; });
      for (std::size_t a = 0; a < e.size(); ++a) {
        if (a == 0 || e[a].key != e[a - 1].key) {
          if (a > 0) pair_offset.push_back(static_cast<int>(pair_i.size()));
          const int jn = e[a].key >= ng ? static_cast<int>(e[a].key - ng) : -1;
          owner.push_back(p);
          partner_grain.push_back(jn >= 0 ? s.nodes.grain[jn] : static_cast<int>(e[a].key));
          partner_node.push_back(jn);
        }
        pair_i.push_back(e[a].i);
        pair_j.push_back(e[a].j);
      }
      if (!e.empty()) pair_offset.push_back(static_cast<int>(pair_i.size()));
      grain_slot.push_back(static_cast<int>(owner.size()));
    }
    std::vector<int> wall_offset(static_cast<std::size_t>(l.rows()) + 1, 0), wall_slot;
    for (int j = 0; j < l.rows(); ++j) {
      for (int sl = 0; sl < static_cast<int>(partner_node.size()); ++sl)
        if (partner_node[static_cast<std::size_t>(sl)] == j) wall_slot.push_back(sl);
      wall_offset[static_cast<std::size_t>(j) + 1] = static_cast<int>(wall_slot.size());
    }
    ASSERT_GT(owner.size(), 20u) << "the test needs slots";
    ASSERT_GT(wall_slot.size(), 10u) << "and wall-node slots";
    ASSERT_GT(pair_i.size(), owner.size()) << "and slots of several pairs";
    EXPECT_EQ(l.slots(), static_cast<int>(owner.size())) << threads << " threads";
    EXPECT_EQ(l.grain_slot_offset(), grain_slot);
    EXPECT_EQ(l.slot_owner(), owner);
    EXPECT_EQ(l.slot_partner_grain(), partner_grain);
    EXPECT_EQ(l.slot_partner_node(), partner_node);
    EXPECT_EQ(l.slot_pair_offset(), pair_offset);
    EXPECT_EQ(l.slot_pair_i(), pair_i);
    EXPECT_EQ(l.slot_pair_j(), pair_j);
    EXPECT_EQ(l.wall_slot_offset(), wall_offset);
    EXPECT_EQ(l.wall_slot(), wall_slot);
    EXPECT_EQ(l.entries(), static_cast<int>(l.index().size()));
  }
}

TEST(PdContactList, RebuildAfterHalfSkinDriftOrABrokenBond) {
  PdSystem s = random_system(4, 0.12);
  const double skin = 0.02;
  PdContactList l;
  EXPECT_TRUE(test::needs_rebuild(l, s.nodes)) << "never built";
  test::build_list(l, s.nodes, s.grains, s.bonds, 0.06, skin);
  EXPECT_FALSE(test::needs_rebuild(l, s.nodes));
  s.nodes.y[17] += 0.49 * skin;
  EXPECT_FALSE(test::needs_rebuild(l, s.nodes));
  s.nodes.y[17] += 0.02 * skin;
  EXPECT_TRUE(test::needs_rebuild(l, s.nodes)) << "moved 0.51 skin";
  s.nodes.y[17] -= 0.51 * skin;
  EXPECT_FALSE(test::needs_rebuild(l, s.nodes));
  l.request_rebuild();  // a bond broke
  EXPECT_TRUE(test::needs_rebuild(l, s.nodes));
  test::build_list(l, s.nodes, s.grains, s.bonds, 0.06, skin);
  EXPECT_FALSE(test::needs_rebuild(l, s.nodes));
  expect_input_error([&] { test::build_list(l, s.nodes, s.grains, s.bonds, 0.0, skin); }, "pd_contact.cutoff", "0");
  expect_input_error([&] { test::build_list(l, s.nodes, s.grains, s.bonds, 0.06, -1.0); }, "pd_contact.skin", "-1");
}

// Bonds that break after a build enter the list in place: the list is then exactly the one a build at the
// same (build) positions with the current broken flags gives, rows, order and all, so the force sums and a
// restart (which rebuilds from the build positions) agree bit for bit.
TEST(PdContactList, BrokenBondsAddedInPlaceEqualAFullBuild) {
  PdSystem s = random_system(7, 0.12);
  const double cutoff = 0.05, skin = 0.02;
  const PdNodes at_build = s.nodes;
  PdContactList l;
  test::build_list(l, s.nodes, s.grains, s.bonds, cutoff, skin);
  const int slots = l.slots();
  // The nodes drift (less than skin/2), then bonds break in three waves, some of them twice over.
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-0.2 * skin, 0.2 * skin);
  for (std::size_t i = 0; i < s.nodes.size(); ++i) s.nodes.x[i] += u(rng);
  ASSERT_FALSE(test::needs_rebuild(l, s.nodes));
  long added_in_all = 0;
  for (int wave = 0; wave < 3; ++wave) {
    int broken = 0;
    for (int i = 0; i < static_cast<int>(s.nodes.size()) && broken < 25; i += 7)
      for (int k = s.bonds.offset[i]; k < s.bonds.offset[i + 1]; ++k)
        if ((k + wave) % 5 == 0) {
          break_bond(s.bonds, i, s.bonds.partner[k]);
          ++broken;
        }
    const long added = test::add_broken_bonds(l, s.bonds);
    added_in_all += added;
    EXPECT_EQ(test::add_broken_bonds(l, s.bonds), 0) << "nothing left to add";
    PdContactList fresh;
    test::build_list(fresh, at_build, s.grains, s.bonds, cutoff, skin);
    EXPECT_EQ(l.offset(), fresh.offset()) << "wave " << wave;
    EXPECT_EQ(l.index(), fresh.index()) << "wave " << wave;
    EXPECT_EQ(l.entries(), fresh.entries()) << "wave " << wave;
    EXPECT_EQ(l.slots(), slots) << "self-contact pairs have no slots";
    EXPECT_EQ(l.slot_pair_i(), fresh.slot_pair_i());
  }
  EXPECT_GT(added_in_all, 20) << "the test needs broken bonds within reach";
  EXPECT_FALSE(test::needs_rebuild(l, s.nodes)) << "an in-place update is not a rebuild";

  // A build with bonds broken already starts from them: the next additions are the new bonds only.
  const PdNodes at_rebuild = s.nodes;
  test::build_list(l, s.nodes, s.grains, s.bonds, cutoff, skin);
  EXPECT_EQ(test::add_broken_bonds(l, s.bonds), 0) << "the build holds every bond broken before it";
  int broken = 0;
  for (int i = 3; i < static_cast<int>(s.nodes.size()) && broken < 25; i += 5)
    for (int k = s.bonds.offset[i]; k < s.bonds.offset[i + 1]; ++k)
      if (!s.bonds.broken[static_cast<std::size_t>(k)] && k % 3 == 0) {
        break_bond(s.bonds, i, s.bonds.partner[k]);
        ++broken;
      }
  EXPECT_GT(test::add_broken_bonds(l, s.bonds), 0);
  PdContactList fresh;
  test::build_list(fresh, at_rebuild, s.grains, s.bonds, cutoff, skin);
  EXPECT_EQ(l.offset(), fresh.offset());
  EXPECT_EQ(l.index(), fresh.index());
}

}  // namespace
}  // namespace debris
