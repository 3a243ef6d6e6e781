// Vector arithmetic on Point3 for the core's geometry (angles, normals, distances): one definition instead of a
// copy per file. Plain doubles, no rounding beyond each operation's own.
#pragma once

#include <cmath>

#include "qualmesh/types.h"

namespace qualmesh::vec3 {

using Vec = Point3;
inline Vec sub(const Vec& a, const Vec& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
inline Vec add(const Vec& a, const Vec& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
inline Vec scale(const Vec& a, double s) { return {a[0] * s, a[1] * s, a[2] * s}; }
inline double dot(const Vec& a, const Vec& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline Vec cross(const Vec& a, const Vec& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
inline double sq_norm(const Vec& a) { return dot(a, a); }
inline double norm(const Vec& a) { return std::sqrt(dot(a, a)); }
inline double sq_dist(const Point3& a, const Point3& b) { return sq_norm(sub(a, b)); }
inline double dist(const Point3& a, const Point3& b) { return norm(sub(a, b)); }
// a / |a| as a * (1 / |a|); the zero vector for a zero vector.
inline Vec unit(const Vec& a) {
  const double n = norm(a);
  return n > 0 ? scale(a, 1 / n) : Vec{0, 0, 0};
}
inline Vec face_normal(const Point3& a, const Point3& b, const Point3& c) { return cross(sub(b, a), sub(c, a)); }

}  // namespace qualmesh::vec3
