// Subfacets (paper Section 3.2): for each input facet, the two-dimensional Delaunay triangulation of the vertices
// on it, in an orthonormal frame of its plane, constrained by its subsegments (so that the facet's domain stays
// defined while some subsegment is encroached; once none is, it equals the unconstrained Delaunay triangulation of
// Section 3.2). Its in-domain triangles are the subfacets; one that is not a face of the 3D triangulation is seen
// as missing and refined (Rule 2) or, when the 3D triangulation chose the other diagonal of a cocircular
// quadrilateral, flipped to match (both are Delaunay).
//
// In/out (plc.h): a triangle is in the facet when it is covered by an odd number of the facet's closed polygons and
// no facet hole point reaches it without crossing a polygon edge. After an insertion only the star of the new
// vertex changes, and each new triangle inherits from the old triangle across its edge opposite the new vertex.
// Lemma 3.5 (projection): subfacet_containing_projection() locates the orthogonal projection of a point in the 2D
// triangulation.
#include <algorithm>
#include <cstdio>
#include <exception>
#include <string>
#include <unordered_set>

#include "qualmesh/error.h"
#include "refine/refine_state.h"

namespace qualmesh::detail {

namespace {

KPoint2 local_point(const MeshState& s, Index facet, const Point3& p) {
  const auto uv = s.complex.frames[facet].to_local(p);
  return KPoint2(uv[0], uv[1]);
}

struct EdgeFlags {
  bool polygon_edge = false;
  bool toggles = false;
};

// Flags of the 2D edge (u, v) of facet f: on a closed polygon of f, and toggling the in/out parity.
EdgeFlags edge_flags(const MeshState& s, Index facet, const Fh2& fh, int i) {
  EdgeFlags flags;
  if (!fh->is_constrained(i)) return flags;
  const Index u = fh->vertex(Cdt2::ccw(i))->info();
  const Index v = fh->vertex(Cdt2::cw(i))->info();
  const Index segment = subsegment_of(s, u, v);
  if (segment == kNoIndex) return flags;
  if (const SegmentInFacet* sf = s.complex.segment_in_facet(segment, facet)) {
    flags.polygon_edge = sf->polygon_edge;
    flags.toggles = sf->toggles;
  }
  return flags;
}

void mark_domain(const MeshState& s, Index facet, Cdt2& cdt) {
  for (auto f = cdt.all_faces_begin(); f != cdt.all_faces_end(); ++f) f->info() = FaceInfo2{};
  // Parity: breadth-first from the infinite faces, toggling across polygon edges of odd coverage.
  std::vector<Fh2> stack;
  std::unordered_set<Fh2> seen;
  auto key_seen = [&](Fh2 f) { return seen.count(f) != 0; };
  for (auto f = cdt.all_faces_begin(); f != cdt.all_faces_end(); ++f)
    if (cdt.is_infinite(f)) {
      seen.insert(f);
      stack.push_back(f);
    }
  while (!stack.empty()) {
    Fh2 f = stack.back();
    stack.pop_back();
    for (int i = 0; i < 3; ++i) {
      Fh2 g = f->neighbor(i);
      if (key_seen(g)) continue;
      seen.insert(g);
      const EdgeFlags flags = edge_flags(s, facet, f, i);
      g->info().parity = f->info().parity != flags.toggles;
      stack.push_back(g);
    }
  }
  // Facet hole points: everything reached without crossing a polygon edge.
  for (const Point3& h : s.plc->facets[facet].holes) {
    Fh2 start = cdt.locate(local_point(s, facet, h));
    if (start == Fh2() || cdt.is_infinite(start) || start->info().hole) continue;
    start->info().hole = true;
    stack.assign(1, start);
    while (!stack.empty()) {
      Fh2 f = stack.back();
      stack.pop_back();
      for (int i = 0; i < 3; ++i) {
        Fh2 g = f->neighbor(i);
        if (cdt.is_infinite(g) || g->info().hole || edge_flags(s, facet, f, i).polygon_edge) continue;
        g->info().hole = true;
        stack.push_back(g);
      }
    }
  }
}

// Recomputes the in/out flags of the star of vh (the only faces an insertion or flip creates).
void update_star(MeshState& s, Index facet, Cdt2& cdt, Vh2 vh, std::vector<std::array<Index, 3>>* new_faces) {
  auto fc = cdt.incident_faces(vh), done = fc;
  if (fc == nullptr) return;
  do {
    Fh2 f = fc;
    if (cdt.is_infinite(f)) {
      f->info() = FaceInfo2{};
      continue;
    }
    const int i = f->index(vh);
    Fh2 g = f->neighbor(i);
    if (cdt.is_infinite(g)) {
      f->info() = FaceInfo2{};
      f->info().parity = edge_flags(s, facet, f, i).toggles;
    } else {
      const EdgeFlags flags = edge_flags(s, facet, f, i);
      f->info().parity = g->info().parity != flags.toggles;
      f->info().hole = flags.polygon_edge ? false : g->info().hole;
    }
    if (new_faces && f->info().in_domain())
      new_faces->push_back({f->vertex(0)->info(), f->vertex(1)->info(), f->vertex(2)->info()});
  } while (++fc != done);
}

}  // namespace

void build_facet_meshes(MeshState& s) {
  const Plc& plc = *s.plc;
  s.facets.clear();
  s.facets.resize(plc.facets.size());
  std::vector<std::vector<Index>> facet_segments(plc.facets.size());
  for (Index seg = 0; seg < s.complex.segments.size(); ++seg)
    for (const SegmentInFacet& sf : s.complex.segment_facets[seg]) facet_segments[sf.facet].push_back(seg);
  for (Index f = 0; f < plc.facets.size(); ++f) {
    FacetMesh& fm = s.facets[f];
    fm.cdt.infinite_vertex()->info() = kNoIndex;
    Fh2 hint;
    for (Index v : s.complex.facet_vertices[f]) {
      const std::size_t before = fm.cdt.number_of_vertices();
      Vh2 vh = fm.cdt.insert(local_point(s, f, s.point(v)), hint);
      if (fm.cdt.number_of_vertices() == before) {
        throw InputError(ErrorCode::DuplicateVertex,
                         "vertices " + std::to_string(vh->info()) + " and " + std::to_string(v) +
                             " coincide in the plane of facet " + std::to_string(f),
                         plc.name, 0, ElementIds{{vh->info(), v}, {}, {f}, {}});
      }
      vh->info() = v;
      fm.handle_map.set(v, vh);
      hint = vh->face();
    }
    for (Index seg : facet_segments[f]) {
      const Segment& sg = s.complex.segments[seg];
      const Vh2 a = fm.find(sg.a), b = fm.find(sg.b);
      bool inserted = a != Vh2() && b != Vh2();  // both ends were inserted above, unless the input is broken
      if (inserted) {
        try {
          fm.cdt.insert_constraint(a, b);
        } catch (const std::exception&) {
          inserted = false;
        }
      }
      if (!inserted) {
        throw InputError(ErrorCode::Intersection,
                         "segment " + std::to_string(seg) + " crosses another element of facet " + std::to_string(f),
                         plc.name, 0, ElementIds{{sg.a, sg.b}, {seg}, {f}, {}});
      }
    }
    mark_domain(s, f, fm.cdt);
  }
}

bool is_subfacet(const MeshState& s, Index facet, Index a, Index b, Index c) {
  const FacetMesh& fm = s.facets[facet];
  const Vh2 va = facet_vertex_handle(s, facet, a), vb = facet_vertex_handle(s, facet, b),
            vc = facet_vertex_handle(s, facet, c);
  if (va == Vh2() || vb == Vh2() || vc == Vh2()) return false;
  Fh2 fh;
  return fm.cdt.is_face(va, vb, vc, fh) && fh->info().in_domain();
}

Index subfacet_of(const MeshState& s, Index a, Index b, Index c) {
  const Index abc[3] = {a, b, c};
  for (Index v : abc)
    if (s.vertices[v].kind == VertexKind::Volume) return kNoIndex;
  auto try_facet = [&](Index f) {
    for (Index v : abc)
      if (!vertex_on_facet(s, v, f)) return false;
    return is_subfacet(s, f, a, b, c);
  };
  for (Index v : abc) {
    const VertexRecord& r = s.vertices[v];
    if (r.kind == VertexKind::Facet) return try_facet(r.host) ? r.host : kNoIndex;
  }
  for (Index v : abc) {
    const VertexRecord& r = s.vertices[v];
    if (r.kind == VertexKind::Segment) {
      for (const SegmentInFacet& sf : s.complex.segment_facets[r.host])
        if (try_facet(sf.facet)) return sf.facet;
      return kNoIndex;
    }
  }
  for (Index f : s.complex.vertex_facets[a])
    if (try_facet(f)) return f;
  return kNoIndex;
}

namespace {

// Whether inserting p on edge (fh, i) leaves every new triangle counterclockwise: p strictly inside the union of the
// edge's two triangles (an infinite side imposes nothing).
bool splits_edge_without_fold(const Cdt2& cdt, Fh2 fh, int i, const KPoint2& p) {
  const Fh2 g = fh->neighbor(i);
  const int j = cdt.mirror_index(fh, i);
  const std::array<std::pair<Fh2, int>, 2> sides = {{{fh, i}, {g, j}}};
  for (const auto& [f, k] : sides) {
    if (cdt.is_infinite(f)) continue;
    const KPoint2 &c = f->vertex(k)->point(), &x = f->vertex(Cdt2::ccw(k))->point(),
                  &y = f->vertex(Cdt2::cw(k))->point();
    if (CGAL::orientation(c, x, p) != CGAL::LEFT_TURN || CGAL::orientation(c, p, y) != CGAL::LEFT_TURN) return false;
  }
  return true;
}

// Where a boundary point goes in one facet's 2D triangulation, as CGAL's insert(point, locate type, face, index)
// takes it. A point on a segment splits the constrained edge between its chain neighbours; a facet point is
// located. `ok` is false when the point cannot go in without corrupting the triangulation: its 2D location is an
// existing vertex (a runaway of Rules 1-2 at the limit of double precision: CGAL would return that vertex, and the
// new vertex's id would overwrite the old one's), or a segment point whose chain neighbours are not joined by an
// edge.
struct FacetPlacement {
  bool ok = false;
  KPoint2 point;
  Cdt2::Locate_type type = Cdt2::EDGE;
  Fh2 face;
  int index = 0;
};

FacetPlacement place_in_facet(const MeshState& s, Index facet, const VertexRecord& r) {
  const FacetMesh& fm = s.facets[facet];
  FacetPlacement out;
  out.point = local_point(s, facet, r.point);
  if (r.kind == VertexKind::Segment) {
    // Symbolically on the constrained edge between its chain neighbours: split that edge.
    const Vh2 a = facet_vertex_handle(s, facet, r.prev), b = facet_vertex_handle(s, facet, r.next);
    Fh2 fh;
    int i = 0;
    if (a == Vh2() || b == Vh2() || !fm.cdt.is_edge(a, b, fh, i)) return out;
    // The point projected from 3D normally lies in the edge's two triangles. Next to a needle triangle rounding
    // can put it outside, and splitting the edge there folds the triangulation; then take the point on the 2D
    // edge at the vertex's parameter between its chain neighbours instead, when that one lies inside. (Where
    // neither does, e.g. collinear with a neighbour on a straight chain, the projected point is kept: CGAL's
    // flips repair those, 1385_Laufrad_1000.stp has such points and meshes exactly; but not one on a vertex.)
    if (!splits_edge_without_fold(fm.cdt, fh, i, out.point)) {
      const double ta = segment_parameter(s, r.host, r.prev), tb = segment_parameter(s, r.host, r.next);
      const KPoint2 pa = a->point(), pb = b->point();
      const double u = tb != ta ? (r.t - ta) / (tb - ta) : 0.5;
      const KPoint2 q(pa.x() + u * (pb.x() - pa.x()), pa.y() + u * (pb.y() - pa.y()));
      if (splits_edge_without_fold(fm.cdt, fh, i, q)) {
        out.point = q;
      } else {
        Cdt2::Locate_type lt;
        int li = 0;
        fm.cdt.locate(out.point, lt, li, fh);
        if (lt == Cdt2::VERTEX) return out;
      }
    }
    out.face = fh;
    out.index = i;
  } else {
    // No hint, as CGAL's insert(p) locates: the levels' check and the insertion then make the same walk and find
    // the same place. (With a hint at a vertex of the split subfacet, bottle.brep at --size 80 found no vertex
    // there and the insertion then found one: near the runaway the facet's triangulation is folded, and the walk's
    // answer depends on where it starts.)
    out.face = fm.cdt.locate(out.point, out.type, out.index);
    if (out.type == Cdt2::VERTEX) return out;
  }
  out.ok = true;
  return out;
}

}  // namespace

bool facet_accepts_point(const MeshState& s, const VertexRecord& r) {
  if (r.kind == VertexKind::Segment) {
    for (const SegmentInFacet& sf : s.complex.segment_facets[r.host])
      if (!place_in_facet(s, sf.facet, r).ok) return false;
    return true;
  }
  return r.kind != VertexKind::Facet || place_in_facet(s, r.host, r).ok;
}

void MeshState::stop_at_precision(const std::string& element, double size, const Point3& where) {
  vertex_limit_reached = true;
  if (!precision_stop.empty()) return;
  char text[200];
  std::snprintf(text, sizeof text, " (size %.3g) at (%.17g, %.17g, %.17g)", size, where[0], where[1], where[2]);
  precision_stop = "the split point of an element of " + element + text +
                   " falls on a vertex of a facet's 2D triangulation";
}

void insert_into_facet(MeshState& s, Index facet, Index w, std::vector<std::array<Index, 3>>* new_faces) {
  FacetMesh& fm = s.facets[facet];
  const FacetPlacement at = place_in_facet(s, facet, s.vertices[w]);
  if (!at.ok)  // the levels ask facet_accepts_point() before inserting anywhere
    throw std::logic_error("insert_into_facet: vertex " + std::to_string(w) + " has no place in facet " +
                           std::to_string(facet) + "'s triangulation");
  const Vh2 vh = fm.cdt.insert(at.point, at.type, at.face, at.index);
  vh->info() = w;
  if (s.vertices[w].kind == VertexKind::Facet) s.vertices[w].facet_handle = vh;
  else fm.handle_map.set(w, vh);
  update_star(s, facet, fm.cdt, vh, new_faces);
}

bool encroaches_in_facet_plane(const MeshState& s, Index facet, const std::array<Index, 3>& abc, Index w) {
  auto handle = [&](Index v) { return facet_vertex_handle(s, facet, v); };
  const Vh2 va = handle(abc[0]), vb = handle(abc[1]), vc = handle(abc[2]), vw = handle(w);
  if (va == Vh2() || vb == Vh2() || vc == Vh2() || vw == Vh2()) return true;  // not decidable in 2D: assume so
  return CGAL::side_of_bounded_circle(va->point(), vb->point(), vc->point(), vw->point()) == CGAL::ON_BOUNDED_SIDE;
}

std::optional<std::array<Index, 3>> subfacet_containing_projection(const MeshState& s, Index facet, const Point3& p,
                                                                   Index hint) {
  const FacetMesh& fm = s.facets[facet];
  Cdt2::Locate_type lt;
  int li = 0;
  const Vh2 hv = hint == kNoIndex ? Vh2() : facet_vertex_handle(s, facet, hint);
  Fh2 fh = fm.cdt.locate(local_point(s, facet, p), lt, li, hv == Vh2() ? Fh2() : hv->face());
  if (fh == Fh2() || fm.cdt.is_infinite(fh) || !fh->info().in_domain()) return std::nullopt;
  return std::array<Index, 3>{fh->vertex(0)->info(), fh->vertex(1)->info(), fh->vertex(2)->info()};
}

bool facet_point_in_domain(const MeshState& s, Index facet, const Point3& p, Index hint) {
  const FacetMesh& fm = s.facets[facet];
  Cdt2::Locate_type lt;
  int li = 0;
  const Vh2 hv = hint == kNoIndex ? Vh2() : facet_vertex_handle(s, facet, hint);
  Fh2 fh = fm.cdt.locate(local_point(s, facet, p), lt, li, hv == Vh2() ? Fh2() : hv->face());
  if (fh == Fh2()) return false;
  if (!fm.cdt.is_infinite(fh) && fh->info().in_domain()) return true;
  if (lt == Cdt2::EDGE) {
    Fh2 g = fh->neighbor(li);
    return !fm.cdt.is_infinite(g) && g->info().in_domain();
  }
  return false;
}

std::optional<std::array<Index, 2>> subsegment_towards(const MeshState& s, Index facet,
                                                      const std::array<Index, 3>& abc, const Point3& p) {
  const FacetMesh& fm = s.facets[facet];
  auto handle = [&](Index v) { return facet_vertex_handle(s, facet, v); };
  const Vh2 va = handle(abc[0]), vb = handle(abc[1]), vc = handle(abc[2]);
  Fh2 fh;
  if (va == Vh2() || vb == Vh2() || vc == Vh2() || !fm.cdt.is_face(va, vb, vc, fh)) return std::nullopt;
  const KPoint2 q = local_point(s, facet, p);
  const KPoint2 o = CGAL::centroid(va->point(), vb->point(), vc->point());
  // Straight walk from o to q: leave each face through an edge that q lies strictly beyond and that the line oq
  // meets. Bounded: a centre that far away is left to the caller's general path.
  for (int steps = 0; steps < 256; ++steps) {
    if (fm.cdt.is_infinite(fh)) return std::nullopt;
    int exit = -1;
    for (int i = 0; i < 3 && exit < 0; ++i) {
      const KPoint2& x = fh->vertex(Cdt2::ccw(i))->point();
      const KPoint2& y = fh->vertex(Cdt2::cw(i))->point();
      if (CGAL::orientation(x, y, q) != CGAL::RIGHT_TURN) continue;  // the face lies left of (x, y)
      const CGAL::Orientation ox = CGAL::orientation(o, q, x), oy = CGAL::orientation(o, q, y);
      if (ox != oy || ox == CGAL::COLLINEAR) exit = i;
    }
    if (exit < 0) return std::nullopt;  // q is in this face: no subsegment in between
    if (fh->is_constrained(exit))
      return std::array<Index, 2>{fh->vertex(Cdt2::ccw(exit))->info(), fh->vertex(Cdt2::cw(exit))->info()};
    fh = fh->neighbor(exit);
  }
  return std::nullopt;
}

bool flip_subfacet_to_match(MeshState& s, Index facet, const std::array<Index, 3>& abc,
                            std::vector<std::array<Index, 3>>* new_faces, Index only_across_from) {
  FacetMesh& fm = s.facets[facet];
  auto handle = [&](Index v) { return facet_vertex_handle(s, facet, v); };
  const Vh2 va = handle(abc[0]), vb = handle(abc[1]), vc = handle(abc[2]);
  Fh2 fh;
  if (va == Vh2() || vb == Vh2() || vc == Vh2() || !fm.cdt.is_face(va, vb, vc, fh)) return false;
  for (int i = 0; i < 3; ++i) {
    if (fh->is_constrained(i)) continue;
    Fh2 g = fh->neighbor(i);
    if (fm.cdt.is_infinite(g) || !g->info().in_domain()) continue;
    const Vh2 c = fh->vertex(i), x = fh->vertex(Cdt2::ccw(i)), y = fh->vertex(Cdt2::cw(i));
    if (only_across_from != kNoIndex && c->info() != only_across_from) continue;
    const Vh2 d = g->vertex(fm.cdt.mirror_index(fh, i));
    const Vh3 c3 = s.vertices[c->info()].handle, d3 = s.vertices[d->info()].handle;
    const Vh3 x3 = s.vertices[x->info()].handle, y3 = s.vertices[y->info()].handle;
    Ch3 cell;
    int i0 = 0, i1 = 0, i2 = 0;
    if (!s.tr.is_edge(c3, d3, cell, i0, i1)) continue;
    if (!s.tr.is_facet(c3, d3, x3, cell, i0, i1, i2) || !s.tr.is_facet(c3, d3, y3, cell, i0, i1, i2)) continue;
    // The quadrilateral must be strictly convex for the flip (cd crosses xy).
    const auto o1 = CGAL::orientation(x->point(), y->point(), c->point());
    const auto o2 = CGAL::orientation(x->point(), y->point(), d->point());
    const auto o3 = CGAL::orientation(c->point(), d->point(), x->point());
    const auto o4 = CGAL::orientation(c->point(), d->point(), y->point());
    if (o1 == CGAL::COLLINEAR || o2 == CGAL::COLLINEAR || o1 == o2 || o3 == CGAL::COLLINEAR ||
        o4 == CGAL::COLLINEAR || o3 == o4)
      continue;
    const FaceInfo2 info = fh->info();
    fm.cdt.flip(fh, i);
    // Both faces of the flip now hold c and d.
    auto fc = fm.cdt.incident_faces(c), done = fc;
    do {
      Fh2 f = fc;
      if (!fm.cdt.is_infinite(f) && f->has_vertex(d)) {
        f->info() = info;
        if (new_faces) new_faces->push_back({f->vertex(0)->info(), f->vertex(1)->info(), f->vertex(2)->info()});
      }
    } while (++fc != done);
    ++s.stats.num_subfacet_flips;
    return true;
  }
  return false;
}

void collect_subfacets(const MeshState& s, Index facet, std::vector<std::array<Index, 3>>& out) {
  const FacetMesh& fm = s.facets[facet];
  for (auto f = fm.cdt.finite_faces_begin(); f != fm.cdt.finite_faces_end(); ++f)
    if (f->info().in_domain()) out.push_back({f->vertex(0)->info(), f->vertex(1)->info(), f->vertex(2)->info()});
}

Index face_subfacet(const MeshState& s, Ch3 c, int i) {
  Index ids[3];
  for (int k = 0; k < 3; ++k) {
    ids[k] = c->vertex((i + 1 + k) & 3)->info();
    if (ids[k] == kNoIndex) return kNoIndex;
  }
  return subfacet_of(s, ids[0], ids[1], ids[2]);
}

// --- After pumping (pump_star.cpp apply_weight) ---

namespace {

// Whether two sides of triangle (a, b, c) are subsegments of one segment: its vertices are consecutive on that
// segment, hence collinear, whatever their rounded coordinates say.
bool consecutive_on_a_segment(const MeshState& s, Index a, Index b, Index c) {
  const auto middle = [&s](Index u, Index m, Index w) {
    const Index seg = subsegment_of(s, u, m);
    return seg != kNoIndex && subsegment_of(s, m, w) == seg;
  };
  return middle(a, b, c) || middle(b, c, a) || middle(c, a, b);
}

}  // namespace

// After a move that changed subfacets (StarEvaluator::lost_subfacets): flips the 2D triangulation of each such
// facet F to the new star. Raising v's weight lowers v's lifted point, so, as for an insertion, the 2D weighted
// Delaunay triangulation of F's vertices is reached by flipping edges opposite v that are not locally regular; each
// flip makes an edge vd that the 3D star has (the target). Returns false if some lost subfacet is left, or a
// subfacet at v is no 3D face (a bug: the move was checked to retile F).
bool retile_facets(MeshState& s, Index v, const std::vector<std::pair<Index, std::array<Index, 3>>>& lost) {
  std::vector<Index> facets;
  for (const auto& l : lost) facets.push_back(l.first);
  std::sort(facets.begin(), facets.end());
  facets.erase(std::unique(facets.begin(), facets.end()), facets.end());
  const Vh3 v3 = s.vertices[v].handle;
  for (const Index facet : facets) {
    FacetMesh& fm = s.facets[facet];
    const Vh2 v2 = facet_vertex_handle(s, facet, v);
    if (v2 == Vh2()) return false;
    bool flipped = true;
    for (int round = 0; flipped && round < 1000; ++round) {
      flipped = false;
      auto fc = fm.cdt.incident_faces(v2), done = fc;
      do {
        Fh2 fh = fc;
        if (fm.cdt.is_infinite(fh) || !fh->info().in_domain()) continue;
        const int i = fh->index(v2);
        if (fh->is_constrained(i)) continue;
        const Fh2 g = fh->neighbor(i);
        if (fm.cdt.is_infinite(g) || !g->info().in_domain()) continue;
        const Vh2 d = g->vertex(fm.cdt.mirror_index(fh, i));
        const Vh2 x = fh->vertex(Cdt2::ccw(i)), y = fh->vertex(Cdt2::cw(i));
        Ch3 cell;
        int i0 = 0, i1 = 0;
        if (!s.tr.is_edge(v3, s.vertices[d->info()].handle, cell, i0, i1)) continue;
        // xy crosses vd: the quadrilateral v x d y is strictly convex.
        const auto o1 = CGAL::orientation(x->point(), y->point(), v2->point());
        const auto o2 = CGAL::orientation(x->point(), y->point(), d->point());
        const auto o3 = CGAL::orientation(v2->point(), d->point(), x->point());
        const auto o4 = CGAL::orientation(v2->point(), d->point(), y->point());
        if (o1 == CGAL::COLLINEAR || o2 == CGAL::COLLINEAR || o1 == o2 || o3 == CGAL::COLLINEAR ||
            o4 == CGAL::COLLINEAR || o3 == o4)
          continue;
        // The 2D points are rounded projections, so three consecutive vertices of one segment may pass the test
        // above, and the 3D triangulation can have the edge vd over a flat triangle of them (outside the domain).
        // Symbolically such a quadrilateral is not convex: the flip would make a triangle of collinear vertices.
        if (consecutive_on_a_segment(s, v, x->info(), d->info()) ||
            consecutive_on_a_segment(s, v, d->info(), y->info()))
          continue;
        const FaceInfo2 info = fh->info();
        fm.cdt.flip(fh, i);
        auto nc = fm.cdt.incident_faces(v2), ndone = nc;
        do {
          const Fh2 f = nc;
          if (!fm.cdt.is_infinite(f) && f->has_vertex(d)) f->info() = info;
        } while (++nc != ndone);
        flipped = true;
        break;  // the circulator is stale
      } while (++fc != done);
    }
  }
  for (const auto& l : lost)
    if (is_subfacet(s, l.first, l.second[0], l.second[1], l.second[2])) return false;
  // And every subfacet at v on those facets is a face of the 3D triangulation.
  for (const Index facet : facets) {
    const FacetMesh& fm = s.facets[facet];
    const Vh2 v2 = facet_vertex_handle(s, facet, v);
    auto fc = fm.cdt.incident_faces(v2), done = fc;
    do {
      if (fm.cdt.is_infinite(fc) || !fc->info().in_domain()) continue;
      Ch3 cell;
      int i, j, k;
      if (!s.tr.is_facet(s.vertices[fc->vertex(0)->info()].handle, s.vertices[fc->vertex(1)->info()].handle,
                         s.vertices[fc->vertex(2)->info()].handle, cell, i, j, k))
        return false;
    } while (++fc != done);
  }
  return true;
}

}  // namespace qualmesh::detail
