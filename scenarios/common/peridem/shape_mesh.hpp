#pragma once
// Reference meshes of grain and wall shapes, made in-process by Gmsh's C++ API (gmsh_api.hpp) from the
// geometry PeriDEM's .geo scripts describe (paper B, section 3.1), written as an MSH file and read back.
//
// The 2D particle shapes use Gmsh's built-in kernel with the same points, curves and embedded centre
// point as PeriDEM's own scripts (the .geo files in scenarios/peridem/data), so the meshes are the same:
//  - circle: four quarter arcs about the centre (radius R);
//  - hexagon (paper Fig 18a): vertices x_c + R rot(a, k pi/3), k = 0..5 (R the circumradius, a the axis);
//  - concave polygon, PeriDEM's "drum2d" (paper Fig 18b): the hexagon with its two vertices on the axis
//    pulled in to the neck vertices x_c +- w a; in PeriDEM's vertex order
//      v1 = x_c + w a,  v2 = x_c + R rot(a, pi/3),  v3 = v2 - R a,
//      v4 = x_c - w a,  v6 = x_c + R rot(a, -pi/3), v5 = v6 - R a,
//    with area sqrt(3) R (R/2 + w). It is concave (a notch at each neck vertex) for 0 < w < R/2; at w = R/2
//    it is a rectangle. w is the half neck width, the distance from the centre to a neck vertex: Fig 19 of
//    the paper quotes "w = 0.5 R", but PeriDEM's script passes that number as the full neck width and puts
//    the neck vertex at 0.25 R (two_particle_concave_hex: R = 1.5 mm, deck parameter 0.75 mm, mesh vertex
//    at 0.375 mm); a half width of 0.5 R would be the rectangle. compressive_small_set_ci uses w = 0.2 R.
// Every point carries the mesh size h as its characteristic length, and the centre of the three shapes
// above is embedded in the surface (the scripts' `Point{1} In Surface{1}`), so the grain has a node at its
// centre.
//
// The rectangle [lo, hi] (2D, in the plane z = lo.z) is PeriDEM's wall script: four corner points carrying
// h, built-in kernel. The others use Gmsh's OpenCASCADE kernel with Mesh.CharacteristicLengthMax = h:
//  - rectangle minus rectangle: [lo, hi] minus [inner_lo, inner_hi] (a boolean difference of the two
//    rectangles, each built from its corner points), e.g. the U-shaped container of the compressive tests,
//    whose inner rectangle reaches the outer top edge;
//  - sphere (radius R about x_c) and box [lo, hi] in 3D (OpenCASCADE's box is a corner plus its lengths).
// Gmsh writes the mesh with 16 significant digits, so a vertex read back may differ from the given one in
// the last bit; the file is the mesh, so a run that reuses it gets the bits of the run that made it.
#include <string>

#include "core/io/gmsh_msh.hpp"
#include "core/vec3.hpp"

namespace debris {

enum class Shape { circle, hexagon, concave_polygon, rectangle, rectangle_minus_rectangle, sphere, box };

/// "circle", "hexagon", "concave_polygon", "rectangle", "rectangle_minus_rectangle", "sphere", "box".
const char* shape_name(Shape shape);
/// 2 or 3.
int shape_dimension(Shape shape);

struct ShapeSpec {
  Shape shape = Shape::circle;
  double mesh_size = 0;        // h: Gmsh's characteristic length (the target edge length)
  double radius = 0;           // R: circle, sphere; hexagon and concave polygon: centre to outer vertex
  double neck_half_width = 0;  // w: concave polygon, centre to neck vertex, 0 < w < R/2
  Vec3 centre;                 // x_c: circle, hexagon, concave polygon, sphere
  Vec3 axis{1, 0, 0};          // a: hexagon, concave polygon: from the centre towards v1, in the xy plane
  Vec3 lo, hi;                 // rectangle, box, and the outer rectangle of rectangle_minus_rectangle
  Vec3 inner_lo, inner_hi;     // rectangle_minus_rectangle: the rectangle taken away

  static ShapeSpec make_circle(double R, double h, Vec3 centre = {});
  static ShapeSpec make_hexagon(double R, double h, Vec3 centre = {}, Vec3 axis = {1, 0, 0});
  static ShapeSpec make_concave_polygon(double R, double w, double h, Vec3 centre = {}, Vec3 axis = {1, 0, 0});
  static ShapeSpec make_rectangle(Vec3 lo, Vec3 hi, double h);
  static ShapeSpec make_rectangle_minus_rectangle(Vec3 lo, Vec3 hi, Vec3 inner_lo, Vec3 inner_hi, double h);
  static ShapeSpec make_sphere(double R, double h, Vec3 centre = {});
  static ShapeSpec make_box(Vec3 lo, Vec3 hi, double h);
};

/// Throws InputError naming the parameter ("concave_polygon.neck_half_width") and its value for
/// non-positive or non-finite sizes, an axis that is zero or leaves the xy plane, a concave polygon with w
/// outside (0, R/2), empty rectangles or boxes, and an inner rectangle that misses or covers the outer one.
void validate_shape(const ShapeSpec& spec);

/// The exact area (2D) or volume (3D) of the geometry itself (a circle's is pi R^2, not its mesh's).
double shape_measure(const ShapeSpec& spec);

struct GmshRun {
  std::string directory;  // where the .msh files go (created if missing)
  int msh_version = 22;   // 22 or 41: the MSH format Gmsh writes and we read back
  bool reuse = true;      // read an existing mesh of the same shape instead of meshing it again
};

/// Meshes the shape with Gmsh's API and reads the mesh back. The file is named after the shape and a hash
/// of its numbers, the format and Gmsh's version (`circle-<hash>.msh`), so with `reuse` a shape is meshed
/// once per directory. Gmsh writes to a temporary name that is renamed into place, so concurrent runs never
/// read half a file. Throws InputError for a bad spec, when debris was built without Gmsh's API (saying
/// how to get it), and when Gmsh fails (with its messages).
SimplexMesh mesh_shape(const ShapeSpec& spec, const GmshRun& run);

}  // namespace debris
