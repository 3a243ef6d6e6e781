// OFF surface reader (Geomview Object File Format, as written by CGAL, OpenSCAD and MeshLab): header "OFF" (also
// COFF, NOFF, CNOFF, STOFF...), counts "nv nf ne", nv vertex lines "x y z [extra]", nf face lines
// "n i1 .. in [colour]" with 0-based indices. Records are read line by line so that colours and normals are
// ignored. Binary OFF and 4-dimensional OFF are not read.
#include <string>
#include <vector>

#include "plc_read_formats.h"
#include "qualmesh/error.h"
#include "text_scanner.h"

namespace qualmesh::plc_io {

namespace {
constexpr std::size_t kMinVertexBytes = 6;  // "0 0 0\n"
constexpr std::size_t kMinFaceBytes = 8;    // "3 0 1 2\n"
}  // namespace

Plc read_off(const std::string& path, const ReadOptions& options, std::vector<std::string>* notes) {
  TextScanner scanner(read_whole_file(path), path, true);
  std::vector<std::string_view> tokens;
  if (!scanner.next_line(tokens)) throw InputError(ErrorCode::Empty, "the file is empty", path);

  // Header keyword, possibly followed by the counts on the same line.
  const std::string keyword = to_lower(tokens[0]);
  const bool is_off_keyword = keyword.size() >= 3 && keyword.compare(keyword.size() - 3, 3, "off") == 0;
  if (!is_off_keyword) scanner.fail(ErrorCode::Parse, "missing the OFF header: the first word is not 'OFF'");
  if (keyword.find('4') != std::string::npos) {
    scanner.fail(ErrorCode::Unsupported, "'" + std::string(tokens[0]) + "' files (not 3D) are not read");
  }
  std::size_t first_count = 1;
  if (tokens.size() > 1 && to_lower(tokens[1]) == "binary") {
    scanner.fail(ErrorCode::Unsupported, "binary OFF is not read; convert it to ASCII OFF");
  }
  if (tokens.size() < 2) {
    if (!scanner.next_line(tokens)) scanner.fail(ErrorCode::Parse, "unexpected end of file: expected the counts line");
    first_count = 0;
  }
  if (tokens.size() < first_count + 2) scanner.fail(ErrorCode::Parse, "the counts line needs 'vertices faces [edges]'");
  const std::size_t num_vertices = scanner.to_count(tokens[first_count], "vertex count", kMinVertexBytes);
  const std::size_t num_faces = scanner.to_count(tokens[first_count + 1], "face count", kMinFaceBytes);
  if (num_vertices == 0) scanner.fail(ErrorCode::Empty, "the vertex count is 0");
  if (num_faces == 0) scanner.fail(ErrorCode::Empty, "the face count is 0");
  if (static_cast<unsigned long long>(num_vertices) * kMinVertexBytes +
          static_cast<unsigned long long>(num_faces) * kMinFaceBytes >
      scanner.remaining_bytes() + 2) {
    scanner.fail(ErrorCode::Parse, "the counts (" + std::to_string(num_vertices) + " vertices, " +
                                       std::to_string(num_faces) + " faces) do not fit in the " +
                                       std::to_string(scanner.remaining_bytes()) + " bytes left in the file");
  }

  SurfaceSoup soup;
  soup.vertices.reserve(num_vertices);
  static const char* axis[3] = {"x", "y", "z"};
  for (std::size_t i = 0; i < num_vertices; ++i) {
    if (!scanner.next_line(tokens)) {
      scanner.fail(ErrorCode::Parse, "unexpected end of file: expected vertex " + std::to_string(i) + " (of " +
                                         std::to_string(num_vertices) + ", numbered from 0)");
    }
    Point3 p{};
    for (int k = 0; k < 3; ++k) {
      const std::string what = std::string(axis[k]) + " coordinate of vertex " + std::to_string(i);
      if (static_cast<std::size_t>(k) >= tokens.size()) scanner.fail(ErrorCode::Parse, "missing the " + what);
      p[k] = scanner.to_double(tokens[k], what);
    }
    soup.vertices.push_back(p);
  }
  soup.faces.reserve(num_faces);
  for (std::size_t f = 0; f < num_faces; ++f) {
    const std::string name = "face " + std::to_string(f);
    if (!scanner.next_line(tokens)) {
      scanner.fail(ErrorCode::Parse, "unexpected end of file: expected " + name + " (of " + std::to_string(num_faces) +
                                         ", numbered from 0)");
    }
    const std::size_t n = scanner.to_count(tokens[0], "vertex count of " + name, 0);
    if (n < 3) scanner.fail(ErrorCode::Parse, name + " has " + std::to_string(n) + " vertices; at least 3 are needed");
    if (tokens.size() < n + 1) {
      scanner.fail(ErrorCode::Parse, name + " announces " + std::to_string(n) + " vertices but the line has " +
                                         std::to_string(tokens.size() - 1));
    }
    std::vector<Index> face;
    face.reserve(n);
    for (std::size_t k = 0; k < n; ++k) {
      const long long v = scanner.to_integer(tokens[1 + k], "vertex of " + name);
      if (v < 0 || v >= static_cast<long long>(num_vertices)) {
        scanner.fail(ErrorCode::IndexOutOfRange,
                     name + " refers to vertex " + std::to_string(v) + ", but there are " +
                         std::to_string(num_vertices) + " vertices (numbered 0.." + std::to_string(num_vertices - 1) +
                         ")",
                     ElementIds{{}, {}, {static_cast<Index>(f)}, {}});
      }
      face.push_back(static_cast<Index>(v));
    }
    soup.faces.push_back(std::move(face));
    soup.markers.push_back(0);
    soup.lines.push_back(scanner.line());
  }
  soup.first_face_number = 0;
  return finish_surface(std::move(soup), path, options, notes);
}

}  // namespace qualmesh::plc_io
