// Boundary points onto the curved CAD entities their elements stand for (beyond the paper; MeshOptions::
// project_to_boundary). A CAD model reaches the engine as a PLC whose curved faces are triangles and whose curved
// edges are chains of segments: a point that Rule 1 puts on a subsegment, or Rule 2 on a subfacet, lies on a chord
// of the surface. The CLI fitted such points onto the CAD surface after meshing, which a point next to a thin
// element cannot take without inverting it (cad_fit.cpp: "part way"). Here the point is moved onto its CAD edge (a
// segment with a CAD edge number, Segment::marker) or face (a facet's Facet::marker; a segment inside one curved
// face, between facets of that face only) before its conflict test, so the triangulation is built around it where
// it belongs. Membership stays symbolic (the host segment or facet and its parameter, Section "Key decisions" of
// DESIGN.md): the point is off the chord by the sagitta only, and a move larger than a quarter of the element it
// splits (a projection gone astray) is not made.
#include <cmath>

#include "refine/refine_state.h"
#include "vec3.h"

namespace qualmesh::detail {

namespace {

// Applies the projection when it moves p by at most max_move.
bool project_within(const MeshState& s, int edge, int face, double max_move, Point3& p) {
  Point3 q = p;
  if (!s.options.project_to_boundary(edge, face, q)) return false;
  if (!(vec3::dist(p, q) <= max_move)) return false;
  p = q;
  return true;
}

}  // namespace

bool project_segment_point(const MeshState& s, Index segment, double max_move, Point3& p) {
  if (!s.options.project_to_boundary) return false;
  const int edge = s.complex.segments[segment].marker;
  if (edge > 0) return project_within(s, edge, 0, max_move, p);
  // A segment with no CAD edge: an edge between triangles of one curved face (all its facets carry that face).
  int face = 0;
  for (const SegmentInFacet& in : s.complex.segment_facets[segment]) {
    const int marker = s.complex.plc->facets[in.facet].marker;
    if (marker <= 0 || (face != 0 && marker != face)) return false;
    face = marker;
  }
  return face > 0 && project_within(s, 0, face, max_move, p);
}

bool project_facet_point(const MeshState& s, Index facet, double max_move, Point3& p) {
  if (!s.options.project_to_boundary) return false;
  const int face = s.complex.plc->facets[facet].marker;
  return face > 0 && project_within(s, 0, face, max_move, p);
}

}  // namespace qualmesh::detail
