#include "scenarios/common/dem/replicate_sample.hpp"

#include <cstdint>

#include "core/box.hpp"
#include "core/particles.hpp"

namespace debris {

void replicate_sample(Particles& p, Box& box, std::array<int, 3> n) {
  if (n[0] == 1 && n[1] == 1 && n[2] == 1) return;
  const Vec3 lo = box.lo(), len = box.length();
  const std::size_t m = p.size();
  // Every axis folded, as a box periodic along all three would (the sample was relaxed so), images dropped.
  Box(lo, box.hi(), {true, true, true}).wrap(p);
  for (std::size_t i = 0; i < m; ++i) p.ix[i] = p.iy[i] = p.iz[i] = 0;
  const std::size_t copies = static_cast<std::size_t>(n[0]) * n[1] * n[2];
  const std::int64_t id_step = p.max_id() + 1;
  p.resize(m * copies);
  p.for_each_column([&](const char*, auto& column) {
    for (std::size_t c = 1; c < copies; ++c)
      for (std::size_t i = 0; i < m; ++i) column[c * m + i] = column[i];
  });
  for (int cz = 0; cz < n[2]; ++cz)
    for (int cy = 0; cy < n[1]; ++cy)
      for (int cx = 0; cx < n[0]; ++cx) {
        const std::size_t c = static_cast<std::size_t>(cx) + n[0] * (static_cast<std::size_t>(cy) + n[1] * cz);
        if (c == 0) continue;
        for (std::size_t i = c * m; i < (c + 1) * m; ++i) {
          p.x[i] += cx * len.x;
          p.y[i] += cy * len.y;
          p.z[i] += cz * len.z;
          p.id[i] += static_cast<std::int64_t>(c) * id_step;
        }
      }
  box = Box(lo, Vec3{lo.x + n[0] * len.x, lo.y + n[1] * len.y, lo.z + n[2] * len.z}, box.periodic());
}

}  // namespace debris
