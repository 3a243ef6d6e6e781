// The reference side of the mesh checker: geometry of the input facets (plane, projected loops, nesting, filled
// area, point-in-facet) and the volume the input encloses. See mesh_check_internal.h for the method and limits.
//
// A facet is the region of its plane covered by an odd number of its loops, less each connected part that a facet
// hole point reaches (plc.h). For loops that do not cross (a PLC rule), a point lies in the same part as a hole
// point exactly when the same loops enclose both, and the filled area is the sum of the loop areas signed by
// nesting depth (even adds, odd subtracts), less, for each hole part that is filled, the area of its innermost
// loop minus that loop's children.
#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "mesh_check_internal.h"
#include "vec3.h"

namespace qualmesh::check {
namespace {

double signed_area_2d(const std::vector<Point2>& loop) {
  double twice = 0;
  for (std::size_t i = 0, n = loop.size(); i < n; ++i) {
    const Point2& a = loop[i];
    const Point2& b = loop[(i + 1) % n];
    twice += a[0] * b[1] - a[1] * b[0];
  }
  return twice / 2;
}

// Crossing-number test; points on the boundary go either way.
bool inside_2d(const std::vector<Point2>& loop, const Point2& p) {
  bool inside = false;
  for (std::size_t i = 0, n = loop.size(), j = n - 1; i < n; j = i++) {
    const Point2& a = loop[i];
    const Point2& b = loop[j];
    if ((a[1] > p[1]) != (b[1] > p[1])) {
      const double x = a[0] + (p[1] - a[1]) * (b[0] - a[0]) / (b[1] - a[1]);
      if (p[0] < x) inside = !inside;
    }
  }
  return inside;
}

Point3 newell_normal(const Plc& plc, const std::vector<Index>& loop) {
  Point3 n{0, 0, 0};
  for (std::size_t i = 0, m = loop.size(); i < m; ++i) {
    const Point3& a = plc.vertices[loop[i]];
    const Point3& b = plc.vertices[loop[(i + 1) % m]];
    n[0] += (a[1] - b[1]) * (a[2] + b[2]);
    n[1] += (a[2] - b[2]) * (a[0] + b[0]);
    n[2] += (a[0] - b[0]) * (a[1] + b[1]);
  }
  return n;
}

}  // namespace

bool FacetGeometry::contains(const Point3& p) const {
  if (degenerate) return false;
  const Point2 q = project(p);
  std::vector<char> enclosure(loops_2d.size());
  int count = 0;
  for (std::size_t i = 0; i < loops_2d.size(); ++i) {
    enclosure[i] = inside_2d(loops_2d[i], q);
    count += enclosure[i];
  }
  if (count % 2 == 0) return false;
  for (const auto& hole : hole_enclosure) {
    if (hole == enclosure) return false;
  }
  return true;
}

FacetGeometry make_facet_geometry(const Plc& plc, const Facet& facet) {
  FacetGeometry g;
  for (const auto& polygon : facet.polygons) {
    if (polygon.size() >= 3) g.loops.push_back(polygon);
    for (Index v : polygon) {
      if (v < plc.vertices.size()) g.box.add(plc.vertices[v]);
    }
  }
  for (const auto& loop : g.loops) {
    for (Index v : loop) {
      if (v >= plc.vertices.size()) {
        g.degenerate = true;
        return g;
      }
    }
  }
  // Normal of the loop of largest area (the outer boundary for any sensible facet).
  Point3 best{0, 0, 0};
  for (const auto& loop : g.loops) {
    const Point3 n = newell_normal(plc, loop);
    if (vec3::norm(n) > vec3::norm(best)) best = n;
  }
  const double norm = vec3::norm(best);
  if (!(norm > 0)) {
    g.degenerate = true;
    return g;
  }
  g.normal = {best[0] / norm, best[1] / norm, best[2] / norm};
  // Offset: mean over the vertices, which averages out rounding of nearly planar input.
  double sum = 0;
  std::size_t count = 0;
  for (const auto& loop : g.loops) {
    for (Index v : loop) {
      const Point3& p = plc.vertices[v];
      sum += g.normal[0] * p[0] + g.normal[1] * p[1] + g.normal[2] * p[2];
      ++count;
    }
  }
  g.offset = sum / static_cast<double>(count);
  for (const auto& loop : g.loops) {
    for (std::size_t i = 0; i < loop.size(); ++i) {
      const Point3& p = plc.vertices[loop[i]];
      const Point3& q = plc.vertices[loop[(i + 1) % loop.size()]];
      g.flatness = std::max(g.flatness, std::fabs(g.normal[0] * p[0] + g.normal[1] * p[1] + g.normal[2] * p[2] -
                                                  g.offset));
      g.perimeter += std::sqrt((q[0] - p[0]) * (q[0] - p[0]) + (q[1] - p[1]) * (q[1] - p[1]) +
                               (q[2] - p[2]) * (q[2] - p[2]));
    }
  }
  g.drop_axis = 0;
  for (int k = 1; k < 3; ++k) {
    if (std::fabs(g.normal[k]) > std::fabs(g.normal[g.drop_axis])) g.drop_axis = k;
  }
  const double scale = std::fabs(g.normal[g.drop_axis]);  // projected area = true area * scale

  std::vector<double> projected_area(g.loops.size());
  for (std::size_t i = 0; i < g.loops.size(); ++i) {
    std::vector<Point2> loop_2d;
    for (Index v : g.loops[i]) loop_2d.push_back(g.project(plc.vertices[v]));
    projected_area[i] = signed_area_2d(loop_2d);
    // Positive 2D area means positive turning around +axis k; flip by the sign of normal[k].
    g.winding.push_back((projected_area[i] >= 0) == (g.normal[g.drop_axis] >= 0) ? 1 : -1);
    g.loops_2d.push_back(std::move(loop_2d));
  }
  // Nesting: loop i is inside loop j when one of its vertices that is not a vertex of j lies inside j.
  const std::size_t num_loops = g.loops.size();
  std::vector<std::vector<char>> inside(num_loops, std::vector<char>(num_loops, 0));
  g.depth.assign(num_loops, 0);
  for (std::size_t i = 0; i < num_loops; ++i) {
    for (std::size_t j = 0; j < num_loops; ++j) {
      if (i == j) continue;
      for (std::size_t k = 0; k < g.loops[i].size(); ++k) {
        const Index v = g.loops[i][k];
        if (std::find(g.loops[j].begin(), g.loops[j].end(), v) != g.loops[j].end()) continue;
        inside[i][j] = inside_2d(g.loops_2d[j], g.loops_2d[i][k]);
        break;
      }
      g.depth[i] += inside[i][j];
    }
  }
  double area = 0;
  for (std::size_t i = 0; i < num_loops; ++i) {
    area += (g.depth[i] % 2 == 0 ? 1 : -1) * std::fabs(projected_area[i]);
  }
  // Hole points: each distinct filled part they reach is removed once.
  std::set<std::vector<char>> removed;
  for (const Point3& hole : facet.holes) {
    const Point2 q = g.project(hole);
    std::vector<char> enclosure(num_loops);
    int count_enclosing = 0;
    std::size_t innermost = num_loops;
    for (std::size_t i = 0; i < num_loops; ++i) {
      enclosure[i] = inside_2d(g.loops_2d[i], q);
      if (enclosure[i]) {
        ++count_enclosing;
        if (innermost == num_loops || g.depth[i] > g.depth[innermost]) innermost = i;
      }
    }
    g.hole_enclosure.push_back(enclosure);
    if (count_enclosing % 2 == 0 || !removed.insert(enclosure).second) continue;
    double part = std::fabs(projected_area[innermost]);
    for (std::size_t i = 0; i < num_loops; ++i) {
      if (inside[i][innermost] && g.depth[i] == g.depth[innermost] + 1) part -= std::fabs(projected_area[i]);
    }
    area -= part;
  }
  g.area = area / scale;
  g.degenerate = !(g.area > 0);
  return g;
}

namespace {

double solid_angle(const Point3& p, const Point3& pa, const Point3& pb, const Point3& pc) {
  Point3 a, b, c;
  for (int k = 0; k < 3; ++k) {
    a[k] = pa[k] - p[k];
    b[k] = pb[k] - p[k];
    c[k] = pc[k] - p[k];
  }
  const double la = vec3::norm(a), lb = vec3::norm(b), lc = vec3::norm(c);
  const double det = a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
                     a[2] * (b[0] * c[1] - b[1] * c[0]);
  const double ab = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
  const double ac = a[0] * c[0] + a[1] * c[1] + a[2] * c[2];
  const double bc = b[0] * c[0] + b[1] * c[1] + b[2] * c[2];
  return 2 * std::atan2(det, la * lb * lc + ab * lc + ac * lb + bc * la);
}


struct UnionFind {
  std::vector<std::size_t> parent;
  explicit UnionFind(std::size_t n) : parent(n) {
    for (std::size_t i = 0; i < n; ++i) parent[i] = i;
  }
  std::size_t find(std::size_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  }
  void unite(std::size_t a, std::size_t b) { parent[find(a)] = find(b); }
};

// TetGen's semantics for PLCs with internal facets or volume holes: the domain is every bounded cell of the
// arrangement of the facets, less the cells holding a hole seed. The sides of the facets are grouped into cell
// boundary components by sorting the facets around each edge by angle (two facets consecutive around an edge face
// the same cell through the wedge between them). A component's divergence-theorem volume, with normals out of its
// cell, is positive when it encloses its cell (the cell's outer boundary) and negative when it is the outside of a
// structure lying in a larger cell (a cavity of that cell, or the outside of everything). A cell's volume is its
// positive component plus the negative components whose innermost enclosing positive component is it.
// Limits: facets must meet only along polygon edges (no T-junctions, no facet touching another inside).
ReferenceVolume compute_cell_volume(const Plc& plc, const std::vector<FacetGeometry>& facets) {
  const std::size_t num_facets = facets.size();
  // Directed boundary edges of each facet, oriented so that the facet's filled region lies on their left seen
  // from +normal.
  struct Use {
    std::size_t facet;
    Index from, to;
  };
  std::map<std::pair<Index, Index>, std::vector<Use>> edge_uses;
  for (std::size_t f = 0; f < num_facets; ++f) {
    const FacetGeometry& g = facets[f];
    if (g.degenerate) continue;
    for (std::size_t l = 0; l < g.loops.size(); ++l) {
      const int direction = g.winding[l] * (g.depth[l] % 2 == 0 ? 1 : -1);
      const auto& loop = g.loops[l];
      for (std::size_t i = 0, n = loop.size(); i < n; ++i) {
        Index a = loop[i], b = loop[(i + 1) % n];
        if (direction < 0) std::swap(a, b);
        if (a != b) edge_uses[{std::min(a, b), std::max(a, b)}].push_back({f, a, b});
      }
    }
  }
  // Side s of facet f: 2f (+normal side) or 2f+1 (-normal side).
  UnionFind sides(2 * num_facets);
  for (const auto& [edge, uses] : edge_uses) {
    const Point3& u = plc.vertices[edge.first];
    const Point3& v = plc.vertices[edge.second];
    Point3 axis{v[0] - u[0], v[1] - u[1], v[2] - u[2]};
    const double axis_length = vec3::norm(axis);
    for (double& c : axis) c /= axis_length;
    std::vector<std::pair<double, std::size_t>> order;  // angle, use
    std::vector<Point3> inward(uses.size());
    for (std::size_t i = 0; i < uses.size(); ++i) {
      const Point3& a = plc.vertices[uses[i].from];
      const Point3& b = plc.vertices[uses[i].to];
      inward[i] = vec3::cross(facets[uses[i].facet].normal, {b[0] - a[0], b[1] - a[1], b[2] - a[2]});
    }
    const Point3 x0 = inward[0];
    const Point3 y0 = vec3::cross(axis, x0);
    for (std::size_t i = 0; i < uses.size(); ++i) {
      order.push_back({std::atan2(vec3::dot(inward[i], y0), vec3::dot(inward[i], x0)), i});
    }
    std::sort(order.begin(), order.end());
    for (std::size_t k = 0; k < order.size(); ++k) {
      const std::size_t i = order[k].second, j = order[(k + 1) % order.size()].second;
      // The wedge from facet i to facet j (counterclockwise around the axis).
      const Point3 ahead = vec3::cross(axis, inward[i]);
      const Point3 behind = vec3::cross(inward[j], axis);
      const std::size_t fi = uses[i].facet, fj = uses[j].facet;
      const std::size_t side_i = 2 * fi + (vec3::dot(facets[fi].normal, ahead) > 0 ? 0 : 1);
      const std::size_t side_j = 2 * fj + (vec3::dot(facets[fj].normal, behind) > 0 ? 0 : 1);
      sides.unite(side_i, side_j);
    }
  }
  // Volume of each component, normals out of its cell: the +side's cell sees -normal as outward.
  std::map<std::size_t, double> component_volume;
  std::map<std::size_t, std::vector<std::size_t>> component_sides;
  for (std::size_t f = 0; f < num_facets; ++f) {
    if (facets[f].degenerate) continue;
    for (int s = 0; s < 2; ++s) {
      const std::size_t root = sides.find(2 * f + s);
      component_volume[root] += (s == 0 ? -1 : 1) * facets[f].offset * facets[f].area;  // divided by 3 below
      component_sides[root].push_back(2 * f + s);
    }
  }
  for (auto& entry : component_volume) entry.second /= 3;
  const double tiny = 1e-12;
  double scale = 0;
  for (const auto& [root, volume] : component_volume) scale = std::max(scale, std::fabs(volume));
  // Winding number of p with respect to a component (normals out of its cell), skipping facets through p.
  std::map<std::size_t, std::set<Index>> component_vertices;
  for (const auto& [root, list] : component_sides) {
    for (std::size_t side : list) {
      for (const auto& loop : facets[side / 2].loops) component_vertices[root].insert(loop.begin(), loop.end());
    }
  }
  const auto winding = [&](const Point3& p, std::size_t root) {
    double total = 0;
    for (std::size_t side : component_sides[root]) {
      const FacetGeometry& g = facets[side / 2];
      const int outward = side % 2 == 0 ? -1 : 1;
      for (std::size_t l = 0; l < g.loops.size(); ++l) {
        const int direction = outward * g.winding[l] * (g.depth[l] % 2 == 0 ? 1 : -1);
        const auto& loop = g.loops[l];
        for (std::size_t i = 1; i + 1 < loop.size(); ++i) {
          total += direction * solid_angle(p, plc.vertices[loop[0]], plc.vertices[loop[i]], plc.vertices[loop[i + 1]]);
        }
      }
    }
    return total / (4 * 3.14159265358979323846);
  };
  std::vector<std::size_t> positive, negative;
  for (const auto& [root, volume] : component_volume) {
    if (volume > tiny * scale) positive.push_back(root);
    else if (volume < -tiny * scale) negative.push_back(root);
  }
  // The innermost positive component (bounded cell) around p, or none; components through `on_vertex` (the
  // vertex p is) are not candidates.
  const auto cell_of = [&](const Point3& p, Index on_vertex) {
    std::size_t best = static_cast<std::size_t>(-1);
    for (std::size_t root : positive) {
      if (on_vertex != kNoIndex && component_vertices[root].count(on_vertex)) continue;
      if (std::fabs(winding(p, root)) > 0.5 &&
          (best == static_cast<std::size_t>(-1) || component_volume[root] < component_volume[best])) {
        best = root;
      }
    }
    return best;
  };
  std::set<std::size_t> hole_cells;
  for (const Point3& h : plc.holes) hole_cells.insert(cell_of(h, kNoIndex));
  // The cell each component faces: itself when it encloses a cell, else the innermost cell around it (none: the
  // unbounded cell). A cell is in the domain unless it is unbounded or holds a hole seed.
  const std::size_t none = static_cast<std::size_t>(-1);
  std::map<std::size_t, std::size_t> cell_faced;
  for (const auto& [root, list] : component_sides) {
    const double v = component_volume[root];
    if (v > tiny * scale) {
      cell_faced[root] = root;
    } else {
      const Index probe = facets[list.front() / 2].loops[0][0];
      cell_faced[root] = cell_of(plc.vertices[probe], probe);
    }
  }
  const auto in_domain = [&](std::size_t cell) { return cell != none && !hole_cells.count(cell); };
  ReferenceVolume result;
  for (std::size_t root : positive) {
    if (in_domain(root)) result.volume += component_volume[root];
  }
  for (std::size_t root : negative) {
    if (in_domain(cell_faced[root])) result.volume += component_volume[root];
  }
  result.facet_bounds_domain.assign(num_facets, 1);
  for (std::size_t f = 0; f < num_facets; ++f) {
    if (facets[f].degenerate) continue;
    result.facet_bounds_domain[f] =
        in_domain(cell_faced[sides.find(2 * f)]) || in_domain(cell_faced[sides.find(2 * f + 1)]);
  }
  result.method = "cells (" + std::to_string(positive.size()) + " bounded cells, " +
                  std::to_string(plc.holes.size()) + " hole seeds; internal facets or holes)";
  return result;
}

}  // namespace

ReferenceVolume compute_reference_volume(const Plc& plc, const std::vector<FacetGeometry>& facets) {
  ReferenceVolume result;
  // Each facet's edges, oriented so that the facet turns positively around its normal (outer loops forward,
  // loops at odd depth backward). Edge (a < b) -> uses: (facet, +1 when traversed a -> b).
  std::map<std::pair<Index, Index>, std::vector<std::pair<std::size_t, int>>> edge_uses;
  for (std::size_t f = 0; f < facets.size(); ++f) {
    const FacetGeometry& g = facets[f];
    if (g.degenerate) continue;
    for (std::size_t l = 0; l < g.loops.size(); ++l) {
      const int direction = g.winding[l] * (g.depth[l] % 2 == 0 ? 1 : -1);
      const auto& loop = g.loops[l];
      for (std::size_t i = 0, n = loop.size(); i < n; ++i) {
        Index a = loop[i], b = loop[(i + 1) % n];
        if (direction < 0) std::swap(a, b);
        if (a == b) continue;
        edge_uses[{std::min(a, b), std::max(a, b)}].push_back({f, a < b ? 1 : -1});
      }
    }
  }
  bool manifold = plc.holes.empty();
  for (const auto& [edge, uses] : edge_uses) {
    manifold = manifold && uses.size() == 2 && uses[0].first != uses[1].first;
  }
  if (!manifold) return compute_cell_volume(plc, facets);
  // Facet adjacency with the orientation relation: s_g = -s_f * d_f * d_g.
  std::vector<std::vector<std::pair<std::size_t, int>>> adjacent(facets.size());
  for (const auto& [edge, uses] : edge_uses) {
    const int relation = -uses[0].second * uses[1].second;
    adjacent[uses[0].first].push_back({uses[1].first, relation});
    adjacent[uses[1].first].push_back({uses[0].first, relation});
  }
  std::vector<int> sign(facets.size(), 0);
  std::vector<int> shell_of(facets.size(), -1);
  std::vector<double> shell_volume;
  for (std::size_t start = 0; start < facets.size(); ++start) {
    if (facets[start].degenerate || shell_of[start] >= 0) continue;
    const int shell = static_cast<int>(shell_volume.size());
    shell_volume.push_back(0);
    std::vector<std::size_t> stack{start};
    sign[start] = 1;
    shell_of[start] = shell;
    while (!stack.empty()) {
      const std::size_t f = stack.back();
      stack.pop_back();
      shell_volume[shell] += sign[f] * facets[f].offset * facets[f].area;  // divided by 3 below
      for (const auto& [g, relation] : adjacent[f]) {
        const int wanted = sign[f] * relation;
        if (shell_of[g] < 0) {
          shell_of[g] = shell;
          sign[g] = wanted;
          stack.push_back(g);
        } else if (sign[g] != wanted) {
          return compute_cell_volume(plc, facets);  // non-orientable: the cells do not need orientations
        }
      }
    }
  }
  const std::size_t num_shells = shell_volume.size();
  for (double& v : shell_volume) v /= 3;  // one rounding instead of one per facet
  for (std::size_t f = 0; f < facets.size(); ++f) {
    if (shell_of[f] >= 0 && shell_volume[shell_of[f]] < 0) sign[f] = -sign[f];
  }
  for (double& v : shell_volume) v = std::fabs(v);

  // Nesting depth of each shell: winding number of one of its vertices with respect to every other shell.
  std::vector<int> depth(num_shells, 0);
  if (num_shells > 1) {
    std::vector<Index> probe(num_shells, kNoIndex);
    std::vector<std::set<Index>> shell_vertices(num_shells);
    for (std::size_t f = 0; f < facets.size(); ++f) {
      if (shell_of[f] < 0) continue;
      for (const auto& loop : facets[f].loops) {
        shell_vertices[shell_of[f]].insert(loop.begin(), loop.end());
        if (probe[shell_of[f]] == kNoIndex) probe[shell_of[f]] = loop[0];
      }
    }
    for (std::size_t s = 0; s < num_shells; ++s) {
      const Point3& p = plc.vertices[probe[s]];
      std::vector<double> winding(num_shells, 0);
      for (std::size_t f = 0; f < facets.size(); ++f) {
        const int t = shell_of[f];
        if (t < 0 || static_cast<std::size_t>(t) == s || shell_vertices[t].count(probe[s])) continue;
        const FacetGeometry& g = facets[f];
        for (std::size_t l = 0; l < g.loops.size(); ++l) {
          const int direction = sign[f] * g.winding[l] * (g.depth[l] % 2 == 0 ? 1 : -1);
          const auto& loop = g.loops[l];
          for (std::size_t i = 1; i + 1 < loop.size(); ++i) {
            // Van Oosterom-Strackee solid angle of the fan triangle (loop[0], loop[i], loop[i+1]) seen from p.
            Point3 a, b, c;
            for (int k = 0; k < 3; ++k) {
              a[k] = plc.vertices[loop[0]][k] - p[k];
              b[k] = plc.vertices[loop[i]][k] - p[k];
              c[k] = plc.vertices[loop[i + 1]][k] - p[k];
            }
            const double la = vec3::norm(a), lb = vec3::norm(b), lc = vec3::norm(c);
            const double det = a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
                               a[2] * (b[0] * c[1] - b[1] * c[0]);
            const double ab = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
            const double ac = a[0] * c[0] + a[1] * c[1] + a[2] * c[2];
            const double bc = b[0] * c[0] + b[1] * c[1] + b[2] * c[2];
            const double den = la * lb * lc + ab * lc + ac * lb + bc * la;
            winding[t] += direction * 2 * std::atan2(det, den);
          }
        }
      }
      const double four_pi = 4 * 3.14159265358979323846;
      for (std::size_t t = 0; t < num_shells; ++t) {
        if (t != s && std::fabs(winding[t] / four_pi) > 0.5) ++depth[s];
      }
    }
  }
  result.volume = 0;
  for (std::size_t s = 0; s < num_shells; ++s) result.volume += (depth[s] % 2 == 0 ? 1 : -1) * shell_volume[s];
  result.method = num_shells == 1 ? "closed-shells (1 shell)"
                                  : "closed-shells (" + std::to_string(num_shells) + " shells, signed by nesting)";
  return result;
}

}  // namespace qualmesh::check
