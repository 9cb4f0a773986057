#pragma once
// Two PeriDEM runs that must be the same bit for bit (a restart against the run in one piece, the device
// against host fallback, one thread count against another): one comparison for every test that asks it.
#include <gtest/gtest.h>

#include <string>
#include <type_traits>

#include "scenarios/common/peridem/peridem_simulation.hpp"

namespace debris::test {

/// Every column of the two node stores (same storage order), the bonds' broken flags, the grain centres, the
/// contact list's rows and build positions, and the grain names.
inline void expect_same_pd_state(const PeridemSimulation& a, const PeridemSimulation& b) {
  EXPECT_EQ(a.step_count(), b.step_count());
  EXPECT_EQ(a.time(), b.time());
  EXPECT_EQ(a.broken_bonds(), b.broken_bonds());
  EXPECT_EQ(a.contact_rebuilds(), b.contact_rebuilds());
  const PdNodes& na = a.nodes();
  const PdNodes& nb = b.nodes();
  ASSERT_EQ(na.size(), nb.size());
  na.for_each_column([&](const char* name, const auto& col) {
    nb.for_each_column([&](const char* other, const auto& col_b) {
      if (std::string(name) != other) return;
      if constexpr (std::is_same_v<std::decay_t<decltype(col)>, std::decay_t<decltype(col_b)>>) {
        for (std::size_t i = 0; i < col.size(); ++i) ASSERT_EQ(col[i], col_b[i]) << name << "[" << i << "]";
      }
    });
  });
  EXPECT_EQ(a.bonds().broken, b.bonds().broken);
  EXPECT_EQ(a.grains().cx, b.grains().cx);
  EXPECT_EQ(a.grains().cvy, b.grains().cvy);
  EXPECT_EQ(a.contacts().offset(), b.contacts().offset());
  EXPECT_EQ(a.contacts().index(), b.contacts().index());
  EXPECT_EQ(a.contacts().slot_pair_i(), b.contacts().slot_pair_i());
  EXPECT_EQ(a.contacts().x_at_build(), b.contacts().x_at_build());
  EXPECT_EQ(a.grain_names(), b.grain_names());
}

}  // namespace debris::test
