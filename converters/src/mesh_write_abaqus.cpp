// Abaqus / CalculiX .inp writer: *NODE (NSET=NALL), one *ELEMENT block TYPE=C3D4 per region with ELSET=Region<attr>
// (RegionM<n> for a negative attribute), ELSET=EALL with every element, and one element-based *SURFACE Face<m>
// per facet label (face_labels()) so that loads and supports can be put on input facets.
// Node order: CalculiX C3D4 is positively oriented ((n2-n1) x (n3-n1) . (n4-n1) > 0; FREECAD.md: C3D4 =
// SMESH[1,0,2,3], SMESH's tetrahedron being negative), as QualMesh's tetrahedra are, so nodes are written as they
// are. C3D4 faces: S1 = 1-2-3, S2 = 1-4-2, S3 = 2-4-3, S4 = 3-4-1 (CalculiX manual, section 6.2.x).
#include <algorithm>
#include <map>
#include <ostream>

#include "atomic_file.h"
#include "mesh_io_internal.h"

namespace qualmesh::io {
namespace {

std::string set_name(const char* prefix, int value) {
  return std::string(prefix) + (value < 0 ? "M" + std::to_string(-static_cast<long long>(value)) : std::to_string(value));
}

std::array<Index, 3> sorted_face(Index a, Index b, Index c) {
  std::array<Index, 3> f{a, b, c};
  std::sort(f.begin(), f.end());
  return f;
}

}  // namespace

void write_abaqus(const TetMesh& mesh, const std::string& path) {
  const std::vector<int> labels = face_labels(mesh);
  // Boundary face -> (element id, side) of a tetrahedron that has it.
  std::vector<std::pair<std::size_t, int>> face_sides(mesh.faces.size(), {0, 0});
  if (!mesh.faces.empty()) {
    static const int kSides[4][3] = {{0, 1, 2}, {0, 3, 1}, {1, 3, 2}, {2, 3, 0}};
    std::map<std::array<Index, 3>, std::pair<std::size_t, int>> side_of;
    for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
      const auto& v = mesh.tets[t];
      for (int s = 0; s < 4; ++s) {
        side_of.emplace(sorted_face(v[kSides[s][0]], v[kSides[s][1]], v[kSides[s][2]]), std::make_pair(t + 1, s + 1));
      }
    }
    for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
      const auto& v = mesh.faces[f];
      const auto it = side_of.find(sorted_face(v[0], v[1], v[2]));
      if (it != side_of.end()) face_sides[f] = it->second;
    }
  }

  write_file_atomically(path, [&](std::ostream& out) {
    out << "*HEADING\nQualMesh tetrahedral mesh\n*NODE, NSET=NALL\n";
    for (std::size_t i = 0; i < mesh.points.size(); ++i) {
      const Point3& p = mesh.points[i];
      out << i + 1 << ", ";
      put_double(out, p[0]);
      out << ", ";
      put_double(out, p[1]);
      out << ", ";
      put_double(out, p[2]);
      out << '\n';
    }
    std::map<int, std::vector<std::size_t>> tets_by_region;
    for (std::size_t t = 0; t < mesh.tets.size(); ++t) tets_by_region[tet_region_of(mesh, t)].push_back(t);
    for (const auto& [region, members] : tets_by_region) {
      out << "*ELEMENT, TYPE=C3D4, ELSET=" << set_name("Region", region) << '\n';
      for (std::size_t t : members) {
        const auto& v = mesh.tets[t];
        out << t + 1 << ", " << v[0] + 1 << ", " << v[1] + 1 << ", " << v[2] + 1 << ", " << v[3] + 1 << '\n';
      }
    }
    if (!mesh.tets.empty()) {
      out << "*ELSET, ELSET=EALL\n";
      for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
        out << t + 1 << ((t % 16 == 15 || t + 1 == mesh.tets.size()) ? "\n" : ", ");
      }
    }
    std::map<int, std::vector<std::size_t>> faces_by_label;
    for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
      if (face_sides[f].first != 0) faces_by_label[labels[f]].push_back(f);
    }
    for (const auto& [label, members] : faces_by_label) {
      out << "*SURFACE, NAME=" << set_name("Face", label) << ", TYPE=ELEMENT\n";
      for (std::size_t f : members) out << face_sides[f].first << ", S" << face_sides[f].second << '\n';
    }
  });
}

}  // namespace qualmesh::io
