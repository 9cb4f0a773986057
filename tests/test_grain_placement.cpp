// PeriDEM's particle lists and grain placement: the 502-grain compressive test loaded from its own meshes and
// CSV (the node counts its README states), grains as scaled, rotated, moved copies of the reference mesh
// (centroid, volume, shape), PeriDEM's grain order, permanent ids, walls, and the errors.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <set>
#include <sstream>
#include <string>

#include "core/error.hpp"
#include "scenarios/common/peridem/grain_placement.hpp"
#include "core/io/gmsh_msh.hpp"
#include "core/io/grain_csv.hpp"
#include "scenarios/common/peridem/nodal_volume.hpp"
#include "tests/cli_helpers.hpp"

namespace debris {
namespace {

namespace fs = std::filesystem;

const std::string kData = std::string(DEBRIS_SOURCE_DIR) + "/scenarios/peridem/data";

fs::path scratch(const std::string& name) { return debris::test::fresh_directory("debris_pd_" + name); }

using test::contains;

std::string csv_error(const std::string& path) {
  try {
    read_grain_csv(path);
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no InputError reading " << path;
  return "";
}

/// compressive_n500's zones: Zone_1 circle and Zone_2 hexagon, both with Parameters[0] = R_ref = 1e-3.
std::vector<ReferenceGrain> compressive_zones() {
  const std::string dir = kData + "/compressive_n500/";
  return {make_reference_grain(read_gmsh_msh(dir + "mesh_particle_1_0.msh"), 1e-3, 0, "zone 1 mesh"),
          make_reference_grain(read_gmsh_msh(dir + "mesh_particle_2_0.msh"), 1e-3, 0, "zone 2 mesh")};
}

using test::sum;

// ---------------------------------------------------------------------------------------------------------

TEST(PdGrainCsv, ReadsPeriDEMsParticleList) {
  const std::string path = kData + "/compressive_n500/particle_locations_0.csv";
  const std::vector<GrainRecord> g = read_grain_csv(path);
  // One record per line after the header, values as written.
  std::ifstream in(path);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);)
    if (!line.empty()) lines.push_back(line);
  ASSERT_EQ(g.size(), lines.size() - 1);
  ASSERT_EQ(g.size(), 502u);  // the README's 502 particles
  for (std::size_t k = 0; k < g.size(); k += 97) {
    std::istringstream s(lines[k + 1]);
    int zone;
    char comma;
    double x, y, z, r, o;
    s >> zone >> comma >> x >> comma >> y >> comma >> z >> comma >> r >> comma >> o;
    EXPECT_EQ(g[k].zone, zone);
    EXPECT_EQ(g[k].x, x);
    EXPECT_EQ(g[k].y, y);
    EXPECT_EQ(g[k].z, z);
    EXPECT_EQ(g[k].radius, r);
    EXPECT_EQ(g[k].orientation, o);
  }
}

TEST(PdGrainCsv, ErrorsNameTheFileTheLineAndTheColumn) {
  const fs::path dir = scratch("pd_grain_csv_errors");
  const std::string header = "i, x, y, z, r, o\n";
  struct Case {
    const char* name;
    std::string text;
    std::vector<std::string> expect;
  };
  const std::vector<Case> cases = {
      {"locrad.csv", "i, x, y, z, r\n0, 0, 0, 0, 1\n", {"orientation column 'o'", "line 1"}},
      {"header.csv", "zone, x, y, z, r, o\n", {"expected the header", "line 1"}},
      {"empty.csv", "", {"is empty"}},
      {"columns.csv", header + "0, 1, 2, 3, 4\n", {"expected 6 comma-separated values", "line 2"}},
      {"radius.csv", header + "0, 1, 2, 3, 4, 5\n1, 1, 2, 3, 0, 5\n", {"'r' = '0'", "radius must be > 0", "line 3"}},
      {"number.csv", header + "0, 1, 2x, 3, 4, 5\n", {"'y' = '2x'", "not a finite number", "line 2"}},
      {"nan.csv", header + "0, 1, 2, nan, 4, 5\n", {"'z' = 'nan'", "line 2"}},
      {"zone.csv", header + "-1, 1, 2, 3, 4, 5\n", {"'i' = '-1'", "line 2"}},
      {"zonefraction.csv", header + "1.5, 1, 2, 3, 4, 5\n", {"'i' = '1.5'", "whole number"}},
  };
  for (const Case& c : cases) {
    const std::string path = test::write_text_file(dir, c.name, c.text);
    const std::string message = csv_error(path);
    EXPECT_TRUE(contains(message, path)) << c.name << ": " << message;
    for (const std::string& part : c.expect) EXPECT_TRUE(contains(message, part)) << c.name << ": " << message;
  }
  EXPECT_TRUE(contains(csv_error((dir / "absent.csv").string()), "cannot be opened"));
}

TEST(PdGrainPlacement, CompressiveTestHasTheREADMEsNodeCounts) {
  const std::vector<ReferenceGrain> zones = compressive_zones();
  // R_ref = the deck's Parameters[0] is the reference mesh's circumradius (its farthest node from the origin).
  for (const ReferenceGrain& z : zones) {
    double far = 0;
    for (const Vec3& p : z.mesh.nodes) far = std::max(far, norm(p));
    EXPECT_NEAR(far, z.radius, 1e-15);
  }
  const std::vector<GrainRecord> records = read_grain_csv(kData + "/compressive_n500/particle_locations_0.csv");
  PdNodes nodes;
  PdGrains grains;
  place_grains(zones, records, nodes, grains);
  EXPECT_EQ(grains.size(), 502u);
  EXPECT_EQ(nodes.size(), 57394u);  // README: 57,394 nodes in particles
  const int rigid =
      append_wall(read_gmsh_msh(kData + "/compressive_n500/mesh_rigid_wall_0.msh"), 1, nodes, grains, "rigid wall");
  const int moving =
      append_wall(read_gmsh_msh(kData + "/compressive_n500/mesh_moving_wall_0.msh"), 1, nodes, grains, "moving wall");
  EXPECT_EQ(nodes.size(), 62994u);  // README: 62,994 nodes with the walls
  // The deck's Displacement_BC fixes particle 502 and moves particle 503: PeriDEM numbers the grains from 0
  // and the walls after them, so the walls must be grains 502 and 503 here too.
  EXPECT_EQ(rigid, 502);
  EXPECT_EQ(moving, 503);
  EXPECT_EQ(grains.kind[rigid], static_cast<int>(PdGrainKind::wall));
  EXPECT_EQ(grains.material[moving], 1);

  // PeriDEM's order: the 366 circles (zone 0) in file order, then the hexagons.
  std::size_t g = 0;
  for (int zone : {0, 1})
    for (const GrainRecord& r : records)
      if (r.zone == zone) {
        const ReferenceGrain& ref = zones[static_cast<std::size_t>(zone)];
        ASSERT_EQ(static_cast<std::size_t>(grains.node_end[g] - grains.node_begin[g]), ref.mesh.nodes.size());
        const double s = r.radius / ref.radius;
        EXPECT_NEAR(grains.volume[g], sum(ref.volume) * s * s, 1e-13 * grains.volume[g]) << "grain " << g;
        EXPECT_EQ(grains.kind[g], static_cast<int>(PdGrainKind::particle));
        ++g;
      }

  // Grains contiguous and in order, each node's grain right, ids 1..N, volumes summing to the grain volume.
  int expected_begin = 0;
  for (std::size_t k = 0; k < grains.size(); ++k) {
    EXPECT_EQ(grains.node_begin[k], expected_begin);
    expected_begin = grains.node_end[k];
    double v = 0;
    for (int i = grains.node_begin[k]; i < grains.node_end[k]; ++i) {
      ASSERT_EQ(nodes.grain[i], static_cast<int>(k));
      v += nodes.volume[i];
    }
    EXPECT_EQ(grains.volume[k], v);
  }
  EXPECT_EQ(static_cast<std::size_t>(expected_begin), nodes.size());
  for (std::size_t i = 0; i < nodes.size(); ++i) ASSERT_EQ(nodes.id[i], static_cast<std::int64_t>(i) + 1);
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    ASSERT_EQ(nodes.x0[i], nodes.x[i]);
    ASSERT_EQ(nodes.y0[i], nodes.y[i]);
  }
  // The walls are the meshes placed as is: the container's first node is its corner.
  EXPECT_EQ(nodes.x[grains.node_begin[rigid]], -0.00082);
  EXPECT_EQ(nodes.y[grains.node_begin[rigid]], -0.00082);
}

TEST(PdGrainPlacement, RotatedScaledGrainKeepsCentroidVolumeAndShape) {
  const std::vector<ReferenceGrain> zones = compressive_zones();
  const ReferenceGrain& hex = zones[1];  // vertex (R_ref, 0) is node 2, the centre node 1
  GrainRecord r;
  r.zone = 1;
  r.x = 0.031;
  r.y = -0.007;
  r.z = 0.002;
  r.radius = 1.3e-3;
  r.orientation = 2.1;
  PdNodes nodes;
  PdGrains grains;
  const int g = place_grain(hex, r, nodes, grains);
  const double s = r.radius / hex.radius;
  // Volume scaled by s^2 (2D); centroid at (x, y): the hexagon's first moment is zero (see PdMeshVolume).
  EXPECT_NEAR(grains.volume[g], sum(hex.volume) * s * s, 1e-14 * grains.volume[g]);
  EXPECT_NEAR(grains.volume[g], 1.5 * std::sqrt(3.0) * r.radius * r.radius, 1e-12 * grains.volume[g]);
  EXPECT_NEAR(grains.cx[g], r.x, 1e-15);
  EXPECT_NEAR(grains.cy[g], r.y, 1e-15);
  EXPECT_EQ(grains.cz[g], r.z);
  // The centre node at (x, y, z); the vertex (R_ref, 0) at the centre + r (cos o, sin o): counter-clockwise.
  EXPECT_NEAR(nodes.x[0], r.x, 1e-18);
  EXPECT_NEAR(nodes.y[0], r.y, 1e-18);
  EXPECT_NEAR(nodes.x[1], r.x + r.radius * std::cos(r.orientation), 1e-15);
  EXPECT_NEAR(nodes.y[1], r.y + r.radius * std::sin(r.orientation), 1e-15);
  // A similarity: every distance scaled by s, every node volume by s^2.
  for (std::size_t k = 0; k < hex.mesh.nodes.size(); ++k) {
    const Vec3 p{nodes.x[k] - nodes.x[1], nodes.y[k] - nodes.y[1], nodes.z[k] - nodes.z[1]};
    EXPECT_NEAR(norm(p), s * norm(hex.mesh.nodes[k] - hex.mesh.nodes[1]), 1e-15);
    EXPECT_NEAR(nodes.volume[k], hex.volume[k] * s * s, 1e-15 * nodes.volume[k]);
    EXPECT_EQ(nodes.z[k], r.z);
  }
}

TEST(PdGrainPlacement, ThreeDimensionalGrainRotatesAboutZAndScalesVolumeByCube) {
  SimplexMesh tet;
  tet.dimension = 3;
  tet.nodes = {{0, 0, 0}, {2, 0, 0}, {0, 2, 0}, {0, 0, 2}};
  tet.tetrahedra = {{0, 1, 2, 3}};
  const ReferenceGrain ref = make_reference_grain(tet, 2.0, 3, "tetrahedron");
  GrainRecord r;
  r.x = 1;
  r.y = 2;
  r.z = 3;
  r.radius = 0.5;  // s = 1/4
  r.orientation = std::numbers::pi / 2;
  PdNodes nodes;
  PdGrains grains;
  place_grain(ref, r, nodes, grains);
  EXPECT_NEAR(grains.volume[0], (8.0 / 6.0) / 64.0, 1e-16);
  EXPECT_EQ(grains.material[0], 3);
  // Quarter turn about z, then s: (2, 0, 0) -> (0, 0.5, 0), (0, 2, 0) -> (-0.5, 0, 0), (0, 0, 2) -> (0, 0, 0.5).
  EXPECT_NEAR(nodes.x[1], 1.0, 1e-16);
  EXPECT_NEAR(nodes.y[1], 2.5, 1e-16);
  EXPECT_NEAR(nodes.x[2], 0.5, 1e-16);
  EXPECT_NEAR(nodes.y[2], 2.0, 1e-16);
  EXPECT_NEAR(nodes.z[3], 3.5, 1e-16);
  EXPECT_NEAR(nodes.x[3], 1.0, 1e-16);
}

TEST(PdGrainPlacement, IdsContinueAndBadZonesAreErrors) {
  const std::vector<ReferenceGrain> zones = compressive_zones();
  PdNodes nodes;
  PdGrains grains;
  append_wall(read_gmsh_msh(kData + "/compressive_n500/mesh_moving_wall_0.msh"), 0, nodes, grains, "plate");
  const std::size_t wall_nodes = nodes.size();
  GrainRecord r;
  r.radius = 1e-3;
  place_grains(zones, {r}, nodes, grains);
  EXPECT_EQ(nodes.id[wall_nodes], static_cast<std::int64_t>(wall_nodes) + 1);
  EXPECT_EQ(grains.node_begin[1], static_cast<int>(wall_nodes));

  GrainRecord bad = r;
  bad.zone = 2;
  const std::size_t before = nodes.size();
  try {
    place_grains(zones, {r, bad}, nodes, grains);
    ADD_FAILURE() << "no InputError for zone 2";
  } catch (const InputError& e) {
    EXPECT_TRUE(contains(e.what(), "'grain 1 zone' = 2")) << e.what();
    EXPECT_TRUE(contains(e.what(), "2 zones given")) << e.what();
  }
  EXPECT_EQ(nodes.size(), before);  // nothing placed
  try {
    make_reference_grain(zones[0].mesh, 0.0, 0, "zone 1 mesh");
    ADD_FAILURE() << "no InputError for R_ref = 0";
  } catch (const InputError& e) {
    EXPECT_TRUE(contains(e.what(), "'zone 1 mesh reference radius' = 0")) << e.what();
  }
}

}  // namespace
}  // namespace debris
