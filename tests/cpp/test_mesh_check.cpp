// Tests of the mesh checker (mesh_check.h): a unit cube split into 6 (Kuhn) or 5 tetrahedra conforms to the cube
// PLC; a flipped, a missing and a duplicated tetrahedron are each reported; the reference volume of nested and
// disjoint shells and the area of a facet with a hole loop are exact. Weighted Delaunay (regularity) test: a 2-3 flip
// configuration whose regular triangulation switches with the weights of its shared face, Delaunay and regular
// triangulations of random points built by CGAL (no false alarm), one 2-3 flip in them (exactly 3 faces flagged),
// and weights kept bit for bit through VTU and TetGen files and seen by `qualmesh check --require-regular`.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>
#include <random>
#include <type_traits>

#include <sys/wait.h>

#include <CGAL/Delaunay_triangulation_3.h>

#include "cgal_types.h"
#include "qualmesh/mesh_check.h"
#include "qualmesh/mesh_io.h"
#include "qualmesh/quality.h"
#include "sample_meshes.h"
#include "test_support.h"

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
  const CheckReport r = check_mesh(kuhn_unit_cube(), &plc);
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

TEST(MeshCheck, FacetsFlatOnlyToATolerancePassWithinIt) {
  // Corner 7 raised by 1e-7 (D = sqrt 3): the three facets through it are flat to about 2.5e-8 only (validate_plc
  // accepts them up to 1e-6 D, and --coplanar-tolerance makes such facets). A mesh on the same points lies on them
  // within twice that, far beyond the default distance tolerance of 1e-9 D, and passes.
  Plc plc = cube_plc();
  plc.vertices[7][2] += 1e-7;
  TetMesh mesh = kuhn_unit_cube();
  mesh.points = plc.vertices;
  const CheckReport r = check_mesh(mesh, &plc);
  EXPECT_TRUE(r.ok) << to_text(r);
  EXPECT_EQ(r.num_faces_off_input, 0u);
  EXPECT_EQ(r.num_miscovered_facets, 0u);
  // The same mesh with corner 7 a further 1e-6 up is off those facets: the allowance is the facets' own flatness.
  mesh.points[7][2] += 1e-6;
  const CheckReport off = check_mesh(mesh, &plc);
  EXPECT_FALSE(off.ok);
  EXPECT_GT(off.num_faces_off_input, 0u);
}

TEST(MeshCheck, FlippedTetIsReported) {
  const Plc plc = cube_plc();
  TetMesh mesh = kuhn_unit_cube();
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
  TetMesh mesh = kuhn_unit_cube();
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
  TetMesh mesh = kuhn_unit_cube();
  mesh.tets.push_back(mesh.tets[0]);
  const CheckReport r = check_mesh(mesh, &plc);
  EXPECT_FALSE(r.ok);
  EXPECT_EQ(r.num_duplicate_tets, 1u);
  EXPECT_EQ(r.num_overshared_faces, 2u);  // its two inner faces: three tetrahedra each
  EXPECT_EQ(r.num_folded_faces, 2u);      // its two hull faces: two tetrahedra on the same side
}

TEST(MeshCheck, WithoutReferenceOnlyStructure) {
  const CheckReport r = check_mesh(kuhn_unit_cube(), nullptr);
  EXPECT_TRUE(r.ok) << to_text(r);
  EXPECT_FALSE(r.has_reference);
  EXPECT_EQ(r.num_boundary_faces, 12u);
}

TEST(MeshCheck, RegionInterfaceNeedsAnInternalFacet) {
  const Plc plc = cube_plc();
  TetMesh mesh = kuhn_unit_cube();
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
  const CheckReport r = check_mesh(kuhn_unit_cube(), &plc);
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
  const CheckReport r = check_mesh(kuhn_unit_cube(), &plc);
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
  // Only the first cube is meshed. The facets of the two hole cubes, the one at x = 2 between them included, have
  // no tetrahedron on either side: nothing is to cover them, and the first cube's mesh conforms.
  r = check_mesh(kuhn_unit_cube(), &plc);
  ASSERT_EQ(r.facets.size(), 16u);
  for (std::size_t f = 0; f < 16; ++f) {
    const bool first_cube = f <= 1 || (f >= 4 && f <= 7);
    EXPECT_EQ(r.facets[f].bounds_domain, first_cube) << "facet " << f;
    EXPECT_EQ(r.facets[f].area, 1.0) << "facet " << f;
  }
  EXPECT_EQ(r.num_miscovered_facets, 0u);
  EXPECT_EQ(r.facet_area, 6.0);
  EXPECT_TRUE(r.ok) << to_text(r);
  // A face on a facet between two holes is a defect: a tetrahedron of the first cube moved into the second.
  TetMesh moved = kuhn_unit_cube();
  for (Point3& p : moved.points) p[0] += 1;
  r = check_mesh(moved, &plc);
  EXPECT_GT(r.facets[2].covered_area, 0.0);
  EXPECT_GE(r.num_miscovered_facets, 1u);
  EXPECT_FALSE(r.ok);
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
  const CheckReport r = check_mesh(kuhn_unit_cube(), &plc);
  const std::string json = to_json(r);
  for (const char* key : {"\"ok\": true", "\"num_tets\": 6", "\"reference_volume\": 1",
                          "\"num_boundary_faces\": 12", "\"min_dihedral_deg\": 45", "\"problems\": []"}) {
    EXPECT_NE(json.find(key), std::string::npos) << key << "\n" << json;
  }
  EXPECT_NE(to_text(r).find("OK"), std::string::npos);
}

// Five points for the 2-3 flip: triangle a, b, c (ids 0-2) in the plane z = 0 around the z axis, d (3) above and e
// (4) below it on the axis. Two tetrahedra (abcd, abce) share the face abc; three (deab, debc, deca) share the edge
// de. Lifting p to |p|^2 - w: with weight W on a, b and c and none on d, e, the hyperplane through the lifted a, b,
// c, d passes at 1.91 - 2W above e, whose lift is 0.09: the two-tet side is regular iff W > 0.91. Unweighted, e lies
// inside the circumsphere of abcd (the three-tet side is the Delaunay one).
TetMesh flip_points(double weight_abc) {
  TetMesh mesh;
  const double s = std::sqrt(3.0) / 2;
  mesh.points = {{1, 0, 0}, {-0.5, s, 0}, {-0.5, -s, 0}, {0, 0, 0.3}, {0, 0, -0.3}};
  if (weight_abc != 0) mesh.weights = {weight_abc, weight_abc, weight_abc, 0, 0};
  return mesh;
}

TetMesh two_tets(double weight_abc) {
  TetMesh mesh = flip_points(weight_abc);
  mesh.tets = {{0, 1, 2, 3}, {0, 1, 2, 4}};
  orient(mesh);
  return mesh;
}

TetMesh three_tets(double weight_abc) {
  TetMesh mesh = flip_points(weight_abc);
  mesh.tets = {{3, 4, 0, 1}, {3, 4, 1, 2}, {3, 4, 2, 0}};
  orient(mesh);
  return mesh;
}

TEST(MeshCheckRegularity, TwoThreeFlipFollowsTheWeights) {
  // Unweighted: the two-tet side fails on its one interior face, the three-tet side is Delaunay.
  CheckReport r = check_mesh(two_tets(0), nullptr);
  EXPECT_TRUE(r.weighted_delaunay_checked);
  EXPECT_EQ(r.num_regularity_tested_faces, 1u);
  EXPECT_EQ(r.num_non_regular_faces, 1u) << to_text(r);
  EXPECT_TRUE(r.ok) << "Report mode: counted, not a defect\n" << to_text(r);
  r = check_mesh(three_tets(0), nullptr);
  EXPECT_EQ(r.num_regularity_tested_faces, 3u);
  EXPECT_EQ(r.num_non_regular_faces, 0u) << to_text(r);
  // Weight 1 on a, b, c (> 0.91): now the two-tet side is the regular one and all three faces of the other fail.
  r = check_mesh(two_tets(1.0), nullptr);
  EXPECT_EQ(r.num_weighted_points, 3u);
  EXPECT_EQ(r.max_weight, 1.0);
  EXPECT_EQ(r.num_non_regular_faces, 0u) << to_text(r);
  r = check_mesh(three_tets(1.0), nullptr);
  EXPECT_EQ(r.num_non_regular_faces, 3u) << to_text(r);
  // Just either side of the threshold (0.91 is not a double; 0.90 and 0.92 are safely apart from it).
  EXPECT_EQ(check_mesh(two_tets(0.90), nullptr).num_non_regular_faces, 1u);
  EXPECT_EQ(check_mesh(two_tets(0.92), nullptr).num_non_regular_faces, 0u);
}

TEST(MeshCheckRegularity, RequireMakesViolationsProblemsAndSkipSkips) {
  CheckOptions options;
  options.regularity = RegularityCheck::Require;
  CheckReport r = check_mesh(two_tets(0), nullptr, options);
  EXPECT_FALSE(r.ok);
  EXPECT_EQ(r.num_problems, 1u);
  ASSERT_EQ(r.problems.size(), 1u);
  EXPECT_NE(r.problems[0].find("face (0, 1, 2)"), std::string::npos) << r.problems[0];
  EXPECT_TRUE(check_mesh(two_tets(1.0), nullptr, options).ok);
  options.regularity = RegularityCheck::Skip;
  r = check_mesh(two_tets(0), nullptr, options);
  EXPECT_FALSE(r.weighted_delaunay_checked);
  EXPECT_EQ(r.num_non_regular_faces, 0u);
  const std::string json = to_json(check_mesh(three_tets(1.0), nullptr));
  for (const char* key : {"\"weighted_delaunay_checked\": true", "\"num_non_regular_faces\": 3",
                          "\"num_weighted_points\": 3", "\"num_regularity_tested_faces\": 3"}) {
    EXPECT_NE(json.find(key), std::string::npos) << key << "\n" << json;
  }
}

TEST(MeshCheckRegularity, MalformedWeightsAreProblems) {
  TetMesh mesh = two_tets(1.0);
  mesh.weights.pop_back();
  CheckReport r = check_mesh(mesh, nullptr);
  EXPECT_FALSE(r.ok);
  EXPECT_FALSE(r.weighted_delaunay_checked);
  mesh = two_tets(1.0);
  mesh.weights[1] = std::nan("");
  r = check_mesh(mesh, nullptr);
  EXPECT_FALSE(r.ok);
  EXPECT_FALSE(r.weighted_delaunay_checked);
}

TEST(MeshCheckRegularity, CosphericalKuhnCubeIsDelaunay) {
  // All eight vertices on one sphere: every test is "orthogonal", which is not a violation.
  const CheckReport r = check_mesh(kuhn_unit_cube(), nullptr);
  EXPECT_TRUE(r.weighted_delaunay_checked);
  EXPECT_EQ(r.num_regularity_tested_faces, 6u);
  EXPECT_EQ(r.num_non_regular_faces, 0u);
}

// The finite cells of a CGAL (regular or Delaunay) triangulation as a TetMesh, with the weights when asked.
template <class Triangulation>
TetMesh mesh_of(const Triangulation& triangulation, bool with_weights) {
  TetMesh mesh;
  std::map<typename Triangulation::Vertex_handle, Index> ids;
  for (auto v = triangulation.finite_vertices_begin(); v != triangulation.finite_vertices_end(); ++v) {
    ids[v] = static_cast<Index>(mesh.points.size());
    const auto& p = triangulation.point(v);
    if constexpr (std::is_same_v<std::decay_t<decltype(p)>, detail::KWeightedPoint3>) {
      mesh.points.push_back({p.x(), p.y(), p.z()});
      if (with_weights) mesh.weights.push_back(p.weight());
    } else {
      mesh.points.push_back({p.x(), p.y(), p.z()});
    }
  }
  for (auto c = triangulation.finite_cells_begin(); c != triangulation.finite_cells_end(); ++c) {
    mesh.tets.push_back({ids[c->vertex(0)], ids[c->vertex(1)], ids[c->vertex(2)], ids[c->vertex(3)]});
  }
  return mesh;
}

std::vector<Point3> random_points(std::size_t n, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> unit(0, 1);
  std::vector<Point3> points(n);
  for (Point3& p : points) p = {unit(random), unit(random), unit(random)};
  return points;
}

// Applies one 2-3 flip to `mesh`: the first face abc of two tetrahedra abcd, abce whose edge de crosses the
// triangle's interior becomes the three tetrahedra around de. Returns false when no face allows it.
bool flip_two_three(TetMesh& mesh) {
  std::map<std::array<Index, 3>, std::vector<std::size_t>> tets_of_face;
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
    for (int skip = 0; skip < 4; ++skip) {
      std::array<Index, 3> key;
      int k = 0;
      for (int i = 0; i < 4; ++i) {
        if (i != skip) key[k++] = mesh.tets[t][i];
      }
      std::sort(key.begin(), key.end());
      tets_of_face[key].push_back(t);
    }
  }
  const auto opposite = [&mesh](std::size_t t, const std::array<Index, 3>& face) {
    for (Index v : mesh.tets[t]) {
      if (std::find(face.begin(), face.end(), v) == face.end()) return v;
    }
    return kNoIndex;
  };
  const auto volume = [&mesh](Index p, Index q, Index r, Index s) {
    return tet_signed_volume(mesh.points[p], mesh.points[q], mesh.points[r], mesh.points[s]);
  };
  for (const auto& [face, tets] : tets_of_face) {
    if (tets.size() != 2) continue;
    const Index d = opposite(tets[0], face), e = opposite(tets[1], face);
    const double v0 = volume(d, e, face[0], face[1]), v1 = volume(d, e, face[1], face[2]),
                 v2 = volume(d, e, face[2], face[0]);
    const double smallest = std::min({std::fabs(v0), std::fabs(v1), std::fabs(v2)});
    if (!((v0 > 0 && v1 > 0 && v2 > 0) || (v0 < 0 && v1 < 0 && v2 < 0)) || smallest < 1e-6) continue;
    const std::size_t first = std::min(tets[0], tets[1]), second = std::max(tets[0], tets[1]);
    mesh.tets.erase(mesh.tets.begin() + second);
    mesh.tets.erase(mesh.tets.begin() + first);
    mesh.tets.push_back({d, e, face[0], face[1]});
    mesh.tets.push_back({d, e, face[1], face[2]});
    mesh.tets.push_back({d, e, face[2], face[0]});
    orient(mesh);
    return true;
  }
  return false;
}

TEST(MeshCheckRegularity, DelaunayOfRandomPointsPassesAndOneFlipIsFlaggedThreeTimes) {
  const std::vector<Point3> points = random_points(2000, 7);
  CGAL::Delaunay_triangulation_3<detail::Kernel> delaunay;
  for (const Point3& p : points) delaunay.insert(detail::to_kpoint(p));
  TetMesh mesh = mesh_of(delaunay, false);
  orient(mesh);
  CheckReport r = check_mesh(mesh, nullptr);
  ASSERT_TRUE(r.ok) << to_text(r);
  EXPECT_GT(r.num_regularity_tested_faces, 10000u);
  EXPECT_EQ(r.num_non_regular_faces, 0u);
  // After one 2-3 flip: the three new faces around the flipped edge fail (each test involves the same five
  // points); the six outer faces do not (the old neighbours' circumspheres were empty).
  ASSERT_TRUE(flip_two_three(mesh));
  r = check_mesh(mesh, nullptr);
  EXPECT_EQ(r.num_nonpositive_tets + r.num_folded_faces + r.num_overshared_faces, 0u) << to_text(r);
  EXPECT_EQ(r.num_non_regular_faces, 3u) << to_text(r);
}

TEST(MeshCheckRegularity, RegularTriangulationOfWeightedPointsPasses) {
  const std::vector<Point3> points = random_points(1500, 11);
  std::mt19937 random(5);
  std::uniform_real_distribution<double> weight(0, 0.003);  // about (0.05)^2: some points get hidden
  detail::RegularTriangulation3 regular;
  for (const Point3& p : points) regular.insert(detail::KWeightedPoint3(detail::to_kpoint(p), weight(random)));
  TetMesh mesh = mesh_of(regular, true);
  orient(mesh);
  CheckReport r = check_mesh(mesh, nullptr);
  ASSERT_TRUE(r.ok) << to_text(r);
  EXPECT_GT(r.num_weighted_points, 1000u);
  EXPECT_EQ(r.num_non_regular_faces, 0u);
  // The same tetrahedra judged without their weights are not Delaunay; one flip adds exactly three violations.
  TetMesh unweighted = mesh;
  unweighted.weights.clear();
  const std::size_t unweighted_violations = check_mesh(unweighted, nullptr).num_non_regular_faces;
  EXPECT_GT(unweighted_violations, 0u);
  ASSERT_TRUE(flip_two_three(mesh));
  EXPECT_EQ(check_mesh(mesh, nullptr).num_non_regular_faces, 3u);
}

TEST(MeshCheckRegularity, WeightsRoundTripThroughVtuAndTetGen) {
  const auto dir = test::temp_dir("mesh-check-weights");
  TetMesh mesh = three_tets(1.0);
  mesh.weights = {1.0, 0.1 + 0.2, 1.0 / 3.0, 0, 5e-300};  // exact decimal round trip of awkward doubles
  const std::string path = (dir / "weighted.vtu").string();
  write_tet_mesh(mesh, path);
  const TetMesh back = read_tet_mesh(path);
  ASSERT_EQ(back.weights.size(), mesh.weights.size());
  for (std::size_t i = 0; i < mesh.weights.size(); ++i) EXPECT_EQ(back.weights[i], mesh.weights[i]) << i;
  // TetGen: the weight is vertex attribute 1, read back only from a .node file that QualMesh announced it in.
  const std::string node = (dir / "weighted.node").string();
  write_tet_mesh(mesh, node);
  const TetMesh back_tetgen = read_tet_mesh(node);
  ASSERT_EQ(back_tetgen.weights.size(), mesh.weights.size());
  for (std::size_t i = 0; i < mesh.weights.size(); ++i) EXPECT_EQ(back_tetgen.weights[i], mesh.weights[i]) << i;
  // No weights written, none read.
  TetMesh plain = three_tets(0);
  write_tet_mesh(plain, (dir / "plain.vtu").string());
  EXPECT_TRUE(read_tet_mesh((dir / "plain.vtu").string()).weights.empty());
  write_tet_mesh(plain, (dir / "plain.node").string());
  EXPECT_TRUE(read_tet_mesh((dir / "plain.node").string()).weights.empty());
  // The pumped-looking mesh judged from the file: regular with its weights (two tets), not with the three.
  write_tet_mesh(two_tets(1.0), (dir / "two.vtu").string());
  write_tet_mesh(three_tets(1.0), (dir / "three.vtu").string());
  EXPECT_EQ(check_mesh(read_tet_mesh((dir / "two.vtu").string()), nullptr).num_non_regular_faces, 0u);
  EXPECT_EQ(check_mesh(read_tet_mesh((dir / "three.vtu").string()), nullptr).num_non_regular_faces, 3u);
  // And through the CLI: --require-regular turns the violations into exit code 3.
  if (!std::filesystem::exists(test::qualmesh_exe())) GTEST_SKIP() << "qualmesh CLI not built";
  const auto run = [&](const std::string& file) {
    const std::string command = "'" + test::qualmesh_exe() + "' check --require-regular '" + (dir / file).string() +
                                "' > /dev/null";
    const int status = std::system(command.c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  };
  EXPECT_EQ(run("two.vtu"), 0);
  EXPECT_EQ(run("three.vtu"), 3);
}

}  // namespace
}  // namespace qualmesh
