// TetGen mesh reader: BASE.node, BASE.ele and, when present, BASE.face (TetGen 1.5 file formats). The first index of
// the .node file sets the numbering (0 or 1, as TetGen itself decides); .ele with 10 nodes per tetrahedron is read as
// its 4 corners; the region is the first tetrahedron attribute (0 when none); the face marker is the .face boundary
// marker. The first vertex attribute is read as the weight (TetMesh::weights) only when the .node file carries
// QualMesh's comment kWeightAttributeComment (a foreign file's attributes mean anything). Node order is kept: TetGen
// 1.5.0 writes positively oriented tetrahedra.
#include <filesystem>

#include "mesh_io_internal.h"

namespace qualmesh::io {
namespace {

Index read_vertex_index(Tokenizer& tokens, long long first_index, std::size_t num_points) {
  const long long raw = tokens.next_integer("a vertex index");
  // raw - first_index may overflow (raw = -2^63 from the file: undefined behaviour, found by fuzzing): checked.
  long long index = 0;
  if (__builtin_sub_overflow(raw, first_index, &index) || index < 0 ||
      static_cast<std::size_t>(index) >= num_points) {
    ElementIds ids;
    tokens.fail(ErrorCode::IndexOutOfRange, "vertex index " + std::to_string(raw) + " out of range", ids);
  }
  return static_cast<Index>(index);
}

}  // namespace

TetMesh read_tetgen(const std::string& base) {
  TetMesh mesh;
  long long first_index = 0;
  {
    const std::string file = base + ".node";
    const std::string text = read_whole_file(file);
    const bool weighted = text.find(kWeightAttributeComment) != std::string::npos;
    Tokenizer tokens(text, file, '#');
    const std::size_t num_points = tokens.next_count("the number of vertices");
    const long long dimension = tokens.next_integer("the dimension");
    if (dimension != 3) tokens.fail(ErrorCode::Unsupported, "dimension " + std::to_string(dimension) + ", expected 3");
    const std::size_t num_attributes = tokens.next_count("the number of attributes");
    const long long num_markers = tokens.next_integer("the number of boundary markers");
    if (num_markers != 0 && num_markers != 1) tokens.fail(ErrorCode::Parse, "boundary marker count must be 0 or 1");
    if (num_points == 0) tokens.fail(ErrorCode::Empty, "no vertices (a .node file of a mesh lists its vertices)");
    if (weighted && num_attributes == 0) tokens.fail(ErrorCode::Parse, "weights announced but no vertex attribute");
    mesh.points.resize(num_points);
    if (weighted) mesh.weights.resize(num_points);
    for (std::size_t i = 0; i < num_points; ++i) {
      const long long index = tokens.next_integer("a vertex index");
      if (i == 0) {
        if (index != 0 && index != 1) tokens.fail(ErrorCode::Parse, "the first vertex must be numbered 0 or 1");
        first_index = index;
      } else if (index != first_index + static_cast<long long>(i)) {
        tokens.fail(ErrorCode::Parse, "vertex numbers must be consecutive, got " + std::to_string(index));
      }
      for (int c = 0; c < 3; ++c) mesh.points[i][c] = tokens.next_double("a coordinate");
      for (std::size_t a = 0; a < num_attributes; ++a) {
        const double attribute = tokens.next_double("a vertex attribute");
        if (weighted && a == 0) mesh.weights[i] = attribute;
      }
      if (num_markers) tokens.next_integer("a boundary marker");
    }
  }
  {
    const std::string file = base + ".ele";
    Tokenizer tokens(read_whole_file(file), file, '#');
    const std::size_t num_tets = tokens.next_count("the number of tetrahedra");
    const long long nodes_per_tet = tokens.next_integer("the number of nodes per tetrahedron");
    if (nodes_per_tet != 4 && nodes_per_tet != 10) {
      tokens.fail(ErrorCode::Unsupported, "tetrahedra with " + std::to_string(nodes_per_tet) + " nodes");
    }
    const std::size_t num_attributes = tokens.next_count("the number of attributes");
    mesh.tets.resize(num_tets);
    mesh.tet_region.assign(num_tets, 0);
    for (std::size_t t = 0; t < num_tets; ++t) {
      tokens.next_integer("a tetrahedron index");
      for (long long k = 0; k < nodes_per_tet; ++k) {
        const Index v = read_vertex_index(tokens, first_index, mesh.points.size());
        if (k < 4) mesh.tets[t][k] = v;
      }
      for (std::size_t a = 0; a < num_attributes; ++a) {
        const double attribute = tokens.next_double("a tetrahedron attribute");
        // The region is an int; a larger value would be undefined behaviour to convert (found by fuzzing).
        if (a == 0 && !(attribute >= -2e9 && attribute <= 2e9)) {
          tokens.fail(ErrorCode::Parse, "the region attribute of tetrahedron " + std::to_string(t + first_index) +
                                            " (" + std::to_string(attribute) + ") is outside -2e9..2e9");
        }
        if (a == 0) mesh.tet_region[t] = static_cast<int>(attribute);
      }
    }
  }
  const std::string face_file = base + ".face";
  if (std::filesystem::exists(face_file)) {
    Tokenizer tokens(read_whole_file(face_file), face_file, '#');
    const std::size_t num_faces = tokens.next_count("the number of faces");
    const long long num_markers = tokens.next_integer("the number of boundary markers");
    if (num_markers != 0 && num_markers != 1) tokens.fail(ErrorCode::Parse, "boundary marker count must be 0 or 1");
    mesh.faces.resize(num_faces);
    mesh.face_facet.assign(num_faces, -1);
    mesh.face_marker.assign(num_faces, 0);
    for (std::size_t f = 0; f < num_faces; ++f) {
      tokens.next_integer("a face index");
      for (int k = 0; k < 3; ++k) mesh.faces[f][k] = read_vertex_index(tokens, first_index, mesh.points.size());
      if (num_markers) mesh.face_marker[f] = static_cast<int>(tokens.next_integer("a boundary marker"));
    }
  }
  return mesh;
}

}  // namespace qualmesh::io
