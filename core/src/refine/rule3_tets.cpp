// Rule 3 of QUALMESH (Cheng & Dey, Section 3.7, step 2): insert the circumcentre z of a tetrahedron inside the
// domain whose radius-edge ratio exceeds rho0 (or, beyond the paper, that is too large for the size field:
// RefineParams::sq_max_edge, max_volume and region seeds), unless
//   - z encroaches subsegments: they are split instead (Rule 1), or
//   - z encroaches subfacets (or its insertion would remove one): the subfacet containing z's projection is split
//     instead (Rule 2, which applies Lemma 3.5 with the point z);
// then the tetrahedron is queued again (up to 8 times, then given up: MeshStats' "rejected").
//
// Beyond the paper:
//   - Steiner mode (EncroachmentPolicy::walks_to_centres): z's conflict zone is first grown inside the cell's
//     region (conflict_zone_in_region); when it would cross a subfacet, the crossed subfacets get the paper's test
//     (split when any vertex encroaches them), and from the cell's third attempt on are split as the paper's mode
//     splits every subfacet z's zone destroys (cheese.off: the encroached subfacet is not always one z crosses).
//     The full zone of a centre outside the domain can be most of the mesh (a non-Gabriel boundary gives its cells
//     huge circumspheres); this part of it stays local;
//   - acute input angles: a tetrahedron whose shortest edge joins vertices on two input elements that meet at an
//     acute apex is not split (that edge is forced by the small angle; splitting it would cascade), unless it is
//     degenerate (four nearly cocircular points, which concentric shells make: degenerate_cell_centre);
//   - a flat tetrahedron on a facet (near-cocircular facet points that rounding made slightly non-coplanar) gets
//     its subfacets split instead of its meaningless circumcentre; remove_flat_boundary_cells() flips those left
//     out of the domain before extraction.
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <unordered_set>

#include "refine/refine_state.h"
#include "vec3.h"

namespace qualmesh::detail {

namespace {

using vec3::sq_dist;

// The facet holding all four vertices of cell c (a face of c is its subfacet and the opposite vertex lies on it
// too), or kNoIndex: a flat tetrahedron of near-cocircular facet points that rounding made slightly non-coplanar.
Index facet_under_flat_cell(const MeshState& s, Ch3 c) {
  for (int i = 0; i < 4; ++i) {
    const Index facet = face_subfacet(s, c, i);
    if (facet != kNoIndex && vertex_on_plane(s, c->vertex(i)->info(), s.complex.plane_group[facet])) return facet;
  }
  return kNoIndex;
}

// A nearly flat cell of four nearly cocircular points (two segments through an acute apex carry vertices at equal
// radii, which make isosceles trapezoids): rounding makes its circumsphere arbitrarily large and its centre
// meaningless. Returns the centre of the circle through its largest face when the circumsphere is more than 100
// times that circle's radius or the volume is negligible: the circle all four points nearly share, whose centre
// lies inside the circumsphere (the sphere meets that face's plane in exactly that circle), so Rule 3 can insert it
// instead.
std::optional<KPoint3> degenerate_cell_centre(const MeshState& s, const std::array<Index, 4>& v) {
  double sq_rf = 0;
  KPoint3 zf;
  for (int i = 0; i < 4; ++i) {
    const KPoint3 a = s.kpoint(v[(i + 1) & 3]), b = s.kpoint(v[(i + 2) & 3]), d = s.kpoint(v[(i + 3) & 3]);
    if (CGAL::collinear(a, b, d)) continue;
    const double r = CGAL::squared_radius(a, b, d);
    if (r > sq_rf) sq_rf = r, zf = CGAL::circumcenter(a, b, d);
  }
  if (!(sq_rf > 0)) return std::nullopt;
  const KPoint3 p0 = s.kpoint(v[0]), p1 = s.kpoint(v[1]), p2 = s.kpoint(v[2]), p3 = s.kpoint(v[3]);
  // Degenerate: exactly coplanar, a volume below 1e-12 of the cube of the face circle's radius (rounding can make
  // it non-positive in the output), or a circumsphere 100 times that circle.
  if (CGAL::coplanar(p0, p1, p2, p3) || std::fabs(CGAL::volume(p0, p1, p2, p3)) < 1e-12 * sq_rf * std::sqrt(sq_rf) ||
      !(CGAL::squared_radius(p0, p1, p2, p3) < 1e4 * sq_rf))
    return zf;
  return std::nullopt;
}

// c's faces that are subfacets, each queued for a forced Rule 2 split (no point: Lemma 3.5 has nothing to
// project); false when c has none.
bool queue_subfacets_of(MeshState& s, Ch3 c) {
  bool any = false;
  for (int i = 0; i < 4; ++i) {
    const Index facet = face_subfacet(s, c, i);
    if (facet == kNoIndex) continue;
    std::array<Index, 3> f{c->vertex((i + 1) & 3)->info(), c->vertex((i + 2) & 3)->info(),
                           c->vertex((i + 3) & 3)->info()};
    s.rule2.push({facet, f, false, {}, true});
    any = true;
  }
  return any;
}

// Steiner mode: the part of z's conflict zone reachable from c without crossing a subfacet (a search over cells
// whose power sphere holds z), into `zone`. Returns the subfacets with a conflicting cell on both sides, where the
// zone would leave across the boundary (sorted; none: `zone` is the whole conflict zone).
std::vector<std::array<Index, 4>> conflict_zone_in_region(MeshState& s, const KPoint3& z, Ch3 c,
                                                          std::vector<Ch3>& zone) {
  const KWeightedPoint3 wp(z, 0);
  std::vector<std::array<Index, 4>> crossed;
  std::vector<Ch3> stack{c};
  std::unordered_set<const void*> seen{&*c};  // membership only: the search order is the stack's
  while (!stack.empty()) {
    const Ch3 x = stack.back();
    stack.pop_back();
    zone.push_back(x);
    for (int i = 0; i < 4; ++i) {
      const Ch3 n = x->neighbor(i);
      if (seen.count(&*n)) continue;
      const Index facet = face_subfacet(s, x, i);
      if (s.tr.side_of_power_sphere(n, wp, true) != CGAL::ON_BOUNDED_SIDE) continue;
      if (facet != kNoIndex) {
        std::array<Index, 3> f{x->vertex((i + 1) & 3)->info(), x->vertex((i + 2) & 3)->info(),
                               x->vertex((i + 3) & 3)->info()};
        std::sort(f.begin(), f.end());
        crossed.push_back({facet, f[0], f[1], f[2]});
        continue;
      }
      seen.insert(&*n);
      stack.push_back(n);
    }
  }
  s.zone_cells += zone.size();
  ++s.zone_count;
  std::sort(crossed.begin(), crossed.end());
  crossed.erase(std::unique(crossed.begin(), crossed.end()), crossed.end());
  return crossed;
}

}  // namespace

TetVerdict Rule3Tets::judge(MeshState& s, Ch3 c) const {
  Index ids[4];
  for (int k = 0; k < 4; ++k) ids[k] = c->vertex(k)->info();
  double sq_min = std::numeric_limits<double>::infinity(), sq_max = 0;
  int emin_a = 0, emin_b = 1;
  for (int a = 0; a < 4; ++a)
    for (int b = a + 1; b < 4; ++b) {
      const double d = sq_dist(s.point(ids[a]), s.point(ids[b]));
      if (d < sq_min) sq_min = d, emin_a = a, emin_b = b;
      sq_max = std::max(sq_max, d);
    }
  const KPoint3 p0 = s.kpoint(ids[0]), p1 = s.kpoint(ids[1]), p2 = s.kpoint(ids[2]), p3 = s.kpoint(ids[3]);
  if (s.params.sq_max_edge > 0 && sq_max > s.params.sq_max_edge) return TetVerdict::TooLarge;
  double max_volume = s.params.max_volume;
  const int region = c->info().region;
  if (region >= 0 && s.regions[region].max_volume > 0)
    max_volume = max_volume > 0 ? std::min(max_volume, s.regions[region].max_volume) : s.regions[region].max_volume;
  if (max_volume > 0 && CGAL::volume(p0, p1, p2, p3) > max_volume) return TetVerdict::TooLarge;
  // A flat tetrahedron lying on one plane of facets: four near-cocircular points of a facet whose circumsphere,
  // ill-defined, may pass the radius-edge test. Rule 2 removes it (refine_one), except where its shortest edge is
  // forced by an acute input angle (concentric shells make isosceles trapezoids, which are cocircular: splitting
  // them there cascades).
  const double volume = std::fabs(CGAL::volume(p0, p1, p2, p3));
  const bool flat = volume < 1e-6 * sq_max * std::sqrt(sq_max) && facet_under_flat_cell(s, c) != kNoIndex;
  const double sq_r = CGAL::squared_radius(p0, p1, p2, p3);
  if (!flat && !s.params.sq_radius_edge_above_bound(sq_r, sq_min)) return TetVerdict::Good;
  // Shortest edge forced by an acute input angle (the one definition: tet_touches_acute_angle()). A degenerate
  // (flat, nearly cocircular) cell off the facets is split even there (at its circle's centre): no output element
  // may be that bad. One on a facet is left (splitting those cascades at concentric shells): extraction flips it
  // out of the domain (remove_flat_boundary_cells()).
  if (shortest_edge_forced_by_acute_angle(s, ids[emin_a], ids[emin_b]) &&
      (flat || !degenerate_cell_centre(s, {ids[0], ids[1], ids[2], ids[3]})))
    return TetVerdict::ForcedBySmallAngle;
  return TetVerdict::Skinny;
}

void Rule3Tets::enqueue_if_bad(MeshState& s, Ch3 c) {
  if (s.tr.is_infinite(c) || c->info().region < 0) return;
  const TetVerdict verdict = judge(s, c);
  if (verdict == TetVerdict::ForcedBySmallAngle) ++s.stats.num_skipped_small_angle;
  if (verdict == TetVerdict::Skinny || verdict == TetVerdict::TooLarge)
    queue.push_back({{c->vertex(0)->info(), c->vertex(1)->info(), c->vertex(2)->info(), c->vertex(3)->info()}, 0});
}

void Rule3Tets::enqueue_all(MeshState& s) {
  for (auto c = s.tr.finite_cells_begin(); c != s.tr.finite_cells_end(); ++c) enqueue_if_bad(s, c);
}

KPoint3 Rule3Tets::refinement_point(const MeshState& s, const std::array<Index, 4>& v) const {
  KPoint3 z = CGAL::circumcenter(s.kpoint(v[0]), s.kpoint(v[1]), s.kpoint(v[2]), s.kpoint(v[3]));
  if (auto zf = degenerate_cell_centre(s, v)) z = *zf;
  return z;
}

Conflict Rule3Tets::conflict(MeshState& s, const TetEntry& e, Ch3 c, const KPoint3& z, ConflictZone& cz,
                             Candidates& cand) {
  const int region = c->info().region;
  if (s.params.encroachment.walks_to_centres()) {
    // Steiner mode: find from the in-region part of the zone whether z leaves the region (file comment), before
    // computing a zone that may be huge. z encroaches subsegments -> Rule 1. Else z left the domain through
    // subfacets: those z encroaches are split (Rule 2 with the point z); the others get the paper's test (split
    // when any vertex encroaches them: with no encroached subfacet every circumcentre lies in the domain) and c is
    // tried again; from c's third attempt on they are split too. When z leaves nothing, the part is the whole
    // zone, so the general path below finds no subfacet inside it.
    ConflictZone part;
    const std::vector<std::array<Index, 4>> crossed = conflict_zone_in_region(s, z, c, part.cells);
    if (!crossed.empty()) {
      Candidates part_cand;
      collect_candidates(s, part, part_cand);
      bool encroached = false;
      for (const auto& sg : part_cand.subsegments) {
        if (!strictly_encroaches(s.kpoint(sg[1]), s.kpoint(sg[2]), z)) continue;
        s.rule1.push({sg[0], sg[1], sg[2], true});
        encroached = true;
      }
      for (const auto& f : crossed) {
        if (encroached) break;  // Rule 1 first
        if (strictly_encroaches(s.kpoint(f[1]), s.kpoint(f[2]), s.kpoint(f[3]), z) || e.attempts >= 2)
          s.rule2.push({f[0], {f[1], f[2], f[3]}, true, to_point3(z), true});
        else
          s.rule2.push({f[0], {f[1], f[2], f[3]}, false, {}, false, 0, true});
      }
      return encroached ? Conflict::SplitSubsegment : Conflict::SplitSubfacet;
    }
  }
  if (!find_conflict_zone(s, z, c, cz) || std::find(cz.cells.begin(), cz.cells.end(), c) == cz.cells.end()) {
    // Rounding put z on a vertex, or so far away (a nearly flat cell on two nearly coplanar facets of a curved
    // CAD face) that the conflict zone found from z misses c: split c's subfacets instead (Rule 2; the empty
    // circumsphere of a cell of the bounded domain can only be that large by crossing them).
    return queue_subfacets_of(s, c) ? Conflict::SplitSubfacet : Conflict::Drop;
  }
  collect_candidates(s, cz, cand);
  // First bullet: z encroaches subsegments -> Rule 1.
  bool rejected = false;
  for (const auto& seg : cand.subsegments) {
    if (strictly_encroaches(s.kpoint(seg[1]), s.kpoint(seg[2]), z)) {
      s.rule1.push({seg[0], seg[1], seg[2], true});
      rejected = true;
    }
  }
  if (rejected) return Conflict::SplitSubsegment;
  // Second bullet: z encroaches subfacets (or its insertion would remove one) -> Rule 2 on the subfacet that holds
  // z's projection (Rule2Subfacets::refine_one applies Lemma 3.5 with the point z).
  std::vector<std::array<Index, 4>> destroyed;
  for (const Facet3& f : cz.internal) {
    Index ids[3];
    for (int k = 0; k < 3; ++k) ids[k] = f.first->vertex((f.second + 1 + k) & 3)->info();
    if (ids[0] == kNoIndex || ids[1] == kNoIndex || ids[2] == kNoIndex) continue;
    const Index facet = subfacet_of(s, ids[0], ids[1], ids[2]);
    if (facet != kNoIndex) destroyed.push_back({facet, ids[0], ids[1], ids[2]});
  }
  for (const auto& f : cand.subfacets) {
    if (strictly_encroaches(s.kpoint(f[1]), s.kpoint(f[2]), s.kpoint(f[3]), z)) destroyed.push_back(f);
  }
  for (const auto& f : destroyed) s.rule2.push({f[0], {f[1], f[2], f[3]}, true, to_point3(z), true});
  if (!destroyed.empty()) return Conflict::SplitSubfacet;
  // Without an encroached element the conflict zone cannot cross the boundary, so it lies in one region; if it
  // does not (numerically inconsistent), split c's subfacets instead.
  for (const Ch3& cell : cz.cells)
    if (cell->info().region != region) return queue_subfacets_of(s, c) ? Conflict::SplitSubfacet : Conflict::Drop;
  return Conflict::None;
}

void Rule3Tets::give_up(std::array<Index, 4> v) {
  std::sort(v.begin(), v.end());
  given_up.push_back(v);
}

void Rule3Tets::refine_one(MeshState& s) {
  const TetEntry e = queue.front();
  queue.pop_front();
  Ch3 c;
  const auto& v = e.vertices;
  if (!s.tr.is_cell(s.vertices[v[0]].handle, s.vertices[v[1]].handle, s.vertices[v[2]].handle,
                    s.vertices[v[3]].handle, c))
    return;  // stale
  const int region = c->info().region;
  if (region < 0) return;
  const TetVerdict verdict = judge(s, c);
  if (verdict == TetVerdict::ForcedBySmallAngle) {
    ++s.stats.num_skipped_small_angle;
    return;
  }
  if (verdict == TetVerdict::Good) return;
  // Queued again behind the splits its point asked for, up to 8 times.
  auto reconsider = [&]() {
    if (e.attempts < 8) queue.push_back({e.vertices, e.attempts + 1});
    else give_up(e.vertices);
  };
  // A flat tetrahedron whose four vertices lie on one facet: its circumcentre is meaningless; split its subfacets
  // on that facet's plane instead (Rule 2).
  const Index common = facet_under_flat_cell(s, c);
  if (common != kNoIndex) {
    for (int i = 0; i < 4; ++i) {
      const Index facet = face_subfacet(s, c, i);
      if (facet == kNoIndex || s.complex.plane_group[facet] != s.complex.plane_group[common]) continue;
      std::array<Index, 3> f{c->vertex((i + 1) & 3)->info(), c->vertex((i + 2) & 3)->info(),
                             c->vertex((i + 3) & 3)->info()};
      s.rule2.push({facet, f, false, {}, true});
    }
    reconsider();
    return;
  }
  const KPoint3 z = refinement_point(s, e.vertices);
  ConflictZone cz;
  Candidates cand;
  switch (conflict(s, e, c, z, cz, cand)) {
    case Conflict::None: {
      const Index w = add_vertex(s, to_point3(z), VertexKind::Volume, kNoIndex);
      ++s.stats.num_rule3_insertions;
      notify_insertion(s, insert_vertex(s, w, cz, cand, region));
      return;
    }
    case Conflict::SplitSubsegment:
    case Conflict::SplitSubfacet:
      ++s.stats.num_rejected_circumcenters;
      reconsider();
      return;
    case Conflict::Drop:  // nothing to split: given up at once
      ++s.stats.num_rejected_circumcenters;
      give_up(e.vertices);
      return;
  }
}

void Rule3Tets::after_insertion(MeshState& s, const InsertionResult& r) {
  if (r.region < 0) return;  // boundary points: their cells are judged when the regions are flooded
  for (const Ch3& c : r.new_cells) enqueue_if_bad(s, c);
}

// --- After refinement ---------------------------------------------------------------------------------------------

namespace {

// Is the in-domain cell c cut off from its region: outside cells across its faces that are not subfacets, and
// cells of the domain only across subfacets? Its region then contradicts the flood (regions.cpp), which crosses
// exactly the faces that are not subfacets.
bool outside_by_its_faces(const MeshState& s, Ch3 c) {
  bool outside_nb = false;
  for (int i = 0; i < 4; ++i) {
    if (face_subfacet(s, c, i) != kNoIndex) continue;
    if (c->neighbor(i)->info().region >= 0) return false;
    outside_nb = true;
  }
  return outside_nb;
}

}  // namespace

void remove_flat_boundary_cells(MeshState& s) {
  std::vector<Ch3> flat;
  std::size_t num_cut_off = 0;
  for (auto c = s.tr.finite_cells_begin(); c != s.tr.finite_cells_end(); ++c) {
    if (c->info().region < 0) continue;
    std::array<Index, 4> v;
    for (int k = 0; k < 4; ++k) v[k] = c->vertex(k)->info();
    if (!degenerate_cell_centre(s, v)) continue;
    // A flat cell glued onto the outer side of a subfacet (cube1000.igs at --size 27.95: four nearly coplanar
    // points of one boundary plane, one face the subfacet, the other three against outside cells). It appears
    // during Rule 4's cascade of boundary splits, whose cells get their regions from flood_pending_regions(); a
    // debug check showed that no insertion gives it its region directly, and which step does was not found.
    // Zero volume, so moving it outside changes no volume, and its subfacet becomes the boundary.
    if (outside_by_its_faces(s, c)) {
      c->info().region = kOutsideRegion;
      ++num_cut_off;
      continue;
    }
    if (facet_under_flat_cell(s, c) != kNoIndex) flat.push_back(c);
  }
  if (num_cut_off > 0)
    s.log_line("extraction: " + std::to_string(num_cut_off) +
               " flat cell(s) outside the boundary (against outside cells across every face but a subfacet) "
               "left out");
  for (const Ch3& c : flat) {
    // Its two faces that are subfacets of one facet, with outside cells across them (the quadrilateral's two
    // triangles); the 2D flip of their common edge makes the cell's other two faces the subfacets.
    int on[4], n_on = 0;
    Index facet = kNoIndex;
    for (int i = 0; i < 4; ++i) {
      const Index f = face_subfacet(s, c, i);
      if (f == kNoIndex || c->neighbor(i)->info().region >= 0) continue;
      if (facet != kNoIndex && f != facet) n_on = 3;  // two facets: leave it
      facet = f;
      if (n_on < 4) on[std::min(n_on, 3)] = i;
      ++n_on;
    }
    if (n_on != 2) continue;
    const int i1 = on[0], i2 = on[1];
    const std::array<Index, 3> face1{c->vertex((i1 + 1) & 3)->info(), c->vertex((i1 + 2) & 3)->info(),
                                     c->vertex((i1 + 3) & 3)->info()};
    if (flip_subfacet_to_match(s, facet, face1, nullptr, c->vertex(i2)->info()))
      c->info().region = kOutsideRegion;
  }
}

void sort_given_up(MeshState& s) {
  auto& g = s.rule3.given_up;
  std::sort(g.begin(), g.end());
  g.erase(std::unique(g.begin(), g.end()), g.end());
}

LeftReason why_left(MeshState& s, Ch3 c) {
  const TetVerdict verdict = s.rule3.judge(s, c);
  if (verdict == TetVerdict::ForcedBySmallAngle) return LeftReason::AcuteAngle;
  std::array<Index, 4> v;
  for (int k = 0; k < 4; ++k) v[k] = c->vertex(k)->info();
  std::sort(v.begin(), v.end());
  const auto& g = s.rule3.given_up;
  return std::binary_search(g.begin(), g.end(), v) ? LeftReason::Rejected : LeftReason::Other;
}

}  // namespace qualmesh::detail
