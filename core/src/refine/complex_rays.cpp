// Ray queries of the input complex at a facet's own corners and edges in O(log n) (issue 18 item 6). Building the
// complex asks, for every segment of a facet, which side of it the facet covers (inward_directions, for the
// dihedral angles along shared segments) and, for every segment leaving a facet's corner, whether the facet covers
// its projection (segment_facet_angle_deg). facet_covers_ray answers by the parity of crossings with all n edges of
// the facet: n queries of n edges made a prism with 8000-gon caps take 39 s before refinement.
//
// For closed polygons that do not cross (a valid PLC), that parity is the side of the one edge, or the wedge of the
// one corner, at the ray's origin, given the side of each polygon its interior lies on. This file indexes each
// facet's corners and edges (sorted, binary search) and finds each polygon's interior side once, by the scan from
// its longest edge. A query is answered from the index only when that is decisive: the edge or corner is used once
// in the facet's closed polygons, the polygon's side is known (the scan found exactly one side covered), and the
// direction is more than 1e-9 rad from the corner's edges (so rounding cannot flip it). Anything else goes to the
// scan, which is the reference (InputComplex::scan_rays makes every query scan; the tests compare the two).
#include <algorithm>
#include <cmath>

#include "refine/complex.h"
#include "vec3.h"

namespace qualmesh::detail {

namespace {

using namespace vec3;

constexpr double kMargin = 1e-9;  // relative: |sin| of the angle between a direction and an edge

// Sign of the turn from x to y about n (+1 counterclockwise seen from +n), or 0 within the margin.
int turn(const Point3& n, const Point3& x, const Point3& y) {
  const double t = dot(n, cross(x, y));
  if (!(std::fabs(t) > kMargin * norm(x) * norm(y))) return 0;
  return t > 0 ? 1 : -1;
}

}  // namespace

void InputComplex::build_facet_index(Index f) {
  FacetIndex& index = facet_index[f];
  const auto& polygons = plc->facets[f].polygons;
  for (Index l = 0; l < polygons.size(); ++l) {
    const auto& loop = polygons[l];
    if (loop.size() < 3) continue;
    for (Index k = 0; k < loop.size(); ++k) {
      index.corners.push_back({loop[k], l, k});
      const Index a = loop[k], b = loop[(k + 1) % loop.size()];
      if (a != b) index.edges.push_back({key(a, b), {l, k}});
    }
  }
  std::sort(index.corners.begin(), index.corners.end());
  std::sort(index.edges.begin(), index.edges.end());
  const auto edge_used_once = [&](std::uint64_t k) {
    const auto it = std::lower_bound(index.edges.begin(), index.edges.end(), std::make_pair(k, std::array<Index, 2>{}));
    return it != index.edges.end() && it->first == k && (it + 1 == index.edges.end() || (it + 1)->first != k);
  };
  // Each polygon's interior side, from the scan at its longest edge used once (seg.a -> seg.b gives the scan's d).
  index.loop_side.assign(polygons.size(), 0);
  for (Index l = 0; l < polygons.size(); ++l) {
    const auto& loop = polygons[l];
    if (loop.size() < 3) continue;
    double longest = 0;
    Index best = kNoIndex;
    for (Index k = 0; k < loop.size(); ++k) {
      const Index a = loop[k], b = loop[(k + 1) % loop.size()];
      if (a == b || !edge_used_once(key(a, b))) continue;
      const Point3 e = sub(plc->vertices[b], plc->vertices[a]);
      if (dot(e, e) > longest) longest = dot(e, e), best = k;
    }
    if (best == kNoIndex) continue;
    const Index a = loop[best], b = loop[(best + 1) % loop.size()];
    const Index s = find_segment(a, b);
    if (s == kNoIndex) continue;
    const std::vector<Point3> inward = scan_inward_directions(f, s);
    if (inward.size() != 1) continue;
    const Point3 d = cross(frames[f].normal, sub(plc->vertices[segments[s].b], plc->vertices[segments[s].a]));
    const bool on_d_side = dot(inward[0], d) > 0;  // relative to seg.a -> seg.b
    const bool forward = segments[s].a == a;        // the loop runs seg.a -> seg.b here
    index.loop_side[l] = on_d_side == forward ? 1 : -1;
  }
}

std::pair<const std::array<Index, 3>*, const std::array<Index, 3>*> InputComplex::corners_at(Index f, Index v) const {
  const auto& corners = facet_index[f].corners;
  const auto first = std::lower_bound(corners.begin(), corners.end(), std::array<Index, 3>{v, 0, 0});
  auto last = first;
  while (last != corners.end() && (*last)[0] == v) ++last;
  return {corners.data() + (first - corners.begin()), corners.data() + (last - corners.begin())};
}

int InputComplex::indexed_edge_side(Index f, Index s) const {
  const FacetIndex& index = facet_index[f];
  const Segment& seg = segments[s];
  const std::uint64_t k = key(seg.a, seg.b);
  const auto it = std::lower_bound(index.edges.begin(), index.edges.end(), std::make_pair(k, std::array<Index, 2>{}));
  if (it == index.edges.end() || it->first != k) return 0;  // not a polygon edge (a segment inside the facet)
  if (it + 1 != index.edges.end() && (it + 1)->first == k) return 0;  // on two polygons, or twice on one
  const Index l = it->second[0], position = it->second[1];
  const int side = index.loop_side[l];
  if (side == 0) return 0;
  const bool forward = plc->facets[f].polygons[l][position] == seg.a;
  return forward ? side : -side;
}

int InputComplex::indexed_corner_covers(Index f, Index v, const Point3& dir) const {
  const auto [first, last] = corners_at(f, v);
  if (last - first != 1) return 0;  // v on two corners of the facet: the wedges together decide, scan
  const Index l = (*first)[1], k = (*first)[2];
  const int side = facet_index[f].loop_side[l];
  if (side == 0) return 0;
  const auto& loop = plc->facets[f].polygons[l];
  const Point3& at = plc->vertices[v];
  const Point3 previous = sub(plc->vertices[loop[(k + loop.size() - 1) % loop.size()]], at);
  const Point3 next = sub(plc->vertices[loop[(k + 1) % loop.size()]], at);
  // The interior is the counterclockwise sweep (about the normal) from `next` to `previous` when it lies on the
  // cross(normal, edge) side of the loop's edges, else from `previous` to `next`.
  const Point3& from = side > 0 ? next : previous;
  const Point3& to = side > 0 ? previous : next;
  // The ray in the plane as the scan sees it: a zero direction covers nothing there (every crossing test fails).
  const PlaneFrame& frame = frames[f];
  const double dx = dot(dir, frame.e1), dy = dot(dir, frame.e2);
  if (dx == 0 && dy == 0) return -1;
  const Point3 in_plane{dx * frame.e1[0] + dy * frame.e2[0], dx * frame.e1[1] + dy * frame.e2[1],
                        dx * frame.e1[2] + dy * frame.e2[2]};
  const Point3& n = frame.normal;
  const int sweep = turn(n, from, to), enter = turn(n, from, in_plane), leave = turn(n, in_plane, to);
  if (sweep == 0 || enter == 0 || leave == 0) return 0;  // straight or spike corner, or dir along an edge
  const bool inside = sweep > 0 ? (enter > 0 && leave > 0) : (enter > 0 || leave > 0);
  return inside ? 1 : -1;
}

}  // namespace qualmesh::detail
