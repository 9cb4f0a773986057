#pragma once
// Regions of space that an input uses to choose particles (removal, labels, groups): an axis-aligned
// block, a finite cylinder along x, y or z, and unions and differences of those. One small value type,
// tested point by point; nothing here runs in the step loop.
//
//   block      per axis [lo, hi), either side open (-inf / inf)
//   cylinder   axis a, the axis line through `centre` (its a-component is unused), distance to the line
//              <= radius, and [lo, hi) along a (open by default)
//   union      inside any part
//   difference inside parts[0] and in none of the others (the junction's gap: a layer minus a cylinder)
//
// Periodic boxes: a point is tested as given, which for particles is their wrapped position in [lo, hi)
// of the box. No periodic image of a region is considered, so a cylinder or block that crosses a periodic
// face does not continue on the other side: place regions inside the box. read_region refuses a cylinder
// wider than the box, which no placement could make fit.
#include <limits>
#include <string>
#include <vector>

#include "core/vec3.hpp"

namespace debris {

class Box;
class InputNode;
class KeyReference;

struct Region {
  enum class Kind { block, cylinder, union_of, difference };
  Kind kind = Kind::block;
  // block bounds; for a cylinder only lo/hi[axis] (its extent) is used.
  double lo[3], hi[3];
  int axis = 2;                // cylinder
  Vec3 centre{0, 0, 0};        // cylinder: a point on its axis line
  double radius = 0;           // cylinder
  std::vector<Region> parts;   // union_of, difference

  /// The whole space (a block with every side open).
  Region();
  static Region block(Vec3 lo, Vec3 hi);
  /// Extent [lo, hi) along `axis`; defaults open.
  static Region cylinder(int axis, Vec3 centre, double radius, double lo = -std::numeric_limits<double>::infinity(),
                         double hi = std::numeric_limits<double>::infinity());
  static Region union_of(std::vector<Region> parts);
  static Region difference(std::vector<Region> parts);

  bool contains(Vec3 p) const;

  /// One line for messages: "cylinder axis y centre [..] radius .. extent [..]", "union of 2: ...".
  std::string describe() const;
};

/// A region from its input form, one of
///   {block: {x: [lo, hi], y: [..], z: [..]}}    missing axes are open; bounds may be -inf/inf (or min/max)
///   {x: [lo, hi], ...}                          the same block, the groups' older form
///   {cylinder: {axis: y, centre: [30 nm, 0, 20 nm], radius: 10 nm, extent: [18 nm, 23 nm]}}
///   {union: [region, region, ...]}
///   {difference: [region, minus this, and this, ...]}
/// InputError naming the key and value for a malformed one; with `box`, also for a cylinder whose diameter
/// exceeds the box's length along one of the two axes across it (a cylinder larger than the box).
Region read_region(const InputNode& node, const Box* box = nullptr);

/// Describes the keys of a region as the shared table "region" of `ref` (a key that holds a region says
/// `.follows("region")`).
void document_regions(KeyReference& ref);

/// A region bound: a length, or -inf/inf (also min/max) for an open side.
double read_bound(const InputNode& n);

}  // namespace debris
