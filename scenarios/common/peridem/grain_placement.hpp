#pragma once
// Grains and walls into PdNodes + PdGrains (paper B, section 3.1): each grain is its zone's reference
// mesh, scaled, rotated and moved; each wall is a mesh placed as is.
//
// How PeriDEM does it (v0.2.1; DEMModel::createParticlesFromFile, ParticleTransform::apply and the
// BaseParticle constructor), which is what this file does:
//  - a zone's reference particle is its mesh together with the zone's geometry (deck "Particle: Zone_k:
//    Type, Parameters"); R_ref is that geometry's bounding radius, which for every shape PeriDEM places from
//    a file (circle, hexagon, triangle, drum2d) is the first parameter. In the decks in
//    scenarios/peridem/data every particle zone has R_ref = 1 mm (Parameters[0] = 1e-3), except the concave
//    (drum2d) zone of two_particle_concave_hex with R_ref = 1.5 mm, and every reference mesh is centred at
//    the origin (Parameters' centre = 0). The "small" and "large" meshes of compressive_small_set_ci are the
//    same mesh; the sizes come from the CSV radii alone.
//  - a grain with CSV row (i, x, y, z, r, o) gets the nodes  x_node = (x, y, z) + s R_z(o) v,  s = r / R_ref,
//    for every reference node v (rotation about the z axis through the reference origin, then the scale,
//    then the move), and the nodal volumes V = V_ref s^d, d the mesh dimension. In 3D too the rotation is
//    about z only (PeriDEM passes the axis (0, 0, 1) whatever the dimension); we do the same.
//  - grains are created zone by zone (all rows of zone 0 in file order, then zone 1, ...), so a grain's
//    index is PeriDEM's particle id, which the decks' Particle_List entries refer to; walls come after all
//    grains, in zone order (compressive_n500: grains 0..501, walls 502 and 503).
// Node ids are permanent: each appended node gets the previous last node's id + 1 (so 1..N when all nodes
// come from here). Node masses are left at 0: they need the material's density (mass = rho V).
#include <string>
#include <vector>

#include "core/io/gmsh_msh.hpp"
#include "core/io/grain_csv.hpp"
#include "core/pd_nodes.hpp"

namespace debris {

/// One zone's reference grain: its mesh about the origin, the nodal volumes of eq 31, and R_ref.
struct ReferenceGrain {
  SimplexMesh mesh;
  std::vector<double> volume;  // eq 31, one per mesh node
  double radius = 0;           // R_ref: the CSV radius r scales the mesh by r / R_ref
  int material = 0;            // index into the scenario's PdMaterial table, for every grain of the zone
};

/// Computes the nodal volumes; throws InputError (naming `what`) for R_ref <= 0 and for what
/// nodal_volumes() rejects.
ReferenceGrain make_reference_grain(SimplexMesh mesh, double radius, int material, const std::string& what);

/// Appends one grain (kind particle) for `record`; returns its grain index.
int place_grain(const ReferenceGrain& reference, const GrainRecord& record, PdNodes& nodes, PdGrains& grains);

/// Appends the grains of `records` in PeriDEM's order (zone by zone, file order within a zone); zone i
/// uses zones[i]. Throws InputError for a record whose zone has no reference grain.
void place_grains(const std::vector<ReferenceGrain>& zones, const std::vector<GrainRecord>& records, PdNodes& nodes,
                  PdGrains& grains);

/// Appends a wall: the mesh's nodes as they are, kind wall, at rest (wall velocity 0); returns its grain
/// index. `what` names the mesh in errors.
int append_wall(const SimplexMesh& mesh, int material, PdNodes& nodes, PdGrains& grains, const std::string& what);

}  // namespace debris
