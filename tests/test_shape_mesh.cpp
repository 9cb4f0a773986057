// Reference shapes meshed in-process by Gmsh's API: PeriDEM's own scripts reproduced, every node inside its
// shape, nodal volumes summing to the exact area (polygons) or the inscribed polygon / polyhedron (circle,
// sphere), the concave polygon's notches free of nodes, reuse of a meshed file, and the errors for bad
// shapes and a failing Gmsh. Coarse meshes: each takes well under a second.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <string>

#include "core/error.hpp"
#include "core/io/gmsh_msh.hpp"
#include "scenarios/common/peridem/nodal_volume.hpp"
#include "scenarios/common/peridem/shape_mesh.hpp"
#include "tests/cli_helpers.hpp"

namespace debris {
namespace {

namespace fs = std::filesystem;

const std::string kData = std::string(DEBRIS_SOURCE_DIR) + "/scenarios/peridem/data";

/// A scratch directory in the build tree (beside the test binary), emptied first so that Gmsh really runs.
fs::path scratch(const std::string& name) { return debris::test::fresh_directory("debris_pd_" + name); }

GmshRun fresh_run(const std::string& name, int msh_version = 22) {
  GmshRun run;
  run.directory = scratch(name).string();
  run.msh_version = msh_version;
  return run;
}

using test::contains;

using test::sum;

double segment_distance(Vec3 p, Vec3 a, Vec3 b) {
  const Vec3 ab = b - a;
  const double t = std::clamp(dot(p - a, ab) / norm2(ab), 0.0, 1.0);
  return norm(p - (a + t * ab));
}

/// Inside the polygon (2D, by crossings) or within `tol` of its boundary.
bool in_polygon(Vec3 p, const std::vector<Vec3>& poly, double tol) {
  bool inside = false;
  for (std::size_t k = 0, n = poly.size(); k < n; ++k) {
    const Vec3 a = poly[k], b = poly[(k + 1) % n];
    if (segment_distance(p, a, b) <= tol) return true;
    if ((a.y > p.y) != (b.y > p.y) && p.x < a.x + (p.y - a.y) * (b.x - a.x) / (b.y - a.y)) inside = !inside;
  }
  return inside;
}

/// The hexagon (k = 0..5 at angles k pi/3 from the axis) and concave polygon of shape_mesh.hpp, written out
/// again here from the paper's Fig 18 description.
std::vector<Vec3> hexagon(double R) {
  std::vector<Vec3> v;
  for (int k = 0; k < 6; ++k)
    v.push_back({R * std::cos(k * std::numbers::pi / 3), R * std::sin(k * std::numbers::pi / 3), 0});
  return v;
}
std::vector<Vec3> concave(double R, double w) {
  const double s = R * std::sqrt(3.0) / 2;
  return {{w, 0, 0}, {R / 2, s, 0}, {-R / 2, s, 0}, {-w, 0, 0}, {-R / 2, -s, 0}, {R / 2, -s, 0}};
}

/// Area of a simple polygon (shoelace).
double polygon_area(const std::vector<Vec3>& v) {
  double a = 0;
  for (std::size_t k = 0; k < v.size(); ++k) a += v[k].x * v[(k + 1) % v.size()].y - v[(k + 1) % v.size()].x * v[k].y;
  return 0.5 * std::abs(a);
}

/// Node coordinates equal to a PeriDEM mesh's, tag by tag (same script, same Gmsh: Debian 12 ships 4.8.4,
/// which reproduces the shipped files; another Gmsh version may place interior nodes differently).
void expect_same_nodes(const SimplexMesh& ours, const std::string& peridem_file, double scale) {
  const SimplexMesh theirs = read_gmsh_msh(kData + "/" + peridem_file);
  ASSERT_EQ(ours.nodes.size(), theirs.nodes.size()) << peridem_file;
  std::map<std::int64_t, Vec3> by_tag;
  for (std::size_t i = 0; i < theirs.nodes.size(); ++i) by_tag[theirs.node_tag[i]] = theirs.nodes[i];
  for (std::size_t i = 0; i < ours.nodes.size(); ++i) {
    ASSERT_EQ(by_tag.count(ours.node_tag[i]), 1u) << peridem_file << " tag " << ours.node_tag[i];
    ASSERT_LT(norm(ours.nodes[i] - by_tag[ours.node_tag[i]]), 1e-12 * scale) << peridem_file << " node " << i;
  }
  EXPECT_EQ(ours.triangles.size(), theirs.triangles.size()) << peridem_file;
}

std::string shape_error(const ShapeSpec& spec, const GmshRun& run) {
  try {
    mesh_shape(spec, run);
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no InputError for " << shape_name(spec.shape);
  return "";
}

// ---------------------------------------------------------------------------------------------------------

TEST(PdShape, CircleIsPeriDEMsMeshAndTheInscribedPolygon) {
  const double R = 1e-3, h = 2e-4;  // PeriDEM's circle zones (mesh_cir_1_0.geo)
  const SimplexMesh m = mesh_shape(ShapeSpec::make_circle(R, h), fresh_run("pd_shape_circle"));
  ASSERT_EQ(m.dimension, 2);
  expect_same_nodes(m, "two_particle_circ_example/mesh_cir_1_0.msh", R);
  EXPECT_EQ(norm(m.nodes[0]), 0.0);  // the embedded centre
  std::vector<Vec3> rim;
  for (const Vec3& p : m.nodes) {
    EXPECT_LE(norm(p), R * (1 + 1e-15));
    if (norm(p) > R * (1 - 1e-12)) rim.push_back(p);
  }
  std::sort(rim.begin(), rim.end(), [](Vec3 a, Vec3 b) { return std::atan2(a.y, a.x) < std::atan2(b.y, b.x); });
  const std::vector<double> v = nodal_volumes(m, "circle");
  // The mesh is the polygon inscribed through its rim nodes: the same area to round-off. Inscribed, it is
  // smaller than pi R^2, by about (2 pi / N)^2 / 6 for N equal sides (0.7% here).
  EXPECT_NEAR(sum(v), polygon_area(rim), 1e-13 * sum(v));
  const double N = static_cast<double>(rim.size());
  EXPECT_LE(sum(v), 0.5 * N * R * R * std::sin(2 * std::numbers::pi / N) * (1 + 1e-13));  // the regular N-gon's
  EXPECT_LT(sum(v), shape_measure(ShapeSpec::make_circle(R, h)));
  EXPECT_GT(sum(v), 0.98 * std::numbers::pi * R * R);
}

TEST(PdShape, HexagonAndConcavePolygonArePeriDEMsMeshesWithExactAreas) {
  const double R = 1e-3, h = 2e-4;
  const ShapeSpec hex = ShapeSpec::make_hexagon(R, h);
  const SimplexMesh mh = mesh_shape(hex, fresh_run("pd_shape_hexagon"));
  expect_same_nodes(mh, "compressive_n500/mesh_particle_2_0.msh", R);
  for (const Vec3& p : mh.nodes) EXPECT_TRUE(in_polygon(p, hexagon(R), 1e-15));
  const double hex_area = 1.5 * std::sqrt(3.0) * R * R;
  EXPECT_NEAR(shape_measure(hex), hex_area, 1e-15 * hex_area);
  EXPECT_NEAR(sum(nodal_volumes(mh, "hexagon")), hex_area, 1e-13 * hex_area);

  // The concave drum of two_particle_concave_hex: R = 1.5 mm, neck vertex at w = 0.375 mm.
  const double Rc = 1.5e-3, w = 0.375e-3;
  const ShapeSpec drum = ShapeSpec::make_concave_polygon(Rc, w, h);
  const SimplexMesh md = mesh_shape(drum, fresh_run("pd_shape_concave"));
  expect_same_nodes(md, "two_particle_concave_hex/mesh_particle_1_0.msh", Rc);
  const double drum_area = polygon_area(concave(Rc, w));
  EXPECT_NEAR(shape_measure(drum), drum_area, 1e-15 * drum_area);
  EXPECT_NEAR(sum(nodal_volumes(md, "drum")), drum_area, 1e-13 * drum_area);
  for (const Vec3& p : md.nodes) EXPECT_TRUE(in_polygon(p, concave(Rc, w), 1e-15));
}

TEST(PdShape, ConcavePolygonHasNodeFreeNotches) {
  // A rotated, off-centre concave polygon: the notch at each neck vertex (the triangle between the neck vertex
  // and the two outer vertices beside it) holds no node, though the outer vertices are nodes of the mesh.
  const double R = 1e-3, w = 0.2e-3, h = 2e-4, angle = 0.3;
  const Vec3 c{0.004, -0.002, 0}, a{std::cos(angle), std::sin(angle), 0};
  const SimplexMesh m = mesh_shape(ShapeSpec::make_concave_polygon(R, w, h, c, a), fresh_run("pd_shape_notch"));
  std::vector<Vec3> poly;
  for (const Vec3& p : concave(R, w)) poly.push_back(c + Vec3{a.x * p.x - a.y * p.y, a.y * p.x + a.x * p.y, 0});
  for (const Vec3& p : m.nodes) EXPECT_TRUE(in_polygon(p, poly, 1e-15));
  for (const auto& [neck, left, right] : {std::array<int, 3>{0, 5, 1}, std::array<int, 3>{3, 2, 4}}) {
    const Vec3 n = poly[neck], l = poly[left], r = poly[right];
    // The outer vertices are nodes (Gmsh keeps geometry points), so the notch lies within the node cloud.
    auto is_node = [&](Vec3 q) {
      return std::any_of(m.nodes.begin(), m.nodes.end(), [&](Vec3 p) { return norm(p - q) < 1e-12 * R; });
    };
    EXPECT_TRUE(is_node(l) && is_node(r) && is_node(n));
    const double area = 0.5 * std::abs(cross(l - n, r - n).z);
    EXPECT_GT(area, h * h);  // a notch several mesh cells large
    int inside = 0;
    for (const Vec3& p : m.nodes) {
      // Barycentric coordinates in the notch triangle, all > 0 strictly inside.
      const double b1 = 0.5 * cross(r - p, n - p).z / (0.5 * cross(r - l, n - l).z);
      const double b2 = 0.5 * cross(n - p, l - p).z / (0.5 * cross(r - l, n - l).z);
      const double b0 = 1 - b1 - b2;
      inside += b0 > 1e-9 && b1 > 1e-9 && b2 > 1e-9;
    }
    EXPECT_EQ(inside, 0) << "neck vertex " << neck;
    EXPECT_FALSE(in_polygon(c + ((w + R / 2) / 2) * a * (neck == 0 ? 1.0 : -1.0), poly, 0.0));
  }
}

TEST(PdShape, RectangleAndUShapedContainerOfTheCompressiveTest) {
  // compressive_n500's walls: the moving top plate (a rectangle, PeriDEM's built-in script) and the fixed
  // U-shaped container (rectangle minus rectangle, OpenCASCADE here, eight corner points in PeriDEM's).
  const double h = 2e-4;
  const Vec3 lo{-2.2e-4, 4.122e-2, 0}, hi{6.872e-2, 4.182e-2, 0};
  const SimplexMesh plate = mesh_shape(ShapeSpec::make_rectangle(lo, hi, h), fresh_run("pd_shape_rectangle", 41));
  // PeriDEM's compressive_n500 walls were made by another Gmsh version than its particles: the same number of
  // nodes and the same edge nodes, but other interior nodes. So compare those.
  const SimplexMesh theirs = read_gmsh_msh(kData + "/compressive_n500/mesh_moving_wall_0.msh");
  EXPECT_EQ(plate.nodes.size(), theirs.nodes.size());
  auto edge_nodes = [&](const SimplexMesh& m) {
    std::vector<std::pair<double, double>> e;
    for (const Vec3& p : m.nodes)
      if (p.x == lo.x || p.x == hi.x || p.y == lo.y || p.y == hi.y) e.push_back({p.x, p.y});
    std::sort(e.begin(), e.end());
    return e;
  };
  const auto ours_edge = edge_nodes(plate), theirs_edge = edge_nodes(theirs);
  ASSERT_EQ(ours_edge.size(), theirs_edge.size());
  EXPECT_GT(ours_edge.size(), 2 * (hi.x - lo.x) / h);
  for (std::size_t k = 0; k < ours_edge.size(); ++k) {
    EXPECT_NEAR(ours_edge[k].first, theirs_edge[k].first, 1e-15);
    EXPECT_NEAR(ours_edge[k].second, theirs_edge[k].second, 1e-15);
  }
  const double plate_area = (hi.x - lo.x) * (hi.y - lo.y);
  EXPECT_NEAR(sum(nodal_volumes(plate, "plate")), plate_area, 1e-13 * plate_area);
  for (const Vec3& p : plate.nodes) EXPECT_TRUE(p.x >= lo.x && p.x <= hi.x && p.y >= lo.y && p.y <= hi.y);

  const Vec3 olo{-8.2e-4, -8.2e-4, 0}, ohi{6.932e-2, 4.182e-2, 0}, ilo{-2.2e-4, -2.2e-4, 0}, ihi{6.872e-2, 4.182e-2, 0};
  const ShapeSpec u = ShapeSpec::make_rectangle_minus_rectangle(olo, ohi, ilo, ihi, h);
  const SimplexMesh wall = mesh_shape(u, fresh_run("pd_shape_u"));
  const double u_area = (ohi.x - olo.x) * (ohi.y - olo.y) - (ihi.x - ilo.x) * (ihi.y - ilo.y);
  EXPECT_NEAR(shape_measure(u), u_area, 1e-15 * u_area);
  EXPECT_NEAR(sum(nodal_volumes(wall, "container")), u_area, 1e-12 * u_area);
  // Same number of nodes as PeriDEM's container mesh (same corners and sizes, other kernel).
  EXPECT_EQ(wall.nodes.size(), read_gmsh_msh(kData + "/compressive_n500/mesh_rigid_wall_0.msh").nodes.size());
  int on_inner = 0;
  const double tol = 1e-12 * (ohi.x - olo.x);
  for (const Vec3& p : wall.nodes) {
    EXPECT_TRUE(p.x >= olo.x - tol && p.x <= ohi.x + tol && p.y >= olo.y - tol && p.y <= ohi.y + tol);
    const bool strictly_inner = p.x > ilo.x + tol && p.x < ihi.x - tol && p.y > ilo.y + tol;
    EXPECT_FALSE(strictly_inner) << p.x << " " << p.y;
    on_inner += std::abs(p.y - ilo.y) < tol && p.x > ilo.x && p.x < ihi.x;
  }
  EXPECT_GT(on_inner, 0);  // the container's floor is meshed up to the cavity
}

TEST(PdShape, RectangleMinusRectangleMayComeInPieces) {
  // An inner rectangle across the outer one leaves two bars: both are meshed.
  const ShapeSpec cut = ShapeSpec::make_rectangle_minus_rectangle({0, 0, 0}, {4, 1, 0}, {1, -1, 0}, {2, 2, 0}, 0.25);
  const SimplexMesh m = mesh_shape(cut, fresh_run("pd_shape_pieces"));
  EXPECT_EQ(shape_measure(cut), 3.0);
  EXPECT_NEAR(sum(nodal_volumes(m, "two bars")), 3.0, 1e-13);
  int left = 0, right = 0;
  for (const Vec3& p : m.nodes) {
    EXPECT_FALSE(p.x > 1 + 1e-12 && p.x < 2 - 1e-12);
    left += p.x <= 1;
    right += p.x >= 2;
  }
  EXPECT_GT(left, 0);
  EXPECT_GT(right, left);  // the right bar is three times as long
}

TEST(PdShape, SphereIsInscribedAndBoxIsExact) {
  const double R = 1e-3, h = R / 5;
  const SimplexMesh s = mesh_shape(ShapeSpec::make_sphere(R, h), fresh_run("pd_shape_sphere"));
  ASSERT_EQ(s.dimension, 3);
  for (const Vec3& p : s.nodes) EXPECT_LE(norm(p), R * (1 + 1e-12));
  // The volume the boundary faces (faces of one tetrahedron only) enclose, by the divergence theorem:
  // sum of det(a, b, c) / 6 over the faces turned outwards (away from their tetrahedron's fourth vertex).
  std::map<std::array<int, 3>, int> faces;
  std::vector<std::pair<std::array<int, 3>, int>> oriented;
  for (const auto& t : s.tetrahedra)
    for (int k = 0; k < 4; ++k) {
      std::array<int, 3> f{t[(k + 1) % 4], t[(k + 2) % 4], t[(k + 3) % 4]};
      oriented.push_back({f, t[k]});
      std::sort(f.begin(), f.end());
      ++faces[f];
    }
  double enclosed = 0;
  for (auto [f, opposite] : oriented) {
    std::array<int, 3> key = f;
    std::sort(key.begin(), key.end());
    if (faces[key] != 1) continue;
    const Vec3 a = s.nodes[f[0]], b = s.nodes[f[1]], c = s.nodes[f[2]];
    const double sign = dot(cross(b - a, c - a), s.nodes[opposite] - a) > 0 ? -1.0 : 1.0;
    enclosed += sign * dot(a, cross(b, c)) / 6.0;
  }
  // Eq 31's volumes fill that polyhedron, whose vertices lie on the sphere, so it is inscribed (convexity):
  // below the ball's volume, by 1.4% with h = R / 5 (measured; the cut-off shell shrinks as h^2).
  const double ball = 4.0 / 3.0 * std::numbers::pi * R * R * R;
  const double vs = sum(nodal_volumes(s, "sphere"));
  EXPECT_NEAR(vs, enclosed, 1e-12 * vs);
  EXPECT_LT(vs, ball);
  EXPECT_GT(vs, 0.98 * ball);

  const Vec3 lo{-1e-3, 0, 2e-3}, hi{2e-3, 1e-3, 2.5e-3};
  const SimplexMesh b = mesh_shape(ShapeSpec::make_box(lo, hi, 2.5e-4), fresh_run("pd_shape_box", 41));
  ASSERT_EQ(b.dimension, 3);
  const double tol = 1e-12 * 3e-3;
  for (const Vec3& p : b.nodes)
    EXPECT_TRUE(p.x >= lo.x - tol && p.x <= hi.x + tol && p.y >= lo.y - tol && p.y <= hi.y + tol && p.z >= lo.z - tol &&
                p.z <= hi.z + tol);
  const double box = (hi.x - lo.x) * (hi.y - lo.y) * (hi.z - lo.z);
  EXPECT_NEAR(sum(nodal_volumes(b, "box")), box, 1e-12 * box);
}

TEST(PdShape, ReusesTheMeshFileOfTheSameShape) {
  GmshRun run = fresh_run("pd_shape_reuse");
  const ShapeSpec spec = ShapeSpec::make_hexagon(1e-3, 3e-4);
  const SimplexMesh first = mesh_shape(spec, run);
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(run.directory)) files.push_back(e.path());
  ASSERT_EQ(files.size(), 1u);  // one .msh, no temporary left behind
  EXPECT_EQ(files[0].extension(), ".msh");
  EXPECT_TRUE(contains(files[0].filename().string(), "hexagon-"));
  // With reuse the file is the mesh: put another mesh there and that one comes back, Gmsh is not asked.
  fs::copy_file(kData + "/compressive_n500/mesh_particle_1_0.msh", files[0], fs::copy_options::overwrite_existing);
  EXPECT_EQ(mesh_shape(spec, run).nodes.size(), 123u);  // PeriDEM's circle
  run.reuse = false;
  const SimplexMesh again = mesh_shape(spec, run);
  ASSERT_EQ(again.nodes.size(), first.nodes.size());
  for (std::size_t i = 0; i < first.nodes.size(); ++i) EXPECT_EQ(norm(again.nodes[i] - first.nodes[i]), 0.0);
  EXPECT_EQ(read_gmsh_msh(files[0].string()).nodes.size(), first.nodes.size());  // the file was written again
  // Another mesh size, another format: other files.
  run.reuse = true;
  mesh_shape(ShapeSpec::make_hexagon(1e-3, 2.9e-4), run);
  run.msh_version = 41;
  mesh_shape(spec, run);
  EXPECT_EQ(std::distance(fs::directory_iterator(run.directory), fs::directory_iterator()), 3);
}

TEST(PdShape, BadShapesNameTheParameterAndValue) {
  const GmshRun run = fresh_run("pd_shape_bad");
  struct Case {
    ShapeSpec spec;
    std::vector<std::string> expect;
  };
  const Vec3 o{0, 0, 0}, one{1, 1, 0};
  const std::vector<Case> cases = {
      {ShapeSpec::make_circle(-1e-3, 1e-4), {"'circle.radius' = -0.001", "> 0"}},
      {ShapeSpec::make_circle(1e-3, 0), {"'circle.mesh_size' = 0"}},
      {ShapeSpec::make_sphere(1e-3, NAN), {"'sphere.mesh_size' = nan"}},
      {ShapeSpec::make_hexagon(1e-3, 1e-4, o, {0, 0, 0}), {"'hexagon.axis'", "non-zero"}},
      {ShapeSpec::make_hexagon(1e-3, 1e-4, o, {1, 0, 1}), {"'hexagon.axis'", "xy plane"}},
      {ShapeSpec::make_concave_polygon(1e-3, 0.5e-3, 1e-4), {"'concave_polygon.neck_half_width' = 0.0005", "(0, R/2)"}},
      {ShapeSpec::make_concave_polygon(1e-3, 0, 1e-4), {"'concave_polygon.neck_half_width' = 0"}},
      {ShapeSpec::make_concave_polygon(1e-3, 2e-3, 1e-4), {"'concave_polygon.neck_half_width' = 0.002"}},
      {ShapeSpec::make_rectangle(one, o, 0.1), {"'rectangle.hi' = (0, 0, 0)", "in x"}},
      {ShapeSpec::make_box({0, 0, 0}, {1, 1, 0}, 0.1), {"'box.hi' = (1, 1, 0)", "in z"}},
      {ShapeSpec::make_rectangle_minus_rectangle(o, one, {2, 2, 0}, {3, 3, 0}, 0.1),
       {"'rectangle_minus_rectangle.inner_lo' = (2, 2, 0)", "overlap"}},
      {ShapeSpec::make_rectangle_minus_rectangle(o, one, {-1, -1, 0}, {2, 2, 0}, 0.1), {"covers the outer one"}},
  };
  for (const Case& c : cases) {
    const std::string message = shape_error(c.spec, run);
    for (const std::string& part : c.expect) EXPECT_TRUE(contains(message, part)) << message;
  }
  GmshRun bad_version = run;
  bad_version.msh_version = 40;
  EXPECT_TRUE(contains(shape_error(ShapeSpec::make_circle(1, 0.5), bad_version), "'gmsh.msh_version' = 40"));
}

TEST(PdShape, AMeshDirectoryThatCannotBeMadeIsAnOutputError) {
  GmshRun run = fresh_run("pd_shape_no_dir");
  const std::string file = test::write_text_file(run.directory, "a_file", "not a directory\n");
  run.directory = file + "/meshes";
  try {
    mesh_shape(ShapeSpec::make_circle(1e-3, 2e-4), run);
    ADD_FAILURE() << "no OutputError";
  } catch (const OutputError& e) {
    EXPECT_TRUE(contains(e.what(), "gmsh.directory")) << e.what();
    EXPECT_TRUE(contains(e.what(), run.directory)) << e.what();
  }
}

}  // namespace
}  // namespace debris
