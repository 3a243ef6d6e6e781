// Wavefront OBJ surface reader: "v x y z [w]" vertices and "f a b c ..." faces, where a face corner is "v", "v/vt",
// "v//vn" or "v/vt/vn", 1-based, or negative (relative to the vertices defined so far, -1 = the last one). Other
// statements (vt, vn, g, o, s, usemtl, mtllib, l, p) are ignored.
#include <string>
#include <vector>

#include "plc_read_formats.h"
#include "qualmesh/error.h"
#include "text_scanner.h"

namespace qualmesh::plc_io {

Plc read_obj(const std::string& path, const ReadOptions& options, std::vector<std::string>* notes) {
  TextScanner scanner(read_whole_file(path), path, true);
  std::vector<std::string_view> tokens;
  SurfaceSoup soup;
  // Positive references may point forward (most readers accept it); they are checked at the end of the file.
  std::vector<long> face_lines;
  static const char* axis[3] = {"x", "y", "z"};
  while (scanner.next_line(tokens)) {
    const std::string_view keyword = tokens[0];
    if (keyword == "v") {
      const std::string name = "vertex " + std::to_string(soup.vertices.size() + 1);
      Point3 p{};
      for (int k = 0; k < 3; ++k) {
        const std::string what = std::string(axis[k]) + " coordinate of " + name;
        if (tokens.size() < static_cast<std::size_t>(k) + 2) scanner.fail(ErrorCode::Parse, "missing the " + what);
        p[k] = scanner.to_double(tokens[1 + k], what);
      }
      soup.vertices.push_back(p);
    } else if (keyword == "f") {
      const std::string name = "face " + std::to_string(soup.faces.size() + 1);
      if (tokens.size() < 4) {
        scanner.fail(ErrorCode::Parse, name + " has " + std::to_string(tokens.size() - 1) +
                                           " vertices; at least 3 are needed");
      }
      std::vector<Index> face;
      face.reserve(tokens.size() - 1);
      for (std::size_t k = 1; k < tokens.size(); ++k) {
        const std::string_view corner = tokens[k].substr(0, tokens[k].find('/'));
        const long long ref = scanner.to_integer(corner, "vertex of " + name);
        long long absolute = ref;
        if (ref < 0) absolute = static_cast<long long>(soup.vertices.size()) + 1 + ref;
        if (ref == 0) {
          scanner.fail(ErrorCode::IndexOutOfRange, name + " refers to vertex 0, but OBJ vertices are numbered from 1",
                       ElementIds{{}, {}, {static_cast<Index>(soup.faces.size())}, {}});
        }
        if (absolute < 1) {
          scanner.fail(ErrorCode::IndexOutOfRange,
                       name + " refers to vertex " + std::to_string(ref) + " (relative), but only " +
                           std::to_string(soup.vertices.size()) + " vertices are defined before it",
                       ElementIds{{}, {}, {static_cast<Index>(soup.faces.size())}, {}});
        }
        if (absolute > static_cast<long long>(kNoIndex) - 1) {
          scanner.fail(ErrorCode::IndexOutOfRange, name + " refers to vertex " + std::to_string(ref) +
                                                       ", beyond any possible vertex count");
        }
        face.push_back(static_cast<Index>(absolute - 1));
      }
      soup.faces.push_back(std::move(face));
      soup.markers.push_back(0);
      face_lines.push_back(scanner.line());
    } else if (keyword == "vt" || keyword == "vn" || keyword == "vp" || keyword == "g" || keyword == "o" ||
               keyword == "s" || keyword == "usemtl" || keyword == "mtllib" || keyword == "l" || keyword == "p" ||
               keyword == "cstype" || keyword == "deg" || keyword == "curv" || keyword == "surf" ||
               keyword == "parm" || keyword == "end" || keyword == "usemap" || keyword == "maplib") {
      continue;
    } else {
      scanner.fail(ErrorCode::Parse, "unknown OBJ statement " + quoted(keyword));
    }
  }
  for (std::size_t f = 0; f < soup.faces.size(); ++f) {
    for (Index v : soup.faces[f]) {
      if (v >= soup.vertices.size()) {
        throw InputError(ErrorCode::IndexOutOfRange,
                         "face " + std::to_string(f + 1) + " refers to vertex " + std::to_string(v + 1) +
                             ", but there are " + std::to_string(soup.vertices.size()) + " vertices",
                         path, face_lines[f], ElementIds{{}, {}, {static_cast<Index>(f)}, {}});
      }
    }
  }
  if (soup.faces.empty()) throw InputError(ErrorCode::Empty, "the file holds no faces", path);
  soup.lines = std::move(face_lines);
  return finish_surface(std::move(soup), path, options, notes);
}

}  // namespace qualmesh::plc_io
