// The one insertion module of the refinement engine (levels.h): every vertex that Rules 1-3 and sliver insertion
// add goes through insert_vertex(), which inserts it into the hole of its conflict zone, into the 2D triangulations
// of the facets it lies on (subfacets.cpp), gives the new cells their region, and returns what changed
// (InsertionResult): the new star, the zone's subsegments and subfacets with whether each survived, and the new
// subsegments and subfacets. The levels' after-insertion hooks (scheduler.cpp notify_insertion) then queue what it
// encroached or removed. Also here: the Delaunay triangulation of the input vertices (QUALMESH step 1, Cheng & Dey
// Section 3.7), conflict zones, and the zone's candidate elements.
//
// Why the zone is enough (DESIGN.md, "found locally"). Gabriel property: a subsegment (subfacet) is missing from the
// Delaunay triangulation only if its closed diametral ball holds a vertex, and a present one whose diametral ball
// holds a vertex has such a vertex among the apices of its incident cells (for a subfacet, the two cells on its
// sides). A new point p can only encroach or remove elements that are faces or edges of cells in p's conflict zone
// (cells whose circumsphere holds p: any sphere through a subfacet on p's side contains the part of its diametral
// ball on that side). So after each insertion only the conflict zone's edges and faces, and the new subsegments and
// subfacets (the 2D star of the new vertex), are checked; nothing is ever scanned globally after the start.
#include <algorithm>
#include <string>

#include "qualmesh/error.h"
#include "refine/refine_state.h"

namespace qualmesh::detail {

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

Index add_vertex(MeshState& s, const Point3& p, VertexKind kind, Index host, double t) {
  VertexRecord r;
  r.point = p;
  r.kind = kind;
  r.host = host;
  r.t = t;
  s.vertices.push_back(r);
  return Index(s.vertices.size() - 1);
}

Ch3 hint_of(const MeshState& s, Index v) { return s.vertices[v].handle->cell(); }

InsertionResult insert_vertex(MeshState& s, Index id, ConflictZone& cz, const Candidates& cand, int region) {
  InsertionResult result;
  result.vertex = id;
  result.region = region;
  result.num_destroyed_cells = cz.cells.size();
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
  result.zone_subsegments = cand.subsegments;
  for (const auto& e : cand.subsegments)  // e[1] < e[2]
    result.zone_subsegment_kept.push_back(
        std::binary_search(kept_edges.begin(), kept_edges.end(), std::array<Index, 2>{e[1], e[2]}));
  result.zone_subfacets = cand.subfacets;
  for (const auto& f : cand.subfacets)  // f[1] < f[2] < f[3]
    result.zone_subfacet_kept.push_back(
        std::binary_search(kept_faces.begin(), kept_faces.end(), std::array<Index, 3>{f[1], f[2], f[3]}));
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
  if (s.tr.number_of_vertices() >= s.params.max_vertices) s.vertex_limit_reached = true;
  if (s.tr.number_of_vertices() >= s.pumping_vertex_budget) s.projection_runaway = s.vertex_limit_reached = true;
  s.poll_cancel();

  // The facets' 2D triangulations (Section 3.2's subfacets): the new vertex's stars there are new subfacets.
  const VertexRecord& r = s.vertices[id];
  std::vector<std::array<Index, 3>> new_faces;
  if (r.kind == VertexKind::Segment) {
    for (const SegmentInFacet& sf : s.complex.segment_facets[r.host]) {
      const std::size_t before = new_faces.size();
      insert_into_facet(s, sf.facet, id, &new_faces);
      for (std::size_t n = before; n < new_faces.size(); ++n)
        result.new_subfacets.push_back({sf.facet, new_faces[n][0], new_faces[n][1], new_faces[n][2]});
    }
  } else if (r.kind == VertexKind::Facet) {
    insert_into_facet(s, r.host, id, &new_faces);
    for (const auto& f : new_faces) result.new_subfacets.push_back({r.host, f[0], f[1], f[2]});
  }

  // Cells of the star: their region (kUnknownRegion until the next flood for boundary points).
  result.new_cells.reserve(outer.size());
  for (const HoleFace& o : outer) result.new_cells.push_back(o.new_cell());
  for (const Ch3& c : result.new_cells) {
    if (s.tr.is_infinite(c)) {
      c->info().region = s.regions_known ? kOutsideRegion : kUnknownRegion;
      continue;
    }
    c->info().region = region;
  }
  if (region < 0 && s.regions_known) s.region_pending.push_back(id);
  if (r.kind == VertexKind::Segment) {
    result.new_subsegments.push_back({r.host, r.prev, id});
    result.new_subsegments.push_back({r.host, id, r.next});
  }
  return result;
}

Index insert_volume_vertex(MeshState& s, const Point3& p, std::vector<Ch3>& cells, std::vector<Facet3>& boundary,
                           int region) {
  ConflictZone cz;
  cz.cells.swap(cells);
  cz.boundary.swap(boundary);
  Candidates cand;
  collect_candidates(s, cz, cand);
  const Index w = add_vertex(s, p, VertexKind::Volume, kNoIndex);
  notify_insertion(s, insert_vertex(s, w, cz, cand, region));
  return w;
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

}  // namespace qualmesh::detail
