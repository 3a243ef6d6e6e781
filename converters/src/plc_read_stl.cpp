// STL surface reader, ASCII and binary. Binary is told from ASCII by the file size alone (84 + 50 n bytes, n the
// little-endian count at bytes 80..83), never by the word "solid": many binary writers start their 80-byte header
// with "solid" (e.g. Solid Edge). A file of another size is ASCII when it starts with "solid" and holds no NUL byte;
// otherwise it is a binary file of wrong size (truncated or with a corrupt count). Every triangle becomes a facet; vertices are merged by exact coordinates.
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "plc_read_formats.h"
#include "qualmesh/error.h"
#include "text_scanner.h"

namespace qualmesh::plc_io {

namespace {

constexpr std::size_t kHeaderBytes = 84;
constexpr std::size_t kTriangleBytes = 50;

float read_float_le(const unsigned char* bytes) {
  const std::uint32_t bits = static_cast<std::uint32_t>(bytes[0]) | (static_cast<std::uint32_t>(bytes[1]) << 8) |
                             (static_cast<std::uint32_t>(bytes[2]) << 16) |
                             (static_cast<std::uint32_t>(bytes[3]) << 24);
  float value;
  std::memcpy(&value, &bits, sizeof value);
  return value;
}

std::uint32_t read_count(const std::string& data) {
  const auto* bytes = reinterpret_cast<const unsigned char*>(data.data()) + 80;
  return static_cast<std::uint32_t>(bytes[0]) | (static_cast<std::uint32_t>(bytes[1]) << 8) |
         (static_cast<std::uint32_t>(bytes[2]) << 16) | (static_cast<std::uint32_t>(bytes[3]) << 24);
}

// Index of a new vertex in the soup (duplicates are merged later, by finish_surface).
Index push_vertex(SurfaceSoup& soup, const Point3& p) {
  soup.vertices.push_back(p);
  return static_cast<Index>(soup.vertices.size() - 1);
}

SurfaceSoup read_binary(const std::string& data, const std::string& path) {
  const std::uint32_t count = read_count(data);  // the caller checked 84 + 50 count == size
  SurfaceSoup soup;
  soup.vertices.reserve(3 * static_cast<std::size_t>(count));
  soup.faces.reserve(count);
  const auto* bytes = reinterpret_cast<const unsigned char*>(data.data());
  for (std::uint32_t t = 0; t < count; ++t) {
    const unsigned char* record = bytes + kHeaderBytes + kTriangleBytes * static_cast<std::size_t>(t);
    std::vector<Index> face;
    for (int corner = 0; corner < 3; ++corner) {
      Point3 p{};
      for (int k = 0; k < 3; ++k) {
        p[k] = static_cast<double>(read_float_le(record + 12 + 12 * corner + 4 * k));
        if (!std::isfinite(p[k])) {
          throw InputError(ErrorCode::NonFinite,
                           "triangle " + std::to_string(t + 1) + " (of " + std::to_string(count) +
                               ") has a non-finite coordinate at corner " + std::to_string(corner + 1),
                           path, 0, ElementIds{{}, {}, {t}, {}});
        }
      }
      face.push_back(push_vertex(soup, p));
    }
    soup.faces.push_back(std::move(face));
    soup.markers.push_back(0);
  }
  soup.face_word = "triangle";
  return soup;
}

// Expects the keyword `word` (case-insensitive) as the next token.
void expect_word(TextScanner& scanner, const char* word, const std::string& context) {
  const std::string_view token = scanner.next_token();
  if (token.empty()) scanner.fail(ErrorCode::Parse, std::string("unexpected end of file: expected '") + word + "' " + context);
  if (to_lower(token) != word) {
    scanner.fail(ErrorCode::Parse, std::string("expected '") + word + "' " + context + ", got '" +
                                       std::string(token.substr(0, 40)) + "'");
  }
}

SurfaceSoup read_ascii(std::string data, const std::string& path) {
  TextScanner scanner(std::move(data), path, false);
  SurfaceSoup soup;
  std::size_t num_solids = 0;
  while (!scanner.at_end()) {
    expect_word(scanner, "solid", num_solids == 0 ? "at the start of an ASCII STL file" : "or the end of the file");
    scanner.skip_rest_of_line();  // the solid's name
    ++num_solids;
    for (;;) {
      const std::string_view token = scanner.next_token();
      if (token.empty()) scanner.fail(ErrorCode::Parse, "unexpected end of file: expected 'facet' or 'endsolid'");
      const std::string word = to_lower(token);
      if (word == "endsolid") {
        scanner.skip_rest_of_line();
        break;
      }
      const std::string name = "facet " + std::to_string(soup.faces.size() + 1);
      if (word != "facet") {
        scanner.fail(ErrorCode::Parse, "expected 'facet' or 'endsolid', got '" + std::string(token.substr(0, 40)) + "'");
      }
      soup.lines.push_back(scanner.line());
      expect_word(scanner, "normal", "after 'facet'");
      for (int k = 0; k < 3; ++k) {
        // Normals are recomputed from the vertices; a NaN normal (common in exported files) is harmless.
        double ignored = 0;
        const std::string_view value = scanner.next_token();
        if (!parse_double(value, ignored)) {
          scanner.fail(ErrorCode::Parse, "expected a number for the normal of " + name + ", got '" +
                                             std::string(value.substr(0, 40)) + "'");
        }
      }
      expect_word(scanner, "outer", "in " + name);
      expect_word(scanner, "loop", "in " + name);
      std::vector<Index> face;
      for (;;) {
        const std::string_view keyword = scanner.next_token();
        const std::string lower = to_lower(keyword);
        if (lower == "endloop") break;
        if (lower != "vertex") {
          scanner.fail(ErrorCode::Parse, keyword.empty() ? "unexpected end of file in " + name
                                                         : "expected 'vertex' or 'endloop' in " + name + ", got '" +
                                                               std::string(keyword.substr(0, 40)) + "'");
        }
        Point3 p{};
        static const char* axis[3] = {"x", "y", "z"};
        for (int k = 0; k < 3; ++k) {
          p[k] = scanner.to_double(scanner.next_token(), std::string(axis[k]) + " coordinate of vertex " +
                                                              std::to_string(face.size() + 1) + " of " + name);
        }
        face.push_back(push_vertex(soup, p));
      }
      if (face.size() < 3) {
        scanner.fail(ErrorCode::Parse, name + " has " + std::to_string(face.size()) + " vertices; at least 3 are needed");
      }
      expect_word(scanner, "endfacet", "after 'endloop' of " + name);
      soup.faces.push_back(std::move(face));
      soup.markers.push_back(0);
    }
  }
  if (num_solids == 0) throw InputError(ErrorCode::Empty, "the file is empty", path);
  soup.face_word = "facet";
  return soup;
}

bool starts_with_solid(const std::string& data) {
  std::size_t i = data.compare(0, 3, "\xEF\xBB\xBF") == 0 ? 3 : 0;  // a UTF-8 byte order mark
  while (i < data.size() && (data[i] == ' ' || data[i] == '\t' || data[i] == '\r' || data[i] == '\n')) ++i;
  return to_lower(std::string_view(data).substr(i, 5)) == "solid";
}

}  // namespace

Plc read_stl(const std::string& path, const ReadOptions& options, std::vector<std::string>* notes) {
  std::string data = read_whole_file(path);
  if (data.empty()) throw InputError(ErrorCode::Empty, "the file is empty", path);
  if (data.size() >= kHeaderBytes) {
    const std::uint64_t count = read_count(data);
    const std::uint64_t expected = kHeaderBytes + kTriangleBytes * count;
    if (expected == data.size()) {
      if (count == 0) throw InputError(ErrorCode::Empty, "the binary STL file holds 0 triangles", path);
      return finish_surface(read_binary(data, path), path, options, notes);
    }
    // Not binary by size. ASCII STL starts with "solid" and holds no NUL byte (a binary header or float does).
    if (!starts_with_solid(data) || data.find('\0') != std::string::npos) {
      throw InputError(ErrorCode::Parse,
                       "binary STL of wrong size: the header announces " + std::to_string(count) + " triangles (" +
                           std::to_string(expected) + " bytes) but the file has " + std::to_string(data.size()) +
                           " bytes",
                       path);
    }
  } else if (!starts_with_solid(data)) {
    throw InputError(ErrorCode::Parse,
                     "not an STL file: " + std::to_string(data.size()) +
                         " bytes is too short for binary STL and it does not start with 'solid'",
                     path);
  }
  return finish_surface(read_ascii(std::move(data), path), path, options, notes);
}

}  // namespace qualmesh::plc_io
