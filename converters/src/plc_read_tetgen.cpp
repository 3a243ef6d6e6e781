// TetGen PLC readers: .node (points), .poly and .smesh (points, facets with polygons and facet holes, volume holes,
// region seeds). Follows the file format description of TetGen 1.5 (Si, "TetGen user's guide", Section 5.2):
// '#' comments, indices counted from the first node index (0 or 1), optional attributes and boundary markers, a
// node count of 0 meaning "the nodes are in the sibling .node file". Records are read line by line; extra tokens
// at the end of a line are ignored, as TetGen does.
#include <filesystem>
#include <string>
#include <vector>

#include "plc_read_formats.h"
#include "qualmesh/error.h"
#include "text_scanner.h"

namespace qualmesh::plc_io {

namespace {

// Smallest sizes of records, to reject absurd counts before allocating.
constexpr std::size_t kMinNodeBytes = 8;    // "1 0 0 0\n"
constexpr std::size_t kMinFacetBytes = 4;   // "1\n" + "1 1\n"
constexpr std::size_t kMinPointBytes = 8;   // hole: "1 0 0 0\n"

struct NodeList {
  std::vector<Point3> points;
  long long first_index = 1;
};

// Requires a next record line; fails with "unexpected end of file: expected <what>".
void require_line(TextScanner& scanner, std::vector<std::string_view>& tokens, const std::string& what) {
  if (!scanner.next_line(tokens)) scanner.fail(ErrorCode::Parse, "unexpected end of file: expected " + what);
}

std::string_view token_at(TextScanner& scanner, const std::vector<std::string_view>& tokens, std::size_t i,
                          const std::string& what) {
  if (i >= tokens.size()) scanner.fail(ErrorCode::Parse, "missing the " + what);
  return tokens[i];
}

// Reads the node list from the current position: header "n dim [nattr [nmarker]]" and n node lines.
NodeList read_nodes(TextScanner& scanner, std::vector<std::string_view>& tokens, bool header_read) {
  if (!header_read) require_line(scanner, tokens, "the node count line");
  const std::size_t count = scanner.to_count(token_at(scanner, tokens, 0, "node count"), "node count", kMinNodeBytes);
  NodeList nodes;
  if (count == 0) return nodes;
  if (tokens.size() > 1) {
    const long long dim = scanner.to_integer(tokens[1], "dimension");
    if (dim != 3) scanner.fail(ErrorCode::Unsupported, "dimension " + std::to_string(dim) + " (only 3 is read)");
  }
  nodes.points.reserve(count);
  for (std::size_t i = 0; i < count; ++i) {
    const std::string ordinal = std::to_string(i + 1);
    require_line(scanner, tokens, "node line " + ordinal + " of " + std::to_string(count));
    const long long id = scanner.to_integer(tokens[0], "index of node " + ordinal);
    if (i == 0) {
      nodes.first_index = id;
      if (id != 0 && id != 1) {
        scanner.fail(ErrorCode::Parse, "the first node index is " + std::to_string(id) + "; it must be 0 or 1");
      }
    }
    Point3 p{};
    static const char* axis[3] = {"x", "y", "z"};
    for (int k = 0; k < 3; ++k) {
      const std::string what = std::string(axis[k]) + " coordinate of node " + std::to_string(id);
      p[k] = scanner.to_double(token_at(scanner, tokens, 1 + k, what), what);
    }
    nodes.points.push_back(p);
  }
  return nodes;
}

// A vertex reference of a facet polygon, in the file's numbering, converted to 0-based.
Index read_vertex_ref(TextScanner& scanner, std::string_view token, const NodeList& nodes,
                      const std::string& element) {
  const long long ref = scanner.to_integer(token, "vertex of " + element);
  const long long zero_based = ref - nodes.first_index;
  if (zero_based < 0 || zero_based >= static_cast<long long>(nodes.points.size())) {
    const long long last = nodes.first_index + static_cast<long long>(nodes.points.size()) - 1;
    scanner.fail(ErrorCode::IndexOutOfRange,
                 element + " refers to vertex " + std::to_string(ref) + ", but there are " +
                     std::to_string(nodes.points.size()) + " vertices (numbered " +
                     std::to_string(nodes.first_index) + ".." + std::to_string(last) + ")");
  }
  return static_cast<Index>(zero_based);
}

Point3 read_point(TextScanner& scanner, const std::vector<std::string_view>& tokens, std::size_t first,
                  const std::string& element) {
  Point3 p{};
  static const char* axis[3] = {"x", "y", "z"};
  for (int k = 0; k < 3; ++k) {
    const std::string what = std::string(axis[k]) + " coordinate of " + element;
    p[k] = scanner.to_double(token_at(scanner, tokens, first + k, what), what);
  }
  return p;
}

}  // namespace

Plc read_tetgen_node(const std::string& path) {
  TextScanner scanner(read_whole_file(path), path, true);
  std::vector<std::string_view> tokens;
  NodeList nodes = read_nodes(scanner, tokens, false);
  if (nodes.points.empty()) throw InputError(ErrorCode::Empty, "the file holds no nodes", path, scanner.line());
  Plc plc;
  plc.vertices = std::move(nodes.points);
  return plc;
}

Plc read_tetgen_poly(const std::string& path) {
  const bool smesh = lower_extension(path) == ".smesh";
  TextScanner scanner(read_whole_file(path), path, true);
  std::vector<std::string_view> tokens;

  // Part 1: nodes, here or in the sibling .node file.
  require_line(scanner, tokens, "the node count line");
  NodeList nodes;
  if (scanner.to_integer(token_at(scanner, tokens, 0, "node count"), "node count") == 0) {
    const std::string node_path = std::filesystem::path(path).replace_extension(".node").string();
    if (!std::filesystem::exists(node_path)) {
      scanner.fail(ErrorCode::Io, "the node count is 0, so the nodes must be in '" + node_path +
                                      "', which does not exist");
    }
    TextScanner node_scanner(read_whole_file(node_path), node_path, true);
    std::vector<std::string_view> node_tokens;
    nodes = read_nodes(node_scanner, node_tokens, false);
  } else {
    nodes = read_nodes(scanner, tokens, true);
  }
  if (nodes.points.empty()) throw InputError(ErrorCode::Empty, "the PLC has no vertices", path, scanner.line());
  const long long base = nodes.first_index;

  Plc plc;
  plc.vertices = nodes.points;

  // Part 2: facets.
  require_line(scanner, tokens, "the facet count line");
  const std::size_t num_facets =
      scanner.to_count(token_at(scanner, tokens, 0, "facet count"), "facet count", kMinFacetBytes);
  const bool has_markers =
      tokens.size() > 1 && scanner.to_integer(tokens[1], "boundary marker flag of the facet list") != 0;
  plc.facets.reserve(num_facets);
  for (std::size_t f = 0; f < num_facets; ++f) {
    const std::string facet_name = "facet " + std::to_string(static_cast<long long>(f) + base);
    Facet facet;
    require_line(scanner, tokens, facet_name + " of " + std::to_string(num_facets));
    if (smesh) {
      const std::size_t n = scanner.to_count(tokens[0], "vertex count of " + facet_name, 0);
      if (n == 0) scanner.fail(ErrorCode::Parse, facet_name + " has no vertices");
      if (tokens.size() < 1 + n) {
        scanner.fail(ErrorCode::Parse, facet_name + " announces " + std::to_string(n) + " vertices but the line has " +
                                           std::to_string(tokens.size() - 1));
      }
      std::vector<Index> loop;
      loop.reserve(n);
      for (std::size_t k = 0; k < n; ++k) loop.push_back(read_vertex_ref(scanner, tokens[1 + k], nodes, facet_name));
      facet.polygons.push_back(std::move(loop));
      if (has_markers && tokens.size() > 1 + n) {
        facet.marker = static_cast<int>(scanner.to_integer(tokens[1 + n], "boundary marker of " + facet_name));
      }
    } else {
      const std::size_t num_polygons = scanner.to_count(tokens[0], "polygon count of " + facet_name, 2);
      if (num_polygons == 0) scanner.fail(ErrorCode::Parse, facet_name + " has no polygons");
      std::size_t num_holes = 0;
      if (tokens.size() > 1) num_holes = scanner.to_count(tokens[1], "hole count of " + facet_name, kMinPointBytes);
      if (has_markers && tokens.size() > 2) {
        facet.marker = static_cast<int>(scanner.to_integer(tokens[2], "boundary marker of " + facet_name));
      }
      facet.polygons.reserve(num_polygons);
      for (std::size_t p = 0; p < num_polygons; ++p) {
        const std::string polygon_name = "polygon " + std::to_string(p + 1) + " of " + facet_name;
        require_line(scanner, tokens, polygon_name);
        const std::size_t n = scanner.to_count(tokens[0], "vertex count of " + polygon_name, 0);
        if (n == 0) scanner.fail(ErrorCode::Parse, polygon_name + " has no vertices");
        if (tokens.size() < 1 + n) {
          scanner.fail(ErrorCode::Parse, polygon_name + " announces " + std::to_string(n) +
                                             " vertices but the line has " + std::to_string(tokens.size() - 1));
        }
        std::vector<Index> loop;
        loop.reserve(n);
        for (std::size_t k = 0; k < n; ++k) {
          loop.push_back(read_vertex_ref(scanner, tokens[1 + k], nodes, facet_name));
        }
        facet.polygons.push_back(std::move(loop));
      }
      for (std::size_t h = 0; h < num_holes; ++h) {
        const std::string hole_name = "hole " + std::to_string(h + 1) + " of " + facet_name;
        require_line(scanner, tokens, hole_name);
        facet.holes.push_back(read_point(scanner, tokens, 1, hole_name));
      }
    }
    plc.facets.push_back(std::move(facet));
  }

  // Part 3: volume holes (optional at the end of the file).
  if (!scanner.next_line(tokens)) return plc;
  const std::size_t num_holes = scanner.to_count(tokens[0], "hole count", kMinPointBytes);
  for (std::size_t h = 0; h < num_holes; ++h) {
    const std::string hole_name = "hole " + std::to_string(static_cast<long long>(h) + base);
    require_line(scanner, tokens, hole_name);
    plc.holes.push_back(read_point(scanner, tokens, 1, hole_name));
  }

  // Part 4: regions (optional): "i x y z attribute [max_volume]".
  if (!scanner.next_line(tokens)) return plc;
  const std::size_t num_regions = scanner.to_count(tokens[0], "region count", kMinPointBytes);
  for (std::size_t r = 0; r < num_regions; ++r) {
    const std::string region_name = "region " + std::to_string(static_cast<long long>(r) + base);
    require_line(scanner, tokens, region_name);
    RegionSeed seed;
    seed.point = read_point(scanner, tokens, 1, region_name);
    // TetGen stores region attributes as reals; QualMesh's are integers (rounded).
    const double attribute =
        scanner.to_double(token_at(scanner, tokens, 4, "attribute of " + region_name), "attribute of " + region_name);
    if (attribute < -2e9 || attribute > 2e9) scanner.fail(ErrorCode::Parse, "the attribute of " + region_name + " is too large");
    seed.attribute = static_cast<int>(attribute < 0 ? attribute - 0.5 : attribute + 0.5);
    if (tokens.size() > 5) seed.max_volume = scanner.to_double(tokens[5], "maximum volume of " + region_name);
    plc.regions.push_back(seed);
  }
  return plc;
}

}  // namespace qualmesh::plc_io
