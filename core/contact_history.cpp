#include "core/contact_history.hpp"

#include <algorithm>
#include <stdexcept>
#include <unordered_map>

#include "core/comm/migration.hpp"
#include "core/exec.hpp"
#include "core/neighbor_list.hpp"
#include "core/particles.hpp"
#include "core/resize_for_overwrite.hpp"

namespace debris {

void ContactHistory::reset(const NeighborList& list) {
  const std::size_t m = static_cast<std::size_t>(list.entries());
#if defined(DEBRIS_OFFLOAD_TARGET)
  // Zeroed on the device (a kernel, not a transfer of m zeros).
  resize_for_overwrite(hx, m);
  resize_for_overwrite(hy, m);
  resize_for_overwrite(hz, m);
  const int entries = static_cast<int>(m);
  double *__restrict a = hx.data(), *__restrict b = hy.data(), *__restrict c = hz.data();
  DEBRIS_RESIDENT(a, b, c);
  DEBRIS_KERNEL
  for (int k = 0; k < entries; ++k) a[k] = b[k] = c[k] = 0.0;
#else
  hx.assign(m, 0.0);
  hy.assign(m, 0.0);
  hz.assign(m, 0.0);
#endif
}

void ContactHistory::to_host() const {
  exec::to_host(hx);
  exec::to_host(hy);
  exec::to_host(hz);
}

void ContactHistory::to_device() const {
  exec::to_device(hx);
  exec::to_device(hy);
  exec::to_device(hz);
}

void ContactHistory::remember(const Particles& p, const NeighborList& list) {
  const int n = list.rows();
  // The offsets and the largest id are taken where they are current: on the device in offload builds (the
  // list's prefix sum runs there, and a re-sort leaves the host's ids stale).
#if defined(DEBRIS_OFFLOAD_TARGET)
  old_offset_.resize(list.offset().size());
  {
    const int* src = list.offset().data();
    int* dst = old_offset_.data();
    const int m = static_cast<int>(old_offset_.size());
    DEBRIS_RESIDENT(src, dst);
    DEBRIS_KERNEL
    for (int i = 0; i < m; ++i) dst[i] = src[i];
  }
#else
  old_offset_ = list.offset();
#endif
  old_partner_.resize(static_cast<std::size_t>(list.entries()));
#if defined(DEBRIS_OFFLOAD_TARGET)
  std::int64_t max_id = -1;
  {
    const std::int64_t* ids = p.id.data();
    const int count = static_cast<int>(p.size());
    DEBRIS_RESIDENT(ids);
    DEBRIS_KERNEL_MAX(max_id)
    for (int i = 0; i < count; ++i) max_id = ids[i] > max_id ? ids[i] : max_id;
  }
#else
  const std::int64_t max_id = p.max_id();
#endif
#if defined(DEBRIS_OFFLOAD_TARGET)
  // Cleared on the device (a kernel, not a transfer of max_id + 1 ints).
  resize_for_overwrite(old_row_of_id_, static_cast<std::size_t>(max_id + 1));
  {
    int* __restrict clear = old_row_of_id_.data();
    const int ids = static_cast<int>(max_id + 1);
    DEBRIS_RESIDENT(clear);
    DEBRIS_KERNEL
    for (int k = 0; k < ids; ++k) clear[k] = -1;
  }
#else
  old_row_of_id_.assign(static_cast<std::size_t>(max_id + 1), -1);
#endif
  const int* offset = list.offset().data();
  const int* index = list.index().data();
  const std::int64_t* id = p.id.data();
  std::int64_t* partner = old_partner_.data();
  int* row_of_id = old_row_of_id_.data();
  DEBRIS_RESIDENT(offset, index, id, partner, row_of_id);
  DEBRIS_KERNEL
  for (int i = 0; i < n; ++i) {
    row_of_id[id[i]] = i;
    for (int k = offset[i]; k < offset[i + 1]; ++k) partner[k] = id[index[k]];
  }
  old_hx_.swap(hx);
  old_hy_.swap(hy);
  old_hz_.swap(hz);
}

void ContactHistory::rows_seen_from(const Particles& p, const NeighborList& list, const unsigned char* keep,
                                    comm::PairRows& rows) const {
  if constexpr (exec::offload_build()) throw std::logic_error("ContactHistory::rows_seen_from: host builds only");
  const int n = list.rows();
  const int* offset = list.offset().data();
  const int* index = list.index().data();
  // Count, then fill: row of kept particle i = its own entries, then the entries that name it as partner.
  std::vector<std::size_t> count(p.size(), 0);
  for (int i = 0; i < n; ++i)
    for (int k = offset[i]; k < offset[i + 1]; ++k) {
      const int j = index[k];
      if (keep[i]) ++count[static_cast<std::size_t>(i)];
      if (keep[j]) ++count[static_cast<std::size_t>(j)];
    }
  std::vector<std::size_t> at(p.size(), 0);  // where each kept particle's row starts
  rows.offset.assign(1, 0);
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (!keep[i]) continue;
    at[i] = rows.offset.back();
    rows.offset.push_back(at[i] + count[i]);
  }
  const std::size_t total = rows.offset.back();
  rows.partner.resize(total);
  rows.value.resize(comm::PairRows::kValues * total);
  auto put = [&](std::size_t owner, std::int64_t partner, double sign, int k) {
    const std::size_t r = at[owner]++;
    rows.partner[r] = partner;
    rows.value[3 * r] = sign * hx[static_cast<std::size_t>(k)];
    rows.value[3 * r + 1] = sign * hy[static_cast<std::size_t>(k)];
    rows.value[3 * r + 2] = sign * hz[static_cast<std::size_t>(k)];
  };
  for (int i = 0; i < n; ++i)
    for (int k = offset[i]; k < offset[i + 1]; ++k) {
      const int j = index[k];
      if (keep[i]) put(static_cast<std::size_t>(i), p.id[static_cast<std::size_t>(j)], 1.0, k);
      if (keep[j]) put(static_cast<std::size_t>(j), p.id[static_cast<std::size_t>(i)], -1.0, k);  // seen from j
    }
}

void ContactHistory::remember_rows(const Particles& p, const comm::PairRows& rows, const std::vector<int>& stored_at) {
  if constexpr (exec::offload_build()) throw std::logic_error("ContactHistory::remember_rows: host builds only");
  static_assert(comm::PairRows::kValues == 3, "the cohesive model's tangential spring: three doubles per pair");
  const std::size_t n = rows.offset.size() - 1;
  if (n != stored_at.size()) throw std::logic_error("ContactHistory::remember_rows: one storage index per row");
  // The storage index of each id stored here (a hash of this rank's particles, not an array over all ids).
  std::unordered_map<std::int64_t, int> index_of_id;
  index_of_id.reserve(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) index_of_id.emplace(p.id[i], static_cast<int>(i));
  old_offset_.resize(n + 1);
  old_row_of_id_.assign(p.size(), -1);
  for (std::size_t k = 0; k <= n; ++k) old_offset_[k] = static_cast<int>(rows.offset[k]);
  for (std::size_t k = 0; k < n; ++k) old_row_of_id_[static_cast<std::size_t>(stored_at[k])] = static_cast<int>(k);
  const std::size_t m = rows.partner.size();
  old_partner_.resize(m);
  old_hx_.resize(m);
  old_hy_.resize(m);
  old_hz_.resize(m);
  for (std::size_t r = 0; r < m; ++r) {
    // A partner no longer stored here is farther than the ghost width: its pair is not in the next list.
    const auto it = index_of_id.find(rows.partner[r]);
    old_partner_[r] = it == index_of_id.end() ? -1 : it->second;
    old_hx_[r] = rows.value[3 * r];
    old_hy_[r] = rows.value[3 * r + 1];
    old_hz_[r] = rows.value[3 * r + 2];
  }
  by_index_ = true;
}

void ContactHistory::carry_over(const Particles& p, const NeighborList& list) {
  reset(list);
  if (old_offset_.empty()) return;
  const int n = list.rows();
  const int* offset = list.offset().data();
  const int* index = list.index().data();
  const std::int64_t* id = p.id.data();
  const int* old_offset = old_offset_.data();
  const std::int64_t* old_partner = old_partner_.data();
  const int* row_of_id = old_row_of_id_.data();
  const int known_ids = static_cast<int>(old_row_of_id_.size());
  const double *ohx = old_hx_.data(), *ohy = old_hy_.data(), *ohz = old_hz_.data();
  double *nhx = hx.data(), *nhy = hy.data(), *nhz = hz.data();
  const int by_index = by_index_ ? 1 : 0;  // remember_rows(): particles keyed by storage index, not id
  by_index_ = false;
  DEBRIS_RESIDENT(offset, index, id, old_offset, old_partner, row_of_id, ohx, ohy, ohz, nhx, nhy, nhz);
  // In a half list a pair sits in the row of whichever end has the lower index, which a re-sort can swap:
  // then the state is found in the partner's old row and seen from the other end (opposite sign).
  DEBRIS_KERNEL
  for (int i = 0; i < n; ++i) {
    const std::int64_t key_i = by_index ? i : id[i];
    const int r = key_i < known_ids ? row_of_id[key_i] : -1;  // -1: new since, or never listed
    for (int k = offset[i]; k < offset[i + 1]; ++k) {
      const std::int64_t q = by_index ? index[k] : id[index[k]];
      int found = -1;
      double sign = 1.0;
      if (r >= 0)
        for (int o = old_offset[r]; o < old_offset[r + 1] && found < 0; ++o)
          if (old_partner[o] == q) found = o;
      const int rq = q < known_ids ? row_of_id[q] : -1;
      if (found < 0 && rq >= 0) {
        for (int o = old_offset[rq]; o < old_offset[rq + 1] && found < 0; ++o)
          if (old_partner[o] == key_i) found = o;
        sign = -1.0;
      }
      if (found >= 0) {
        nhx[k] = sign * ohx[found];
        nhy[k] = sign * ohy[found];
        nhz[k] = sign * ohz[found];
      }
    }
  }
}

}  // namespace debris
