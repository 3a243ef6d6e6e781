// Tests of the group-carrying writers and the readers of issue 14 (mesh_io.h): Abaqus/CalculiX .inp (short numbers,
// C3D10, Solid/Face/Edge sets, reading our decks and FreeCAD-style ones), UNV, Gmsh 4.1 second order, VTU face
// cells, the Elmer mesh directory and Medit P2, on the hand-built cube meshes of sample_meshes.h (linear and second
// order, mid-nodes at the edge midpoints). Independent readers (ccx, meshio, gmsh, FreeCAD) are exercised by
// tests/python/test_writers_groups.py.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "mesh_groups.h"
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

std::array<Index, 3> sorted3(std::array<Index, 3> f) {
  std::sort(f.begin(), f.end());
  return f;
}

// Faces as a set of (sorted corners -> marker).
std::map<std::array<Index, 3>, int> face_set(const TetMesh& mesh) {
  std::map<std::array<Index, 3>, int> faces;
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) faces[sorted3(mesh.faces[f])] = mesh.face_marker[f];
  return faces;
}

void expect_same_points_and_tets(const TetMesh& a, const TetMesh& b) {
  ASSERT_EQ(a.points.size(), b.points.size());
  for (std::size_t i = 0; i < a.points.size(); ++i) EXPECT_EQ(a.points[i], b.points[i]) << "point " << i;
  EXPECT_EQ(a.tets, b.tets);
  EXPECT_EQ(a.tet_mid, b.tet_mid);
  std::vector<int> labels_a, labels_b;
  for (std::size_t t = 0; t < a.tets.size(); ++t) labels_a.push_back(tet_region_label(a, t));
  for (std::size_t t = 0; t < b.tets.size(); ++t) labels_b.push_back(tet_region_label(b, t));
  EXPECT_EQ(labels_a, labels_b);
}

// Every face mid-node of `mesh` is the tet mid-node of the same edge, and sits at that edge's midpoint.
void expect_mid_nodes_at_midpoints(const TetMesh& mesh) {
  const auto at_mid = [&](Index a, Index b, Index m) {
    for (int c = 0; c < 3; ++c) {
      EXPECT_DOUBLE_EQ(mesh.points[m][c], (mesh.points[a][c] + mesh.points[b][c]) / 2) << a << "-" << b;
    }
  };
  ASSERT_EQ(mesh.tet_mid.size(), mesh.tets.size());
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
    for (int k = 0; k < 6; ++k) at_mid(mesh.tets[t][kTetEdges[k][0]], mesh.tets[t][kTetEdges[k][1]], mesh.tet_mid[t][k]);
  }
  for (std::size_t f = 0; f < mesh.face_mid.size(); ++f) {
    for (int k = 0; k < 3; ++k) at_mid(mesh.faces[f][k], mesh.faces[f][(k + 1) % 3], mesh.face_mid[f][k]);
  }
  for (std::size_t e = 0; e < mesh.edge_mid.size(); ++e) at_mid(mesh.edges[e][0], mesh.edges[e][1], mesh.edge_mid[e]);
}

TEST(ShortDouble, AtMostTwentyCharactersAndFourteenDigits) {
  const double values[] = {2.6056314875475606E-15, -2.6056314875475606E-15, -1.2345678901234567e-300, 1e22 / 3,
                           -0.00012345678901234567, 0.1 + 1 / 3.0, 1e10 + 0.7, 0.0, -0.0, 5e-324, 1.7976931348623157e308,
                           -123456789.12345678};
  for (double v : values) {
    const std::string s = io::short_double(v);
    EXPECT_LE(s.size(), 20u) << s;
    const double back = std::strtod(s.c_str(), nullptr);
    EXPECT_LE(std::fabs(back - v), 5e-13 * std::fabs(v)) << s;  // 13 significant digits at least
  }
  EXPECT_EQ(io::short_double(0.5), "0.5");
  EXPECT_EQ(io::short_double(0.1 + 1 / 3.0), "0.43333333333333335");  // shortest exact form when it fits
}

TEST(MeshIoAbaqus, LinearRoundTripKeepsSetsAndFaces) {
  const auto dir = test::temp_dir("io-inp-linear");
  const TetMesh mesh = sample_mesh();
  write_tet_mesh(mesh, (dir / "m.inp").string());
  const TetMesh back = read_tet_mesh((dir / "m.inp").string());
  expect_same_points_and_tets(mesh, back);
  EXPECT_EQ(face_set(back), face_set(mesh));
  // Surfaces read back as faces whose normal points out of their tetrahedron.
  for (const auto& f : back.faces) {
    const Point3 c{0.1 + 1 / 6.0, -7.25 + 1.65e-3, 1e10 + 0.35};
    EXPECT_LT(tet_signed_volume(back.points[f[0]], back.points[f[1]], back.points[f[2]], c), 0);
  }
  const std::string text = slurp(dir / "m.inp");
  EXPECT_NE(text.find("*NSET, NSET=Face1\n"), std::string::npos);
  EXPECT_EQ(text.find("Region"), std::string::npos);
}

TEST(MeshIoAbaqus, SecondOrderRoundTrip) {
  const auto dir = test::temp_dir("io-inp-quadratic");
  const TetMesh mesh = sample_mesh_quadratic();
  write_tet_mesh(mesh, (dir / "m.inp").string());
  const std::string text = slurp(dir / "m.inp");
  EXPECT_NE(text.find("*ELEMENT, TYPE=C3D10, ELSET=Solid7\n"), std::string::npos);
  EXPECT_NE(text.find("*NSET, NSET=Edge1\n"), std::string::npos);
  // Face1 = cube face x = min: 4 corners, 5 edges (4 sides + 1 diagonal) -> 9 nodes.
  const std::size_t at = text.find("*NSET, NSET=Face1\n");
  ASSERT_NE(at, std::string::npos);
  const std::string block = text.substr(at, text.find('*', at + 1) - at);
  EXPECT_EQ(std::count(block.begin(), block.end(), ',') + std::count(block.begin(), block.end(), '\n'), 9 + 2);
  const TetMesh back = read_tet_mesh((dir / "m.inp").string());
  expect_same_points_and_tets(mesh, back);
  EXPECT_EQ(face_set(back), face_set(mesh));
  expect_mid_nodes_at_midpoints(back);
}

TEST(MeshIoAbaqus, ReadsFreeCadStyleDeck) {
  const auto dir = test::temp_dir("io-inp-freecad");
  // Lower-case keywords, comments, a continuation line, GENERATE, sets by name, a shell element and a surface on
  // an element set, as FreeCAD's and Gmsh's writers produce them.
  write_text(dir / "fc.inp",
             "** written by FreeCAD\n*Node, NSET=Nall\n1, 0, 0, 0\n2, 1.0D0, 0, 0\n3, 0, 1, 0\n4, 0, 0, 1\n"
             "5, 0.5, 0, 0\n6, 0.5, 0.5, 0\n7, 0, 0.5, 0\n8, 0, 0, 0.5\n9, 0.5, 0, 0.5\n10, 0, 0.5, 0.5\n"
             "** Volume elements\n*element, type=C3D10, elset=Evolumes\n11, 1, 2, 3, 4, 5, 6,\n 7, 8, 9, 10\n"
             "*Element, TYPE=S6, ELSET=Efaces\n20, 1, 3, 2, 7, 6, 5\n"
             "*ELSET, ELSET=Solid3, GENERATE\n11, 11, 1\n*ELSET,ELSET=Face5\nEfaces\n"
             "*ELSET, ELSET=Ebottom\n11\n*Surface, Name=Face9, type=Element\nEbottom, S1\n11, S2\n"
             "*Nset, Nset=Face9\n1, 2, 3, 5, 6, 7\n*STEP\n*STATIC\n*END STEP\n");
  const TetMesh mesh = read_tet_mesh((dir / "fc.inp").string());
  ASSERT_EQ(mesh.tets.size(), 1u);
  EXPECT_EQ(mesh.tets[0], (std::array<Index, 4>{0, 1, 2, 3}));
  EXPECT_EQ(mesh.tet_region, std::vector<int>{3});
  EXPECT_EQ(mesh.points[1][0], 1.0);
  ASSERT_EQ(mesh.tet_mid.size(), 1u);
  expect_mid_nodes_at_midpoints(mesh);
  ASSERT_EQ(mesh.faces.size(), 3u);
  EXPECT_EQ(mesh.face_marker, (std::vector<int>{5, 9, 9}));
  EXPECT_EQ(sorted3(mesh.faces[1]), (std::array<Index, 3>{0, 1, 2}));  // S1 = 1-2-3
  EXPECT_EQ(sorted3(mesh.faces[2]), (std::array<Index, 3>{0, 1, 3}));  // S2 = 1-4-2
  EXPECT_EQ(mesh.face_mid.size(), 3u);
}

// Edges as a set of (sorted ends -> marker).
std::map<std::array<Index, 2>, int> edge_set(const TetMesh& mesh) {
  std::map<std::array<Index, 2>, int> edges;
  for (std::size_t e = 0; e < mesh.edges.size(); ++e) {
    edges[{std::min(mesh.edges[e][0], mesh.edges[e][1]), std::max(mesh.edges[e][0], mesh.edges[e][1])}] =
        mesh.edge_marker[e];
  }
  return edges;
}

TEST(MeshIoUnv, LinearAndSecondOrderRoundTrips) {
  const auto dir = test::temp_dir("io-unv");
  for (const TetMesh& mesh : {sample_mesh(), sample_mesh_quadratic()}) {
    write_tet_mesh(mesh, (dir / "m.unv").string());
    const TetMesh back = read_tet_mesh((dir / "m.unv").string());
    expect_same_points_and_tets(mesh, back);  // %25.16E coordinates: exact
    EXPECT_EQ(back.faces, mesh.faces);
    EXPECT_EQ(back.face_marker, mesh.face_marker);
    EXPECT_EQ(edge_set(back), edge_set(mesh));
    if (mesh.is_second_order()) {
      EXPECT_EQ(back.face_mid, mesh.face_mid);
      expect_mid_nodes_at_midpoints(back);
    }
  }
  const std::string text = slurp(dir / "m.unv");
  for (const char* name : {"\nSolid1\n", "\nSolid7\n", "\nFace3\n", "\nFace3_Nodes\n", "\nEdge1\n", "\nEdge1_Nodes\n"}) {
    EXPECT_NE(text.find(name), std::string::npos) << name;
  }
  EXPECT_NE(text.find("       118         2         1         7        10\n"), std::string::npos);
}

TEST(MeshIoUnv, ReadsFreeCadExport) {
  // FreeCAD 0.20's FemMesh.write of a SMESH tet10 with nodes (smesh) 2 1 3 4 | 5 7 6 9 8 10 and a tri6 face.
  const auto dir = test::temp_dir("io-unv-freecad");
  std::string text = "    -1\n   164\n         1  SI: Meter (newton)         2\n"
                     "    1.0000000000000000E+0    1.0000000000000000E+0    1.0000000000000000E+0\n"
                     "    2.7314999999999998E+2\n    -1\n    -1\n  2411\n";
  const double xyz[10][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0.5, 0, 0},
                             {0.5, 0.5, 0}, {0, 0.5, 0}, {0, 0, 0.5}, {0.5, 0, 0.5}, {0, 0.5, 0.5}};
  for (int i = 0; i < 10; ++i) {
    char line[200];
    std::snprintf(line, sizeof line, "%10d%10d%10d%10d\n%25.16E%25.16E%25.16E\n", i + 1, 1, 1, 11, xyz[i][0],
                  xyz[i][1], xyz[i][2]);
    text += line;
  }
  text += "    -1\n    -1\n  2412\n"
          "         2        42         2         1         7         6\n"
          "         1         7         3         6         2         5\n"
          "         1       118         2         1         7        10\n"
          "         2         6         3         7         1         5         9        10\n"
          "         8         4\n    -1\n    -1\n  2467\n"
          "         1         0         0         0         0         0         0         1\nSolid4\n"
          "         8         1         0         0\n"
          "         2         0         0         0         0         0         0         1\nFace2_Faces\n"
          "         8         2         0         0\n    -1\n";
  write_text(dir / "fc.unv", text);
  const TetMesh mesh = read_tet_mesh((dir / "fc.unv").string());
  ASSERT_EQ(mesh.tets.size(), 1u);
  const auto& p = mesh.points;
  const auto& t = mesh.tets[0];
  EXPECT_GT(tet_signed_volume(p[t[0]], p[t[1]], p[t[2]], p[t[3]]), 0);  // SMESH's negative tet read positive
  EXPECT_EQ(mesh.tet_region, std::vector<int>{4});
  expect_mid_nodes_at_midpoints(mesh);
  EXPECT_EQ(mesh.face_marker, std::vector<int>{2});
}

TEST(MeshIoGmsh, SecondOrderRoundTripWithCurves) {
  const auto dir = test::temp_dir("io-gmsh-groups");
  for (const TetMesh& mesh : {sample_mesh_quadratic(false), sample_mesh_quadratic()}) {
    write_tet_mesh(mesh, (dir / "m.msh").string());
    const TetMesh back = read_tet_mesh((dir / "m.msh").string());
    expect_same_points_and_tets(mesh, back);
    EXPECT_EQ(back.faces, mesh.faces);
    EXPECT_EQ(back.face_marker, mesh.face_marker);
    EXPECT_EQ(back.face_mid, mesh.face_mid);
    EXPECT_EQ(edge_set(back), edge_set(mesh));
    expect_mid_nodes_at_midpoints(back);
  }
  const std::string text = slurp(dir / "m.msh");
  EXPECT_NE(text.find("1 12 \"Edge12\""), std::string::npos);
  EXPECT_NE(text.find("3 7 \"Solid7\""), std::string::npos);
  EXPECT_NE(text.find(" 11 3\n"), std::string::npos);  // a block of three tet10
}

TEST(MeshIoVtu, FaceCellsWithFaceIdsRoundTrip) {
  const auto dir = test::temp_dir("io-vtu-groups");
  for (TetMesh mesh : {sample_mesh(), sample_mesh_quadratic()}) {
    mesh.weights.assign(8, 0.25);  // corner weights; mid-nodes get none
    write_tet_mesh(mesh, (dir / "m.vtu").string());
    const TetMesh back = read_tet_mesh((dir / "m.vtu").string());
    expect_same_points_and_tets(mesh, back);
    EXPECT_EQ(back.tet_region, mesh.tet_region);
    EXPECT_EQ(back.faces, mesh.faces);
    EXPECT_EQ(back.face_marker, mesh.face_marker);
    EXPECT_EQ(back.face_mid, mesh.face_mid);
    EXPECT_EQ(back.weights, mesh.weights);
  }
  const std::string text = slurp(dir / "m.vtu");
  EXPECT_NE(text.find("NumberOfCells=\"18\""), std::string::npos);
  EXPECT_NE(text.find("Name=\"face_id\""), std::string::npos);
  EXPECT_NE(text.find("          24\n"), std::string::npos);
  EXPECT_NE(text.find("          22\n"), std::string::npos);
}

// Lines of a file split into integers / tokens.
std::vector<std::vector<std::string>> token_lines(const fs::path& path) {
  std::vector<std::vector<std::string>> lines;
  std::istringstream in(slurp(path));
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream words(line);
    std::vector<std::string> tokens;
    for (std::string w; words >> w;) tokens.push_back(w);
    if (!tokens.empty()) lines.push_back(tokens);
  }
  return lines;
}

TEST(MeshIoElmer, DirectoryFollowsTheFormat) {
  const auto dir = test::temp_dir("io-elmer");
  const TetMesh mesh = sample_mesh_quadratic();
  EXPECT_EQ(mesh_format_from_path("a/beam.elmer/"), MeshFormat::Elmer);
  fs::create_directories(dir / "beam.elmer" / "stale");  // an older mesh of that name is replaced
  write_tet_mesh(mesh, (dir / "beam.elmer").string());
  EXPECT_FALSE(fs::exists(dir / "beam.elmer" / "stale"));
  const auto header = token_lines(dir / "beam.elmer" / "mesh.header");
  ASSERT_EQ(header.size(), 4u);
  EXPECT_EQ(header[0], (std::vector<std::string>{std::to_string(mesh.points.size()), "6", "12"}));
  EXPECT_EQ(header[1], std::vector<std::string>{"2"});
  EXPECT_EQ(header[2], (std::vector<std::string>{"510", "6"}));
  EXPECT_EQ(header[3], (std::vector<std::string>{"306", "12"}));
  const auto nodes = token_lines(dir / "beam.elmer" / "mesh.nodes");
  ASSERT_EQ(nodes.size(), mesh.points.size());
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    ASSERT_EQ(nodes[i].size(), 5u);
    EXPECT_EQ(nodes[i][0], std::to_string(i + 1));
    EXPECT_EQ(nodes[i][1], "-1");
    for (int c = 0; c < 3; ++c) EXPECT_EQ(std::strtod(nodes[i][2 + c].c_str(), nullptr), mesh.points[i][c]);
  }
  const auto elements = token_lines(dir / "beam.elmer" / "mesh.elements");
  ASSERT_EQ(elements.size(), 6u);
  for (std::size_t t = 0; t < 6; ++t) {
    ASSERT_EQ(elements[t].size(), 13u);
    EXPECT_EQ(elements[t][1], std::to_string(mesh.tet_region[t]));
    EXPECT_EQ(elements[t][2], "510");
    for (int k = 0; k < 4; ++k) EXPECT_EQ(elements[t][3 + k], std::to_string(mesh.tets[t][k] + 1));
    for (int k = 0; k < 6; ++k) EXPECT_EQ(elements[t][7 + k], std::to_string(mesh.tet_mid[t][k] + 1));
  }
  const auto boundary = token_lines(dir / "beam.elmer" / "mesh.boundary");
  ASSERT_EQ(boundary.size(), 12u);
  for (std::size_t f = 0; f < 12; ++f) {
    ASSERT_EQ(boundary[f].size(), 11u);
    EXPECT_EQ(boundary[f][1], std::to_string(mesh.face_marker[f]));
    const long parent = std::stol(boundary[f][2]);
    ASSERT_GE(parent, 1);
    EXPECT_EQ(boundary[f][3], "0");  // hull faces have one parent
    std::set<Index> corners(mesh.tets[parent - 1].begin(), mesh.tets[parent - 1].end());
    for (Index v : mesh.faces[f]) EXPECT_TRUE(corners.count(v));
    EXPECT_EQ(boundary[f][4], "306");
  }
  const std::string names = slurp(dir / "beam.elmer" / "mesh.names");
  EXPECT_NE(names.find("! ----- names for bodies -----\n$ Solid1 = 1\n$ Solid7 = 7\n"), std::string::npos);
  EXPECT_NE(names.find("! ----- names for boundaries -----\n$ Face1 = 1\n"), std::string::npos);
  for (const auto& entry : fs::directory_iterator(dir)) {
    EXPECT_EQ(entry.path().filename().string().find(".tmp-"), std::string::npos) << entry.path();
    EXPECT_EQ(entry.path().filename().string().find(".old-"), std::string::npos) << entry.path();
  }
}

TEST(MeshIoMedit, P2RoundTripWithEdges) {
  const auto dir = test::temp_dir("io-medit-groups");
  for (const TetMesh& mesh : {sample_mesh_quadratic(), sample_mesh_quadratic(false)}) {
    write_tet_mesh(mesh, (dir / "m.mesh").string());
    const TetMesh back = read_tet_mesh((dir / "m.mesh").string());
    expect_same_points_and_tets(mesh, back);
    EXPECT_EQ(back.faces, mesh.faces);
    EXPECT_EQ(back.face_marker, mesh.face_marker);
    EXPECT_EQ(back.face_mid, mesh.face_mid);
    EXPECT_EQ(back.edges, mesh.edges);
    EXPECT_EQ(back.edge_marker, mesh.edge_marker);
    EXPECT_EQ(back.edge_mid, mesh.edge_mid);
  }
  const std::string text = slurp(dir / "m.mesh");
  EXPECT_NE(text.find("\nTetrahedraP2\n6\n"), std::string::npos);
  EXPECT_NE(text.find("\nTrianglesP2\n12\n"), std::string::npos);
}

TEST(MeshIoAbaqus, ErrorsNameFileAndLine) {
  const auto dir = test::temp_dir("io-inp-errors");
  const auto expect_error = [&](const std::string& text, ErrorCode code, long line) {
    write_text(dir / "bad.inp", text);
    try {
      read_tet_mesh((dir / "bad.inp").string());
      ADD_FAILURE() << "no exception for:\n" << text;
    } catch (const InputError& e) {
      EXPECT_EQ(e.code(), code) << e.what();
      EXPECT_EQ(e.line(), line) << e.what();
      EXPECT_NE(e.file().find("bad.inp"), std::string::npos) << e.what();
    }
  };
  const std::string nodes = "*NODE\n1, 0, 0, 0\n2, 1, 0, 0\n3, 0, 1, 0\n4, 0, 0, 1\n";
  expect_error(nodes + "*ELEMENT, TYPE=C3D4\n1, 1, 2, 3, 9\n", ErrorCode::IndexOutOfRange, 7);
  expect_error(nodes + "*ELEMENT, TYPE=C3D8\n1, 1, 2, 3, 4, 1, 2, 3, 4\n", ErrorCode::Unsupported, 7);
  expect_error(nodes + "*ELEMENT, TYPE=C3D4\n1, 1, 2, 3\n", ErrorCode::Parse, 7);
  expect_error("*NODE\n1, 0, zero, 0\n", ErrorCode::Parse, 2);
  expect_error("1, 0, 0, 0\n", ErrorCode::Parse, 1);
  expect_error(nodes + "*ELEMENT, TYPE=C3D4\n1, 1, 2, 3, 4\n*SURFACE, NAME=S\n1, S7\n", ErrorCode::Parse, 9);
  // A set names what is defined above it, with the line of the name.
  expect_error(nodes + "*NSET, NSET=Face1\n1, 2\n5\n", ErrorCode::IndexOutOfRange, 8);
  expect_error(nodes + "*ELSET, ELSET=Solid1\n1\n*ELEMENT, TYPE=C3D4\n1, 1, 2, 3, 4\n", ErrorCode::IndexOutOfRange, 7);
}

// A set copied into itself line after line holds each id once (fuzzing finding tests/fuzz/regressions/inp/
// set-copied-into-itself: each copy doubled the set, and 6 kB of them took 4 GB and 223 s), and an element set
// copied into itself and then into a surface gives each face once.
TEST(MeshIoAbaqus, SetsHoldEachIdOnce) {
  const auto dir = test::temp_dir("io-inp-set-doubling");
  std::string text = "*NODE\n1, 0, 0, 0\n2, 1, 0, 0\n3, 0, 1, 0\n4, 0, 0, 1\n"
                     "*ELEMENT, TYPE=C3D4, ELSET=E\n1, 1, 2, 3, 4\n"
                     "*NSET, NSET=Face1\n1, 2, 3\n";
  for (int i = 0; i < 64; ++i) text += "*NSET, NSET=Face1\nFace1, 1, 2\n*ELSET, ELSET=E\nE, 1\n";
  text += "*SURFACE, NAME=Face1, TYPE=ELEMENT\nE, S1\n";
  write_text(dir / "twice.inp", text);
  const TetMesh mesh = read_tet_mesh((dir / "twice.inp").string());
  ASSERT_EQ(mesh.tets.size(), 1u);
  ASSERT_EQ(mesh.faces.size(), 1u);
  EXPECT_EQ(sorted3(mesh.faces[0]), (std::array<Index, 3>{0, 1, 2}));
}

}  // namespace
}  // namespace qualmesh
