// Abaqus / CalculiX .inp writer (Abaqus Keywords Reference; CalculiX 2.20 manual, sections 6.2.33 C3D4/C3D10 and 7
// *NODE, *ELEMENT, *NSET, *ELSET, *SURFACE):
//   *NODE, NSET=NALL                       every node, corners first, then mid-edge nodes;
//   *ELEMENT, TYPE=C3D4|C3D10, ELSET=Solid<r>   one block per region label r (tet_region_label);
//   *ELSET, ELSET=EALL                     every element;
//   *NSET, NSET=Face<m>                    the nodes (mid-nodes included) of the faces with label m (face_labels);
//   *NSET, NSET=Edge<e>                    the nodes of the edges with marker e;
//   *SURFACE, NAME=Face<m>, TYPE=ELEMENT   "element, S<side>" for each face of label m that is a tetrahedron face.
// Node order: C3D4 is positively oriented, (n2-n1) x (n3-n1) . (n4-n1) > 0, as QualMesh's tetrahedra are
// (FREECAD.md: C3D4 = SMESH[1,0,2,3], SMESH's tetrahedron being negative); C3D10 nodes 5..10 are the mid-nodes of
// edges 1-2, 2-3, 1-3, 1-4, 2-4, 3-4, which is TetMesh::tet_mid's order. Faces of C3D4 and C3D10 (by corners):
// S1 = 1-2-3, S2 = 1-4-2, S3 = 2-4-3, S4 = 3-4-1.
// Numbers: CalculiX reads each field of a data line with a 20-character format, so coordinates are written in at
// most 20 characters (short_double: at least 14 significant digits); ccx 2.20 failed with "*ERROR reading *NODE"
// on 22-character fields. Data lines hold at most 16 entries (CalculiX's limit) and stay under its 132 columns:
// element lines have 5 or 11 entries, set lines 8.
#include <algorithm>
#include <map>
#include <ostream>

#include "atomic_file.h"
#include "mesh_groups.h"
#include "mesh_io_internal.h"

namespace qualmesh::io {
namespace {

std::array<Index, 3> sorted_face(Index a, Index b, Index c) {
  std::array<Index, 3> f{a, b, c};
  std::sort(f.begin(), f.end());
  return f;
}

}  // namespace

// C3D4 / C3D10 side k+1 is made of these corners (0-based).
static const int kAbaqusSides[4][3] = {{0, 1, 2}, {0, 3, 1}, {1, 3, 2}, {2, 3, 0}};

void write_abaqus(const TetMesh& mesh, const std::string& path) {
  const MidNodes mids = mid_nodes(mesh);
  const MeshGroups groups = mesh_groups(mesh, mids);
  const bool quadratic = mids.tet != nullptr;
  // Face -> (element id, side) of a tetrahedron that has it; (0, 0) when none has it.
  std::vector<std::pair<std::size_t, int>> face_sides(mesh.faces.size(), {0, 0});
  if (!mesh.faces.empty()) {
    std::map<std::array<Index, 3>, std::pair<std::size_t, int>> side_of;
    for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
      const auto& v = mesh.tets[t];
      for (int s = 0; s < 4; ++s) {
        side_of.emplace(sorted_face(v[kAbaqusSides[s][0]], v[kAbaqusSides[s][1]], v[kAbaqusSides[s][2]]),
                        std::make_pair(t + 1, s + 1));
      }
    }
    for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
      const auto& v = mesh.faces[f];
      const auto it = side_of.find(sorted_face(v[0], v[1], v[2]));
      if (it != side_of.end()) face_sides[f] = it->second;
    }
  }

  write_file_atomically(path, [&](std::ostream& out) {
    out << "*HEADING\nQualMesh tetrahedral mesh (" << (quadratic ? "C3D10" : "C3D4")
        << "); sets Solid<n>, Face<n>, Edge<n>, EALL, NALL\n*NODE, NSET=NALL\n";
    for (std::size_t i = 0; i < mesh.points.size(); ++i) {
      const Point3& p = mesh.points[i];
      out << i + 1 << ", " << short_double(p[0]) << ", " << short_double(p[1]) << ", " << short_double(p[2]) << '\n';
    }
    for (const auto& [label, members] : groups.solids) {
      out << "*ELEMENT, TYPE=" << (quadratic ? "C3D10" : "C3D4") << ", ELSET=" << group_name("Solid", label) << '\n';
      for (std::size_t t : members) {
        const auto& v = mesh.tets[t];
        out << t + 1 << ", " << v[0] + 1 << ", " << v[1] + 1 << ", " << v[2] + 1 << ", " << v[3] + 1;
        if (quadratic) {
          for (Index m : (*mids.tet)[t]) out << ", " << m + 1;
        }
        out << '\n';
      }
    }
    if (!mesh.tets.empty()) {
      out << "*ELSET, ELSET=EALL\n";
      std::vector<std::size_t> all(mesh.tets.size());
      for (std::size_t t = 0; t < all.size(); ++t) all[t] = t;
      put_id_lines(out, all, 8);
    }
    for (const auto& [label, nodes] : groups.face_nodes) {
      out << "*NSET, NSET=" << group_name("Face", label) << '\n';
      put_id_lines(out, nodes, 8);
    }
    for (const auto& [marker, nodes] : groups.edge_nodes) {
      out << "*NSET, NSET=" << group_name("Edge", marker) << '\n';
      put_id_lines(out, nodes, 8);
    }
    for (const auto& [label, members] : groups.faces) {
      bool any = false;
      for (std::size_t f : members) any = any || face_sides[f].first != 0;
      if (!any) continue;
      out << "*SURFACE, NAME=" << group_name("Face", label) << ", TYPE=ELEMENT\n";
      for (std::size_t f : members) {
        if (face_sides[f].first != 0) out << face_sides[f].first << ", S" << face_sides[f].second << '\n';
      }
    }
  });
}

}  // namespace qualmesh::io
