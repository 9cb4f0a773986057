#include "core/groups.hpp"

#include "core/error.hpp"
#include "core/exec.hpp"
#include "core/particles.hpp"

namespace debris {

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
  for (auto& g : list) {
    g.count = 0;
    g.mass = 0.0;
  }
  for (std::size_t i = 0; i < p.size(); ++i) {
    const int g = p.group[i];
    if (g < 0) continue;
    list[static_cast<std::size_t>(g)].count += 1;
    list[static_cast<std::size_t>(g)].mass += p.mass[i];
  }
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
  return View{mode_.data(), vx_.data(), vy_.data(), vz_.data()};
}

void Groups::kick_rigid(double dt) {
  for (auto& g : list)
    if (g.motion == GroupMotion::force && g.mass > 0.0) g.velocity += (dt / g.mass) * (g.reaction + g.external_force);
}

void Groups::measure_reactions(const Particles& p) {
  const int n = static_cast<int>(p.size());
  const int* group = p.group.data();
  const double *fx = p.fx.data(), *fy = p.fy.data(), *fz = p.fz.data();
  for (std::size_t g = 0; g < list.size(); ++g) {
    const int gi = static_cast<int>(g);
    double sx = 0, sy = 0, sz = 0;
    DEBRIS_KERNEL_SUM3(sx, sy, sz)
    for (int i = 0; i < n; ++i) {
      if (group[i] == gi) {
        sx += fx[i];
        sy += fy[i];
        sz += fz[i];
      }
    }
    list[g].reaction = {sx, sy, sz};
  }
}

void Groups::accumulate_displacements(const Particles& p, double dt) {
  const int n = static_cast<int>(p.size());
  const int* group = p.group.data();
  const double *vx = p.vx.data(), *vy = p.vy.data(), *vz = p.vz.data(), *mass = p.mass.data();
  for (std::size_t g = 0; g < list.size(); ++g) {
    Group& gr = list[g];
    if (gr.motion == GroupMotion::frozen || gr.mass <= 0.0) continue;
    if (gr.motion != GroupMotion::free) {
      gr.displacement += dt * gr.velocity;
      continue;
    }
    const int gi = static_cast<int>(g);
    double px = 0, py = 0, pz = 0;
    DEBRIS_KERNEL_SUM3(px, py, pz)
    for (int i = 0; i < n; ++i) {
      if (group[i] == gi) {
        px += mass[i] * vx[i];
        py += mass[i] * vy[i];
        pz += mass[i] * vz[i];
      }
    }
    gr.displacement += (dt / gr.mass) * Vec3{px, py, pz};
  }
}

}  // namespace debris
