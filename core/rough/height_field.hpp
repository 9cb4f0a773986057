#pragma once
// A height field h over the plane across a normal axis: heights on a regular periodic grid, read between grid
// points by bilinear interpolation. It is what a rough surface is everywhere in debris: the generator makes one
// (self_affine_surface), a measured map is read into one (height_map_file), a carving region cuts a body with
// one (region "surface"), and the census measures a worn body's face as one (surface_spectrum analyses it).
//
// The in-plane axes are the other two axes in increasing order: normal y -> (x, z), z -> (x, y), x -> (y, z);
// call them a and b. Grid point (i, j) sits at (origin_a + i * length_a / n_a, origin_b + j * length_b / n_b)
// and holds h[i * n_b + j]. The field is periodic with periods length_a and length_b, so it tiles a periodic
// box. A profile (a thin slab's 1D surface) has n_b = 1: constant along b.
#include <vector>

#include "core/vec3.hpp"

namespace debris {

struct HeightField {
  int normal_axis = 1;
  double origin_a = 0, origin_b = 0;
  double length_a = 0, length_b = 0;
  int n_a = 0, n_b = 0;
  std::vector<double> h;  // n_a * n_b heights, row-major in a (h[i * n_b + j])

  /// The in-plane axes a and b (0, 1, 2 for x, y, z).
  int axis_a() const { return normal_axis == 0 ? 1 : 0; }
  int axis_b() const { return normal_axis == 2 ? 1 : 2; }
  double spacing_a() const { return length_a / n_a; }
  double spacing_b() const { return length_b / n_b; }
  double at(int i, int j) const { return h[static_cast<std::size_t>(i) * n_b + j]; }

  /// h at in-plane coordinates (a, b), periodic, bilinear between grid points (along a only for a profile).
  double height(double a, double b) const;
  /// h under point p (its in-plane components).
  double height_under(Vec3 p) const;

  double mean() const;
  /// Root mean square of h - mean over the grid points.
  double rms_height() const;
  /// Root mean square of the gradient's magnitude, by central differences on the periodic grid (along a only
  /// for a profile). Short waves come out low (by sin(k d) / (k d)); the spectral one, exact for the
  /// band-limited field the generator makes, is spectral_rms_slope (surface_spectrum.hpp).
  double rms_slope() const;
};

}  // namespace debris
