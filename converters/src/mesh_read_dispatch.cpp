// read_tet_mesh: picks the reader by extension, then checks what every reader must guarantee (indices in range,
// finite coordinates, one region per tetrahedron).
#include <cmath>
#include <fstream>
#include <sstream>

#include "file_read.h"
#include "mesh_io_internal.h"
#include "qualmesh/mesh_io.h"

namespace qualmesh {

TetMesh read_tet_mesh(const std::string& path) {
  TetMesh mesh;
  switch (mesh_format_from_path(path)) {
    case MeshFormat::TetGen: mesh = io::read_tetgen(io::strip_extension(path)); break;
    case MeshFormat::Gmsh41: mesh = io::read_gmsh(path); break;
    case MeshFormat::Medit: mesh = io::read_medit(path); break;
    case MeshFormat::Vtu: mesh = io::read_vtu(path); break;
    case MeshFormat::Abaqus: mesh = io::read_abaqus(path); break;
    case MeshFormat::Unv: mesh = io::read_unv(path); break;
    case MeshFormat::Elmer:
      throw InputError(ErrorCode::Unsupported, "reading Elmer mesh directories is not supported", path);
  }
  io::check_mesh_indices(mesh, path);
  return mesh;
}

namespace io {

// Regular files only, at most their size (file_read.h: FIFOs, directories, /dev/zero refused); every mesh format
// read is text, so a byte order mark goes and CR-only line ends become line feeds (io_detail::as_text).
std::string read_whole_file(const std::string& path) { return io_detail::as_text(io_detail::read_regular_file(path)); }

void check_mesh_indices(const TetMesh& mesh, const std::string& file) {
  const Index n = static_cast<Index>(mesh.points.size());
  for (std::size_t i = 0; i < mesh.points.size(); ++i) {
    for (double c : mesh.points[i]) {
      if (!std::isfinite(c)) {
        ElementIds ids;
        ids.vertices.push_back(static_cast<Index>(i));
        throw InputError(ErrorCode::NonFinite, "vertex " + std::to_string(i) + " has a non-finite coordinate", file,
                         0, ids);
      }
    }
  }
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
    for (Index v : mesh.tets[t]) {
      if (v >= n) {
        ElementIds ids;
        ids.elements.push_back(static_cast<Index>(t));
        throw InputError(ErrorCode::IndexOutOfRange,
                         "tetrahedron " + std::to_string(t) + " refers to a missing vertex", file, 0, ids);
      }
    }
  }
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    for (Index v : mesh.faces[f]) {
      if (v >= n) {
        throw InputError(ErrorCode::IndexOutOfRange, "face " + std::to_string(f) + " refers to a missing vertex",
                         file);
      }
    }
  }
  const auto check = [&](Index v, const char* what, std::size_t i) {
    if (v >= n) {
      throw InputError(ErrorCode::IndexOutOfRange, std::string(what) + " " + std::to_string(i) +
                                                       " refers to a missing vertex", file);
    }
  };
  for (std::size_t e = 0; e < mesh.edges.size(); ++e) for (Index v : mesh.edges[e]) check(v, "edge", e);
  for (std::size_t t = 0; t < mesh.tet_mid.size(); ++t) for (Index v : mesh.tet_mid[t]) check(v, "tetrahedron", t);
  for (std::size_t f = 0; f < mesh.face_mid.size(); ++f) for (Index v : mesh.face_mid[f]) check(v, "face", f);
  for (std::size_t e = 0; e < mesh.edge_mid.size(); ++e) check(mesh.edge_mid[e], "edge", e);
  if (!mesh.tet_mid.empty() && mesh.tet_mid.size() != mesh.tets.size()) {
    throw InputError(ErrorCode::Parse, "mixed linear and quadratic tetrahedra", file);
  }
}

}  // namespace io
}  // namespace qualmesh
