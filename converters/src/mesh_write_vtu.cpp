// VTU writer: VTK XML UnstructuredGrid, ASCII, linear tetrahedra (VTK_TETRA = 10, positive orientation as QualMesh
// writes them). Cell data: "region" (Int32), and per-tetrahedron quality "min_dihedral_deg" and "radius_edge" (Float64)
// so that ParaView can colour by quality directly. Point data: "weight" (Float64, the paper's squared radius X^2,
// TetMesh::weights) when the mesh has weights, so that `qualmesh check` can test the weighted Delaunay property of a
// pumped mesh. Boundary faces are not written (VTU cells of mixed dimension confuse most viewers); the checker finds
// them again from the tetrahedra.
#include <ostream>

#include "atomic_file.h"
#include "mesh_io_internal.h"
#include "qualmesh/quality.h"

namespace qualmesh::io {

void write_vtu(const TetMesh& mesh, const std::string& path) {
  write_file_atomically(path, [&mesh](std::ostream& out) {
    const std::size_t num_tets = mesh.tets.size();
    out << "<?xml version=\"1.0\"?>\n"
           "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" "
           "header_type=\"UInt64\">\n"
           "  <UnstructuredGrid>\n"
        << "    <Piece NumberOfPoints=\"" << mesh.points.size() << "\" NumberOfCells=\"" << num_tets << "\">\n"
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
    for (const auto& t : mesh.tets) out << "          " << t[0] << ' ' << t[1] << ' ' << t[2] << ' ' << t[3] << '\n';
    out << "        </DataArray>\n"
           "        <DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
    for (std::size_t t = 0; t < num_tets; ++t) out << "          " << 4 * (t + 1) << '\n';
    out << "        </DataArray>\n"
           "        <DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
    for (std::size_t t = 0; t < num_tets; ++t) out << "          10\n";
    out << "        </DataArray>\n"
           "      </Cells>\n";
    if (!mesh.weights.empty()) {
      out << "      <PointData Scalars=\"weight\">\n"
             "        <DataArray type=\"Float64\" Name=\"weight\" format=\"ascii\">\n";
      for (double w : mesh.weights) {
        out << "          ";
        put_double(out, w);
        out << '\n';
      }
      out << "        </DataArray>\n"
             "      </PointData>\n";
    }
    out << "      <CellData Scalars=\"region\">\n"
           "        <DataArray type=\"Int32\" Name=\"region\" format=\"ascii\">\n";
    for (std::size_t t = 0; t < num_tets; ++t) out << "          " << tet_region_of(mesh, t) << '\n';
    std::vector<double> min_dihedral_deg(num_tets), radius_edge(num_tets);
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
