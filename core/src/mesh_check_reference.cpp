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

double length(const Point3& v) { return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }

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
    if (length(n) > length(best)) best = n;
  }
  const double norm = length(best);
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

ReferenceVolume compute_reference_volume(const Plc& plc, const std::vector<FacetGeometry>& facets) {
  ReferenceVolume result;
  const double nan = std::nan("");
  if (!plc.holes.empty()) return {nan, "unsupported: volume hole seeds"};
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
  for (const auto& [edge, uses] : edge_uses) {
    if (uses.size() != 2 || uses[0].first == uses[1].first) {
      return {nan, "unsupported: edge (" + std::to_string(edge.first) + ", " + std::to_string(edge.second) +
                       ") is used by " + std::to_string(uses.size()) +
                       " facet sides (open input, internal facets or T-junctions)"};
    }
  }
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
      shell_volume[shell] += sign[f] * facets[f].offset * facets[f].area / 3;
      for (const auto& [g, relation] : adjacent[f]) {
        const int wanted = sign[f] * relation;
        if (shell_of[g] < 0) {
          shell_of[g] = shell;
          sign[g] = wanted;
          stack.push_back(g);
        } else if (sign[g] != wanted) {
          return {nan, "unsupported: facets " + std::to_string(f) + " and " + std::to_string(g) +
                           " cannot be oriented consistently (non-orientable shell)"};
        }
      }
    }
  }
  const std::size_t num_shells = shell_volume.size();
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
            const double la = length(a), lb = length(b), lc = length(c);
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
