// merge_coplanar_facets(): boxes become squares, a through-hole gives an outer and an inner loop, facets touching
// at a vertex only, non-coplanar neighbours and folded coplanar neighbours stay apart, every vertex stays
// referenced, and the result is deterministic. With a tolerance: near-coplanar neighbours merge, a gently curved
// strip is cut into pieces that each stay within the tolerance of one plane, and pinion.off's rounded flat faces
// become TetGen's facets, which then mesh without a tet below 15 deg.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <vector>

#include "qualmesh/facet_merge.h"
#include "qualmesh/mesh_check.h"
#include "qualmesh/mesher.h"
#include "qualmesh/plc.h"
#include "qualmesh/plc_io.h"
#include "qualmesh/plc_validate.h"
#include "qualmesh/quality.h"
#include "test_support.h"

namespace qualmesh {
namespace {

Facet triangle(Index a, Index b, Index c, int marker = 0) {
  Facet f;
  f.polygons = {{a, b, c}};
  f.marker = marker;
  return f;
}

ReadOptions unmerged() {
  ReadOptions options;
  options.merge_coplanar = false;
  return options;
}

// Signed area of a loop projected on the xy plane (the test inputs are axis-aligned).
double signed_area_xy(const Plc& plc, const std::vector<Index>& loop) {
  double area = 0;
  for (std::size_t i = 0; i < loop.size(); ++i) {
    const Point3& p = plc.vertices[loop[i]];
    const Point3& q = plc.vertices[loop[(i + 1) % loop.size()]];
    area += p[0] * q[1] - q[0] * p[1];
  }
  return area / 2;
}

TEST(FacetMerge, BoxBecomesSixSquares) {
  const Plc raw = read_plc(test::source_path("tests/data/small/box.stl"), unmerged());
  ASSERT_EQ(raw.facets.size(), 12u);
  const Plc merged = merge_coplanar_facets(raw);
  ASSERT_EQ(merged.facets.size(), 6u);
  EXPECT_EQ(merged.vertices, raw.vertices);
  std::set<std::pair<Index, Index>> edges;
  for (const Facet& f : merged.facets) {
    ASSERT_EQ(f.polygons.size(), 1u);
    ASSERT_EQ(f.polygons[0].size(), 4u);
    // A square: its four vertices share one coordinate (0 or 1), so no diagonal survives.
    for (int axis = 0, flat = 0; axis < 3; ++axis) {
      bool same = true;
      for (Index v : f.polygons[0]) same = same && raw.vertices[v][axis] == raw.vertices[f.polygons[0][0]][axis];
      flat += same;
      if (axis == 2) EXPECT_EQ(flat, 1);
    }
  }
  EXPECT_EQ(collect_segments(merged).size(), 12u);  // the cube's 12 edges, no diagonals
  EXPECT_EQ(collect_segments(raw).size(), 18u);
}

TEST(FacetMerge, OrientationOfTheFirstFacetIsKept) {
  const Plc raw = read_plc(test::source_path("tests/data/small/box.stl"), unmerged());
  const Plc merged = merge_coplanar_facets(raw);
  // Facet 0 is the bottom z = 0, written with outward normal -z: clockwise seen from above.
  EXPECT_LT(signed_area_xy(merged, merged.facets[0].polygons[0]), 0);
  EXPECT_DOUBLE_EQ(signed_area_xy(merged, merged.facets[0].polygons[0]), -1.0);
  EXPECT_DOUBLE_EQ(signed_area_xy(merged, merged.facets[1].polygons[0]), 1.0);  // top, +z
}

TEST(FacetMerge, ThroughHoleGivesOuterAndInnerLoop) {
  const Plc raw = read_plc(test::source_path("tests/data/small/box_hole.off"), unmerged());
  ASSERT_EQ(raw.vertices.size(), 16u);
  ASSERT_EQ(raw.facets.size(), 32u);
  const Plc merged = merge_coplanar_facets(raw);
  // Top and bottom annuli, 4 outer walls, 4 inner walls.
  ASSERT_EQ(merged.facets.size(), 10u);
  int annuli = 0;
  for (const Facet& f : merged.facets) {
    if (f.polygons.size() == 1) {
      EXPECT_EQ(f.polygons[0].size(), 4u);
      continue;
    }
    ++annuli;
    ASSERT_EQ(f.polygons.size(), 2u);
    EXPECT_TRUE(f.holes.empty());  // implied by the odd-count rule
    const double outer = signed_area_xy(merged, f.polygons[0]);
    const double inner = signed_area_xy(merged, f.polygons[1]);
    EXPECT_DOUBLE_EQ(std::abs(outer), 9.0);
    EXPECT_DOUBLE_EQ(std::abs(inner), 1.0);
    EXPECT_LT(outer * inner, 0) << "inner loop runs the other way";
    for (Index v : f.polygons[1]) {
      EXPECT_GE(merged.vertices[v][0], 1.0);
      EXPECT_LE(merged.vertices[v][0], 2.0);
    }
  }
  EXPECT_EQ(annuli, 2);
}

TEST(FacetMerge, TrianglesSharingOnlyAVertexStayApart) {
  Plc plc;
  plc.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {-1, 0, 0}, {0, -1, 0}};
  plc.facets = {triangle(0, 1, 2), triangle(0, 3, 4)};
  const Plc merged = merge_coplanar_facets(plc);
  ASSERT_EQ(merged.facets.size(), 2u);
  EXPECT_EQ(merged.facets[0].polygons, plc.facets[0].polygons);
  EXPECT_EQ(merged.facets[1].polygons, plc.facets[1].polygons);
}

TEST(FacetMerge, NonCoplanarNeighboursStayApart) {
  Plc plc;
  // Two triangles over the edge (0,1); the apex of the second is lifted by 1e-12 (not exactly coplanar).
  plc.vertices = {{0, 0, 0}, {1, 0, 0}, {0.5, 1, 0}, {0.5, -1, 1e-12}};
  plc.facets = {triangle(0, 1, 2), triangle(1, 0, 3)};
  EXPECT_EQ(merge_coplanar_facets(plc).facets.size(), 2u);
  plc.vertices[3][2] = 0;  // now exactly coplanar: merged into one quadrilateral
  const Plc merged = merge_coplanar_facets(plc);
  ASSERT_EQ(merged.facets.size(), 1u);
  EXPECT_EQ(merged.facets[0].polygons, (std::vector<std::vector<Index>>{{0, 3, 1, 2}}));
}

TEST(FacetMerge, FoldedCoplanarNeighboursStayApart) {
  Plc plc;
  // Both apexes on the same side of the shared edge: the triangles overlap, merging would be wrong.
  plc.vertices = {{0, 0, 0}, {1, 0, 0}, {0.5, 1, 0}, {0.3, 0.5, 0}};
  plc.facets = {triangle(0, 1, 2), triangle(1, 0, 3)};
  EXPECT_EQ(merge_coplanar_facets(plc).facets.size(), 2u);
}

TEST(FacetMerge, EdgeUsedByThreeFacetsIsNotMergedAcross) {
  Plc plc;
  plc.vertices = {{0, 0, 0}, {1, 0, 0}, {0.5, 1, 0}, {0.5, -1, 0}, {0.5, 0, 1}};
  plc.facets = {triangle(0, 1, 2), triangle(1, 0, 3), triangle(0, 1, 4)};
  EXPECT_EQ(merge_coplanar_facets(plc).facets.size(), 3u);
}

TEST(FacetMerge, CollinearAndInteriorVerticesAreKept) {
  Plc plc;
  // A square split at its centre 4 into four triangles, with a collinear vertex 5 on its bottom side.
  plc.vertices = {{0, 0, 0}, {2, 0, 0}, {2, 2, 0}, {0, 2, 0}, {1, 1, 0}, {1, 0, 0}};
  plc.facets = {triangle(0, 5, 4, 7), triangle(5, 1, 4, 7), triangle(1, 2, 4, 7), triangle(2, 3, 4, 7),
                triangle(3, 0, 4, 7)};
  const Plc merged = merge_coplanar_facets(plc);
  ASSERT_EQ(merged.facets.size(), 1u);
  const Facet& f = merged.facets[0];
  EXPECT_EQ(f.marker, 7);
  ASSERT_EQ(f.polygons.size(), 2u);
  EXPECT_EQ(f.polygons[0], (std::vector<Index>{0, 5, 1, 2, 3}));  // collinear 5 kept
  EXPECT_EQ(f.polygons[1], (std::vector<Index>{4}));              // centre kept as an isolated vertex
}

TEST(FacetMerge, MarkerDroppedWhenFacetsDisagree) {
  Plc plc;
  plc.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  plc.facets = {triangle(0, 1, 2, 4), triangle(0, 2, 3, 5)};
  const Plc merged = merge_coplanar_facets(plc);
  ASSERT_EQ(merged.facets.size(), 1u);
  EXPECT_EQ(merged.facets[0].marker, 0);
  plc.facets[1].marker = 4;
  EXPECT_EQ(merge_coplanar_facets(plc).facets[0].marker, 4);
}

TEST(FacetMerge, TetgenFacetsWithHolesAreLeftAlone) {
  const std::string path = test::shared_path("data/plc/example.poly");
  QM_REQUIRE_FILE(path);
  const Plc plc = read_plc(path);
  const Plc merged = merge_coplanar_facets(plc);
  // Facets 1..4 of example.poly's bottom block are not coplanar with each other; multi-polygon facet 3 is skipped.
  ASSERT_EQ(merged.facets.size(), plc.facets.size());
  EXPECT_EQ(merged.facets[2].polygons, plc.facets[2].polygons);
  EXPECT_EQ(merged.facets[2].holes, plc.facets[2].holes);
}

TEST(FacetMerge, DeterministicAndIdempotent) {
  const std::string path = test::shared_path("data/plc/fandisk.off");
  QM_REQUIRE_FILE(path);
  const Plc raw = read_plc(path, unmerged());
  const Plc first = merge_coplanar_facets(raw);
  const Plc second = merge_coplanar_facets(raw);
  ASSERT_EQ(first.facets.size(), second.facets.size());
  for (std::size_t f = 0; f < first.facets.size(); ++f) {
    ASSERT_EQ(first.facets[f].polygons, second.facets[f].polygons);
    ASSERT_EQ(first.facets[f].marker, second.facets[f].marker);
  }
  EXPECT_LT(first.facets.size(), raw.facets.size());  // fandisk has flat CAD faces
  // Merging again changes nothing.
  const Plc again = merge_coplanar_facets(first);
  ASSERT_EQ(again.facets.size(), first.facets.size());
  for (std::size_t f = 0; f < first.facets.size(); ++f) EXPECT_EQ(again.facets[f].polygons, first.facets[f].polygons);
  // Every vertex stays referenced by some facet.
  std::vector<char> used(first.vertices.size(), 0);
  for (const Facet& f : first.facets)
    for (const auto& loop : f.polygons)
      for (Index v : loop) used[v] = 1;
  EXPECT_EQ(std::count(used.begin(), used.end(), 1), static_cast<long>(first.vertices.size()));
}

TEST(FacetMerge, NearCoplanarNeighboursMergeWithinTheTolerance) {
  Plc plc;
  // The apex of the second triangle is lifted by 1e-9; the diagonal D is sqrt(5).
  plc.vertices = {{0, 0, 0}, {1, 0, 0}, {0.5, 1, 0}, {0.5, -1, 1e-9}};
  plc.facets = {triangle(0, 1, 2), triangle(1, 0, 3)};
  EXPECT_EQ(merge_coplanar_facets(plc).facets.size(), 2u);         // exact rule
  EXPECT_EQ(merge_coplanar_facets(plc, 1e-10).facets.size(), 2u);  // 1e-9 > 1e-10 D
  const Plc merged = merge_coplanar_facets(plc, 1e-6);
  ASSERT_EQ(merged.facets.size(), 1u);
  EXPECT_EQ(merged.facets[0].polygons, (std::vector<std::vector<Index>>{{0, 3, 1, 2}}));
  EXPECT_EQ(merged.vertices, plc.vertices);  // nothing moves
  plc.vertices[3][2] = 1e-5;                 // beyond 1e-6 D
  EXPECT_EQ(merge_coplanar_facets(plc, 1e-6).facets.size(), 2u);
  plc.vertices[3] = {0.3, 0.5, 1e-9};  // folded onto the first triangle: never merged
  EXPECT_EQ(merge_coplanar_facets(plc, 1e-6).facets.size(), 2u);
}

TEST(FacetMerge, NearCoplanarGroupsStayWithinTheToleranceOfOnePlane) {
  // A strip of 2 x 40 triangles over z = c x^2: each pair of neighbours is coplanar within the tolerance, the whole
  // strip is not, so growing across neighbours alone would make one facet that validation refuses as non-planar.
  Plc plc;
  const int n = 40;
  const double c = 2e-7;
  for (int i = 0; i <= n; ++i) {
    plc.vertices.push_back({double(i), 0, c * i * i});
    plc.vertices.push_back({double(i), 1, c * i * i});
  }
  for (int i = 0; i < n; ++i) {
    const Index a = 2 * i, b = 2 * i + 2, d = 2 * i + 3, e = 2 * i + 1;
    plc.facets.push_back(triangle(a, b, d));
    plc.facets.push_back(triangle(a, d, e));
  }
  const double relative = 1e-6;
  const double tolerance = relative * bounding_box(plc).diagonal();
  ASSERT_GT(c * n * n / 4, tolerance);  // the strip's sag over one plane exceeds the tolerance
  const Plc merged = merge_coplanar_facets(plc, relative);
  EXPECT_GT(merged.facets.size(), 1u);
  EXPECT_LT(merged.facets.size(), plc.facets.size() / 4);
  for (const Facet& f : merged.facets) {
    // A piece over x in [lo, hi] is flat to its sag, the largest gap between z = c x^2 and its chord there; a piece
    // whose vertices lie within the tolerance of one plane has a sag of at most twice it.
    double lo = 1e300, hi = -1e300;
    for (const auto& loop : f.polygons)
      for (Index v : loop) lo = std::min(lo, plc.vertices[v][0]), hi = std::max(hi, plc.vertices[v][0]);
    const auto z = [&](double x) { return c * x * x; };
    double sag = 0;
    for (const auto& loop : f.polygons)
      for (Index v : loop) {
        const double x = plc.vertices[v][0];
        const double chord = z(lo) + (z(hi) - z(lo)) * (x - lo) / std::max(hi - lo, 1e-300);
        sag = std::max(sag, std::abs(chord - z(x)));
      }
    EXPECT_LE(sag, 2 * tolerance) << "facet spanning x in [" << lo << ", " << hi << "]";
  }
}

TEST(FacetMerge, PinionFlatFacesMergeWithinTheTolerance) {
  // pinion.off is a gear whose flat faces are strips of needle triangles (corners down to 1.33 deg), bent off one
  // plane by the file's rounding (adjacent normals 1e-4 to 1e-2 deg apart). TetGen merges them (it reports 227
  // facets and 695 segments). Exactly, the needles' corners are sharp input angles that Rule 3 may not refine:
  // the default mesh has 7001 tets below 10 deg (min 0.89); merged, none below 15 deg.
  const std::string path = test::shared_path("data/plc/pinion.off");
  QM_REQUIRE_FILE(path);
  const Plc exact = read_plc(path);
  ReadOptions options;
  options.coplanar_tolerance = 1e-6;
  const Plc plc = read_plc(path, options);
  EXPECT_EQ(exact.facets.size(), 1299u);
  EXPECT_EQ(plc.facets.size(), 238u);
  EXPECT_EQ(collect_segments(exact).size(), 1949u);
  EXPECT_EQ(collect_segments(plc).size(), 717u);
  EXPECT_EQ(plc.vertices, exact.vertices);
  ASSERT_TRUE(validate_plc(plc).ok());

  const MeshResult result = mesh_plc(plc, MeshOptions{});
  ASSERT_EQ(result.status, MeshStatus::Ok);
  const TetMesh& mesh = result.mesh;
  double min_dihedral = 180;
  std::size_t below_15 = 0;
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
    const auto& tet = mesh.tets[t];
    const double d = tet_min_dihedral_deg(mesh.points[tet[0]], mesh.points[tet[1]], mesh.points[tet[2]],
                                          mesh.points[tet[3]]);
    min_dihedral = std::min(min_dihedral, d);
    below_15 += d < 15;
  }
  EXPECT_GE(min_dihedral, 14.99);  // TetGen -pq2: 5.23 deg, 239 tets below 10
  EXPECT_EQ(below_15, 0u);
  EXPECT_LT(mesh.points.size(), 1.2 * 4424);  // TetGen's vertex count
  // Conformity: to the merged facets (the checker allows each facet its own flatness), and the volume within 1e-8
  // of the exact surface's.
  const CheckReport merged_report = check_mesh(mesh, &plc);
  EXPECT_TRUE(merged_report.ok) << to_text(merged_report);
  EXPECT_EQ(merged_report.num_nonpositive_tets, 0u);
  EXPECT_EQ(merged_report.num_faces_off_input, 0u);
  EXPECT_EQ(merged_report.num_miscovered_facets, 0u);
  EXPECT_LT(merged_report.max_facet_area_relative_error, 1e-8);
  const CheckReport exact_report = check_mesh(mesh, &exact);
  EXPECT_LT(exact_report.volume_relative_error, 1e-8);
}

TEST(FacetMerge, ReaderSuggestsTheToleranceAndMergesTetgenFilesWhenAsked) {
  const std::string path = test::shared_path("data/plc/joint.off");
  QM_REQUIRE_FILE(path);
  std::vector<std::string> notes;
  const Plc exact = read_plc(path, ReadOptions{}, &notes);
  ASSERT_EQ(exact.facets.size(), 130u);
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_NE(notes[0].find("130 facets after merging exactly coplanar ones; 109 with --coplanar-tolerance 1e-6"),
            std::string::npos) << notes[0];
  notes.clear();
  read_plc(test::source_path("tests/data/small/box.stl"), ReadOptions{}, &notes);  // exactly flat: nothing to say
  EXPECT_TRUE(notes.empty());

  // A TetGen file is merged only when a tolerance is asked for.
  const auto dir = test::temp_dir("facet-merge-poly");
  const std::string poly = (dir / "joint.poly").string();
  write_plc(read_plc(path, unmerged()), poly);
  EXPECT_EQ(read_plc(poly).facets.size(), 446u);
  ReadOptions options;
  options.coplanar_tolerance = 1e-6;
  EXPECT_EQ(read_plc(poly, options).facets.size(), 109u);
}

}  // namespace
}  // namespace qualmesh
