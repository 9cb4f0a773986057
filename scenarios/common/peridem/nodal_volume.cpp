#include "scenarios/common/peridem/nodal_volume.hpp"

#include <cmath>
#include <string>

#include "core/error.hpp"

namespace debris {

double triangle_area(const Vec3& a, const Vec3& b, const Vec3& c) { return 0.5 * norm(cross(b - a, c - a)); }

double tetrahedron_volume(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  return std::abs(dot(b - a, cross(c - a, d - a))) / 6.0;
}

namespace {

template <std::size_t N, class Size>
void share_equally(const std::vector<Vec3>& x, const std::vector<std::array<int, N>>& elements, Size size,
                   std::vector<double>& volume, const std::string& what) {
  for (std::size_t e = 0; e < elements.size(); ++e) {
    const auto& v = elements[e];
    for (const int k : v)
      if (k < 0 || static_cast<std::size_t>(k) >= x.size())
        throw input_error(what, "element " + std::to_string(e),
                          "refers to node index " + std::to_string(k) + " of " + std::to_string(x.size()));
    const double size_e = size(v);
    if (!(size_e > 0) || !std::isfinite(size_e))
      throw input_error(what, "element " + std::to_string(e),
                        "has size " + format_value(size_e) + ": a degenerate element has no interpolation functions");
    // Eq 31 with linear phi: integral of phi_i over T_e = |T_e| / (number of vertices).
    const double share = size_e / static_cast<double>(N);
    for (const int k : v) volume[static_cast<std::size_t>(k)] += share;
  }
}

}  // namespace

std::vector<double> nodal_volumes(const SimplexMesh& mesh, const std::string& what) {
  const auto& x = mesh.nodes;
  std::vector<double> volume(x.size(), 0.0);
  if (mesh.dimension == 2) {
    share_equally(
        x, mesh.triangles, [&](const std::array<int, 3>& t) { return triangle_area(x[t[0]], x[t[1]], x[t[2]]); },
        volume, what);
  } else if (mesh.dimension == 3) {
    share_equally(
        x, mesh.tetrahedra,
        [&](const std::array<int, 4>& t) { return tetrahedron_volume(x[t[0]], x[t[1]], x[t[2]], x[t[3]]); }, volume,
        what);
  } else {
    throw input_error(what, std::to_string(mesh.dimension), "mesh dimension must be 2 or 3");
  }
  for (std::size_t i = 0; i < volume.size(); ++i)
    if (volume[i] == 0.0) {
      const std::string tag = i < mesh.node_tag.size() ? " (tag " + std::to_string(mesh.node_tag[i]) + ")" : "";
      const Vec3& p = x[i];
      throw input_error(what, "node " + std::to_string(i) + tag,
                        "at (" + format_value(p.x) + ", " + format_value(p.y) + ", " + format_value(p.z) +
                            ") belongs to no " + (mesh.dimension == 2 ? "triangle" : "tetrahedron") +
                            ", so eq 31 gives it no volume; remove it from the mesh (e.g. embed the point in the "
                            "surface with 'Point{..} In Surface{..}', or do not save geometry points)");
    }
  return volume;
}

}  // namespace debris
