#include "core/contact_history.hpp"

#include "core/exec.hpp"
#include "core/neighbor_list.hpp"
#include "core/particles.hpp"

namespace debris {

void ContactHistory::reset(const NeighborList& list) {
  const std::size_t m = static_cast<std::size_t>(list.entries());
  hx.assign(m, 0.0);
  hy.assign(m, 0.0);
  hz.assign(m, 0.0);
}

void ContactHistory::remember(const Particles& p, const NeighborList& list) {
  const int n = list.rows();
  old_offset_ = list.offset();
  old_partner_.resize(static_cast<std::size_t>(list.entries()));
  old_row_of_id_.assign(static_cast<std::size_t>(p.max_id() + 1), -1);
  const int* offset = list.offset().data();
  const int* index = list.index().data();
  const std::int64_t* id = p.id.data();
  std::int64_t* partner = old_partner_.data();
  int* row_of_id = old_row_of_id_.data();
  DEBRIS_KERNEL
  for (int i = 0; i < n; ++i) {
    row_of_id[id[i]] = i;
    for (int k = offset[i]; k < offset[i + 1]; ++k) partner[k] = id[index[k]];
  }
  old_hx_.swap(hx);
  old_hy_.swap(hy);
  old_hz_.swap(hz);
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
  // In a half list a pair sits in the row of whichever end has the lower index, which a re-sort can swap:
  // then the state is found in the partner's old row and seen from the other end (opposite sign).
  DEBRIS_KERNEL
  for (int i = 0; i < n; ++i) {
    const int r = id[i] < known_ids ? row_of_id[id[i]] : -1;  // -1: new since, or never listed
    for (int k = offset[i]; k < offset[i + 1]; ++k) {
      const std::int64_t q = id[index[k]];
      int found = -1;
      double sign = 1.0;
      if (r >= 0)
        for (int o = old_offset[r]; o < old_offset[r + 1] && found < 0; ++o)
          if (old_partner[o] == q) found = o;
      const int rq = q < known_ids ? row_of_id[q] : -1;
      if (found < 0 && rq >= 0) {
        for (int o = old_offset[rq]; o < old_offset[rq + 1] && found < 0; ++o)
          if (old_partner[o] == id[i]) found = o;
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
