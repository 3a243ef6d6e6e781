// Mesh format by file extension, and write_tet_mesh: hands the mesh to the writer of its format.
#include <algorithm>
#include <cctype>
#include <filesystem>

#include "mesh_io_internal.h"
#include "qualmesh/mesh_io.h"

namespace qualmesh {
namespace {

std::string lower_extension(std::string path) {
  while (path.size() > 1 && path.back() == '/') path.pop_back();  // "beam.elmer/"
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

bool format_of_extension(const std::string& ext, MeshFormat& format) {
  if (ext == ".vtu") format = MeshFormat::Vtu;
  else if (ext == ".node" || ext == ".ele") format = MeshFormat::TetGen;
  else if (ext == ".msh") format = MeshFormat::Gmsh41;
  else if (ext == ".mesh") format = MeshFormat::Medit;
  else if (ext == ".inp") format = MeshFormat::Abaqus;
  else if (ext == ".unv") format = MeshFormat::Unv;
  else if (ext == ".elmer") format = MeshFormat::Elmer;
  else return false;
  return true;
}

}  // namespace

MeshFormat mesh_format_from_path(const std::string& path) {
  MeshFormat format{};
  if (!format_of_extension(lower_extension(path), format)) {
    throw InputError(ErrorCode::Unsupported,
                     "unknown mesh format (expected .vtu, .node, .ele, .msh, .mesh, .inp, .unv or .elmer)", path);
  }
  return format;
}

bool is_mesh_path(const std::string& path) {
  MeshFormat format{};
  return format_of_extension(lower_extension(path), format);
}

void write_tet_mesh(const TetMesh& mesh, const std::string& path) {
  write_tet_mesh(mesh, path, mesh_format_from_path(path));
}

void write_tet_mesh(const TetMesh& mesh, const std::string& path, MeshFormat format) {
  switch (format) {
    case MeshFormat::Vtu: io::write_vtu(mesh, path); return;
    case MeshFormat::TetGen: {
      const std::string ext = lower_extension(path);
      io::write_tetgen(mesh, ext == ".node" || ext == ".ele" || ext == ".face" ? io::strip_extension(path) : path);
      return;
    }
    case MeshFormat::Gmsh41: io::write_gmsh41(mesh, path); return;
    case MeshFormat::Medit: io::write_medit(mesh, path); return;
    case MeshFormat::Abaqus: io::write_abaqus(mesh, path); return;
    case MeshFormat::Unv: io::write_unv(mesh, path); return;
    case MeshFormat::Elmer: io::write_elmer(mesh, path); return;
  }
}

namespace io {

std::string strip_extension(const std::string& path) {
  const std::filesystem::path p(path);
  if (!p.has_extension()) return path;
  return (p.parent_path() / p.stem()).string();
}

}  // namespace io
}  // namespace qualmesh
