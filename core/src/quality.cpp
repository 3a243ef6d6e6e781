// Quality measures of a tetrahedron (paper Section 2: rho = R / L, sigma = V / L^3) and its dihedral angles.
//
// Dihedral angle at edge e = (a, b) between the faces (a, b, c) and (a, b, d): with u = c - a, v = d - a, the
// face normals are n1 = e x u and n2 = e x v, and the identity (e x u) x (e x v) = (e . (u x v)) e gives
// |n1 x n2| = |e| |det(e, u, v)|. So angle = atan2(|e| |det|, n1 . n2): accurate for both tiny and nearly
// straight angles (acos loses precision there).
//
// Circumcentre relative to p0, with a = p1 - p0, b = p2 - p0, c = p3 - p0:
//   x = (|a|^2 (b x c) + |b|^2 (c x a) + |c|^2 (a x b)) / (2 a . (b x c)),  R = |x|.
// For a nearly flat tetrahedron (|a . (b x c)| below 1e-10 of the longest edge cubed) rounding makes that quotient
// meaningless and dependent on the vertex order (joint.off: a flat cell on a tilted facet measured 2.24 in one
// order, below 2 in another, 1.59 exactly), so R^2 is then computed from exact big-float products.
#include "qualmesh/quality.h"

#include <CGAL/Gmpzf.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>
#include <utility>

#include "vec3.h"

namespace qualmesh {
namespace {

using namespace vec3;

constexpr double kRadToDeg = 180.0 / 3.14159265358979323846;

// Circumradius of a tetrahedron whose points are exact (doubles), in exact arithmetic: see the file comment.
// R^2 = |num|^2 / (4 det^2). Both are products of differences of doubles, exact in big floats (Gmpzf: no gcd, unlike
// rationals, hence several times faster), and both are independent of the vertex order (det^2, and 4 det^2 R^2);
// each is rounded once to double, so R is within about two ulps of the exact value, whatever the order.
double exact_circumradius(const Point3& p0, const Point3& p1, const Point3& p2, const Point3& p3) {
  using F = CGAL::Gmpzf;
  using FVec = std::array<F, 3>;
  auto fsub = [](const Point3& u, const Point3& v) -> FVec {
    return FVec{F(u[0]) - F(v[0]), F(u[1]) - F(v[1]), F(u[2]) - F(v[2])};
  };
  auto fdot = [](const FVec& u, const FVec& v) -> F { return u[0] * v[0] + u[1] * v[1] + u[2] * v[2]; };
  auto fcross = [](const FVec& u, const FVec& v) -> FVec {
    return FVec{u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
  };
  const FVec a = fsub(p1, p0), b = fsub(p2, p0), c = fsub(p3, p0);
  const FVec bc = fcross(b, c), ca = fcross(c, a), ab = fcross(a, b);
  const F det = fdot(a, bc);
  if (CGAL::is_zero(det)) return std::numeric_limits<double>::infinity();
  const F sa = fdot(a, a), sb = fdot(b, b), sc = fdot(c, c);
  const FVec num{sa * bc[0] + sb * ca[0] + sc * ab[0], sa * bc[1] + sb * ca[1] + sc * ab[1],
                 sa * bc[2] + sb * ca[2] + sc * ab[2]};
  const double sq_num = CGAL::to_double(fdot(num, num)), sq_den = CGAL::to_double(F(4) * det * det);
  return std::sqrt(sq_num / sq_den);
}

// The dihedral angle at edge (a, b) between faces (a, b, c) and (a, b, d) as the pair (|n1 x n2|, n1 . n2) whose
// atan2 it is (see the file comment): sin_part >= 0, so the angle is in [0, 180] degrees.
struct AnglePair {
  double sin_part, cos_part;
};

double to_deg(const AnglePair& a) { return std::atan2(a.sin_part, a.cos_part) * kRadToDeg; }

// Edges (i, j) with the opposite pair (k, l), in the order of tet_dihedral_angles_deg.
const int kEdges[6][4] = {{0, 1, 2, 3}, {0, 2, 1, 3}, {0, 3, 1, 2}, {1, 2, 0, 3}, {1, 3, 0, 2}, {2, 3, 0, 1}};

// The six pairs, in kEdges order. For edge (a, b) with the others c, d (kEdges[i]), n1 = (b - a) x (c - a) is the
// oriented normal of triangle (a, b, c) and n2 = (b - a) x (d - a) that of (a, b, d). So each is the normal of a face
// with its vertices in increasing order (face k: the one opposite vertex k, 4 cross products in all) signed by the
// parity of (a, b, c) or (a, b, d) as a permutation of that order, and |e . (u x v)| = 6 |volume| for every edge.
void dihedral_pairs(const Point3* const p[4], AnglePair out[6]) {
  const Vec e01 = sub(*p[1], *p[0]), e02 = sub(*p[2], *p[0]), e03 = sub(*p[3], *p[0]);
  const Vec e12 = sub(*p[2], *p[1]), e13 = sub(*p[3], *p[1]), e23 = sub(*p[3], *p[2]);
  const Vec f3 = cross(e01, e02), f2 = cross(e01, e03), f1 = cross(e02, e03), f0 = cross(e12, e13);
  const double six_vol = std::fabs(dot(e01, f1));
  out[0] = {norm(e01) * six_vol, dot(f3, f2)};
  out[1] = {norm(e02) * six_vol, -dot(f3, f1)};
  out[2] = {norm(e03) * six_vol, dot(f2, f1)};
  out[3] = {norm(e12) * six_vol, dot(f3, f0)};
  out[4] = {norm(e13) * six_vol, -dot(f2, f0)};
  out[5] = {norm(e23) * six_vol, dot(f1, f0)};
}

// The smallest and largest of the six dihedral angles, in degrees, with two atan2 calls instead of six: for angles
// x = atan2(s1, c1) and y = atan2(s2, c2) in (0, pi) (s1, s2 > 0), x - y is in (-pi, pi), so x < y exactly when
// sin(x - y) < 0, i.e. s1 c2 - c1 s2 < 0. A flat tetrahedron (s = 0: angles of exactly 0 or 180 degrees, whose
// difference pi the test cannot see) or a non-finite pair falls back to measuring all six. Without `with_max` the
// largest is not measured (returned as 0): one atan2 call.
std::pair<double, double> min_max_dihedral_deg(const Point3* const p[4], bool with_max = true) {
  AnglePair a[6];
  dihedral_pairs(p, a);
  bool plain = true;
  for (const AnglePair& x : a)
    plain = plain && std::isfinite(x.sin_part) && std::isfinite(x.cos_part) && x.sin_part > 0;
  if (!plain) {
    double lo = 180, hi = 0;
    for (const AnglePair& x : a) {
      const double deg = to_deg(x);
      lo = std::min(lo, deg);
      hi = std::max(hi, deg);
    }
    return {lo, hi};
  }
  int lo = 0, hi = 0;
  for (int i = 1; i < 6; ++i) {
    if (a[i].sin_part * a[lo].cos_part - a[i].cos_part * a[lo].sin_part < 0) lo = i;
    if (a[i].sin_part * a[hi].cos_part - a[i].cos_part * a[hi].sin_part > 0) hi = i;
  }
  return {std::min(180.0, to_deg(a[lo])), with_max ? std::max(0.0, to_deg(a[hi])) : 0.0};
}

}  // namespace

std::array<double, 6> tet_dihedral_angles_deg(const Point3& p0, const Point3& p1, const Point3& p2, const Point3& p3) {
  const Point3* p[4] = {&p0, &p1, &p2, &p3};
  AnglePair a[6];
  dihedral_pairs(p, a);
  std::array<double, 6> angles;
  for (int i = 0; i < 6; ++i) angles[i] = to_deg(a[i]);
  return angles;
}

double tet_signed_volume(const Point3& p0, const Point3& p1, const Point3& p2, const Point3& p3) {
  return dot(cross(sub(p1, p0), sub(p2, p0)), sub(p3, p0)) / 6.0;
}

namespace {

// Everything of tet_quality but the dihedral angles: volume, edge lengths, circumradius (what tet_radius_edge needs,
// without the angles' atan2 and cross products; the improvement pass's radius-edge guard calls it per trial move).
TetQuality tet_quality_without_angles(const Point3& p0, const Point3& p1, const Point3& p2, const Point3& p3) {
  const Point3* p[4] = {&p0, &p1, &p2, &p3};
  TetQuality q;
  const Vec a = sub(p1, p0), b = sub(p2, p0), c = sub(p3, p0);
  const double det = dot(a, cross(b, c));
  q.volume = det / 6.0;

  q.shortest_edge = std::numeric_limits<double>::infinity();
  q.longest_edge = 0;
  for (const auto& e : kEdges) {
    const double len = norm(sub(*p[e[1]], *p[e[0]]));
    q.shortest_edge = std::min(q.shortest_edge, len);
    q.longest_edge = std::max(q.longest_edge, len);
  }

  const double inf = std::numeric_limits<double>::infinity();
  if (det == 0) {
    q.circumradius = inf;
  } else if (std::fabs(det) < 1e-10 * q.longest_edge * q.longest_edge * q.longest_edge) {
    q.circumradius = exact_circumradius(p0, p1, p2, p3);
  } else {
    const Vec bc = cross(b, c), ca = cross(c, a), ab = cross(a, b);
    const double sa = dot(a, a), sb = dot(b, b), sc = dot(c, c);
    const Vec x = {(sa * bc[0] + sb * ca[0] + sc * ab[0]) / (2 * det),
                   (sa * bc[1] + sb * ca[1] + sc * ab[1]) / (2 * det),
                   (sa * bc[2] + sb * ca[2] + sc * ab[2]) / (2 * det)};
    q.circumradius = norm(x);
  }
  if (q.shortest_edge > 0) {
    q.radius_edge = q.circumradius / q.shortest_edge;
    q.sigma = std::fabs(q.volume) / (q.shortest_edge * q.shortest_edge * q.shortest_edge);
  } else {
    q.radius_edge = inf;
    q.sigma = 0;
  }
  return q;
}

}  // namespace

TetQuality tet_quality(const Point3& p0, const Point3& p1, const Point3& p2, const Point3& p3) {
  TetQuality q = tet_quality_without_angles(p0, p1, p2, p3);
  const Point3* p[4] = {&p0, &p1, &p2, &p3};
  std::tie(q.min_dihedral_deg, q.max_dihedral_deg) = min_max_dihedral_deg(p);
  return q;
}

double tet_min_dihedral_deg(const Point3& p0, const Point3& p1, const Point3& p2, const Point3& p3) {
  // The angles alone, as tet_quality() computes them (no circumradius: exact for a flat cell, and not needed).
  const Point3* p[4] = {&p0, &p1, &p2, &p3};
  return min_max_dihedral_deg(p, /*with_max=*/false).first;
}

double tet_radius_edge(const Point3& p0, const Point3& p1, const Point3& p2, const Point3& p3) {
  return tet_quality_without_angles(p0, p1, p2, p3).radius_edge;
}

}  // namespace qualmesh
