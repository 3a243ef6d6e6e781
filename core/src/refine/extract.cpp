// Extraction (issue 3): the cells of the domain's regions become a TetMesh. Vertices are numbered in the engine's
// vertex order (input vertices first, then Steiner points in insertion order), keeping only those used; tetrahedra
// are positively oriented (CGAL cells are) and sorted by vertex ids, so the output is deterministic. Every face on
// an input facet (domain boundary or internal facet) is listed once with the facet it lies on, oriented with its
// normal pointing out of the tetrahedron it was taken from (for boundary faces: out of the domain).
#include <algorithm>

#include "qualmesh/quality.h"

#include "refine/refine_state.h"

namespace qualmesh::detail {

TetMesh extract_mesh(MeshState& s, std::vector<std::uint8_t>& touches_acute) {
  TetMesh mesh;
  std::vector<Index> new_id(s.vertices.size(), kNoIndex);
  struct Tet {
    std::array<Index, 4> v;
    int region;
    bool acute;
  };
  std::vector<Tet> tets;
  struct Face {
    std::array<Index, 3> v;
    int facet;
  };
  std::vector<Face> faces;
  sort_given_up(s);
  remove_flat_boundary_cells(s);
  for (auto c = s.tr.finite_cells_begin(); c != s.tr.finite_cells_end(); ++c) {
    const int region = c->info().region;
    if (region < 0) continue;
    Tet t;
    for (int k = 0; k < 4; ++k) {
      t.v[k] = c->vertex(k)->info();
      new_id[t.v[k]] = 0;
    }
    t.region = region;
    t.acute = tet_touches_acute_angle(s, t.v);
    {
      // Quality audit (MeshStats): radius-edge ratio above rho0, and why Rule 3 left it.
      const Point3 &p0 = s.point(t.v[0]), &p1 = s.point(t.v[1]), &p2 = s.point(t.v[2]), &p3 = s.point(t.v[3]);
      const double rho = tet_radius_edge(p0, p1, p2, p3);
      if (!t.acute) s.stats.max_radius_edge_away_from_acute = std::max(s.stats.max_radius_edge_away_from_acute, rho);
      if (rho > s.params.radius_edge_bound) {
        ++s.stats.num_tets_above_bound;
        if (t.acute) {
          ++s.stats.num_above_bound_acute;
        } else if (why_left(s, c) == LeftReason::Rejected) {
          ++s.stats.num_above_bound_rejected;
        } else {
          ++s.stats.num_above_bound_other;
        }
      }
    }
    tets.push_back(t);
    for (int i = 0; i < 4; ++i) {
      const Ch3 n = c->neighbor(i);
      const int other = n->info().region;
      const Index facet = face_subfacet(s, c, i);
      if (facet == kNoIndex && other == region) continue;
      // Both sides inside the domain: take the face once, from the side with the smaller opposite vertex id.
      if (other >= 0) {
        const Index mine = c->vertex(i)->info();
        const Index theirs = n->vertex(n->index(c))->info();
        if (theirs < mine) continue;
      }
      Face f;
      // CGAL cells are positively oriented, so (i+1, i+2, i+3) has its normal towards vertex i for odd i and away
      // from it for even i; keep the outward orientation.
      f.v = {c->vertex((i + 1) & 3)->info(), c->vertex((i + 2) & 3)->info(), c->vertex((i + 3) & 3)->info()};
      if (i % 2 == 1) std::swap(f.v[1], f.v[2]);
      f.facet = facet == kNoIndex ? -1 : int(facet);
      faces.push_back(f);
    }
  }
  Index next = 0;
  for (Index v = 0; v < s.vertices.size(); ++v) {
    if (new_id[v] == kNoIndex) continue;
    new_id[v] = next++;
    mesh.points.push_back(s.vertices[v].point);
    // Pumping (pump.cpp) leaves weights on the triangulation's vertices; all zero without it.
    const double w = s.vertices[v].handle->point().weight();
    // The first nonzero weight fills zeros for the points before it, then every point gets its weight (the point
    // itself included, also when it is the first one: weights is still empty after assigning it zero entries).
    if (w != 0 && mesh.weights.empty()) mesh.weights.assign(mesh.points.size() - 1, 0.0);
    if (!mesh.weights.empty() || w != 0) mesh.weights.push_back(w);
  }
  for (Tet& t : tets)
    for (Index& v : t.v) v = new_id[v];
  for (Face& f : faces)
    for (Index& v : f.v) v = new_id[v];
  // Canonical order: rotate each tet so its smallest id comes first (an even permutation keeps the orientation).
  for (Tet& t : tets) {
    auto& v = t.v;
    const int m = int(std::min_element(v.begin(), v.end()) - v.begin());
    // Even permutations moving position m to 0.
    if (m == 1) v = {v[1], v[0], v[3], v[2]};
    else if (m == 2) v = {v[2], v[3], v[0], v[1]};
    else if (m == 3) v = {v[3], v[2], v[1], v[0]};
  }
  std::sort(tets.begin(), tets.end(), [](const Tet& a, const Tet& b) { return a.v < b.v; });
  for (Face& f : faces) {
    auto& v = f.v;
    const int m = int(std::min_element(v.begin(), v.end()) - v.begin());
    std::rotate(v.begin(), v.begin() + m, v.end());
  }
  std::sort(faces.begin(), faces.end(), [](const Face& a, const Face& b) { return a.v < b.v; });
  touches_acute.clear();
  touches_acute.reserve(tets.size());
  for (const Tet& t : tets) touches_acute.push_back(t.acute ? 1 : 0);
  mesh.tets.reserve(tets.size());
  mesh.tet_region.reserve(tets.size());
  for (const Tet& t : tets) {
    mesh.tets.push_back(t.v);
    mesh.tet_region.push_back(s.regions[t.region].attribute);
  }
  // Every region boundary is made of subfacets once the flood is consistent (regions.cpp); a face on no input
  // facet (face_facet -1, marker 0) means a cell's region contradicts its neighbours' (cube1000.igs before
  // remove_flat_boundary_cells() handled flat cells glued onto a subfacet).
  const auto num_off_input = std::count_if(faces.begin(), faces.end(), [](const Face& f) { return f.facet < 0; });
  if (num_off_input > 0)
    s.log_line("extraction: warning: " + std::to_string(num_off_input) + " boundary face(s) on no input facet");
  for (const Face& f : faces) {
    mesh.faces.push_back(f.v);
    mesh.face_facet.push_back(f.facet);
    mesh.face_marker.push_back(f.facet >= 0 ? s.plc->facets[f.facet].marker : 0);
  }
  // The subsegments of every marked input segment (CAD edges: Edge<marker>), walking its chain from a to b; the
  // segments are in collect_segments order, so the list is deterministic.
  for (Index seg = 0; seg < s.complex.segments.size(); ++seg) {
    const Segment& segment = s.complex.segments[seg];
    if (segment.marker == 0) continue;
    for (Index u = segment.a, v; u != segment.b; u = v) {
      v = next_on_segment(s, seg, u);
      if (new_id[u] == kNoIndex || new_id[v] == kNoIndex) continue;  // outside the meshed regions
      mesh.edges.push_back({new_id[u], new_id[v]});
      mesh.edge_marker.push_back(segment.marker);
    }
  }
  return mesh;
}

}  // namespace qualmesh::detail
