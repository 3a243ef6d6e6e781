// Acute input angles (beyond the paper, whose Lemmas 3.3 and 3.4 assume no input angle below 90 degrees): the
// protection of small angles in one place, after Shewchuk, "Mesh generation for domains with small angles".
//   - Rule 1 splits subsegments next to an acute input vertex on concentric shells (subsegments.cpp
//     subsegment_split_parameter), so that segments through the apex share their split radii;
//   - Rule 2 leaves a present subfacet encroached only by a vertex on an element meeting its facet at an acute
//     angle (subfacet_encroacher_exempt);
//   - Rule 3 leaves a tetrahedron whose shortest edge is forced by an acute angle (shortest_edge_forced_by_
//     acute_angle), and the quality figures report such tetrahedra apart (tet_touches_acute_angle, the one
//     definition behind MeshResult::tet_touches_acute_angle);
//   - Rule 4 tests no element meeting the vertex's host element at an acute angle (rule4.cpp).
// The angles themselves are InputComplex::elements_meet_acute's (complex.cpp): below 90 degrees under the paper's
// encroachment rule; under the relaxed rule on a surface or PLC a corner between two edges only below 30
// (RefineParams::corner_acute_deg), while the shells' apices (acute_vertex) keep 90. Protecting weighted balls at
// sharp vertices and segments (Cheng, Dey and Ramos; issue 16) would belong here too.
#include <limits>

#include "refine/refine_state.h"
#include "vec3.h"

namespace qualmesh::detail {

namespace {

using vec3::sq_dist;

// Whether w lies on an input segment that meets, at an acute angle, the segment of one of abc's vertices.
bool on_segment_acute_to_subfacet(const MeshState& s, Index w, const std::array<Index, 3>& abc) {
  const VertexRecord& rw = s.vertices[w];
  if (rw.kind != VertexKind::Segment) return false;
  for (Index v : abc) {
    const VertexRecord& rv = s.vertices[v];
    if (rv.kind == VertexKind::Segment && rv.host != rw.host &&
        s.complex.elements_meet_acute({InputComplex::ElementKind::Segment, rw.host},
                                      {InputComplex::ElementKind::Segment, rv.host}))
      return true;
  }
  return false;
}

}  // namespace

InputComplex::ElementRef host_element(const MeshState& s, Index v, bool* has) {
  const VertexRecord& r = s.vertices[v];
  *has = true;
  switch (r.kind) {
    case VertexKind::Input: return {InputComplex::ElementKind::Vertex, v};
    case VertexKind::Segment: return {InputComplex::ElementKind::Segment, r.host};
    case VertexKind::Facet: return {InputComplex::ElementKind::Facet, r.host};
    case VertexKind::Volume: break;
  }
  *has = false;
  return {InputComplex::ElementKind::Vertex, kNoIndex};
}

bool shortest_edge_forced_by_acute_angle(const MeshState& s, Index u, Index w) {
  bool hu = false, hw = false;
  const InputComplex::ElementRef eu = host_element(s, u, &hu), ew = host_element(s, w, &hw);
  return hu && hw && s.complex.elements_meet_acute(eu, ew);
}

bool tet_touches_acute_angle(const MeshState& s, const std::array<Index, 4>& ids) {
  double sq_min = std::numeric_limits<double>::infinity();
  int ea = 0, eb = 1;
  for (int a = 0; a < 4; ++a)
    for (int b = a + 1; b < 4; ++b) {
      const double d = sq_dist(s.point(ids[a]), s.point(ids[b]));
      if (d < sq_min) sq_min = d, ea = a, eb = b;
    }
  return shortest_edge_forced_by_acute_angle(s, ids[ea], ids[eb]);
}

bool subfacet_encroacher_exempt(const MeshState& s, Index facet, const std::array<Index, 3>& abc, Index enc) {
  // Concentric shells put the vertices of two segments meeting at an acute apex at equal radii: isosceles
  // trapezoids, whose four corners are cocircular, so whether one corner encroaches the subfacet of the other three
  // is decided by rounding in the exact 3D test (example024.scad's needle triangles: splitting there cascaded to
  // rounding-level subsegments). On the subfacet's own facet the facet's 2D Delaunay triangulation decides: the
  // subfacet is present and is the facet's Delaunay triangle (Section 7.2's definition of subfacets).
  if (on_segment_acute_to_subfacet(s, enc, abc) && vertex_on_facet(s, enc, facet) &&
      !encroaches_in_facet_plane(s, facet, abc, enc))
    return true;
  // An encroacher on an input element meeting the facet at an acute angle: splitting the subfacet would make the
  // two elements encroach each other without end; conformity only needs it present.
  bool has = false;
  const InputComplex::ElementRef he = host_element(s, enc, &has);
  return has && s.complex.elements_meet_acute(he, {InputComplex::ElementKind::Facet, facet});
}

}  // namespace qualmesh::detail
