#include "core/groups.hpp"

#include "core/comm/exact_sum.hpp"
#include "core/error.hpp"
#include "core/exec.hpp"
#include "core/particles.hpp"

namespace debris {

const char* motion_name(GroupMotion m) {
  switch (m) {
    case GroupMotion::free: return "free";
    case GroupMotion::frozen: return "frozen";
    case GroupMotion::velocity: return "velocity";
    case GroupMotion::force: return "force";
  }
  return "?";
}

int Groups::add(Group g) {
  if (g.name.empty()) throw input_error("groups.name", "''", "a group needs a non-empty name");
  if (find(g.name) >= 0) throw input_error("groups.name", g.name, "group names must be unique");
  list.push_back(std::move(g));
  return static_cast<int>(list.size()) - 1;
}

int Groups::find(const std::string& name) const {
  for (std::size_t g = 0; g < list.size(); ++g)
    if (list[g].name == name) return static_cast<int>(g);
  return -1;
}

void Groups::refresh_members(const Particles& p) {
  // Exact sums (host side, at set-up): the group masses are the same bits in any storage order.
  std::vector<comm::ExactSum> mass(list.size());
  for (auto& g : list) g.count = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const int g = p.group[i];
    if (g < 0) continue;
    list[static_cast<std::size_t>(g)].count += 1;
    mass[static_cast<std::size_t>(g)].add(p.mass[i]);
  }
  for (std::size_t g = 0; g < list.size(); ++g) list[g].mass = mass[g].value();
}

Groups::View Groups::view() {
  const std::size_t n = list.size();
  mode_.resize(n);
  vx_.resize(n);
  vy_.resize(n);
  vz_.resize(n);
  for (std::size_t g = 0; g < n; ++g) {
    mode_[g] = static_cast<int>(list[g].motion);
    vx_[g] = list[g].velocity.x;
    vy_[g] = list[g].velocity.y;
    vz_[g] = list[g].velocity.z;
  }
  exec::to_device(mode_);
  exec::to_device(vx_);
  exec::to_device(vy_);
  exec::to_device(vz_);
  return View{mode_.data(), vx_.data(), vy_.data(), vz_.data()};
}

void Groups::sum_by_group(const Particles& p, const double* a, const double* b, const double* c, const double* w,
                          std::vector<Vec3>& out, SumScope scope) {
  const int n = static_cast<int>(p.size());
  const int ng = static_cast<int>(list.size());
  const int blocks = sum_blocks(n);
  const int k = 3 * ng;  // sums per block
  const std::size_t len = static_cast<std::size_t>(blocks) * static_cast<std::size_t>(k);
  std::int64_t* part = partials_.reserve(len);
  const int* group = p.group.data();
  const unsigned char* owned = scope.owned;
  // One pass for all groups: each block adds its members' terms into its own exact accumulators (whichever
  // thread or device team runs it), then the host adds the blocks' accumulators as integers: the same bits
  // in any order.
  DEBRIS_RESIDENT(part, group, a, b, c, w, owned);
  DEBRIS_KERNEL
  for (int blk = 0; blk < blocks; ++blk) {
    std::int64_t* s = part + static_cast<std::size_t>(blk) * static_cast<std::size_t>(k) * comm::kExactWords;
    exact_zero(s, k);
    const BlockRange r = block_range(blk, n);
    for (int i = r.begin; i < r.end; ++i) {
      const int g = group[i];
      if (g < 0 || (owned && !owned[i])) continue;  // a ghost: its owner counts it
      const double wi = w ? w[i] : 1.0;  // 1.0 * x is exact
      comm::exact_add(s + (3 * g) * comm::kExactWords, wi * a[i]);
      comm::exact_add(s + (3 * g + 1) * comm::kExactWords, wi * b[i]);
      comm::exact_add(s + (3 * g + 2) * comm::kExactWords, wi * c[i]);
    }
  }
  partials_.to_host(len);
  sums_flat_.resize(static_cast<std::size_t>(k));
  partials_.add_up(blocks, k, sums_flat_.data(), scope.across_ranks);
  out.resize(static_cast<std::size_t>(ng));
  for (int g = 0; g < ng; ++g) {
    const double* t = sums_flat_.data() + 3 * static_cast<std::size_t>(g);
    out[static_cast<std::size_t>(g)] = Vec3{t[0], t[1], t[2]};
  }
}

void Groups::measure_reactions(const Particles& p, SumScope scope) {
  if (list.empty()) return;
  sum_by_group(p, p.fx.data(), p.fy.data(), p.fz.data(), nullptr, sums_, scope);
  for (std::size_t g = 0; g < list.size(); ++g) list[g].reaction = sums_[g];
}

void Groups::accumulate_displacements(const Particles& p, double dt, SumScope scope) {
  bool any_free = false;
  for (Group& gr : list) {
    if (gr.motion == GroupMotion::frozen || gr.mass <= 0.0) continue;
    if (gr.motion == GroupMotion::free) any_free = true;
    else gr.displacement += dt * gr.velocity;
  }
  if (!any_free) return;  // rigid groups only: no pass over the particles
  sum_by_group(p, p.vx.data(), p.vy.data(), p.vz.data(), p.mass.data(), sums_, scope);
  for (std::size_t g = 0; g < list.size(); ++g) {
    Group& gr = list[g];
    if (gr.motion == GroupMotion::free && gr.mass > 0.0) gr.displacement += (dt / gr.mass) * sums_[g];
  }
}

}  // namespace debris
