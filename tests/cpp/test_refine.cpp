// Tests of the conforming Delaunay refinement engine (issue 3; Cheng & Dey Section 3.7, Rules 1-3) on generated
// non-acute PLCs: boxes, an L-shaped prism, a box with a box-shaped hole, stacked boxes sharing an internal facet,
// and a grid-aligned cluster of boxes. Properties asserted: every tetrahedron has radius-edge ratio <= rho0; exact
// conformity (volume and boundary area agree with the input to 1e-9; every boundary face lies on the input facet it
// names); the output is Delaunay (empty circumspheres, exact predicate); region ids; determinism.
#include <gtest/gtest.h>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <array>
#include <cmath>
#include <map>
#include <set>

#include "qualmesh/mesher.h"
#include "qualmesh/quality.h"

namespace {

using qualmesh::Index;
using qualmesh::Plc;
using qualmesh::Point3;
using K = CGAL::Epick;

// Adds an axis-aligned box [lo, hi] as 8 vertices and 6 quad facets (shared vertices merged by position).
struct PlcBuilder {
  Plc plc;
  std::map<Point3, Index> index;
  Index vertex(const Point3& p) {
    auto it = index.find(p);
    if (it != index.end()) return it->second;
    plc.vertices.push_back(p);
    return index[p] = Index(plc.vertices.size() - 1);
  }
  std::set<std::vector<Index>> seen;
  void quad(const Point3& a, const Point3& b, const Point3& c, const Point3& d) {
    std::vector<Index> loop{vertex(a), vertex(b), vertex(c), vertex(d)};
    std::vector<Index> key = loop;
    std::sort(key.begin(), key.end());
    if (!seen.insert(key).second) return;  // shared facet between two boxes: once
    qualmesh::Facet f;
    f.polygons.push_back(loop);
    plc.facets.push_back(f);
  }
  void box(const Point3& lo, const Point3& hi) {
    auto P = [&](int i, int j, int k) { return Point3{i ? hi[0] : lo[0], j ? hi[1] : lo[1], k ? hi[2] : lo[2]}; };
    quad(P(0, 0, 0), P(1, 0, 0), P(1, 1, 0), P(0, 1, 0));
    quad(P(0, 0, 1), P(1, 0, 1), P(1, 1, 1), P(0, 1, 1));
    quad(P(0, 0, 0), P(1, 0, 0), P(1, 0, 1), P(0, 0, 1));
    quad(P(0, 1, 0), P(1, 1, 0), P(1, 1, 1), P(0, 1, 1));
    quad(P(0, 0, 0), P(0, 1, 0), P(0, 1, 1), P(0, 0, 1));
    quad(P(1, 0, 0), P(1, 1, 0), P(1, 1, 1), P(1, 0, 1));
  }
};

Plc l_shape() {
  // L-shaped prism: the L polygon {(0,0),(2,0),(2,1),(1,1),(1,2),(0,2)} extruded to z in [0, 1].
  PlcBuilder b;
  const std::vector<std::array<double, 2>> l{{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};
  for (double z : {0.0, 1.0}) {
    qualmesh::Facet f;
    std::vector<Index> loop;
    for (const auto& q : l) loop.push_back(b.vertex({q[0], q[1], z}));
    f.polygons.push_back(loop);
    b.plc.facets.push_back(f);
  }
  for (std::size_t i = 0; i < l.size(); ++i) {
    const auto& p = l[i];
    const auto& q = l[(i + 1) % l.size()];
    b.quad({p[0], p[1], 0}, {q[0], q[1], 0}, {q[0], q[1], 1}, {p[0], p[1], 1});
  }
  return b.plc;
}

double sq_dist(const Point3& a, const Point3& b) {
  return (a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]);
}

double triangle_area(const Point3& a, const Point3& b, const Point3& c) {
  const Point3 u{b[0] - a[0], b[1] - a[1], b[2] - a[2]}, v{c[0] - a[0], c[1] - a[1], c[2] - a[2]};
  const Point3 n{u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
  return 0.5 * std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
}

// Area of a planar polygon facet (single loop).
double facet_area(const Plc& plc, const qualmesh::Facet& f) {
  const auto& loop = f.polygons[0];
  double area = 0;
  for (std::size_t i = 1; i + 1 < loop.size(); ++i) {
    // Signed fan areas via the Newell normal projection.
    (void)i;
  }
  Point3 n{0, 0, 0};
  for (std::size_t i = 0; i < loop.size(); ++i) {
    const Point3& p = plc.vertices[loop[i]];
    const Point3& q = plc.vertices[loop[(i + 1) % loop.size()]];
    n[0] += (p[1] - q[1]) * (p[2] + q[2]);
    n[1] += (p[2] - q[2]) * (p[0] + q[0]);
    n[2] += (p[0] - q[0]) * (p[1] + q[1]);
  }
  area = 0.5 * std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  return area;
}

struct Expect {
  double volume;
  double boundary_area;  // sum of the areas of all facets (each internal facet counted once)
};

void check_mesh_properties(const Plc& plc, const qualmesh::MeshResult& r, double rho0, const Expect& expect) {
  ASSERT_EQ(r.status, qualmesh::MeshStatus::Ok);
  const auto& m = r.mesh;
  ASSERT_FALSE(m.tets.empty());
  double volume = 0;
  double max_rho = 0;
  for (const auto& t : m.tets) {
    const auto q = qualmesh::tet_quality(m.points[t[0]], m.points[t[1]], m.points[t[2]], m.points[t[3]]);
    EXPECT_GT(q.volume, 0);
    volume += q.volume;
    max_rho = std::max(max_rho, q.radius_edge);
  }
  EXPECT_LE(max_rho, rho0 * (1 + 1e-12));
  EXPECT_NEAR(volume, expect.volume, 1e-9 * std::max(1.0, expect.volume));
  // Boundary faces: on their facet's plane, areas adding up per facet.
  std::vector<double> area(plc.facets.size(), 0);
  for (std::size_t i = 0; i < m.faces.size(); ++i) {
    const int f = m.face_facet[i];
    ASSERT_GE(f, 0) << "face " << i << " on no input facet";
    const auto& loop = plc.facets[f].polygons[0];
    const K::Point_3 a(plc.vertices[loop[0]][0], plc.vertices[loop[0]][1], plc.vertices[loop[0]][2]);
    const K::Point_3 b(plc.vertices[loop[1]][0], plc.vertices[loop[1]][1], plc.vertices[loop[1]][2]);
    const K::Point_3 c(plc.vertices[loop[2]][0], plc.vertices[loop[2]][1], plc.vertices[loop[2]][2]);
    for (Index v : m.faces[i]) {
      const auto& p = m.points[v];
      EXPECT_EQ(CGAL::orientation(a, b, c, K::Point_3(p[0], p[1], p[2])), CGAL::COPLANAR);
    }
    area[f] += triangle_area(m.points[m.faces[i][0]], m.points[m.faces[i][1]], m.points[m.faces[i][2]]);
  }
  double total = 0;
  for (std::size_t f = 0; f < plc.facets.size(); ++f) {
    EXPECT_NEAR(area[f], facet_area(plc, plc.facets[f]), 1e-9) << "facet " << f;
    total += area[f];
  }
  EXPECT_NEAR(total, expect.boundary_area, 1e-9 * std::max(1.0, expect.boundary_area));
  // Empty circumspheres (exact predicate), brute force.
  std::vector<K::Point_3> pts;
  for (const auto& p : m.points) pts.emplace_back(p[0], p[1], p[2]);
  std::size_t violations = 0;
  for (const auto& t : m.tets) {
    const K::Sphere_3 sphere(pts[t[0]], pts[t[1]], pts[t[2]], pts[t[3]]);
    for (std::size_t v = 0; v < pts.size(); ++v) {
      if (v == t[0] || v == t[1] || v == t[2] || v == t[3]) continue;
      if (CGAL::side_of_oriented_sphere(pts[t[0]], pts[t[1]], pts[t[2]], pts[t[3]], pts[v]) ==
          CGAL::ON_POSITIVE_SIDE)
        ++violations;
    }
    (void)sphere;
  }
  EXPECT_EQ(violations, 0u);
}

double box_area(double a, double b, double c) { return 2 * (a * b + b * c + a * c); }

class RefineRho : public ::testing::TestWithParam<double> {};

TEST_P(RefineRho, UnitBox) {
  PlcBuilder b;
  b.box({0, 0, 0}, {1, 1, 1});
  qualmesh::MeshOptions o;
  o.pump = false;  // Rules 1-3 only: the Delaunay check below is unweighted (pumping: test_pump.cpp)
  o.radius_edge_bound = GetParam();
  const auto r = qualmesh::mesh_plc(b.plc, o);
  check_mesh_properties(b.plc, r, GetParam(), {1.0, 6.0});
}

TEST_P(RefineRho, FlatBoxWithSizeLimit) {
  PlcBuilder b;
  b.box({0, 0, 0}, {3, 1, 0.25});
  qualmesh::MeshOptions o;
  o.pump = false;  // Rules 1-3 only: the Delaunay check below is unweighted (pumping: test_pump.cpp)
  o.radius_edge_bound = GetParam();
  o.max_edge_length = 0.3;
  const auto r = qualmesh::mesh_plc(b.plc, o);
  check_mesh_properties(b.plc, r, GetParam(), {0.75, box_area(3, 1, 0.25)});
  double max_edge = 0;
  for (const auto& t : r.mesh.tets)
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) max_edge = std::max(max_edge, sq_dist(r.mesh.points[t[i]], r.mesh.points[t[j]]));
  EXPECT_LE(std::sqrt(max_edge), 0.3);
}

TEST_P(RefineRho, LShape) {
  const Plc plc = l_shape();
  qualmesh::MeshOptions o;
  o.pump = false;  // Rules 1-3 only: the Delaunay check below is unweighted (pumping: test_pump.cpp)
  o.radius_edge_bound = GetParam();
  const auto r = qualmesh::mesh_plc(plc, o);
  check_mesh_properties(plc, r, GetParam(), {3.0, 2 * 3.0 + 8.0});
}

TEST_P(RefineRho, BoxWithBoxHole) {
  PlcBuilder b;
  b.box({0, 0, 0}, {3, 3, 3});
  b.box({1, 1, 1}, {2, 2, 2});
  b.plc.holes.push_back({1.5, 1.5, 1.5});
  qualmesh::MeshOptions o;
  o.pump = false;  // Rules 1-3 only: the Delaunay check below is unweighted (pumping: test_pump.cpp)
  o.radius_edge_bound = GetParam();
  const auto r = qualmesh::mesh_plc(b.plc, o);
  check_mesh_properties(b.plc, r, GetParam(), {26.0, 60.0});
}

TEST_P(RefineRho, StackedBoxesWithRegions) {
  PlcBuilder b;
  b.box({0, 0, 0}, {1, 1, 1});
  b.box({0, 0, 1}, {1, 1, 2});
  b.plc.regions.push_back({{0.5, 0.5, 0.5}, 7, 0});
  b.plc.regions.push_back({{0.5, 0.5, 1.5}, 9, 0.01});
  ASSERT_EQ(b.plc.facets.size(), 11u);
  qualmesh::MeshOptions o;
  o.pump = false;  // Rules 1-3 only: the Delaunay check below is unweighted (pumping: test_pump.cpp)
  o.radius_edge_bound = GetParam();
  const auto r = qualmesh::mesh_plc(b.plc, o);
  check_mesh_properties(b.plc, r, GetParam(), {2.0, 11.0});
  const auto& m = r.mesh;
  ASSERT_EQ(m.tet_region.size(), m.tets.size());
  for (std::size_t i = 0; i < m.tets.size(); ++i) {
    double z = 0;
    for (Index v : m.tets[i]) z += m.points[v][2] / 4;
    EXPECT_EQ(m.tet_region[i], z < 1 ? 7 : 9) << "tet " << i;
    if (m.tet_region[i] == 9) {
      const auto& t = m.tets[i];
      EXPECT_LE(qualmesh::tet_signed_volume(m.points[t[0]], m.points[t[1]], m.points[t[2]], m.points[t[3]]), 0.01);
    }
  }
  // The internal facet (z = 1) is listed once.
  std::size_t internal = 0;
  for (std::size_t i = 0; i < m.faces.size(); ++i) {
    bool on = true;
    for (Index v : m.faces[i]) on = on && m.points[v][2] == 1.0;
    internal += on;
  }
  EXPECT_GE(internal, 2u);
}

TEST_P(RefineRho, GridAlignedCluster) {
  // 3 x 2 x 2 unit boxes sharing facets: cospherical everywhere.
  PlcBuilder b;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 2; ++j)
      for (int k = 0; k < 2; ++k) b.box({double(i), double(j), double(k)}, {i + 1.0, j + 1.0, k + 1.0});
  qualmesh::MeshOptions o;
  o.pump = false;  // Rules 1-3 only: the Delaunay check below is unweighted (pumping: test_pump.cpp)
  o.radius_edge_bound = GetParam();
  const auto r = qualmesh::mesh_plc(b.plc, o);
  check_mesh_properties(b.plc, r, GetParam(), {12.0, double(b.plc.facets.size())});
}

INSTANTIATE_TEST_SUITE_P(Bounds, RefineRho, ::testing::Values(2.0, 1.5));

TEST(Refine, SizeLimitsAndDeterminism) {
  const Plc plc = l_shape();
  qualmesh::MeshOptions o;
  o.pump = false;  // Rules 1-3 only: the Delaunay check below is unweighted (pumping: test_pump.cpp)
  o.max_volume = 0.002;
  const auto a = qualmesh::mesh_plc(plc, o);
  const auto b = qualmesh::mesh_plc(plc, o);
  check_mesh_properties(plc, a, 2.0, {3.0, 14.0});
  EXPECT_GT(a.mesh.tets.size(), 1500u);
  EXPECT_EQ(a.mesh.points, b.mesh.points);
  EXPECT_EQ(a.mesh.tets, b.mesh.tets);
  EXPECT_EQ(a.mesh.faces, b.mesh.faces);
  EXPECT_EQ(a.mesh.face_facet, b.mesh.face_facet);
  for (const auto& t : a.mesh.tets)
    EXPECT_LE(qualmesh::tet_signed_volume(a.mesh.points[t[0]], a.mesh.points[t[1]], a.mesh.points[t[2]],
                                          a.mesh.points[t[3]]),
              0.002);
}

TEST(Refine, ProgressAndStats) {
  PlcBuilder b;
  b.box({0, 0, 0}, {2, 1, 1});
  std::size_t events = 0;
  bool saw_extraction = false;
  const auto r = qualmesh::mesh_plc(b.plc, {}, [&](const qualmesh::ProgressEvent& e) {
    ++events;
    EXPECT_GE(e.fraction, 0.0);
    EXPECT_LE(e.fraction, 1.0);
    saw_extraction = saw_extraction || e.stage == qualmesh::MeshStage::Extraction;
  });
  EXPECT_GT(events, 0u);
  EXPECT_TRUE(saw_extraction);
  EXPECT_EQ(r.stats.num_input_vertices, 8u);
  EXPECT_EQ(r.stats.num_tets, r.mesh.tets.size());
  EXPECT_EQ(r.mesh.points.size(), 8u + r.stats.num_steiner_vertices);
}

}  // namespace
