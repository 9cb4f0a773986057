#pragma once
// A body's face measured as a height field: on a grid over the box's two in-plane lengths, for each grid point
// the highest (side top) or lowest (side bottom) point of the body's spheres over it,
//   top:    max_i  y_i + sqrt(r_i^2 - d_i^2)      over the spheres with in-plane distance d_i <= r_i
//   bottom: min_i  y_i - sqrt(r_i^2 - d_i^2)
// (y standing for the normal axis), with the spheres' periodic images along the box's periodic in-plane axes.
//
// Why the envelope of the spheres and not the top particle centre per column: a column's top centre jumps by a
// layer spacing wherever the column's top particle changes, and it is one radius below the face a probe (or the
// other body) touches, by an amount that depends on the size of the particle at the top. Its spectrum shows the
// lattice of columns, not the face. The envelope is continuous, is the surface the other body actually meets,
// and reads a flat lattice face as flat up to its caps (amplitude ~ r (1 - cos) between neighbours, at the
// particle scale, which the spectrum's fit leaves out).
//
// Cost: each sphere is scattered over the grid points of its footprint only (its in-plane bounding square of
// side 2 r_i): O(N (2 r / spacing)^2), independent of how deep the body is and never O(N x grid). (The sketch's
// alternative, binning the spheres in-plane and gathering per grid point, tests every sphere of a column bin
// through the body's whole depth at every grid point over the bin: ~9 x depth / r times the work here.) The
// maximum (minimum) does not depend on the order of the spheres, so the result is the same bits however the
// particles are sorted.
//
// Grid points that no sphere covers (gaps in a sparse face; a selection with holes) are filled from their
// neighbours: each pass gives every uncovered point that has a filled one among its 4 grid neighbours (periodic
// along periodic axes) the mean of those, from the values of the previous pass, until all are filled. Their
// number is reported; an empty selection is a std::invalid_argument.
#include <cstddef>
#include <span>

#include "core/rough/height_field.hpp"

namespace debris {

class Box;

enum class EnvelopeSide { top, bottom };

struct SurfaceEnvelope {
  HeightField field;       // the grid of HeightField: n = ceil(length / spacing) points along each in-plane axis
  long filled_points = 0;  // grid points no sphere covers, given their neighbours' mean
};

/// The envelope of the spheres `selection` (indices into x, y, z, radius) on a grid of at most `spacing`
/// over the box's in-plane lengths across `normal_axis`. std::invalid_argument for spacing <= 0, an empty
/// selection, or an index out of range.
SurfaceEnvelope surface_envelope(const Box& box, int normal_axis, EnvelopeSide side, double spacing,
                                 std::span<const double> x, std::span<const double> y, std::span<const double> z,
                                 std::span<const double> radius, std::span<const std::size_t> selection);

/// The same for the spheres whose `mask` entry is non-zero (one entry per sphere).
SurfaceEnvelope surface_envelope(const Box& box, int normal_axis, EnvelopeSide side, double spacing,
                                 std::span<const double> x, std::span<const double> y, std::span<const double> z,
                                 std::span<const double> radius, std::span<const char> mask);

}  // namespace debris
