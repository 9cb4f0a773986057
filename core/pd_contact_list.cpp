#include "core/pd_contact_list.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>

#include "core/bond_list.hpp"
#include "core/device_counting_sort.hpp"
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
  entries_ = static_cast<int>(total);
  build_slots(nodes, grains);  // where the rows are: nothing but the scans' totals moves
}

void PdContactList::build_slots(const PdNodes& nodes, const PdGrains& grains) {
  // Kernels over grains (offload builds: on the device, with the three totals as the only transfers), each
  // grain's slots in the order of the serial definition: its cross-grain pairs in row order (i ascending,
  // then list order), stably sorted by partner key, one slot per key. The sorts are insertion sorts of one
  // grain's few dozen pairs, so the result does not depend on the thread count or the device.
  const int ng = static_cast<int>(grains.size()), n = rows_;
  const int* __restrict grain = nodes.grain.data();
  const int* __restrict kind = grains.kind.data();
  const int* __restrict node_begin = grains.node_begin.data();
  const int* __restrict node_end = grains.node_end.data();
  const int* __restrict off = offset_.data();
  const int* __restrict idx = index_.data();
  const int wall = static_cast<int>(PdGrainKind::wall);

  // The node pairs of each particle grain with another grain or a wall node: counts, then their offsets.
  grain_pair_offset_.resize(static_cast<std::size_t>(ng) + 1);
  grain_slot_offset_.resize(static_cast<std::size_t>(ng) + 1);
  int* __restrict pair_start = grain_pair_offset_.data();
  int* __restrict slot_start = grain_slot_offset_.data();
  if (ng == 0) {  // no kernel writes the leading zeros
    grain_pair_offset_[0] = grain_slot_offset_[0] = 0;
    exec::to_device(grain_pair_offset_);
    exec::to_device(grain_slot_offset_);
  }
  DEBRIS_RESIDENT(grain, kind, node_begin, node_end, off, idx, pair_start);
  DEBRIS_KERNEL
  for (int p = 0; p < ng; ++p) {
    if (p == 0) pair_start[0] = 0;
    int count = 0;
    if (kind[p] != wall)
      for (int i = node_begin[p]; i < node_end[p]; ++i)
        for (int k = off[i]; k < off[i + 1]; ++k) count += grain[idx[k]] != p ? 1 : 0;
    pair_start[p + 1] = count;
  }
  const long long pairs = inclusive_scan(pair_start + 1, ng, scan_scratch_);

  // Each grain's pairs with their keys (partner grain q, or grains + wall node), stably sorted by key; the
  // number of distinct keys is the grain's slot count.
  slot_key_.resize(static_cast<std::size_t>(pairs));
  slot_pair_i_.resize(static_cast<std::size_t>(pairs));
  slot_pair_j_.resize(static_cast<std::size_t>(pairs));
  long long* __restrict key = slot_key_.data();
  int* __restrict pair_i = slot_pair_i_.data();
  int* __restrict pair_j = slot_pair_j_.data();
  DEBRIS_RESIDENT(grain, kind, node_begin, node_end, off, idx, pair_start, slot_start, key, pair_i, pair_j);
  DEBRIS_KERNEL
  for (int p = 0; p < ng; ++p) {
    if (p == 0) slot_start[0] = 0;
    const int first = pair_start[p], last = pair_start[p + 1];
    int e = first;
    for (int i = node_begin[p]; i < node_end[p] && e < last; ++i)
      for (int k = off[i]; k < off[i + 1]; ++k) {
        const int j = idx[k], q = grain[j];
        if (q == p) continue;
        key[e] = kind[q] == wall ? static_cast<long long>(ng) + j : q;
        pair_i[e] = i;
        pair_j[e] = j;
        ++e;
      }
    for (int a = first + 1; a < last; ++a) {  // stable: equal keys keep their row order
      const long long kv = key[a];
      const int iv = pair_i[a], jv = pair_j[a];
      int h = a;
      for (; h > first && key[h - 1] > kv; --h) {
        key[h] = key[h - 1];
        pair_i[h] = pair_i[h - 1];
        pair_j[h] = pair_j[h - 1];
      }
      key[h] = kv;
      pair_i[h] = iv;
      pair_j[h] = jv;
    }
    int distinct = 0;
    for (int a = first; a < last; ++a) distinct += a == first || key[a] != key[a - 1] ? 1 : 0;
    slot_start[p + 1] = distinct;
  }
  const long long slots = inclusive_scan(slot_start + 1, ng, scan_scratch_);

  // One slot per distinct key of a grain, numbered from the grain's first slot.
  const int ns = static_cast<int>(slots), np = static_cast<int>(pairs);
  slot_owner_.resize(static_cast<std::size_t>(ns));
  slot_partner_grain_.resize(static_cast<std::size_t>(ns));
  slot_partner_node_.resize(static_cast<std::size_t>(ns));
  slot_pair_offset_.resize(static_cast<std::size_t>(ns) + 1);
  int* __restrict owner = slot_owner_.data();
  int* __restrict partner_grain = slot_partner_grain_.data();
  int* __restrict partner_node = slot_partner_node_.data();
  int* __restrict pair_offset = slot_pair_offset_.data();
  if (ng == 0) {
    slot_pair_offset_[0] = 0;
    exec::to_device(slot_pair_offset_);
  }
  DEBRIS_RESIDENT(grain, pair_start, slot_start, key, owner, partner_grain, partner_node, pair_offset);
  DEBRIS_KERNEL
  for (int p = 0; p < ng; ++p) {
    if (p == 0) pair_offset[ns] = np;
    int s = slot_start[p];
    for (int a = pair_start[p]; a < pair_start[p + 1]; ++a) {
      if (a > pair_start[p] && key[a] == key[a - 1]) continue;
      const long long kv = key[a];
      const int jn = kv >= ng ? static_cast<int>(kv - ng) : -1;
      owner[s] = p;
      partner_grain[s] = jn >= 0 ? grain[jn] : static_cast<int>(kv);
      partner_node[s] = jn;
      pair_offset[s] = a;
      ++s;
    }
  }

  // Slots by partner wall node, in slot order, for the reaction on the wall nodes.
  wall_slot_offset_.resize(static_cast<std::size_t>(n) + 1);
  wall_cursor_.resize(static_cast<std::size_t>(n));
  wall_slot_.resize(static_cast<std::size_t>(ns));  // at most one per slot; trimmed to the count below
  const long long wall_slots = counting_sort_by_bucket(partner_node, ns, n, wall_slot_offset_.data(),
                                                       wall_cursor_.data(), wall_slot_.data(), scan_scratch_);
  wall_slot_.resize(static_cast<std::size_t>(wall_slots));
}

void PdContactList::to_host() const {
  for (const auto* v : {&offset_, &index_, &grain_slot_offset_, &slot_owner_, &slot_partner_grain_, &slot_partner_node_,
                        &slot_pair_offset_, &slot_pair_i_, &slot_pair_j_, &wall_slot_offset_, &wall_slot_})
    exec::to_host(*v);
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
    if (i == 0) add[0] = 0;
    add[i + 1] = count;
  }
  // Prefix sum where the counts are (offload builds: the total comes back, nothing else).
  const long long total = n > 0 ? inclusive_scan(add + 1, n, scan_scratch_) : 0;
  if (total == 0) return 0;
  if (total + static_cast<long long>(entries_) > std::numeric_limits<int>::max())
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
  // Each row's end moves by the entries added up to it (after the merge, which read the old offsets).
  int* __restrict row_end = offset_.data() + 1;
  DEBRIS_RESIDENT(row_end, add);
  DEBRIS_KERNEL
  for (int i = 0; i < n; ++i) row_end[i] += add[i + 1];
  entries_ += static_cast<int>(total);
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
                           grain_pair_offset_.capacity() + wall_cursor_.capacity() +
                           grain_slot_offset_.capacity() + slot_owner_.capacity() + slot_partner_grain_.capacity() +
                           slot_partner_node_.capacity() + slot_pair_offset_.capacity() + slot_pair_i_.capacity() +
                           slot_pair_j_.capacity() + wall_slot_offset_.capacity() + wall_slot_.capacity();
  return sizeof(int) * ints + sizeof(double) * (x0_.capacity() + y0_.capacity() + z0_.capacity()) +
         handled_.capacity() + sizeof(long long) * slot_key_.capacity() + cells_.bytes();
}

}  // namespace debris
