// Medit .mesh writer (INRIA's ASCII format, as read by Medit, MMG, Gmsh and meshio): Vertices with reference 0,
// Triangles with the facet marker as reference (face_labels()), Tetrahedra with the region as reference.
// 1-based indices; tetrahedra positively oriented, as MMG expects.
#include <ostream>

#include "atomic_file.h"
#include "mesh_io_internal.h"

namespace qualmesh::io {

void write_medit(const TetMesh& mesh, const std::string& path) {
  const std::vector<int> labels = face_labels(mesh);
  write_file_atomically(path, [&mesh, &labels](std::ostream& out) {
    out << "MeshVersionFormatted 2\n\nDimension 3\n\nVertices\n" << mesh.points.size() << '\n';
    for (const Point3& p : mesh.points) {
      put_double(out, p[0]);
      out << ' ';
      put_double(out, p[1]);
      out << ' ';
      put_double(out, p[2]);
      out << " 0\n";
    }
    if (!mesh.faces.empty()) {
      out << "\nTriangles\n" << mesh.faces.size() << '\n';
      for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
        const auto& v = mesh.faces[f];
        out << v[0] + 1 << ' ' << v[1] + 1 << ' ' << v[2] + 1 << ' ' << labels[f] << '\n';
      }
    }
    out << "\nTetrahedra\n" << mesh.tets.size() << '\n';
    for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
      const auto& v = mesh.tets[t];
      out << v[0] + 1 << ' ' << v[1] + 1 << ' ' << v[2] + 1 << ' ' << v[3] + 1 << ' ' << tet_region_of(mesh, t)
          << '\n';
    }
    out << "\nEnd\n";
  });
}

}  // namespace qualmesh::io
