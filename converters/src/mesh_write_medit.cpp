// Medit .mesh writer (INRIA's ASCII format, libMeshb keywords, as read by Medit, MMG, Gmsh and meshio): Vertices
// with reference 0; Edges (reference = edge marker, Edge<e>), Triangles (reference = face label of face_labels(),
// Face<m>) and Tetrahedra (reference = region attribute, Solid<r>); for a second-order mesh EdgesP2, TrianglesP2 and
// TetrahedraP2 instead, each the corners followed by the mid-nodes: edges (1,2) (2,3) (3,1) for a triangle, and
// (1,2) (2,3) (1,3) (1,4) (2,4) (3,4) for a tetrahedron (TetMesh's and VTK's order; Gmsh 4.8's own .mesh export of
// a tet10 writes its mid-nodes in this order too, nodes 9 and 10 swapped against its .msh). meshio 5 reads only
// the linear keywords. 1-based indices; tetrahedra positively oriented, as MMG expects.
#include <ostream>

#include "atomic_file.h"
#include "mesh_groups.h"
#include "mesh_io_internal.h"

namespace qualmesh::io {

void write_medit(const TetMesh& mesh, const std::string& path) {
  const std::vector<int> labels = face_labels(mesh);
  const MidNodes mids = mid_nodes(mesh);
  const bool p2 = mids.tet != nullptr;
  write_file_atomically(path, [&](std::ostream& out) {
    out << "MeshVersionFormatted 2\n\nDimension 3\n\nVertices\n" << mesh.points.size() << '\n';
    for (const Point3& p : mesh.points) {
      put_double(out, p[0]);
      out << ' ';
      put_double(out, p[1]);
      out << ' ';
      put_double(out, p[2]);
      out << " 0\n";
    }
    if (!mesh.edges.empty()) {
      out << (p2 ? "\nEdgesP2\n" : "\nEdges\n") << mesh.edges.size() << '\n';
      for (std::size_t e = 0; e < mesh.edges.size(); ++e) {
        out << mesh.edges[e][0] + 1 << ' ' << mesh.edges[e][1] + 1;
        if (p2) out << ' ' << mids.edge[e] + 1;
        out << ' ' << (e < mesh.edge_marker.size() ? mesh.edge_marker[e] : 0) << '\n';
      }
    }
    if (!mesh.faces.empty()) {
      out << (p2 ? "\nTrianglesP2\n" : "\nTriangles\n") << mesh.faces.size() << '\n';
      for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
        const auto& v = mesh.faces[f];
        out << v[0] + 1 << ' ' << v[1] + 1 << ' ' << v[2] + 1;
        if (p2) {
          for (Index m : mids.face[f]) out << ' ' << m + 1;
        }
        out << ' ' << labels[f] << '\n';
      }
    }
    out << (p2 ? "\nTetrahedraP2\n" : "\nTetrahedra\n") << mesh.tets.size() << '\n';
    for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
      const auto& v = mesh.tets[t];
      out << v[0] + 1 << ' ' << v[1] + 1 << ' ' << v[2] + 1 << ' ' << v[3] + 1;
      if (p2) {
        for (Index m : (*mids.tet)[t]) out << ' ' << m + 1;
      }
      out << ' ' << tet_region_of(mesh, t) << '\n';
    }
    out << "\nEnd\n";
  });
}

}  // namespace qualmesh::io
