// Subsegments (paper Section 3.2): the vertices on an input segment, kept as an ordered chain per segment, and the
// split point of Rule 1. Membership of a vertex in a segment or facet is symbolic (its host element), never decided
// by a distance.
//
// Rule 1 inserts the midpoint of an encroached subsegment. When a subsegment ends at an input vertex that is the apex
// of an acute input angle, the split point is instead the point at a power-of-two distance from the apex that lies
// in the middle third of the subsegment (Shewchuk's concentric shells, "Mesh generation for domains with small
// angles", 2000): vertices on the segments around the apex then lie on common spheres centred at the apex, so
// subsegments on adjacent segments stop encroaching each other and refinement terminates although Lemma 3.3 (which
// needs angles >= pi/2) does not hold there.
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

double subsegment_split_parameter(const MeshState& s, Index segment, Index u, Index v) {
  const Segment& seg = s.complex.segments[segment];
  auto param = [&](Index w) { return w == seg.a ? 0.0 : (w == seg.b ? 1.0 : s.vertices[w].t); };
  const double tu = param(u), tv = param(v);
  const double mid = 0.5 * (tu + tv);
  const bool acute_u = s.vertices[u].kind == VertexKind::Input && s.complex.acute_vertex[u];
  const bool acute_v = s.vertices[v].kind == VertexKind::Input && s.complex.acute_vertex[v];
  if (acute_u == acute_v) return mid;  // neither end, or both ends (split at the midpoint first), are apices
  // Concentric shells around the acute apex: distance 2^k from it, in the middle third of the subsegment.
  const Point3& a = s.point(seg.a);
  const Point3& b = s.point(seg.b);
  const double seg_len = std::sqrt((b[0] - a[0]) * (b[0] - a[0]) + (b[1] - a[1]) * (b[1] - a[1]) + (b[2] - a[2]) * (b[2] - a[2]));
  const double len = std::abs(tv - tu) * seg_len;
  if (!(len > 0)) return mid;
  const double d = std::exp2(std::floor(std::log2(len * (2.0 / 3.0))));  // in (len/3, 2len/3]
  const double dt = d / seg_len;
  if (acute_u) return tu + (tv > tu ? dt : -dt);
  return tv + (tu > tv ? dt : -dt);
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
