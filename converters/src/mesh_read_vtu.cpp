// VTU reader for the files QualMesh writes: VTK XML UnstructuredGrid, one Piece, ASCII DataArrays ("binary" and
// "appended" data are not read). Keeps tetrahedra (VTK_TETRA = 10, node order as in the file) and the "region" cell
// array (0 when absent) and the "weight" point array (TetMesh::weights; empty when absent); triangles (VTK_TRIANGLE =
// 5) become faces with the "face_id" cell array as marker (0 when absent); quadratic tetrahedra and triangles (24,
// 22) give tet_mid / face_mid (VTK's mid-node order is TetMesh's) when every tetrahedron is quadratic, else their
// corners only; vertex and line cells are skipped; other cells are refused. Not a general XML parser: it finds the <Points>, <Cells> and <CellData>
// blocks and their DataArrays.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "mesh_groups.h"
#include "mesh_io_internal.h"

namespace qualmesh::io {
namespace {

// A value for a message: %g, so that 3.1e+78 or nan reads as such.
std::string shown(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%g", v);
  return buffer;
}

struct DataArray {
  std::string parent;  // "Points", "Cells", "CellData", "PointData", ...
  std::string name;
  std::vector<double> values;
  long line = 0;
};

class VtuReader {
 public:
  explicit VtuReader(const std::string& path) : path_(path), text_(read_whole_file(path)) {}

  TetMesh read() {
    if (text_.find("<VTKFile") == std::string::npos || text_.find("UnstructuredGrid") == std::string::npos) {
      fail(ErrorCode::Parse, "not a VTK XML UnstructuredGrid file", 1L);
    }
    if (text_.find("<AppendedData") != std::string::npos) {
      fail(ErrorCode::Unsupported, "appended (binary) VTU data is not read; write ASCII", 1L);
    }
    const std::size_t piece = text_.find("<Piece");
    if (piece == std::string::npos) fail(ErrorCode::Parse, "no <Piece>", 1L);
    if (text_.find("<Piece", piece + 1) != std::string::npos) fail(ErrorCode::Unsupported, "several pieces", line_at(piece));
    const std::size_t num_points = count_attribute(piece, "NumberOfPoints");
    const std::size_t num_cells = count_attribute(piece, "NumberOfCells");

    std::vector<DataArray> arrays = read_arrays();
    const DataArray* points = find(arrays, "Points", "");
    const DataArray* connectivity = find(arrays, "Cells", "connectivity");
    const DataArray* offsets = find(arrays, "Cells", "offsets");
    const DataArray* types = find(arrays, "Cells", "types");
    const DataArray* region = find(arrays, "CellData", "region");
    const DataArray* face_id = find(arrays, "CellData", "face_id");
    const DataArray* weight = find(arrays, "PointData", "weight");
    if (!points || !connectivity || !offsets || !types) fail(ErrorCode::Parse, "missing Points or Cells arrays", line_at(piece));
    if (points->values.size() != 3 * num_points) fail(ErrorCode::Parse, "wrong number of coordinates", points->line);
    if (offsets->values.size() != num_cells || types->values.size() != num_cells) {
      fail(ErrorCode::Parse, "offsets/types do not match NumberOfCells", offsets->line);
    }
    if (region && region->values.size() != num_cells) fail(ErrorCode::Parse, "wrong size of 'region'", region->line);
    if (face_id && face_id->values.size() != num_cells) fail(ErrorCode::Parse, "wrong size of 'face_id'", face_id->line);
    if (weight && weight->values.size() != num_points) fail(ErrorCode::Parse, "wrong size of 'weight'", weight->line);

    TetMesh mesh;
    mesh.points.resize(num_points);
    for (std::size_t i = 0; i < num_points; ++i) {
      for (int c = 0; c < 3; ++c) mesh.points[i][c] = points->values[3 * i + c];
    }
    if (weight) mesh.weights = weight->values;
    std::size_t begin = 0;
    bool quadratic = true, faces_quadratic = true;
    for (std::size_t cell = 0; cell < num_cells; ++cell) {
      // Every value of an integer array is checked before it is converted: a cast of a value the target type cannot
      // hold (an offset of 3e78, NaN) is undefined behaviour (found by fuzzing).
      const double offset = offsets->values[cell];
      if (!(offset >= double(begin) && offset <= double(connectivity->values.size())) || offset != std::floor(offset))
        fail(ErrorCode::Parse, "bad offsets: cell " + std::to_string(cell) + " ends at " + shown(offset) +
                                   ", outside " + std::to_string(begin) + ".." +
                                   std::to_string(connectivity->values.size()) + " or not a whole number",
             offsets->line);
      const auto end = static_cast<std::size_t>(offset);
      std::vector<Index> nodes;
      for (std::size_t k = begin; k < end; ++k) {
        const double v = connectivity->values[k];
        if (!(v >= 0 && v < static_cast<double>(num_points)) || v != std::floor(v)) {  // NaN too
          fail(ErrorCode::IndexOutOfRange, "cell " + std::to_string(cell) + " refers to a missing point",
               connectivity->line);
        }
        nodes.push_back(static_cast<Index>(v));
      }
      begin = end;
      const double type_value = types->values[cell];
      if (!(type_value >= 0 && type_value <= 255) || type_value != std::floor(type_value))
        fail(ErrorCode::Parse, "cell " + std::to_string(cell) + " has no VTK cell type (" + shown(type_value) +
                                   "; types are whole numbers 0..255)", types->line);
      const int type = static_cast<int>(type_value);
      if ((type == 10 && nodes.size() == 4) || (type == 24 && nodes.size() == 10)) {
        mesh.tets.push_back({nodes[0], nodes[1], nodes[2], nodes[3]});
        mesh.tet_region.push_back(region ? int_label(region, cell, "region") : 0);
        quadratic = quadratic && type == 24;
        if (quadratic) mesh.tet_mid.push_back({nodes[4], nodes[5], nodes[6], nodes[7], nodes[8], nodes[9]});
      } else if ((type == 5 && nodes.size() == 3) || (type == 22 && nodes.size() == 6)) {
        mesh.faces.push_back({nodes[0], nodes[1], nodes[2]});
        mesh.face_facet.push_back(-1);
        mesh.face_marker.push_back(face_id ? int_label(face_id, cell, "face_id") : 0);
        faces_quadratic = faces_quadratic && type == 22;
        if (faces_quadratic) mesh.face_mid.push_back({nodes[3], nodes[4], nodes[5]});
      } else if (type == 1 || type == 2 || type == 3 || type == 4 || type == 21) {
        // Vertices, poly-vertices, lines, poly-lines, quadratic edges: not part of a tetrahedral mesh; skipped.
      } else {
        fail(ErrorCode::Unsupported, "cell " + std::to_string(cell) + " of VTK type " + std::to_string(type) +
                                         " (only tetrahedra, triangles, vertices and lines are read)", types->line);
      }
    }
    if (!quadratic || mesh.tets.empty()) mesh.tet_mid.clear();
    if (mesh.tet_mid.empty() || !faces_quadratic) mesh.face_mid.clear();
    if (!mesh.tet_mid.empty()) {
      renumber_corners_first(mesh);
      // Weights belong to corner nodes only (tet_mesh.h); the writer pads mid-nodes with 0.
      std::vector<char> corner(mesh.points.size(), 0);
      for (const auto& t : mesh.tets) for (Index v : t) corner[v] = 1;
      for (const auto& f : mesh.faces) for (Index v : f) corner[v] = 1;
      std::size_t num_corners = 0;
      while (num_corners < corner.size() && corner[num_corners]) ++num_corners;
      if (mesh.weights.size() > num_corners) mesh.weights.resize(num_corners);
    }
    return mesh;
  }

 private:
  // 1-based line of byte `pos` (or a line number already).
  long line_at(std::size_t pos) const {
    return 1 + static_cast<long>(std::count(text_.begin(), text_.begin() + std::min(pos, text_.size()), '\n'));
  }
  // A cell's region or face label: a whole number an int holds (its array's line in the message otherwise).
  int int_label(const DataArray* array, std::size_t cell, const char* name) const {
    const double v = array->values[cell];
    if (!(v >= -2e9 && v <= 2e9) || v != std::floor(v))
      fail(ErrorCode::Parse, std::string("the '") + name + "' of cell " + std::to_string(cell) + " (" +
                                 shown(v) + ") is not a whole number in -2e9..2e9", array->line);
    return static_cast<int>(v);
  }

  [[noreturn]] void fail(ErrorCode code, const std::string& message, long line) const {
    throw InputError(code, message, path_, line);
  }

  // Value of attribute `name` in the tag starting at `tag`.
  std::string attribute(std::size_t tag, const std::string& name) const {
    const std::size_t close = text_.find('>', tag);
    const std::string key = " " + name + "=\"";
    const std::size_t at = text_.find(key, tag);
    if (at == std::string::npos || at > close) return {};
    const std::size_t start = at + key.size();
    return text_.substr(start, text_.find('"', start) - start);
  }

  std::size_t count_attribute(std::size_t tag, const std::string& name) const {
    const std::string value = attribute(tag, name);
    char* end = nullptr;
    const long long count = std::strtoll(value.c_str(), &end, 10);
    if (value.empty() || *end != '\0' || count < 0) fail(ErrorCode::Parse, "bad or missing " + name, line_at(tag));
    return static_cast<std::size_t>(count);
  }

  std::vector<DataArray> read_arrays() const {
    static const char* kParents[] = {"Points", "Cells", "CellData", "PointData", "FieldData"};
    std::vector<DataArray> arrays;
    for (std::size_t at = text_.find("<DataArray"); at != std::string::npos; at = text_.find("<DataArray", at + 1)) {
      DataArray array;
      array.line = line_at(at);
      std::size_t best = 0;
      for (const char* parent : kParents) {
        const std::size_t open = text_.rfind(std::string("<") + parent, at);
        if (open != std::string::npos && open >= best) {
          const std::size_t closed = text_.rfind(std::string("</") + parent, at);
          if (closed == std::string::npos || closed < open) {
            best = open;
            array.parent = parent;
          }
        }
      }
      array.name = attribute(at, "Name");
      const std::string format = attribute(at, "format");
      if (format != "ascii") fail(ErrorCode::Unsupported, "DataArray format '" + format + "' (only ascii)", array.line);
      const std::size_t start = text_.find('>', at) + 1;
      const std::size_t end = text_.find("</DataArray>", start);
      if (end == std::string::npos) fail(ErrorCode::Parse, "unterminated DataArray", array.line);
      const std::string body = text_.substr(start, end - start);
      const char* p = body.c_str();
      while (true) {
        char* next = nullptr;
        const double value = std::strtod(p, &next);
        if (next == p) break;
        array.values.push_back(value);
        p = next;
      }
      while (*p == ' ' || *p == '\n' || *p == '\t' || *p == '\r') ++p;
      if (*p != '\0') fail(ErrorCode::Parse, "garbage in DataArray '" + array.name + "'", array.line);
      arrays.push_back(std::move(array));
    }
    return arrays;
  }

  static const DataArray* find(const std::vector<DataArray>& arrays, const std::string& parent,
                               const std::string& name) {
    for (const DataArray& a : arrays) {
      if (a.parent == parent && (name.empty() || a.name == name)) return &a;
    }
    return nullptr;
  }

  std::string path_;
  std::string text_;
};

}  // namespace

TetMesh read_vtu(const std::string& path) { return VtuReader(path).read(); }

}  // namespace qualmesh::io
