// Edge splits of the improvement pass (improve.h; beyond the paper, after QUALMESH), Klingner & Shewchuk's vertex
// insertion in its simplest form: where flips and smoothing leave a tetrahedron below the sliver angle, one of its
// edges is split at its midpoint and the new vertex smoothed within its freedom. The split is kept only when the
// smallest angle of the tets around the edge grows, else undone completely (the point is removed again). A free
// vertex whose midpoint start is itself bad (a flat half inverted, or beyond the radius-edge guard) starts again
// towards the centroid of the edge's ring.
//   - An interior edge of one region (no constraint face holds it, its ring closes, not protected): the new vertex is
//     free (Klingner & Shewchuk's vertex insertion).
//   - With `boundary` (ImproveOptions::boundary_insertion), also an edge inside one planar input facet: exactly two
//     constraint faces hold it, both of that facet and in its plane, and it is on no segment (not protected). The new
//     vertex lies on the facet (InFacet), both faces are split in two with the facet's id and marker, and each
//     tetrahedron keeps its region, so the facet stays the union of its faces and conformity stays exact. This is
//     issue 16's sliver-removing point on the boundary (a Rule 2-style split of the subfacets under a boundary
//     sliver), used only where the weighted framework left the sliver.
#include <algorithm>
#include <limits>

#include "improve/work_mesh.h"

namespace qualmesh::detail {
namespace {

using namespace vec3;

// The constraint faces (indices into TetMesh::faces) holding the edge uv.
std::vector<Index> faces_on_edge(const WorkMesh& w, const TetMesh& mesh, Index u, Index v) {
  std::vector<Index> out;
  for (Index f : w.vertex_faces[u]) {
    const auto& t = mesh.faces[f];
    if (t[0] == v || t[1] == v || t[2] == v) out.push_back(f);
  }
  return out;
}


// The faces of `on_edge` (each holding edge uv) split at the new vertex m: face f keeps its index with v replaced by
// m, and its other half (u replaced by m) is appended with f's facet and marker. Bookkeeping: WorkMesh's
// vertex-to-face lists (which also answer is_constraint_face). `undo` restores everything (the halves are dropped
// again).
class FaceSplit {
 public:
  FaceSplit(WorkMesh& w, TetMesh& mesh, std::vector<Index> on_edge, Index u, Index v, Index m)
      : w_(w), mesh_(mesh), on_edge_(std::move(on_edge)), u_(u), v_(v), m_(m), first_(mesh.faces.size()) {
    for (Index f : on_edge_) {
      const auto old = mesh.faces[f];
      auto a = old, b = old;
      for (int k = 0; k < 3; ++k) {
        if (a[k] == v) a[k] = m;
        if (b[k] == u) b[k] = m;
      }
      const Index half = Index(mesh.faces.size());
      mesh.faces[f] = a;
      mesh.faces.push_back(b);
      mesh.face_facet.push_back(mesh.face_facet[f]);
      if (!mesh.face_marker.empty()) mesh.face_marker.push_back(mesh.face_marker[f]);
      replace_in(w.vertex_faces[v], f, half);
      for (Index x : old)
        if (x != u && x != v) w.vertex_faces[x].push_back(half);
      w.vertex_faces[m].push_back(f);
      w.vertex_faces[m].push_back(half);
    }
  }
  void undo() {
    for (std::size_t i = 0; i < on_edge_.size(); ++i) {
      const Index f = on_edge_[i], half = Index(first_ + i);
      auto old = mesh_.faces[f];
      for (Index& x : old)
        if (x == m_) x = v_;
      replace_in(w_.vertex_faces[v_], half, f);
      for (Index x : old)
        if (x != u_ && x != v_) {
          auto& list = w_.vertex_faces[x];
          list.erase(std::find(list.begin(), list.end(), half));
        }
      mesh_.faces[f] = old;
    }
    mesh_.faces.resize(first_);
    mesh_.face_facet.resize(first_);
    if (!mesh_.face_marker.empty()) mesh_.face_marker.resize(first_);
  }

 private:
  WorkMesh& w_;
  TetMesh& mesh_;
  std::vector<Index> on_edge_;
  Index u_, v_, m_;
  std::size_t first_;
};

}  // namespace

bool split_edge(WorkMesh& w, TetMesh& mesh, const std::vector<Point3>& facet_normals,
                std::vector<VertexConstraint>& constraints, Index u, Index v, bool boundary, double threshold,
                const std::function<void(Index)>& smooth, bool* on_boundary) {
  if (w.is_protected_edge(u, v)) return false;
  std::vector<Index> on_edge = faces_on_edge(w, mesh, u, v);
  Vec normal{0, 0, 0};
  if (!on_edge.empty()) {
    if (!boundary || on_edge.size() != 2 || mesh.face_facet.size() != mesh.faces.size()) return false;
    const int facet = mesh.face_facet[on_edge[0]];
    if (facet < 0 || facet != mesh.face_facet[on_edge[1]] || std::size_t(facet) >= facet_normals.size()) return false;
    normal = facet_normals[facet];
    if (norm(normal) == 0) return false;
    for (Index f : on_edge) {
      const auto& t = mesh.faces[f];
      const Vec fn = face_normal(w.point(t[0]), w.point(t[1]), w.point(t[2]));
      if (!(norm(cross(fn, normal)) <= 1e-7 * norm(fn))) return false;
    }
  }
  std::vector<Index> around;
  w.tets_around_edge(u, v, around);
  if (around.size() < (on_edge.empty() ? 3u : 1u)) return false;
  std::vector<Index> ring;
  double old_min = std::numeric_limits<double>::infinity(), old_max_rho = 0;
  std::size_t old_below = 0;
  for (Index t : around) {
    if (on_edge.empty() && w.region[t] != w.region[around[0]]) return false;
    const double q = w.quality(t);
    old_min = std::min(old_min, q);
    old_below += q < threshold;
    if (w.rho_bound > 0) old_max_rho = std::max(old_max_rho, w.radius_edge(t));
    for (Index x : w.tets[t])
      if (x != u && x != v) ring.push_back(x);
  }
  // A closed ring: every ring vertex in exactly two tets around the edge; on the hull, the ring is open at the
  // third vertices of the two faces holding the edge, which are in one tet each.
  std::sort(ring.begin(), ring.end());
  std::size_t open_ends = 0;
  for (std::size_t i = 0; i < ring.size();) {
    std::size_t j = i;
    while (j < ring.size() && ring[j] == ring[i]) ++j;
    if (j - i == 1) {
      bool end_of_face = false;
      for (Index f : on_edge)
        for (Index x : mesh.faces[f]) end_of_face = end_of_face || x == ring[i];
      if (!end_of_face) return false;
      ++open_ends;
    } else if (j - i != 2) {
      return false;
    }
    i = j;
  }
  if (open_ends != 0 && open_ends != 2) return false;
  const Point3 &pu = w.point(u), &pv = w.point(v);
  const Index m = Index(w.points->size());
  w.points->push_back({(pu[0] + pv[0]) / 2, (pu[1] + pv[1]) / 2, (pu[2] + pv[2]) / 2});
  w.incident.emplace_back();
  w.vertex_faces.emplace_back();
  constraints.push_back(on_edge.empty() ? VertexConstraint{VertexFreedom::Interior, {0, 0, 0}}
                                        : VertexConstraint{VertexFreedom::InFacet, unit(normal)});
  FaceSplit faces(w, mesh, on_edge, u, v, m);
  const std::size_t first_new = w.tets.size();
  for (Index t : around) {
    w.kill_tet(t);
    Tet4 a = w.tets[t], b = w.tets[t];
    for (int k = 0; k < 4; ++k) {
      if (a[k] == u) a[k] = m;
      if (b[k] == v) b[k] = m;
    }
    w.add_tet(a, w.region[t]);
    w.add_tet(b, w.region[t]);
  }
  // The split with m starting at `start`, then smoothed: whether it is kept (positive tets, the radius-edge guard,
  // a better smallest angle and, with `no_more_below`, no more tets below `threshold` than around the edge before:
  // the smoother's rule). *bad_start: a new tet was not positive, or failed the guard, at `start`.
  const auto attempt = [&](const Point3& start, bool no_more_below, bool* bad_start) {
    (*w.points)[m] = start;
    *bad_start = false;
    for (std::size_t t = first_new; t < w.tets.size(); ++t) {
      if (!(w.quality(Index(t)) >= 0)) {
        *bad_start = true;
        return false;
      }
      *bad_start = *bad_start || !w.rho_allowed(w.tets[t], old_max_rho);
    }
    smooth(m);
    double new_min = std::numeric_limits<double>::infinity();
    std::size_t new_below = 0;
    for (std::size_t t = first_new; t < w.tets.size(); ++t) {
      const double q = w.quality(Index(t));
      new_min = std::min(new_min, q);
      new_below += q < threshold;
      if (!w.rho_allowed(w.tets[t], old_max_rho)) return false;
    }
    return new_min > old_min + 1e-9 && (!no_more_below || new_below <= old_below);
  };
  const Point3 mid = (*w.points)[m];
  bool bad_start = false;
  bool kept = attempt(mid, false, &bad_start);
  if (!kept && bad_start && on_edge.empty()) {
    // The midpoint of an edge of a flat tetrahedron makes two flat halves, which can be inverted by rounding or too
    // flat for the radius-edge guard to let the smoother take the first small steps out of them (fandisk.off: a
    // 0.108-degree tet whose four corners are input vertices, at a noise fold beside a wall, the one tet below 15
    // degrees the pass left). A free vertex may start anywhere inside the kernel of the edge's star: it starts
    // again from points towards the centroid of the ring.
    Point3 centroid{0, 0, 0};
    for (Index x : ring)
      for (int k = 0; k < 3; ++k) centroid[k] += w.point(x)[k] / double(ring.size());
    for (const double t : {0.5, 1.0}) {
      if (kept) break;
      kept = attempt({mid[0] + t * (centroid[0] - mid[0]), mid[1] + t * (centroid[1] - mid[1]),
                      mid[2] + t * (centroid[2] - mid[2])},
                     true, &bad_start);
    }
  }
  if (kept) {
    *on_boundary = !on_edge.empty();
    return true;
  }
  // Undo: the new tets go (their ids stay dead), the old ones come back, the faces are joined, the point is removed.
  for (std::size_t t = first_new; t < w.tets.size(); ++t) w.kill_tet(Index(t));
  w.tets.resize(first_new);
  w.region.resize(first_new);
  w.alive.resize(first_new);
  w.touched.resize(first_new);
  for (Index t : around) w.revive_tet(t);
  faces.undo();
  w.points->pop_back();
  w.incident.pop_back();
  w.vertex_faces.pop_back();
  constraints.pop_back();
  return false;
}

}  // namespace qualmesh::detail
