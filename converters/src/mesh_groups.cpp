// Group membership, completed second-order fields and short number formatting for the writers (mesh_groups.h).
#include "mesh_groups.h"

#include <algorithm>
#include <charconv>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <unordered_map>

#include "mesh_io_internal.h"
#include "qualmesh/error.h"

namespace qualmesh::io {
namespace {

std::uint64_t edge_key(Index a, Index b) {
  if (a > b) std::swap(a, b);
  return (static_cast<std::uint64_t>(a) << 32) | static_cast<std::uint64_t>(b);
}

template <class T>
void sort_unique(std::vector<T>& v) {
  std::sort(v.begin(), v.end());
  v.erase(std::unique(v.begin(), v.end()), v.end());
}

}  // namespace

MidNodes mid_nodes(const TetMesh& mesh) {
  MidNodes mids;
  if (mesh.tet_mid.empty()) return mids;
  if (mesh.tet_mid.size() != mesh.tets.size()) {
    throw InputError(ErrorCode::Parse, "second-order mesh: " + std::to_string(mesh.tet_mid.size()) +
                                           " tet mid-node entries for " + std::to_string(mesh.tets.size()) + " tets");
  }
  mids.tet = &mesh.tet_mid;
  const bool faces_given = mesh.face_mid.size() == mesh.faces.size();
  const bool edges_given = mesh.edge_mid.size() == mesh.edges.size();
  if (faces_given) mids.face = mesh.face_mid;
  if (edges_given) mids.edge = mesh.edge_mid;
  if (faces_given && edges_given) return mids;
  std::unordered_map<std::uint64_t, Index> mid_of_edge;
  mid_of_edge.reserve(mesh.tets.size() * 2);
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
    for (int k = 0; k < 6; ++k) {
      mid_of_edge.emplace(edge_key(mesh.tets[t][kTetEdges[k][0]], mesh.tets[t][kTetEdges[k][1]]), mesh.tet_mid[t][k]);
    }
  }
  const auto find = [&](Index a, Index b, const char* what, std::size_t i) {
    const auto it = mid_of_edge.find(edge_key(a, b));
    if (it == mid_of_edge.end()) {
      throw InputError(ErrorCode::Parse, std::string("second-order mesh: ") + what + " " + std::to_string(i) +
                                             " has an edge that no tetrahedron has (no mid-node)");
    }
    return it->second;
  };
  if (!faces_given) {
    mids.face.resize(mesh.faces.size());
    for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
      const auto& v = mesh.faces[f];
      for (int k = 0; k < 3; ++k) mids.face[f][k] = find(v[k], v[(k + 1) % 3], "face", f);
    }
  }
  if (!edges_given) {
    mids.edge.resize(mesh.edges.size());
    for (std::size_t e = 0; e < mesh.edges.size(); ++e) mids.edge[e] = find(mesh.edges[e][0], mesh.edges[e][1], "edge", e);
  }
  return mids;
}

MeshGroups mesh_groups(const TetMesh& mesh, const MidNodes& mids) {
  MeshGroups groups;
  const std::vector<int> regions = tet_region_labels(mesh);
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) groups.solids[regions[t]].push_back(t);
  const std::vector<int> labels = face_labels(mesh);
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    groups.faces[labels[f]].push_back(f);
    auto& nodes = groups.face_nodes[labels[f]];
    nodes.insert(nodes.end(), mesh.faces[f].begin(), mesh.faces[f].end());
    if (!mids.face.empty()) nodes.insert(nodes.end(), mids.face[f].begin(), mids.face[f].end());
  }
  for (std::size_t e = 0; e < mesh.edges.size(); ++e) {
    const int marker = e < mesh.edge_marker.size() ? mesh.edge_marker[e] : 0;
    groups.edges[marker].push_back(e);
    auto& nodes = groups.edge_nodes[marker];
    nodes.insert(nodes.end(), mesh.edges[e].begin(), mesh.edges[e].end());
    if (!mids.edge.empty()) nodes.push_back(mids.edge[e]);
  }
  for (auto& [label, nodes] : groups.face_nodes) sort_unique(nodes);
  for (auto& [label, nodes] : groups.edge_nodes) sort_unique(nodes);
  return groups;
}

void renumber_corners_first(TetMesh& mesh) {
  const std::size_t n = mesh.points.size();
  std::vector<char> corner(n, 0);
  for (const auto& t : mesh.tets) for (Index v : t) corner[v] = 1;
  for (const auto& f : mesh.faces) for (Index v : f) corner[v] = 1;
  for (const auto& e : mesh.edges) for (Index v : e) corner[v] = 1;
  std::vector<Index> new_index(n);
  Index next = 0;
  for (int pass = 1; pass >= 0; --pass) {
    for (std::size_t i = 0; i < n; ++i) {
      if (corner[i] == pass) new_index[i] = next++;
    }
  }
  bool identity = true;
  for (std::size_t i = 0; i < n && identity; ++i) identity = new_index[i] == i;
  if (identity) return;
  std::vector<Point3> points(n);
  for (std::size_t i = 0; i < n; ++i) points[new_index[i]] = mesh.points[i];
  mesh.points = std::move(points);
  if (mesh.weights.size() == n) {
    std::vector<double> weights(n);
    for (std::size_t i = 0; i < n; ++i) weights[new_index[i]] = mesh.weights[i];
    mesh.weights = std::move(weights);
  }
  for (auto& t : mesh.tets) for (Index& v : t) v = new_index[v];
  for (auto& f : mesh.faces) for (Index& v : f) v = new_index[v];
  for (auto& e : mesh.edges) for (Index& v : e) v = new_index[v];
  for (auto& t : mesh.tet_mid) for (Index& v : t) v = new_index[v];
  for (auto& f : mesh.face_mid) for (Index& v : f) v = new_index[v];
  for (Index& v : mesh.edge_mid) v = new_index[v];
}

std::string short_double(double value) {
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  std::size_t length = static_cast<std::size_t>(result.ptr - buffer);
  // Fixed notation of a number like 1e22 can come out longer than 20 characters; %g switches to an exponent.
  for (int digits = 17; length > 20 && digits > 0; --digits) {
    length = static_cast<std::size_t>(std::snprintf(buffer, sizeof buffer, "%.*g", digits, value));
  }
  return std::string(buffer, length);
}

void put_short_double(std::ostream& out, double value) { out << short_double(value); }

template <class T>
static void put_lines(std::ostream& out, const std::vector<T>& ids, std::size_t per_line) {
  for (std::size_t i = 0; i < ids.size(); ++i) {
    out << ids[i] + 1 << ((i % per_line == per_line - 1 || i + 1 == ids.size()) ? "\n" : ", ");
  }
}

void put_id_lines(std::ostream& out, const std::vector<Index>& ids, std::size_t per_line) { put_lines(out, ids, per_line); }
void put_id_lines(std::ostream& out, const std::vector<std::size_t>& ids, std::size_t per_line) {
  put_lines(out, ids, per_line);
}

}  // namespace qualmesh::io
