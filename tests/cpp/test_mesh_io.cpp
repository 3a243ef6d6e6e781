// Tests of the mesh writers and readers (mesh_io.h): exact round trips through every format that has a reader,
// the Abaqus file's sets, Gmsh 2.2 input, error reports with file and line, and atomic writes (a failed write
// leaves an existing file untouched and no temporary behind).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "atomic_file.h"
#include "qualmesh/error.h"
#include "qualmesh/mesh_io.h"
#include "qualmesh/quality.h"
#include "sample_meshes.h"
#include "test_support.h"

namespace qualmesh {
namespace {

namespace fs = std::filesystem;

using test::slurp;
using test::write_text;

void expect_same_volume_mesh(const TetMesh& a, const TetMesh& b) {
  ASSERT_EQ(a.points.size(), b.points.size());
  for (std::size_t i = 0; i < a.points.size(); ++i) EXPECT_EQ(a.points[i], b.points[i]) << "point " << i;
  ASSERT_EQ(a.tets.size(), b.tets.size());
  for (std::size_t t = 0; t < a.tets.size(); ++t) EXPECT_EQ(a.tets[t], b.tets[t]) << "tet " << t;
  EXPECT_EQ(a.tet_region, b.tet_region);
}

void expect_same_faces(const TetMesh& a, const TetMesh& b) {
  EXPECT_EQ(a.faces, b.faces);
  EXPECT_EQ(a.face_marker, b.face_marker);
  EXPECT_EQ(b.face_facet, std::vector<int>(b.faces.size(), -1));
}

TEST(MeshIo, FormatsByExtension) {
  EXPECT_EQ(mesh_format_from_path("a/b.vtu"), MeshFormat::Vtu);
  EXPECT_EQ(mesh_format_from_path("b.node"), MeshFormat::TetGen);
  EXPECT_EQ(mesh_format_from_path("b.1.ele"), MeshFormat::TetGen);
  EXPECT_EQ(mesh_format_from_path("b.MSH"), MeshFormat::Gmsh41);
  EXPECT_EQ(mesh_format_from_path("b.mesh"), MeshFormat::Medit);
  EXPECT_EQ(mesh_format_from_path("b.inp"), MeshFormat::Abaqus);
  EXPECT_TRUE(is_mesh_path("x.vtu"));
  EXPECT_FALSE(is_mesh_path("x.off"));
  try {
    mesh_format_from_path("x.stl");
    FAIL() << "no exception";
  } catch (const InputError& e) {
    EXPECT_EQ(e.code(), ErrorCode::Unsupported);
  }
}

TEST(MeshIo, VtuRoundTrip) {
  const auto dir = test::temp_dir("io-vtu");
  const TetMesh mesh = sample_mesh();
  write_tet_mesh(mesh, (dir / "m.vtu").string());
  const TetMesh back = read_tet_mesh((dir / "m.vtu").string());
  expect_same_volume_mesh(mesh, back);
  const std::string text = slurp(dir / "m.vtu");
  EXPECT_NE(text.find("Name=\"min_dihedral_deg\""), std::string::npos);
  EXPECT_NE(text.find("Name=\"radius_edge\""), std::string::npos);
}

TEST(MeshIo, TetGenRoundTrip) {
  const auto dir = test::temp_dir("io-tetgen");
  const TetMesh mesh = sample_mesh();
  write_tet_mesh(mesh, (dir / "m.1.ele").string());
  EXPECT_TRUE(fs::exists(dir / "m.1.node"));
  EXPECT_TRUE(fs::exists(dir / "m.1.face"));
  for (const char* ext : {".ele", ".node"}) {
    const TetMesh back = read_tet_mesh((dir / ("m.1" + std::string(ext))).string());
    expect_same_volume_mesh(mesh, back);
    expect_same_faces(mesh, back);
  }
}

TEST(MeshIo, GmshRoundTrip) {
  const auto dir = test::temp_dir("io-gmsh");
  const TetMesh mesh = sample_mesh();
  write_tet_mesh(mesh, (dir / "m.msh").string());
  const TetMesh back = read_tet_mesh((dir / "m.msh").string());
  expect_same_volume_mesh(mesh, back);
  expect_same_faces(mesh, back);
  const std::string text = slurp(dir / "m.msh");
  EXPECT_NE(text.find("3 7 \"Solid7\""), std::string::npos);
  EXPECT_NE(text.find("2 4 \"Face4\""), std::string::npos);
}

TEST(MeshIo, MeditRoundTrip) {
  const auto dir = test::temp_dir("io-medit");
  const TetMesh mesh = sample_mesh();
  write_tet_mesh(mesh, (dir / "m.mesh").string());
  const TetMesh back = read_tet_mesh((dir / "m.mesh").string());
  expect_same_volume_mesh(mesh, back);
  expect_same_faces(mesh, back);
}

TEST(MeshIo, AbaqusHasSets) {
  const auto dir = test::temp_dir("io-abaqus");
  write_tet_mesh(sample_mesh(), (dir / "m.inp").string());
  const std::string text = slurp(dir / "m.inp");
  EXPECT_NE(text.find("*ELEMENT, TYPE=C3D4, ELSET=Solid1"), std::string::npos);
  EXPECT_NE(text.find("*ELEMENT, TYPE=C3D4, ELSET=Solid7"), std::string::npos);
  EXPECT_NE(text.find("*SURFACE, NAME=Face6, TYPE=ELEMENT"), std::string::npos);
  EXPECT_NE(text.find("*NSET, NSET=Face6"), std::string::npos);
  EXPECT_NE(text.find("*NODE, NSET=NALL"), std::string::npos);
}

TEST(MeshIo, ReadsGmsh22) {
  const auto dir = test::temp_dir("io-gmsh22");
  write_text(dir / "t.msh",
             "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n1\n3 5 \"Region9\"\n$EndPhysicalNames\n"
             "$Nodes\n4\n10 0 0 0\n20 1 0 0\n30 0 1 0\n40 0 0 1\n$EndNodes\n"
             "$Elements\n2\n1 2 2 3 1 10 20 30\n2 4 2 5 1 10 20 30 40\n$EndElements\n");
  const TetMesh mesh = read_tet_mesh((dir / "t.msh").string());
  ASSERT_EQ(mesh.tets.size(), 1u);
  EXPECT_EQ(mesh.tets[0], (std::array<Index, 4>{0, 1, 2, 3}));
  EXPECT_EQ(mesh.tet_region, std::vector<int>{9});
  ASSERT_EQ(mesh.faces.size(), 1u);
  EXPECT_EQ(mesh.face_marker, std::vector<int>{3});
}

TEST(MeshIo, ErrorsNameFileAndLine) {
  const auto dir = test::temp_dir("io-errors");
  write_text(dir / "bad.node", "4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n");
  write_text(dir / "bad.ele", "1 4 0\n# a comment\n1 1 2 3 9\n");
  try {
    read_tet_mesh((dir / "bad.ele").string());
    FAIL() << "no exception";
  } catch (const InputError& e) {
    EXPECT_EQ(e.code(), ErrorCode::IndexOutOfRange);
    EXPECT_EQ(e.line(), 3);
    EXPECT_NE(e.file().find("bad.ele"), std::string::npos);
  }
  write_text(dir / "bad.mesh", "MeshVersionFormatted 2\nDimension 3\nVertices\n1\n0 0 zero 0\nEnd\n");
  try {
    read_tet_mesh((dir / "bad.mesh").string());
    FAIL() << "no exception";
  } catch (const InputError& e) {
    EXPECT_EQ(e.code(), ErrorCode::Parse);
    EXPECT_EQ(e.line(), 5);
  }
  try {
    read_tet_mesh((dir / "missing.msh").string());
    FAIL() << "no exception";
  } catch (const InputError& e) {
    EXPECT_EQ(e.code(), ErrorCode::Io);
  }
}

TEST(MeshIo, FailedWriteLeavesExistingFileUntouched) {
  const auto dir = test::temp_dir("io-atomic");
  const fs::path target = dir / "m.vtu";
  write_text(target, "old contents");
  // A fill that fails half-way.
  EXPECT_THROW(io::write_file_atomically(target.string(),
                                         [](std::ostream& out) {
                                           out << "half";
                                           throw InputError(ErrorCode::Io, "simulated failure");
                                         }),
               InputError);
  EXPECT_EQ(slurp(target), "old contents");
  // A writer into a missing folder.
  EXPECT_THROW(write_tet_mesh(sample_mesh(), (dir / "no-such-folder" / "m.vtu").string()), InputError);
  // A writer whose target cannot be replaced (a non-empty folder of that name).
  fs::create_directories(dir / "blocked.msh" / "inside");
  EXPECT_THROW(write_tet_mesh(sample_mesh(), (dir / "blocked.msh").string()), InputError);
  EXPECT_TRUE(fs::is_directory(dir / "blocked.msh" / "inside"));
  // No temporary left behind.
  for (const auto& entry : fs::directory_iterator(dir)) {
    EXPECT_EQ(entry.path().filename().string().find(".tmp-"), std::string::npos) << entry.path();
  }
  EXPECT_EQ(slurp(target), "old contents");
}

}  // namespace
}  // namespace qualmesh
