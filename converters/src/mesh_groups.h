// Private helpers of the writers that carry groups (tet_mesh.h: Solid<r>, Face<m>, Edge<e>): which elements and
// nodes each group holds, the second-order fields completed from the tetrahedra when a caller left the face or edge
// mid-nodes out, and numbers short enough for fixed-width readers (CalculiX reads at most 20 characters a field).
#pragma once

#include <array>
#include <map>
#include <ostream>
#include <string>
#include <vector>

#include "qualmesh/tet_mesh.h"

namespace qualmesh::io {

// The elements and nodes of every group, keyed by label, sorted by label; element and node lists sorted (0-based).
struct MeshGroups {
  std::map<int, std::vector<std::size_t>> solids;      // region label -> tetrahedra
  std::map<int, std::vector<std::size_t>> faces;       // face label -> faces
  std::map<int, std::vector<Index>> face_nodes;        // face label -> nodes of those faces, mid-nodes included
  std::map<int, std::vector<std::size_t>> edges;       // edge marker -> edges
  std::map<int, std::vector<Index>> edge_nodes;        // edge marker -> nodes of those edges, mid-nodes included
};

// Second-order view of a mesh: face_mid and edge_mid given, or found from the tetrahedra's mid-nodes (by edge).
// For a linear mesh every vector is empty. Throws InputError(Parse) when tet_mid's size is not the number of tets
// or a face / edge of a second-order mesh is not an edge of any tetrahedron.
struct MidNodes {
  const std::vector<std::array<Index, 6>>* tet = nullptr;
  std::vector<std::array<Index, 3>> face;
  std::vector<Index> edge;
};
MidNodes mid_nodes(const TetMesh& mesh);

MeshGroups mesh_groups(const TetMesh& mesh, const MidNodes& mids);

// Renumbers the points of a mesh read from a file so that the corners of tets, faces and edges come first (in
// their old order), then every other node (mid-nodes, unused nodes), as TetMesh wants; updates every index field.
void renumber_corners_first(TetMesh& mesh);

// Writes `value` in at most 20 characters with as many significant digits as fit (the shortest exact form when it
// fits: at most 17 digits; at least 14 digits for any finite double). CalculiX 2.20 refuses longer fields.
void put_short_double(std::ostream& out, double value);
std::string short_double(double value);

// Writes `ids` (0-based, written +1) as comma-separated data lines of at most `per_line` entries.
void put_id_lines(std::ostream& out, const std::vector<Index>& ids, std::size_t per_line);
void put_id_lines(std::ostream& out, const std::vector<std::size_t>& ids, std::size_t per_line);

}  // namespace qualmesh::io
