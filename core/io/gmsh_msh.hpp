#pragma once
// Gmsh MSH ASCII files, formats 2.2 and 4.1 (the version is read from $MeshFormat): the meshes PeriDEM grains
// and walls are made from (paper B, section 3.1). Only what a meshless discretisation needs is kept: node
// coordinates and the linear simplices, 3-node triangles (Gmsh type 2) in 2D and 4-node tetrahedra (type 4)
// in 3D. Elements of lower dimension (points, lines, and the boundary triangles of a 3D mesh) are skipped;
// elements of the mesh's own dimension that are not linear simplices (quadrangles, second-order elements,
// hexahedra...) are an error rather than a silent hole in the domain.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/vec3.hpp"

namespace debris {

/// A mesh of linear simplices. Node indices are 0-based positions in `nodes` (file order); `node_tag` keeps
/// the file's own (possibly non-contiguous) tags.
struct SimplexMesh {
  int dimension = 0;                           // 2: `triangles` hold the mesh; 3: `tetrahedra` do
  std::vector<Vec3> nodes;                     // z = 0 for the planar meshes of 2D runs
  std::vector<std::int64_t> node_tag;          // Gmsh tag of each node
  std::vector<std::array<int, 3>> triangles;   // dimension 2 only
  std::vector<std::array<int, 4>> tetrahedra;  // dimension 3 only
};

/// Throws InputError naming the file and the line for malformed or unsupported content: binary files,
/// versions other than 2.2 and 4.1, missing sections, counts that do not match, duplicate node tags,
/// elements that refer to a missing node, unsupported elements of the mesh's dimension, no element at all.
SimplexMesh read_gmsh_msh(const std::string& path);

}  // namespace debris
