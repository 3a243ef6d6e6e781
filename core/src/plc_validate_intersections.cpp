// PLC validation: the intersection rule of the paper's Section 2 ("if any two elements intersect, their
// intersection is a lower dimensional element in P").
//
// Facets are tested through their triangles (facet_triangulation.h), segments that lie in no facet on their own.
// Candidate pairs come from CGAL's box_intersection_d over closed bounding boxes (O(n log n + pairs)); each pair is
// then decided with exact predicates (CGAL Epick do_intersect / orientation):
//  - triangles of the same facet never count;
//  - no shared vertex: any contact is an intersection;
//  - one shared vertex v: the triangles may meet only at v; they meet elsewhere iff the edge opposite v in one
//    triangle meets the other triangle (their intersection is convex and contains v, so it reaches that edge);
//  - a shared edge uv: coplanar triangles on the same side of uv overlap; otherwise they meet along uv only, which
//    must then be a segment of both facets (not an interior diagonal of either);
//  - three shared vertices: the facets overlap.
// Segment pairs and segment-triangle pairs follow the same rule, and a vertex on no facet and no free segment must
// not lie on any of them. Vertices are compared through their
// representative, so exact duplicates (reported elsewhere) do not flood the report.
#include <CGAL/box_intersection_d.h>
#include <CGAL/intersections.h>

#include <algorithm>
#include <string>
#include <unordered_set>
#include <vector>

#include "cgal_types.h"
#include "plc_validate_internal.h"

namespace qualmesh::detail {
namespace {

using KPoint = Kernel::Point_3;
using KSegment = Kernel::Segment_3;
using KTriangle = Kernel::Triangle_3;
using Box = CGAL::Box_intersection_d::Box_with_info_d<double, 3, std::size_t>;

std::uint64_t pair_key(Index a, Index b) {
  if (a > b) std::swap(a, b);
  return (static_cast<std::uint64_t>(a) << 32) | b;
}

std::uint64_t edge_key(Index a, Index b) { return pair_key(a, b); }

enum class PrimitiveKind : std::uint8_t { Triangle, Segment, Vertex };

// A facet triangle, a free segment or a lone vertex.
struct Primitive {
  PrimitiveKind kind = PrimitiveKind::Triangle;
  Index owner = 0;     // facet id, segment id or vertex id
  Index triangle = 0;  // triangle index in the facet's triangulation
};

class IntersectionChecker {
 public:
  IntersectionChecker(const ValidationInput& input, ProblemSink& sink) : input_(input), sink_(sink) {}

  void run() {
    const Plc& plc = *input_.plc;
    std::vector<Box> boxes;
    std::vector<char> used(plc.vertices.size(), 0);
    for (std::size_t f = 0; f < plc.facets.size(); ++f) {
      if (!input_.facet_usable[f]) continue;
      const FacetTriangulation& tri = input_.triangulations[f];
      for (std::size_t t = 0; t < tri.triangles.size(); ++t) {
        CGAL::Bbox_3 box;
        for (Index id : tri.triangles[t]) box += point(static_cast<Index>(f), id).bbox();
        boxes.emplace_back(box, primitives_.size());
        primitives_.push_back({PrimitiveKind::Triangle, static_cast<Index>(f), static_cast<Index>(t)});
        for (int i = 0; i < 3; ++i) {
          covered_edges_.insert(edge_key(rep(tri.triangles[t][(i + 1) % 3]), rep(tri.triangles[t][(i + 2) % 3])));
          if (tri.is_plc_vertex(tri.triangles[t][i])) used[rep(tri.triangles[t][i])] = 1;
        }
      }
    }
    for (std::size_t s = 0; s < input_.segments.size(); ++s) {
      const Segment& seg = input_.segments[s];
      if (rep(seg.a) == rep(seg.b) || covered_edges_.count(edge_key(rep(seg.a), rep(seg.b)))) continue;
      const CGAL::Bbox_3 box = vertex(seg.a).bbox() + vertex(seg.b).bbox();
      boxes.emplace_back(box, primitives_.size());
      primitives_.push_back({PrimitiveKind::Segment, static_cast<Index>(s), 0});
      used[rep(seg.a)] = used[rep(seg.b)] = 1;
    }
    for (std::size_t v = 0; v < plc.vertices.size(); ++v) {
      if (used[rep(static_cast<Index>(v))] || rep(static_cast<Index>(v)) != v) continue;
      boxes.emplace_back(vertex(static_cast<Index>(v)).bbox(), primitives_.size());
      primitives_.push_back({PrimitiveKind::Vertex, static_cast<Index>(v), 0});
    }
    CGAL::box_self_intersection_d(boxes.begin(), boxes.end(),
                                  [this](const Box& a, const Box& b) { test(a.info(), b.info()); });
  }

 private:
  Index rep(Index id) const { return id < input_.representative.size() ? input_.representative[id] : id; }
  KPoint to_kernel(const Point3& p) const { return KPoint(p[0], p[1], p[2]); }
  KPoint vertex(Index v) const { return to_kernel(input_.plc->vertices[v]); }
  KPoint point(Index facet, Index id) const {
    return to_kernel(input_.triangulations[facet].point(input_.plc->vertices, id));
  }
  // Shared-vertex identity: PLC vertices by representative; Steiner points are never shared.
  Index identity(Index facet, Index id) const {
    return input_.triangulations[facet].is_plc_vertex(id) ? rep(id) : kNoIndex;
  }

  void test(std::size_t i, std::size_t j) {
    const Primitive& a = primitives_[i];
    const Primitive& b = primitives_[j];
    using K = PrimitiveKind;
    if (a.kind == K::Vertex || b.kind == K::Vertex) {
      if (a.kind != K::Vertex) test_vertex(b, a);
      if (b.kind != K::Vertex) test_vertex(a, b);
    } else if (a.kind == K::Triangle && b.kind == K::Triangle) {
      if (a.owner != b.owner) test_triangles(a, b);
    } else if (a.kind == K::Triangle) {
      test_segment_triangle(b, a);
    } else if (b.kind == K::Triangle) {
      test_segment_triangle(a, b);
    } else {
      test_segments(a, b);
    }
  }

  // A lone vertex (on no facet triangle and no free segment) touching a facet triangle or a free segment.
  void test_vertex(const Primitive& v, const Primitive& other) {
    const KPoint p = vertex(v.owner);
    bool bad;
    std::string what;
    ElementIds ids;
    ids.vertices = std::vector<Index>{v.owner};
    if (other.kind == PrimitiveKind::Triangle) {
      const std::uint64_t key = (static_cast<std::uint64_t>(v.owner) << 32) | other.owner;
      if (reported_vertex_facets_.count(key)) return;
      const auto& tri = input_.triangulations[other.owner].triangles[other.triangle];
      bad = KTriangle(point(other.owner, tri[0]), point(other.owner, tri[1]), point(other.owner, tri[2])).has_on(p);
      if (bad) reported_vertex_facets_.insert(key);
      what = "facet " + std::to_string(other.owner);
      ids.facets = std::vector<Index>{other.owner};
    } else {
      const Segment& seg = input_.segments[other.owner];
      bad = KSegment(vertex(seg.a), vertex(seg.b)).has_on(p);
      what = "segment " + std::to_string(other.owner);
      ids.segments = std::vector<Index>{other.owner};
    }
    if (!bad) return;
    sink_.add(ErrorCode::Intersection,
              "vertex " + std::to_string(v.owner) + " lies on " + what + " but is not one of its vertices", ids);
  }

  void test_triangles(const Primitive& a, const Primitive& b) {
    if (reported_facets_.count(pair_key(a.owner, b.owner))) return;
    const auto& ta = input_.triangulations[a.owner].triangles[a.triangle];
    const auto& tb = input_.triangulations[b.owner].triangles[b.triangle];
    KPoint pa[3], pb[3];
    Index ia[3], ib[3];
    for (int k = 0; k < 3; ++k) {
      pa[k] = point(a.owner, ta[k]);
      pb[k] = point(b.owner, tb[k]);
      ia[k] = identity(a.owner, ta[k]);
      ib[k] = identity(b.owner, tb[k]);
    }
    int shared = 0, sa[3], sb[3];  // corners shared: sa[n] in a matches sb[n] in b
    for (int x = 0; x < 3; ++x)
      for (int y = 0; y < 3; ++y)
        if (ia[x] != kNoIndex && ia[x] == ib[y]) sa[shared] = x, sb[shared] = y, ++shared;
    bool bad = false;
    const char* how = "";
    if (shared == 0) {
      bad = CGAL::do_intersect(KTriangle(pa[0], pa[1], pa[2]), KTriangle(pb[0], pb[1], pb[2]));
    } else if (shared == 1) {
      const int x = sa[0], y = sb[0];
      bad = CGAL::do_intersect(KSegment(pa[(x + 1) % 3], pa[(x + 2) % 3]), KTriangle(pb[0], pb[1], pb[2])) ||
            CGAL::do_intersect(KSegment(pb[(y + 1) % 3], pb[(y + 2) % 3]), KTriangle(pa[0], pa[1], pa[2]));
      how = " beyond their shared vertex";
    } else if (shared == 2) {
      const int xa = 3 - sa[0] - sa[1], xb = 3 - sb[0] - sb[1];  // the corners off the shared edge
      const KPoint& u = pa[sa[0]];
      const KPoint& v = pa[sa[1]];
      if (CGAL::orientation(u, v, pa[xa], pb[xb]) == CGAL::COPLANAR) {
        bad = CGAL::coplanar_orientation(u, v, pa[xa], pb[xb]) == CGAL::POSITIVE;
        how = " (they overlap)";
      } else {
        const bool on_loop_a = input_.triangulations[a.owner].constrained_edges[a.triangle] & (1u << xa);
        const bool on_loop_b = input_.triangulations[b.owner].constrained_edges[b.triangle] & (1u << xb);
        bad = !on_loop_a || !on_loop_b;
        how = " (one meets the other's interior along an edge that is not a segment of both)";
      }
    } else {
      bad = true;
      how = " (they overlap)";
    }
    if (!bad) return;
    reported_facets_.insert(pair_key(a.owner, b.owner));
    ElementIds ids;
    ids.facets = std::vector<Index>{std::min(a.owner, b.owner), std::max(a.owner, b.owner)};
    sink_.add(ErrorCode::Intersection,
              "facets " + std::to_string(ids.facets[0]) + " and " + std::to_string(ids.facets[1]) +
                  " intersect (not in a shared vertex or edge)" + how,
              ids);
  }

  void test_segment_triangle(const Primitive& s, const Primitive& t) {
    const std::uint64_t key = (static_cast<std::uint64_t>(s.owner) << 32) | t.owner;
    if (reported_segment_facets_.count(key)) return;
    const Segment& seg = input_.segments[s.owner];
    const auto& tri = input_.triangulations[t.owner].triangles[t.triangle];
    KPoint p[3];
    Index id[3];
    for (int k = 0; k < 3; ++k) p[k] = point(t.owner, tri[k]), id[k] = identity(t.owner, tri[k]);
    const KPoint a = vertex(seg.a), b = vertex(seg.b);
    int shared_corner = -1;
    bool a_shared = false;
    for (int k = 0; k < 3; ++k) {
      if (id[k] == kNoIndex) continue;
      if (id[k] == rep(seg.a)) shared_corner = k, a_shared = true;
      if (id[k] == rep(seg.b)) shared_corner = k, a_shared = false;
    }
    bool bad;
    if (shared_corner < 0) {
      bad = CGAL::do_intersect(KSegment(a, b), KTriangle(p[0], p[1], p[2]));
    } else {
      // The segment leaves the shared corner; it meets the triangle elsewhere iff it runs into the closed corner.
      const KPoint& apex = p[shared_corner];
      const KPoint& far = a_shared ? b : a;
      const KPoint& q = p[(shared_corner + 1) % 3];
      const KPoint& r = p[(shared_corner + 2) % 3];
      bad = CGAL::orientation(apex, q, r, far) == CGAL::COPLANAR &&
            CGAL::coplanar_orientation(apex, q, r, far) != CGAL::NEGATIVE &&
            CGAL::coplanar_orientation(apex, r, q, far) != CGAL::NEGATIVE;
    }
    if (!bad) return;
    reported_segment_facets_.insert(key);
    ElementIds ids;
    ids.segments = std::vector<Index>{s.owner};
    ids.facets = std::vector<Index>{t.owner};
    ids.vertices = std::vector<Index>{seg.a, seg.b};
    sink_.add(ErrorCode::Intersection,
              "segment " + std::to_string(s.owner) + " (vertices " + std::to_string(seg.a) + ", " +
                  std::to_string(seg.b) + ") and facet " + std::to_string(t.owner) +
                  " intersect (not in a shared vertex)",
              ids);
  }

  void test_segments(const Primitive& s, const Primitive& t) {
    const Segment& x = input_.segments[s.owner];
    const Segment& y = input_.segments[t.owner];
    const Index xa = rep(x.a), xb = rep(x.b), ya = rep(y.a), yb = rep(y.b);
    bool bad;
    if (xa != ya && xa != yb && xb != ya && xb != yb) {
      bad = CGAL::do_intersect(KSegment(vertex(x.a), vertex(x.b)), KSegment(vertex(y.a), vertex(y.b)));
    } else if ((xa == ya && xb == yb) || (xa == yb && xb == ya)) {
      bad = true;  // the same segment twice through duplicate vertices
    } else {
      const Index apex_id = (xa == ya || xa == yb) ? x.a : x.b;
      const Index far_x = apex_id == x.a ? x.b : x.a;
      const Index far_y = (rep(y.a) == rep(apex_id)) ? y.b : y.a;
      const KPoint apex = vertex(apex_id), p = vertex(far_x), q = vertex(far_y);
      // They overlap iff collinear with both far ends on the same side of the shared vertex.
      bad = CGAL::collinear(apex, p, q) && !CGAL::collinear_are_strictly_ordered_along_line(p, apex, q);
    }
    if (!bad) return;
    ElementIds ids;
    ids.segments = std::vector<Index>{std::min(s.owner, t.owner), std::max(s.owner, t.owner)};
    sink_.add(ErrorCode::Intersection,
              "segments " + std::to_string(ids.segments[0]) + " and " + std::to_string(ids.segments[1]) +
                  " intersect (not in a shared vertex)",
              ids);
  }

  const ValidationInput& input_;
  ProblemSink& sink_;
  std::vector<Primitive> primitives_;
  std::unordered_set<std::uint64_t> covered_edges_;
  std::unordered_set<std::uint64_t> reported_facets_;
  std::unordered_set<std::uint64_t> reported_segment_facets_;
  std::unordered_set<std::uint64_t> reported_vertex_facets_;
};

}  // namespace

void check_intersections(const ValidationInput& input, ProblemSink& sink) {
  IntersectionChecker checker(input, sink);
  checker.run();
}

}  // namespace qualmesh::detail
