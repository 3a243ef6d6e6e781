// Tests of the mesh checker (mesh_check.h): a unit cube split into 6 (Kuhn) or 5 tetrahedra conforms to the cube
// PLC; a flipped, a missing and a duplicated tetrahedron are each reported; the reference volume of nested and
// disjoint shells and the area of a facet with a hole loop are exact.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "qualmesh/mesh_check.h"
#include "qualmesh/quality.h"

namespace qualmesh {
namespace {

// Vertex v of the cube [o, o+s]^3 has coordinates (bit 0, bit 1, bit 2) of v.
std::vector<Point3> cube_points(double s = 1, Point3 o = {0, 0, 0}) {
  std::vector<Point3> points;
  for (int v = 0; v < 8; ++v) points.push_back({o[0] + s * (v & 1), o[1] + s * ((v >> 1) & 1), o[2] + s * ((v >> 2) & 1)});
  return points;
}

// The six quadrilateral facets of that cube, vertex ids offset by `base`.
std::vector<Facet> cube_facets(Index base = 0) {
  const Index loops[6][4] = {{0, 2, 6, 4}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 5, 7, 6}};
  std::vector<Facet> facets;
  for (int f = 0; f < 6; ++f) {
    Facet facet;
    facet.polygons.push_back({loops[f][0] + base, loops[f][1] + base, loops[f][2] + base, loops[f][3] + base});
    facet.marker = f + 1;
    facets.push_back(facet);
  }
  return facets;
}

Plc cube_plc() {
  Plc plc;
  plc.vertices = cube_points();
  plc.facets = cube_facets();
  plc.name = "cube";
  return plc;
}

// Makes every tetrahedron positively oriented.
void orient(TetMesh& mesh) {
  for (auto& t : mesh.tets) {
    if (tet_signed_volume(mesh.points[t[0]], mesh.points[t[1]], mesh.points[t[2]], mesh.points[t[3]]) < 0) {
      std::swap(t[0], t[1]);
    }
  }
}

// Kuhn's split: the six tetrahedra along the diagonal 0-7, one per permutation of the axes.
TetMesh kuhn_cube() {
  TetMesh mesh;
  mesh.points = cube_points();
  int axes[3] = {0, 1, 2};
  do {
    const Index a = 1u << axes[0];
    const Index b = a | (1u << axes[1]);
    mesh.tets.push_back({0, a, b, 7});
  } while (std::next_permutation(axes, axes + 3));
  orient(mesh);
  return mesh;
}

// The 5-tetrahedron split: a central regular tetrahedron (0, 3, 5, 6) and four corners.
TetMesh five_tet_cube() {
  TetMesh mesh;
  mesh.points = cube_points();
  mesh.tets = {{0, 3, 5, 6}, {1, 0, 3, 5}, {2, 0, 3, 6}, {4, 0, 5, 6}, {7, 3, 5, 6}};
  orient(mesh);
  return mesh;
}

TEST(MeshCheck, KuhnCubeConforms) {
  const Plc plc = cube_plc();
  const CheckReport r = check_mesh(kuhn_cube(), &plc);
  EXPECT_TRUE(r.ok) << to_text(r);
  EXPECT_EQ(r.num_points, 8u);
  EXPECT_EQ(r.num_tets, 6u);
  EXPECT_EQ(r.num_boundary_faces, 12u);
  EXPECT_EQ(r.num_faces, 12u + 6u);
  EXPECT_EQ(r.num_nonpositive_tets, 0u);
  EXPECT_NEAR(r.mesh_volume, 1.0, 1e-15);
  EXPECT_NEAR(r.reference_volume, 1.0, 1e-15);
  EXPECT_LT(r.volume_relative_error, 1e-15);
  EXPECT_NEAR(r.facet_area, 6.0, 1e-15);
  EXPECT_NEAR(r.covered_area, 6.0, 1e-14);
  ASSERT_EQ(r.facets.size(), 6u);
  for (const FacetCoverage& f : r.facets) {
    EXPECT_NEAR(f.area, 1.0, 1e-15);
    EXPECT_NEAR(f.covered_area, 1.0, 1e-15);
  }
  EXPECT_EQ(r.num_faces_off_input, 0u);
  // Kuhn tetrahedra: right-angle corners; min dihedral 45 deg, max 90 deg... their dihedral angles are 45, 60, 90.
  EXPECT_NEAR(r.min_dihedral_deg, 45.0, 1e-12);
  EXPECT_NEAR(r.max_dihedral_deg, 90.0, 1e-12);
  EXPECT_NEAR(r.min_volume, 1.0 / 6.0, 1e-15);
  std::size_t total = 0;
  for (std::size_t c : r.dihedral_histogram) total += c;
  EXPECT_EQ(total, 36u);
  EXPECT_EQ(r.num_tets_min_dihedral_below_15, 0u);
}

TEST(MeshCheck, FiveTetCubeConforms) {
  const Plc plc = cube_plc();
  const CheckReport r = check_mesh(five_tet_cube(), &plc);
  EXPECT_TRUE(r.ok) << to_text(r);
  EXPECT_NEAR(r.mesh_volume, 1.0, 1e-15);
  EXPECT_NEAR(r.covered_area, 6.0, 1e-14);
  EXPECT_EQ(r.num_boundary_faces, 12u);
  // The central tetrahedron is regular: radius-edge sqrt(6)/4; the corners are right-corner tetrahedra.
  EXPECT_NEAR(r.max_radius_edge, std::sqrt(3.0) / 2.0, 1e-12);
}

TEST(MeshCheck, FlippedTetIsReported) {
  const Plc plc = cube_plc();
  TetMesh mesh = kuhn_cube();
  std::swap(mesh.tets[2][0], mesh.tets[2][1]);
  const CheckReport r = check_mesh(mesh, &plc);
  EXPECT_FALSE(r.ok);
  EXPECT_EQ(r.num_nonpositive_tets, 1u);
  EXPECT_NEAR(r.mesh_volume, 1.0 - 2.0 / 6.0, 1e-15);
  bool named = false;
  for (const auto& p : r.problems) named = named || p.find("tet 2: non-positive volume") != std::string::npos;
  EXPECT_TRUE(named) << to_text(r);
}

TEST(MeshCheck, MissingTetLeavesAGap) {
  const Plc plc = cube_plc();
  TetMesh mesh = kuhn_cube();
  mesh.tets.erase(mesh.tets.begin() + 3);
  const CheckReport r = check_mesh(mesh, &plc);
  EXPECT_FALSE(r.ok);
  // The removed tetrahedron had two faces on the cube and two inside: the inside ones are now off the input.
  EXPECT_EQ(r.num_faces_off_input, 2u);
  EXPECT_EQ(r.num_miscovered_facets, 2u);
  EXPECT_NEAR(r.volume_relative_error, 1.0 / 6.0, 1e-14);
}

TEST(MeshCheck, DuplicatedTetIsReported) {
  const Plc plc = cube_plc();
  TetMesh mesh = kuhn_cube();
  mesh.tets.push_back(mesh.tets[0]);
  const CheckReport r = check_mesh(mesh, &plc);
  EXPECT_FALSE(r.ok);
  EXPECT_EQ(r.num_duplicate_tets, 1u);
  EXPECT_EQ(r.num_overshared_faces, 2u);  // its two inner faces: three tetrahedra each
  EXPECT_EQ(r.num_folded_faces, 2u);      // its two hull faces: two tetrahedra on the same side
}

TEST(MeshCheck, WithoutReferenceOnlyStructure) {
  const CheckReport r = check_mesh(kuhn_cube(), nullptr);
  EXPECT_TRUE(r.ok) << to_text(r);
  EXPECT_FALSE(r.has_reference);
  EXPECT_EQ(r.num_boundary_faces, 12u);
}

TEST(MeshCheck, RegionInterfaceNeedsAnInternalFacet) {
  const Plc plc = cube_plc();
  TetMesh mesh = kuhn_cube();
  mesh.tet_region = {1, 1, 1, 2, 2, 2};
  const CheckReport r = check_mesh(mesh, &plc);
  EXPECT_GT(r.num_region_interface_faces, 0u);
  EXPECT_EQ(r.num_faces_off_input, r.num_region_interface_faces);
  EXPECT_FALSE(r.ok);
}

TEST(MeshCheck, InternalFacetInsideOneRegionIsCoveredByInteriorFaces) {
  // The diagonal plane x = y through the cube: Kuhn's tetrahedra have faces (0, 3, 7) and (0, 4, 7) on it.
  Plc plc = cube_plc();
  Facet internal;
  internal.polygons.push_back({0, 3, 7, 4});
  plc.facets.push_back(internal);
  const CheckReport r = check_mesh(kuhn_cube(), &plc);
  EXPECT_EQ(r.num_interior_faces_on_input, 2u);
  ASSERT_EQ(r.facets.size(), 7u);
  EXPECT_NEAR(r.facets[6].area, std::sqrt(2.0), 1e-15);
  EXPECT_NEAR(r.facets[6].covered_area, std::sqrt(2.0), 1e-15);
  // Internal facet: non-manifold edges, so the volume comes from the cells of the arrangement.
  EXPECT_EQ(r.reference_volume_method.rfind("cells", 0), 0u) << r.reference_volume_method;
  EXPECT_NEAR(r.reference_volume, 1.0, 1e-15);
  EXPECT_TRUE(r.ok) << to_text(r);
}

TEST(MeshCheck, ReferenceVolumeOfNestedAndDisjointShells) {
  Plc plc;
  plc.vertices = cube_points(1);
  plc.facets = cube_facets(0);
  const auto inner = cube_points(0.5, {0.25, 0.25, 0.25});
  plc.vertices.insert(plc.vertices.end(), inner.begin(), inner.end());
  auto inner_facets = cube_facets(8);
  // Reverse two inner loops: the checker orients each shell itself.
  std::reverse(inner_facets[0].polygons[0].begin(), inner_facets[0].polygons[0].end());
  plc.facets.insert(plc.facets.end(), inner_facets.begin(), inner_facets.end());
  CheckReport r = check_mesh(TetMesh{}, &plc);
  EXPECT_NEAR(r.reference_volume, 1.0 - 0.125, 1e-15) << r.reference_volume_method;

  const auto far = cube_points(2, {5, 0, 0});
  plc.vertices.insert(plc.vertices.end(), far.begin(), far.end());
  const auto far_facets = cube_facets(16);
  plc.facets.insert(plc.facets.end(), far_facets.begin(), far_facets.end());
  r = check_mesh(TetMesh{}, &plc);
  EXPECT_NEAR(r.reference_volume, 1.0 - 0.125 + 8.0, 1e-14) << r.reference_volume_method;
}

TEST(MeshCheck, OpenInputEnclosesNothing) {
  Plc plc = cube_plc();
  plc.facets.pop_back();
  const CheckReport r = check_mesh(kuhn_cube(), &plc);
  EXPECT_EQ(r.reference_volume, 0.0) << r.reference_volume_method;
  EXPECT_EQ(r.num_faces_off_input, 2u);  // the two faces on the missing facet
  EXPECT_FALSE(r.ok);
}

TEST(MeshCheck, TwoRegionsAndAVolumeHole) {
  // Three unit cubes in a row along x (internal facets at x = 1 and x = 2); a hole seed in the last one.
  Plc plc;
  for (int i = 0; i < 4; ++i) {
    for (int v = 0; v < 4; ++v) plc.vertices.push_back({double(i), double(v & 1), double((v >> 1) & 1)});
  }
  // Vertex (i, y, z) has id 4i + y + 2z.
  const auto id = [](int i, int y, int z) { return static_cast<Index>(4 * i + y + 2 * z); };
  const auto add = [&plc](std::vector<Index> loop) {
    Facet f;
    f.polygons.push_back(loop);
    plc.facets.push_back(f);
  };
  for (int i = 0; i < 4; ++i) add({id(i, 0, 0), id(i, 1, 0), id(i, 1, 1), id(i, 0, 1)});
  for (int i = 0; i < 3; ++i) {
    add({id(i, 0, 0), id(i + 1, 0, 0), id(i + 1, 0, 1), id(i, 0, 1)});
    add({id(i, 1, 0), id(i + 1, 1, 0), id(i + 1, 1, 1), id(i, 1, 1)});
    add({id(i, 0, 0), id(i + 1, 0, 0), id(i + 1, 1, 0), id(i, 1, 0)});
    add({id(i, 0, 1), id(i + 1, 0, 1), id(i + 1, 1, 1), id(i, 1, 1)});
  }
  CheckReport r = check_mesh(TetMesh{}, &plc);
  EXPECT_NEAR(r.reference_volume, 3.0, 1e-14) << r.reference_volume_method;
  plc.holes.push_back({2.5, 0.5, 0.5});
  r = check_mesh(TetMesh{}, &plc);
  EXPECT_NEAR(r.reference_volume, 2.0, 1e-14) << r.reference_volume_method;
  plc.holes.push_back({1.5, 0.5, 0.5});
  r = check_mesh(TetMesh{}, &plc);
  EXPECT_NEAR(r.reference_volume, 1.0, 1e-14) << r.reference_volume_method;
}

TEST(MeshCheck, FacetWithAHoleLoopAndAHolePoint) {
  Plc plc;
  plc.vertices = {{0, 0, 0}, {4, 0, 0}, {4, 4, 0}, {0, 4, 0}, {1, 1, 0}, {3, 1, 0}, {3, 3, 0}, {1, 3, 0},
                  {1.5, 1.5, 0}, {2.5, 1.5, 0}, {2.5, 2.5, 0}, {1.5, 2.5, 0}};
  Facet annulus;  // outer 4x4, inner loop 2x2: annulus of area 12, and an island of 1 inside the hole.
  annulus.polygons = {{0, 1, 2, 3}, {4, 5, 6, 7}, {8, 9, 10, 11}};
  plc.facets.push_back(annulus);
  CheckReport r = check_mesh(TetMesh{}, &plc);
  ASSERT_EQ(r.facets.size(), 1u);
  EXPECT_NEAR(r.facets[0].area, 16.0 - 4.0 + 1.0, 1e-14);
  // A hole point in the island removes it; one in the annulus removes the annulus.
  plc.facets[0].holes = {{2, 2, 0}};
  r = check_mesh(TetMesh{}, &plc);
  EXPECT_NEAR(r.facets[0].area, 12.0, 1e-14);
  plc.facets[0].holes = {{0.5, 0.5, 0}};
  r = check_mesh(TetMesh{}, &plc);
  EXPECT_NEAR(r.facets[0].area, 1.0, 1e-14);
}

TEST(MeshCheck, JsonHasStableKeysAndExactNumbers) {
  const Plc plc = cube_plc();
  const CheckReport r = check_mesh(kuhn_cube(), &plc);
  const std::string json = to_json(r);
  for (const char* key : {"\"ok\": true", "\"num_tets\": 6", "\"reference_volume\": 1",
                          "\"num_boundary_faces\": 12", "\"min_dihedral_deg\": 45", "\"problems\": []"}) {
    EXPECT_NE(json.find(key), std::string::npos) << key << "\n" << json;
  }
  EXPECT_NE(to_text(r).find("OK"), std::string::npos);
}

}  // namespace
}  // namespace qualmesh
