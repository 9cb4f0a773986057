#pragma once
// Regions of space that an input uses to choose particles (removal, labels, groups): an axis-aligned
// block, a finite cylinder along x, y or z, the space below or above a rough surface, and unions and
// differences of those. One small value type, tested point by point; nothing here runs in the step loop.
//
//   block      per axis [lo, hi), either side open (-inf / inf)
//   cylinder   axis a, the axis line through `centre` (its a-component is unused), distance to the line
//              <= radius, and [lo, hi) along a (open by default)
//   surface    a height field h over the plane across the normal axis n (core/rough/height_field.hpp):
//              below, p_n < h(p); above, p_n >= h(p). The field spans the box's two in-plane lengths, so
//              it is periodic with the box; it is shared (std::shared_ptr<const HeightField>), so copying
//              the region copies no heights.
//   union      inside any part
//   difference inside parts[0] and in none of the others (the junction's gap: a layer minus a cylinder)
//
// Periodic boxes: a point is tested as given, which for particles is their wrapped position in [lo, hi)
// of the box. No periodic image of a region is considered, so a cylinder or block that crosses a periodic
// face does not continue on the other side: place regions inside the box. read_region refuses a cylinder
// wider than the box, which no placement could make fit. A surface is the exception by construction: its
// field is periodic with the box's in-plane lengths, so it continues across the periodic faces.
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "core/vec3.hpp"

namespace debris {

class Box;
class InputNode;
class KeyReference;
struct HeightField;

struct Region {
  enum class Kind { block, cylinder, surface, union_of, difference };
  Kind kind = Kind::block;
  // block bounds; for a cylinder only lo/hi[axis] (its extent) is used.
  double lo[3], hi[3];
  int axis = 2;                // cylinder; surface: the normal axis
  Vec3 centre{0, 0, 0};        // cylinder: a point on its axis line
  double radius = 0;           // cylinder
  std::vector<Region> parts;   // union_of, difference
  // surface: the heights where they stand (their mean is the input's `at`), which side is inside, what made
  // the field (for describe), and its shortest wavelength with the key that sets it (a self-affine field's
  // cut-off, twice a measured map's spacing), which the DEM input holds against the particle size.
  std::shared_ptr<const HeightField> field;
  bool below = true;
  std::string made_by;
  double shortest_wavelength = 0;
  std::string shortest_wavelength_key;

  /// The whole space (a block with every side open).
  Region();
  static Region block(Vec3 lo, Vec3 hi);
  /// Extent [lo, hi) along `axis`; defaults open.
  static Region cylinder(int axis, Vec3 centre, double radius, double lo = -std::numeric_limits<double>::infinity(),
                         double hi = std::numeric_limits<double>::infinity());
  /// The space below (or above) `field` along its normal axis; `made_by` says where the field came from
  /// ("self-affine H 0.8 ..."), for describe().
  static Region surface(std::shared_ptr<const HeightField> field, bool below, std::string made_by = "",
                        double shortest_wavelength = 0, std::string shortest_wavelength_key = "");
  static Region union_of(std::vector<Region> parts);
  static Region difference(std::vector<Region> parts);

  bool contains(Vec3 p) const;

  /// The surface regions in this one (itself, or among its parts at any depth), in input order.
  std::vector<const Region*> surfaces() const;

  /// One line for messages: "cylinder axis y centre [..] radius .. extent [..]", "surface normal y below at
  /// .. (rms height .., self-affine H ..)", "union of (...)".
  std::string describe() const;
};

/// A region from its input form, one of
///   {block: {x: [lo, hi], y: [..], z: [..]}}    missing axes are open; bounds may be -inf/inf (or min/max)
///   {x: [lo, hi], ...}                          the same block, the groups' older form
///   {cylinder: {axis: y, centre: [30 nm, 0, 20 nm], radius: 10 nm, extent: [18 nm, 23 nm]}}
///   {surface: {normal: y, side: below, at: 12 nm, self_affine: {hurst: 0.8, rms_height: 1 nm,
///              cutoff_wavelength: 2 nm, seed: 3}, grid_spacing: 0.2 nm}}
///   {surface: {normal: y, side: above, at: 12 nm, height_map: {file: afm.txt, spacing: [1 nm, 1 nm], unit: nm}}}
///   {union: [region, region, ...]}
///   {difference: [region, minus this, and this, ...]}
/// InputError naming the key and value for a malformed one; with `box`, also for a cylinder whose diameter
/// exceeds the box's length along one of the two axes across it (a cylinder larger than the box). A surface
/// needs `box` (its field spans the box's in-plane lengths) and must fit inside it along the normal; a
/// relative height_map file is looked for in `base_directory` (the input file's folder) when one is given.
Region read_region(const InputNode& node, const Box* box = nullptr, const std::string& base_directory = "");

/// A rough surface is carved by testing particle centres, so its features must span several particles: every
/// surface in `region` needs a shortest wavelength of at least two diameters of the largest particle. InputError
/// naming the key that sets the wavelength, the wavelength and the two diameters otherwise.
void check_surface_resolution(const Region& region, double largest_diameter);

/// Describes the keys of a region as the shared table "region" of `ref` (a key that holds a region says
/// `.follows("region")`).
void document_regions(KeyReference& ref);

/// A region bound: a length, or -inf/inf (also min/max) for an open side.
double read_bound(const InputNode& n);

}  // namespace debris
