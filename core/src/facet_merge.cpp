// Merging of adjacent, exactly coplanar facets into polygonal facets (see facet_merge.h).
//
// Geometry. Two planar facets sharing an edge uv are merged when the four plane-defining points are exactly
// coplanar (CGAL orientation_3, exact predicate on the input doubles) and the facets lie on opposite sides of uv in
// their common plane, so a zero-thickness fold (two coplanar facets overlapping along uv) is never merged. "Side"
// is decided without constructions: every facet gets an exact orientation sign in the coordinate projection its
// plane maps one-to-one onto (xy, else yz, else zx, a property of the plane alone), read at its lexicographically
// smallest projected vertex, which is a strictly convex corner of a simple polygon. A facet's interior lies left of
// its directed edges when that sign is positive.
//
// Tolerance (merge_coplanar_facets' relative_tolerance > 0). Facets are grown from a seed, in index order: a facet
// joins the seed's group across an edge of two uses when all its vertices lie within the tolerance of the seed's
// plane (so the group cannot drift away from one plane along a gently curved strip) and the sides agree, decided in
// the projection along the seed normal's largest component; plane and projection are compute_facet_frame's, as
// validate_plc measures them. The merged facet is kept only when its vertices are within the tolerance of its own
// such plane, else the group stays unmerged.
// With a zero tolerance the groups are exactly those of the exact rule above.
//
// Topology. The facets of a group are re-oriented like the group's first facet; directed edges that occur both ways
// cancel, and the boundary edges left are chained into closed loops, split at repeated vertices into simple loops.
// By the odd-count rule of plc.h, any such decomposition describes the union (the winding number of the boundary is
// 1 inside and 0 outside, and each simple loop adds +-1). Whatever cannot be chained cleanly (inconsistent input)
// leaves the group unmerged.
#include "qualmesh/facet_merge.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <numeric>
#include <optional>
#include <tuple>
#include <utility>
#include <vector>

#include "facet_triangulation.h"

namespace qualmesh {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using P3 = Kernel::Point_3;
using P2 = Kernel::Point_2;

// Which coordinate is dropped to project a plane one-to-one onto a coordinate plane.
enum class Projection { DropZ, DropX, DropY };

P3 to_cgal(const Point3& p) { return P3(p[0], p[1], p[2]); }

P2 project(const Point3& p, Projection projection) {
  switch (projection) {
    case Projection::DropZ: return P2(p[0], p[1]);
    case Projection::DropX: return P2(p[1], p[2]);
    case Projection::DropY: return P2(p[2], p[0]);
  }
  return P2(p[0], p[1]);
}

Projection choose_projection(const Point3& a, const Point3& b, const Point3& c) {
  if (CGAL::orientation(project(a, Projection::DropZ), project(b, Projection::DropZ), project(c, Projection::DropZ)) !=
      CGAL::COLLINEAR) {
    return Projection::DropZ;
  }
  if (CGAL::orientation(project(a, Projection::DropX), project(b, Projection::DropX), project(c, Projection::DropX)) !=
      CGAL::COLLINEAR) {
    return Projection::DropX;
  }
  return Projection::DropY;
}

// Exact orientation sign (+1 / -1) of a simple loop in `projection`; 0 when degenerate.
int loop_orientation(const std::vector<Index>& loop, const std::vector<Point3>& vertices, Projection projection) {
  const std::size_t n = loop.size();
  if (n < 3) return 0;
  std::size_t lowest = 0;
  P2 lowest_point = project(vertices[loop[0]], projection);
  for (std::size_t i = 1; i < n; ++i) {
    const P2 q = project(vertices[loop[i]], projection);
    if (CGAL::compare_xy(q, lowest_point) == CGAL::SMALLER) {
      lowest = i;
      lowest_point = q;
    }
  }
  const P2 prev = project(vertices[loop[(lowest + n - 1) % n]], projection);
  const P2 next = project(vertices[loop[(lowest + 1) % n]], projection);
  switch (CGAL::orientation(prev, lowest_point, next)) {
    case CGAL::LEFT_TURN: return 1;
    case CGAL::RIGHT_TURN: return -1;
    default: return 0;
  }
}

// What the merge needs to know of one facet.
struct FacetShape {
  bool mergeable = false;
  std::array<Index, 3> plane{};  // three non-collinear vertices of the facet
  Projection projection = Projection::DropZ;
  int orientation = 0;  // +1 / -1 in `projection`
};

FacetShape describe_facet(const Facet& facet, const std::vector<Point3>& vertices) {
  FacetShape shape;
  if (facet.polygons.size() != 1 || !facet.holes.empty()) return shape;
  const std::vector<Index>& loop = facet.polygons[0];
  if (loop.size() < 3) return shape;
  for (Index v : loop) {
    if (v >= vertices.size()) return shape;
  }
  std::vector<Index> sorted = loop;
  std::sort(sorted.begin(), sorted.end());
  if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end()) return shape;  // repeated vertex
  const P3 a = to_cgal(vertices[loop[0]]);
  const P3 b = to_cgal(vertices[loop[1]]);
  if (a == b) return shape;
  std::size_t third = 2;
  while (third < loop.size() && CGAL::collinear(a, b, to_cgal(vertices[loop[third]]))) ++third;
  if (third == loop.size()) return shape;  // all collinear
  const P3 c = to_cgal(vertices[loop[third]]);
  for (Index v : loop) {
    if (CGAL::orientation(a, b, c, to_cgal(vertices[v])) != CGAL::COPLANAR) return shape;  // not planar
  }
  shape.plane = {loop[0], loop[1], loop[third]};
  shape.projection = choose_projection(vertices[loop[0]], vertices[loop[1]], vertices[loop[third]]);
  shape.orientation = loop_orientation(loop, vertices, shape.projection);
  shape.mergeable = shape.orientation != 0;
  return shape;
}

// One use of an undirected edge (a < b) by a facet loop or an explicit segment.
struct EdgeUse {
  Index a, b;
  Index facet;   // kNoIndex for an explicit segment
  int direction;  // +1 when the facet runs a -> b, -1 when b -> a
};

struct DisjointSets {
  std::vector<Index> parent;
  explicit DisjointSets(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), Index{0}); }
  Index find(Index x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  }
  void unite(Index x, Index y) {  // the smaller index becomes the root
    x = find(x);
    y = find(y);
    if (x == y) return;
    if (x > y) std::swap(x, y);
    parent[y] = x;
  }
};

using EdgeKey = std::pair<Index, Index>;

// Splits a closed walk into simple loops at repeated vertices.
void split_walk(const std::vector<Index>& walk, std::vector<std::vector<Index>>& loops) {
  std::vector<Index> stack;
  std::map<Index, std::size_t> position;
  for (Index v : walk) {
    auto it = position.find(v);
    if (it == position.end()) {
      position[v] = stack.size();
      stack.push_back(v);
      continue;
    }
    std::vector<Index> loop(stack.begin() + static_cast<std::ptrdiff_t>(it->second), stack.end());
    for (std::size_t i = it->second + 1; i < stack.size(); ++i) position.erase(stack[i]);
    stack.resize(it->second + 1);
    loops.push_back(std::move(loop));
  }
  if (!stack.empty()) loops.push_back(std::move(stack));
}

// Builds the merged facet of a group; false when the boundary does not chain into simple loops.
bool merge_group(const Plc& plc, const std::vector<Index>& group, const std::vector<FacetShape>& shapes,
                 const std::map<EdgeKey, int>& global_uses, Facet& merged) {
  const FacetShape& reference = shapes[group.front()];
  std::map<EdgeKey, int> directed;  // remaining multiplicity of each directed edge
  std::vector<EdgeKey> cancelled;
  std::vector<Index> group_vertices;
  for (Index f : group) {
    std::vector<Index> loop = plc.facets[f].polygons[0];
    if (shapes[f].orientation != reference.orientation) std::reverse(loop.begin(), loop.end());
    for (std::size_t i = 0; i < loop.size(); ++i) {
      const Index u = loop[i], v = loop[(i + 1) % loop.size()];
      group_vertices.push_back(u);
      auto reverse = directed.find({v, u});
      if (reverse != directed.end() && reverse->second > 0) {
        --reverse->second;
        cancelled.push_back({std::min(u, v), std::max(u, v)});
      } else {
        ++directed[{u, v}];
      }
    }
  }
  // Chain the boundary edges: out-edges per vertex, in increasing order of target (deterministic).
  std::map<Index, std::vector<Index>> out;
  std::size_t num_edges = 0;
  for (const auto& [edge, count] : directed) {
    for (int k = 0; k < count; ++k) {
      out[edge.first].push_back(edge.second);
      ++num_edges;
    }
  }
  for (auto& [v, targets] : out) std::reverse(targets.begin(), targets.end());  // pop_back takes the smallest
  std::vector<std::vector<Index>> loops;
  while (num_edges > 0) {
    Index start = kNoIndex;
    for (const auto& [v, targets] : out) {
      if (!targets.empty()) {
        start = v;
        break;
      }
    }
    std::vector<Index> walk{start};
    Index current = start;
    for (;;) {
      auto it = out.find(current);
      if (it == out.end() || it->second.empty()) return false;  // unbalanced: not a clean boundary
      const Index next = it->second.back();
      it->second.pop_back();
      --num_edges;
      if (next == start) break;
      walk.push_back(next);
      current = next;
    }
    split_walk(walk, loops);
  }
  for (const auto& loop : loops) {
    if (loop.size() < 3) return false;
  }
  // Outer loops (oriented like the group) first, inner loops after; each loop starts at its smallest vertex.
  std::vector<std::vector<Index>> outer, inner;
  for (auto& loop : loops) {
    std::rotate(loop.begin(), std::min_element(loop.begin(), loop.end()), loop.end());
    const int sign = loop_orientation(loop, plc.vertices, reference.projection);
    (sign == reference.orientation ? outer : inner).push_back(std::move(loop));
  }
  if (outer.empty()) return false;
  merged.polygons = std::move(outer);
  for (auto& loop : inner) merged.polygons.push_back(std::move(loop));
  // Interior edges also used outside the group (or explicit segments) stay, as segments lying in the facet.
  std::sort(cancelled.begin(), cancelled.end());
  cancelled.erase(std::unique(cancelled.begin(), cancelled.end()), cancelled.end());
  for (const EdgeKey& edge : cancelled) {
    auto it = global_uses.find(edge);
    if (it != global_uses.end() && it->second != 2) merged.polygons.push_back({edge.first, edge.second});
  }
  // Vertices left inside the merged facet stay, as isolated vertices of the facet.
  std::vector<char> on_loop(plc.vertices.size(), 0);
  for (const auto& loop : merged.polygons) {
    for (Index v : loop) on_loop[v] = 1;
  }
  std::sort(group_vertices.begin(), group_vertices.end());
  group_vertices.erase(std::unique(group_vertices.begin(), group_vertices.end()), group_vertices.end());
  for (Index v : group_vertices) {
    if (!on_loop[v]) merged.polygons.push_back({v});
  }
  merged.marker = plc.facets[group.front()].marker;
  for (Index f : group) {
    if (plc.facets[f].marker != merged.marker) merged.marker = 0;
  }
  return true;
}

// True when every vertex of `facet` lies within `tolerance` of its plane as plc_validate measures it.
bool within_plane(const Plc& plc, const Facet& facet, double tolerance) {
  const auto frame = detail::compute_facet_frame(plc.vertices, facet);
  if (!frame) return false;
  for (const auto& loop : facet.polygons)
    for (Index v : loop)
      if (!(std::abs(detail::signed_distance(*frame, plc.vertices[v])) <= tolerance)) return false;
  return true;
}

// Groups of facets within `tolerance` (model units, > 0) of their seed's plane, grown across the edges in `pairs`
// (two facet uses each); see the file comment. `shapes` of the members get the seed's projection and their
// orientation in it, as merge_group reads them.
void grow_near_coplanar_groups(const Plc& plc, const std::vector<std::pair<EdgeUse, EdgeUse>>& pairs,
                               double tolerance, std::vector<FacetShape>& shapes, DisjointSets& sets) {
  const std::size_t n = plc.facets.size();
  std::vector<std::vector<std::pair<EdgeUse, EdgeUse>>> adjacent(n);  // (use by this facet, use by the other)
  for (const auto& [x, y] : pairs) {
    adjacent[x.facet].push_back({x, y});
    adjacent[y.facet].push_back({y, x});
  }
  std::vector<char> assigned(n, 0);
  for (std::size_t seed = 0; seed < n; ++seed) {
    if (assigned[seed] || !shapes[seed].mergeable) continue;
    assigned[seed] = 1;
    // The seed's plane and projection as validate_plc sees them (compute_facet_frame).
    const std::optional<detail::FacetFrame> frame = detail::compute_facet_frame(plc.vertices, plc.facets[seed]);
    if (!frame) continue;
    const Projection projection = frame->drop_axis == 0   ? Projection::DropX
                                  : frame->drop_axis == 1 ? Projection::DropY
                                                          : Projection::DropZ;
    const auto orientation = [&](std::size_t f) {
      return loop_orientation(plc.facets[f].polygons[0], plc.vertices, projection);
    };
    const auto near_plane = [&](std::size_t f) {
      for (Index v : plc.facets[f].polygons[0])
        if (!(std::abs(detail::signed_distance(*frame, plc.vertices[v])) <= tolerance)) return false;
      return true;
    };
    std::vector<std::pair<Index, int>> members{{static_cast<Index>(seed), orientation(seed)}};  // and orientation
    for (std::size_t next = 0; next < members.size(); ++next) {  // breadth first: `members` is the queue
      const auto [f, f_sign] = members[next];
      for (const auto& [mine, other] : adjacent[f]) {
        const Index g = other.facet;
        if (assigned[g] || !shapes[g].mergeable || !near_plane(g)) continue;
        const int g_sign = orientation(g);
        if (g_sign == 0 || f_sign * mine.direction != -(g_sign * other.direction)) continue;
        assigned[g] = 1;
        members.push_back({g, g_sign});
      }
    }
    if (members.size() < 2) continue;
    for (const auto& [f, sign] : members) {
      shapes[f].projection = projection;
      shapes[f].orientation = sign;
      sets.unite(static_cast<Index>(seed), f);
    }
  }
}

}  // namespace

Plc merge_coplanar_facets(const Plc& plc, double relative_tolerance) {
  const std::size_t n = plc.facets.size();
  std::vector<FacetShape> shapes(n);
  for (std::size_t f = 0; f < n; ++f) shapes[f] = describe_facet(plc.facets[f], plc.vertices);

  // Every use of every edge, sorted so that the uses of one edge are adjacent (deterministic order).
  std::vector<EdgeUse> uses;
  for (std::size_t f = 0; f < n; ++f) {
    for (const auto& loop : plc.facets[f].polygons) {
      if (loop.size() < 2) continue;
      const std::size_t m = loop.size() == 2 ? 1 : loop.size();
      for (std::size_t i = 0; i < m; ++i) {
        const Index u = loop[i], v = loop[(i + 1) % loop.size()];
        if (u == v) continue;
        uses.push_back({std::min(u, v), std::max(u, v), static_cast<Index>(f), u < v ? 1 : -1});
      }
    }
  }
  for (const Segment& s : plc.segments) {
    if (s.a != s.b) uses.push_back({std::min(s.a, s.b), std::max(s.a, s.b), kNoIndex, 0});
  }
  std::sort(uses.begin(), uses.end(), [](const EdgeUse& x, const EdgeUse& y) {
    return std::tie(x.a, x.b, x.facet, x.direction) < std::tie(y.a, y.b, y.facet, y.direction);
  });

  const double tolerance = relative_tolerance > 0 ? relative_tolerance * bounding_box(plc).diagonal() : 0.0;
  std::map<EdgeKey, int> global_uses;
  DisjointSets sets(n);
  std::vector<std::pair<EdgeUse, EdgeUse>> pairs;  // tolerance: edges across which facets may join
  for (std::size_t i = 0; i < uses.size();) {
    std::size_t j = i;
    while (j < uses.size() && uses[j].a == uses[i].a && uses[j].b == uses[i].b) ++j;
    global_uses[{uses[i].a, uses[i].b}] = static_cast<int>(j - i);
    if (j - i == 2) {
      const EdgeUse& x = uses[i];
      const EdgeUse& y = uses[i + 1];
      if (x.facet != kNoIndex && y.facet != kNoIndex && x.facet != y.facet && shapes[x.facet].mergeable &&
          shapes[y.facet].mergeable) {
        if (tolerance > 0) {
          pairs.push_back({x, y});
          i = j;
          continue;
        }
        const FacetShape& fx = shapes[x.facet];
        const FacetShape& fy = shapes[y.facet];
        const P3 a = to_cgal(plc.vertices[fx.plane[0]]);
        const P3 b = to_cgal(plc.vertices[fx.plane[1]]);
        const P3 c = to_cgal(plc.vertices[fx.plane[2]]);
        bool coplanar = true;
        for (Index v : fy.plane) coplanar = coplanar && CGAL::orientation(a, b, c, to_cgal(plc.vertices[v])) == CGAL::COPLANAR;
        // Same plane, hence the same projection; interiors on opposite sides of the edge.
        if (coplanar && fx.orientation * x.direction == -(fy.orientation * y.direction)) sets.unite(x.facet, y.facet);
      }
    }
    i = j;
  }
  if (tolerance > 0) grow_near_coplanar_groups(plc, pairs, tolerance, shapes, sets);

  std::vector<std::vector<Index>> groups(n);
  for (std::size_t f = 0; f < n; ++f) groups[sets.find(static_cast<Index>(f))].push_back(static_cast<Index>(f));

  Plc merged = plc;
  merged.facets.clear();
  merged.facets.reserve(n);
  for (std::size_t f = 0; f < n; ++f) {
    const std::vector<Index>& group = groups[f];
    if (group.empty()) continue;  // f is not the root (smallest index) of its group
    if (group.size() == 1) {
      merged.facets.push_back(plc.facets[f]);
      continue;
    }
    Facet facet;
    const bool built = merge_group(plc, group, shapes, global_uses, facet);
    if (built && (tolerance == 0 || within_plane(plc, facet, tolerance))) {
      merged.facets.push_back(std::move(facet));
    } else {
      for (Index g : group) merged.facets.push_back(plc.facets[g]);
    }
  }
  return merged;
}

}  // namespace qualmesh
