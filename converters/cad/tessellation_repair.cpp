// Repairs of BRepMesh's triangles of one face before they become facets (brep_to_plc.cpp's tessellation mode):
// flat triangles and mirrored pairs, which are no facets, removed with the surface kept closed.
#include <gp_Vec.hxx>

#include <algorithm>
#include <cmath>
#include <map>

#include "cad_private.h"

namespace qualmesh::cad {
namespace {

using Triangle = std::array<Index, 3>;

double distance(const Point3& a, const Point3& b) {
  return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
}

// Distance of c from the line through a and b.
double height(const Point3& a, const Point3& b, const Point3& c) {
  const gp_Vec u(b[0] - a[0], b[1] - a[1], b[2] - a[2]), w(c[0] - a[0], c[1] - a[1], c[2] - a[2]);
  const double length = u.Magnitude();
  return length > 0 ? u.Crossed(w).Magnitude() / length : w.Magnitude();
}

}  // namespace

// Two triangles of one face on the same three vertices with opposite orientations (a flat fold BRepMesh makes
// on zero-width strips, U_Joint_2.stp) cover nothing: both are removed, and every edge keeps an even use count.
void remove_mirrored_pairs(std::vector<Triangle>& triangles) {
  auto canonical = [](Triangle t) {  // rotate so the smallest id is first; orientation kept
    std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
    return t;
  };
  std::map<Triangle, std::vector<std::size_t>> by_key;
  for (std::size_t i = 0; i < triangles.size(); ++i) by_key[canonical(triangles[i])].push_back(i);
  std::vector<bool> dead(triangles.size(), false);
  for (auto& [key, list] : by_key) {
    const Triangle mirror = canonical({key[0], key[2], key[1]});
    auto other = by_key.find(mirror);
    if (other == by_key.end()) continue;
    auto& others = other->second;
    while (!list.empty() && !others.empty()) {
      dead[list.back()] = dead[others.back()] = true;
      list.pop_back();
      others.pop_back();
    }
  }
  std::vector<Triangle> kept;
  for (std::size_t i = 0; i < triangles.size(); ++i)
    if (!dead[i]) kept.push_back(triangles[i]);
  triangles = std::move(kept);
}

// BRepMesh leaves flat triangles at times (three points of one edge chain on a cone, Kurbelwelle.stp), which are
// no facets. A flat triangle (p, q, r) with r within `flat` of its longest edge pq is removed and
// the face's triangle across pq, (q, p, s), is split at r into (q, r, s) and (r, p, s): the surface is unchanged
// and stays closed. A flat triangle whose longest edge is on the face's boundary is kept (its neighbour belongs to
// another face's shared chain).
void remove_flat_triangles(std::vector<Triangle>& triangles, const std::vector<Point3>& vertices, double flat) {
  for (int pass = 0; pass < 8; ++pass) {
    bool changed = false;
    std::map<std::pair<Index, Index>, std::size_t> by_edge;  // directed edge -> triangle
    for (std::size_t i = 0; i < triangles.size(); ++i)
      for (int k = 0; k < 3; ++k) by_edge[{triangles[i][k], triangles[i][(k + 1) % 3]}] = i;
    std::vector<bool> dead(triangles.size(), false);
    std::vector<Triangle> added;
    for (std::size_t i = 0; i < triangles.size(); ++i) {
      if (dead[i]) continue;
      const Triangle& t = triangles[i];
      int longest = 0;  // edge t[k] -> t[k+1]
      double best = -1;
      for (int k = 0; k < 3; ++k) {
        const Point3& a = vertices[t[k]];
        const Point3& b = vertices[t[(k + 1) % 3]];
        const double d = distance(a, b);
        if (d > best) best = d, longest = k;
      }
      const Index p = t[longest], q = t[(longest + 1) % 3], r = t[(longest + 2) % 3];
      if (height(vertices[p], vertices[q], vertices[r]) > flat) continue;
      auto across = by_edge.find({q, p});
      if (across == by_edge.end() || dead[across->second] || across->second == i) continue;
      const Triangle& u = triangles[across->second];
      Index s = kNoIndex;
      for (Index v : u)
        if (v != p && v != q) s = v;
      if (s == kNoIndex || s == r) continue;
      dead[i] = dead[across->second] = true;
      added.push_back({q, r, s});
      added.push_back({r, p, s});
      changed = true;
    }
    if (!changed) return;
    std::vector<Triangle> next;
    for (std::size_t i = 0; i < triangles.size(); ++i)
      if (!dead[i]) next.push_back(triangles[i]);
    next.insert(next.end(), added.begin(), added.end());
    triangles = std::move(next);
  }
}

}  // namespace qualmesh::cad
