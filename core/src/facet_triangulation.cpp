// Facet plane and facet triangulation (see facet_triangulation.h): a constrained Delaunay triangulation of the
// facet's loops in its plane, then the odd-coverage rule and the hole points of plc.h decide which triangles belong
// to the facet. Exact predicates (CGAL Epick); the only constructions are the crossing points of loops, which a
// valid facet does not have.
#include "facet_triangulation.h"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Constrained_triangulation_face_base_2.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <cmath>
#include <deque>
#include <unordered_map>
#include <utility>

#include "cgal_types.h"
#include "vec3.h"

namespace qualmesh::detail {
namespace {

// The kernel is cgal_types.h's; the 2D triangulation differs from its Cdt2 in two ways: vertices may carry no PLC id
// (crossing points), and crossing constraints are allowed (Exact_predicates_tag), since facets may overlap.
struct VertexInfo {
  Index id = kNoIndex;  // PLC vertex id; kNoIndex for a point the triangulation added
};
struct FacetFaceInfo {
  int parity = -1;    // number of polygons covering the face, mod 2; -1 = not reached yet
  bool holed = false;  // reached from a hole point
};

using Vb = CGAL::Triangulation_vertex_base_with_info_2<VertexInfo, Kernel>;
using Fbb = CGAL::Triangulation_face_base_with_info_2<FacetFaceInfo, Kernel>;
using Fb = CGAL::Constrained_triangulation_face_base_2<Kernel, Fbb>;
using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
using Cdt = CGAL::Constrained_Delaunay_triangulation_2<Kernel, Tds, CGAL::Exact_predicates_tag>;

KPoint3 to_kernel(const Point3& p) { return KPoint3(p[0], p[1], p[2]); }

using namespace vec3;

std::uint64_t edge_key(Index a, Index b) {
  if (a > b) std::swap(a, b);
  return (static_cast<std::uint64_t>(a) << 32) | b;
}

// The two coordinates kept by the projection, ordered so that counter-clockwise in 2D is counter-clockwise about
// the frame's normal.
std::pair<int, int> projection_axes(const FacetFrame& frame) {
  const int d = frame.drop_axis;
  int a1 = (d + 1) % 3, a2 = (d + 2) % 3;
  if (frame.normal[d] < 0) std::swap(a1, a2);
  return {a1, a2};
}

// Even-odd rule: is `q` inside the polygons of `facet` (projected)? Used only for facets whose loops cross.
bool inside_by_crossings(const std::vector<Point3>& vertices, const Facet& facet, int a1, int a2, double qx,
                         double qy) {
  bool inside = false;
  for (const auto& loop : facet.polygons) {
    if (loop.size() < 3) continue;
    for (std::size_t i = 0; i < loop.size(); ++i) {
      const Point3& p = vertices[loop[i]];
      const Point3& r = vertices[loop[(i + 1) % loop.size()]];
      const double py = p[a2], ry = r[a2];
      if ((py > qy) != (ry > qy)) {
        const double x = p[a1] + (qy - py) / (ry - py) * (r[a1] - p[a1]);
        if (qx < x) inside = !inside;
      }
    }
  }
  return inside;
}

}  // namespace

std::optional<FacetFrame> compute_facet_frame(const std::vector<Point3>& vertices, const Facet& facet) {
  std::vector<Index> ids;
  for (const auto& loop : facet.polygons) ids.insert(ids.end(), loop.begin(), loop.end());
  if (ids.size() < 3) return std::nullopt;
  const Point3& p0 = vertices[ids[0]];
  // p1: farthest from p0; p2: farthest from the line p0 p1. Well-conditioned normal from the best triangle.
  Index i1 = ids[0];
  double best = 0;
  for (Index id : ids) {
    const Point3 d = sub(vertices[id], p0);
    const double sq = dot(d, d);
    if (sq > best) best = sq, i1 = id;
  }
  if (best == 0) return std::nullopt;
  const Point3 e1 = sub(vertices[i1], p0);
  Index i2 = kNoIndex;
  best = 0;
  for (Index id : ids) {
    const Point3 c = cross(e1, sub(vertices[id], p0));
    const double sq = dot(c, c);
    if (sq > best) best = sq, i2 = id;
  }
  const KPoint3 k0 = to_kernel(p0), k1 = to_kernel(vertices[i1]);
  if (i2 == kNoIndex || CGAL::collinear(k0, k1, to_kernel(vertices[i2]))) {
    // The floating-point search found nothing usable; settle collinearity exactly.
    i2 = kNoIndex;
    for (Index id : ids) {
      if (!CGAL::collinear(k0, k1, to_kernel(vertices[id]))) {
        i2 = id;
        break;
      }
    }
    if (i2 == kNoIndex) return std::nullopt;
  }
  Point3 n = cross(e1, sub(vertices[i2], p0));
  const double len = std::sqrt(dot(n, n));
  if (!(len > 0)) return std::nullopt;
  FacetFrame frame;
  frame.origin = p0;
  for (int i = 0; i < 3; ++i) n[i] /= len;
  frame.normal = n;
  frame.drop_axis = 0;
  for (int i = 1; i < 3; ++i)
    if (std::abs(n[i]) > std::abs(n[frame.drop_axis])) frame.drop_axis = i;
  return frame;
}

double signed_distance(const FacetFrame& frame, const Point3& p) { return dot(frame.normal, sub(p, frame.origin)); }

FacetTriangulation triangulate_facet(const std::vector<Point3>& vertices, const Facet& facet,
                                     const FacetFrame& frame) {
  FacetTriangulation result;
  result.num_plc_vertices = static_cast<Index>(vertices.size());

  // Fast path: a single triangle, the common case of surface meshes.
  if (facet.polygons.size() == 1 && facet.polygons[0].size() == 3 && facet.holes.empty()) {
    std::array<Index, 3> t{facet.polygons[0][0], facet.polygons[0][1], facet.polygons[0][2]};
    if (t[0] != t[1] && t[1] != t[2] && t[0] != t[2]) {
      const Point3 n = cross(sub(vertices[t[1]], vertices[t[0]]), sub(vertices[t[2]], vertices[t[0]]));
      if (dot(n, frame.normal) < 0) std::swap(t[1], t[2]);
      result.triangles.push_back(t);
      result.constrained_edges.push_back(7);
      return result;
    }
  }

  const auto [a1, a2] = projection_axes(frame);
  auto project = [&, a1 = a1, a2 = a2](const Point3& p) { return KPoint2(p[a1], p[a2]); };

  Cdt cdt;
  std::unordered_map<Index, Cdt::Vertex_handle> handle_of;
  auto vertex = [&](Index id) {
    auto it = handle_of.find(id);
    if (it != handle_of.end()) return it->second;
    Cdt::Vertex_handle v = cdt.insert(project(vertices[id]));
    if (v->info().id == kNoIndex) v->info().id = id;  // a second id at the same 2D spot keeps the first
    handle_of.emplace(id, v);
    return v;
  };
  std::unordered_map<std::uint64_t, int> polygon_edge_count;  // uses of an edge by loops of >= 3 vertices
  std::vector<std::pair<Cdt::Vertex_handle, Cdt::Vertex_handle>> polygon_edges;
  for (const auto& loop : facet.polygons) {
    if (loop.size() == 1) {
      vertex(loop[0]);
    } else if (loop.size() == 2) {
      Cdt::Vertex_handle va = vertex(loop[0]), vb = vertex(loop[1]);
      if (va != vb) cdt.insert_constraint(va, vb);
    } else {
      for (std::size_t i = 0; i < loop.size(); ++i) {
        const Index a = loop[i], b = loop[(i + 1) % loop.size()];
        Cdt::Vertex_handle va = vertex(a), vb = vertex(b);
        if (va == vb) continue;
        cdt.insert_constraint(va, vb);
        ++polygon_edge_count[edge_key(a, b)];
        polygon_edges.emplace_back(va, vb);
      }
    }
  }

  // Did any constraint get split (loops crossing, or a loop through another vertex)? Then the edge counts no longer
  // describe the triangulation's edges and the even-odd rule is evaluated per triangle instead.
  bool split = false;
  for (auto v = cdt.finite_vertices_begin(); v != cdt.finite_vertices_end() && !split; ++v)
    split = v->info().id == kNoIndex;
  for (std::size_t i = 0; i < polygon_edges.size() && !split; ++i)
    split = !cdt.is_edge(polygon_edges[i].first, polygon_edges[i].second);

  auto edge_polygon_count = [&](Cdt::Face_handle f, int i) {
    if (!f->is_constrained(i)) return 0;
    if (split) return 1;  // parity is not taken from edges in this case
    const Index a = f->vertex(Cdt::cw(i))->info().id, b = f->vertex(Cdt::ccw(i))->info().id;
    auto it = polygon_edge_count.find(edge_key(a, b));
    return it == polygon_edge_count.end() ? 0 : it->second;
  };

  // Parity of coverage: flood from the outside, toggling across edges used by an odd number of polygons.
  if (!split) {
    std::deque<Cdt::Face_handle> queue;
    for (auto f = cdt.all_faces_begin(); f != cdt.all_faces_end(); ++f) {
      if (!cdt.is_infinite(f)) continue;
      f->info().parity = 0;
      queue.push_back(f);
    }
    while (!queue.empty()) {
      Cdt::Face_handle f = queue.front();
      queue.pop_front();
      for (int i = 0; i < 3; ++i) {
        Cdt::Face_handle g = f->neighbor(i);
        if (g->info().parity != -1) continue;
        g->info().parity = (f->info().parity + edge_polygon_count(f, i)) % 2;
        queue.push_back(g);
      }
    }
  } else {
    for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
      const KPoint2 c = CGAL::centroid(f->vertex(0)->point(), f->vertex(1)->point(), f->vertex(2)->point());
      f->info().parity = inside_by_crossings(vertices, facet, a1, a2, c.x(), c.y()) ? 1 : 0;
    }
  }

  // Hole points eat what they reach without crossing a loop edge (a polygon edge or a 2-vertex loop, as TetGen
  // carves facet holes up to any segment).
  for (const Point3& hole : facet.holes) {
    Cdt::Face_handle start = cdt.locate(project(hole));
    if (start == Cdt::Face_handle() || cdt.is_infinite(start) || start->info().holed) continue;
    std::deque<Cdt::Face_handle> queue{start};
    start->info().holed = true;
    while (!queue.empty()) {
      Cdt::Face_handle f = queue.front();
      queue.pop_front();
      for (int i = 0; i < 3; ++i) {
        Cdt::Face_handle g = f->neighbor(i);
        if (cdt.is_infinite(g) || g->info().holed || f->is_constrained(i)) continue;
        g->info().holed = true;
        queue.push_back(g);
      }
    }
  }

  // Ids for the points the triangulation added, lifted onto the plane.
  std::unordered_map<Cdt::Vertex_handle, Index> steiner_id;
  auto id_of = [&, a1 = a1, a2 = a2](Cdt::Vertex_handle v) -> Index {
    if (v->info().id != kNoIndex) return v->info().id;
    auto it = steiner_id.find(v);
    if (it != steiner_id.end()) return it->second;
    Point3 p{};
    p[a1] = v->point().x();
    p[a2] = v->point().y();
    const int d = frame.drop_axis;
    p[d] = frame.origin[d] - (frame.normal[a1] * (p[a1] - frame.origin[a1]) +
                              frame.normal[a2] * (p[a2] - frame.origin[a2])) /
                                 frame.normal[d];
    const Index id = result.num_plc_vertices + static_cast<Index>(result.steiner_points.size());
    result.steiner_points.push_back(p);
    steiner_id.emplace(v, id);
    return id;
  };
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
    if (f->info().parity != 1 || f->info().holed) continue;
    result.triangles.push_back({id_of(f->vertex(0)), id_of(f->vertex(1)), id_of(f->vertex(2))});
    std::uint8_t mask = 0;
    for (int i = 0; i < 3; ++i)
      if (f->is_constrained(i)) mask |= static_cast<std::uint8_t>(1u << i);
    result.constrained_edges.push_back(mask);
  }
  return result;
}

}  // namespace qualmesh::detail
