// The sized CAD surface mesh (converters/cad/size_field.cpp, face_mesh.cpp; issue 15) on a cylinder, a sphere and a
// torus (tests/data/cad, OpenCASCADE primitives written by gmsh's OCC kernel) and on part.step:
//  - the facets carry exactly the CAD face numbers 1..N, and the PLC is valid;
//  - every node of a face's facets lies on that CAD face (OpenCASCADE's distance, to 1e-7 of the diagonal: nodes
//    are surface points, not chord points);
//  - halving --size multiplies the surface nodes by 1.5 to 8 (less than 4 where curvature already sets the size)
//    and never lowers them; the volume mesh of the cylinder
//    grows by 4 to 12 times;
//  - a local size refines its face; a local size on a face that does not exist is refused by name;
//  - the same input gives the same PLC, bit for bit.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "qualmesh/cad_import.h"
#include "qualmesh/error.h"
#include "qualmesh/mesher.h"
#include "qualmesh/plc_validate.h"
#include "test_support.h"

namespace qualmesh {
namespace {

std::string model_path(const std::string& name) {
  if (name == "part.step") return test::shared_path("data/cad/part.step");
  return test::source_path("tests/data/cad/" + name);
}

CadModel read_sized(const std::string& name, double size, std::vector<CadLocalSize> local = {}) {
  CadOptions options;
  options.size = size;
  options.local_sizes = std::move(local);
  return read_cad(model_path(name), options);
}

double diagonal(const Plc& plc) {
  Point3 lo = plc.vertices.front(), hi = lo;
  for (const Point3& p : plc.vertices)
    for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], p[k]), hi[k] = std::max(hi[k], p[k]);
  return std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                   (hi[2] - lo[2]) * (hi[2] - lo[2]));
}

struct Case {
  const char* name;
  double size;
};
const Case kCases[] = {{"cylinder.brep", 5}, {"sphere.brep", 5}, {"torus.brep", 2}, {"part.step", 10}};

class SizedSurface : public ::testing::TestWithParam<Case> {};

TEST_P(SizedSurface, FaceIdsAreOneToNAndNodesLieOnTheirCadFaces) {
  const Case c = GetParam();
  QM_REQUIRE_FILE(model_path(c.name));
  const CadModel model = read_sized(c.name, c.size);
  ASSERT_TRUE(model.summary.surface_fallback.empty()) << model.summary.surface_fallback;
  EXPECT_TRUE(validate_plc(model.plc).ok());
  std::set<int> markers;
  for (const Facet& f : model.plc.facets) markers.insert(f.marker);
  ASSERT_EQ(markers.size(), model.summary.num_faces);
  EXPECT_EQ(*markers.begin(), 1);
  EXPECT_EQ(*markers.rbegin(), static_cast<int>(model.summary.num_faces));

  std::vector<Point3> points;
  std::vector<int> faces;
  std::set<std::pair<Index, int>> seen;
  for (const Facet& f : model.plc.facets)
    for (const auto& loop : f.polygons)
      for (Index v : loop)
        if (seen.insert({v, f.marker}).second) points.push_back(model.plc.vertices[v]), faces.push_back(f.marker);
  CadOptions options;
  options.size = c.size;
  const std::vector<double> d = distances_to_cad_faces(model_path(c.name), points, faces, options);
  const double tolerance = 1e-7 * diagonal(model.plc);
  double worst = 0;
  std::size_t beyond = 0;
  for (double x : d) worst = std::max(worst, x), beyond += x > tolerance;
  EXPECT_EQ(beyond, 0u) << c.name << ": largest distance " << worst << " (tolerance " << tolerance << ")";
}

TEST_P(SizedSurface, HalvingTheSizeRefinesAndTheOutputIsReproducible) {
  const Case c = GetParam();
  QM_REQUIRE_FILE(model_path(c.name));
  const CadModel coarse = read_sized(c.name, c.size), fine = read_sized(c.name, c.size / 2);
  const double ratio = double(fine.plc.vertices.size()) / coarse.plc.vertices.size();
  EXPECT_GE(ratio, 1.5) << coarse.plc.vertices.size() << " -> " << fine.plc.vertices.size();
  EXPECT_LE(ratio, 8.0) << coarse.plc.vertices.size() << " -> " << fine.plc.vertices.size();
  const CadModel again = read_sized(c.name, c.size);
  EXPECT_EQ(again.plc.vertices, coarse.plc.vertices);
  ASSERT_EQ(again.plc.facets.size(), coarse.plc.facets.size());
  for (std::size_t i = 0; i < again.plc.facets.size(); ++i) {
    EXPECT_EQ(again.plc.facets[i].polygons, coarse.plc.facets[i].polygons);
    EXPECT_EQ(again.plc.facets[i].marker, coarse.plc.facets[i].marker);
  }
}

INSTANTIATE_TEST_SUITE_P(Models, SizedSurface, ::testing::ValuesIn(kCases),
                         [](const ::testing::TestParamInfo<Case>& info) {
                           std::string name = info.param.name;
                           return name.substr(0, name.find('.'));
                         });

TEST(SizedSurface, LocalSizeRefinesItsFace) {
  QM_REQUIRE_FILE(model_path("part.step"));
  const CadModel plain = read_sized("part.step", 10);
  const CadModel local = read_sized("part.step", 10, {{CadLocalSize::Kind::Face, 26, 2.5}});
  auto count = [](const CadModel& m, int face) {
    std::set<Index> nodes;
    for (const Facet& f : m.plc.facets)
      if (f.marker == face)
        for (const auto& loop : f.polygons) nodes.insert(loop.begin(), loop.end());
    return nodes.size();
  };
  EXPECT_GT(count(local, 26), 4 * count(plain, 26));
  EXPECT_GT(local.plc.vertices.size(), plain.plc.vertices.size());
  try {
    read_sized("part.step", 10, {{CadLocalSize::Kind::Face, 27, 1}});
    FAIL() << "Face27 of a 26-face model was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.code(), ErrorCode::IndexOutOfRange);
    EXPECT_NE(e.message().find("Face27"), std::string::npos) << e.message();
  }
}

TEST(SizedSurface, HalvingTheSizeMultipliesTheCylinderTets) {
  QM_REQUIRE_FILE(model_path("cylinder.brep"));
  std::size_t previous = 0;
  for (double size : {5.0, 2.5}) {
    const CadModel model = read_sized("cylinder.brep", size);
    MeshOptions options;
    options.max_edge_length = size;
    const MeshResult result = mesh_plc(model.plc, options);
    ASSERT_EQ(result.status, MeshStatus::Ok);
    if (previous) {
      const double ratio = double(result.mesh.tets.size()) / previous;
      EXPECT_GE(ratio, 4.0) << previous << " -> " << result.mesh.tets.size();
      EXPECT_LE(ratio, 12.0) << previous << " -> " << result.mesh.tets.size();
    }
    previous = result.mesh.tets.size();
  }
}

}  // namespace
}  // namespace qualmesh
