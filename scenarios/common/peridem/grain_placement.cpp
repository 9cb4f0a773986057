#include "scenarios/common/peridem/grain_placement.hpp"

#include <algorithm>
#include <climits>
#include <cmath>

#include "core/error.hpp"
#include "scenarios/common/peridem/nodal_volume.hpp"

namespace debris {

namespace {

/// Appends n nodes for grain `g` (nodes.resize zeroes velocities, forces and flags); returns the first index.
std::size_t append_nodes(std::size_t n, PdNodes& nodes, PdGrains& grains, PdGrainKind kind, int material, int& g) {
  const std::size_t begin = nodes.size();
  if (begin + n > static_cast<std::size_t>(INT_MAX))
    throw input_error("nodes", std::to_string(begin + n), "more nodes than PdGrains' int node ranges can index");
  const std::int64_t first_id = begin == 0 ? 1 : nodes.id[begin - 1] + 1;
  nodes.resize(begin + n);
  g = static_cast<int>(grains.size());
  grains.resize(grains.size() + 1);
  grains.node_begin[g] = static_cast<int>(begin);
  grains.node_end[g] = static_cast<int>(begin + n);
  grains.kind[g] = static_cast<int>(kind);
  grains.material[g] = material;
  for (std::size_t k = 0; k < n; ++k) {
    nodes.id[begin + k] = first_id + static_cast<std::int64_t>(k);
    nodes.grain[begin + k] = g;
  }
  return begin;
}

/// Sets the reference = current positions, the grain's volume and its volume-weighted centre.
void finish_grain(int g, PdNodes& nodes, PdGrains& grains) {
  double v = 0, cx = 0, cy = 0, cz = 0;
  for (int i = grains.node_begin[g]; i < grains.node_end[g]; ++i) {
    nodes.x0[i] = nodes.x[i];
    nodes.y0[i] = nodes.y[i];
    nodes.z0[i] = nodes.z[i];
    v += nodes.volume[i];
    cx += nodes.volume[i] * nodes.x[i];
    cy += nodes.volume[i] * nodes.y[i];
    cz += nodes.volume[i] * nodes.z[i];
  }
  grains.volume[g] = v;
  grains.cx[g] = cx / v;
  grains.cy[g] = cy / v;
  grains.cz[g] = cz / v;
}

}  // namespace

ReferenceGrain make_reference_grain(SimplexMesh mesh, double radius, int material, const std::string& what) {
  if (!(radius > 0) || !std::isfinite(radius))
    throw input_error(what + " reference radius", format_value(radius), "must be a finite number > 0");
  ReferenceGrain r;
  r.volume = nodal_volumes(mesh, what);
  r.mesh = std::move(mesh);
  r.radius = radius;
  r.material = material;
  return r;
}

int place_grain(const ReferenceGrain& reference, const GrainRecord& record, PdNodes& nodes, PdGrains& grains) {
  const auto& v = reference.mesh.nodes;
  if (reference.volume.size() != v.size() || !(reference.radius > 0))
    throw input_error("reference grain", "zone " + std::to_string(record.zone),
                      "was not made by make_reference_grain (volumes or radius missing)");
  const double s = record.radius / reference.radius;
  const double c = std::cos(record.orientation), sn = std::sin(record.orientation);
  const double volume_scale = std::pow(s, reference.mesh.dimension);
  int g = 0;
  const std::size_t begin = append_nodes(v.size(), nodes, grains, PdGrainKind::particle, reference.material, g);
  for (std::size_t k = 0; k < v.size(); ++k) {
    // x = centre + s R_z(o) v (PeriDEM's ParticleTransform::apply); V = V_ref s^d.
    nodes.x[begin + k] = record.x + s * (c * v[k].x - sn * v[k].y);
    nodes.y[begin + k] = record.y + s * (sn * v[k].x + c * v[k].y);
    nodes.z[begin + k] = record.z + s * v[k].z;
    nodes.volume[begin + k] = reference.volume[k] * volume_scale;
  }
  finish_grain(g, nodes, grains);
  return g;
}

void place_grains(const std::vector<ReferenceGrain>& zones, const std::vector<GrainRecord>& records, PdNodes& nodes,
                  PdGrains& grains) {
  int max_zone = -1;
  for (std::size_t k = 0; k < records.size(); ++k) {
    const int zone = records[k].zone;
    if (zone < 0 || static_cast<std::size_t>(zone) >= zones.size())
      throw input_error("grain " + std::to_string(k) + " zone", std::to_string(zone),
                        "has no reference grain (" + std::to_string(zones.size()) + " zones given, 0-based)");
    max_zone = std::max(max_zone, zone);
  }
  for (int zone = 0; zone <= max_zone; ++zone)
    for (const GrainRecord& r : records)
      if (r.zone == zone) place_grain(zones[static_cast<std::size_t>(zone)], r, nodes, grains);
}

int append_wall(const SimplexMesh& mesh, int material, PdNodes& nodes, PdGrains& grains, const std::string& what) {
  const std::vector<double> volume = nodal_volumes(mesh, what);
  int g = 0;
  const std::size_t begin = append_nodes(mesh.nodes.size(), nodes, grains, PdGrainKind::wall, material, g);
  for (std::size_t k = 0; k < mesh.nodes.size(); ++k) {
    nodes.x[begin + k] = mesh.nodes[k].x;
    nodes.y[begin + k] = mesh.nodes[k].y;
    nodes.z[begin + k] = mesh.nodes[k].z;
    nodes.volume[begin + k] = volume[k];
  }
  finish_grain(g, nodes, grains);
  return g;
}

}  // namespace debris
