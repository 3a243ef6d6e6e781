// merge_coplanar_facets(): boxes become squares, a through-hole gives an outer and an inner loop, facets touching
// at a vertex only, non-coplanar neighbours and folded coplanar neighbours stay apart, every vertex stays
// referenced, and the result is deterministic.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <vector>

#include "qualmesh/facet_merge.h"
#include "qualmesh/plc.h"
#include "qualmesh/plc_io.h"
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

}  // namespace
}  // namespace qualmesh
