#include "core/pd_contact_list.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>

#include "core/bond_list.hpp"
#include "core/device_scan.hpp"
#include "core/error.hpp"
#include "core/exec.hpp"
#include "core/cell_stencil.hpp"
#include "core/pd_nodes.hpp"
#include "core/vec3.hpp"

namespace debris {

namespace {

DEBRIS_DECLARE_TARGET

// BondList::intact on raw arrays, usable inside a kernel: a binary search in the sorted row, written without
// a data-dependent branch (the halving picks by a select). Every neighbour of a node in its own grain is
// looked up here; with a mispredicted branch per halving, the search took 15 of the 40 ms of a list build on
// the compressive test (bench/bench_peridem.cpp).
inline int bond_intact(const int* b_offset, const int* b_partner, const unsigned char* b_broken, int i, int j) {
  const int first = b_offset[i];
  int count = b_offset[i + 1] - first;
  if (count == 0) return 0;
  int base = first;
  while (count > 1) {
    const int half = count / 2;
    base = b_partner[base + half - 1] < j ? base + half : base;
    count -= half;
  }
  return b_partner[base] == j && !b_broken[base];
}

// The pairs that may touch (header comment). kind: PdGrainKind per grain, 1 = wall.
inline int may_touch(int i, int j, const int* grain, const int* kind, const int* b_offset, const int* b_partner,
                     const unsigned char* b_broken, int has_bonds) {
  const int gi = grain[i], gj = grain[j];
  if (kind[gi] == 1 && kind[gj] == 1) return 0;
  if (gi != gj) return 1;
  return !(has_bonds && bond_intact(b_offset, b_partner, b_broken, i, j));
}

// Scans the 27 cells around node i; writes the first `capacity` kept partners to out; returns how many were
// kept in all.
inline int contact_row(int i, const double* x, const double* y, const double* z, const int* cell_of,
                       const int* cell_start, const int* sorted, int n0, int n1, int n2, double reach2,
                       const int* grain, const int* kind, const int* b_offset, const int* b_partner,
                       const unsigned char* b_broken, int has_bonds, int* out, int capacity) {
  const double xi = x[i], yi = y[i], zi = z[i];
  const int not_periodic[3] = {0, 0, 0};
  const Stencil st = cell_stencil(cell_of[i], n0, n1, n2, not_periodic);
  int count = 0;
  for (int a = 0; a < st.nsz; ++a) {
    for (int b = 0; b < st.nsy; ++b) {
      for (int c = 0; c < st.nsx; ++c) {
        const int cell = st.sx[c] + n0 * (st.sy[b] + n1 * st.sz[a]);
        const int end = cell_start[cell + 1];
        for (int k = cell_start[cell]; k < end; ++k) {
          const int j = sorted[k];
          if (j == i) continue;
          const double dx = xi - x[j], dy = yi - y[j], dz = zi - z[j];
          if (dx * dx + dy * dy + dz * dz >= reach2) continue;
          if (!may_touch(i, j, grain, kind, b_offset, b_partner, b_broken, has_bonds)) continue;
          if (count < capacity) out[count] = j;
          ++count;
        }
      }
    }
  }
  return count;
}

// Rows are kept ascending, so that a list built at once and one that received the pairs of broken bonds
// later (add_broken_bonds) hold the same rows in the same order: the force sums, and so a restart, agree
// bit for bit. Rows are short (tens of entries): insertion sort.
inline void sort_row(int* row, int count) {
  for (int a = 1; a < count; ++a) {
    const int v = row[a];
    int b = a;
    for (; b > 0 && row[b - 1] > v; --b) row[b] = row[b - 1];
    row[b] = v;
  }
}

// True when the 8 flags from a and from b are equal: one load each, not eight.
inline int same_flags8(const unsigned char* a, const unsigned char* b) {
  unsigned long long wa, wb;
  std::memcpy(&wa, a, sizeof wa);
  std::memcpy(&wb, b, sizeof wb);
  return wa == wb;
}

// True when j is in the ascending row [first, last).
inline int row_has(const int* first, const int* end, int j) {
  const int* last = end;
  while (first < last) {  // lower bound of j
    const int* mid = first + (last - first) / 2;
    if (*mid < j)
      first = mid + 1;
    else
      last = mid;
  }
  return first != end && *first == j;
}

DEBRIS_END_DECLARE_TARGET

void check_layout(const PdNodes& nodes, const PdGrains& grains, const BondList& bonds) {
  const std::size_t n = nodes.size();
  if (n > static_cast<std::size_t>(std::numeric_limits<int>::max() / 2))
    throw std::invalid_argument("pd_contact_list: too many nodes for int indices");
  const int ng = static_cast<int>(grains.size());
  if (grains.node_end.size() != grains.size() || grains.kind.size() != grains.size())
    throw std::invalid_argument("pd_contact_list: PdGrains columns of different sizes");
  for (int g = 0; g < ng; ++g) {
    const int b = grains.node_begin[g], e = grains.node_end[g];
    if (b < 0 || b > e || e > static_cast<int>(n))
      throw std::invalid_argument("pd_contact_list: grain " + std::to_string(g) + " has a bad node range");
    for (int i = b; i < e; ++i)
      if (nodes.grain[i] != g)
        throw std::invalid_argument("pd_contact_list: node " + std::to_string(i) + " lies in the range of grain " +
                                    std::to_string(g) + " but says grain " + std::to_string(nodes.grain[i]));
  }
  for (std::size_t i = 0; i < n; ++i)
    if (nodes.grain[i] < 0 || nodes.grain[i] >= ng)
      throw std::invalid_argument("pd_contact_list: node " + std::to_string(i) + " has no grain");
  if (!bonds.offset.empty() && bonds.nodes() != n)
    throw std::invalid_argument("pd_contact_list: the bond list has " + std::to_string(bonds.nodes()) + " rows for " +
                                std::to_string(n) + " nodes");
}

}  // namespace

void PdContactList::build(const PdNodes& nodes, const PdGrains& grains, const BondList& bonds, double cutoff,
                          double skin) {
  if (!(std::isfinite(cutoff) && cutoff > 0))
    throw input_error("pd_contact.cutoff", format_value(cutoff), "must be finite and > 0 (the contact radius)");
  if (!(std::isfinite(skin) && skin >= 0))
    throw input_error("pd_contact.skin", format_value(skin), "must be finite and >= 0");
  check_layout(nodes, grains, bonds);
  const int n = static_cast<int>(nodes.size());
  const double reach = cutoff + skin;

  const double* __restrict x = nodes.x.data();
  const double* __restrict y = nodes.y.data();
  const double* __restrict z = nodes.z.data();
  DEBRIS_RESIDENT(x, y, z);

  // Cells over the bounding box of the current positions (a min/max reduction: exact on any thread count).
  // As the serial scan it replaced, which started from node 0: a NaN compares false and is skipped, except
  // at node 0, where it made the box NaN (refused below, as is an infinite coordinate anywhere).
  BoxView box{};
  double lo0 = 0, lo1 = 0, lo2 = 0, hi0 = 0, hi1 = 0, hi2 = 0;
  if (n > 0) {
    const double inf = std::numeric_limits<double>::infinity();
    lo0 = lo1 = lo2 = inf;
    hi0 = hi1 = hi2 = -inf;
    DEBRIS_KERNEL_MINMAX3(lo0, lo1, lo2, hi0, hi1, hi2)
    for (int i = 0; i < n; ++i) {
      const double xi = x[i], yi = y[i], zi = z[i];
      const double nan_at_0 = i == 0 && !(xi == xi && yi == yi && zi == zi) ? inf : -inf;
      lo0 = xi < lo0 ? xi : lo0;
      lo1 = yi < lo1 ? yi : lo1;
      lo2 = zi < lo2 ? zi : lo2;
      hi0 = xi > hi0 ? xi : hi0;
      hi0 = nan_at_0 > hi0 ? nan_at_0 : hi0;
      hi1 = yi > hi1 ? yi : hi1;
      hi2 = zi > hi2 ? zi : hi2;
    }
  }
  const double lo[3] = {lo0, lo1, lo2}, hi[3] = {hi0, hi1, hi2};
  for (int a = 0; a < 3; ++a) {
    if (!(std::isfinite(lo[a]) && std::isfinite(hi[a])))
      throw input_error("pd_nodes.position", "(not finite)", "every node position must be finite to build contacts");
    box.lo[a] = lo[a];
    box.len[a] = std::max(hi[a] - lo[a], reach);  // a flat axis (2D) is one cell
    box.periodic[a] = 0;
  }
  cells_.build(box, x, y, z, n, reach);

  const int* __restrict grain = nodes.grain.data();
  const int* __restrict kind = grains.kind.data();
  const int has_bonds = bonds.offset.empty() ? 0 : 1;
  const int* __restrict b_offset = has_bonds ? bonds.offset.data() : nullptr;
  const int* __restrict b_partner = bonds.partner.data();
  const unsigned char* __restrict b_broken = bonds.broken.data();
  const int* __restrict cell_of = cells_.cell_of().data();
  const int* __restrict cell_start = cells_.cell_start().data();
  const int* __restrict sorted = cells_.sorted_index().data();
  const std::array<int, 3> dims = cells_.dims();
  const int n0 = dims[0], n1 = dims[1], n2 = dims[2];
  const double reach2 = reach * reach;

  // One search per node: the rows are counted and, up to kRowBuffer partners each, kept in row_buffer_; the
  // fill below copies them and searches again only for longer rows (rare: most candidates are bonded).
  offset_.resize(static_cast<std::size_t>(n) + 1);
  row_buffer_.resize(static_cast<std::size_t>(n) * kRowBuffer);
  int* __restrict off = offset_.data();
  int* __restrict buffer = row_buffer_.data();
  DEBRIS_RESIDENT(x, y, z, grain, kind, b_offset, b_partner, b_broken, cell_of, cell_start, sorted, off, buffer);
  DEBRIS_KERNEL
  for (int i = 0; i < n; ++i) {
    if (i == 0) off[0] = 0;
    off[i + 1] =
        contact_row(i, x, y, z, cell_of, cell_start, sorted, n0, n1, n2, reach2, grain, kind, b_offset, b_partner,
                    b_broken, has_bonds, buffer + static_cast<std::size_t>(i) * kRowBuffer, kRowBuffer);
  }
  // Prefix sum where the counts are (offload builds: on the device, the total back): exact integers, the
  // same offsets on any thread count.
  if (n == 0) {  // no kernel wrote off[0]
    off[0] = 0;
    exec::to_device(offset_);
  }
  const long long total = inclusive_scan(off + 1, n, scan_scratch_);
  if (total > std::numeric_limits<int>::max())
    throw input_error("pd_contact.skin", format_value(skin), "too many contact candidates for int offsets");
  index_.resize(static_cast<std::size_t>(total));
  int* __restrict idx = index_.data();
  DEBRIS_RESIDENT(x, y, z, grain, kind, b_offset, b_partner, b_broken, cell_of, cell_start, sorted, off, buffer, idx);
  DEBRIS_KERNEL
  for (int i = 0; i < n; ++i) {
    const int count = off[i + 1] - off[i];
    if (count <= kRowBuffer) {
      const int* row = buffer + static_cast<std::size_t>(i) * kRowBuffer;
      for (int k = 0; k < count; ++k) idx[off[i] + k] = row[k];
    } else {
      contact_row(i, x, y, z, cell_of, cell_start, sorted, n0, n1, n2, reach2, grain, kind, b_offset, b_partner,
                  b_broken, has_bonds, idx + off[i], count);
    }
    sort_row(idx + off[i], count);
  }

  // The positions of this build, copied where they are (the device in offload builds).
  x0_.resize(static_cast<std::size_t>(n));
  y0_.resize(static_cast<std::size_t>(n));
  z0_.resize(static_cast<std::size_t>(n));
  double* __restrict bx = x0_.data(), *__restrict by = y0_.data(), *__restrict bz = z0_.data();
  DEBRIS_RESIDENT(x, y, z, bx, by, bz);
  DEBRIS_KERNEL
  for (int i = 0; i < n; ++i) {
    bx[i] = x[i];
    by[i] = y[i];
    bz[i] = z[i];
  }
  // Every bond broken now is in the rows where within reach: add_broken_bonds starts from here.
  handled_.resize(bonds.broken.size());
  if (!handled_.empty()) {
    const int entries_b = static_cast<int>(handled_.size());
    unsigned char* __restrict seen = handled_.data();
    DEBRIS_RESIDENT(b_broken, seen);
    DEBRIS_KERNEL
    for (int k = 0; k < entries_b; ++k) seen[k] = b_broken[k];
  }
  rows_ = n;
  cutoff_ = cutoff;
  skin_ = skin;
  built_ = true;
  stale_ = false;
  // The slots are built on the host from the rows (offload builds: the offsets and entries() ints to the
  // host; the slot arrays go to the device at the end of build_slots).
  exec::to_host(offset_);
  exec::to_host(index_);
  build_slots(nodes, grains);
}

void PdContactList::build_slots(const PdNodes& nodes, const PdGrains& grains) {
  const int ng = static_cast<int>(grains.size());
  grain_slot_offset_.assign(static_cast<std::size_t>(ng) + 1, 0);
  slot_owner_.clear();
  slot_partner_grain_.clear();
  slot_partner_node_.clear();
  slot_pair_offset_.assign(1, 0);
  slot_pair_i_.clear();
  slot_pair_j_.clear();
  const int wall = static_cast<int>(PdGrainKind::wall);
  for (int p = 0; p < ng; ++p) {
    grain_slot_offset_[static_cast<std::size_t>(p)] = static_cast<int>(slot_owner_.size());
    if (grains.kind[static_cast<std::size_t>(p)] == wall) continue;
    scratch_.clear();
    for (int i = grains.node_begin[static_cast<std::size_t>(p)]; i < grains.node_end[static_cast<std::size_t>(p)];
         ++i) {
      for (int k = offset_[static_cast<std::size_t>(i)]; k < offset_[static_cast<std::size_t>(i) + 1]; ++k) {
        const int j = index_[static_cast<std::size_t>(k)];
        const int q = nodes.grain[static_cast<std::size_t>(j)];
        if (q == p) continue;
        const std::int64_t key = grains.kind[static_cast<std::size_t>(q)] == wall ? std::int64_t{ng} + j : q;
        scratch_.push_back({key, i, j});
      }
    }
    // Stable: within a slot the pairs stay in row order (i ascending, then list order).
    std::stable_sort(scratch_.begin(), scratch_.end(),
                     [](const SlotEntry& a, const SlotEntry& b) { return a.key < b.key; });
    for (std::size_t e = 0; e < scratch_.size(); ++e) {
      const std::int64_t key = scratch_[e].key;
      if (e == 0 || key != scratch_[e - 1].key) {
        if (e > 0) slot_pair_offset_.push_back(static_cast<int>(slot_pair_i_.size()));
        const bool node_partner = key >= ng;
        const int jn = node_partner ? static_cast<int>(key - ng) : -1;
        slot_owner_.push_back(p);
        slot_partner_grain_.push_back(node_partner ? nodes.grain[static_cast<std::size_t>(jn)] : static_cast<int>(key));
        slot_partner_node_.push_back(jn);
      }
      slot_pair_i_.push_back(scratch_[e].i);
      slot_pair_j_.push_back(scratch_[e].j);
    }
    if (!scratch_.empty()) slot_pair_offset_.push_back(static_cast<int>(slot_pair_i_.size()));
  }
  grain_slot_offset_[static_cast<std::size_t>(ng)] = static_cast<int>(slot_owner_.size());

  // Slots by partner wall node (counting sort, slot order kept), for the reaction on the wall nodes.
  wall_slot_offset_.assign(static_cast<std::size_t>(rows_) + 1, 0);
  for (int jn : slot_partner_node_)
    if (jn >= 0) ++wall_slot_offset_[static_cast<std::size_t>(jn) + 1];
  for (int i = 0; i < rows_; ++i)
    wall_slot_offset_[static_cast<std::size_t>(i) + 1] += wall_slot_offset_[static_cast<std::size_t>(i)];
  wall_slot_.resize(static_cast<std::size_t>(wall_slot_offset_.back()));
  std::vector<int> cursor(wall_slot_offset_.begin(), wall_slot_offset_.end() - 1);
  for (int s = 0; s < static_cast<int>(slot_partner_node_.size()); ++s) {
    const int jn = slot_partner_node_[static_cast<std::size_t>(s)];
    if (jn >= 0) wall_slot_[static_cast<std::size_t>(cursor[static_cast<std::size_t>(jn)]++)] = s;
  }
  for (const auto* v : {&grain_slot_offset_, &slot_owner_, &slot_partner_grain_, &slot_partner_node_,
                        &slot_pair_offset_, &slot_pair_i_, &slot_pair_j_, &wall_slot_offset_, &wall_slot_})
    exec::to_device(*v);
}

void PdContactList::to_host() const {
  exec::to_host(offset_);
  exec::to_host(index_);
  exec::to_host(x0_);
  exec::to_host(y0_);
  exec::to_host(z0_);
}

long PdContactList::add_broken_bonds(const BondList& bonds) {
  if (!built_ || bonds.offset.empty()) return 0;
  if (bonds.nodes() != static_cast<std::size_t>(rows_) || bonds.broken.size() != handled_.size())
    throw std::invalid_argument("pd_contact_list: the bond list does not match the list's rows");
  const int n = rows_;
  const double reach = cutoff_ + skin_, reach2 = reach * reach;
  const double* __restrict x = x0_.data(), *__restrict y = y0_.data(), *__restrict z = z0_.data();
  const int* __restrict b_offset = bonds.offset.data();
  const int* __restrict b_partner = bonds.partner.data();
  const unsigned char* __restrict b_broken = bonds.broken.data();
  unsigned char* __restrict seen = handled_.data();
  const int* __restrict off = offset_.data();
  const int* __restrict idx = index_.data();

  // The pairs a build would hold now and this list does not: bonds broken since the last look (broken, not
  // handled) that lie within reach at the build positions. Bonds join nodes of one particle grain, so
  // may_touch holds for every broken one. A new bond out of reach is marked handled here and never looked at
  // again (the build positions stay until the next build); one within reach is left for the merge below,
  // which marks it. The row search only guards the invariant: a handled-clear bond is never in its row.
  // Each row writes the flags of its own entries only.
  added_.resize(static_cast<std::size_t>(n) + 1);
  int* __restrict add = added_.data();
  DEBRIS_RESIDENT(x, y, z, b_offset, b_partner, b_broken, seen, off, idx, add);
  DEBRIS_KERNEL
  for (int i = 0; i < n; ++i) {
    int count = 0;
    const int end = b_offset[i + 1];
    for (int k0 = b_offset[i]; k0 < end; k0 += 8) {
      // Almost every group of 8 entries has nothing new: the flags are compared a word at a time (this scan
      // over all entries was most of the call's time).
      if (k0 + 8 <= end && same_flags8(b_broken + k0, seen + k0)) continue;
      const int k1 = k0 + 8 < end ? k0 + 8 : end;
      for (int k = k0; k < k1; ++k) {
        if (b_broken[k] == seen[k]) continue;  // intact, or broken and handled
        const int j = b_partner[k];
        const double dx = x[i] - x[j], dy = y[i] - y[j], dz = z[i] - z[j];
        if (dx * dx + dy * dy + dz * dz >= reach2 || row_has(idx + off[i], idx + off[i + 1], j))
          seen[k] = 1;
        else
          ++count;
      }
    }
    add[i + 1] = count;
  }
  // Prefix sum on the host (offload builds: n ints each way, on steps that broke bonds only).
  exec::to_host(added_);
  long long total = 0;
  add[0] = 0;
  for (int i = 1; i <= n; ++i) {
    total += add[i];
    add[i] = static_cast<int>(total);
  }
  if (total == 0) return 0;
  exec::to_device(added_);
  if (total + static_cast<long long>(entries()) > std::numeric_limits<int>::max())
    throw input_error("pd_contact.skin", format_value(skin_), "too many contact candidates for int offsets");

  // Merge each row with its new partners (both ascending) into the spare index array, then swap.
  spare_index_.resize(index_.size() + static_cast<std::size_t>(total));
  int* __restrict out = spare_index_.data();
  DEBRIS_RESIDENT(b_offset, b_partner, b_broken, seen, off, idx, add, out);
  DEBRIS_KERNEL
  for (int i = 0; i < n; ++i) {
    const int* a = idx + off[i];
    const int* const a_end = idx + off[i + 1];
    int* o = out + off[i] + add[i];
    if (add[i + 1] != add[i]) {
      for (int k = b_offset[i]; k < b_offset[i + 1]; ++k) {
        if (b_broken[k] == seen[k]) continue;
        seen[k] = 1;
        const int j = b_partner[k];
        while (a < a_end && *a < j) *o++ = *a++;
        *o++ = j;
      }
    }
    while (a < a_end) *o++ = *a++;
  }
  // The host copy of offset_ is current since the build's prefix sum (or the last addition).
  for (int i = 1; i <= n; ++i) offset_[static_cast<std::size_t>(i)] += added_[static_cast<std::size_t>(i)];
  exec::to_device(offset_);
  index_.swap(spare_index_);
  return static_cast<long>(total);
}

bool PdContactList::needs_rebuild(const PdNodes& nodes) const {
  if (!built_ || stale_ || nodes.size() != x0_.size()) return true;
  const int n = static_cast<int>(nodes.size());
  const double* __restrict x = nodes.x.data();
  const double* __restrict y = nodes.y.data();
  const double* __restrict z = nodes.z.data();
  const double* __restrict x0 = x0_.data();
  const double* __restrict y0 = y0_.data();
  const double* __restrict z0 = z0_.data();
  double max_d2 = 0.0;
  DEBRIS_RESIDENT(x, y, z, x0, y0, z0);
  DEBRIS_KERNEL_MAX(max_d2)
  for (int i = 0; i < n; ++i) {
    const double dx = x[i] - x0[i], dy = y[i] - y0[i], dz = z[i] - z0[i];
    const double d2 = dx * dx + dy * dy + dz * dz;
    max_d2 = d2 > max_d2 ? d2 : max_d2;
  }
  const double half_skin = 0.5 * skin_;
  return max_d2 > half_skin * half_skin;
}

std::size_t PdContactList::bytes() const {
  const std::size_t ints = offset_.capacity() + index_.capacity() + row_buffer_.capacity() + added_.capacity() +
                           spare_index_.capacity() +
                           grain_slot_offset_.capacity() + slot_owner_.capacity() + slot_partner_grain_.capacity() +
                           slot_partner_node_.capacity() + slot_pair_offset_.capacity() + slot_pair_i_.capacity() +
                           slot_pair_j_.capacity() + wall_slot_offset_.capacity() + wall_slot_.capacity();
  return sizeof(int) * ints + sizeof(double) * (x0_.capacity() + y0_.capacity() + z0_.capacity()) +
         handled_.capacity() + sizeof(SlotEntry) * scratch_.capacity() + cells_.bytes();
}

}  // namespace debris
