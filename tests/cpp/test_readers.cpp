// PLC readers and writers: the counts of MANIFEST.md on the real inputs of shared/data/plc (unmerged), TetGen
// details (regions, holes, facet holes, 0-based .smesh), binary STL with a "solid" header, the small inputs of
// tests/data/small in every format (merged into 6 squares), and write -> read round trips.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <string>
#include <vector>

#include "qualmesh/error.h"
#include "qualmesh/plc.h"
#include "qualmesh/plc_io.h"
#include "qualmesh/plc_validate.h"
#include "test_support.h"

namespace qualmesh {
namespace {

using test::shared_path;
using test::source_path;

ReadOptions unmerged() {
  ReadOptions options;
  options.merge_coplanar = false;
  return options;
}

struct ManifestCount {
  const char* file;
  std::size_t vertices;
  std::size_t facets;
};

// Used vertices / facets as listed in shared/data/MANIFEST.md.
const ManifestCount kManifest[] = {
    {"example.poly", 28, 23},      {"wedge-1.smesh", 6, 5},         {"spike-1-10.smesh", 11, 11},
    {"slit-1.smesh", 14, 13},      {"fandisk.off", 6475, 12946},    {"elephant.off", 2775, 5558},
    {"anchor.off", 519, 1050},     {"joint.off", 221, 446},         {"couplingdown.off", 1841, 3714},
    {"bunny00.off", 37706, 75408}, {"elephant.mesh", 931, 1871},    {"t13_data.stl", 788, 1580},
    {"aorta2.stl", 6278, 12455},   {"lever.stl", 377, 774},         {"pinion.off", 650, 1300},
    {"turbine.off", 9210, 18460},  {"cheese.off", 8629, 17786},     {"cubes.off", 14, 24},
};

class ManifestCounts : public ::testing::TestWithParam<ManifestCount> {};

TEST_P(ManifestCounts, UnmergedCountsMatchManifest) {
  const ManifestCount& expected = GetParam();
  const std::string path = shared_path(std::string("data/plc/") + expected.file);
  QM_REQUIRE_FILE(path);
  const Plc plc = read_plc(path, unmerged());
  EXPECT_EQ(plc.vertices.size(), expected.vertices) << expected.file;
  EXPECT_EQ(plc.facets.size(), expected.facets) << expected.file;
  EXPECT_EQ(plc.name, expected.file);
}

INSTANTIATE_TEST_SUITE_P(SharedPlc, ManifestCounts, ::testing::ValuesIn(kManifest),
                         [](const ::testing::TestParamInfo<ManifestCount>& info) {
                           std::string name = info.param.file;
                           std::replace_if(name.begin(), name.end(), [](char c) { return !std::isalnum(c); }, '_');
                           return name;
                         });

TEST(ReadOff, CowDuplicateVertexIsMerged) {
  // cow.off lists 2904 vertices, all used (MANIFEST counts 2904), but vertex 2903 repeats vertex 44 exactly
  // (-0.410173, 0.204796, -1.55991e-08); surface readers merge exact duplicates, first occurrence kept.
  const std::string path = shared_path("data/plc/cow.off");
  QM_REQUIRE_FILE(path);
  const Plc plc = read_plc(path, unmerged());
  EXPECT_EQ(plc.vertices.size(), 2903u);
  EXPECT_EQ(plc.facets.size(), 5804u);
  EXPECT_EQ(plc.vertices[44], (Point3{-0.410173, 0.204796, -1.55991e-08}));
}

TEST(ReadOff, CubesSharingAnEdgeMergeIntoTwelveSquares) {
  // Two unit cubes touching along one edge: each cube face is two triangles; the shared edge is used by four
  // facets, so nothing is merged across it. 24 triangles -> 12 squares, all 14 vertices kept.
  const std::string path = shared_path("data/plc/cubes.off");
  QM_REQUIRE_FILE(path);
  const Plc plc = read_plc(path);
  EXPECT_EQ(plc.vertices.size(), 14u);
  ASSERT_EQ(plc.facets.size(), 12u);
  for (const Facet& f : plc.facets) {
    ASSERT_EQ(f.polygons.size(), 1u);
    EXPECT_EQ(f.polygons[0].size(), 4u);
  }
}

TEST(ReadTetgen, ExamplePolyRegionsHolesAndFacetHole) {
  const std::string path = shared_path("data/plc/example.poly");
  QM_REQUIRE_FILE(path);
  const Plc plc = read_plc(path);  // TetGen files are never merged
  ASSERT_EQ(plc.vertices.size(), 28u);
  ASSERT_EQ(plc.facets.size(), 23u);
  // 1-based file: node 13 is (0.25, 0.25, 0.5).
  EXPECT_EQ(plc.vertices[12], (Point3{0.25, 0.25, 0.5}));
  // Facet 3 has two polygons and one hole point (1, 0, 2.25), marker 3.
  const Facet& third = plc.facets[2];
  ASSERT_EQ(third.polygons.size(), 2u);
  EXPECT_EQ(third.polygons[0], (std::vector<Index>{0, 1, 5, 4}));
  EXPECT_EQ(third.polygons[1], (std::vector<Index>{20, 21, 25, 24}));
  ASSERT_EQ(third.holes.size(), 1u);
  EXPECT_EQ(third.holes[0], (Point3{1, 0, 2.25}));
  EXPECT_EQ(third.marker, 3);
  EXPECT_EQ(plc.facets[1].marker, 9);
  std::size_t polygons = 0;
  for (const Facet& f : plc.facets) polygons += f.polygons.size();
  EXPECT_EQ(polygons, 24u);
  ASSERT_EQ(plc.holes.size(), 2u);
  EXPECT_EQ(plc.holes[0], (Point3{1, 0.4, 2.25}));
  EXPECT_EQ(plc.holes[1], (Point3{1, 0.4, 0.75}));
  ASSERT_EQ(plc.regions.size(), 2u);
  EXPECT_EQ(plc.regions[0].point, (Point3{1, 0.25, 0.1}));
  EXPECT_EQ(plc.regions[0].attribute, 10);
  EXPECT_DOUBLE_EQ(plc.regions[0].max_volume, 0.001);
  EXPECT_EQ(plc.regions[1].attribute, 20);
  EXPECT_DOUBLE_EQ(plc.regions[1].max_volume, 0.01);
}

TEST(ReadTetgen, SmeshZeroBasedWithMarkers) {
  const std::string path = shared_path("data/plc/wedge-1.smesh");
  QM_REQUIRE_FILE(path);
  const Plc plc = read_plc(path);
  ASSERT_EQ(plc.vertices.size(), 6u);
  ASSERT_EQ(plc.facets.size(), 5u);
  EXPECT_EQ(plc.vertices[0], (Point3{0, 0, 0}));
  // "4 0 2 3 1 1": 0-based indices kept as they are, marker 1.
  EXPECT_EQ(plc.facets[0].polygons[0], (std::vector<Index>{0, 2, 3, 1}));
  EXPECT_EQ(plc.facets[0].marker, 1);
  EXPECT_EQ(plc.facets[2].polygons[0], (std::vector<Index>{0, 2, 4}));
  EXPECT_EQ(plc.facets[2].marker, 3);
  EXPECT_TRUE(plc.holes.empty());
  EXPECT_TRUE(plc.regions.empty());
}

TEST(ReadTetgen, PolyWithNodesInSiblingNodeFile) {
  const auto dir = test::temp_dir("readers-sibling-node");
  {
    std::ofstream node(dir / "tet.node");
    node << "4 3 0 0\n0 0 0 0\n1 1 0 0\n2 0 1 0\n3 0 0 1\n";
    std::ofstream poly(dir / "tet.poly");
    poly << "0 3 0 0\n4 0\n1\n3 0 2 1\n1\n3 0 1 3\n1\n3 1 2 3\n1\n3 2 0 3\n0\n";
  }
  const Plc plc = read_plc((dir / "tet.poly").string());
  ASSERT_EQ(plc.vertices.size(), 4u);
  ASSERT_EQ(plc.facets.size(), 4u);
  EXPECT_EQ(plc.facets[3].polygons[0], (std::vector<Index>{2, 0, 3}));
  const Plc points = read_plc((dir / "tet.node").string());
  EXPECT_EQ(points.vertices.size(), 4u);
  EXPECT_TRUE(points.facets.empty());
}

TEST(ReadStl, LeverIsBinaryDespiteSolidHeader) {
  const std::string path = shared_path("data/plc/lever.stl");
  QM_REQUIRE_FILE(path);
  {
    std::ifstream in(path, std::ios::binary);
    char head[5] = {};
    in.read(head, 5);
    ASSERT_EQ(std::string(head, 5), "solid");  // the trap this test is about
  }
  const Plc plc = read_plc(path, unmerged());
  EXPECT_EQ(plc.vertices.size(), 377u);
  EXPECT_EQ(plc.facets.size(), 774u);
  for (const Facet& f : plc.facets) ASSERT_EQ(f.polygons[0].size(), 3u);
}

// Every format of the small box: 8 vertices, 12 triangles unmerged, 6 squares merged.
class SmallBox : public ::testing::TestWithParam<const char*> {};

TEST_P(SmallBox, TwelveTrianglesMergeIntoSixSquares) {
  const std::string path = source_path(std::string("tests/data/small/") + GetParam());
  const Plc raw = read_plc(path, unmerged());
  EXPECT_EQ(raw.vertices.size(), 8u);  // duplicates merged, unused vertex dropped
  EXPECT_EQ(raw.facets.size(), 12u);
  const Plc merged = read_plc(path);
  EXPECT_EQ(merged.vertices.size(), 8u);
  ASSERT_EQ(merged.facets.size(), 6u);
  for (const Facet& f : merged.facets) {
    ASSERT_EQ(f.polygons.size(), 1u);
    EXPECT_EQ(f.polygons[0].size(), 4u);
  }
}

INSTANTIATE_TEST_SUITE_P(Formats, SmallBox,
                         ::testing::Values("box.stl", "box_binary.stl", "box.obj", "box.mesh"),
                         [](const ::testing::TestParamInfo<const char*>& info) {
                           std::string name = info.param;
                           std::replace(name.begin(), name.end(), '.', '_');
                           return name;
                         });

TEST(ReadStl, AsciiAndBinaryBoxAgreeVertexForVertex) {
  const Plc ascii = read_plc(source_path("tests/data/small/box.stl"), unmerged());
  const Plc binary = read_plc(source_path("tests/data/small/box_binary.stl"), unmerged());
  EXPECT_EQ(ascii.vertices, binary.vertices);
  ASSERT_EQ(ascii.facets.size(), binary.facets.size());
  for (std::size_t f = 0; f < ascii.facets.size(); ++f) EXPECT_EQ(ascii.facets[f].polygons, binary.facets[f].polygons);
  // First occurrence order: the first triangle is (0,0,0) (0,1,0) (1,1,0).
  EXPECT_EQ(ascii.vertices[0], (Point3{0, 0, 0}));
  EXPECT_EQ(ascii.vertices[1], (Point3{0, 1, 0}));
  EXPECT_EQ(ascii.vertices[2], (Point3{1, 1, 0}));
}

TEST(ReadMedit, ReferencesBecomeMarkers) {
  const Plc plc = read_plc(source_path("tests/data/small/box.mesh"));
  ASSERT_EQ(plc.facets.size(), 6u);
  for (std::size_t f = 0; f < 6; ++f) EXPECT_EQ(plc.facets[f].marker, static_cast<int>(f) + 1);
}

TEST(ReadPoly, SmallBoxPolyKeepsSquares) {
  const Plc plc = read_plc(source_path("tests/data/small/box.poly"));
  ASSERT_EQ(plc.vertices.size(), 8u);
  ASSERT_EQ(plc.facets.size(), 6u);
  EXPECT_EQ(plc.facets[0].polygons[0], (std::vector<Index>{0, 3, 2, 1}));
  EXPECT_EQ(plc.facets[5].marker, 6);
}

TEST(PlcPaths, ExtensionsCaseInsensitive) {
  EXPECT_TRUE(is_plc_path("a.poly"));
  EXPECT_TRUE(is_plc_path("dir/B.STL"));
  EXPECT_TRUE(is_plc_path("x.Smesh"));
  EXPECT_TRUE(is_plc_path("x.node"));
  EXPECT_TRUE(is_plc_path("x.obj"));
  EXPECT_TRUE(is_plc_path("x.mesh"));
  EXPECT_TRUE(is_plc_path("x.OFF"));
  EXPECT_FALSE(is_plc_path("x.step"));
  EXPECT_FALSE(is_plc_path("x.msh"));
  EXPECT_FALSE(is_plc_path("noextension"));
}

// A facet as a vertex cycle, rotated to start at its smallest vertex (orientation kept).
std::vector<Index> canonical_cycle(std::vector<Index> loop) {
  std::rotate(loop.begin(), std::min_element(loop.begin(), loop.end()), loop.end());
  return loop;
}

TEST(RoundTrip, OffToPolyToOffKeepsThePlc) {
  const std::string path = shared_path("data/plc/joint.off");
  QM_REQUIRE_FILE(path);
  const Plc original = read_plc(path, unmerged());
  const auto dir = test::temp_dir("readers-roundtrip");
  write_plc(original, (dir / "joint.poly").string());
  const Plc poly = read_plc((dir / "joint.poly").string());
  write_plc(poly, (dir / "joint.off").string());
  const Plc back = read_plc((dir / "joint.off").string(), unmerged());
  for (const Plc* copy : {&poly, &back}) {
    ASSERT_EQ(copy->vertices, original.vertices);  // bit for bit
    ASSERT_EQ(copy->facets.size(), original.facets.size());
    for (std::size_t f = 0; f < original.facets.size(); ++f) {
      ASSERT_EQ(copy->facets[f].polygons.size(), 1u);
      EXPECT_EQ(canonical_cycle(copy->facets[f].polygons[0]), canonical_cycle(original.facets[f].polygons[0]))
          << "facet " << f;
    }
  }
}

TEST(RoundTrip, ExamplePolyThroughPolyAndSmesh) {
  const std::string path = shared_path("data/plc/example.poly");
  QM_REQUIRE_FILE(path);
  const Plc original = read_plc(path);
  const auto dir = test::temp_dir("readers-roundtrip-poly");
  write_plc(original, (dir / "copy.poly").string());
  const Plc copy = read_plc((dir / "copy.poly").string());
  EXPECT_EQ(copy.vertices, original.vertices);
  ASSERT_EQ(copy.facets.size(), original.facets.size());
  for (std::size_t f = 0; f < copy.facets.size(); ++f) {
    EXPECT_EQ(copy.facets[f].polygons, original.facets[f].polygons);
    EXPECT_EQ(copy.facets[f].holes, original.facets[f].holes);
    EXPECT_EQ(copy.facets[f].marker, original.facets[f].marker);
  }
  EXPECT_EQ(copy.holes, original.holes);
  ASSERT_EQ(copy.regions.size(), 2u);
  EXPECT_EQ(copy.regions[1].point, original.regions[1].point);
  EXPECT_EQ(copy.regions[1].attribute, 20);
  EXPECT_EQ(copy.regions[1].max_volume, 0.01);
  // .smesh and .off cannot hold facet 2 (two polygons and a hole): Unsupported naming it, nothing written.
  for (const char* name : {"copy.smesh", "copy.off"}) {
    try {
      write_plc(original, (dir / name).string());
      FAIL() << "expected InputError for " << name;
    } catch (const InputError& e) {
      EXPECT_EQ(e.code(), ErrorCode::Unsupported);
      EXPECT_NE(e.message().find("facet 2 "), std::string::npos) << e.what();
    }
    EXPECT_FALSE(std::filesystem::exists(dir / name));
  }
}

TEST(RoundTrip, SmeshKeepsMarkers) {
  const std::string path = shared_path("data/plc/slit-1.smesh");
  QM_REQUIRE_FILE(path);
  const Plc original = read_plc(path);
  const auto dir = test::temp_dir("readers-roundtrip-smesh");
  write_plc(original, (dir / "slit.smesh").string());
  const Plc copy = read_plc((dir / "slit.smesh").string());
  EXPECT_EQ(copy.vertices, original.vertices);
  ASSERT_EQ(copy.facets.size(), 13u);
  for (std::size_t f = 0; f < copy.facets.size(); ++f) {
    EXPECT_EQ(copy.facets[f].polygons, original.facets[f].polygons);
    EXPECT_EQ(copy.facets[f].marker, original.facets[f].marker);
  }
}

TEST(WritePlc, UnknownExtensionIsUnsupported) {
  const Plc plc = read_plc(source_path("tests/data/small/box.poly"));
  const auto dir = test::temp_dir("readers-write-unknown");
  try {
    write_plc(plc, (dir / "box.stl").string());
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.code(), ErrorCode::Unsupported);
  }
}


// Degenerate surface triangles (issue 18): repaired exactly, as TetGen meshes such files, or refused by face number.
// The unit cube, outward triangles; vertex 8 = (0.5, 0, 0) is the middle of the edge 0-1.
const char* kCubeVertices = "0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n0.5 0 0\n";
const std::vector<std::string> kCubeTriangles = {"0 2 1", "0 3 2", "4 5 6", "4 6 7", "0 1 5", "0 5 4",
                                                 "3 7 6", "3 6 2", "0 4 7", "0 7 3", "1 2 6", "1 6 5"};

std::string off_text(const std::vector<std::string>& triangles) {
  std::string text = "OFF\n9 " + std::to_string(triangles.size()) + " 0\n" + kCubeVertices;
  for (const std::string& t : triangles) text += "3 " + t + "\n";
  return text;
}

// Volume enclosed by the facets (each polygon fanned from its first vertex): the divergence theorem.
double enclosed_volume(const Plc& plc) {
  double six_v = 0;
  for (const Facet& f : plc.facets)
    for (const auto& loop : f.polygons)
      for (std::size_t i = 1; i + 1 < loop.size(); ++i) {
        const Point3 &a = plc.vertices[loop[0]], &b = plc.vertices[loop[i]], &c = plc.vertices[loop[i + 1]];
        six_v += a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
                 a[2] * (b[0] * c[1] - b[1] * c[0]);
      }
  return six_v / 6;
}

TEST(SurfaceRepair, TriangleRepeatingAVertexIsDropped) {
  const auto dir = test::temp_dir("repair-repeat");
  std::vector<std::string> triangles = kCubeTriangles;
  triangles.insert(triangles.begin() + 3, "5 5 6");
  test::write_text(dir / "cube.off", off_text(triangles));
  std::vector<std::string> notes;
  const Plc plc = read_plc((dir / "cube.off").string(), unmerged(), &notes);
  EXPECT_EQ(plc.facets.size(), 12u);
  EXPECT_TRUE(validate_plc(plc).ok());
  EXPECT_DOUBLE_EQ(enclosed_volume(plc), 1.0);
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_NE(notes[0].find("1 triangle(s) repeating a vertex dropped, 0 collinear"), std::string::npos) << notes[0];
  EXPECT_NE(notes[0].find("face 3 (line 15) repeats a vertex"), std::string::npos) << notes[0];  // OFF counts from 0
}

// A T-junction in disguise: the bottom has vertex 8 in its edge 1-0, the front does not, and the triangle (1, 0, 8)
// of zero area closes the gap. The repair drops it and splits the front triangle (0, 1, 5) at 8.
TEST(SurfaceRepair, CollinearTriangleSplitsItsNeighbourAcrossTheLongEdge) {
  const auto dir = test::temp_dir("repair-collinear");
  std::vector<std::string> triangles = kCubeTriangles;
  triangles[0] = "0 2 8";
  triangles.push_back("8 2 1");
  triangles.push_back("1 0 8");
  test::write_text(dir / "cube.off", off_text(triangles));
  // Without the repair the surface is closed but the triangle is refused, by its number and line.
  ReadOptions no_repair = unmerged();
  no_repair.repair_degenerate = false;
  try {
    read_plc((dir / "cube.off").string(), no_repair);
    FAIL() << "the collinear triangle was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.code(), ErrorCode::DegenerateFacet);
    EXPECT_EQ(e.line(), 25);
    EXPECT_NE(std::string(e.what()).find("face 13 has zero area"), std::string::npos) << e.what();
  }
  std::vector<std::string> notes;
  const Plc plc = read_plc((dir / "cube.off").string(), unmerged(), &notes);
  EXPECT_EQ(plc.facets.size(), 14u);  // 13 triangles + 1 from the split - the collinear one
  const ValidationReport report = validate_plc(plc);
  EXPECT_TRUE(report.ok()) << (report.problems.empty() ? "" : report.problems[0].message);
  EXPECT_DOUBLE_EQ(enclosed_volume(plc), 1.0);
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_NE(notes[0].find("face 13 (line 25) has collinear corners: dropped, and face 4 (line 16) across its long "
                          "edge split at its middle corner (0.5, 0, 0)"),
            std::string::npos)
      << notes[0];
  // Merged, the front and the bottom are squares with vertex 8 in their shared edge.
  const Plc merged = read_plc((dir / "cube.off").string());
  ASSERT_EQ(merged.facets.size(), 6u);
  std::size_t with_middle = 0;
  for (const Facet& f : merged.facets) {
    const auto& loop = f.polygons[0];
    with_middle += std::count_if(loop.begin(), loop.end(), [&](Index v) { return merged.vertices[v] == Point3{0.5, 0, 0}; });
  }
  EXPECT_EQ(with_middle, 2u);
  EXPECT_TRUE(validate_plc(merged).ok());
}

TEST(SurfaceRepair, CollinearTriangleWithoutANeighbourIsRefusedByItsNumber) {
  const auto dir = test::temp_dir("repair-refused");
  std::vector<std::string> triangles = kCubeTriangles;
  triangles.push_back("0 1 8");  // its long edge 0-1 is held the other way round by the bottom and by itself only
  triangles.push_back("1 0 5");  // a second face holding 1 -> 0 besides the bottom: no single neighbour
  test::write_text(dir / "bad.off", off_text(triangles));
  try {
    read_plc((dir / "bad.off").string());
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.code(), ErrorCode::DegenerateFacet);
    EXPECT_EQ(e.line(), 24);
    EXPECT_NE(std::string(e.what()).find("face 12 has zero area: its corners (0, 0, 0), (1, 0, 0), (0.5, 0, 0) are "
                                         "collinear; it is not repaired"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace qualmesh
