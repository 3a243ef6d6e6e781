// repair_degenerate_triangles() (plc_read_formats.h): the exact repairs of degenerate surface triangles that the
// surface readers make before the PLC is built (issue 18: TetGen meshes such files, QualMesh refused them with "facet
// N spans no plane").
//
// Both repairs leave the surface's boundary chain unchanged (the sum of its directed edges), so a closed, consistently
// oriented surface stays closed and consistently oriented, and the enclosed volume does not change:
//  - a triangle (a, a, b) has the edges a->b and b->a, which cancel: dropping it changes nothing;
//  - a triangle (x, y, m) with m exactly between x and y (a T-junction in disguise) has the edges x->y, y->m, m->x.
//    Its neighbour across the long edge holds y->x. Putting m into that edge of the neighbour (a triangle (y, x, c)
//    becomes (y, m, c) and (m, x, c); a larger polygon gets m between y and x) gives the neighbour the edges y->m,
//    m->x in place of y->x, which is what the two faces had together.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <utility>

#include "plc_read_formats.h"
#include "qualmesh/plc_validate.h"

namespace qualmesh::plc_io {
namespace {

// Three distinct corners exactly on one line.
bool collinear(const std::vector<Point3>& vertices, const std::vector<Index>& t) {
  return !repeats_a_vertex(t) && is_degenerate_suspect(vertices, t) && has_zero_area(vertices, t);
}

// The corner of an exactly collinear triangle that lies between the other two: along the axis where the three spread
// most, their coordinates are distinct (the line is not perpendicular to it), so the comparison is exact.
int middle_corner(const std::vector<Point3>& vertices, const std::vector<Index>& t) {
  int axis = 0;
  double spread = -1;
  for (int k = 0; k < 3; ++k) {
    const double lo = std::min({vertices[t[0]][k], vertices[t[1]][k], vertices[t[2]][k]});
    const double hi = std::max({vertices[t[0]][k], vertices[t[1]][k], vertices[t[2]][k]});
    if (hi - lo > spread) spread = hi - lo, axis = k;
  }
  for (int i = 0; i < 3; ++i) {
    const double x = vertices[t[i]][axis], p = vertices[t[(i + 1) % 3]][axis], q = vertices[t[(i + 2) % 3]][axis];
    if ((p < x && x < q) || (q < x && x < p)) return i;
  }
  return -1;
}

std::uint64_t directed(Index a, Index b) { return (std::uint64_t(a) << 32) | b; }

}  // namespace

bool has_zero_area(const std::vector<Point3>& vertices, const std::vector<Index>& loop) {
  Plc alone;
  Facet facet;
  std::vector<Index> local;
  for (Index v : loop) {
    local.push_back(static_cast<Index>(alone.vertices.size()));
    alone.vertices.push_back(vertices[v]);
  }
  facet.polygons.push_back(std::move(local));
  alone.facets.push_back(std::move(facet));
  ValidateOptions validate;
  validate.require_closed = false;
  validate.check_intersections = false;
  for (const Problem& problem : validate_plc(alone, validate).problems)
    if (problem.code == ErrorCode::DegenerateFacet) return true;
  return false;
}

SurfaceRepairs repair_degenerate_triangles(SurfaceSoup& soup) {
  SurfaceRepairs repairs;
  std::vector<std::vector<Index>>& faces = soup.faces;
  if (soup.origin.empty())
    for (std::size_t f = 0; f < faces.size(); ++f) soup.origin.push_back(f);
  const auto name = [&](std::size_t f) {
    const std::size_t o = soup.origin[f];
    std::string text = std::string(soup.face_word) + " " + std::to_string(static_cast<long>(o) + soup.first_face_number);
    if (o < soup.lines.size() && soup.lines[o] > 0) text += " (line " + std::to_string(soup.lines[o]) + ")";
    return text;
  };
  std::vector<char> dead(faces.size(), 0);
  // A pass repairs each triangle whose neighbour is not degenerate itself and not touched yet in this pass; a
  // neighbour that was degenerate is repaired first, so the passes end when nothing changes.
  for (bool changed = true; changed;) {
    changed = false;
    std::multimap<std::uint64_t, std::size_t> faces_with;  // directed edge -> live faces holding it
    for (std::size_t f = 0; f < faces.size(); ++f) {
      if (dead[f]) continue;
      for (std::size_t i = 0; i < faces[f].size(); ++i)
        faces_with.emplace(directed(faces[f][i], faces[f][(i + 1) % faces[f].size()]), f);
    }
    std::vector<char> touched(faces.size(), 0);
    const std::size_t count = faces.size();  // splits append faces; they wait for the next pass
    for (std::size_t f = 0; f < count; ++f) {
      if (dead[f] || touched[f] || faces[f].size() != 3) continue;
      const std::vector<Index> t = faces[f];
      if (repeats_a_vertex(t)) {
        dead[f] = touched[f] = 1;
        ++repairs.num_dropped;
        if (repairs.examples.size() < 3) repairs.examples.push_back(name(f) + " repeats a vertex: dropped");
        changed = true;
        continue;
      }
      if (!collinear(soup.vertices, t)) continue;
      const int m = middle_corner(soup.vertices, t);
      if (m < 0) continue;
      const Index x = t[(m + 1) % 3], y = t[(m + 2) % 3];  // the long edge x->y
      const auto [lo, hi] = faces_with.equal_range(directed(y, x));
      std::size_t neighbour = faces.size(), found = 0;
      for (auto it = lo; it != hi; ++it)
        if (!dead[it->second] && it->second != f) neighbour = it->second, ++found;
      if (found != 1 || touched[neighbour]) continue;
      std::vector<Index>& g = faces[neighbour];
      if (g.size() == 3 && (repeats_a_vertex(g) || collinear(soup.vertices, g))) continue;  // that one first
      // Rotate the neighbour to start with y -> x.
      const auto at = std::find(g.begin(), g.end(), y);
      std::rotate(g.begin(), at, g.end());
      if (g.size() == 3) {
        const Index c = g[2];
        g = {y, t[m], c};
        faces.push_back({t[m], x, c});
        soup.origin.push_back(soup.origin[neighbour]);
        if (!soup.markers.empty()) soup.markers.push_back(soup.markers[neighbour]);
        dead.push_back(0);
        touched.push_back(1);
      } else {
        g.insert(g.begin() + 1, t[m]);
      }
      dead[f] = touched[f] = touched[neighbour] = 1;
      ++repairs.num_split;
      if (repairs.examples.size() < 3) {
        char point[120];
        const Point3& p = soup.vertices[t[m]];
        std::snprintf(point, sizeof point, "(%.17g, %.17g, %.17g)", p[0], p[1], p[2]);
        repairs.examples.push_back(name(f) + " has collinear corners: dropped, and " + name(neighbour) +
                                   " across its long edge split at its middle corner " + point);
      }
      changed = true;
    }
  }
  if (repairs.num_dropped + repairs.num_split == 0) return repairs;
  std::size_t kept = 0;
  for (std::size_t f = 0; f < faces.size(); ++f) {
    if (dead[f]) continue;
    if (kept != f) {  // a vector moved onto itself is left empty
      faces[kept] = std::move(faces[f]);
      soup.origin[kept] = soup.origin[f];
      if (!soup.markers.empty()) soup.markers[kept] = soup.markers[f];
    }
    ++kept;
  }
  faces.resize(kept);
  soup.origin.resize(kept);
  if (!soup.markers.empty()) soup.markers.resize(kept);
  return repairs;
}

std::string SurfaceRepairs::summary() const {
  if (num_dropped + num_split == 0) return "";
  std::string text = "repaired: " + std::to_string(num_dropped) + " triangle(s) repeating a vertex dropped, " +
                     std::to_string(num_split) +
                     " collinear triangle(s) dropped by splitting the neighbour across the long edge (exact: the "
                     "surface and its volume are unchanged)";
  for (const std::string& example : examples) text += "; " + example;
  return text;
}

}  // namespace qualmesh::plc_io
