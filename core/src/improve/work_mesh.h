// The mutable tetrahedral mesh of the improvement pass (improve.h): tetrahedra with region attributes, a
// vertex-to-tetrahedra incidence kept up to date by flips, the constraint faces (every face of TetMesh::faces:
// domain boundary and internal facets) and the protected edges (on input segments) that no flip may remove, and the
// one quality measure (smallest dihedral angle, quality.h). Private to core/src/improve/.
#pragma once

#include <algorithm>
#include <cmath>
#include <array>
#include <cstdint>
#include <functional>
#include <limits>
#include <vector>

#include "improve/improve.h"
#include "qualmesh/quality.h"
#include "qualmesh/tet_mesh.h"
#include "vec3.h"

namespace qualmesh::detail {

using Tet4 = std::array<Index, 4>;
using Face3 = std::array<Index, 3>;
using Edge2 = std::array<Index, 2>;

inline Face3 sorted_face(Index a, Index b, Index c) {
  Face3 f{a, b, c};
  std::sort(f.begin(), f.end());
  return f;
}
inline Edge2 sorted_edge(Index a, Index b) { return a < b ? Edge2{a, b} : Edge2{b, a}; }

// One index swapped for another in a list that holds it.
inline void replace_in(std::vector<Index>& list, Index from, Index to) {
  *std::find(list.begin(), list.end(), from) = to;
}

// The corners (local 0..3, the first pair found on ties) of the shortest edge of the tetrahedron p[0..3]: the edge
// by which the output's acute-angle flag of a changed tet is judged (improve.h, shortest_edge_forced).
inline Edge2 shortest_edge(const Point3* p) {
  double sq_min = std::numeric_limits<double>::infinity();
  Edge2 out{0, 1};
  for (Index a = 0; a < 4; ++a)
    for (Index b = a + 1; b < 4; ++b) {
      const double dx = p[a][0] - p[b][0], dy = p[a][1] - p[b][1], dz = p[a][2] - p[b][2];
      const double sq = dx * dx + dy * dy + dz * dz;
      if (sq < sq_min) sq_min = sq, out = {a, b};
    }
  return out;
}

// Smallest dihedral angle in degrees of (p0, p1, p2, p3), or -1 when it is not positively oriented by a margin
// (six times its volume at most 1e-13 of its longest edge cubed).
double oriented_min_dihedral_deg(const Point3& p0, const Point3& p1, const Point3& p2, const Point3& p3);

struct WorkMesh {
  std::vector<Point3>* points = nullptr;
  const std::vector<std::array<Index, 3>>* faces = nullptr;  // TetMesh::faces: the constraint faces
  std::vector<Tet4> tets;
  std::vector<int> region;
  std::vector<std::uint8_t> alive;
  std::vector<std::uint8_t> touched;           // new (flip) or with a moved vertex
  std::vector<std::vector<Index>> incident;    // vertex -> alive tets holding it
  std::vector<Edge2> protected_edges;          // sorted pairs, sorted
  std::vector<std::vector<Index>> vertex_faces;  // vertex -> indices into TetMesh::faces holding it
  // The radius-edge guard (ImproveOptions::radius_edge_bound; 0: off) and the acute-angle criterion of the output
  // (improve.h's shortest_edge_forced; may be empty).
  double rho_bound = 0;
  std::function<bool(Index, Index)> edge_forced;

  const Point3& point(Index v) const { return (*points)[v]; }
  double quality(Index t) const {
    const Tet4& v = tets[t];
    return oriented_min_dihedral_deg(point(v[0]), point(v[1]), point(v[2]), point(v[3]));
  }
  // The index into TetMesh::faces of constraint face abc, or kNoIndex: the one of a's faces (vertex_faces) that holds
  // b and c. A scan of a handful of faces, kept up to date by the same edits as vertex_faces; a sorted list of all
  // faces, kept in step by insertions and erasures, moved megabytes per boundary edge split tried (cheese.off: 11% of
  // the run in memmove).
  Index face_index(Index a, Index b, Index c) const {
    for (Index f : vertex_faces[a]) {
      const auto& t = (*faces)[f];
      if ((t[0] == b || t[1] == b || t[2] == b) && (t[0] == c || t[1] == c || t[2] == c)) return f;
    }
    return kNoIndex;
  }
  bool is_constraint_face(Index a, Index b, Index c) const { return face_index(a, b, c) != kNoIndex; }
  bool is_protected_edge(Index a, Index b) const {
    return std::binary_search(protected_edges.begin(), protected_edges.end(), sorted_edge(a, b));
  }
  // The radius-edge guard on one new or changed tetrahedron with corners p[0..3] (vertex ids v): it may exceed
  // rho_bound only where the output will excuse it (its shortest edge is forced by an acute input angle, the
  // criterion by which touches_acute is set for changed tets) and not beyond `old_max`, the largest ratio among the
  // tetrahedra it replaces. So no operation of the pass leaves a tet above rho_bound away from acute input angles
  // (Rule 3 of Section 3 leaves rho0 there, relaxed by kImproveRadiusEdgeFactor for changed tets) nor makes the
  // worst one worse.
  bool rho_allowed(const Tet4& v, const Point3* p, double old_max) const {
    if (rho_bound <= 0) return true;
    const double rho = tet_radius_edge(p[0], p[1], p[2], p[3]);
    if (rho <= rho_bound) return true;
    if (!(rho <= old_max) || !edge_forced) return false;
    const Edge2 e = shortest_edge(p);
    return edge_forced(v[e[0]], v[e[1]]);
  }
  bool rho_allowed(const Tet4& v, double old_max) const {
    const Point3 p[4] = {point(v[0]), point(v[1]), point(v[2]), point(v[3])};
    return rho_allowed(v, p, old_max);
  }
  double radius_edge(Index t) const {
    const Tet4& v = tets[t];
    return tet_radius_edge(point(v[0]), point(v[1]), point(v[2]), point(v[3]));
  }
  // The alive tetrahedra holding both u and v (the ring of edge uv), in incident[u]'s order.
  void tets_around_edge(Index u, Index v, std::vector<Index>& out) const {
    out.clear();
    for (Index t : incident[u])
      for (Index x : tets[t])
        if (x == v) out.push_back(t);
  }
  // Whether some alive tet holds both u and w.
  bool has_edge(Index u, Index w) const {
    for (Index t : incident[u])
      for (Index x : tets[t])
        if (x == w) return true;
    return false;
  }
  Index add_tet(const Tet4& t, int label) {
    const Index id = Index(tets.size());
    tets.push_back(t);
    region.push_back(label);
    alive.push_back(1);
    touched.push_back(1);
    for (Index v : t) incident[v].push_back(id);
    return id;
  }
  // Undoes kill_tet (the tet keeps its id).
  void revive_tet(Index id) {
    alive[id] = 1;
    for (Index v : tets[id]) incident[v].push_back(id);
  }
  void kill_tet(Index id) {
    alive[id] = 0;
    for (Index v : tets[id]) {
      auto& list = incident[v];
      list.erase(std::find(list.begin(), list.end(), id));
    }
  }
};

// Flips (flips.cpp). Each tries every flip that removes tet `t` (edge removal over its six edges, n from 3 to
// max_ring, and 2-3 flips over its four faces), inside one region and away from constraint faces and protected
// edges, and applies the one whose new tetrahedra have the largest smallest dihedral angle, when that is larger
// than the smallest of the tetrahedra it replaces. Returns 0 (nothing done), 1 (2-3 flip) or n (edge
// removal of a ring of n). The radius-edge guard (WorkMesh::rho_allowed) holds for every new tetrahedron.
int flip_to_remove(WorkMesh& w, Index t, int max_ring);

// Edge split (edge_split.cpp): splits edge uv at its midpoint, in the volume or (with `boundary`) inside one planar
// input facet, calls `smooth` on the new vertex, and keeps the split only when the smallest angle around the edge
// grows; else undoes it completely. A volume edge whose split fails from a bad midpoint start (a new tet not positive,
// or beyond the radius-edge guard) is tried again with the new vertex starting towards the centroid of the edge's
// ring, kept only if it also leaves no more tets below `threshold` (degrees).
// `constraints` gets the new vertex's freedom; `facet_normals` are the PLC facets' unit normals. Returns whether it
// kept the split, and in *on_boundary whether the split was inside a facet.
bool split_edge(WorkMesh& w, TetMesh& mesh, const std::vector<Point3>& facet_normals,
                std::vector<VertexConstraint>& constraints, Index u, Index v, bool boundary, double threshold,
                const std::function<void(Index)>& smooth, bool* on_boundary);

// Cap removal (cap_removal.cpp): removes tet `t` when it is a cap on one CAD face (two hull faces with one
// marker > 0 sharing an edge that no other tet holds), flipping that boundary edge to the other diagonal; the caller
// allows it only with ImproveOptions::project_to_boundary. Returns whether it removed the tet.
bool remove_cap(WorkMesh& w, TetMesh& mesh, Index t);

}  // namespace qualmesh::detail
