// The refinement engine: step 2 of QUALMESH (Cheng & Dey, Section 3.7) without Rule 4 (weighted encroachment,
// which belongs with pumping), in the paper's priority order:
//   Rule 1: split an encroached subsegment (midpoint, or a concentric-shell point next to an acute apex);
//   Rule 2: split an encroached subfacet at its circumcentre, choosing the subfacet that contains the projection
//           of the encroaching vertex (Lemma 3.5); reject the circumcentre when it encroaches a subsegment and split
//           that subsegment instead;
//   Rule 3: insert the circumcentre of a tetrahedron of radius-edge ratio above rho0 (or too large for the size
//           field), unless it encroaches a subsegment (split it, Rule 1) or a subfacet (split the one containing
//           its projection, Rule 2).
// One queue per rule (CGAL Mesh_3's Mesher_level chain, flattened): a rule runs only when the queues of the rules
// before it are empty. Entries are validated when popped (the subsegment still consecutive, the subfacet still in
// its facet's triangulation, the tetrahedron still a cell), so stale entries cost nothing.
//
// Encroachment is found locally. Gabriel property: a subsegment (subfacet) is missing from the Delaunay
// triangulation only if its closed diametral ball holds a vertex, and a present one whose diametral ball holds a
// vertex has such a vertex among the apices of its incident cells (for a subfacet, the two cells on its sides). A
// new point p can only encroach or remove elements that are faces or edges of cells in p's conflict zone (cells
// whose circumsphere holds p: any sphere through a subfacet on p's side contains the part of its diametral ball on
// that side). So after each insertion only the conflict zone's edges and faces, and the new subsegments and
// subfacets (the 2D star of the new vertex), are checked; nothing is ever scanned globally after the start.
//
// Which vertices encroach (MeshOptions::encroaching; the default is the paper's "every vertex"). With
// Encroaching::Steiner (experimental) a present subsegment or subfacet is split by Rules 1-2 only when a Steiner
// vertex lies in its diametral ball (or it is missing, or a rejected Rule 2/3 centre encroaches it). Input vertices
// do not count: a tessellated surface's obtuse triangles put input vertices in the diametral balls of neighbouring
// input edges everywhere, and splitting those is what multiplies the vertex count (elephant.off: 17863 vertices
// with the paper's rule, 2776 without; conformity needs the elements present, not empty balls). Nor does a vertex
// of a segment for the subsegments of another segment sharing an input vertex with it (Shewchuk's rule for small
// angles: on a tessellated surface every input vertex is the apex of acute angles, and those mutual encroachments
// were most of the remaining Rule 1 splits). Where elements are not Gabriel, centres may lie beyond them:
//   - a subfacet's circumcentre beyond a subsegment of its facet rejects it for the first subsegment that the
//     straight walk in the facet's plane crosses (subsegment_towards, as Triangle does), without computing the
//     centre's conflict zone, which is huge outside the domain (the cells there are never refined);
//   - a tetrahedron's circumcentre is first tried on the part of its conflict zone reachable without crossing a
//     subfacet (conflict_zone_in_region); when the zone would cross one, the crossed subfacets get the paper's test
//     (split when any vertex encroaches them), and from the cell's third attempt on are split as the paper's mode
//     splits every subfacet z's zone destroys (cheese.off: the encroached subfacet is not always one z crosses).
// Steiner mode guarantees neither recovery nor small conflict zones: mesher.cpp checks after each stage that every
// subsegment and subfacet is present and that regions end at subfacets, run_refinement() keeps a budget on the
// average conflict zone, and when either fails the input is meshed again with the paper's rule
// (MeshStats::encroaching_fell_back; bottle.brep, part.step and U_Joint_2.stp do).
//
// Acute input angles (beyond the paper, which assumes none): concentric shells for Rule 1 (subsegments.cpp), and
// Rule 3 does not split a tetrahedron whose shortest edge joins vertices on two input elements that meet at an
// acute apex (that edge is forced by the small angle; splitting it would cascade), unless the tetrahedron is
// degenerate (four nearly cocircular points, which shells make: degenerate_cell_centre). MeshOptions::max_vertices
// is the last-resort stop.
#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <unordered_set>

#include "qualmesh/error.h"
#include "refine/refine_state.h"

namespace qualmesh::detail {

namespace {

const Kernel& kernel() {
  static const Kernel k;
  return k;
}

bool strictly_encroaches(const KPoint3& a, const KPoint3& b, const KPoint3& p) {
  return kernel().side_of_bounded_sphere_3_object()(a, b, p) == CGAL::ON_BOUNDED_SIDE;
}
bool strictly_encroaches(const KPoint3& a, const KPoint3& b, const KPoint3& c, const KPoint3& p) {
  return kernel().side_of_bounded_sphere_3_object()(a, b, c, p) == CGAL::ON_BOUNDED_SIDE;
}

bool is_infinite(const MeshState& s, Vh3 v) { return v == s.tr.infinite_vertex(); }

// Whether vertex v inside the diametral ball of a present subsegment or subfacet makes Rules 1-2 split it
// (MeshOptions::encroaching: the paper, and the default, count every vertex; Steiner mode not input vertices).
bool segments_share_endpoint(const MeshState& s, Index s1, Index s2) {
  const Segment& a = s.complex.segments[s1];
  const Segment& b = s.complex.segments[s2];
  return a.a == b.a || a.a == b.b || a.b == b.a || a.b == b.b;
}

bool encroacher_counts(const MeshState& s, Index v, Index segment = kNoIndex) {
  if (s.options.encroaching == MeshOptions::Encroaching::All) return true;
  const VertexRecord& r = s.vertices[v];
  if (r.kind == VertexKind::Input) return false;
  if (segment != kNoIndex && r.kind == VertexKind::Segment && r.host != segment &&
      segments_share_endpoint(s, r.host, segment))
    return false;
  return true;
}

// --- Encroachment of one element, from the triangulation around it -----------------------------------------------

// True when subsegment (u, v) is missing from the triangulation or a vertex that encroacher_counts lies strictly
// inside its diametral ball; `encroacher` gets that vertex (kNoIndex when missing).
bool subsegment_encroached(const MeshState& s, Index segment, Index u, Index v, Index* encroacher) {
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
      if (w == hu || w == hv || is_infinite(s, w) || !encroacher_counts(s, w->info(), segment)) continue;
      if (strictly_encroaches(a, b, s.kpoint(w->info()))) {
        *encroacher = w->info();
        return true;
      }
    }
  } while (++cc != done);
  return false;
}

bool subfacet_encroached(const MeshState& s, const std::array<Index, 3>& abc, Index* encroacher, bool all) {
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
    if (is_infinite(s, w) || !(all || encroacher_counts(s, w->info()))) continue;
    if (strictly_encroaches(a, b, cc, s.kpoint(w->info()))) {
      *encroacher = w->info();
      return true;
    }
  }
  return false;
}

// --- Conflict zones --------------------------------------------------------------------------------------------

struct ConflictZone {
  std::vector<Ch3> cells;
  std::vector<Facet3> boundary;
  std::vector<Facet3> internal;
};

// Subsegments (segment, u, v) and subfacets (facet, a, b, c) that are edges / faces of the conflict zone's cells.
struct Candidates {
  std::vector<std::array<Index, 3>> subsegments;
  std::vector<std::array<Index, 4>> subfacets;
};

// The cells whose circumsphere holds p (the cells p's insertion destroys); false when p coincides with a vertex.
bool find_conflict_zone(MeshState& s, const KPoint3& p, Ch3 hint, ConflictZone& cz) {
  RegularTriangulation3::Locate_type lt;
  int li = 0, lj = 0;
  const KWeightedPoint3 wp(p, 0);
  Ch3 c = s.tr.locate(wp, lt, li, lj, hint);
  if (lt == RegularTriangulation3::VERTEX) return false;
  cz.cells.clear();
  cz.boundary.clear();
  cz.internal.clear();
  s.tr.find_conflicts(wp, c, std::back_inserter(cz.boundary), std::back_inserter(cz.cells),
                      std::back_inserter(cz.internal));
  s.zone_cells += cz.cells.size();
  ++s.zone_count;
  return !cz.cells.empty() && !cz.boundary.empty();
}

void collect_candidates(const MeshState& s, const ConflictZone& cz, Candidates& out) {
  out.subsegments.clear();
  out.subfacets.clear();
  for (const Ch3& c : cz.cells) {
    Index ids[4];
    for (int k = 0; k < 4; ++k) ids[k] = c->vertex(k)->info();
    for (int a = 0; a < 4; ++a) {
      if (ids[a] == kNoIndex) continue;
      for (int b = a + 1; b < 4; ++b) {
        if (ids[b] == kNoIndex) continue;
        const Index seg = subsegment_of(s, ids[a], ids[b]);
        if (seg != kNoIndex) out.subsegments.push_back({seg, std::min(ids[a], ids[b]), std::max(ids[a], ids[b])});
      }
    }
    for (int i = 0; i < 4; ++i) {
      std::array<Index, 3> f{ids[(i + 1) & 3], ids[(i + 2) & 3], ids[(i + 3) & 3]};
      if (f[0] == kNoIndex || f[1] == kNoIndex || f[2] == kNoIndex) continue;
      const Index facet = subfacet_of(s, f[0], f[1], f[2]);
      if (facet == kNoIndex) continue;
      std::sort(f.begin(), f.end());
      out.subfacets.push_back({facet, f[0], f[1], f[2]});
    }
  }
  std::sort(out.subsegments.begin(), out.subsegments.end());
  out.subsegments.erase(std::unique(out.subsegments.begin(), out.subsegments.end()), out.subsegments.end());
  std::sort(out.subfacets.begin(), out.subfacets.end());
  out.subfacets.erase(std::unique(out.subfacets.begin(), out.subfacets.end()), out.subfacets.end());
}

// --- Quality and size of tetrahedra (Rule 3) ---------------------------------------------------------------------

double sq_dist(const Point3& a, const Point3& b) {
  return (a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]);
}

enum class TetVerdict { Good, Skinny, TooLarge, ForcedBySmallAngle };

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

namespace {

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

TetVerdict judge_tet(MeshState& s, Ch3 c) {
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
  if (s.sq_max_edge > 0 && sq_max > s.sq_max_edge) return TetVerdict::TooLarge;
  double max_volume = s.max_volume;
  const int region = c->info().region;
  if (region >= 0 && s.regions[region].max_volume > 0)
    max_volume = max_volume > 0 ? std::min(max_volume, s.regions[region].max_volume) : s.regions[region].max_volume;
  if (max_volume > 0 && CGAL::volume(p0, p1, p2, p3) > max_volume) return TetVerdict::TooLarge;
  // A flat tetrahedron lying on one plane of facets: four near-cocircular points of a facet whose circumsphere,
  // ill-defined, may pass the radius-edge test. Rule 2 removes it (process_tet), except where its shortest edge is
  // forced by an acute input angle (concentric shells make isosceles trapezoids, which are cocircular: splitting
  // them there cascades).
  const double volume = std::fabs(CGAL::volume(p0, p1, p2, p3));
  const bool flat = volume < 1e-6 * sq_max * std::sqrt(sq_max) && facet_under_flat_cell(s, c) != kNoIndex;
  const double sq_r = CGAL::squared_radius(p0, p1, p2, p3);
  if (!flat && !(sq_r > s.sq_radius_edge_bound * sq_min)) return TetVerdict::Good;
  // Shortest edge forced by an acute input angle (the one definition: tet_touches_acute_angle()). A degenerate
  // (flat, nearly cocircular) cell off the facets is split even there (at its circle's centre, process_tet): no
  // output element may be that bad. One on a facet is left (splitting those cascades at concentric shells):
  // extraction flips it out of the domain (remove_flat_boundary_cells()).
  if (shortest_edge_forced_by_acute_angle(s, ids[emin_a], ids[emin_b]) &&
      (flat || !degenerate_cell_centre(s, {ids[0], ids[1], ids[2], ids[3]})))
    return TetVerdict::ForcedBySmallAngle;
  return TetVerdict::Skinny;
}

// --- Insertion --------------------------------------------------------------------------------------------------

Index add_vertex(MeshState& s, const Point3& p, VertexKind kind, Index host, double t = 0) {
  VertexRecord r;
  r.point = p;
  r.kind = kind;
  r.host = host;
  r.t = t;
  s.vertices.push_back(r);
  return Index(s.vertices.size() - 1);
}

void enqueue_subsegment_if_encroached(MeshState& s, Index seg, Index u, Index v) {
  Index enc;
  if (subsegment_encroached(s, seg, u, v, &enc)) s.subsegment_queue.push_back({seg, u, v});
}

void enqueue_subfacet_if_encroached(MeshState& s, Index facet, const std::array<Index, 3>& abc) {
  Index enc;
  if (subfacet_encroached(s, abc, &enc, false)) s.subfacet_queue.push_back({facet, abc, false, {}});
}

void enqueue_tet_if_bad(MeshState& s, Ch3 c) {
  if (s.tr.is_infinite(c) || c->info().region < 0) return;
  const TetVerdict verdict = judge_tet(s, c);
  if (verdict == TetVerdict::ForcedBySmallAngle) ++s.stats.num_skipped_small_angle;
  if (verdict == TetVerdict::Skinny || verdict == TetVerdict::TooLarge)
    s.tet_queue.push_back({{c->vertex(0)->info(), c->vertex(1)->info(), c->vertex(2)->info(), c->vertex(3)->info()}, 0});
}

// Inserts vertex `id` into the hole of conflict zone `cz`, then checks everything the insertion may have
// encroached or removed: the candidates (edges and faces of the destroyed cells), the new subsegments and the new
// subfacets (2D stars of the new vertex). `region`: region of the new cells (kUnknownRegion for boundary points).
void insert_vertex(MeshState& s, Index id, ConflictZone& cz, const Candidates& cand, int region) {
  const KWeightedPoint3 wp(s.kpoint(id), 0);
  // Which candidates survive: every new cell joins the new vertex to a facet of the hole's boundary, so an edge or
  // face of a destroyed cell is still in the triangulation afterwards exactly when it lies on that boundary (a
  // cell around it outside the hole meets one inside across a boundary facet holding it). Cheaper than asking the
  // triangulation (is_edge / is_facet walk the cells around a vertex) for each candidate. Read before the hole's
  // cells are destroyed.
  std::vector<std::array<Index, 2>> kept_edges;
  std::vector<std::array<Index, 3>> kept_faces;
  const bool want_edges = !cand.subsegments.empty(), want_faces = !cand.subfacets.empty();
  if (want_edges || want_faces) {
    for (const Facet3& f : cz.boundary) {
      std::array<Index, 3> t{f.first->vertex((f.second + 1) & 3)->info(), f.first->vertex((f.second + 2) & 3)->info(),
                             f.first->vertex((f.second + 3) & 3)->info()};
      std::sort(t.begin(), t.end());  // kNoIndex (the infinite vertex) sorts last
      if (want_edges && t[1] != kNoIndex) kept_edges.push_back({t[0], t[1]});
      if (t[2] == kNoIndex) continue;
      if (want_edges) {
        kept_edges.push_back({t[0], t[2]});
        kept_edges.push_back({t[1], t[2]});
      }
      if (want_faces) kept_faces.push_back(t);
    }
    std::sort(kept_edges.begin(), kept_edges.end());
    std::sort(kept_faces.begin(), kept_faces.end());
  }
  // The hole's outer faces, each with the region of the destroyed cell inside (the new cell's guess).
  std::vector<HoleFace> outer;
  outer.reserve(cz.boundary.size());
  for (const Facet3& f : cz.boundary) {
    const CellInfo& inside = f.first->info();
    outer.push_back(hole_face(f, inside.region != kUnknownRegion ? inside.region : inside.guess));
  }
  const Vh3 vh = s.tr.insert_in_hole(wp, cz.cells.begin(), cz.cells.end(), cz.boundary.front().first,
                                     cz.boundary.front().second);
  vh->info() = id;
  s.vertices[id].handle = vh;
  ++s.stats.num_steiner_vertices;
  if (region < 0 && s.regions_known)
    for (const HoleFace& o : outer) o.new_cell()->info().guess = o.region;
  if (s.tr.number_of_vertices() >= s.options.max_vertices) s.vertex_limit_reached = true;
  s.poll_cancel();

  VertexRecord& r = s.vertices[id];
  std::vector<std::array<Index, 3>> new_faces;
  std::vector<Index> face_facets;
  if (r.kind == VertexKind::Segment) {
    for (const SegmentInFacet& sf : s.complex.segment_facets[r.host]) {
      const std::size_t before = new_faces.size();
      insert_into_facet(s, sf.facet, id, &new_faces);
      face_facets.resize(new_faces.size(), sf.facet);
      (void)before;
    }
  } else if (r.kind == VertexKind::Facet) {
    insert_into_facet(s, r.host, id, &new_faces);
    face_facets.resize(new_faces.size(), r.host);
  }

  // Cells of the star: region and Rule 3.
  std::vector<Ch3> star;
  star.reserve(outer.size());
  for (const HoleFace& o : outer) star.push_back(o.new_cell());
  for (const Ch3& c : star) {
    if (s.tr.is_infinite(c)) {
      c->info().region = s.regions_known ? kOutsideRegion : kUnknownRegion;
      continue;
    }
    c->info().region = region;
  }
  if (region >= 0) {
    for (const Ch3& c : star) enqueue_tet_if_bad(s, c);
  } else if (s.regions_known) {
    s.region_pending.push_back(id);
  }

  // Encroachment by the new vertex, or removal, of the conflict zone's subsegments and subfacets.
  const KPoint3 p = s.kpoint(id);
  for (const auto& e : cand.subsegments) {  // e[1] < e[2]
    if (subsegment_of(s, e[1], e[2]) != e[0]) continue;
    if (!std::binary_search(kept_edges.begin(), kept_edges.end(), std::array<Index, 2>{e[1], e[2]}) ||
        strictly_encroaches(s.kpoint(e[1]), s.kpoint(e[2]), p))
      s.subsegment_queue.push_back({e[0], e[1], e[2]});
  }
  for (const auto& f : cand.subfacets) {  // f[1] < f[2] < f[3]
    if (!is_subfacet(s, f[0], f[1], f[2], f[3])) continue;
    if (!std::binary_search(kept_faces.begin(), kept_faces.end(), std::array<Index, 3>{f[1], f[2], f[3]}) ||
        strictly_encroaches(s.kpoint(f[1]), s.kpoint(f[2]), s.kpoint(f[3]), p))
      s.subfacet_queue.push_back({f[0], {f[1], f[2], f[3]}, false, {}});
  }
  // New subsegments and subfacets.
  if (r.kind == VertexKind::Segment) {
    enqueue_subsegment_if_encroached(s, r.host, r.prev, id);
    enqueue_subsegment_if_encroached(s, r.host, id, r.next);
  }
  for (std::size_t n = 0; n < new_faces.size(); ++n) enqueue_subfacet_if_encroached(s, face_facets[n], new_faces[n]);
}

Ch3 hint_of(const MeshState& s, Index v) { return s.vertices[v].handle->cell(); }

// --- Rule 1 -----------------------------------------------------------------------------------------------------

void split_subsegment(MeshState& s, Index seg, Index u, Index v) {
  const double t = subsegment_split_parameter(s, seg, u, v);
  const Segment& sg = s.complex.segments[seg];
  const Point3& a = s.point(sg.a);
  const Point3& b = s.point(sg.b);
  const Point3 p{a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]), a[2] + t * (b[2] - a[2])};
  ConflictZone cz;
  if (!find_conflict_zone(s, to_kpoint(p), hint_of(s, u), cz)) return;  // underflow: nothing to split
  Candidates cand;
  collect_candidates(s, cz, cand);
  const Index w = add_vertex(s, p, VertexKind::Segment, seg, t);
  link_segment_vertex(s, seg, u, v, w);
  ++s.stats.num_rule1_insertions;
  insert_vertex(s, w, cz, cand, kUnknownRegion);
}

void process_subsegment(MeshState& s, const SubsegmentEntry& e) {
  if (subsegment_of(s, e.u, e.v) != e.segment) return;  // stale
  Index enc = kNoIndex;
  if (!e.forced && !subsegment_encroached(s, e.segment, e.u, e.v, &enc)) return;
  split_subsegment(s, e.segment, e.u, e.v);
}

// --- Rule 2 -----------------------------------------------------------------------------------------------------

void check_new_subfacets(MeshState& s, Index facet, const std::vector<std::array<Index, 3>>& faces) {
  for (const auto& f : faces) enqueue_subfacet_if_encroached(s, facet, f);
}

// Splits subfacet abc of `facet` at its circumcentre, unless that centre encroaches a subsegment (then those
// subsegments are queued for Rule 1 and the centre is rejected). Returns whether it inserted the centre.
bool split_subfacet(MeshState& s, Index facet, const std::array<Index, 3>& abc) {
  const KPoint3 a = s.kpoint(abc[0]), b = s.kpoint(abc[1]), c = s.kpoint(abc[2]);
  const KPoint3 center = CGAL::circumcenter(a, b, c);
  if (s.options.encroaching != MeshOptions::Encroaching::All) {
    // Steiner mode: a centre beyond a subsegment (one encroached by a tolerated vertex, typically next to an acute
    // corner of the facet) is rejected for the first subsegment crossed by the straight walk in the facet's plane
    // from the subfacet to the centre, as Triangle does, without computing the centre's conflict zone (huge when
    // the centre is outside the domain: the cells there are never refined) or locating it from afar.
    if (auto uv = subsegment_towards(s, facet, abc, to_point3(center))) {
      const Index seg = subsegment_of(s, (*uv)[0], (*uv)[1]);
      if (seg != kNoIndex) {
        s.subsegment_queue.push_back({seg, std::min((*uv)[0], (*uv)[1]), std::max((*uv)[0], (*uv)[1]), true});
        ++s.stats.num_rejected_circumcenters;
        return false;
      }
    }
  }
  ConflictZone cz;
  if (!find_conflict_zone(s, center, hint_of(s, abc[0]), cz)) return false;
  Candidates cand;
  collect_candidates(s, cz, cand);
  bool rejected = false;
  for (const auto& e : cand.subsegments) {
    if (strictly_encroaches(s.kpoint(e[1]), s.kpoint(e[2]), center)) {
      s.subsegment_queue.push_back({e[0], e[1], e[2], true});
      rejected = true;
    }
  }
  const Point3 p = to_point3(center);
  if (!rejected && !facet_point_in_domain(s, facet, p, abc[0])) {
    // The centre left the facet without encroaching a subsegment in floating point: split the facet's boundary
    // subsegments of this subfacet instead (Rule 1), which is what the exact geometry asks for.
    for (int i = 0; i < 3; ++i) {
      const Index u = abc[i], v = abc[(i + 1) % 3];
      const Index seg = subsegment_of(s, u, v);
      if (seg != kNoIndex) {
        s.subsegment_queue.push_back({seg, std::min(u, v), std::max(u, v), true});
        rejected = true;
      }
    }
    if (!rejected) return false;
  }
  if (rejected) {
    ++s.stats.num_rejected_circumcenters;
    return false;
  }
  const Index w = add_vertex(s, p, VertexKind::Facet, facet);
  ++s.stats.num_rule2_insertions;
  insert_vertex(s, w, cz, cand, kUnknownRegion);
  return true;
}

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

void process_subfacet(MeshState& s, const SubfacetEntry& e) {
  const auto& abc = e.vertices;
  if (!is_subfacet(s, e.facet, abc[0], abc[1], abc[2])) return;  // stale
  Index enc = kNoIndex;
  bool encroached = subfacet_encroached(s, abc, &enc, e.eager);
  const bool missing = encroached && enc == kNoIndex;
  const KPoint3 a = s.kpoint(abc[0]), b = s.kpoint(abc[1]), c = s.kpoint(abc[2]);
  if (!encroached && e.has_point && strictly_encroaches(a, b, c, to_kpoint(e.point))) encroached = true;
  if (!encroached && !e.forced) return;
  // Concentric shells put the vertices of two segments meeting at an acute apex at equal radii: isosceles
  // trapezoids, whose four corners are cocircular, so whether one corner encroaches the subfacet of the other three
  // is decided by rounding in the exact 3D test (example024.scad's needle triangles: splitting there cascaded to
  // rounding-level subsegments). On the subfacet's own facet the facet's 2D Delaunay triangulation decides: the
  // subfacet is present and is the facet's Delaunay triangle (Section 7.2's definition of subfacets).
  if (encroached && !missing && !e.forced && enc != kNoIndex && on_segment_acute_to_subfacet(s, enc, abc) &&
      vertex_on_facet(s, enc, e.facet) && !encroaches_in_facet_plane(s, e.facet, abc, enc)) {
    ++s.stats.num_skipped_small_angle;
    return;
  }
  // Small input angles: a subfacet that is present but encroached only by a vertex on an input element meeting its
  // facet at an acute angle is left alone (splitting it would make the two elements encroach each other without
  // end; conformity only needs it present). Shewchuk, "Mesh generation for domains with small angles".
  if (encroached && !missing && !e.forced && enc != kNoIndex) {
    bool has = false;
    const InputComplex::ElementRef he = host_element(s, enc, &has);
    if (has && s.complex.elements_meet_acute(he, {InputComplex::ElementKind::Facet, e.facet})) {
      ++s.stats.num_skipped_small_angle;
      return;
    }
  }
  if (missing) {
    // Cocircular subfacets: the 3D triangulation may have chosen the other diagonal; both are Delaunay.
    std::vector<std::array<Index, 3>> flipped;
    if (flip_subfacet_to_match(s, e.facet, abc, &flipped)) {
      check_new_subfacets(s, e.facet, flipped);
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
  if (split_subfacet(s, e.facet, target)) return;
  // Rejected (Rule 2's second clause: the centre encroaches subsegments, now queued for Rule 1): the subfacet stays
  // encroached or missing, and a missing one is a face of no cell, so no later conflict zone would find it again.
  // Queue it behind those splits (Rule 1 runs first); stale or healed entries cost nothing when popped.
  if (e.attempts < 16) {
    SubfacetEntry again = e;
    ++again.attempts;
    s.subfacet_queue.push_back(again);
  }
}

// --- Rule 3 -----------------------------------------------------------------------------------------------------

void give_up(MeshState& s, std::array<Index, 4> v) {
  std::sort(v.begin(), v.end());
  s.given_up.push_back(v);
}

// Queues c's faces that are subfacets for a forced Rule 2 split and c again (up to 8 times, then given up).
void retry_through_subfacets(MeshState& s, Ch3 c, const TetEntry& e) {
  bool any = false;
  for (int i = 0; i < 4; ++i) {
    const Index facet = face_subfacet(s, c, i);
    if (facet == kNoIndex) continue;
    std::array<Index, 3> f{c->vertex((i + 1) & 3)->info(), c->vertex((i + 2) & 3)->info(),
                           c->vertex((i + 3) & 3)->info()};
    s.subfacet_queue.push_back({facet, f, false, {}, true});
    any = true;
  }
  ++s.stats.num_rejected_circumcenters;
  if (any && e.attempts < 8) s.tet_queue.push_back({e.vertices, e.attempts + 1});
  else give_up(s, e.vertices);
}

// Encroaching::Steiner, Rule 3: the part of z's conflict zone reachable from c without crossing a subfacet (a
// breadth-first search over cells whose power sphere holds z), into `zone`. Returns the subfacets with a conflicting
// cell on both sides, where the zone would leave across the boundary (sorted; none: `zone` is the whole conflict
// zone). The full zone of a centre outside the domain can be most of the mesh (a non-Gabriel boundary gives its
// cells huge circumspheres); this part of it stays local.
std::vector<std::array<Index, 4>> conflict_zone_in_region(MeshState& s, const KPoint3& z, Ch3 c,
                                                          std::vector<Ch3>& zone) {
  const KWeightedPoint3 wp(z, 0);
  std::vector<std::array<Index, 4>> crossed;
  std::vector<Ch3> stack{c};
  std::unordered_set<const void*> seen{&*c};
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

void process_tet(MeshState& s, const TetEntry& e) {
  Ch3 c;
  const auto& v = e.vertices;
  if (!s.tr.is_cell(s.vertices[v[0]].handle, s.vertices[v[1]].handle, s.vertices[v[2]].handle,
                    s.vertices[v[3]].handle, c))
    return;  // stale
  const int region = c->info().region;
  if (region < 0) return;
  const TetVerdict verdict = judge_tet(s, c);
  if (verdict == TetVerdict::ForcedBySmallAngle) {
    ++s.stats.num_skipped_small_angle;
    return;
  }
  if (verdict == TetVerdict::Good) return;
  // A flat tetrahedron whose four vertices lie on one facet (near-cocircular points of a tilted facet, which
  // rounding made slightly non-coplanar): its circumcentre is meaningless; split its subfacets instead (Rule 2).
  {
    const Index common = facet_under_flat_cell(s, c);
    if (common != kNoIndex) {
      for (int i = 0; i < 4; ++i) {
        const Index facet = face_subfacet(s, c, i);
        if (facet == kNoIndex || s.complex.plane_group[facet] != s.complex.plane_group[common]) continue;
        std::array<Index, 3> f{c->vertex((i + 1) & 3)->info(), c->vertex((i + 2) & 3)->info(),
                               c->vertex((i + 3) & 3)->info()};
        s.subfacet_queue.push_back({facet, f, false, {}, true});
      }
      if (e.attempts < 8) s.tet_queue.push_back({e.vertices, e.attempts + 1});
      else give_up(s, e.vertices);
      return;
    }
  }
  KPoint3 z = CGAL::circumcenter(s.kpoint(v[0]), s.kpoint(v[1]), s.kpoint(v[2]), s.kpoint(v[3]));
  if (auto zf = degenerate_cell_centre(s, v)) z = *zf;
  if (s.options.encroaching != MeshOptions::Encroaching::All) {
    // Steiner mode: find from the in-region part of the zone whether z leaves the region (see above), before
    // computing a zone that may be huge. z encroaches subsegments -> Rule 1 (first bullet). Else z left the domain
    // through subfacets: those z encroaches are split (Rule 2 with the point z); the others get the paper's test
    // (split when any vertex encroaches them: with no encroached subfacet every circumcentre lies in the domain)
    // and c is tried again; from c's third attempt on they are split too (cheese.off: the encroached subfacet is
    // not always one that z crosses). When z leaves nothing, the part is the whole zone, so the general path below
    // finds no subfacet inside it.
    ConflictZone part;
    const std::vector<std::array<Index, 4>> crossed = conflict_zone_in_region(s, z, c, part.cells);
    if (!crossed.empty()) {
      Candidates cand;
      collect_candidates(s, part, cand);
      bool encroached = false;
      for (const auto& sg : cand.subsegments) {
        if (!strictly_encroaches(s.kpoint(sg[1]), s.kpoint(sg[2]), z)) continue;
        s.subsegment_queue.push_back({sg[0], sg[1], sg[2], true});
        encroached = true;
      }
      for (const auto& f : crossed) {
        if (encroached) break;  // Rule 1 first
        if (strictly_encroaches(s.kpoint(f[1]), s.kpoint(f[2]), s.kpoint(f[3]), z) || e.attempts >= 2)
          s.subfacet_queue.push_back({f[0], {f[1], f[2], f[3]}, true, to_point3(z), true});
        else
          s.subfacet_queue.push_back({f[0], {f[1], f[2], f[3]}, false, {}, false, 0, true});
      }
      ++s.stats.num_rejected_circumcenters;
      if (e.attempts < 8) s.tet_queue.push_back({e.vertices, e.attempts + 1});
      else give_up(s, e.vertices);
      return;
    }
  }
  ConflictZone cz;
  if (!find_conflict_zone(s, z, c, cz) || std::find(cz.cells.begin(), cz.cells.end(), c) == cz.cells.end()) {
    // Rounding put z on a vertex, or so far away (a nearly flat cell on two nearly coplanar facets of a curved
    // CAD face) that the conflict zone found from z misses c: split c's subfacets instead (Rule 2; the empty
    // circumsphere of a cell of the bounded domain can only be that large by crossing them).
    retry_through_subfacets(s, c, e);
    return;
  }
  Candidates cand;
  collect_candidates(s, cz, cand);
  // Rule 3, first bullet: z encroaches subsegments -> Rule 1.
  bool rejected = false;
  for (const auto& seg : cand.subsegments) {
    if (strictly_encroaches(s.kpoint(seg[1]), s.kpoint(seg[2]), z)) {
      s.subsegment_queue.push_back({seg[0], seg[1], seg[2], true});
      rejected = true;
    }
  }
  if (!rejected) {
    // Second bullet: z encroaches subfacets (or its insertion would remove one) -> Rule 2 on the subfacet that
    // holds z's projection (process_subfacet applies Lemma 3.5 with the point z).
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
    for (const auto& f : destroyed) {
      s.subfacet_queue.push_back({f[0], {f[1], f[2], f[3]}, true, to_point3(z), true});
      rejected = true;
    }
  }
  if (!rejected) {
    // Without an encroached element the conflict zone cannot cross the boundary, so it lies in one region.
    for (const Ch3& cell : cz.cells) {
      if (cell->info().region != region) {
        rejected = true;  // numerically inconsistent (z encroaches nothing, yet the zone leaves the region)
        break;
      }
    }
    if (rejected) {
      retry_through_subfacets(s, c, e);
      return;
    }
    const Index w = add_vertex(s, to_point3(z), VertexKind::Volume, kNoIndex);
    ++s.stats.num_rule3_insertions;
    insert_vertex(s, w, cz, cand, region);
    return;
  }
  ++s.stats.num_rejected_circumcenters;
  if (e.attempts < 8) {
    TetEntry again = e;
    ++again.attempts;
    s.tet_queue.push_back(again);
  } else {
    give_up(s, e.vertices);
  }
}


void report(MeshState& s, double fraction) {
  if (!s.progress) return;
  ProgressEvent event;
  event.stage = s.stage;
  event.fraction = std::max(0.0, std::min(1.0, fraction));
  event.num_vertices = s.tr.number_of_vertices();
  s.progress(event);
}

}  // namespace

void remove_flat_boundary_cells(MeshState& s) {
  std::vector<Ch3> flat;
  for (auto c = s.tr.finite_cells_begin(); c != s.tr.finite_cells_end(); ++c) {
    if (c->info().region < 0) continue;
    std::array<Index, 4> v;
    for (int k = 0; k < 4; ++k) v[k] = c->vertex(k)->info();
    if (degenerate_cell_centre(s, v) && facet_under_flat_cell(s, c) != kNoIndex) flat.push_back(c);
  }
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
  std::sort(s.given_up.begin(), s.given_up.end());
  s.given_up.erase(std::unique(s.given_up.begin(), s.given_up.end()), s.given_up.end());
}

LeftReason why_left(MeshState& s, Ch3 c) {
  const TetVerdict verdict = judge_tet(s, c);
  if (verdict == TetVerdict::ForcedBySmallAngle) return LeftReason::AcuteAngle;
  std::array<Index, 4> v;
  for (int k = 0; k < 4; ++k) v[k] = c->vertex(k)->info();
  std::sort(v.begin(), v.end());
  return std::binary_search(s.given_up.begin(), s.given_up.end(), v) ? LeftReason::Rejected : LeftReason::Other;
}

Index face_subfacet(const MeshState& s, Ch3 c, int i) {
  Index ids[3];
  for (int k = 0; k < 3; ++k) {
    ids[k] = c->vertex((i + 1 + k) & 3)->info();
    if (ids[k] == kNoIndex) return kNoIndex;
  }
  return subfacet_of(s, ids[0], ids[1], ids[2]);
}

void insert_input_vertices(MeshState& s) {
  const Plc& plc = *s.plc;
  s.tr.infinite_vertex()->info() = kNoIndex;
  s.vertices.clear();
  s.vertices.reserve(plc.vertices.size() * 4);
  Vh3 hint;
  for (Index v = 0; v < plc.vertices.size(); ++v) {
    const Index id = add_vertex(s, plc.vertices[v], VertexKind::Input, v);
    const std::size_t before = s.tr.number_of_vertices();
    const Vh3 vh = s.tr.insert(KWeightedPoint3(s.kpoint(id), 0), hint);
    if (s.tr.number_of_vertices() == before) {
      throw InputError(ErrorCode::DuplicateVertex,
                       "vertices " + std::to_string(vh->info()) + " and " + std::to_string(v) + " coincide",
                       plc.name, 0, ElementIds{{vh->info(), v}, {}, {}, {}});
    }
    vh->info() = id;
    s.vertices[id].handle = vh;
    hint = vh;
    if (s.poll_cancel()) throw MeshCancelled();  // no triangulation to stop with yet
  }
  if (s.tr.dimension() < 3)
    throw InputError(ErrorCode::Empty, "the input vertices span no volume", plc.name);
  s.chains.assign(s.complex.segments.size(), SegmentChain{});
  s.stats.num_input_vertices = plc.vertices.size();
}

void enqueue_initial_boundary(MeshState& s) {
  for (Index seg = 0; seg < s.complex.segments.size(); ++seg) {
    const Segment& sg = s.complex.segments[seg];
    enqueue_subsegment_if_encroached(s, seg, std::min(sg.a, sg.b), std::max(sg.a, sg.b));
  }
  std::vector<std::array<Index, 3>> faces;
  for (Index f = 0; f < s.facets.size(); ++f) {
    faces.clear();
    collect_subfacets(s, f, faces);
    check_new_subfacets(s, f, faces);
  }
}

void enqueue_all_tets(MeshState& s) {
  for (auto c = s.tr.finite_cells_begin(); c != s.tr.finite_cells_end(); ++c) enqueue_tet_if_bad(s, c);
}

bool region_boundaries_are_subfacets(const MeshState& s) {
  for (auto c = s.tr.finite_cells_begin(); c != s.tr.finite_cells_end(); ++c) {
    const int region = c->info().region;
    if (region < 0) continue;
    for (int i = 0; i < 4; ++i) {
      const Ch3 n = c->neighbor(i);
      const int other = s.tr.is_infinite(n) ? kOutsideRegion : n->info().region;
      if (other != region && face_subfacet(s, c, i) == kNoIndex) return false;
    }
  }
  return true;
}

bool boundary_present(const MeshState& s) {
  for (Index seg = 0; seg < s.complex.segments.size(); ++seg) {
    const Index end = s.complex.segments[seg].b;
    for (Index u = s.complex.segments[seg].a, v; u != end; u = v) {
      v = next_on_segment(s, seg, u);
      Ch3 c;
      int i = 0, j = 0;
      if (!s.tr.is_edge(s.vertices[u].handle, s.vertices[v].handle, c, i, j)) return false;
    }
  }
  std::vector<std::array<Index, 3>> faces;
  for (Index f = 0; f < s.facets.size(); ++f) {
    faces.clear();
    collect_subfacets(s, f, faces);
    for (const auto& abc : faces) {
      Ch3 c;
      int i = 0, j = 0, k = 0;
      if (!s.tr.is_facet(s.vertices[abc[0]].handle, s.vertices[abc[1]].handle, s.vertices[abc[2]].handle, c, i, j, k))
        return false;
    }
  }
  return true;
}


Index insert_volume_vertex(MeshState& s, const Point3& p, std::vector<Ch3>& cells, std::vector<Facet3>& boundary,
                           int region) {
  ConflictZone cz;
  cz.cells.swap(cells);
  cz.boundary.swap(boundary);
  Candidates cand;
  collect_candidates(s, cz, cand);
  const Index w = add_vertex(s, p, VertexKind::Volume, kNoIndex);
  insert_vertex(s, w, cz, cand, region);
  return w;
}

// Average conflict-zone size (cells) over a window of insertions above which Encroaching::Steiner gives way to the
// paper's rule. Measured averages: 17-70 on the benchmark models in either mode.
constexpr std::size_t kSteinerZoneBudget = 250;

void run_refinement(MeshState& s, bool with_rule3) {
  std::size_t steps = 0;
  std::vector<Ch3> assigned;
  while (!s.vertex_limit_reached) {
    if (++steps % 4096 == 0) {
      const double queued = double(s.subsegment_queue.size() + s.subfacet_queue.size() + s.tet_queue.size());
      const double done = double(s.stats.num_steiner_vertices);
      report(s, done / (done + queued + 1));
      // Encroaching::Steiner's work budget: where tolerated encroachers leave the boundary far from Gabriel, cells
      // near it get huge circumspheres and every insertion's conflict zone becomes large (U_Joint_2.stp: averages
      // of 300-700 cells, against 20-60 on the same model with the paper's rule). Then mesh_plc() starts again with
      // the paper's rule.
      if (s.options.encroaching != MeshOptions::Encroaching::All && s.zone_count >= 4096) {
        if (s.zone_cells > kSteinerZoneBudget * s.zone_count) {
          s.steiner_abandoned = "conflict zones of " + std::to_string(s.zone_cells / s.zone_count) +
                                " cells on average";
          return;
        }
        s.zone_cells = s.zone_count = 0;
      }
      if (steps % (1u << 18) == 0)
        s.log_line("refinement: " + std::to_string(steps) + " steps, " + std::to_string(s.tr.number_of_vertices()) +
                   " vertices (rule 1 " + std::to_string(s.stats.num_rule1_insertions) + ", rule 2 " +
                   std::to_string(s.stats.num_rule2_insertions) + ", rule 3 " +
                   std::to_string(s.stats.num_rule3_insertions) + "), queued " +
                   std::to_string(s.subsegment_queue.size()) + "/" + std::to_string(s.subfacet_queue.size()) + "/" +
                   std::to_string(s.tet_queue.size()) + ", " + std::to_string(s.stats.num_rejected_circumcenters) +
                   " centres rejected, " + std::to_string(s.stats.num_skipped_small_angle) + " small-angle skips");
    }
    if (!s.subsegment_queue.empty()) {
      const SubsegmentEntry e = s.subsegment_queue.front();
      s.subsegment_queue.pop_front();
      process_subsegment(s, e);
      continue;
    }
    if (!s.subfacet_queue.empty()) {
      const SubfacetEntry e = s.subfacet_queue.front();
      s.subfacet_queue.pop_front();
      process_subfacet(s, e);
      continue;
    }
    if (!with_rule3) break;
    if (!s.region_pending.empty()) {
      assigned.clear();
      flood_pending_regions(s, assigned);
      for (const Ch3& c : assigned) enqueue_tet_if_bad(s, c);
      continue;
    }
    if (!s.tet_queue.empty()) {
      const TetEntry e = s.tet_queue.front();
      s.tet_queue.pop_front();
      process_tet(s, e);
      continue;
    }
    break;
  }
  report(s, 1.0);
}

}  // namespace qualmesh::detail
