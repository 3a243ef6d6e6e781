// The improvement pass (improve.h; issue 16's last pass, after QUALMESH and extraction, beyond the paper):
// vertex classification, smoothing of sliver vertices within their freedom, and the driver that tries, on each
// tetrahedron below the sliver angle, worst first: cap removal on a CAD input (cap_removal.cpp), flips (flips.cpp),
// smoothing, then an edge split (edge_split.cpp).
// The split is Klingner & Shewchuk's vertex insertion in its simplest form: a tetrahedron with two boundary faces
// on a nearly flat crease (a cylinder's side) is flat whatever its boundary vertices do; splitting its interior edge
// and moving the new vertex into the domain replaces it by two tetrahedra with one boundary face each.
//
// Smoothing follows the non-smooth optimisation of Freitag & Ollivier-Gooch (and Klingner & Shewchuk, 2007): the
// objective is the smallest dihedral angle over the vertex's star; the ascent direction is the point of least norm
// in the convex hull of the gradients of the star's nearly worst tetrahedra (each gradient by central differences,
// projected onto the vertex's line or plane), followed by a line search. Where that finds nothing, deterministic
// pseudo-random trial moves are tried, as CGAL's perturb_mesh_3 does (Sliver_perturber's random perturbation).
// A move is accepted only when the star's smallest angle strictly grows, no more of the star's tetrahedra are
// below the threshold than before, every tetrahedron of the star stays positively oriented (by a margin) and every
// boundary triangle of the star keeps its orientation and its plane. A vertex inside a curved CAD face (OnSurface)
// moves in its tangent plane, each position projected onto the CAD surface (MeshOptions::project_to_boundary) before
// it is judged; its boundary triangles keep their orientation and turn by at most 30 degrees. A vertex inside a
// curved CAD edge (OnCurve) moves the same way along the chord of its two neighbours on the edge, projected onto it.
#include "improve/improve.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "improve/work_mesh.h"

namespace qualmesh::detail {
namespace {

using namespace vec3;

// Newell's normal of a facet (sum over its polygons), unit; zero for a facet without a polygon.
Vec facet_normal(const Plc& plc, const Facet& facet) {
  Vec n{0, 0, 0};
  for (const auto& poly : facet.polygons) {
    if (poly.size() < 3) continue;
    for (std::size_t i = 0; i < poly.size(); ++i) {
      const Point3& p = plc.vertices[poly[i]];
      const Point3& q = plc.vertices[poly[(i + 1) % poly.size()]];
      n[0] += (p[1] - q[1]) * (p[2] + q[2]);
      n[1] += (p[2] - q[2]) * (p[0] + q[0]);
      n[2] += (p[0] - q[0]) * (p[1] + q[1]);
    }
  }
  return unit(n);
}

// Is p on segment ab (strictly between its ends, off its line by at most 1e-9 of its length)?
bool on_segment(const Point3& p, const Point3& a, const Point3& b) {
  const Vec ab = sub(b, a), ap = sub(p, a);
  const double sq = dot(ab, ab);
  if (sq == 0) return false;
  const double t = dot(ap, ab) / sq;
  if (t <= 1e-12 || t >= 1 - 1e-12) return false;
  const Vec c = cross(ab, ap);
  return dot(c, c) <= 1e-18 * sq * sq;
}

// The explicit PLC segments that are no edge of a facet polygon of 3 or more vertices (segments inside facets,
// 2-vertex loops, and segments in the volume): the creases of the boundary faces do not show them.
std::vector<Segment> extra_segments(const Plc& plc) {
  std::vector<Edge2> polygon_edges;
  std::vector<Segment> extra;
  for (const Facet& f : plc.facets)
    for (const auto& poly : f.polygons) {
      if (poly.size() == 2) extra.push_back({poly[0], poly[1], 0});
      if (poly.size() < 3) continue;
      for (std::size_t i = 0; i < poly.size(); ++i)
        polygon_edges.push_back(sorted_edge(poly[i], poly[(i + 1) % poly.size()]));
    }
  std::sort(polygon_edges.begin(), polygon_edges.end());
  for (const Segment& s : plc.segments)
    if (!std::binary_search(polygon_edges.begin(), polygon_edges.end(), sorted_edge(s.a, s.b))) extra.push_back(s);
  return extra;
}

// The vertices of `mesh` whose coordinates are those of a PLC vertex (they stay Fixed). With `cad`, two kinds of
// PLC vertex are surface mesh nodes of the CAD front end and no CAD feature, and are left out:
// - one that appears only alone in facet loops: a node inside a planar face (brep_to_plc.cpp writes a planar face as
//   its polygon with its interior nodes), which may move within its plane like a Steiner point of the facet (pump
//   carter at 22.06: tets below 10 deg 366 -> 271);
// - one on no segment whose loops all belong to facets sharing their marker with another facet: a node inside a
//   curved face, which brep_to_plc.cpp writes as triangle facets all marked with the face's number. It moves on the
//   CAD surface like a Steiner point there (OnSurface).
// - one on exactly two segments that carry one marker > 0: a node inside a CAD edge (brep_to_plc.cpp writes an edge
//   as the chain of its nodes), which moves along the edge (OnSegment on a straight one, OnCurve on a curved one).
//   The ends of each chain are the edge's CAD vertices: there segments of two edges meet (a closed edge's vertex
//   too, where the face's seam meets it; a closed edge without a seam is the exception, its vertex may slide).
// In a PLC from a user such a vertex is one the user placed (a load point): it stays.
std::vector<std::uint8_t> input_vertex_flags(const TetMesh& mesh, const Plc& plc, bool cad) {
  std::vector<std::uint8_t> feature(plc.vertices.size(), cad ? 0 : 1);
  if (cad) {
    std::vector<int> markers;
    for (const Facet& f : plc.facets) markers.push_back(f.marker);
    std::sort(markers.begin(), markers.end());
    const auto shared = [&](int marker) {
      const auto range = std::equal_range(markers.begin(), markers.end(), marker);
      return marker > 0 && range.second - range.first >= 2;
    };
    std::vector<int> segment_count(plc.vertices.size(), 0), edge(plc.vertices.size(), 0);
    std::vector<std::uint8_t> edge_node(plc.vertices.size(), 1);
    for (const Segment& s : plc.segments)
      for (Index v : {s.a, s.b}) {
        if (segment_count[v]++ == 0) edge[v] = s.marker;
        edge_node[v] = edge_node[v] && s.marker > 0 && s.marker == edge[v];
      }
    for (Index v = 0; v < plc.vertices.size(); ++v)
      if (segment_count[v] > 0 && !(edge_node[v] && segment_count[v] == 2)) feature[v] = 1;
    for (const Facet& f : plc.facets)
      if (!shared(f.marker))
        for (const auto& loop : f.polygons)
          if (loop.size() >= 2)
            for (Index v : loop) feature[v] = feature[v] || segment_count[v] == 0;
  }
  std::vector<Point3> input;
  for (Index v = 0; v < plc.vertices.size(); ++v)
    if (feature[v]) input.push_back(plc.vertices[v]);
  std::sort(input.begin(), input.end());
  std::vector<std::uint8_t> flags(mesh.points.size(), 0);
  for (std::size_t v = 0; v < mesh.points.size(); ++v)
    flags[v] = std::binary_search(input.begin(), input.end(), mesh.points[v]) ? 1 : 0;
  return flags;
}

std::vector<std::vector<Index>> faces_per_vertex(const TetMesh& mesh) {
  std::vector<std::vector<Index>> out(mesh.points.size());
  for (Index f = 0; f < mesh.faces.size(); ++f)
    for (Index v : mesh.faces[f]) out[v].push_back(f);
  return out;
}

}  // namespace

double oriented_min_dihedral_deg(const Point3& p0, const Point3& p1, const Point3& p2, const Point3& p3) {
  const double six_vol = 6 * tet_signed_volume(p0, p1, p2, p3);
  const Point3* p[4] = {&p0, &p1, &p2, &p3};
  double sq_long = 0;
  for (int a = 0; a < 4; ++a)
    for (int b = a + 1; b < 4; ++b) {
      const Vec e = sub(*p[a], *p[b]);
      sq_long = std::max(sq_long, dot(e, e));
    }
  if (!(six_vol > 1e-13 * sq_long * std::sqrt(sq_long))) return -1;
  return tet_min_dihedral_deg(p0, p1, p2, p3);
}

std::vector<VertexConstraint> classify_vertices(const TetMesh& mesh, const Plc& plc, bool curved) {
  const std::size_t nv = mesh.points.size();
  std::vector<VertexConstraint> out(nv);
  const std::vector<std::uint8_t> is_input = input_vertex_flags(mesh, plc, curved);
  const std::vector<std::vector<Index>> vfaces = faces_per_vertex(mesh);
  std::vector<Vec> normals;
  normals.reserve(plc.facets.size());
  for (const Facet& f : plc.facets) normals.push_back(facet_normal(plc, f));
  const std::vector<Segment> extra = extra_segments(plc);
  std::vector<std::vector<Index>> marked(nv);  // neighbours along marked TetMesh edges
  std::vector<std::vector<int>> marked_edge(nv);  // and those edges' markers (when the mesh has them)
  const bool edge_markers = mesh.edge_marker.size() == mesh.edges.size();
  for (std::size_t e = 0; e < mesh.edges.size(); ++e)
    for (int end = 0; end < 2; ++end) {
      marked[mesh.edges[e][end]].push_back(mesh.edges[e][1 - end]);
      if (edge_markers) marked_edge[mesh.edges[e][end]].push_back(mesh.edge_marker[e]);
    }
  struct Link {
    Index q;
    int count;
    int facet;
    bool mixed;
  };
  std::vector<Link> links;
  std::vector<Index> creases;
  for (Index v = 0; v < nv; ++v) {
    VertexConstraint& c = out[v];
    if (is_input[v]) continue;  // Fixed
    const Point3& p = mesh.points[v];
    // An explicit segment off the facet polygons holding v: along it.
    bool on_extra = false;
    for (const Segment& s : extra)
      if (on_segment(p, plc.vertices[s.a], plc.vertices[s.b])) {
        c = {VertexFreedom::OnSegment, unit(sub(plc.vertices[s.b], plc.vertices[s.a]))};
        on_extra = true;
        break;
      }
    if (on_extra) continue;
    const auto& faces = vfaces[v];
    if (faces.empty() && marked[v].empty()) {
      c.freedom = VertexFreedom::Interior;
      continue;
    }
    // The edges (v, q) of v's boundary faces: a crease when it is not shared by exactly two faces of one facet.
    links.clear();
    for (Index f : faces) {
      const int facet = mesh.face_facet.empty() ? -1 : mesh.face_facet[f];
      for (Index q : mesh.faces[f]) {
        if (q == v) continue;
        auto it = std::find_if(links.begin(), links.end(), [&](const Link& l) { return l.q == q; });
        if (it == links.end()) {
          links.push_back({q, 1, facet, false});
        } else {
          ++it->count;
          it->mixed = it->mixed || it->facet != facet;
        }
      }
    }
    creases.clear();
    for (const Link& l : links)
      if (l.count != 2 || l.mixed) creases.push_back(l.q);
    for (Index q : marked[v])
      if (std::find(creases.begin(), creases.end(), q) == creases.end()) creases.push_back(q);
    if (creases.empty()) {
      // One facet (or one unlabelled interface) around v: within its plane, if every face lies in it.
      const int facet = mesh.face_facet.empty() ? -1 : mesh.face_facet[faces[0]];
      bool one = true;
      for (Index f : faces) one = one && (mesh.face_facet.empty() ? -1 : mesh.face_facet[f]) == facet;
      const auto& f0 = mesh.faces[faces[0]];
      const Vec own = unit(face_normal(mesh.points[f0[0]], mesh.points[f0[1]], mesh.points[f0[2]]));
      const Vec n = facet >= 0 && std::size_t(facet) < normals.size() ? normals[facet] : own;
      if (!one || norm(n) == 0) continue;
      bool planar = true;
      for (Index f : faces) {
        const auto& t = mesh.faces[f];
        const Vec fn = face_normal(mesh.points[t[0]], mesh.points[t[1]], mesh.points[t[2]]);
        planar = planar && norm(cross(fn, n)) <= 1e-7 * norm(fn);
      }
      if (planar) c = {VertexFreedom::InFacet, n};
      continue;
    }
    if (creases.size() == 2) {
      const Vec d1 = sub(mesh.points[creases[0]], p), d2 = sub(mesh.points[creases[1]], p);
      if (dot(d1, d2) < 0 && norm(cross(d1, d2)) <= 1e-9 * norm(d1) * norm(d2))
        c = {VertexFreedom::OnSegment, unit(sub(mesh.points[creases[1]], mesh.points[creases[0]]))};
    }
  }
  if (!curved) return out;
  // Inside one curved CAD edge: two marked edges with one marker. (Where the edge is straight, the crease test above
  // made it OnSegment already.)
  for (Index v = 0; edge_markers && v < nv; ++v) {
    if (out[v].freedom != VertexFreedom::Fixed || is_input[v] || marked[v].size() != 2) continue;
    const int edge = marked_edge[v][0];
    const Vec d = unit(sub(mesh.points[marked[v][1]], mesh.points[marked[v][0]]));
    if (edge > 0 && marked_edge[v][1] == edge && norm(d) > 0) out[v] = {VertexFreedom::OnCurve, d, 0, edge};
  }
  if (mesh.face_marker.size() != mesh.faces.size()) return out;
  for (Index v = 0; v < nv; ++v) {
    const auto& faces = vfaces[v];
    if (out[v].freedom != VertexFreedom::Fixed || is_input[v] || faces.empty() || !marked[v].empty()) continue;
    // Inside one CAD face: every incident face has its marker.
    const int face = mesh.face_marker[faces[0]];
    Vec n{0, 0, 0}, first{0, 0, 0};
    bool one = face > 0;
    for (Index f : faces) {
      const auto& t = mesh.faces[f];
      Vec fn = face_normal(mesh.points[t[0]], mesh.points[t[1]], mesh.points[t[2]]);
      if (norm(first) == 0) first = fn;
      if (dot(fn, first) < 0) fn = scale(fn, -1);  // whatever the faces' orientation, one side
      n = add(n, fn);
      one = one && mesh.face_marker[f] == face;
    }
    if (one && norm(n) > 0) out[v] = {VertexFreedom::OnSurface, unit(n), face};
  }
  return out;
}

namespace {

// Smoothing of one vertex within its freedom (see the file comment). Returns whether it moved.
class Smoother {
 public:
  Smoother(WorkMesh& w, const TetMesh& mesh, double threshold,
           const std::function<bool(int, int, Point3&)>& project_to_boundary)
      : w_(w), mesh_(mesh), threshold_(threshold), project_to_boundary_(project_to_boundary) {}

  bool smooth(Index v, const VertexConstraint& c, unsigned round) {
    v_ = v;
    c_ = c;
    star_ = w_.incident[v];
    if (star_.empty() || c.freedom == VertexFreedom::Fixed) return false;
    const Point3 start = w_.point(v);
    sq_len_ = std::numeric_limits<double>::infinity();
    for (Index t : star_)
      for (Index x : w_.tets[t])
        if (x != v) {
          const Vec e = sub(w_.point(x), start);
          sq_len_ = std::min(sq_len_, dot(e, e));
        }
    len_ = std::sqrt(sq_len_);
    old_normals_.clear();
    for (Index f : w_.vertex_faces[v]) {
      const auto& t = mesh_.faces[f];
      old_normals_.push_back(face_normal(w_.point(t[0]), w_.point(t[1]), w_.point(t[2])));
    }
    old_max_rho_ = 0;
    if (w_.rho_bound > 0)
      for (Index t : star_) old_max_rho_ = std::max(old_max_rho_, w_.radius_edge(t));
    Point3 p = start;
    order_.clear();
    for (Index t : star_) order_.push_back({tet_quality_at(t, start), t});
    std::sort(order_.begin(), order_.end());
    max_below_ = star_.size();
    double q = star_min(p);
    // No move may leave more tetrahedra of the star below the threshold than before.
    max_below_ = 0;
    for (const auto& [qt, t] : order_) max_below_ += qt < threshold_;
    const double q_start = q;
    for (int iter = 0; iter < 30; ++iter) {
      Point3 next;
      const double qn = ascent_step(p, q, next);
      if (!(qn > q + 1e-7)) break;
      p = next;
      q = qn;
    }
    if (!(q > q_start + 1e-7)) {
      // Deterministic trial moves (a small linear congruential generator seeded by the vertex and the round).
      std::uint64_t state = (std::uint64_t(v) + 1) * 0x9E3779B97F4A7C15ull + round * 0xBF58476D1CE4E5B9ull;
      auto next01 = [&]() {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        return double(state >> 11) * (1.0 / 9007199254740992.0);
      };
      for (int trial = 0; trial < 24; ++trial) {
        Vec d{next01() - 0.5, next01() - 0.5, next01() - 0.5};
        d = unit(project(d));
        if (norm(d) == 0) continue;
        for (double s : {0.1, 0.03, 0.01}) {
          Point3 cand = add(p, scale(d, s * len_));
          const double qc = try_candidate(cand, q + 1e-7);
          if (qc > q + 1e-7) p = cand, q = qc;
        }
      }
    }
    if (!(q > q_start + 1e-7)) return false;
    (*w_.points)[v] = p;
    for (Index t : star_) w_.touched[t] = 1;
    return true;
  }

 private:
  bool on_cad() const { return c_.freedom == VertexFreedom::OnSurface || c_.freedom == VertexFreedom::OnCurve; }

  // A point of the vertex's line, plane, tangent plane or tangent made a position it may take: on its CAD surface
  // for OnSurface, on its CAD curve for OnCurve (false when the projection fails), as it is otherwise.
  bool place(Point3& cand) const {
    if (c_.freedom == VertexFreedom::OnCurve) return project_to_boundary_(c_.cad_edge, 0, cand);
    return !on_cad() || project_to_boundary_(0, c_.cad_face, cand);
  }

  // The star's smallest angle at candidate `cand` (star_min), with `cand` first made a position the vertex may take
  // (place); -1 when it cannot be. OpenCASCADE's projection costs far more than the star: a candidate of a CAD vertex
  // whose tangent point does not beat `bound` is dropped unprojected (the surface is within the square of the step
  // of its tangent plane there, and most random trials fail by far), so only promising ones are projected and judged.
  double try_candidate(Point3& cand, double bound) const {
    if (on_cad() && !(star_min(cand, bound) > bound)) return -1;
    return place(cand) ? star_min(cand, bound) : -1;
  }

  Vec project(const Vec& g) const {
    switch (c_.freedom) {
      case VertexFreedom::Interior: return g;
      case VertexFreedom::InFacet:
      case VertexFreedom::OnSurface: return sub(g, scale(c_.direction, dot(g, c_.direction)));
      case VertexFreedom::OnSegment:
      case VertexFreedom::OnCurve: return scale(c_.direction, dot(g, c_.direction));
      case VertexFreedom::Fixed: break;
    }
    return {0, 0, 0};
  }

  double tet_quality_at(Index t, const Point3& p) const {
    Point3 q[4];
    for (int k = 0; k < 4; ++k) q[k] = w_.tets[t][k] == v_ ? p : w_.point(w_.tets[t][k]);
    return oriented_min_dihedral_deg(q[0], q[1], q[2], q[3]);
  }

  bool rho_allowed_at(Index t, const Point3& p) const {
    Point3 q[4];
    for (int k = 0; k < 4; ++k) q[k] = w_.tets[t][k] == v_ ? p : w_.point(w_.tets[t][k]);
    return w_.rho_allowed(w_.tets[t], q, old_max_rho_);
  }

  // The star's smallest angle with v at p; -1 when a tetrahedron or a boundary triangle would fold. A candidate is
  // kept only when this beats `bound`: so the star's tets are measured worst first (as they were at the start),
  // and the first at or below `bound` ends the evaluation with its angle (a move rejected either way).
  double star_min(const Point3& p, double bound = -1) const {
    for (std::size_t k = 0; k < old_normals_.size(); ++k) {
      const auto& t = mesh_.faces[w_.vertex_faces[v_][k]];
      const Point3 a = t[0] == v_ ? p : w_.point(t[0]), b = t[1] == v_ ? p : w_.point(t[1]),
                   c = t[2] == v_ ? p : w_.point(t[2]);
      // Same orientation, and (a safety net for conformity) the same plane: the normal keeps its direction. On a
      // curved surface the face turns with it: there its normal may turn by up to 30 degrees.
      const Vec n = face_normal(a, b, c), &o = old_normals_[k];
      if (!(dot(n, o) > 1e-6 * dot(o, o))) return -1;
      if (on_cad()) {
        if (!(dot(n, o) > 0.866 * norm(n) * norm(o))) return -1;
      } else if (!(dot(cross(n, o), cross(n, o)) <= 1e-16 * dot(n, n) * dot(o, o))) {
        return -1;
      }
    }
    double q = std::numeric_limits<double>::infinity();
    std::size_t below = 0;
    for (const auto& [q0, t] : order_) {
      const double qt = tet_quality_at(t, p);
      if (qt < 0) return -1;
      if (qt <= bound) return qt;
      if (!rho_allowed_at(t, p)) return -1;
      q = std::min(q, qt);
      below += qt < threshold_;
    }
    return below > max_below_ ? -1 : q;
  }

  // One ascent step from p (star quality q): returns the quality reached and the point in `out`.
  double ascent_step(const Point3& p, double q, Point3& out) const {
    std::vector<Vec> grads;
    const double h = 1e-4 * len_;
    for (Index t : star_) {
      const double qt = tet_quality_at(t, p);
      if (qt > q + 0.5) continue;
      Vec g{0, 0, 0};
      for (int k = 0; k < 3; ++k) {
        Point3 a = p, b = p;
        a[k] += h;
        b[k] -= h;
        g[k] = (tet_quality_at(t, a) - tet_quality_at(t, b)) / (2 * h);
      }
      grads.push_back(project(g));
    }
    if (grads.empty()) return q;
    // The point of least norm in the convex hull of the gradients (Frank-Wolfe / Gilbert's iteration).
    Vec x = grads[0];
    for (int it = 0; it < 64; ++it) {
      std::size_t best = 0;
      for (std::size_t i = 1; i < grads.size(); ++i)
        if (dot(x, grads[i]) < dot(x, grads[best])) best = i;
      const Vec diff = sub(grads[best], x);
      const double sq = dot(diff, diff);
      if (sq == 0 || dot(x, x) - dot(x, grads[best]) <= 1e-12 * dot(x, x)) break;
      const double lambda = std::clamp(-dot(x, diff) / sq, 0.0, 1.0);
      x = add(x, scale(diff, lambda));
    }
    // Opposed gradients cancel: then x is rounding noise that need not even lie in the vertex's line or plane.
    double sq_largest = 0;
    for (const Vec& g : grads) sq_largest = std::max(sq_largest, dot(g, g));
    if (!(dot(x, x) > 1e-16 * sq_largest)) return q;
    const Vec d = unit(project(x));
    if (norm(d) == 0) return q;
    double best_q = q;
    for (double s = 0.2; s > 1e-4; s *= 0.5) {
      Point3 cand = add(p, scale(d, s * len_));
      const double qc = try_candidate(cand, best_q);
      if (qc > best_q) best_q = qc, out = cand;
    }
    return best_q;
  }

  WorkMesh& w_;
  const TetMesh& mesh_;
  Index v_ = 0;
  VertexConstraint c_;
  std::vector<Index> star_;
  std::vector<std::pair<double, Index>> order_;  // the star's tets, worst first at the start of smooth()
  std::vector<Vec> old_normals_;
  double sq_len_ = 0, len_ = 0;
  double threshold_;
  const std::function<bool(int, int, Point3&)>& project_to_boundary_;
  double old_max_rho_ = 0;  // the star's largest radius-edge ratio before the move (the guard's cap)
  std::size_t max_below_ = 0;
};

double mesh_min_dihedral(const TetMesh& mesh, double threshold, std::size_t* below) {
  double q = mesh.tets.empty() ? 0 : 180;
  *below = 0;
  for (const auto& t : mesh.tets) {
    const double a = tet_min_dihedral_deg(mesh.points[t[0]], mesh.points[t[1]], mesh.points[t[2]], mesh.points[t[3]]);
    q = std::min(q, a);
    if (a < threshold) ++*below;
  }
  return q;
}

// extract.cpp's canonical order of a tet: its smallest id first by an even permutation.
Tet4 canonical(Tet4 v) {
  const int m = int(std::min_element(v.begin(), v.end()) - v.begin());
  if (m == 1) v = {v[1], v[0], v[3], v[2]};
  else if (m == 2) v = {v[2], v[3], v[0], v[1]};
  else if (m == 3) v = {v[3], v[2], v[1], v[0]};
  return v;
}

}  // namespace

ImproveResult improve_mesh(TetMesh& mesh, const Plc& plc, const ImproveOptions& options,
                           std::vector<std::uint8_t>* touches_acute,
                           const std::function<bool(Index, Index)>& shortest_edge_forced) {
  ImproveResult res;
  const double threshold = options.sliver_angle_deg;
  res.min_dihedral_before_deg = mesh_min_dihedral(mesh, threshold, &res.num_below_before);
  res.min_dihedral_after_deg = res.min_dihedral_before_deg;
  res.num_below_after = res.num_below_before;
  if (res.num_below_before == 0) return res;

  std::vector<VertexConstraint> constraints = classify_vertices(mesh, plc, bool(options.project_to_boundary));
  for (const VertexConstraint& c : constraints) {
    res.num_fixed += c.freedom == VertexFreedom::Fixed;
    res.num_on_segment += c.freedom == VertexFreedom::OnSegment;
    res.num_in_facet += c.freedom == VertexFreedom::InFacet;
    res.num_on_surface += c.freedom == VertexFreedom::OnSurface;
    res.num_on_curve += c.freedom == VertexFreedom::OnCurve;
    res.num_interior += c.freedom == VertexFreedom::Interior;
  }
  WorkMesh w;
  w.points = &mesh.points;
  w.faces = &mesh.faces;
  w.rho_bound = options.radius_edge_bound;
  w.edge_forced = shortest_edge_forced;
  w.tets = mesh.tets;
  w.region = mesh.tet_region.empty() ? std::vector<int>(mesh.tets.size(), 0) : mesh.tet_region;
  w.alive.assign(mesh.tets.size(), 1);
  w.touched.assign(mesh.tets.size(), 0);
  w.incident.assign(mesh.points.size(), {});
  for (Index t = 0; t < w.tets.size(); ++t)
    for (Index v : w.tets[t]) w.incident[v].push_back(t);
  w.vertex_faces = faces_per_vertex(mesh);
  for (const auto& e : mesh.edges) w.protected_edges.push_back(sorted_edge(e[0], e[1]));
  {
    // Edges along explicit segments off the facet polygons (their vertices are OnSegment or input vertices).
    const std::vector<Segment> extra = extra_segments(plc);
    if (!extra.empty())
      for (const Tet4& t : w.tets)
        for (int a = 0; a < 4; ++a)
          for (int b = a + 1; b < 4; ++b)
            for (const Segment& s : extra) {
              const Point3 &pa = plc.vertices[s.a], &pb = plc.vertices[s.b];
              auto on = [&](Index x) {
                return mesh.points[x] == pa || mesh.points[x] == pb || on_segment(mesh.points[x], pa, pb);
              };
              if (on(t[a]) && on(t[b])) w.protected_edges.push_back(sorted_edge(t[a], t[b]));
            }
  }
  std::sort(w.protected_edges.begin(), w.protected_edges.end());
  w.protected_edges.erase(std::unique(w.protected_edges.begin(), w.protected_edges.end()), w.protected_edges.end());

  std::vector<Vec> facet_normals;
  facet_normals.reserve(plc.facets.size());
  for (const Facet& f : plc.facets) facet_normals.push_back(facet_normal(plc, f));
  Smoother smoother(w, mesh, threshold, options.project_to_boundary);
  std::vector<std::uint8_t> moved(mesh.points.size(), 0);
  bool stop = false;
  for (int round = 0; round < options.max_rounds && !stop; ++round) {
    std::vector<std::pair<double, Index>> bad;
    for (Index t = 0; t < w.tets.size(); ++t) {
      if (!w.alive[t]) continue;
      const double q = w.quality(t);
      if (q < threshold) bad.push_back({q, t});
    }
    std::sort(bad.begin(), bad.end());
    std::size_t changes = 0;
    const auto round_start = std::chrono::steady_clock::now();
    for (const auto& [q0, t] : bad) {
      if (options.cancel && options.cancel()) {
        stop = true;
        break;
      }
      if (!w.alive[t] || w.quality(t) >= threshold) continue;
      if (options.cap_removal && options.project_to_boundary && remove_cap(w, mesh, t)) {
        ++changes;
        ++res.num_caps_removed;
        continue;
      }
      const int kind = options.flips ? flip_to_remove(w, t, options.max_edge_ring) : 0;
      if (kind != 0) {
        ++changes;
        ++res.num_flips;
        if (kind == 1) ++res.num_flips23;
        else ++res.num_edge_removals;
        continue;
      }
      const Tet4 tv = w.tets[t];
      if (options.smoothing)
        for (Index v : tv) {
          if (!smoother.smooth(v, constraints[v], unsigned(round))) continue;
          ++changes;
          ++res.num_vertex_moves;
          moved[v] = 1;
          if (w.quality(t) >= threshold) break;
        }
      if (!options.insertion || !w.alive[t] || w.quality(t) >= threshold) continue;
      for (int a = 0; a < 4; ++a)
        for (int b = a + 1; b < 4; ++b)
          if (bool boundary = false;
              w.alive[t] && split_edge(w, mesh, facet_normals, constraints, tv[a], tv[b], options.boundary_insertion,
                                       threshold, [&](Index m) { smoother.smooth(m, constraints[m], unsigned(round)); },
                                       &boundary)) {
            ++changes;
            ++res.num_insertions;
            res.num_boundary_insertions += boundary;
            moved.push_back(0);
          }
    }
    if (options.log) {
      const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - round_start).count();
      options.log("improve round " + std::to_string(round + 1) + ": " + std::to_string(bad.size()) +
                  " tets below the threshold (min " + std::to_string(bad.empty() ? threshold : bad[0].first) +
                  " deg), " + std::to_string(changes) + " changes, " + std::to_string(seconds) + " s");
    }
    if (changes == 0) break;
  }
  for (std::uint8_t m : moved) res.num_vertices_moved += m;

  // Write the tetrahedra back: in place when no flip happened, else alive ones in extract.cpp's canonical order.
  struct Out {
    Tet4 v;
    int region;
    std::uint8_t acute, touched;
  };
  std::vector<Out> out;
  out.reserve(w.tets.size());
  const bool have_acute = touches_acute && touches_acute->size() == mesh.tets.size();
  for (Index t = 0; t < w.tets.size(); ++t) {
    if (!w.alive[t]) continue;
    Out o{w.tets[t], w.region[t], 0, w.touched[t]};
    if (!o.touched && have_acute) {
      o.acute = (*touches_acute)[t];
    } else if (shortest_edge_forced) {
      const Point3 p[4] = {mesh.points[o.v[0]], mesh.points[o.v[1]], mesh.points[o.v[2]], mesh.points[o.v[3]]};
      const Edge2 e = shortest_edge(p);
      o.acute = shortest_edge_forced(o.v[e[0]], o.v[e[1]]) ? 1 : 0;
    }
    out.push_back(o);
  }
  if (!mesh.weights.empty()) mesh.weights.resize(mesh.points.size(), 0.0);
  if (res.num_flips > 0 || res.num_insertions > 0 || res.num_caps_removed > 0) {
    for (Out& o : out) o.v = canonical(o.v);
    std::sort(out.begin(), out.end(), [](const Out& a, const Out& b) { return a.v < b.v; });
  }
  const bool had_regions = !mesh.tet_region.empty();
  mesh.tets.clear();
  mesh.tet_region.clear();
  if (touches_acute) touches_acute->clear();
  for (const Out& o : out) {
    mesh.tets.push_back(o.v);
    if (had_regions) mesh.tet_region.push_back(o.region);
    if (touches_acute) touches_acute->push_back(o.acute);
    res.num_tets_touched += o.touched;
  }
  res.min_dihedral_after_deg = mesh_min_dihedral(mesh, threshold, &res.num_below_after);
  return res;
}

}  // namespace qualmesh::detail
