// Cap removal of the improvement pass (improve.h; beyond the paper, after QUALMESH): a tetrahedron below the sliver
// angle whose two boundary faces lie on one CAD face is a cap, the flat tet between the two ways of
// triangulating the quadrilateral of its four boundary vertices. No vertex move widens it (its four vertices stay on
// the surface), and an edge split only halves it. Removing it flips the boundary edge ab its two faces share to the
// other diagonal cd: its two other faces become the boundary, every node stays on its CAD face, and the boundary is
// still a mesh of the same CAD faces (as for ImproveOptions::project_to_boundary's moves, the mesh there is fitted to
// the CAD surface, not to the PLC's chords). The volume changes by the cap's own. On a planar CAD face the cap is flat
// and the new faces stay in the plane.
//
// Only with ImproveOptions::project_to_boundary (a CAD input), and only where nothing else changes:
//   - both faces are hull faces (no tet across them: no region on the other side), of one CAD face (marker > 0);
//   - ab is no CAD edge (not protected) and no other tet holds it, so it leaves the mesh;
//   - cd is on no boundary face, and each of the new faces acd, bcd has a tet across it, which keeps its vertices;
//   - the surface stays smooth there: the old faces' normals are within kMaxTurnDeg of each other and of the new
//     faces' normals, and the new faces' smallest angle is at least half the old faces'.
#include <algorithm>
#include <cmath>

#include "improve/work_mesh.h"

namespace qualmesh::detail {
namespace {

using namespace vec3;

constexpr double kMaxTurnDeg = 30;

// The alive tets holding face abc.
std::vector<Index> tets_with_face(const WorkMesh& w, Index a, Index b, Index c) {
  std::vector<Index> out;
  for (Index t : w.incident[a]) {
    int n = 0;
    for (Index x : w.tets[t]) n += (x == b || x == c);
    if (n == 2) out.push_back(t);
  }
  return out;
}

double min_angle_deg(const Point3& a, const Point3& b, const Point3& c) {
  const Point3* p[3] = {&a, &b, &c};
  double best = 180;
  for (int k = 0; k < 3; ++k) {
    const Vec u = sub(*p[(k + 1) % 3], *p[k]), v = sub(*p[(k + 2) % 3], *p[k]);
    best = std::min(best, std::atan2(norm(cross(u, v)), dot(u, v)) * 180 / M_PI);
  }
  return best;
}

// Face (x, y, z) oriented so that its normal points towards `towards` (out of the domain once the cap is gone).
Face3 oriented(const WorkMesh& w, Index x, Index y, Index z, Index towards) {
  const Vec n = face_normal(w.point(x), w.point(y), w.point(z));
  return dot(n, sub(w.point(towards), w.point(x))) > 0 ? Face3{x, y, z} : Face3{x, z, y};
}

// Boundary face f (an index into TetMesh::faces) becomes `to`: the vertex-to-face lists follow
// (`leaving` drops f, `joining` gets it).
void replace_face(WorkMesh& w, TetMesh& mesh, Index f, const Face3& to, Index leaving, Index joining) {
  mesh.faces[f] = to;
  auto& list = w.vertex_faces[leaving];
  list.erase(std::find(list.begin(), list.end(), f));
  w.vertex_faces[joining].push_back(f);
}

}  // namespace

bool remove_cap(WorkMesh& w, TetMesh& mesh, Index t) {
  if (mesh.face_marker.size() != mesh.faces.size()) return false;
  const Tet4 v = w.tets[t];
  int on[4], n_on = 0;
  for (int k = 0; k < 4; ++k) {
    const Index a = v[(k + 1) & 3], b = v[(k + 2) & 3], c = v[(k + 3) & 3];
    if (!w.is_constraint_face(a, b, c)) continue;
    if (n_on == 2 || tets_with_face(w, a, b, c).size() != 1) return false;
    on[n_on++] = k;
  }
  if (n_on != 2) return false;
  // The faces opposite c and d hold the shared edge ab.
  const Index c = v[on[0]], d = v[on[1]];
  Index ab[2], n_ab = 0;
  for (Index x : v)
    if (x != c && x != d) ab[n_ab++] = x;
  const Index a = ab[0], b = ab[1];
  const Index f_abd = w.face_index(a, b, d), f_abc = w.face_index(a, b, c);
  if (f_abc == kNoIndex || f_abd == kNoIndex) return false;
  const int marker = mesh.face_marker[f_abc];
  if (marker <= 0 || mesh.face_marker[f_abd] != marker) return false;
  if (w.is_protected_edge(a, b)) return false;
  std::vector<Index> around_ab;
  w.tets_around_edge(a, b, around_ab);
  if (around_ab.size() != 1) return false;  // t alone
  for (Index f : w.vertex_faces[c]) {
    const auto& tri = mesh.faces[f];
    if (tri[0] == d || tri[1] == d || tri[2] == d) return false;
  }
  if (tets_with_face(w, a, c, d).size() != 2 || tets_with_face(w, b, c, d).size() != 2) return false;

  // The surface stays smooth: old normals (stored outward) and new ones (towards the cap's far vertex, out of the
  // domain once it is gone) within kMaxTurnDeg of each other.
  const double cos_max = std::cos(kMaxTurnDeg * M_PI / 180);
  const auto& tc = mesh.faces[f_abc];
  const auto& td = mesh.faces[f_abd];
  const Vec n_abc = unit(face_normal(w.point(tc[0]), w.point(tc[1]), w.point(tc[2])));
  const Vec n_abd = unit(face_normal(w.point(td[0]), w.point(td[1]), w.point(td[2])));
  const Face3 acd = oriented(w, a, c, d, b), bcd = oriented(w, b, c, d, a);
  const Vec n_acd = unit(face_normal(w.point(acd[0]), w.point(acd[1]), w.point(acd[2])));
  const Vec n_bcd = unit(face_normal(w.point(bcd[0]), w.point(bcd[1]), w.point(bcd[2])));
  const Vec normals[4] = {n_abc, n_abd, n_acd, n_bcd};
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j)
      if (!(dot(normals[i], normals[j]) >= cos_max)) return false;
  const double old_angle = std::min(min_angle_deg(w.point(a), w.point(b), w.point(c)),
                                    min_angle_deg(w.point(a), w.point(b), w.point(d)));
  const double new_angle = std::min(min_angle_deg(w.point(a), w.point(c), w.point(d)),
                                    min_angle_deg(w.point(b), w.point(c), w.point(d)));
  if (!(new_angle >= 0.5 * old_angle)) return false;

  w.kill_tet(t);
  // abc -> acd (b leaves it, d joins), abd -> bcd (a leaves it, c joins); each keeps its marker, and leaves its PLC
  // facet (a chord triangle of the curved face) for none.
  replace_face(w, mesh, f_abc, acd, b, d);
  replace_face(w, mesh, f_abd, bcd, a, c);
  if (mesh.face_facet.size() == mesh.faces.size()) mesh.face_facet[f_abc] = mesh.face_facet[f_abd] = -1;
  return true;
}

}  // namespace qualmesh::detail
