#pragma once
// Nodal volumes of a meshless discretisation taken from a finite-element mesh (paper B, section 3.1, eq 31):
//   V_i = sum over the elements e that have node i as a vertex of  integral over T_e of phi_i(x) dx,
// with phi_i the interpolation (hat) function of vertex i. For linear simplices phi_i is the barycentric
// coordinate of vertex i, whose integral over a simplex is exactly |T_e| / (d + 1): a third of each
// triangle's area, a quarter of each tetrahedron's volume. So the volumes sum to the mesh's area or volume.
#include <string>
#include <vector>

#include "core/io/gmsh_msh.hpp"

namespace debris {

/// |T| of one triangle (area) or tetrahedron (volume), whatever the vertex order.
double triangle_area(const Vec3& a, const Vec3& b, const Vec3& c);
double tetrahedron_volume(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

/// Eq 31 for every node of `mesh` (triangles in 2D, tetrahedra in 3D; area in 2D). Throws InputError naming
/// `what` (the mesh's file or shape) for a node that belongs to no element (it would have no volume and so
/// no mass), for an element of zero or non-finite size, and for a mesh of dimension other than 2 or 3.
std::vector<double> nodal_volumes(const SimplexMesh& mesh, const std::string& what);

}  // namespace debris
