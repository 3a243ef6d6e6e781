// check_mesh far from the origin (issue 18 item 5): the same mesh and input, moved by a large offset, must check as
// they do at the origin. Before the checker worked in a local frame, a unit cube at 1e9 "enclosed 0" (its facets'
// projected areas cancelled to nothing) and joint.off at 1e6 reported a wrong enclosed volume.
#include <gtest/gtest.h>

#include <cmath>

#include "qualmesh/mesh_check.h"
#include "qualmesh/mesher.h"
#include "qualmesh/plc_io.h"
#include "qualmesh/quality.h"
#include "test_support.h"

namespace qualmesh {
namespace {

Point3 moved(const Point3& p, double d) { return {p[0] + d, p[1] + d, p[2] + d}; }

void move(Plc& plc, double d) {
  for (Point3& p : plc.vertices) p = moved(p, d);
  for (Point3& p : plc.holes) p = moved(p, d);
  for (Facet& f : plc.facets)
    for (Point3& p : f.holes) p = moved(p, d);
  for (RegionSeed& r : plc.regions) r.point = moved(r.point, d);
}

// The unit cube [d, d+1]^3 (six quadrilaterals) and Kuhn's six tetrahedra of it.
void unit_cube(double d, Plc& plc, TetMesh& mesh) {
  for (int v = 0; v < 8; ++v) plc.vertices.push_back(moved({double(v & 1), double((v >> 1) & 1), double(v >> 2)}, d));
  const Index loops[6][4] = {{0, 2, 6, 4}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 5, 7, 6}};
  for (const auto& l : loops) {
    Facet f;
    f.polygons.push_back({l[0], l[1], l[2], l[3]});
    plc.facets.push_back(f);
  }
  mesh.points = plc.vertices;
  const Index a[6] = {1, 1, 2, 2, 4, 4}, b[6] = {3, 5, 3, 6, 5, 6};
  for (int i = 0; i < 6; ++i) {
    std::array<Index, 4> t{0, a[i], b[i], 7};
    const auto& p = mesh.points;
    if (tet_signed_volume(p[t[0]], p[t[1]], p[t[2]], p[t[3]]) < 0) std::swap(t[0], t[1]);
    mesh.tets.push_back(t);
  }
}

TEST(MeshCheckPosition, UnitCubeFarFromTheOriginChecksClean) {
  for (double d : {0.0, 1e3, 1e9, 1e15, -1e15}) {
    Plc plc;
    TetMesh mesh;
    unit_cube(d, plc, mesh);
    const CheckReport r = check_mesh(mesh, &plc);
    EXPECT_TRUE(r.ok) << "offset " << d << "\n" << to_text(r);
    EXPECT_NEAR(r.reference_volume, 1.0, 1e-14) << d;
    EXPECT_NEAR(r.mesh_volume, 1.0, 1e-14) << d;
    EXPECT_NEAR(r.facet_area, 6.0, 1e-14) << d;
    EXPECT_NEAR(r.covered_area, 6.0, 1e-14) << d;
    EXPECT_EQ(r.num_faces_off_input, 0u) << d;
    EXPECT_EQ(r.num_miscovered_facets, 0u) << d;
  }
}

// A face near but off the cube is still refused far from the origin: the position term of the tolerance is a few
// ulps, not the model's size.
TEST(MeshCheckPosition, FaceOffTheInputIsStillFoundFarFromTheOrigin) {
  Plc plc;
  TetMesh mesh;
  unit_cube(1e9, plc, mesh);
  mesh.points[7][2] += 1e-5;  // 80 ulps at 1e9: the top facet's faces through vertex 7 leave the plane z = 1e9+1
  const CheckReport r = check_mesh(mesh, &plc);
  EXPECT_FALSE(r.ok);
  EXPECT_GT(r.num_faces_off_input, 0u) << to_text(r);
}

// joint.off moved by 1e6 and meshed there (the mesher works with exact predicates on the moved points): the mesh
// checks clean and the input encloses what it encloses at the origin (0.3595; the old checker said 4.45).
TEST(MeshCheckPosition, JointMovedBy1e6ChecksAsAtTheOrigin) {
  const std::string path = test::shared_path("data/plc/joint.off");
  QM_REQUIRE_FILE(path);
  const Plc plc = read_plc(path);
  MeshOptions options;
  options.pump = false;
  const CheckReport at_origin = check_mesh(mesh_plc(plc, options).mesh, &plc);
  ASSERT_TRUE(at_origin.ok) << to_text(at_origin);
  EXPECT_NEAR(at_origin.reference_volume, 0.3595, 1e-4);
  for (double d : {1e6, -1e6}) {
    Plc far = plc;
    move(far, d);
    const CheckReport r = check_mesh(mesh_plc(far, options).mesh, &far);
    EXPECT_TRUE(r.ok) << "offset " << d << "\n" << to_text(r);
    EXPECT_NEAR(r.reference_volume, at_origin.reference_volume, 1e-9 * at_origin.reference_volume) << d;
    EXPECT_NEAR(r.mesh_volume, at_origin.mesh_volume, 1e-8 * at_origin.mesh_volume) << d;
    EXPECT_EQ(r.num_faces_off_input, 0u) << d;
    EXPECT_EQ(r.num_miscovered_facets, 0u) << d;
  }
}

}  // namespace
}  // namespace qualmesh
