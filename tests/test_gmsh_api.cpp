// Mesh files in formats debris's own reader does not read (binary MSH, MSH 4.0) go through Gmsh's API and
// give the mesh the ASCII file gives, node for node; Gmsh's own errors come back as input errors naming
// the file; the formats the own reader knows stay with it (its errors name the line).
#include <gmsh.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "core/error.hpp"
#include "core/io/gmsh_msh.hpp"
#include "scenarios/common/peridem/gmsh_api.hpp"
#include "tests/cli_helpers.hpp"

namespace debris {
namespace {

namespace fs = std::filesystem;
using test::contains;

const std::string kData = std::string(DEBRIS_SOURCE_DIR) + "/scenarios/peridem/data";

/// `from` written again by Gmsh with the given options (version, binary) as `name` in `dir`.
std::string rewrite(const std::string& from, const fs::path& dir, const std::string& name, double version,
                    bool binary) {
  const std::string to = (dir / name).string();
  with_gmsh("test", from, [&] {
    gmsh::open(from);
    gmsh::option::setNumber("Mesh.MshFileVersion", version);
    gmsh::option::setNumber("Mesh.Binary", binary ? 1 : 0);
    gmsh::write(to);
    gmsh::option::setNumber("Mesh.Binary", 0);
  });
  return to;
}

void expect_same_mesh(const SimplexMesh& a, const SimplexMesh& b, const std::string& what) {
  ASSERT_EQ(a.dimension, b.dimension) << what;
  ASSERT_EQ(a.nodes.size(), b.nodes.size()) << what;
  EXPECT_EQ(a.node_tag, b.node_tag) << what;
  for (std::size_t i = 0; i < a.nodes.size(); ++i) {
    EXPECT_EQ(a.nodes[i].x, b.nodes[i].x) << what << " node " << i;
    EXPECT_EQ(a.nodes[i].y, b.nodes[i].y) << what << " node " << i;
    EXPECT_EQ(a.nodes[i].z, b.nodes[i].z) << what << " node " << i;
  }
  EXPECT_EQ(a.triangles, b.triangles) << what;
  EXPECT_EQ(a.tetrahedra, b.tetrahedra) << what;
}

TEST(GmshApi, BinaryAndMsh40FilesReadThroughGmshEqualTheAsciiFile) {
  ASSERT_TRUE(gmsh_api_available());
  const fs::path dir = test::fresh_directory("debris_gmsh_api_formats");
  for (const char* file : {"two_particle_concave_hex/mesh_particle_1_0.msh", "compressive_n500/mesh_rigid_wall_0.msh"}) {
    const std::string ascii = kData + "/" + file;
    const SimplexMesh ours = read_gmsh_msh(ascii);
    const SimplexMesh binary = read_mesh_file(rewrite(ascii, dir, "binary41.msh", 4.1, true));
    expect_same_mesh(binary, ours, std::string(file) + " as binary MSH 4.1");
    const SimplexMesh v40 = read_mesh_file(rewrite(ascii, dir, "ascii40.msh", 4.0, false));
    expect_same_mesh(v40, ours, std::string(file) + " as MSH 4.0");
    const SimplexMesh binary22 = read_mesh_file(rewrite(ascii, dir, "binary22.msh", 2.2, true));
    expect_same_mesh(binary22, ours, std::string(file) + " as binary MSH 2.2");
  }
}

TEST(GmshApi, TetrahedraOfABinaryFileAndTheirBoundaryTrianglesDropped) {
  // A 3D mesh written with its boundary triangles (physical groups of both dimensions): only the
  // tetrahedra make the grain, as with the own reader.
  const fs::path dir = test::fresh_directory("debris_gmsh_api_tets");
  const std::string geo = test::write_text_file(dir, "cube.geo",
                                                "SetFactory(\"OpenCASCADE\");\nBox(1) = {0, 0, 0, 1, 1, 1};\n"
                                                "Physical Volume(1) = {1};\nPhysical Surface(2) = {1, 2, 3, 4, 5, 6};\n"
                                                "Mesh.CharacteristicLengthMax = 0.5;\n");
  const std::string ascii = (dir / "cube22.msh").string();
  with_gmsh("test", geo, [&] {
    gmsh::open(geo);
    gmsh::model::mesh::generate(3);
    gmsh::option::setNumber("Mesh.MshFileVersion", 2.2);
    gmsh::write(ascii);
  });
  // The binary file is written from the ASCII one, so both hold the same (16-digit) coordinates.
  const SimplexMesh a = read_gmsh_msh(ascii), b = read_mesh_file(rewrite(ascii, dir, "cube41b.msh", 4.1, true));
  EXPECT_EQ(a.dimension, 3);
  EXPECT_TRUE(a.triangles.empty());
  EXPECT_GT(a.tetrahedra.size(), 6u);
  expect_same_mesh(b, a, "cube");
}

TEST(GmshApi, GmshErrorsNameTheFileAndOwnFormatsKeepTheirLineNumbers) {
  const fs::path dir = test::fresh_directory("debris_gmsh_api_errors");
  // A binary MSH cut off after its header: Gmsh fails, the error names the file and quotes Gmsh.
  const std::string cut = test::write_text_file(dir, "cut.msh", "$MeshFormat\n4.1 1 8\n");
  try {
    read_mesh_file(cut);
    ADD_FAILURE() << "no InputError for " << cut;
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_TRUE(contains(m, "'mesh file' = " + cut)) << m;
    EXPECT_TRUE(contains(m, "Gmsh failed")) << m;
  }
  // ASCII 2.2 with a bad number: the own reader's error, with its line.
  const std::string bad =
      test::write_text_file(dir, "bad.msh", "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n1\n1 0.5 abc 0\n$EndNodes\n");
  try {
    read_mesh_file(bad);
    ADD_FAILURE() << "no InputError for " << bad;
  } catch (const InputError& e) {
    EXPECT_TRUE(contains(e.what(), "line 6")) << e.what();
    EXPECT_TRUE(contains(e.what(), "'abc'")) << e.what();
  }
  // A missing file: the own reader's "cannot be opened", not Gmsh's silent empty model.
  try {
    read_mesh_file((dir / "absent.vtk").string());
    ADD_FAILURE() << "no InputError for a missing file";
  } catch (const InputError& e) {
    EXPECT_TRUE(contains(e.what(), "cannot be opened")) << e.what();
  }
}

}  // namespace
}  // namespace debris
