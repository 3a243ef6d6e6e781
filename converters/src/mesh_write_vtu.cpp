// VTU writer: VTK XML UnstructuredGrid, ASCII (VTK file formats, "XML File Formats"). Cells: the tetrahedra first
// (VTK_TETRA = 10, or VTK_QUADRATIC_TETRA = 24 whose nodes 4..9 are the mid-nodes of edges (0,1) (1,2) (0,2) (0,3)
// (1,3) (2,3), TetMesh::tet_mid's order; positive orientation as QualMesh writes them), then the boundary and internal
// faces (VTK_TRIANGLE = 5, or VTK_QUADRATIC_TRIANGLE = 22 with the mid-nodes of (0,1) (1,2) (2,0)). Cell data:
// "region" (Int32: the tetrahedron's region attribute, 0 for faces), "face_id" (Int32: the face label of
// face_labels(), i.e. the Face<m> it belongs to, 0 for tetrahedra), and per-tetrahedron quality "min_dihedral_deg"
// and "radius_edge" (Float64, of the straight tetrahedron; 0 for faces) so that ParaView can colour by quality and
// threshold on face_id to see one CAD face. Point data: "weight" (Float64, the paper's squared radius X^2,
// TetMesh::weights; 0 for mid-nodes) when the mesh has weights, so that `qualmesh check` can test the weighted
// Delaunay property of a pumped mesh.
#include <ostream>

#include "atomic_file.h"
#include "mesh_groups.h"
#include "mesh_io_internal.h"
#include "qualmesh/quality.h"

namespace qualmesh::io {

void write_vtu(const TetMesh& mesh, const std::string& path) {
  const MidNodes mids = mid_nodes(mesh);
  const bool quadratic = mids.tet != nullptr;
  const std::vector<int> labels = face_labels(mesh);
  write_file_atomically(path, [&](std::ostream& out) {
    const std::size_t num_tets = mesh.tets.size(), num_faces = mesh.faces.size(), num_cells = num_tets + num_faces;
    out << "<?xml version=\"1.0\"?>\n"
           "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" "
           "header_type=\"UInt64\">\n"
           "  <UnstructuredGrid>\n"
        << "    <Piece NumberOfPoints=\"" << mesh.points.size() << "\" NumberOfCells=\"" << num_cells << "\">\n"
        << "      <Points>\n"
           "        <DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n";
    for (const Point3& p : mesh.points) {
      out << "          ";
      put_double(out, p[0]);
      out << ' ';
      put_double(out, p[1]);
      out << ' ';
      put_double(out, p[2]);
      out << '\n';
    }
    out << "        </DataArray>\n"
           "      </Points>\n"
           "      <Cells>\n"
           "        <DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n";
    for (std::size_t t = 0; t < num_tets; ++t) {
      const auto& v = mesh.tets[t];
      out << "          " << v[0] << ' ' << v[1] << ' ' << v[2] << ' ' << v[3];
      if (quadratic) {
        for (Index m : (*mids.tet)[t]) out << ' ' << m;
      }
      out << '\n';
    }
    for (std::size_t f = 0; f < num_faces; ++f) {
      const auto& v = mesh.faces[f];
      out << "          " << v[0] << ' ' << v[1] << ' ' << v[2];
      if (quadratic) {
        for (Index m : mids.face[f]) out << ' ' << m;
      }
      out << '\n';
    }
    out << "        </DataArray>\n"
           "        <DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
    std::size_t offset = 0;
    for (std::size_t c = 0; c < num_cells; ++c) {
      offset += c < num_tets ? (quadratic ? 10 : 4) : (quadratic ? 6 : 3);
      out << "          " << offset << '\n';
    }
    out << "        </DataArray>\n"
           "        <DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
    for (std::size_t c = 0; c < num_cells; ++c) {
      out << "          " << (c < num_tets ? (quadratic ? 24 : 10) : (quadratic ? 22 : 5)) << '\n';
    }
    out << "        </DataArray>\n"
           "      </Cells>\n";
    if (!mesh.weights.empty()) {
      out << "      <PointData Scalars=\"weight\">\n"
             "        <DataArray type=\"Float64\" Name=\"weight\" format=\"ascii\">\n";
      for (std::size_t i = 0; i < mesh.points.size(); ++i) {
        out << "          ";
        put_double(out, i < mesh.weights.size() ? mesh.weights[i] : 0.0);
        out << '\n';
      }
      out << "        </DataArray>\n"
             "      </PointData>\n";
    }
    out << "      <CellData Scalars=\"region\">\n"
           "        <DataArray type=\"Int32\" Name=\"region\" format=\"ascii\">\n";
    for (std::size_t t = 0; t < num_tets; ++t) out << "          " << tet_region_of(mesh, t) << '\n';
    for (std::size_t f = 0; f < num_faces; ++f) out << "          0\n";
    out << "        </DataArray>\n"
           "        <DataArray type=\"Int32\" Name=\"face_id\" format=\"ascii\">\n";
    for (std::size_t t = 0; t < num_tets; ++t) out << "          0\n";
    for (std::size_t f = 0; f < num_faces; ++f) out << "          " << labels[f] << '\n';
    std::vector<double> min_dihedral_deg(num_cells, 0.0), radius_edge(num_cells, 0.0);
    for (std::size_t t = 0; t < num_tets; ++t) {
      const auto& v = mesh.tets[t];
      const TetQuality q = tet_quality(mesh.points[v[0]], mesh.points[v[1]], mesh.points[v[2]], mesh.points[v[3]]);
      min_dihedral_deg[t] = q.min_dihedral_deg;
      radius_edge[t] = q.radius_edge;
    }
    const auto put_array = [&out](const char* name, const std::vector<double>& values) {
      out << "        </DataArray>\n"
          << "        <DataArray type=\"Float64\" Name=\"" << name << "\" format=\"ascii\">\n";
      for (double value : values) {
        out << "          ";
        put_double(out, value);
        out << '\n';
      }
    };
    put_array("min_dihedral_deg", min_dihedral_deg);
    put_array("radius_edge", radius_edge);
    out << "        </DataArray>\n"
           "      </CellData>\n"
           "    </Piece>\n"
           "  </UnstructuredGrid>\n"
           "</VTKFile>\n";
  });
}

}  // namespace qualmesh::io
