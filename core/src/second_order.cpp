// Second-order tetrahedra and checked node moves (second_order.h).
#include "qualmesh/second_order.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <map>
#include <stdexcept>
#include <unordered_map>

namespace qualmesh {
namespace {

std::uint64_t edge_key(Index a, Index b) {
  if (a > b) std::swap(a, b);
  return (std::uint64_t(a) << 32) | b;
}

Point3 midpoint(const Point3& a, const Point3& b) {
  return {0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1]), 0.5 * (a[2] + b[2])};
}

double det3(const Point3& a, const Point3& b, const Point3& c) {
  return a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) + a[2] * (b[0] * c[1] - b[1] * c[0]);
}

double signed_volume6(const TetMesh& mesh, std::size_t t) {
  const auto& v = mesh.tets[t];
  const Point3 &p0 = mesh.points[v[0]], &p1 = mesh.points[v[1]], &p2 = mesh.points[v[2]], &p3 = mesh.points[v[3]];
  const Point3 a{p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]};
  const Point3 b{p2[0] - p0[0], p2[1] - p0[1], p2[2] - p0[2]};
  const Point3 c{p3[0] - p0[0], p3[1] - p0[1], p3[2] - p0[2]};
  return det3(a, b, c);
}

// Index of the mid node of corners (i, j) in tet_mid order.
int mid_slot(int i, int j) {
  if (i > j) std::swap(i, j);
  for (int k = 0; k < 6; ++k)
    if (kTetEdges[k][0] == i && kTetEdges[k][1] == j) return k;
  return -1;
}

// Acceptance measure of element t: for second order the Jacobian ratio (<= 0: inverted), for linear the volume.
double element_measure(const TetMesh& mesh, std::size_t t) {
  return mesh.is_second_order() ? tet10_jacobian(mesh, t).ratio() : signed_volume6(mesh, t);
}

// Rounds of NodeMoveOptions::optimise_interior's search for one move.
constexpr int kMaxOptimiseRounds = 30;

}  // namespace

void make_second_order(TetMesh& mesh) {
  if (mesh.is_second_order()) return;
  std::unordered_map<std::uint64_t, Index> mid_of;
  mid_of.reserve(mesh.tets.size() * 2);
  const auto mid = [&](Index a, Index b) {
    auto [it, added] = mid_of.try_emplace(edge_key(a, b), 0);
    if (added) {
      it->second = static_cast<Index>(mesh.points.size());
      mesh.points.push_back(midpoint(mesh.points[a], mesh.points[b]));
    }
    return it->second;
  };
  mesh.tet_mid.resize(mesh.tets.size());
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
    const auto& v = mesh.tets[t];
    for (int k = 0; k < 6; ++k) mesh.tet_mid[t][k] = mid(v[kTetEdges[k][0]], v[kTetEdges[k][1]]);
  }
  const auto existing = [&](Index a, Index b, const char* what) {
    const auto it = mid_of.find(edge_key(a, b));
    if (it == mid_of.end())
      throw std::invalid_argument(std::string("make_second_order: a ") + what + " edge is no tetrahedron edge");
    return it->second;
  };
  mesh.face_mid.resize(mesh.faces.size());
  for (std::size_t f = 0; f < mesh.faces.size(); ++f)
    for (int k = 0; k < 3; ++k) mesh.face_mid[f][k] = existing(mesh.faces[f][k], mesh.faces[f][(k + 1) % 3], "face");
  mesh.edge_mid.resize(mesh.edges.size());
  for (std::size_t e = 0; e < mesh.edges.size(); ++e) mesh.edge_mid[e] = existing(mesh.edges[e][0], mesh.edges[e][1], "CAD");
}

namespace {

// The Jacobian determinant of the element with these corners and mid nodes (tet_mid order), all given relative to
// corner 0 (far from the origin, the sums below would otherwise cancel digits that a small or nearly flat element
// needs), at its ten nodes, the four integration points of the 4-point rule (CalculiX's C3D10 stops with
// "nonpositive jacobian" when it is not positive there, whatever it is at the nodes) and the centroid.
Tet10Jacobian jacobian_of(const Point3 (&corners)[4], const Point3 (&mids)[6]) {
  const auto corner = [&](int i) -> const Point3& { return corners[i]; };
  const auto mid = [&](int i, int j) -> const Point3& { return mids[mid_slot(i, j)]; };
  // Evaluation points: the corners, the edge midpoints, the integration points, the centroid.
  constexpr double kGaussA = 0.1381966011250105;  // (5 - sqrt 5) / 20
  constexpr double kGaussB = 0.5854101966249685;  // (5 + 3 sqrt 5) / 20
  double L[15][4] = {};
  for (int i = 0; i < 4; ++i) L[i][i] = 1;
  for (int k = 0; k < 6; ++k) L[4 + k][kTetEdges[k][0]] = L[4 + k][kTetEdges[k][1]] = 0.5;
  for (int i = 0; i < 4; ++i)
    for (int a = 0; a < 4; ++a) L[10 + i][a] = a == i ? kGaussB : kGaussA;
  for (int a = 0; a < 4; ++a) L[14][a] = 0.25;
  Tet10Jacobian result;
  result.min_det = INFINITY;
  result.max_det = -INFINITY;
  for (const auto& l : L) {
    // d x / d L_a, treating the four barycentric coordinates as independent.
    Point3 g[4];
    for (int a = 0; a < 4; ++a) {
      const double s = 4 * l[a] - 1;
      Point3 d{s * corner(a)[0], s * corner(a)[1], s * corner(a)[2]};
      for (int b = 0; b < 4; ++b) {
        if (b == a) continue;
        const Point3& x = mid(a, b);
        for (int c = 0; c < 3; ++c) d[c] += 4 * l[b] * x[c];
      }
      g[a] = d;
    }
    // Columns d x / d xi_k = d x / d L_k - d x / d L_0 (L_0 = 1 - L_1 - L_2 - L_3).
    Point3 col[3];
    for (int k = 0; k < 3; ++k)
      for (int c = 0; c < 3; ++c) col[k][c] = g[k + 1][c] - g[0][c];
    const double det = det3(col[0], col[1], col[2]);
    result.min_det = std::min(result.min_det, det);
    result.max_det = std::max(result.max_det, det);
  }
  return result;
}

// Element t's nodes relative to its corner 0; `straight`: mid nodes at the (rounded) midpoints of the corners.
void local_nodes(const TetMesh& mesh, std::size_t t, bool straight, Point3 (&corners)[4], Point3 (&mids)[6]) {
  const auto& v = mesh.tets[t];
  const Point3& origin = mesh.points[v[0]];
  const auto local = [&](const Point3& p) { return Point3{p[0] - origin[0], p[1] - origin[1], p[2] - origin[2]}; };
  for (int i = 0; i < 4; ++i) corners[i] = local(mesh.points[v[i]]);
  for (int k = 0; k < 6; ++k)
    mids[k] = local(straight ? midpoint(mesh.points[v[kTetEdges[k][0]]], mesh.points[v[kTetEdges[k][1]]])
                             : mesh.points[mesh.tet_mid[t][k]]);
}

// |6V| <= flat L^3, L the longest edge of tet t.
bool is_flat_corners(const TetMesh& mesh, std::size_t t, double flat) {
  double sq_longest = 0;
  for (const auto& e : kTetEdges) {
    const Point3& a = mesh.points[mesh.tets[t][e[0]]];
    const Point3& b = mesh.points[mesh.tets[t][e[1]]];
    sq_longest = std::max(sq_longest, (a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                                          (a[2] - b[2]) * (a[2] - b[2]));
  }
  return std::fabs(signed_volume6(mesh, t)) <= flat * sq_longest * std::sqrt(sq_longest);
}

// Element t cannot be judged by its Jacobian ratio: its corners are (nearly) in a plane, |6V| <= 1e-6 L^3 (L the
// longest edge; a dihedral angle of about 1e-4 degrees), or it is so small against its distance from the origin
// that even its straight version (mid nodes at the rounded midpoints) has a Jacobian ratio below 1/2.
bool is_flat(const TetMesh& mesh, std::size_t t) {
  if (is_flat_corners(mesh, t, 1e-6)) return true;
  if (!mesh.is_second_order()) return false;
  Point3 corners[4], mids[6];
  local_nodes(mesh, t, /*straight=*/true, corners, mids);
  return jacobian_of(corners, mids).ratio() < 0.5;
}

}  // namespace

Tet10Jacobian tet10_jacobian(const TetMesh& mesh, std::size_t t) {
  Point3 corners[4], mids[6];
  local_nodes(mesh, t, /*straight=*/false, corners, mids);
  return jacobian_of(corners, mids);
}

NodeMoveReport move_nodes_checked(TetMesh& mesh, const std::vector<NodeMove>& moves, const NodeMoveOptions& options,
                                  const std::function<std::vector<Point3>(const NodeMove&)>& alternatives_of) {
  NodeMoveReport report;
  report.num_requested = moves.size();
  // Elements having each node (corner or mid node).
  std::vector<std::vector<std::uint32_t>> elements_of(mesh.points.size());
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
    for (Index v : mesh.tets[t]) elements_of[v].push_back(static_cast<std::uint32_t>(t));
    if (mesh.is_second_order())
      for (Index v : mesh.tet_mid[t]) elements_of[v].push_back(static_cast<std::uint32_t>(t));
  }
  const bool quadratic = mesh.is_second_order();
  // The Jacobian ratio the current attempt asks for: min_jacobian_ratio, or last_resort_jacobian_ratio last.
  double ratio_bar = options.min_jacobian_ratio;
  // What an element whose measure was `before` the move must keep: no worse when it was below the bar already.
  const auto bar_of = [&](double before) {
    if (before <= 0 || (quadratic && before < ratio_bar)) return before;
    return quadratic ? ratio_bar : options.min_volume_fraction * before;  // > 0
  };
  const auto acceptable = [&](std::size_t t, double before) { return element_measure(mesh, t) >= bar_of(before); };
  // Interior nodes (on no boundary or internal face): the ones a move may drag along.
  std::vector<std::uint8_t> on_face(mesh.points.size(), 0);
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    for (Index v : mesh.faces[f]) on_face[v] = 1;
    if (f < mesh.face_mid.size())
      for (Index v : mesh.face_mid[f]) on_face[v] = 1;
  }
  // The nodes of element t (corners, then mid nodes for second order).
  const auto element_nodes = [&](std::size_t t) {
    std::vector<Index> nodes(mesh.tets[t].begin(), mesh.tets[t].end());
    if (quadratic) nodes.insert(nodes.end(), mesh.tet_mid[t].begin(), mesh.tet_mid[t].end());
    return nodes;
  };
  // The elements having any of `nodes`, sorted, each once.
  const auto elements_around = [&](const std::vector<Index>& nodes) {
    std::vector<std::uint32_t> elements;
    for (Index v : nodes) elements.insert(elements.end(), elements_of[v].begin(), elements_of[v].end());
    std::sort(elements.begin(), elements.end());
    elements.erase(std::unique(elements.begin(), elements.end()), elements.end());
    return elements;
  };
  // Moves `nodes` by `shift` (all of them) and tells whether every element around them stays acceptable; on
  // failure everything is put back and `spoiled` lists the elements that were not.
  std::vector<std::size_t> spoiled;
  const auto try_shift = [&](const std::vector<Index>& nodes, const Point3& shift) {
    const std::vector<std::uint32_t> elements = elements_around(nodes);
    std::vector<double> before(elements.size());
    for (std::size_t i = 0; i < elements.size(); ++i) before[i] = element_measure(mesh, elements[i]);
    std::vector<Point3> saved;  // put back exactly (p + s - s need not be p in floating point)
    for (Index v : nodes) {
      saved.push_back(mesh.points[v]);
      for (int c = 0; c < 3; ++c) mesh.points[v][c] += shift[c];
    }
    spoiled.clear();
    for (std::size_t i = 0; i < elements.size(); ++i)
      if (!acceptable(elements[i], before[i])) spoiled.push_back(elements[i]);
    if (spoiled.empty()) return true;
    for (std::size_t i = 0; i < nodes.size(); ++i) mesh.points[nodes[i]] = saved[i];
    return false;
  };
  // Puts group[0] at its start + `shift` and searches positions of the interior nodes group[1..] that make every
  // element around them acceptable: a compass search (steps along the axes, halved when none helps) that maximises
  // the worst element's margin over its bar. It stops as soon as every element is acceptable; on failure everything
  // is put back exactly.
  const auto optimise_interior = [&](const std::vector<Index>& group, const Point3& shift) {
    const std::vector<std::uint32_t> elements = elements_around(group);
    std::vector<double> bar(elements.size()), margin(elements.size());
    for (std::size_t i = 0; i < elements.size(); ++i) bar[i] = bar_of(element_measure(mesh, elements[i]));
    const auto local = [&](std::uint32_t t) {
      return static_cast<std::size_t>(std::lower_bound(elements.begin(), elements.end(), t) - elements.begin());
    };
    std::vector<Point3> saved;
    for (Index v : group) saved.push_back(mesh.points[v]);
    for (int c = 0; c < 3; ++c) mesh.points[group[0]][c] += shift[c];
    for (std::size_t i = 0; i < elements.size(); ++i) margin[i] = element_measure(mesh, elements[i]) - bar[i];
    const auto worst = [&] { return *std::min_element(margin.begin(), margin.end()); };
    double best = worst();
    double step = std::sqrt(shift[0] * shift[0] + shift[1] * shift[1] + shift[2] * shift[2]);
    const double finest = 1e-2 * step;
    std::vector<double> trial;
    for (int round = 0; best < 0 && step > finest && round < kMaxOptimiseRounds; ++round) {
      bool improved = false;
      for (std::size_t k = 1; k < group.size(); ++k) {
        const Index v = group[k];
        for (int d = 0; d < 6; ++d) {
          const Point3 old = mesh.points[v];
          mesh.points[v][d / 2] += d % 2 ? -step : step;
          trial = margin;
          for (std::uint32_t t : elements_of[v]) trial[local(t)] = element_measure(mesh, t) - bar[local(t)];
          const double now = *std::min_element(trial.begin(), trial.end());
          if (now > best) {
            best = now;
            margin.swap(trial);
            improved = true;
          } else {
            mesh.points[v] = old;
          }
        }
      }
      if (!improved) step *= 0.5;
    }
    if (best >= 0) return true;
    for (std::size_t k = 0; k < group.size(); ++k) mesh.points[group[k]] = saved[k];
    return false;
  };
  // The full move of `node` by `shift`, alone, dragging the interior nodes of the elements it spoils, or placing
  // them by the search; 0 when none is acceptable (`blocking` then lists the elements the move alone spoiled).
  enum Full { kNot, kAlone, kDragged, kSearched };
  const auto full_move = [&](Index node, const Point3& shift, std::vector<std::size_t>& blocking) {
    if (try_shift({node}, shift)) return kAlone;
    blocking = spoiled;
    if (!options.drag_interior) return kNot;
    std::vector<Index> group{node};
    for (std::size_t t : blocking)
      for (Index v : element_nodes(t))
        if (!on_face[v] && v != node) group.push_back(v);
    std::sort(group.begin() + 1, group.end());
    group.erase(std::unique(group.begin() + 1, group.end()), group.end());
    if (group.size() == 1) return kNot;
    if (try_shift(group, shift)) return kDragged;
    if (options.optimise_interior && optimise_interior(group, shift)) return kSearched;
    return kNot;
  };
  const bool last_resort = quadratic && options.last_resort_jacobian_ratio > 0 &&
                           options.last_resort_jacobian_ratio < options.min_jacobian_ratio;
  for (const NodeMove& move : moves) {
    const Point3 start = mesh.points[move.node];
    const Point3 full{move.target[0] - start[0], move.target[1] - start[1], move.target[2] - start[2]};
    std::vector<std::size_t> blocking, unused;
    // The target, then each alternative, at min_jacobian_ratio; then all of them again at the last resort's ratio.
    std::vector<Point3> shifts{full};
    bool asked = !move.alternatives.empty() || !alternatives_of;
    for (const Point3& q : move.alternatives) shifts.push_back({q[0] - start[0], q[1] - start[1], q[2] - start[2]});
    Full how = kNot;
    for (int pass = 0; pass < (last_resort ? 2 : 1) && how == kNot; ++pass) {
      ratio_bar = pass == 0 ? options.min_jacobian_ratio : options.last_resort_jacobian_ratio;
      for (std::size_t k = 0; k < shifts.size() && how == kNot; ++k) {
        how = full_move(move.node, shifts[k], pass == 0 && k == 0 ? blocking : unused);
        if (how != kNot && k > 0) ++report.num_alternative;
        if (how == kNot && !asked) {  // the target failed: now the alternatives are worth finding
          asked = true;
          for (const Point3& q : alternatives_of(move))
            shifts.push_back({q[0] - start[0], q[1] - start[1], q[2] - start[2]});
        }
      }
      if (how != kNot && pass == 1) ++report.num_last_resort;
    }
    ratio_bar = options.min_jacobian_ratio;
    if (how == kDragged) ++report.num_dragged;
    if (how == kSearched) ++report.num_optimised;
    double done = how == kNot ? 0 : 1;
    if (done < 1) report.blocking_elements.insert(report.blocking_elements.end(), blocking.begin(), blocking.end());
    for (double fraction : {0.75, 0.5, 0.25}) {
      if (done > 0) break;
      if (try_shift({move.node}, {fraction * full[0], fraction * full[1], fraction * full[2]})) done = fraction;
    }
    if (done == 1) ++report.num_full;
    else if (done > 0) ++report.num_partial;
    else ++report.num_refused;
    const Point3& p = mesh.points[move.node];
    const double left = done == 1 ? 0 : std::sqrt((move.target[0] - p[0]) * (move.target[0] - p[0]) +
                                  (move.target[1] - p[1]) * (move.target[1] - p[1]) +
                                  (move.target[2] - p[2]) * (move.target[2] - p[2]));
    report.max_distance_left = std::max(report.max_distance_left, left);
  }
  std::sort(report.blocking_elements.begin(), report.blocking_elements.end());
  report.blocking_elements.erase(std::unique(report.blocking_elements.begin(), report.blocking_elements.end()),
                                 report.blocking_elements.end());
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
    if (is_flat(mesh, t)) {
      ++report.num_flat_elements;
      continue;
    }
    const double measure = element_measure(mesh, t);
    if (quadratic) {
      report.min_jacobian_ratio = std::min(report.min_jacobian_ratio, measure);
      if (measure < options.min_jacobian_ratio) ++report.num_bad_elements;
    } else if (measure <= 0) {
      ++report.num_bad_elements;
    }
  }
  return report;
}

std::size_t remove_flat_boundary_tets(TetMesh& mesh, double flat) {
  std::size_t removed = 0;
  for (;;) {
    const std::size_t n = remove_boundary_caps(mesh, [&](std::size_t t) { return is_flat_corners(mesh, t, flat); });
    if (n == 0) return removed;
    removed += n;
  }
}

std::size_t remove_boundary_caps(TetMesh& mesh, const std::function<bool(std::size_t)>& select) {
  if (mesh.is_second_order()) throw std::invalid_argument("remove_boundary_caps: linear meshes only");
  const std::vector<int> labels = face_labels(mesh);
  std::vector<std::uint64_t> cad_edges;
  for (const auto& e : mesh.edges) cad_edges.push_back(edge_key(e[0], e[1]));
  std::sort(cad_edges.begin(), cad_edges.end());
  // Outward faces of a positively oriented tet: opposite corner i, (i+1, i+2, i+3), reversed for odd i.
  const auto tet_face = [&](const std::array<Index, 4>& v, int i) {
    std::array<Index, 3> f{v[(i + 1) & 3], v[(i + 2) & 3], v[(i + 3) & 3]};
    if (i % 2 == 1) std::swap(f[1], f[2]);
    return f;
  };
  const auto sorted = [](std::array<Index, 3> f) {
    std::sort(f.begin(), f.end());
    return f;
  };
  std::map<std::array<Index, 3>, std::size_t> face_index;
  std::vector<std::uint64_t> face_edges;  // every edge of a boundary or internal face
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    face_index.emplace(sorted(mesh.faces[f]), f);
    for (int k = 0; k < 3; ++k) face_edges.push_back(edge_key(mesh.faces[f][k], mesh.faces[f][(k + 1) % 3]));
  }
  std::sort(face_edges.begin(), face_edges.end());
  std::map<std::array<Index, 3>, int> tets_at;  // how many tets have each face of mesh.faces
  for (const auto& v : mesh.tets)
    for (int i = 0; i < 4; ++i) {
      const auto key = sorted(tet_face(v, i));
      if (face_index.count(key)) ++tets_at[key];
    }
  std::vector<std::uint8_t> dead_tet(mesh.tets.size(), 0), dead_face(mesh.faces.size(), 0);
  struct NewFace {
    std::array<Index, 3> v;
    int facet, marker;
  };
  std::vector<NewFace> added;
  std::vector<std::uint8_t> touched(mesh.points.size(), 0);  // one removal per neighbourhood and pass
  std::size_t removed = 0;
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
    const auto& v = mesh.tets[t];
    if (touched[v[0]] || touched[v[1]] || touched[v[2]] || touched[v[3]]) continue;
    int boundary[4], n = 0;
    std::size_t which[4];
    bool internal = false;  // a face between two tetrahedra: not a cap of the hull
    for (int i = 0; i < 4; ++i) {
      const auto key = sorted(tet_face(v, i));
      const auto it = face_index.find(key);
      if (it != face_index.end()) {
        boundary[n] = i;
        which[n++] = it->second;
        internal = internal || tets_at[key] != 1;
      }
    }
    if (internal || n != 2 || labels[which[0]] != labels[which[1]]) continue;
    // The two boundary faces are opposite corners boundary[0] and boundary[1]; they share the edge of the other
    // two corners; the new faces share the edge of corners boundary[0] and boundary[1].
    int others[2], k = 0;
    for (int i = 0; i < 4; ++i)
      if (i != boundary[0] && i != boundary[1]) others[k++] = i;
    if (std::binary_search(cad_edges.begin(), cad_edges.end(), edge_key(v[others[0]], v[others[1]]))) continue;
    if (std::binary_search(face_edges.begin(), face_edges.end(), edge_key(v[boundary[0]], v[boundary[1]]))) continue;
    if (!select(t)) continue;
    dead_tet[t] = 1;
    dead_face[which[0]] = dead_face[which[1]] = 1;
    // The new boundary faces point where the old ones did: orient each along the old faces' summed normal (the
    // tet's own orientation is not to be trusted when it is flat).
    const auto normal = [&](const std::array<Index, 3>& f) {
      const Point3 &a = mesh.points[f[0]], &b = mesh.points[f[1]], &c = mesh.points[f[2]];
      const Point3 u{b[0] - a[0], b[1] - a[1], b[2] - a[2]}, w{c[0] - a[0], c[1] - a[1], c[2] - a[2]};
      return Point3{u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
    };
    const Point3 n0 = normal(mesh.faces[which[0]]), n1 = normal(mesh.faces[which[1]]);
    const Point3 up{n0[0] + n1[0], n0[1] + n1[1], n0[2] + n1[2]};
    for (int i : others) {
      std::array<Index, 3> f = tet_face(v, i);
      const Point3 nf = normal(f);
      if (nf[0] * up[0] + nf[1] * up[1] + nf[2] * up[2] < 0) std::swap(f[1], f[2]);
      added.push_back({f, mesh.face_facet.empty() ? -1 : mesh.face_facet[which[0]],
                       mesh.face_marker.empty() ? 0 : mesh.face_marker[which[0]]});
    }
    for (Index x : v) touched[x] = 1;
    ++removed;
  }
  if (removed == 0) return 0;
  TetMesh next = mesh;
  next.tets.clear();
  next.tet_region.clear();
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
    if (dead_tet[t]) continue;
    next.tets.push_back(mesh.tets[t]);
    if (!mesh.tet_region.empty()) next.tet_region.push_back(mesh.tet_region[t]);
  }
  next.faces.clear();
  next.face_facet.clear();
  next.face_marker.clear();
  const auto keep_face = [&](const std::array<Index, 3>& f, int facet, int marker) {
    next.faces.push_back(f);
    if (!mesh.face_facet.empty()) next.face_facet.push_back(facet);
    if (!mesh.face_marker.empty()) next.face_marker.push_back(marker);
  };
  for (std::size_t f = 0; f < mesh.faces.size(); ++f)
    if (!dead_face[f])
      keep_face(mesh.faces[f], mesh.face_facet.empty() ? -1 : mesh.face_facet[f],
                mesh.face_marker.empty() ? 0 : mesh.face_marker[f]);
  for (const NewFace& f : added) keep_face(f.v, f.facet, f.marker);
  mesh = std::move(next);
  return removed;
}

namespace {

// Splits edge c-d at its midpoint m: every tetrahedron and every face of mesh.faces around it becomes two, the half
// at c keeping its index (the half at d appended), so indices from before still name the tetrahedra and faces that
// were not split, and so does the TetMesh::edges entry when c-d is one (its half at its first end). Orientation is
// kept: m lies on the edge.
void split_edge_at_midpoint(TetMesh& mesh, Index c, Index d) {
  const Index m = static_cast<Index>(mesh.points.size());
  mesh.points.push_back(midpoint(mesh.points[c], mesh.points[d]));
  if (!mesh.weights.empty()) mesh.weights.push_back(0);
  const std::size_t count = mesh.tets.size();
  for (std::size_t t = 0; t < count; ++t) {
    std::array<Index, 4> near_c = mesh.tets[t], near_d = mesh.tets[t];
    int has = 0;
    for (int i = 0; i < 4; ++i) {
      if (near_c[i] == d) near_c[i] = m, ++has;  // (.., c, .., m): the half at c
      if (near_d[i] == c) near_d[i] = m, ++has;  // (.., m, .., d): the half at d
    }
    if (has != 2) continue;
    mesh.tets[t] = near_c;
    mesh.tets.push_back(near_d);
    if (!mesh.tet_region.empty()) mesh.tet_region.push_back(mesh.tet_region[t]);
  }
  const std::size_t num_faces = mesh.faces.size();
  for (std::size_t f = 0; f < num_faces; ++f) {
    std::array<Index, 3> near_c = mesh.faces[f], near_d = mesh.faces[f];
    int has = 0;
    for (int i = 0; i < 3; ++i) {
      if (near_c[i] == d) near_c[i] = m, ++has;
      if (near_d[i] == c) near_d[i] = m, ++has;
    }
    if (has != 2) continue;
    mesh.faces[f] = near_c;
    mesh.faces.push_back(near_d);
    if (!mesh.face_facet.empty()) mesh.face_facet.push_back(mesh.face_facet[f]);
    if (!mesh.face_marker.empty()) mesh.face_marker.push_back(mesh.face_marker[f]);
  }
  for (std::size_t e = 0, n = mesh.edges.size(); e < n; ++e) {
    if (edge_key(mesh.edges[e][0], mesh.edges[e][1]) != edge_key(c, d)) continue;
    const Index far = mesh.edges[e][0] == c ? d : c;
    mesh.edges[e] = {mesh.edges[e][0] == c ? c : d, m};
    mesh.edges.push_back({m, far});
    if (!mesh.edge_marker.empty()) mesh.edge_marker.push_back(mesh.edge_marker[e]);
  }
}

}  // namespace

std::size_t split_cap_interior_edges(TetMesh& mesh, const std::function<bool(std::size_t)>& select) {
  if (mesh.is_second_order()) throw std::invalid_argument("split_cap_interior_edges: linear meshes only");
  std::vector<std::uint8_t> on_face(mesh.points.size(), 0);
  std::vector<std::uint64_t> face_edges;
  for (const auto& f : mesh.faces)
    for (int k = 0; k < 3; ++k) {
      on_face[f[k]] = 1;
      face_edges.push_back(edge_key(f[k], f[(k + 1) % 3]));
    }
  std::sort(face_edges.begin(), face_edges.end());
  // Caps whose two boundary faces carry one label are remove_boundary_caps's: left alone.
  const std::vector<int> labels = face_labels(mesh);
  std::map<std::array<Index, 3>, int> label_of;
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    std::array<Index, 3> key = mesh.faces[f];
    std::sort(key.begin(), key.end());
    label_of.emplace(key, labels[f]);
  }
  const auto one_label_cap = [&](const std::array<Index, 4>& v) {
    std::vector<int> found;
    for (int i = 0; i < 4; ++i) {
      std::array<Index, 3> key{v[(i + 1) & 3], v[(i + 2) & 3], v[(i + 3) & 3]};
      std::sort(key.begin(), key.end());
      const auto it = label_of.find(key);
      if (it != label_of.end()) found.push_back(it->second);
    }
    return found.size() == 2 && found[0] == found[1];
  };
  std::vector<std::array<Index, 2>> split;
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
    const auto& v = mesh.tets[t];
    if (!on_face[v[0]] || !on_face[v[1]] || !on_face[v[2]] || !on_face[v[3]] || one_label_cap(v)) continue;
    int inside = -1, n = 0;
    for (int k = 0; k < 6; ++k)
      if (!std::binary_search(face_edges.begin(), face_edges.end(), edge_key(v[kTetEdges[k][0]], v[kTetEdges[k][1]])))
        inside = k, ++n;
    if (n != 1 || !select(t)) continue;
    split.push_back({std::min(v[kTetEdges[inside][0]], v[kTetEdges[inside][1]]),
                     std::max(v[kTetEdges[inside][0]], v[kTetEdges[inside][1]])});
  }
  std::sort(split.begin(), split.end());
  split.erase(std::unique(split.begin(), split.end()), split.end());
  for (const auto& [c, d] : split) split_edge_at_midpoint(mesh, c, d);
  return split.size();
}

std::size_t split_flat_face_corners(TetMesh& mesh, const std::function<bool(std::size_t)>& select, double flat_deg) {
  if (mesh.is_second_order()) throw std::invalid_argument("split_flat_face_corners: linear meshes only");
  std::map<std::array<Index, 3>, std::size_t> face_index;
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    std::array<Index, 3> key = mesh.faces[f];
    std::sort(key.begin(), key.end());
    face_index.emplace(key, f);
  }
  const double flat_cos = std::cos(flat_deg * 3.14159265358979323846 / 180);
  std::vector<std::array<Index, 2>> split;
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
    if (!select(t)) continue;
    const auto& v = mesh.tets[t];
    for (int i = 0; i < 4; ++i) {
      std::array<Index, 3> key{v[(i + 1) & 3], v[(i + 2) & 3], v[(i + 3) & 3]};
      std::sort(key.begin(), key.end());
      if (!face_index.count(key)) continue;
      for (int k = 0; k < 3; ++k) {  // the corner at key[k], opposite edge key[k+1]-key[k+2]
        const Point3 &p = mesh.points[key[k]], &a = mesh.points[key[(k + 1) % 3]], &b = mesh.points[key[(k + 2) % 3]];
        const Point3 u{a[0] - p[0], a[1] - p[1], a[2] - p[2]}, w{b[0] - p[0], b[1] - p[1], b[2] - p[2]};
        const double uw = u[0] * w[0] + u[1] * w[1] + u[2] * w[2];
        const double uu = u[0] * u[0] + u[1] * u[1] + u[2] * u[2], ww = w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
        if (uu <= 0 || ww <= 0 || uw >= flat_cos * std::sqrt(uu * ww)) continue;
        split.push_back({std::min(key[(k + 1) % 3], key[(k + 2) % 3]), std::max(key[(k + 1) % 3], key[(k + 2) % 3])});
      }
    }
  }
  std::sort(split.begin(), split.end());
  split.erase(std::unique(split.begin(), split.end()), split.end());
  for (const auto& [c, d] : split) split_edge_at_midpoint(mesh, c, d);
  return split.size();
}

}  // namespace qualmesh
