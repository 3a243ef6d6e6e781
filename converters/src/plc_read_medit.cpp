// Medit .mesh (ASCII, INRIA "libMesh" format) surface reader: the Vertices section ("x y z ref"), Triangles
// ("a b c ref") and Quadrilaterals ("a b c d ref"), 1-based, the ref becoming the facet marker. Tetrahedra and every
// other section (Edges, Corners, Ridges, Normals...) are skipped: their records are numbers, so skipping runs to the
// next keyword. Only "Dimension 3" is read.
#include <string>
#include <vector>

#include "plc_read_formats.h"
#include "qualmesh/error.h"
#include "text_scanner.h"

namespace qualmesh::plc_io {

namespace {

bool is_keyword(std::string_view token) {
  const char c = token.empty() ? '0' : token[0];
  return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z');
}

}  // namespace

Plc read_medit(const std::string& path, const ReadOptions& options, std::vector<std::string>* notes) {
  TextScanner scanner(read_whole_file(path), path, true);
  SurfaceSoup soup;
  bool saw_version = false;
  bool saw_vertices = false;
  bool saw_end = false;
  // Element references are checked once all sections are read (Triangles may come before Vertices).
  struct PendingFace {
    std::vector<long long> refs;
    long line;
    std::string name;
  };
  std::vector<PendingFace> pending;
  std::string_view token = scanner.next_token();
  if (token.empty()) throw InputError(ErrorCode::Empty, "the file is empty", path);
  static const char* axis[3] = {"x", "y", "z"};
  while (!token.empty() && !saw_end) {
    if (!is_keyword(token)) {
      scanner.fail(ErrorCode::Parse, "expected a section keyword (Vertices, Triangles...), got '" +
                                         std::string(token.substr(0, 40)) + "'");
    }
    const std::string keyword = to_lower(token);
    if (keyword == "meshversionformatted") {
      saw_version = true;
      scanner.to_integer(scanner.next_token(), "version of MeshVersionFormatted");
    } else if (keyword == "dimension") {
      const long long dim = scanner.to_integer(scanner.next_token(), "dimension");
      if (dim != 3) scanner.fail(ErrorCode::Unsupported, "dimension " + std::to_string(dim) + " (only 3 is read)");
    } else if (keyword == "vertices") {
      if (!saw_version) scanner.fail(ErrorCode::Parse, "missing 'MeshVersionFormatted' before 'Vertices'");
      saw_vertices = true;
      const std::size_t count = scanner.to_count(scanner.next_token(), "vertex count", 8);
      soup.vertices.reserve(soup.vertices.size() + count);
      for (std::size_t i = 0; i < count; ++i) {
        const std::string name = "vertex " + std::to_string(soup.vertices.size() + 1);
        Point3 p{};
        for (int k = 0; k < 3; ++k) p[k] = scanner.to_double(scanner.next_token(), std::string(axis[k]) + " coordinate of " + name);
        scanner.to_integer(scanner.next_token(), "reference of " + name);
        soup.vertices.push_back(p);
      }
    } else if (keyword == "triangles" || keyword == "quadrilaterals") {
      if (!saw_version) scanner.fail(ErrorCode::Parse, "missing 'MeshVersionFormatted' before '" + std::string(token) + "'");
      const std::size_t corners = keyword == "triangles" ? 3 : 4;
      const std::string kind = keyword == "triangles" ? "triangle " : "quadrilateral ";
      const std::size_t count = scanner.to_count(scanner.next_token(), kind + "count", 2 * (corners + 1));
      pending.reserve(pending.size() + count);
      for (std::size_t i = 0; i < count; ++i) {
        PendingFace face;
        face.name = kind + std::to_string(i + 1);
        for (std::size_t k = 0; k < corners; ++k) {
          face.refs.push_back(scanner.to_integer(scanner.next_token(), "vertex of " + face.name));
        }
        face.line = scanner.line();
        const long long ref = scanner.to_integer(scanner.next_token(), "reference of " + face.name);
        soup.markers.push_back(static_cast<int>(ref));
        pending.push_back(std::move(face));
      }
    } else if (keyword == "end") {
      saw_end = true;
      break;
    } else {
      // Tetrahedra, Edges, Corners, Ridges, Normals...: numeric records up to the next keyword.
      do {
        token = scanner.next_token();
      } while (!token.empty() && !is_keyword(token));
      continue;
    }
    token = scanner.next_token();
  }
  if (!saw_vertices) throw InputError(ErrorCode::Parse, "no 'Vertices' section", path, scanner.line());
  for (std::size_t f = 0; f < pending.size(); ++f) {
    std::vector<Index> face;
    for (long long ref : pending[f].refs) {
      if (ref < 1 || ref > static_cast<long long>(soup.vertices.size())) {
        throw InputError(ErrorCode::IndexOutOfRange,
                         pending[f].name + " refers to vertex " + std::to_string(ref) + ", but there are " +
                             std::to_string(soup.vertices.size()) + " vertices (numbered 1.." +
                             std::to_string(soup.vertices.size()) + ")",
                         path, pending[f].line, ElementIds{{}, {}, {static_cast<Index>(f)}, {}});
      }
      face.push_back(static_cast<Index>(ref - 1));
    }
    soup.faces.push_back(std::move(face));
    soup.lines.push_back(pending[f].line);
  }
  soup.face_word = "surface element";  // triangles, then quadrilaterals, numbered together from 1
  if (soup.faces.empty()) {
    throw InputError(ErrorCode::Empty, "no 'Triangles' or 'Quadrilaterals' section: the file holds no surface", path);
  }
  return finish_surface(std::move(soup), path, options, notes);
}

}  // namespace qualmesh::plc_io
