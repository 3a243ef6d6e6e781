// Topological flips of the improvement pass (improve.h; beyond the paper, after QUALMESH): the 2-3 flip and edge
// removal, the n-to-2n-4 flip that replaces the n tetrahedra around an interior edge uv by the 2(n-2) tetrahedra
// joining u and v to a triangulation of the edge's ring (n = 3 is the 3-2 flip). The triangulation of the ring is
// the one that maximises the smallest dihedral angle, found by Klincsek's dynamic programme over the ring polygon
// (Shewchuk, "Two discrete optimization algorithms for the topological improvement of tetrahedral meshes", 2002;
// CGAL Mesh_3's Slivers_exuder reaches the same tetrahedra through weights, which the boundary forbids here).
//
// Geometry of the ring: with the ring r_0 .. r_{n-1} ordered so that every old tetrahedron (u, v, r_i, r_{i+1}) is
// positively oriented, a ring triangle (r_i, r_j, r_k), i < j < k, gives the tetrahedra (r_i, r_k, r_j, u) and
// (r_i, r_j, r_k, v). The new tetrahedra fill exactly the old ones' union when every one of them is positively
// oriented (u and v on opposite sides of every ring triangle), so no other tetrahedron is affected.
// A flip never removes a constraint face (boundary or internal facet: the edge's ring faces and the flipped face
// are checked), a protected (segment) edge, and joins only tetrahedra of one region: conformity and region volumes
// are unchanged.
#include <cmath>
#include <limits>

#include "improve/work_mesh.h"

namespace qualmesh::detail {
namespace {

struct FlipPlan {
  std::vector<Index> old_tets;
  std::vector<Tet4> new_tets;
  double new_min = -1;
  int kind = 0;  // 1: 2-3 flip, n: edge removal of a ring of n
};

double quality_of(const WorkMesh& w, const Tet4& t) {
  return oriented_min_dihedral_deg(w.point(t[0]), w.point(t[1]), w.point(t[2]), w.point(t[3]));
}

// Whether every new tetrahedron of the plan passes the radius-edge guard (WorkMesh::rho_allowed).
bool keeps_radius_edge(const WorkMesh& w, const FlipPlan& plan) {
  if (w.rho_bound <= 0) return true;
  double old_max = 0;
  for (Index t : plan.old_tets) old_max = std::max(old_max, w.radius_edge(t));
  for (const Tet4& t : plan.new_tets)
    if (!w.rho_allowed(t, old_max)) return false;
  return true;
}

// Edge removal of uv (see the file comment); false when uv is on the boundary (open ring), on a constraint face,
// protected, between regions, or has a ring of more than max_ring vertices or no valid triangulation.
bool plan_edge_removal(const WorkMesh& w, Index u, Index v, int max_ring, FlipPlan& plan) {
  if (w.is_protected_edge(u, v)) return false;
  std::vector<Index> around;
  w.tets_around_edge(u, v, around);
  const int n = int(around.size());
  if (n < 3 || n > max_ring) return false;
  const int label = w.region[around[0]];
  std::vector<Edge2> pairs;  // per tet: its two vertices other than u and v
  for (Index t : around) {
    if (w.region[t] != label) return false;
    Edge2 p{kNoIndex, kNoIndex};
    int k = 0;
    for (Index x : w.tets[t])
      if (x != u && x != v) p[k++] = x;
    pairs.push_back(p);
  }
  // Chain the pairs into the ring, oriented so that (u, v, r_i, r_{i+1}) is positive.
  std::vector<Index> ring;
  std::vector<std::uint8_t> used(n, 0);
  Edge2 first = pairs[0];
  if (tet_signed_volume(w.point(u), w.point(v), w.point(first[0]), w.point(first[1])) < 0)
    std::swap(first[0], first[1]);
  ring.push_back(first[0]);
  ring.push_back(first[1]);
  used[0] = 1;
  while (int(ring.size()) < n) {
    const Index last = ring.back();
    bool found = false;
    for (int i = 0; i < n && !found; ++i) {
      if (used[i]) continue;
      if (pairs[i][0] == last) ring.push_back(pairs[i][1]), used[i] = 1, found = true;
      else if (pairs[i][1] == last) ring.push_back(pairs[i][0]), used[i] = 1, found = true;
    }
    if (!found) return false;  // open ring: uv is on the domain boundary
  }
  {
    // The last unused pair must close the ring.
    int i = 0;
    while (i < n && used[i]) ++i;
    if (i == n) return false;
    const Edge2 p = pairs[i];
    if (!((p[0] == ring.back() && p[1] == ring[0]) || (p[1] == ring.back() && p[0] == ring[0]))) return false;
  }
  for (int i = 0; i < n; ++i) {
    if (w.is_constraint_face(u, v, ring[i])) return false;
    for (int j = i + 1; j < n; ++j)
      if (ring[i] == ring[j]) return false;
  }
  // Every old tetrahedron is positive in this orientation (a consistent ring).
  for (int i = 0; i < n; ++i)
    if (tet_signed_volume(w.point(u), w.point(v), w.point(ring[i]), w.point(ring[(i + 1) % n])) <= 0) return false;

  // Klincsek: best[i][k] = the best smallest angle over triangulations of the sub-polygon r_i .. r_k.
  const double inf = std::numeric_limits<double>::infinity();
  auto triangle_quality = [&](int i, int j, int k) {
    const Tet4 up{ring[i], ring[k], ring[j], u}, down{ring[i], ring[j], ring[k], v};
    const double qa = quality_of(w, up);
    if (qa < 0) return -1.0;
    return std::min(qa, quality_of(w, down));
  };
  std::vector<double> best(n * n, inf);
  std::vector<int> split(n * n, -1);
  for (int len = 2; len < n; ++len)
    for (int i = 0; i + len < n; ++i) {
      const int k = i + len;
      double b = -1;
      int arg = -1;
      for (int j = i + 1; j < k; ++j) {
        double q = std::min(best[i * n + j], best[j * n + k]);
        if (q <= b) continue;
        q = std::min(q, triangle_quality(i, j, k));
        if (q > b) b = q, arg = j;
      }
      best[i * n + k] = b;
      split[i * n + k] = arg;
    }
  if (best[n - 1] <= 0) return false;
  plan.old_tets = around;
  plan.new_tets.clear();
  std::vector<std::array<int, 2>> stack{{0, n - 1}};
  while (!stack.empty()) {
    const auto [i, k] = stack.back();
    stack.pop_back();
    if (k - i < 2) continue;
    const int j = split[i * n + k];
    // A diagonal r_i r_k (every (i, k) but the closing ring edge (0, n-1)) must not exist elsewhere already.
    if (!(i == 0 && k == n - 1) && w.has_edge(ring[i], ring[k])) return false;
    plan.new_tets.push_back({ring[i], ring[k], ring[j], u});
    plan.new_tets.push_back({ring[i], ring[j], ring[k], v});
    stack.push_back({i, j});
    stack.push_back({j, k});
  }
  plan.new_min = best[n - 1];
  plan.kind = n;
  return true;
}

// 2-3 flip of face `face` (the face opposite corner `face` of tet t) with the tetrahedron across it.
bool plan_flip23(const WorkMesh& w, Index t, int face, FlipPlan& plan) {
  const Tet4& a = w.tets[t];
  const Index d = a[face];
  const Index f0 = a[(face + 1) & 3], f1 = a[(face + 2) & 3], f2 = a[(face + 3) & 3];
  if (w.is_constraint_face(f0, f1, f2)) return false;
  Index other = kNoIndex;
  for (Index s : w.incident[f0]) {
    if (s == t) continue;
    const Tet4& b = w.tets[s];
    int hits = 0;
    for (Index x : b) hits += (x == f1 || x == f2);
    if (hits == 2) other = s;
  }
  if (other == kNoIndex || w.region[other] != w.region[t]) return false;
  Index e = kNoIndex;
  for (Index x : w.tets[other])
    if (x != f0 && x != f1 && x != f2) e = x;
  if (e == kNoIndex || w.has_edge(d, e)) return false;
  const Index f[3] = {f0, f1, f2};
  plan.new_tets.clear();
  int sign = 0;
  for (int k = 0; k < 3; ++k) {
    Tet4 n{f[k], f[(k + 1) % 3], d, e};
    const double vol = tet_signed_volume(w.point(n[0]), w.point(n[1]), w.point(n[2]), w.point(n[3]));
    const int s = vol > 0 ? 1 : vol < 0 ? -1 : 0;
    if (s == 0 || (sign != 0 && s != sign)) return false;
    sign = s;
    if (s < 0) std::swap(n[0], n[1]);
    plan.new_tets.push_back(n);
  }
  double q = std::numeric_limits<double>::infinity();
  for (const Tet4& n : plan.new_tets) q = std::min(q, quality_of(w, n));
  if (q <= 0) return false;
  plan.old_tets = {t, other};
  plan.new_min = q;
  plan.kind = 1;
  return true;
}

}  // namespace

int flip_to_remove(WorkMesh& w, Index t, int max_ring) {
  const Tet4 tv = w.tets[t];
  FlipPlan best, plan;
  for (int a = 0; a < 4; ++a)
    for (int b = a + 1; b < 4; ++b)
      if (plan_edge_removal(w, tv[a], tv[b], max_ring, plan) && plan.new_min > best.new_min &&
          keeps_radius_edge(w, plan))
        best = plan;
  for (int f = 0; f < 4; ++f)
    if (plan_flip23(w, t, f, plan) && plan.new_min > best.new_min && keeps_radius_edge(w, plan))
      best = plan;
  if (best.kind == 0) return 0;
  double old_min = std::numeric_limits<double>::infinity();
  for (Index o : best.old_tets) old_min = std::min(old_min, w.quality(o));
  if (!(best.new_min > old_min + 1e-9)) return 0;
  const int label = w.region[t];
  for (Index o : best.old_tets) w.kill_tet(o);
  for (const Tet4& n : best.new_tets) w.add_tet(n, label);
  return best.kind;
}

}  // namespace qualmesh::detail
