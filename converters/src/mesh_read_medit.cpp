// Medit .mesh reader (ASCII; INRIA's format as written by Medit, MMG, CGAL, Gmsh and QualMesh). Keeps Vertices,
// Triangles (reference = face marker) and Tetrahedra (reference = region); skips the other known sections (Edges,
// Corners, Ridges, Required*, Normals, Tangents, other cells). Keywords are case-insensitive; '#' starts a
// comment. Indices are 1-based in the file. Node order is kept (MMG's tetrahedra are positively oriented).
#include <algorithm>
#include <cctype>
#include <map>

#include "mesh_io_internal.h"

namespace qualmesh::io {
namespace {

std::string lower(std::string_view text) {
  std::string s(text);
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

// Numbers per entry of the sections that are skipped.
const std::map<std::string, int>& skipped_sections() {
  static const std::map<std::string, int> sections = {
      {"edges", 3},           {"quadrilaterals", 5},     {"hexahedra", 9},          {"prisms", 7},
      {"pyramids", 6},        {"corners", 1},            {"ridges", 1},             {"requiredvertices", 1},
      {"requirededges", 1},   {"requiredtriangles", 1},  {"requiredquadrilaterals", 1}, {"requiredtetrahedra", 1},
      {"normals", 3},         {"normalatvertices", 2},   {"tangents", 3},           {"tangentatvertices", 2},
      {"tangentatedges", 3},  {"normalattrianglevertices", 3}, {"normalatquadrilateralvertices", 3},
  };
  return sections;
}

}  // namespace

TetMesh read_medit(const std::string& path) {
  Tokenizer tokens(read_whole_file(path), path, '#');
  TetMesh mesh;
  bool have_vertices = false, have_end = false;
  const auto vertex = [&](const char* what) -> Index {
    const long long raw = tokens.next_integer(what);
    if (raw < 1 || static_cast<std::size_t>(raw) > mesh.points.size()) {
      tokens.fail(ErrorCode::IndexOutOfRange, "vertex index " + std::to_string(raw) + " out of range");
    }
    return static_cast<Index>(raw - 1);
  };
  while (!have_end && tokens.has_more()) {
    const std::string keyword = lower(tokens.next("a keyword"));
    if (keyword == "meshversionformatted") {
      const long long version = tokens.next_integer("the format version");
      if (version < 1 || version > 3) tokens.fail(ErrorCode::Unsupported, "format version " + std::to_string(version));
    } else if (keyword == "dimension") {
      const long long dimension = tokens.next_integer("the dimension");
      if (dimension != 3) tokens.fail(ErrorCode::Unsupported, "dimension " + std::to_string(dimension) + ", expected 3");
    } else if (keyword == "vertices") {
      if (have_vertices) tokens.fail(ErrorCode::Parse, "second Vertices section");
      have_vertices = true;
      mesh.points.resize(tokens.next_count("the number of vertices"));
      for (Point3& p : mesh.points) {
        for (double& c : p) c = tokens.next_double("a coordinate");
        tokens.next_integer("a vertex reference");
      }
    } else if (keyword == "triangles") {
      if (!have_vertices) tokens.fail(ErrorCode::Parse, "Triangles before Vertices");
      const std::size_t count = tokens.next_count("the number of triangles");
      for (std::size_t i = 0; i < count; ++i) {
        std::array<Index, 3> f;
        for (Index& v : f) v = vertex("a vertex index");
        mesh.faces.push_back(f);
        mesh.face_facet.push_back(-1);
        mesh.face_marker.push_back(static_cast<int>(tokens.next_integer("a triangle reference")));
      }
    } else if (keyword == "tetrahedra") {
      if (!have_vertices) tokens.fail(ErrorCode::Parse, "Tetrahedra before Vertices");
      const std::size_t count = tokens.next_count("the number of tetrahedra");
      for (std::size_t i = 0; i < count; ++i) {
        std::array<Index, 4> t;
        for (Index& v : t) v = vertex("a vertex index");
        mesh.tets.push_back(t);
        mesh.tet_region.push_back(static_cast<int>(tokens.next_integer("a tetrahedron reference")));
      }
    } else if (keyword == "end") {
      have_end = true;
    } else {
      const auto it = skipped_sections().find(keyword);
      if (it == skipped_sections().end()) {
        tokens.fail(ErrorCode::Unsupported, "unknown or unsupported Medit section '" + keyword + "'");
      }
      const std::size_t count = tokens.next_count("the number of entries");
      for (std::size_t i = 0; i < count; ++i) {
        for (int k = 0; k < it->second; ++k) tokens.next("an entry");
      }
    }
  }
  if (!have_vertices) tokens.fail(ErrorCode::Parse, "no Vertices section");
  return mesh;
}

}  // namespace qualmesh::io
