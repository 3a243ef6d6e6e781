// Subsegments (paper Section 3.2): the vertices on an input segment, kept as an ordered chain per segment, and the
// split point of Rule 1. Membership of a vertex in a segment or facet is symbolic (its host element), never decided
// by a distance.
//
// Rule 1 inserts the midpoint of an encroached subsegment. On a segment that ends at the apex of an acute input
// angle, the split point is instead at a dyadic distance from the apex (a power of two when the subsegment ends at
// the apex, else the coarsest k 2^j) in the middle third of the subsegment (Shewchuk's concentric shells, "Mesh
// generation for domains with small angles", 2000): the vertices on all segments through the apex then lie on
// common spheres centred at it, and the diametral ball of a subsegment between radii r1 < r2 lies in the shell
// r1 <= |x - apex| <= r2, so subsegments of two segments through the apex never encroach each other, however small
// their angle (a CAD tessellation's needle triangles meet at 0.005 degrees). Refinement then terminates although
// Lemma 3.3 (which needs angles >= pi/2) does not hold there.
#include <algorithm>
#include <cmath>

#include "refine/refine_state.h"

namespace qualmesh::detail {

bool vertex_on_segment(const MeshState& s, Index v, Index segment) {
  const VertexRecord& r = s.vertices[v];
  if (r.kind == VertexKind::Segment) return r.host == segment;
  if (r.kind == VertexKind::Input) {
    const Segment& seg = s.complex.segments[segment];
    return seg.a == v || seg.b == v;
  }
  return false;
}

bool vertex_on_facet(const MeshState& s, Index v, Index facet) {
  const VertexRecord& r = s.vertices[v];
  switch (r.kind) {
    case VertexKind::Facet: return r.host == facet;
    case VertexKind::Segment: return s.complex.facet_has_segment(facet, r.host);
    case VertexKind::Input: {
      const auto& fs = s.complex.vertex_facets[v];
      return std::binary_search(fs.begin(), fs.end(), facet);
    }
    case VertexKind::Volume: return false;
  }
  return false;
}

bool vertex_on_plane(const MeshState& s, Index v, Index group) {
  const VertexRecord& r = s.vertices[v];
  const auto& g = s.complex.plane_group;
  switch (r.kind) {
    case VertexKind::Facet: return g[r.host] == group;
    case VertexKind::Segment:
      for (const SegmentInFacet& sf : s.complex.segment_facets[r.host])
        if (g[sf.facet] == group) return true;
      return false;
    case VertexKind::Input:
      for (Index f : s.complex.vertex_facets[v])
        if (g[f] == group) return true;
      return false;
    case VertexKind::Volume: return false;
  }
  return false;
}

Index next_on_segment(const MeshState& s, Index segment, Index v) {
  const Segment& seg = s.complex.segments[segment];
  const SegmentChain& chain = s.chains[segment];
  if (v == seg.a) return chain.first == kNoIndex ? seg.b : chain.first;
  if (v == seg.b) return kNoIndex;
  return s.vertices[v].next;
}

namespace {
Index prev_on_segment(const MeshState& s, Index segment, Index v) {
  const Segment& seg = s.complex.segments[segment];
  const SegmentChain& chain = s.chains[segment];
  if (v == seg.b) return chain.last == kNoIndex ? seg.a : chain.last;
  if (v == seg.a) return kNoIndex;
  return s.vertices[v].prev;
}
}  // namespace

Index subsegment_of(const MeshState& s, Index u, Index v) {
  const VertexRecord& ru = s.vertices[u];
  const VertexRecord& rv = s.vertices[v];
  if (!can_end_subsegment(ru.kind) || !can_end_subsegment(rv.kind)) return kNoIndex;
  if (ru.kind == VertexKind::Segment || rv.kind == VertexKind::Segment) {
    const Index segment = ru.kind == VertexKind::Segment ? ru.host : rv.host;
    const Index w = ru.kind == VertexKind::Segment ? u : v;
    const Index other = w == u ? v : u;
    if (!vertex_on_segment(s, other, segment)) return kNoIndex;
    if (next_on_segment(s, segment, w) == other || prev_on_segment(s, segment, w) == other) return segment;
    return kNoIndex;
  }
  if (ru.kind == VertexKind::Input && rv.kind == VertexKind::Input) {
    const Index segment = s.complex.find_segment(u, v);
    if (segment == kNoIndex || s.chains[segment].first != kNoIndex) return kNoIndex;
    return segment;
  }
  return kNoIndex;
}

double segment_parameter(const MeshState& s, Index segment, Index w) {
  const Segment& seg = s.complex.segments[segment];
  return w == seg.a ? 0.0 : (w == seg.b ? 1.0 : s.vertices[w].t);
}

double subsegment_split_parameter(const MeshState& s, Index segment, Index u, Index v) {
  const Segment& seg = s.complex.segments[segment];
  const double tu = segment_parameter(s, segment, u), tv = segment_parameter(s, segment, v);
  const double mid = 0.5 * (tu + tv);
  const bool acute_a = s.complex.acute_vertex[seg.a] != 0, acute_b = s.complex.acute_vertex[seg.b] != 0;
  if (!acute_a && !acute_b) return mid;
  if (acute_a && acute_b && std::min(tu, tv) == 0.0 && std::max(tu, tv) == 1.0) return mid;  // halves first
  // The apex that governs this subsegment: the acute end, or the nearer one when both are (the first split of such
  // a segment is its midpoint, so no subsegment straddles it).
  const bool from_a = acute_a && (!acute_b || mid < 0.5);
  const Point3& a = s.point(seg.a);
  const Point3& b = s.point(seg.b);
  const double seg_len = std::sqrt((b[0] - a[0]) * (b[0] - a[0]) + (b[1] - a[1]) * (b[1] - a[1]) + (b[2] - a[2]) * (b[2] - a[2]));
  // Distances from the apex along the segment.
  const double ru = (from_a ? tu : 1.0 - tu) * seg_len, rv = (from_a ? tv : 1.0 - tv) * seg_len;
  const double lo = std::min(ru, rv), hi = std::max(ru, rv);
  if (!(hi > lo)) return mid;
  double r = 0;
  if (lo == 0.0) {
    r = std::exp2(std::floor(std::log2(hi * (2.0 / 3.0))));  // a power of two in (hi/3, 2hi/3]
  } else {
    // The coarsest dyadic radius k 2^j in the middle third [x1, x2]: segments through the apex then share their split
    // radii even where their far ends differ, so nearly parallel segments stop encroaching each other.
    const double x1 = lo + (hi - lo) / 3.0, x2 = lo + 2.0 * (hi - lo) / 3.0;
    double h = std::exp2(std::ceil(std::log2(hi)));
    for (int guard = 0; guard < 2100 && !(r > 0); ++guard, h *= 0.5) {
      const double k = std::ceil(x1 / h);
      if (k * h <= x2) r = k * h;
    }
    if (!(r > 0)) return mid;
  }
  const double t = from_a ? r / seg_len : 1.0 - r / seg_len;
  if (!(t > std::min(tu, tv) && t < std::max(tu, tv))) return mid;
  return t;
}

void link_segment_vertex(MeshState& s, Index segment, Index u, Index v, Index w) {
  // Orient (u, v) along the segment.
  if (next_on_segment(s, segment, u) != v) std::swap(u, v);
  const Segment& seg = s.complex.segments[segment];
  SegmentChain& chain = s.chains[segment];
  VertexRecord& rw = s.vertices[w];
  rw.prev = u;
  rw.next = v;
  if (u == seg.a) chain.first = w; else s.vertices[u].next = w;
  if (v == seg.b) chain.last = w; else s.vertices[v].prev = w;
}

const std::vector<Index>* host_element_vertices(const MeshState& s, Index v, std::vector<Index>& scratch) {
  const VertexRecord& r = s.vertices[v];
  switch (r.kind) {
    case VertexKind::Input:
      scratch.assign(1, v);
      return &scratch;
    case VertexKind::Segment: {
      const Segment& seg = s.complex.segments[r.host];
      scratch = {std::min(seg.a, seg.b), std::max(seg.a, seg.b)};
      return &scratch;
    }
    case VertexKind::Facet: return &s.complex.facet_vertices[r.host];
    case VertexKind::Volume: return nullptr;
  }
  return nullptr;
}

}  // namespace qualmesh::detail
