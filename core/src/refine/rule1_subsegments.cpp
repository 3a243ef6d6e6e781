// Rule 1 of QUALMESH (Cheng & Dey, Section 3.7, step 2): split a subsegment that is encroached (a vertex strictly
// inside its diametral ball, Section 3.2) or missing from the triangulation. The split point is the midpoint, or,
// next to an acute input vertex (beyond the paper, which assumes none), Shewchuk's concentric-shell point
// (subsegments.cpp subsegment_split_parameter), so that segments meeting at a small angle stop encroaching each
// other. Rules 2 and 3 hand this level the subsegments their rejected centres encroach (forced entries); Rule 4
// those a weighted vertex encroaches (rule4.cpp). Which vertices encroach a present subsegment is the policy's
// (EncroachmentPolicy: the paper's "every vertex", or Steiner vertices only).
//
// A subsegment's split point is never rejected (Rule 1 is the first level): its conflict test only drops a point
// that rounding put on a vertex, and a point whose place in a facet's 2D triangulation is a vertex stops refinement
// (MeshState::stop_at_precision). Entries are checked when popped (still consecutive on the segment, still
// encroached or forced), so stale ones cost nothing.
#include <algorithm>
#include <cmath>
#include <string>

#include "refine/refine_state.h"

namespace qualmesh::detail {

bool Rule1Subsegments::encroached(const MeshState& s, Index segment, Index u, Index v, Index* encroacher) const {
  const Vh3 hu = s.vertices[u].handle, hv = s.vertices[v].handle;
  Ch3 c;
  int i = 0, j = 0;
  *encroacher = kNoIndex;
  if (!s.tr.is_edge(hu, hv, c, i, j)) return true;
  const KPoint3 a = s.kpoint(u), b = s.kpoint(v);
  auto cc = s.tr.incident_cells(c, i, j), done = cc;
  do {
    for (int k = 0; k < 4; ++k) {
      const Vh3 w = cc->vertex(k);
      if (w == hu || w == hv || w == s.tr.infinite_vertex() || !policy.counts(s, w->info(), segment)) continue;
      if (strictly_encroaches(a, b, s.kpoint(w->info()))) {
        *encroacher = w->info();
        return true;
      }
    }
  } while (++cc != done);
  return false;
}

void Rule1Subsegments::enqueue_if_encroached(MeshState& s, Index segment, Index u, Index v) {
  Index enc;
  if (encroached(s, segment, u, v, &enc)) push({segment, u, v});
}

Point3 Rule1Subsegments::refinement_point(const MeshState& s, Index segment, Index u, Index v, double* t) const {
  *t = subsegment_split_parameter(s, segment, u, v);
  const Segment& sg = s.complex.segments[segment];
  const Point3& a = s.point(sg.a);
  const Point3& b = s.point(sg.b);
  Point3 p{a[0] + *t * (b[0] - a[0]), a[1] + *t * (b[1] - a[1]), a[2] + *t * (b[2] - a[2])};
  if (!s.options.project_to_boundary) return p;
  // On a curved CAD edge or face: onto it (boundary_projection.cpp), by at most a quarter of the subsegment. The
  // point goes at the same place between u and v as t is between theirs, on the chord uv: u and v were projected
  // when they were inserted, so uv is off the curve by its own sagitta only, while the input segment ab is off it by
  // the whole tessellation chord's. From ab, a split near the tips of part.step's cusps moved 0.36 against a
  // subsegment of 1 and was refused, and the fit after meshing could move the node only part of the way.
  const Point3 &pu = s.point(u), &pv = s.point(v);
  const double length =
      std::sqrt((pu[0] - pv[0]) * (pu[0] - pv[0]) + (pu[1] - pv[1]) * (pu[1] - pv[1]) + (pu[2] - pv[2]) * (pu[2] - pv[2]));
  const double tu = segment_parameter(s, segment, u), tv = segment_parameter(s, segment, v);
  if (tv != tu) {
    const double f = (*t - tu) / (tv - tu);
    Point3 q{pu[0] + f * (pv[0] - pu[0]), pu[1] + f * (pv[1] - pu[1]), pu[2] + f * (pv[2] - pu[2])};
    if (project_segment_point(s, segment, 0.25 * length, q)) return q;
  }
  project_segment_point(s, segment, 0.25 * length, p);
  return p;
}

Conflict Rule1Subsegments::conflict(MeshState& s, const Point3& p, Ch3 hint, ConflictZone& cz) const {
  return find_conflict_zone(s, to_kpoint(p), hint, cz) ? Conflict::None : Conflict::Drop;  // Drop: underflow
}

void Rule1Subsegments::refine_one(MeshState& s) {
  const SubsegmentEntry e = queue.front();
  queue.pop_front();
  if (subsegment_of(s, e.u, e.v) != e.segment) return;  // stale
  Index enc = kNoIndex;
  if (!e.forced && !encroached(s, e.segment, e.u, e.v, &enc)) return;
  // The split floor (RefineParams::sq_split_floor: min_split_length or the rounding floor): a present subsegment
  // below it stays, unless a subfacet's centre forced it (below_floor_too); a missing one is split all the same, and
  // either split is counted.
  if (s.params.subsegment_below_floor(CGAL::squared_distance(s.kpoint(e.u), s.kpoint(e.v)))) {
    Ch3 c;
    int i = 0, j = 0;
    if (!e.below_floor_too && s.tr.is_edge(s.vertices[e.u].handle, s.vertices[e.v].handle, c, i, j)) {
      ++s.stats.num_skipped_floor;
      return;
    }
    s.count_below_floor_split();
  }
  double t = 0;
  const Point3 p = refinement_point(s, e.segment, e.u, e.v, &t);
  VertexRecord r;  // the split point as insert_vertex will see it
  r.point = p;
  r.kind = VertexKind::Segment;
  r.host = e.segment;
  r.t = t;
  r.prev = e.u;
  r.next = e.v;
  if (next_on_segment(s, e.segment, r.prev) != r.next) std::swap(r.prev, r.next);
  if (!facet_accepts_point(s, r)) {
    s.stop_at_precision("segment " + std::to_string(e.segment),
                        std::sqrt(CGAL::squared_distance(s.kpoint(e.u), s.kpoint(e.v))), p);
    return;
  }
  ConflictZone cz;
  if (conflict(s, p, hint_of(s, e.u), cz) != Conflict::None) return;
  Candidates cand;
  collect_candidates(s, cz, cand);
  const Index w = add_vertex(s, p, VertexKind::Segment, e.segment, t);
  link_segment_vertex(s, e.segment, e.u, e.v, w);
  ++s.stats.num_rule1_insertions;
  notify_insertion(s, insert_vertex(s, w, cz, cand, kUnknownRegion));
}

void Rule1Subsegments::after_insertion(MeshState& s, const InsertionResult& r) {
  const KPoint3 p = s.kpoint(r.vertex);
  for (std::size_t n = 0; n < r.zone_subsegments.size(); ++n) {
    const auto& e = r.zone_subsegments[n];  // e[1] < e[2]
    if (subsegment_of(s, e[1], e[2]) != e[0]) continue;
    if (!r.zone_subsegment_kept[n] || strictly_encroaches(s.kpoint(e[1]), s.kpoint(e[2]), p))
      push({e[0], e[1], e[2]});
  }
  for (const auto& e : r.new_subsegments) enqueue_if_encroached(s, e[0], e[1], e[2]);
}

}  // namespace qualmesh::detail
