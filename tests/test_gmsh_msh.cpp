// Gmsh MSH reading (2.2 and 4.1) and the nodal volumes of eq 31, on PeriDEM's own meshes and on
// handwritten files: areas against the exact polygon areas, the first moment against the exact centroid,
// and errors that name the file and the line.
#include <gmsh.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <set>
#include <sstream>
#include <string>

#include "core/error.hpp"
#include "core/io/gmsh_msh.hpp"
#include "scenarios/common/peridem/gmsh_api.hpp"
#include "scenarios/common/peridem/nodal_volume.hpp"
#include "tests/cli_helpers.hpp"

namespace debris {
namespace {

namespace fs = std::filesystem;

const std::string kData = std::string(DEBRIS_SOURCE_DIR) + "/scenarios/peridem/data";

fs::path scratch(const std::string& name) { return debris::test::fresh_directory("debris_pd_" + name); }

std::string read_error(const std::string& path) {
  try {
    read_gmsh_msh(path);
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no InputError reading " << path;
  return "";
}

using test::contains;

using test::sum;

/// The mesh's area by the divergence theorem: the shoelace sum over the boundary edges (edges of one
/// triangle only), each directed as in its counter-clockwise triangle. Independent of eq 31's element sums.
double boundary_area(const SimplexMesh& m) {
  std::map<std::pair<int, int>, int> count;
  std::vector<std::pair<int, int>> directed;
  for (auto t : m.triangles) {
    const Vec3 a = m.nodes[t[0]], b = m.nodes[t[1]], c = m.nodes[t[2]];
    if (cross(b - a, c - a).z < 0) std::swap(t[1], t[2]);
    for (int k = 0; k < 3; ++k) {
      const int i = t[k], j = t[(k + 1) % 3];
      directed.push_back({i, j});
      ++count[{std::min(i, j), std::max(i, j)}];
    }
  }
  double area = 0;
  for (const auto& [i, j] : directed)
    if (count[{std::min(i, j), std::max(i, j)}] == 1)
      area += 0.5 * (m.nodes[i].x * m.nodes[j].y - m.nodes[j].x * m.nodes[i].y);
  return area;
}

/// Element lines of a given Gmsh type in an MSH 2.2 file, counted from the text itself.
long count_elements_22(const std::string& path, int type) {
  std::ifstream in(path);
  long n = 0;
  bool inside = false;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("$Elements", 0) == 0) {
      inside = true;
      std::getline(in, line);  // the count
      continue;
    }
    if (line.rfind("$EndElements", 0) == 0) inside = false;
    if (!inside) continue;
    std::istringstream s(line);
    int number = 0, t = 0;
    s >> number >> t;
    n += t == type;
  }
  return n;
}

// ---------------------------------------------------------------------------------------------------------

TEST(PdMeshMsh, ReadsPeriDEMCircleMsh22) {
  const std::string path = kData + "/compressive_n500/mesh_particle_1_0.msh";
  const SimplexMesh m = read_gmsh_msh(path);
  EXPECT_EQ(m.dimension, 2);
  // PeriDEM's circle: 123 nodes (the README), the triangles of the file; its points and lines are skipped.
  ASSERT_EQ(m.nodes.size(), 123u);
  EXPECT_EQ(static_cast<long>(m.triangles.size()), count_elements_22(path, 2));
  EXPECT_GT(count_elements_22(path, 1), 0);   // there were lines to skip
  EXPECT_GT(count_elements_22(path, 15), 0);  // and points
  EXPECT_TRUE(m.tetrahedra.empty());
  for (std::size_t i = 0; i < m.nodes.size(); ++i) EXPECT_EQ(m.node_tag[i], static_cast<std::int64_t>(i) + 1);
  // Node 1 is the embedded centre, node 2 the point (R, 0) of the script.
  EXPECT_EQ(m.nodes[0].x, 0.0);
  EXPECT_EQ(m.nodes[0].y, 0.0);
  EXPECT_EQ(m.nodes[1].x, 0.001);
  for (const auto& t : m.triangles)
    for (int k : t) ASSERT_TRUE(k >= 0 && k < 123);
}

TEST(PdMeshMsh, Msh41FromGmshEqualsMsh22OfTheSameMesh) {
  // One .geo of PeriDEM's (the concave drum), meshed once by Gmsh's API and written in both formats: the
  // node tags, coordinates and triangles must be the same whichever format carried them (4.1 orders nodes
  // by entity block, 2.2 by tag).
  const fs::path dir = scratch("pd_mesh_msh41");
  // The script sets Mesh.MshFileVersion = 2.2, which would override -format: drop that line.
  std::string script;
  {
    std::ifstream in(kData + "/two_particle_concave_hex/mesh_particle_1_0.geo");
    for (std::string line; std::getline(in, line);)
      if (line.find("MshFileVersion") == std::string::npos) script += line + "\n";
  }
  ASSERT_TRUE(contains(script, "Point{1} In Surface {1}"));
  const std::string geo = test::write_text_file(dir, "drum.geo", script);
  with_gmsh("test", geo, [&] {
    gmsh::open(geo);
    gmsh::model::mesh::generate(2);
    for (const double version : {2.2, 4.1}) {
      gmsh::option::setNumber("Mesh.MshFileVersion", version);
      gmsh::write((dir / (version == 2.2 ? "msh22.msh" : "msh41.msh")).string());
    }
  });
  const SimplexMesh a = read_gmsh_msh((dir / "msh22.msh").string());
  const SimplexMesh b = read_gmsh_msh((dir / "msh41.msh").string());
  {
    std::ifstream in(dir / "msh41.msh");
    std::string first, version;
    std::getline(in, first);
    std::getline(in, version);
    ASSERT_EQ(version.substr(0, 3), "4.1");
  }
  ASSERT_EQ(a.nodes.size(), b.nodes.size());
  ASSERT_EQ(a.triangles.size(), b.triangles.size());
  std::map<std::int64_t, Vec3> by_tag;
  for (std::size_t i = 0; i < a.nodes.size(); ++i) by_tag[a.node_tag[i]] = a.nodes[i];
  for (std::size_t i = 0; i < b.nodes.size(); ++i) {
    ASSERT_EQ(by_tag.count(b.node_tag[i]), 1u);
    const Vec3 p = by_tag[b.node_tag[i]];
    EXPECT_EQ(p.x, b.nodes[i].x);
    EXPECT_EQ(p.y, b.nodes[i].y);
    EXPECT_EQ(p.z, b.nodes[i].z);
  }
  auto tag_triangles = [](const SimplexMesh& m) {
    std::set<std::array<std::int64_t, 3>> s;
    for (const auto& t : m.triangles) s.insert({m.node_tag[t[0]], m.node_tag[t[1]], m.node_tag[t[2]]});
    return s;
  };
  EXPECT_EQ(tag_triangles(a), tag_triangles(b));
  // And the same mesh as the one PeriDEM shipped (made by the same script).
  EXPECT_EQ(a.nodes.size(), read_gmsh_msh(kData + "/two_particle_concave_hex/mesh_particle_1_0.msh").nodes.size());
}

TEST(PdMeshMsh, Msh41BlocksWithGappedTagsAndParametricNodes) {
  // Two triangles on the unit square; tags 7, 10, 20, 35 (not contiguous), one node block parametric (a node on
  // a curve carries u), a line element and a point element to skip.
  const fs::path dir = scratch("pd_mesh_msh41_hand");
  const std::string path = test::write_text_file(dir, "square41.msh", R"($MeshFormat
4.1 0 8
$EndMeshFormat
$Entities
0 0 1 0
1 0 0 0 1 1 0 0 0
$EndEntities
$Nodes
3 4 7 35
0 1 0 1
35
1 1 0
1 2 1 1
20
1 0 0 0.5
2 1 0 2
10
7
0 0 0
0 1 0
$EndNodes
$Elements
3 4 1 4
0 1 15 1
1 35
1 2 1 1
2 10 20
2 1 2 2
3 10 20 35
4 10 35 7
$EndElements
)");
  const SimplexMesh m = read_gmsh_msh(path);
  ASSERT_EQ(m.dimension, 2);
  ASSERT_EQ(m.nodes.size(), 4u);
  EXPECT_EQ(m.node_tag, (std::vector<std::int64_t>{35, 20, 10, 7}));
  EXPECT_EQ(m.nodes[1].x, 1.0);  // tag 20 at (1, 0); its parametric u = 0.5 is not a coordinate
  EXPECT_EQ(m.nodes[1].y, 0.0);
  ASSERT_EQ(m.triangles.size(), 2u);
  EXPECT_EQ(m.triangles[0], (std::array<int, 3>{2, 1, 0}));
  EXPECT_EQ(m.triangles[1], (std::array<int, 3>{2, 0, 3}));
  const std::vector<double> v = nodal_volumes(m, path);
  EXPECT_DOUBLE_EQ(sum(v), 1.0);
}

TEST(PdMeshMsh, TetrahedraIn3DDropTheBoundaryTriangles) {
  const fs::path dir = scratch("pd_mesh_tet");
  const std::string path = test::write_text_file(dir, "tet22.msh", R"($MeshFormat
2.2 0 8
$EndMeshFormat
$PhysicalNames
1
3 1 "v"
$EndPhysicalNames
$Nodes
5
1 0 0 0
2 1 0 0
3 0 1 0
4 0 0 1
5 1 1 1
$EndNodes
$Elements
3
1 2 2 0 1 1 2 3
2 4 2 1 1 1 2 3 4
3 4 2 1 1 2 3 4 5
$EndElements
)");
  const SimplexMesh m = read_gmsh_msh(path);
  EXPECT_EQ(m.dimension, 3);
  EXPECT_TRUE(m.triangles.empty());
  ASSERT_EQ(m.tetrahedra.size(), 2u);
  EXPECT_EQ(m.tetrahedra[1], (std::array<int, 4>{1, 2, 3, 4}));
}

TEST(PdMeshMsh, ErrorsNameTheFileAndTheLine) {
  const fs::path dir = scratch("pd_mesh_errors");
  const std::string head22 = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n";
  const std::string nodes3 = "$Nodes\n3\n1 0 0 0\n2 1 0 0\n3 0 1 0\n$EndNodes\n";
  struct Case {
    const char* name;
    std::string text;
    std::vector<std::string> expect;
  };
  const std::vector<Case> cases = {
      {"binary.msh", "$MeshFormat\n4.1 1 8\n", {"ASCII", "line 2"}},
      {"version.msh", "$MeshFormat\n4.0 0 8\n$EndMeshFormat\n", {"2.2 and 4.1", "'4.0'", "line 2"}},
      {"noformat.msh", "$Nodes\n0\n$EndNodes\n", {"starts with $MeshFormat", "line 1"}},
      {"noelements.msh", head22 + nodes3, {"no $Elements section"}},
      {"nonodes.msh", head22 + "$PhysicalNames\n0\n$EndPhysicalNames\n", {"no $Nodes section"}},
      {"badnumber.msh", head22 + "$Nodes\n1\n1 0.5 abc 0\n$EndNodes\n", {"'abc'", "not a number", "line 6"}},
      {"missingnode.msh",
       head22 + nodes3 + "$Elements\n1\n1 2 0 1 2 9\n$EndElements\n",
       {"'9'", "no node with this tag", "line 12"}},
      {"duplicate.msh", head22 + "$Nodes\n2\n1 0 0 0\n1 1 0 0\n$EndNodes\n", {"duplicate node tag", "line 7"}},
      {"short.msh", head22 + "$Nodes\n3\n1 0 0 0\n2 1 0 0\n$EndNodes\n", {"expected 4 values", "line 8"}},
      {"unterminated.msh", head22 + "$Comments\nhello\n", {"has no $EndComments"}},
      {"quad.msh",
       head22 + nodes3 + "$Elements\n2\n1 2 0 1 2 3\n2 3 0 1 2 3 1\n$EndElements\n",
       {"4-node quadrangle", "only linear triangles", "line 13"}},
      {"nothing.msh", head22 + nodes3 + "$Elements\n1\n1 15 0 1\n$EndElements\n", {"no 3-node triangles"}},
      {"unknown.msh", head22 + nodes3 + "$Elements\n1\n1 77 0 1 2 3\n$EndElements\n", {"'77'", "line 12"}},
      {"count41.msh",
       "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 3 1 3\n2 1 0 2\n1\n2\n0 0 0\n1 0 0\n$EndNodes\n",
       {"blocks hold 2 nodes", "line 5"}},
  };
  for (const Case& c : cases) {
    const std::string path = test::write_text_file(dir, c.name, c.text);
    const std::string message = read_error(path);
    EXPECT_TRUE(contains(message, path)) << c.name << ": " << message;
    for (const std::string& part : c.expect) EXPECT_TRUE(contains(message, part)) << c.name << ": " << message;
  }
  const std::string missing = read_error((dir / "absent.msh").string());
  EXPECT_TRUE(contains(missing, "cannot be opened")) << missing;
}

// ---------------------------------------------------------------------------------------------------------

TEST(PdMeshVolume, OneTriangleAndOneTetrahedron) {
  // Eq 31 with linear hat functions: a third of the triangle's area, a quarter of the tetrahedron's volume.
  SimplexMesh tri;
  tri.dimension = 2;
  tri.nodes = {{0, 0, 0}, {2, 0, 0}, {0, 3, 0}};
  tri.triangles = {{0, 1, 2}};
  for (double v : nodal_volumes(tri, "triangle")) EXPECT_DOUBLE_EQ(v, 1.0);
  SimplexMesh tet;
  tet.dimension = 3;
  tet.nodes = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  tet.tetrahedra = {{0, 2, 1, 3}};  // either orientation
  for (double v : nodal_volumes(tet, "tetrahedron")) EXPECT_DOUBLE_EQ(v, 1.0 / 24.0);
}

TEST(PdMeshVolume, PeriDEMMeshesSumToTheirExactAreas) {
  // The sum of eq 31's volumes is the mesh's area; each mesh's boundary polygon gives that area by the
  // divergence theorem, and for the polygons it is the exact area of the deck's geometry.
  const double R = 1e-3, R15 = 1.5e-3, w = 0.375e-3;
  struct Case {
    std::string file;
    double exact;  // 0: a circle, whose mesh is the inscribed polygon
  };
  const std::vector<Case> cases = {
      {"compressive_n500/mesh_particle_1_0.msh", 0},
      {"compressive_n500/mesh_particle_2_0.msh", 1.5 * std::sqrt(3.0) * R * R},
      {"compressive_n500/mesh_rigid_wall_0.msh",
       (6.932e-2 + 8.2e-4) * (4.182e-2 + 8.2e-4) - (6.872e-2 + 2.2e-4) * (4.182e-2 + 2.2e-4)},
      {"compressive_n500/mesh_moving_wall_0.msh", (6.872e-2 + 2.2e-4) * (4.182e-2 - 4.122e-2)},
      {"two_particle_concave_hex/mesh_particle_1_0.msh", std::sqrt(3.0) * R15 * (0.5 * R15 + w)},
      {"two_particle_circ_example/mesh_cir_1_0.msh", 0},
      {"compressive_small_set_ci/mesh_drum2d_small_0.msh", std::sqrt(3.0) * R * (0.5 * R + 0.2e-3)},
      {"compressive_small_set_ci/mesh_tri_small_0.msh", 0.75 * std::sqrt(3.0) * R * R},
      {"compressive_small_set_ci/mesh_fixed_container_0.msh", 12.6e-3 * 8.6e-3 - 12e-3 * 8.3e-3},
  };
  for (const Case& c : cases) {
    const SimplexMesh m = read_gmsh_msh(kData + "/" + c.file);
    const std::vector<double> v = nodal_volumes(m, c.file);
    const double total = sum(v);
    EXPECT_NEAR(total, boundary_area(m), 1e-12 * total) << c.file;
    if (c.exact > 0) {
      EXPECT_NEAR(total, c.exact, 1e-12 * c.exact) << c.file;
    } else {
      // A circle of radius R: its boundary nodes lie on the circle and the mesh is the inscribed polygon,
      // smaller than pi R^2 by about (2 pi / N)^2 / 6 for N sides of length h (0.7% for h = R / 5).
      const double circle = std::numbers::pi * R * R;
      EXPECT_LT(total, circle) << c.file;
      EXPECT_GT(total, 0.98 * circle) << c.file;
    }
  }
}

TEST(PdMeshVolume, FirstMomentIsTheExactCentroid) {
  // With linear hat functions, sum_i phi_i(x) x_i = x, so eq 31's volumes give sum_i V_i x_i = integral of
  // x over the mesh: for PeriDEM's hexagon and concave polygon, centred at the origin, zero to round-off.
  // A volume share that is not eq 31 (e.g. by the angle at each vertex) would miss this.
  for (const char* file :
       {"compressive_n500/mesh_particle_2_0.msh", "two_particle_concave_hex/mesh_particle_1_0.msh"}) {
    const SimplexMesh m = read_gmsh_msh(kData + "/" + file);
    const std::vector<double> v = nodal_volumes(m, file);
    double mx = 0, my = 0, scale = 0;
    for (std::size_t i = 0; i < v.size(); ++i) {
      mx += v[i] * m.nodes[i].x;
      my += v[i] * m.nodes[i].y;
      scale += v[i] * norm(m.nodes[i]);
    }
    EXPECT_LT(std::abs(mx), 1e-14 * scale) << file;
    EXPECT_LT(std::abs(my), 1e-14 * scale) << file;
  }
}

TEST(PdMeshVolume, NodeInNoElementIsAnError) {
  const fs::path dir = scratch("pd_mesh_orphan");
  const std::string path = test::write_text_file(dir, "orphan.msh", R"($MeshFormat
2.2 0 8
$EndMeshFormat
$Nodes
4
1 0 0 0
2 1 0 0
3 0 1 0
17 5 5 0
$EndNodes
$Elements
2
1 15 2 0 1 17
2 2 2 0 1 1 2 3
$EndElements
)");
  const SimplexMesh m = read_gmsh_msh(path);
  try {
    nodal_volumes(m, path);
    ADD_FAILURE() << "no InputError for the orphan node";
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_TRUE(contains(message, path)) << message;
    EXPECT_TRUE(contains(message, "tag 17")) << message;
    EXPECT_TRUE(contains(message, "belongs to no triangle")) << message;
  }
}

}  // namespace
}  // namespace debris
