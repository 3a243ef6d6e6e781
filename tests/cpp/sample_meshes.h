// Small hand-built meshes for the reader and writer tests: Kuhn's 6-tetrahedron cube with two regions and its
// hull triangles (sample_mesh), and the same made second order with mid-nodes at the edge midpoints, plus the
// tetrahedron edges on the cube's 12 edges as marked edges (sample_mesh_quadratic). For the checker and mesher
// tests: the unit cube as a PLC (unit_cube_plc) and Kuhn's split of it (kuhn_unit_cube); boundary_faces of a mesh.
#pragma once

#include <algorithm>
#include <array>
#include <map>
#include <set>
#include <utility>

#include "qualmesh/plc.h"
#include "qualmesh/quality.h"
#include "qualmesh/tet_mesh.h"

namespace qualmesh {

// The unit cube [0, 1]^3: vertex v at (bit 0, bit 1, bit 2) of v, six square facets without markers.
inline Plc unit_cube_plc() {
  Plc plc;
  for (int v = 0; v < 8; ++v) plc.vertices.push_back({double(v & 1), double((v >> 1) & 1), double((v >> 2) & 1)});
  const Index loops[6][4] = {{0, 2, 6, 4}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 5, 7, 6}};
  for (const auto& loop : loops) {
    Facet facet;
    facet.polygons.push_back({loop[0], loop[1], loop[2], loop[3]});
    plc.facets.push_back(facet);
  }
  return plc;
}

// Kuhn's split of unit_cube_plc's cube: the six tetrahedra around the diagonal 0-7, one per permutation of the
// axes, positively oriented.
inline TetMesh kuhn_unit_cube() {
  TetMesh mesh;
  mesh.points = unit_cube_plc().vertices;
  int axes[3] = {0, 1, 2};
  do {
    const Index a = 1u << axes[0];
    const Index b = a | (1u << axes[1]);
    std::array<Index, 4> t{0, a, b, 7};
    if (tet_signed_volume(mesh.points[t[0]], mesh.points[t[1]], mesh.points[t[2]], mesh.points[t[3]]) < 0) {
      std::swap(t[0], t[1]);
    }
    mesh.tets.push_back(t);
  } while (std::next_permutation(axes, axes + 3));
  return mesh;
}

// Kuhn's 6-tetrahedron unit cube, scaled by awkward numbers so that exact coordinate round trips are tested; two
// regions, the 12 hull triangles with the cube face (1..6) as marker and facet index.
inline TetMesh sample_mesh() {
  TetMesh mesh;
  for (int v = 0; v < 8; ++v) {
    mesh.points.push_back({0.1 + (v & 1) / 3.0, -7.25 + ((v >> 1) & 1) * 1e-3 * 3.3, 1e10 + ((v >> 2) & 1) * 0.7});
  }
  int axes[3] = {0, 1, 2};
  do {
    const Index a = 1u << axes[0];
    const Index b = a | (1u << axes[1]);
    std::array<Index, 4> t{0, a, b, 7};
    const auto& p = mesh.points;
    if (tet_signed_volume(p[t[0]], p[t[1]], p[t[2]], p[t[3]]) < 0) std::swap(t[0], t[1]);
    mesh.tets.push_back(t);
  } while (std::next_permutation(axes, axes + 3));
  mesh.tet_region = {1, 1, 1, 7, 7, 7};
  // Hull triangles: for each tetrahedron face whose vertices share a coordinate bit.
  for (const auto& t : mesh.tets) {
    static const int kFaces[4][3] = {{1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}};
    for (const auto& f : kFaces) {
      const Index a = t[f[0]], b = t[f[1]], c = t[f[2]];
      for (int bit = 0; bit < 3; ++bit) {
        for (int value = 0; value < 2; ++value) {
          const auto has = [&](Index v) { return static_cast<int>((v >> bit) & 1) == value; };
          if (has(a) && has(b) && has(c)) {
            mesh.faces.push_back({a, b, c});
            mesh.face_facet.push_back(2 * bit + value);
            mesh.face_marker.push_back(2 * bit + value + 1);
          }
        }
      }
    }
  }
  return mesh;
}

// Marks the tetrahedron edges along the cube's edges (the two vertices differ in one coordinate bit) with marker
// 1 + 4 * bit + (the other two bits), then adds a mid-node at the midpoint of every tetrahedron edge (shared) and
// fills tet_mid, face_mid and edge_mid.
inline TetMesh sample_mesh_quadratic(bool with_edges = true) {
  TetMesh mesh = sample_mesh();
  std::map<std::pair<Index, Index>, Index> mid;
  const auto mid_of = [&](Index a, Index b) {
    const auto key = std::minmax(a, b);
    const auto it = mid.find(key);
    if (it != mid.end()) return it->second;
    const Point3& p = mesh.points[a];
    const Point3& q = mesh.points[b];
    mesh.points.push_back({(p[0] + q[0]) / 2, (p[1] + q[1]) / 2, (p[2] + q[2]) / 2});
    return mid[key] = static_cast<Index>(mesh.points.size() - 1);
  };
  for (const auto& t : mesh.tets) {
    std::array<Index, 6> m{};
    for (int k = 0; k < 6; ++k) m[k] = mid_of(t[kTetEdges[k][0]], t[kTetEdges[k][1]]);
    mesh.tet_mid.push_back(m);
    for (int k = 0; k < 6; ++k) {
      const Index a = t[kTetEdges[k][0]], b = t[kTetEdges[k][1]];
      const Index x = a ^ b;
      if (!with_edges || (x != 1 && x != 2 && x != 4)) continue;
      const int bit = x == 1 ? 0 : x == 2 ? 1 : 2;
      const std::array<Index, 2> e{std::min(a, b), std::max(a, b)};
      if (std::find(mesh.edges.begin(), mesh.edges.end(), e) != mesh.edges.end()) continue;
      const Index rest = a & ~x;
      int others = 0, shift = 0;
      for (int c = 0; c < 3; ++c) {
        if (c != bit) others |= static_cast<int>((rest >> c) & 1) << shift++;
      }
      mesh.edges.push_back(e);
      mesh.edge_marker.push_back(1 + 4 * bit + others);
    }
  }
  for (const auto& f : mesh.faces) mesh.face_mid.push_back({mid_of(f[0], f[1]), mid_of(f[1], f[2]), mid_of(f[2], f[0])});
  for (const auto& e : mesh.edges) mesh.edge_mid.push_back(mid_of(e[0], e[1]));
  return mesh;
}

// Boundary faces of a tetrahedral mesh: the faces of exactly one tetrahedron (sorted ids).
inline std::set<std::array<Index, 3>> boundary_faces(const TetMesh& m) {
  std::map<std::array<Index, 3>, int> count;
  for (const auto& t : m.tets)
    for (int i = 0; i < 4; ++i) {
      std::array<Index, 3> f{t[(i + 1) & 3], t[(i + 2) & 3], t[(i + 3) & 3]};
      std::sort(f.begin(), f.end());
      ++count[f];
    }
  std::set<std::array<Index, 3>> out;
  for (const auto& kv : count)
    if (kv.second == 1) out.insert(kv.first);
  return out;
}

}  // namespace qualmesh
