// Rule 2 of QUALMESH (Cheng & Dey, Section 3.7, step 2): split a subfacet that is encroached (a vertex strictly
// inside its diametral ball, Section 3.2) or missing from the triangulation, at its circumcentre. Lemma 3.5: of the
// subfacets the encroacher encroaches, the one containing its projection onto the facet is split. Rule 2's second
// clause: a circumcentre that encroaches subsegments is rejected and those subsegments are split instead (Rule 1);
// the subfacet is queued again behind them. Rule 3 hands this level the subfacets its rejected centres encroach
// (entries with the point), Rule 4 those a weighted vertex encroaches (rule4.cpp). Which vertices encroach a
// present subfacet is the policy's (EncroachmentPolicy); an `eager` entry counts every vertex.
//
// Beyond the paper:
//   - Steiner mode: a centre beyond a subsegment of its facet (one that a tolerated vertex encroaches, typically
//     next to an acute corner of the facet) is rejected for the first subsegment the straight walk in the facet's
//     plane crosses (subsegment_towards, as Triangle does), without computing the centre's conflict zone, which is
//     huge outside the domain (the cells there are never refined);
//   - small input angles (Shewchuk, "Mesh generation for domains with small angles"): a present subfacet
//     encroached only by a vertex on an element meeting its facet at an acute angle is left (small_angles.cpp);
//   - a missing subfacet of four cocircular points is first flipped to the 3D triangulation's diagonal.
#include <algorithm>
#include <cmath>
#include <string>

#include "refine/refine_state.h"

namespace qualmesh::detail {

bool Rule2Subfacets::encroached(const MeshState& s, const std::array<Index, 3>& abc, Index* encroacher,
                                bool all) const {
  const Vh3 ha = s.vertices[abc[0]].handle, hb = s.vertices[abc[1]].handle, hc = s.vertices[abc[2]].handle;
  Ch3 c;
  int i = 0, j = 0, k = 0;
  *encroacher = kNoIndex;
  if (!s.tr.is_facet(ha, hb, hc, c, i, j, k)) return true;
  const int l = 6 - i - j - k;
  const Ch3 n = c->neighbor(l);
  const Vh3 apices[2] = {c->vertex(l), n->vertex(n->index(c))};
  const KPoint3 a = s.kpoint(abc[0]), b = s.kpoint(abc[1]), cc = s.kpoint(abc[2]);
  for (const Vh3 w : apices) {
    if (w == s.tr.infinite_vertex() || !(all || policy.counts(s, w->info()))) continue;
    if (strictly_encroaches(a, b, cc, s.kpoint(w->info()))) {
      *encroacher = w->info();
      return true;
    }
  }
  return false;
}

void Rule2Subfacets::enqueue_if_encroached(MeshState& s, Index facet, const std::array<Index, 3>& abc) {
  Index enc;
  if (encroached(s, abc, &enc, false)) push({facet, abc, false, {}});
}

void Rule2Subfacets::enqueue_if_encroached(MeshState& s, Index facet,
                                           const std::vector<std::array<Index, 3>>& faces) {
  for (const auto& f : faces) enqueue_if_encroached(s, facet, f);
}

KPoint3 Rule2Subfacets::refinement_point(const MeshState& s, const std::array<Index, 3>& abc) const {
  return CGAL::circumcenter(s.kpoint(abc[0]), s.kpoint(abc[1]), s.kpoint(abc[2]));
}

Conflict Rule2Subfacets::conflict(MeshState& s, Index facet, const std::array<Index, 3>& abc,
                                  const KPoint3& center, ConflictZone& cz, Candidates& cand) const {
  // Three nearly coincident vertices (a runaway near a tiny input angle splits down to rounding) have no centre in
  // floating point: a NaN point would poison every predicate of the triangulation (bottle.brep at --size 80).
  if (!std::isfinite(center.x()) || !std::isfinite(center.y()) || !std::isfinite(center.z())) return Conflict::Drop;
  if (policy.walks_to_centres()) {
    // Steiner mode: the first subsegment that the walk from the subfacet to its centre crosses (file comment).
    if (auto uv = subsegment_towards(s, facet, abc, to_point3(center))) {
      const Index seg = subsegment_of(s, (*uv)[0], (*uv)[1]);
      if (seg != kNoIndex) {
        s.rule1.push({seg, std::min((*uv)[0], (*uv)[1]), std::max((*uv)[0], (*uv)[1]), true, true});
        return Conflict::SplitSubsegment;
      }
    }
  }
  if (!find_conflict_zone(s, center, hint_of(s, abc[0]), cz)) return Conflict::Drop;
  collect_candidates(s, cz, cand);
  bool rejected = false;
  for (const auto& e : cand.subsegments) {
    if (strictly_encroaches(s.kpoint(e[1]), s.kpoint(e[2]), center)) {
      s.rule1.push({e[0], e[1], e[2], true, true});
      rejected = true;
    }
  }
  if (!rejected && !facet_point_in_domain(s, facet, to_point3(center), abc[0])) {
    // The centre left the facet without encroaching a subsegment in floating point: split the facet's boundary
    // subsegments of this subfacet instead (Rule 1), which is what the exact geometry asks for.
    for (int i = 0; i < 3; ++i) {
      const Index u = abc[i], v = abc[(i + 1) % 3];
      const Index seg = subsegment_of(s, u, v);
      if (seg != kNoIndex) {
        s.rule1.push({seg, std::min(u, v), std::max(u, v), true, true});
        rejected = true;
      }
    }
    if (!rejected) return Conflict::Drop;
  }
  return rejected ? Conflict::SplitSubsegment : Conflict::None;
}

namespace {

// Splits subfacet abc of `facet` at its circumcentre unless the conflict test rejects it; returns whether it
// inserted the centre.
bool split_subfacet(MeshState& s, Rule2Subfacets& level, Index facet, const std::array<Index, 3>& abc) {
  KPoint3 center = level.refinement_point(s, abc);
  // On a curved CAD face: onto it (boundary_projection.cpp), by at most a quarter of the circumradius.
  Point3 p = to_point3(center);
  if (project_facet_point(s, facet, 0.25 * std::sqrt(CGAL::squared_distance(center, s.kpoint(abc[0]))), p))
    center = to_kpoint(p);
  ConflictZone cz;
  Candidates cand;
  const Conflict conflict = level.conflict(s, facet, abc, center, cz, cand);
  if (conflict == Conflict::SplitSubsegment) ++s.stats.num_rejected_circumcenters;
  if (conflict != Conflict::None) return false;
  VertexRecord r;  // the centre as insert_vertex will see it
  r.point = to_point3(center);
  r.kind = VertexKind::Facet;
  r.host = facet;
  if (!facet_accepts_point(s, r)) {
    s.stop_at_precision("facet " + std::to_string(facet),
                        std::sqrt(CGAL::squared_radius(s.kpoint(abc[0]), s.kpoint(abc[1]), s.kpoint(abc[2]))),
                        r.point);
    return false;
  }
  if (s.params.subfacet_below_floor(CGAL::squared_radius(s.kpoint(abc[0]), s.kpoint(abc[1]), s.kpoint(abc[2]))))
    s.count_below_floor_split();  // a missing subfacet below the floor
  const Index w = add_vertex(s, to_point3(center), VertexKind::Facet, facet);
  ++s.stats.num_rule2_insertions;
  notify_insertion(s, insert_vertex(s, w, cz, cand, kUnknownRegion));
  return true;
}

}  // namespace

void Rule2Subfacets::refine_one(MeshState& s) {
  const SubfacetEntry e = queue.front();
  queue.pop_front();
  const auto& abc = e.vertices;
  if (!is_subfacet(s, e.facet, abc[0], abc[1], abc[2])) return;  // stale
  Index enc = kNoIndex;
  bool is_encroached = encroached(s, abc, &enc, e.eager);
  const bool missing = is_encroached && enc == kNoIndex;
  const KPoint3 a = s.kpoint(abc[0]), b = s.kpoint(abc[1]), c = s.kpoint(abc[2]);
  if (!is_encroached && e.has_point && strictly_encroaches(a, b, c, to_kpoint(e.point))) is_encroached = true;
  if (!is_encroached && !e.forced) return;
  if (is_encroached && !missing && !e.forced && enc != kNoIndex && subfacet_encroacher_exempt(s, e.facet, abc, enc)) {
    ++s.stats.num_skipped_small_angle;
    return;
  }
  if (!missing &&
      s.params.subfacet_below_floor(CGAL::squared_radius(s.kpoint(abc[0]), s.kpoint(abc[1]), s.kpoint(abc[2])))) {
    ++s.stats.num_skipped_floor;  // the split floor (RefineParams::sq_split_floor): a present subfacet stays
    return;
  }
  if (missing) {
    // Cocircular subfacets: the 3D triangulation may have chosen the other diagonal; both are Delaunay.
    std::vector<std::array<Index, 3>> flipped;
    if (flip_subfacet_to_match(s, e.facet, abc, &flipped)) {
      enqueue_if_encroached(s, e.facet, flipped);
      return;
    }
  }
  // Lemma 3.5: among the subfacets the encroacher encroaches, split the one containing its projection.
  std::array<Index, 3> target = abc;
  const bool has_encroacher = enc != kNoIndex || e.has_point;
  if (has_encroacher) {
    const Point3 q = enc != kNoIndex ? s.point(enc) : e.point;
    if (auto h = subfacet_containing_projection(s, e.facet, q, abc[0])) {
      if (strictly_encroaches(s.kpoint((*h)[0]), s.kpoint((*h)[1]), s.kpoint((*h)[2]), to_kpoint(q))) target = *h;
    }
  }
  if (split_subfacet(s, *this, e.facet, target)) return;
  // Rejected (Rule 2's second clause: the centre encroaches subsegments, now queued for Rule 1): the subfacet stays
  // encroached or missing, and a missing one is a face of no cell, so no later conflict zone would find it again.
  // Queue it behind those splits (Rule 1 runs first); stale or healed entries cost nothing when popped.
  if (e.attempts < 16) {
    SubfacetEntry again = e;
    ++again.attempts;
    push(again);
  }
}

void Rule2Subfacets::after_insertion(MeshState& s, const InsertionResult& r) {
  const KPoint3 p = s.kpoint(r.vertex);
  for (std::size_t n = 0; n < r.zone_subfacets.size(); ++n) {
    const auto& f = r.zone_subfacets[n];  // f[1] < f[2] < f[3]
    if (!is_subfacet(s, f[0], f[1], f[2], f[3])) continue;
    if (!r.zone_subfacet_kept[n] || strictly_encroaches(s.kpoint(f[1]), s.kpoint(f[2]), s.kpoint(f[3]), p))
      push({f[0], {f[1], f[2], f[3]}, false, {}});
  }
  for (const auto& f : r.new_subfacets) enqueue_if_encroached(s, f[0], {f[1], f[2], f[3]});
}

}  // namespace qualmesh::detail
