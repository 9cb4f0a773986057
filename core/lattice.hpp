#pragma once
// Built-in generators of close-packed sphere lattices (FCC, HCP) in an orthogonal box that is exactly a
// whole number of lattice periods, so that the same particles are a perfect crystal under periodic
// boundaries. Optional random size spread and displacement turn them into the polydisperse, slightly
// disordered packings the cohesive DEM starts from.
#include <array>
#include <cstdint>
#include <string>

#include "core/box.hpp"
#include "core/particles.hpp"
#include "core/vec3.hpp"

namespace debris {

enum class LatticeKind { fcc, hcp };

struct LatticeSpec {
  LatticeKind kind = LatticeKind::fcc;
  double spacing = 1;       // nearest-neighbour distance a
  double diameter = 1;      // mean particle diameter (often == spacing)
  double size_spread = 0;   // d = diameter * (1 + size_spread * U(-1, 1)), in [0, 1)
  double displacement = 0;  // each coordinate moves by displacement * U(-1, 1) (absolute length)
  std::array<int, 3> cells{1, 1, 1};  // repetitions of the orthogonal unit cell along x, y, z
  Vec3 origin{0, 0, 0};               // low corner of the box
  std::uint64_t seed = 1;             // std::mt19937_64; same seed, same particles
  int type = 1;
  // HCP: stacking (c) axis. The other two axes, in increasing order, are the in-plane directions with
  // periods a and a*sqrt(3); the default 1 (y) makes the close-packed planes x-z planes.
  int hcp_c_axis = 1;
};

struct Lattice {
  Box box;               // exactly cells * period on every axis; periodic flags all false (caller sets them)
  Particles particles;   // ids 1..N (LAMMPS numbering), radius d/2, group -1, mass and inertia 0 (the material sets them)
};

/// Periods of the orthogonal unit cell along x, y, z (4 particles per cell for both kinds).
Vec3 lattice_period(const LatticeSpec& spec);

/// Throws InputError naming "lattice.<key>" for the first invalid field.
void validate(const LatticeSpec& spec, const std::string& prefix = "lattice");

/// Generates 4 * cells[0] * cells[1] * cells[2] particles (validates spec first).
Lattice make_lattice(const LatticeSpec& spec);

}  // namespace debris
