// Local feature size f(x) (paper Section 2): the best-first tree search agrees exactly with the definition
// evaluated by brute force over every non-adjacent pair, at random points, for several PLCs; and known values.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "local_feature_size.h"
#include "qualmesh/size_estimate.h"

namespace qualmesh {
namespace {

using Triangles = std::vector<std::vector<std::array<Index, 3>>>;

// Axis-aligned box as 6 quads (outward order irrelevant here), appended to `plc`.
void add_box(Plc& plc, const Point3& lo, const Point3& hi) {
  const Index base = static_cast<Index>(plc.vertices.size());
  for (int k = 0; k < 8; ++k) {
    plc.vertices.push_back({(k & 1) ? hi[0] : lo[0], (k & 2) ? hi[1] : lo[1], (k & 4) ? hi[2] : lo[2]});
  }
  const int quads[6][4] = {{0, 1, 3, 2}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    Facet f;
    f.polygons.push_back({base + q[0], base + q[1], base + q[2], base + q[3]});
    plc.facets.push_back(f);
  }
}

// Fan triangulation of convex facets (all facets in these tests are convex single polygons).
Triangles fan_triangles(const Plc& plc) {
  Triangles result;
  for (const Facet& f : plc.facets) {
    std::vector<std::array<Index, 3>> tris;
    const auto& loop = f.polygons.front();
    for (std::size_t i = 1; i + 1 < loop.size(); ++i) tris.push_back({loop[0], loop[i], loop[i + 1]});
    result.push_back(tris);
  }
  return result;
}

Plc icosahedron() {
  Plc plc;
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  plc.vertices = {{-1, t, 0}, {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                  {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
  const int faces[20][3] = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                            {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                            {3, 8, 9},  {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (const auto& f : faces) {
    Facet facet;
    facet.polygons.push_back({Index(f[0]), Index(f[1]), Index(f[2])});
    plc.facets.push_back(facet);
  }
  return plc;
}

void expect_tree_equals_brute_force(const Plc& plc, int samples, unsigned seed) {
  const LocalFeatureSize lfs(plc, fan_triangles(plc));
  const BoundingBox box = bounding_box(plc);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(-0.2, 1.2);
  for (int i = 0; i < samples; ++i) {
    Point3 x;
    for (int k = 0; k < 3; ++k) x[k] = box.min[k] + unit(rng) * (box.max[k] - box.min[k]);
    ASSERT_EQ(lfs(x), lfs.brute_force(x)) << "at (" << x[0] << ", " << x[1] << ", " << x[2] << ")";
  }
  // At every vertex too (where refinement evaluates it).
  for (const Point3& v : plc.vertices) ASSERT_EQ(lfs(v), lfs.brute_force(v));
}

TEST(LocalFeatureSize, UnitCubeKnownValues) {
  Plc cube;
  add_box(cube, {0, 0, 0}, {1, 1, 1});
  const LocalFeatureSize lfs(cube, fan_triangles(cube));
  // Elements: 8 vertices, 12 segments, 6 facets.
  EXPECT_EQ(lfs.num_elements(), 26u);
  // Centre: every facet at 0.5; opposite facets share no vertex.
  EXPECT_DOUBLE_EQ(lfs({0.5, 0.5, 0.5}), 0.5);
  // At a corner the nearest non-adjacent elements are one edge length away.
  EXPECT_DOUBLE_EQ(lfs({0, 0, 0}), 1.0);
  // Middle of an edge: its two end vertices are 0.5 away and, being distinct vertices, non-adjacent.
  EXPECT_DOUBLE_EQ(lfs({0.5, 0, 0}), 0.5);
  // Just off the centre of a facet: the opposite facet (no shared vertex) is 0.9 away, the four side facets
  // are 0.5 away but each shares vertices with the near facet and with its neighbours; the two opposite side
  // facets share no vertex, so f = 0.5.
  EXPECT_DOUBLE_EQ(lfs({0.5, 0.5, 0.1}), 0.5);
}

TEST(LocalFeatureSize, ThinSlabIsSmallInside) {
  Plc slab;
  add_box(slab, {0, 0, 0}, {1, 1, 0.01});
  const LocalFeatureSize lfs(slab, fan_triangles(slab));
  EXPECT_DOUBLE_EQ(lfs({0.5, 0.5, 0.005}), 0.005);
  EXPECT_DOUBLE_EQ(lfs({0.5, 0.5, 0.0}), 0.01);  // on the bottom facet: the top is 0.01 away
}

TEST(LocalFeatureSize, TreeAgreesWithBruteForceOnBoxes) {
  Plc cube;
  add_box(cube, {0, 0, 0}, {1, 1, 1});
  expect_tree_equals_brute_force(cube, 500, 1);

  Plc nested;  // a box with a box-shaped cavity: two shells
  add_box(nested, {0, 0, 0}, {3, 2, 1});
  add_box(nested, {1, 0.5, 0.25}, {2, 1.5, 0.75});
  expect_tree_equals_brute_force(nested, 500, 2);

  Plc cluster;  // grid-aligned cluster of disjoint boxes with equal coordinates (ties everywhere)
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) add_box(cluster, {2.0 * i, 2.0 * j, 0}, {2.0 * i + 1, 2.0 * j + 1, 1});
  expect_tree_equals_brute_force(cluster, 500, 3);
}

TEST(LocalFeatureSize, TreeAgreesWithBruteForceOnTriangulatedSurface) {
  expect_tree_equals_brute_force(icosahedron(), 1000, 4);
}

// The size estimate (size_estimate.h) integrates dA / f^2 over the facets. On a slab 1 x 1 x t, f = t on the top and
// bottom faces (the pair top/bottom), so the integral is 2 / t^2 plus the sides' small share (area 4t, f >= t/2
// there: at most 16 / t): exact to the sampling, since f is constant over the big faces.
TEST(SizeEstimate, ThinSlabIntegralIsTwoOverThicknessSquared) {
  for (const double t : {1e-2, 1e-4}) {
    Plc slab;
    add_box(slab, {0, 0, 0}, {1, 1, t});
    const FeatureSizeEstimate e = estimate_from_feature_size(slab);
    EXPECT_GE(e.surface_integral, 2 / (t * t)) << t;
    EXPECT_LE(e.surface_integral, 2 / (t * t) + 16 / t) << t;
    EXPECT_DOUBLE_EQ(e.tets, 0.5 * e.surface_integral);  // the calibrated lower bound: 0.5 tets per unit
    EXPECT_LE(e.samples, 8192u + 12u);                   // the default budget (one more piece per triangle at most)
    const FeatureSizeEstimate again = estimate_from_feature_size(slab);
    EXPECT_EQ(again.surface_integral, e.surface_integral);  // deterministic
  }
}

// More facet triangles than samples: every k-th triangle is sampled at its centroid and the integral scaled by
// area. The unit cube's 12 triangles with a budget of 4 (every 3rd triangle) against a fine sampling of all 12: the
// cube's symmetry makes the coarse one close (f is 1 over most of each face, the opposite face).
TEST(SizeEstimate, StrideSamplingOfManyTrianglesScalesByArea) {
  Plc cube;
  add_box(cube, {0, 0, 0}, {1, 1, 1});
  const FeatureSizeEstimate fine = estimate_from_feature_size(cube);
  EXPECT_GT(fine.samples, 8000u);
  const FeatureSizeEstimate strided = estimate_from_feature_size(cube, 4);
  EXPECT_EQ(strided.samples, 4u);
  EXPECT_NEAR(strided.surface_integral, fine.surface_integral, 0.5 * fine.surface_integral)
      << strided.surface_integral << " against " << fine.surface_integral;
}

}  // namespace
}  // namespace qualmesh
