// Tests of the tetrahedron quality measures (quality.h) on shapes whose figures are known in closed form.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "qualmesh/quality.h"

namespace qualmesh {
namespace {

const double kPi = 3.14159265358979323846;

TEST(TetQuality, RegularTetrahedron) {
  // Vertices of a cube alternately: edge 2 sqrt(2), circumradius sqrt(3).
  const Point3 a{1, 1, 1}, b{1, -1, -1}, c{-1, 1, -1}, d{-1, -1, 1};
  TetQuality q = tet_quality(a, b, c, d);
  if (q.volume < 0) q = tet_quality(a, c, b, d);
  EXPECT_NEAR(q.volume, 8.0 / 3.0, 1e-12);
  const double regular_dihedral_deg = std::acos(1.0 / 3.0) * 180.0 / kPi;
  EXPECT_NEAR(regular_dihedral_deg, 70.5288, 1e-4);
  EXPECT_NEAR(q.min_dihedral_deg, regular_dihedral_deg, 1e-10);
  EXPECT_NEAR(q.max_dihedral_deg, regular_dihedral_deg, 1e-10);
  EXPECT_NEAR(q.radius_edge, std::sqrt(6.0) / 4.0, 1e-12);
  EXPECT_NEAR(q.sigma, 1.0 / (6.0 * std::sqrt(2.0)), 1e-12);
  EXPECT_NEAR(q.shortest_edge, 2 * std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(q.longest_edge, 2 * std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(q.circumradius, std::sqrt(3.0), 1e-12);
  EXPECT_NEAR(tet_min_dihedral_deg(a, b, c, d), regular_dihedral_deg, 1e-10);
  EXPECT_NEAR(tet_radius_edge(a, b, c, d), std::sqrt(6.0) / 4.0, 1e-12);
}

TEST(TetQuality, RightCornerTetrahedron) {
  const Point3 o{0, 0, 0}, x{1, 0, 0}, y{0, 1, 0}, z{0, 0, 1};
  const TetQuality q = tet_quality(o, x, y, z);
  EXPECT_NEAR(q.volume, 1.0 / 6.0, 1e-15);
  EXPECT_NEAR(q.max_dihedral_deg, 90.0, 1e-12);
  // The angle between the slanted face x+y+z=1 and a coordinate plane: acos(1/sqrt(3)).
  EXPECT_NEAR(q.min_dihedral_deg, std::acos(1.0 / std::sqrt(3.0)) * 180.0 / kPi, 1e-12);
  EXPECT_NEAR(q.circumradius, std::sqrt(3.0) / 2.0, 1e-15);
  EXPECT_NEAR(q.radius_edge, std::sqrt(3.0) / 2.0, 1e-15);
  EXPECT_NEAR(q.sigma, 1.0 / 6.0, 1e-15);
  EXPECT_NEAR(q.shortest_edge, 1.0, 1e-15);
  EXPECT_NEAR(q.longest_edge, std::sqrt(2.0), 1e-15);
}

TEST(TetQuality, SliverOnASquare) {
  // Four corners of the unit square, one lifted by eps: a sliver. Good radius-edge ratio, tiny sigma.
  const double eps = 1e-6;
  const Point3 a{0, 0, 0}, b{1, 0, 0}, c{1, 1, eps}, d{0, 1, 0};
  TetQuality q = tet_quality(a, b, d, c);
  EXPECT_NEAR(std::fabs(q.volume), eps / 6.0, 1e-15);
  EXPECT_NEAR(q.sigma, eps / 6.0, 1e-15);
  EXPECT_NEAR(q.radius_edge, std::sqrt(2.0) / 2.0, 1e-6);
  EXPECT_LT(q.min_dihedral_deg, 1e-3);
  EXPECT_GT(q.max_dihedral_deg, 179.999);
}

TEST(TetQuality, FlatTetrahedronHasInfiniteRadiusEdge) {
  const Point3 a{0, 0, 0}, b{1, 0, 0}, c{1, 1, 0}, d{0, 1, 0};
  const TetQuality q = tet_quality(a, b, c, d);
  EXPECT_EQ(q.volume, 0.0);
  EXPECT_TRUE(std::isinf(q.radius_edge));
  EXPECT_TRUE(std::isinf(q.circumradius));
  EXPECT_EQ(q.sigma, 0.0);
  EXPECT_EQ(q.min_dihedral_deg, 0.0);
}

// A flat tetrahedron of joint.off's mesh (two input vertices and two Steiner points of one tilted facet: six times
// its volume is 5e-21 for edges near 0.02). The double formula gave radius-edge ratios from below 2 to 2.24
// depending on the vertex order; the exact value, from rational arithmetic outside the program, is
// 1.586202146040732, and the circumradius must come out the same double in all 24 orders.
TEST(TetQuality, NearlyFlatTetrahedronHasItsExactRadiusEdge) {
  const std::array<Point3, 4> p{Point3{0.060885876881281963, -0.42126664795479085, 0.21902527982443559},
                                Point3{0.045260899999999993, -0.39759100000000003, 0.239422},
                                Point3{0.029635899999999993, -0.39759100000000003, 0.239422},
                                Point3{0.060885888440640981, -0.40942882397739544, 0.22922363991221781}};
  std::array<int, 4> order{0, 1, 2, 3};
  int permutations = 0;
  const double first = tet_quality(p[0], p[1], p[2], p[3]).circumradius;
  do {
    const TetQuality q = tet_quality(p[order[0]], p[order[1]], p[order[2]], p[order[3]]);
    EXPECT_NEAR(q.radius_edge, 1.586202146040732, 1e-12) << order[0] << order[1] << order[2] << order[3];
    EXPECT_EQ(q.circumradius, first) << order[0] << order[1] << order[2] << order[3];  // the same in every order
    EXPECT_LT(q.min_dihedral_deg, 1e-9);
    ++permutations;
  } while (std::next_permutation(order.begin(), order.end()));
  EXPECT_EQ(permutations, 24);
}

// tet_quality and tet_min_dihedral_deg pick the smallest and largest dihedral angles by comparing (sin, cos) pairs
// and take two arctangents; the six angles of tet_dihedral_angles_deg are measured one by one. Both must agree,
// value for value, on ordinary, sliver, needle, cap and degenerate (repeated vertex, collinear) tetrahedra.
TEST(TetQuality, ExtremeDihedralAnglesMatchTheSixAngles) {
  std::uint64_t state = 12345;
  auto next = [&state]() {  // deterministic, in [-1, 1)
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return double(state >> 11) / double(1ull << 52) - 1.0;
  };
  std::vector<std::array<Point3, 4>> tets;
  for (int i = 0; i < 2000; ++i) {
    std::array<Point3, 4> t;
    for (auto& p : t) p = {next(), next(), next()};
    if (i % 4 == 1) t[3] = {0.25 * (t[0][0] + t[1][0] + t[2][0]) + 1e-7 * next(), 0.25 * (t[0][1] + t[1][1] + t[2][1]),
                            (t[0][2] + t[1][2] + t[2][2]) / 3};  // nearly on the plane of the other three
    if (i % 4 == 2) t[3] = {t[2][0] + 1e-6 * next(), t[2][1] + 1e-6 * next(), t[2][2]};  // a short edge
    tets.push_back(t);
  }
  tets.push_back({Point3{0, 0, 0}, Point3{1, 0, 0}, Point3{0, 1, 0}, Point3{0, 0, 0}});  // repeated vertex
  tets.push_back({Point3{0, 0, 0}, Point3{1, 0, 0}, Point3{2, 0, 0}, Point3{0, 1, 1}});  // three collinear
  tets.push_back({Point3{0, 0, 0}, Point3{1, 0, 0}, Point3{1, 1, 0}, Point3{0, 1, 0}});  // flat square
  for (std::size_t i = 0; i < tets.size(); ++i) {
    const auto& t = tets[i];
    const std::array<double, 6> six = tet_dihedral_angles_deg(t[0], t[1], t[2], t[3]);
    const double lo = *std::min_element(six.begin(), six.end()), hi = *std::max_element(six.begin(), six.end());
    const TetQuality q = tet_quality(t[0], t[1], t[2], t[3]);
    EXPECT_EQ(q.min_dihedral_deg, lo) << "tet " << i;
    EXPECT_EQ(q.max_dihedral_deg, hi) << "tet " << i;
    EXPECT_EQ(tet_min_dihedral_deg(t[0], t[1], t[2], t[3]), lo) << "tet " << i;
  }
}

TEST(TetQuality, SixAnglesMatchThePerEdgeFormula) {
  // The six angles come from four shared face normals (quality.cpp dihedral_pairs); here each is measured on its own,
  // from its edge e = b - a and the two other corners c, d: atan2(|e| |e . (u x v)|, (e x u) . (e x v)).
  auto sub = [](const Point3& a, const Point3& b) { return Point3{a[0] - b[0], a[1] - b[1], a[2] - b[2]}; };
  auto cross = [](const Point3& a, const Point3& b) {
    return Point3{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
  };
  auto dot = [](const Point3& a, const Point3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; };
  const int edges[6][4] = {{0, 1, 2, 3}, {0, 2, 1, 3}, {0, 3, 1, 2}, {1, 2, 0, 3}, {1, 3, 0, 2}, {2, 3, 0, 1}};
  std::uint64_t state = 777;
  auto next = [&state]() {  // deterministic, in [-1, 1)
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return double(state >> 11) / double(1ull << 52) - 1.0;
  };
  double worst = 0;
  for (int i = 0; i < 5000; ++i) {
    std::array<Point3, 4> t;
    for (auto& p : t) p = {next(), next(), next()};
    if (i % 3 == 1) t[3] = {t[2][0] + 1e-3 * next(), t[2][1] + 1e-3 * next(), t[2][2] + 1e-3 * next()};  // short edge
    const std::array<double, 6> six = tet_dihedral_angles_deg(t[0], t[1], t[2], t[3]);
    for (int k = 0; k < 6; ++k) {
      const Point3 &a = t[edges[k][0]], &b = t[edges[k][1]], &c = t[edges[k][2]], &d = t[edges[k][3]];
      const Point3 e = sub(b, a), u = sub(c, a), v = sub(d, a);
      const double expected = std::atan2(std::sqrt(dot(e, e)) * std::fabs(dot(e, cross(u, v))),
                                         dot(cross(e, u), cross(e, v))) * 180.0 / 3.14159265358979323846;
      worst = std::max(worst, std::fabs(six[k] - expected));
      ASSERT_NEAR(six[k], expected, 1e-7) << "tet " << i << " edge " << k;
    }
  }
  // Not vacuous: the tets span every angle, and a wrong sign or face would be off by degrees.
  EXPECT_LT(worst, 1e-7);
  EXPECT_NEAR(tet_dihedral_angles_deg({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1})[0], 90.0, 1e-12);
  EXPECT_NEAR(tet_dihedral_angles_deg({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1})[3], 54.735610317245346, 1e-9);
}

TEST(TetQuality, OrientationSign) {
  const Point3 o{0, 0, 0}, x{2, 0, 0}, y{0, 3, 0}, z{0, 0, 4};
  EXPECT_NEAR(tet_quality(o, x, y, z).volume, 4.0, 1e-14);
  EXPECT_NEAR(tet_quality(o, y, x, z).volume, -4.0, 1e-14);
  EXPECT_NEAR(tet_signed_volume(x, o, y, z), -4.0, 1e-14);
  // Every measure but the volume is independent of the order.
  const TetQuality p = tet_quality(o, x, y, z), n = tet_quality(o, y, x, z);
  EXPECT_DOUBLE_EQ(p.min_dihedral_deg, n.min_dihedral_deg);
  EXPECT_DOUBLE_EQ(p.radius_edge, n.radius_edge);
  EXPECT_DOUBLE_EQ(p.sigma, n.sigma);
}

TEST(TetQuality, ScaleInvariance) {
  const Point3 a{0.1, 0.2, 0.3}, b{1.4, 0.1, 0.2}, c{0.5, 1.7, 0.1}, d{0.3, 0.4, 1.9};
  const double s = 1e3;
  const Point3 as{a[0] * s, a[1] * s, a[2] * s}, bs{b[0] * s, b[1] * s, b[2] * s},
      cs{c[0] * s, c[1] * s, c[2] * s}, ds{d[0] * s, d[1] * s, d[2] * s};
  const TetQuality q = tet_quality(a, b, c, d), qs = tet_quality(as, bs, cs, ds);
  EXPECT_NEAR(q.radius_edge, qs.radius_edge, 1e-12);
  EXPECT_NEAR(q.sigma, qs.sigma, 1e-12);
  EXPECT_NEAR(q.min_dihedral_deg, qs.min_dihedral_deg, 1e-10);
  EXPECT_NEAR(qs.volume, q.volume * s * s * s, 1e-6 * std::fabs(qs.volume));
}

}  // namespace
}  // namespace qualmesh
