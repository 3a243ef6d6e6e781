// Local feature size (Cheng & Dey, Section 2): best-first search over a bounding-volume tree. See the header.
#include "local_feature_size.h"

#include "facet_triangulation.h"
#include "vec3.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <queue>
#include <tuple>
#include <utility>
#include <vector>

namespace qualmesh {

namespace {

using namespace vec3;

double sq_distance_point_segment(const Point3& x, const Point3& a, const Point3& b) {
  const Vec ab = sub(b, a);
  const double len2 = sq_norm(ab);
  double t = len2 > 0 ? dot(sub(x, a), ab) / len2 : 0.0;
  t = std::clamp(t, 0.0, 1.0);
  const Point3 c{a[0] + t * ab[0], a[1] + t * ab[1], a[2] + t * ab[2]};
  return sq_norm(sub(x, c));
}

// Closest point on triangle abc to p, by Voronoi regions (Ericson, Real-Time Collision Detection, 5.1.5).
double sq_distance_point_triangle(const Point3& p, const Point3& a, const Point3& b, const Point3& c) {
  const Vec ab = sub(b, a), ac = sub(c, a), ap = sub(p, a);
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return sq_norm(ap);
  const Vec bp = sub(p, b);
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return sq_norm(bp);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return sq_distance_point_segment(p, a, b);
  const Vec cp = sub(p, c);
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return sq_norm(cp);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return sq_distance_point_segment(p, a, c);
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return sq_distance_point_segment(p, b, c);
  const double denom = va + vb + vc;
  if (!(denom > 0)) {  // degenerate triangle: distance to its edges
    return std::min({sq_distance_point_segment(p, a, b), sq_distance_point_segment(p, b, c),
                     sq_distance_point_segment(p, a, c)});
  }
  const double v = vb / denom, w = vc / denom;
  const Point3 q{a[0] + ab[0] * v + ac[0] * w, a[1] + ab[1] * v + ac[1] * w, a[2] + ab[2] * v + ac[2] * w};
  return sq_norm(sub(p, q));
}

double sq_distance_point_box(const Point3& x, const Point3& lo, const Point3& hi) {
  double sq = 0;
  for (int i = 0; i < 3; ++i) {
    const double d = x[i] < lo[i] ? lo[i] - x[i] : (x[i] > hi[i] ? x[i] - hi[i] : 0.0);
    sq += d * d;
  }
  return sq;
}

}  // namespace

LocalFeatureSize::LocalFeatureSize(const Plc& plc,
                                   const std::vector<std::vector<std::array<Index, 3>>>& facet_triangles)
    : points_(plc.vertices) {
  for (Index v = 0; v < plc.vertices.size(); ++v) {
    elements_.push_back({{v}});
    primitives_.push_back({PrimitiveKind::Point, {v, v, v}, static_cast<Index>(elements_.size() - 1)});
  }
  for (const Segment& s : collect_segments(plc)) {
    elements_.push_back({{std::min(s.a, s.b), std::max(s.a, s.b)}});
    primitives_.push_back({PrimitiveKind::Segment, {s.a, s.b, s.b}, static_cast<Index>(elements_.size() - 1)});
  }
  for (std::size_t f = 0; f < plc.facets.size(); ++f) {
    Element element;
    for (const auto& loop : plc.facets[f].polygons) element.vertices.insert(element.vertices.end(), loop.begin(), loop.end());
    std::sort(element.vertices.begin(), element.vertices.end());
    element.vertices.erase(std::unique(element.vertices.begin(), element.vertices.end()), element.vertices.end());
    elements_.push_back(std::move(element));
    const Index id = static_cast<Index>(elements_.size() - 1);
    if (f < facet_triangles.size()) {
      for (const auto& t : facet_triangles[f]) primitives_.push_back({PrimitiveKind::Triangle, t, id});
    }
  }
  for (Primitive& p : primitives_) {
    const int n = p.kind == PrimitiveKind::Point ? 1 : (p.kind == PrimitiveKind::Segment ? 2 : 3);
    for (int k = 0; k < n; ++k)
      for (int i = 0; i < 3; ++i) p.centroid[i] += points_[p.vertices[k]][i] / n;
  }
  if (!primitives_.empty()) build(0, static_cast<std::uint32_t>(primitives_.size()));
}

std::uint32_t LocalFeatureSize::build(std::uint32_t first, std::uint32_t count) {
  Node node{};
  BoundingBox box;
  BoundingBox centroid_box;
  for (std::uint32_t i = first; i < first + count; ++i) {
    const Primitive& p = primitives_[i];
    for (Index v : p.vertices) box.add(points_[v]);
    centroid_box.add(p.centroid);
  }
  node.box_min = box.min;
  node.box_max = box.max;
  const std::uint32_t index = static_cast<std::uint32_t>(nodes_.size());
  nodes_.push_back(node);
  if (count <= 4) {
    nodes_[index].first = first;
    nodes_[index].count = count;
    return index;
  }
  int axis = 0;
  for (int i = 1; i < 3; ++i) {
    if (centroid_box.max[i] - centroid_box.min[i] > centroid_box.max[axis] - centroid_box.min[axis]) axis = i;
  }
  const std::uint32_t half = count / 2;
  std::nth_element(primitives_.begin() + first, primitives_.begin() + first + half,
                   primitives_.begin() + first + count, [&](const Primitive& a, const Primitive& b) {
                     const double ca = a.centroid[axis], cb = b.centroid[axis];
                     if (ca != cb) return ca < cb;
                     return std::tie(a.element, a.vertices) < std::tie(b.element, b.vertices);  // determinism
                   });
  const std::uint32_t left = build(first, half);
  const std::uint32_t right = build(first + half, count - half);
  nodes_[index].count = 0;
  nodes_[index].left = left;
  nodes_[index].right = right;
  return index;
}

double LocalFeatureSize::sq_distance(const Primitive& p, const Point3& x) const {
  switch (p.kind) {
    case PrimitiveKind::Point: return sq_norm(sub(x, points_[p.vertices[0]]));
    case PrimitiveKind::Segment:
      return sq_distance_point_segment(x, points_[p.vertices[0]], points_[p.vertices[1]]);
    case PrimitiveKind::Triangle:
      return sq_distance_point_triangle(x, points_[p.vertices[0]], points_[p.vertices[1]], points_[p.vertices[2]]);
  }
  return std::numeric_limits<double>::infinity();
}

bool LocalFeatureSize::adjacent(Index a, Index b) const {
  const auto& va = elements_[a].vertices;
  const auto& vb = elements_[b].vertices;
  std::size_t i = 0, j = 0;
  while (i < va.size() && j < vb.size()) {
    if (va[i] == vb[j]) return true;
    if (va[i] < vb[j]) ++i; else ++j;
  }
  return false;
}

double LocalFeatureSize::operator()(const Point3& x) const {
  if (nodes_.empty()) return std::numeric_limits<double>::infinity();
  // Queue entries: (squared distance or lower bound, is_primitive, index). Ties: nodes before primitives does not
  // matter for the value; the order among equal distances cannot change f(x) (see the header).
  using Entry = std::pair<double, std::pair<bool, std::uint32_t>>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
  queue.push({sq_distance_point_box(x, nodes_[0].box_min, nodes_[0].box_max), {false, 0}});
  std::vector<Index> visited;  // elements in order of distance
  // seen[e] == stamp: element e was reached. The stamps outlive the call, so a query does not clear an array of
  // every vertex, segment and facet (a zeroed vector per query was 4% of fandisk.off's run: pumping asks f(v) for
  // every new vertex).
  thread_local std::vector<std::uint32_t> seen;
  thread_local std::uint32_t stamp = 0;
  if (seen.size() < elements_.size()) seen.resize(elements_.size(), 0);
  if (++stamp == 0) {  // wrapped
    std::fill(seen.begin(), seen.end(), 0);
    stamp = 1;
  }
  while (!queue.empty()) {
    const auto [sq, item] = queue.top();
    queue.pop();
    const auto [is_primitive, index] = item;
    if (is_primitive) {
      const Index element = primitives_[index].element;
      if (seen[element] == stamp) continue;  // a nearer primitive of this element came first
      seen[element] = stamp;
      for (Index earlier : visited) {
        if (!adjacent(earlier, element)) return std::sqrt(sq);
      }
      visited.push_back(element);
      continue;
    }
    const Node& node = nodes_[index];
    if (node.count > 0) {
      for (std::uint32_t i = node.first; i < node.first + node.count; ++i) {
        if (seen[primitives_[i].element] != stamp) queue.push({sq_distance(primitives_[i], x), {true, i}});
      }
    } else {
      for (std::uint32_t child : {node.left, node.right}) {
        queue.push({sq_distance_point_box(x, nodes_[child].box_min, nodes_[child].box_max), {false, child}});
      }
    }
  }
  return std::numeric_limits<double>::infinity();
}

double LocalFeatureSize::brute_force(const Point3& x) const {
  std::vector<double> sq(elements_.size(), std::numeric_limits<double>::infinity());
  for (const Primitive& p : primitives_) sq[p.element] = std::min(sq[p.element], sq_distance(p, x));
  double best = std::numeric_limits<double>::infinity();
  for (Index a = 0; a < elements_.size(); ++a) {
    for (Index b = a + 1; b < elements_.size(); ++b) {
      if (!adjacent(a, b)) best = std::min(best, std::max(sq[a], sq[b]));
    }
  }
  return std::sqrt(best);
}

std::vector<std::vector<std::array<Index, 3>>> plc_facet_triangles(const Plc& plc) {
  std::vector<std::vector<std::array<Index, 3>>> out(plc.facets.size());
  for (std::size_t f = 0; f < plc.facets.size(); ++f) {
    const Facet& facet = plc.facets[f];
    const auto frame = detail::compute_facet_frame(plc.vertices, facet);
    if (!frame) continue;
    // A lone triangle is its own triangulation (a tessellated surface is all of them: for bunny00.off's 75408
    // facets the 2D constrained triangulations took about 0.4 s of a 9.5 s run).
    if (facet.polygons.size() == 1 && facet.polygons[0].size() == 3 && facet.holes.empty()) {
      const auto& t = facet.polygons[0];
      out[f].push_back({t[0], t[1], t[2]});
      continue;
    }
    const detail::FacetTriangulation ft = detail::triangulate_facet(plc.vertices, facet, *frame);
    for (const auto& t : ft.triangles)
      if (ft.is_plc_vertex(t[0]) && ft.is_plc_vertex(t[1]) && ft.is_plc_vertex(t[2])) out[f].push_back(t);
  }
  return out;
}

}  // namespace qualmesh
