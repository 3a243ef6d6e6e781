// Medit .mesh reader (ASCII; INRIA's format as written by Medit, MMG, CGAL, Gmsh and QualMesh). Keeps Vertices,
// Triangles / TrianglesP2 (reference = face marker), Tetrahedra / TetrahedraP2 (reference = region) and Edges /
// EdgesP2 (reference = edge marker); P2 mid-nodes in the order mesh_write_medit.cpp describes (TetMesh's). Skips the
// other known sections (Corners, Ridges, Required*, Normals, Tangents, other cells). Keywords are case-insensitive;
// '#' starts a comment. Indices are 1-based in the file. Node order is kept (MMG's tetrahedra are positively
// oriented). A second-order mesh's points are renumbered corners first.
#include <algorithm>
#include <cctype>
#include <map>

#include "mesh_groups.h"
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
      {"quadrilaterals", 5},     {"hexahedra", 9},          {"prisms", 7},
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
  bool have_vertices = false, have_end = false, any_tet4 = false;
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
    } else if (keyword == "triangles" || keyword == "trianglesp2" || keyword == "tetrahedra" ||
               keyword == "tetrahedrap2" || keyword == "edges" || keyword == "edgesp2") {
      if (!have_vertices) tokens.fail(ErrorCode::Parse, keyword + " before Vertices");
      const bool p2 = keyword.size() > 2 && keyword.compare(keyword.size() - 2, 2, "p2") == 0;
      const int corners = keyword[0] == 't' && keyword[1] == 'e' ? 4 : keyword[0] == 't' ? 3 : 2;
      const int extra = p2 ? (corners == 4 ? 6 : corners == 3 ? 3 : 1) : 0;
      const std::size_t count = tokens.next_count("the number of elements");
      std::vector<Index> v(corners + extra);
      for (std::size_t i = 0; i < count; ++i) {
        for (Index& n : v) n = vertex("a vertex index");
        const int ref = static_cast<int>(tokens.next_integer("a reference"));
        if (corners == 4) {
          mesh.tets.push_back({v[0], v[1], v[2], v[3]});
          mesh.tet_region.push_back(ref);
          if (p2) mesh.tet_mid.push_back({v[4], v[5], v[6], v[7], v[8], v[9]});
          any_tet4 = any_tet4 || !p2;
        } else if (corners == 3) {
          mesh.faces.push_back({v[0], v[1], v[2]});
          mesh.face_facet.push_back(-1);
          mesh.face_marker.push_back(ref);
          if (p2) mesh.face_mid.push_back({v[3], v[4], v[5]});
        } else {
          mesh.edges.push_back({v[0], v[1]});
          mesh.edge_marker.push_back(ref);
          if (p2) mesh.edge_mid.push_back(v[2]);
        }
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
  if (any_tet4) mesh.tet_mid.clear();  // mixed linear and quadratic: corners only
  if (mesh.tet_mid.empty() || mesh.face_mid.size() != mesh.faces.size()) mesh.face_mid.clear();
  if (mesh.tet_mid.empty() || mesh.edge_mid.size() != mesh.edges.size()) mesh.edge_mid.clear();
  if (!mesh.tet_mid.empty()) renumber_corners_first(mesh);
  return mesh;
}

}  // namespace qualmesh::io
