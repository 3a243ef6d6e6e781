// Gmsh .msh reader, ASCII versions 4.1 and 2.2 (gmsh reference manual, "MSH file format"). Tetrahedra (type 4;
// type 11 with its mid-nodes when every tetrahedron is type 11, Gmsh's nodes 8 and 9 being edges (2,3) and (1,3)),
// triangles (types 2 and 9) and lines (types 1 and 8, as edges) are kept; points and other cells are skipped.
// Region of a tetrahedron: the n of a volume physical named "Solid<n>" (or the older "Region<n>"), else the
// physical tag, else (no physical) the elementary entity tag; face markers likewise with "Face<n>" for triangles,
// edge markers with "Edge<n>" for lines. Elements are kept in the order of their tags (QualMesh writes tetrahedron
// t as tag t+1), node order within an element as in the file (Gmsh's own tetrahedra are positively oriented). A
// second-order mesh's points are renumbered corners first (TetMesh's rule).
#include <algorithm>
#include <map>
#include <unordered_map>

#include "mesh_groups.h"
#include "mesh_io_internal.h"

namespace qualmesh::io {
namespace {

// Number of nodes of a Gmsh element type; 0 when unknown.
int nodes_of_type(long long type) {
  switch (type) {
    case 1: return 2;
    case 2: return 3;
    case 3: return 4;
    case 4: return 4;
    case 5: return 8;
    case 6: return 6;
    case 7: return 5;
    case 8: return 3;
    case 9: return 6;
    case 10: return 9;
    case 11: return 10;
    case 12: return 27;
    case 13: return 18;
    case 14: return 14;
    case 15: return 1;
    case 16: return 8;
    case 17: return 20;
    case 18: return 15;
    case 19: return 13;
    default: return 0;
  }
}

struct Element {
  long long tag;
  long long type;
  std::vector<Index> nodes;
  int label;
};

class GmshReader {
 public:
  GmshReader(const std::string& path) : tokens_(read_whole_file(path), path, 0) {}

  TetMesh read() {
    bool have_format = false, have_nodes = false, have_elements = false;
    while (tokens_.has_more()) {
      const std::string section(tokens_.next("a section"));
      if (section == "$MeshFormat") {
        const std::string version(tokens_.next("the format version"));
        const long long file_type = tokens_.next_integer("the file type");
        tokens_.next_integer("the data size");
        if (file_type != 0) tokens_.fail(ErrorCode::Unsupported, "binary .msh files are not read; save as ASCII");
        if (version.rfind("4.1", 0) == 0) version_ = 4;
        else if (version.rfind("2.", 0) == 0) version_ = 2;
        else tokens_.fail(ErrorCode::Unsupported, "MSH version " + version + " (4.1 and 2.2 are read)");
        have_format = true;
        expect_end("$EndMeshFormat");
      } else if (!have_format) {
        tokens_.fail(ErrorCode::Parse, "a .msh file must start with $MeshFormat");
      } else if (section == "$PhysicalNames") {
        read_physical_names();
      } else if (section == "$Entities" && version_ == 4) {
        read_entities();
      } else if (section == "$Nodes") {
        version_ == 4 ? read_nodes41() : read_nodes22();
        have_nodes = true;
      } else if (section == "$Elements") {
        if (!have_nodes) tokens_.fail(ErrorCode::Parse, "$Elements before $Nodes");
        version_ == 4 ? read_elements41() : read_elements22();
        have_elements = true;
      } else if (section.size() > 1 && section[0] == '$') {
        skip_section(section);
      } else {
        tokens_.fail(ErrorCode::Parse, "expected a $Section, got '" + section + "'");
      }
    }
    if (!have_nodes || !have_elements) tokens_.fail(ErrorCode::Parse, "missing $Nodes or $Elements");
    return build();
  }

 private:
  void expect_end(const char* end) {
    const std::string token(tokens_.next(end));
    if (token != end) tokens_.fail(ErrorCode::Parse, std::string("expected ") + end + ", got '" + token + "'");
  }

  void skip_section(const std::string& section) {
    const std::string end = "$End" + section.substr(1);
    while (true) {
      if (std::string(tokens_.next(end.c_str())) == end) return;
    }
  }

  void read_physical_names() {
    const std::size_t count = tokens_.next_count("the number of physical names");
    for (std::size_t i = 0; i < count; ++i) {
      const long long dim = tokens_.next_integer("a dimension");
      const long long tag = tokens_.next_integer("a physical tag");
      const std::string name(tokens_.next("a physical name"));
      for (const char* prefix : {dim == 3 ? "Solid" : dim == 2 ? "Face" : dim == 1 ? "Edge" : nullptr,
                                 dim == 3 ? "Region" : nullptr}) {
        if (!prefix) continue;
        const std::string p(prefix);
        if (name.size() > p.size() && name.compare(0, p.size(), p) == 0) {
          std::string number = name.substr(p.size());
          if (number[0] == 'M') number = "-" + number.substr(1);
          char* end = nullptr;
          const long value = std::strtol(number.c_str(), &end, 10);
          if (*end == '\0') named_value_[{dim, tag}] = static_cast<int>(value);
        }
      }
    }
    expect_end("$EndPhysicalNames");
  }

  void read_entities() {
    std::size_t counts[4];
    for (auto& c : counts) c = tokens_.next_count("an entity count");
    for (int dim = 0; dim < 4; ++dim) {
      for (std::size_t i = 0; i < counts[dim]; ++i) {
        const long long tag = tokens_.next_integer("an entity tag");
        for (int k = 0; k < (dim == 0 ? 3 : 6); ++k) tokens_.next_double("a bounding-box coordinate");
        const std::size_t num_physicals = tokens_.next_count("the number of physical tags");
        for (std::size_t k = 0; k < num_physicals; ++k) {
          const long long physical = tokens_.next_integer("a physical tag");
          if (k == 0) entity_physical_[{dim, tag}] = physical;
        }
        if (dim > 0) {
          const std::size_t num_bounding = tokens_.next_count("the number of bounding entities");
          for (std::size_t k = 0; k < num_bounding; ++k) tokens_.next_integer("a bounding entity tag");
        }
      }
    }
    expect_end("$EndEntities");
  }

  void add_node(long long tag, const Point3& p) {
    if (!node_index_.emplace(tag, static_cast<Index>(points_.size())).second) {
      tokens_.fail(ErrorCode::Parse, "node tag " + std::to_string(tag) + " given twice");
    }
    points_.push_back(p);
  }

  Point3 read_point() {
    Point3 p;
    for (auto& c : p) c = tokens_.next_double("a coordinate");
    return p;
  }

  void read_nodes41() {
    const std::size_t num_blocks = tokens_.next_count("the number of node blocks");
    tokens_.next_count("the number of nodes");
    tokens_.next_integer("the smallest node tag");
    tokens_.next_integer("the largest node tag");
    for (std::size_t b = 0; b < num_blocks; ++b) {
      const long long dim = tokens_.next_integer("an entity dimension");
      tokens_.next_integer("an entity tag");
      const long long parametric = tokens_.next_integer("the parametric flag");
      const std::size_t count = tokens_.next_count("the number of nodes in the block");
      std::vector<long long> tags(count);
      for (auto& tag : tags) tag = tokens_.next_integer("a node tag");
      for (long long tag : tags) {
        add_node(tag, read_point());
        if (parametric) {
          for (long long k = 0; k < dim; ++k) tokens_.next_double("a parametric coordinate");
        }
      }
    }
    expect_end("$EndNodes");
  }

  void read_nodes22() {
    const std::size_t count = tokens_.next_count("the number of nodes");
    for (std::size_t i = 0; i < count; ++i) {
      const long long tag = tokens_.next_integer("a node tag");
      add_node(tag, read_point());
    }
    expect_end("$EndNodes");
  }

  Index node(long long tag) {
    const auto it = node_index_.find(tag);
    if (it == node_index_.end()) {
      tokens_.fail(ErrorCode::IndexOutOfRange, "element refers to missing node " + std::to_string(tag));
    }
    return it->second;
  }

  // The region / face marker of an element of dimension `dim` with physical tag `physical` (or none) on entity
  // `entity`.
  int label_of(long long dim, bool has_physical, long long physical, long long entity) const {
    if (!has_physical) return static_cast<int>(entity);
    const auto it = named_value_.find({dim, physical});
    return it != named_value_.end() ? it->second : static_cast<int>(physical);
  }

  void add_element(long long type, long long tag, const std::vector<Index>& nodes, int label) {
    Element e{tag, type, nodes, label};
    if (type == 4 || type == 11) {
      tets_.push_back(std::move(e));
    } else if (type == 2 || type == 9) {
      faces_.push_back(std::move(e));
    } else if (type == 1 || type == 8) {
      edges_.push_back(std::move(e));
    }
  }

  void read_elements41() {
    const std::size_t num_blocks = tokens_.next_count("the number of element blocks");
    tokens_.next_count("the number of elements");
    tokens_.next_integer("the smallest element tag");
    tokens_.next_integer("the largest element tag");
    std::vector<Index> nodes;
    for (std::size_t b = 0; b < num_blocks; ++b) {
      const long long dim = tokens_.next_integer("an entity dimension");
      const long long entity = tokens_.next_integer("an entity tag");
      const long long type = tokens_.next_integer("an element type");
      const std::size_t count = tokens_.next_count("the number of elements in the block");
      const int num_nodes = nodes_of_type(type);
      if (num_nodes == 0) tokens_.fail(ErrorCode::Unsupported, "element type " + std::to_string(type));
      const auto physical = entity_physical_.find({dim, entity});
      const int label = label_of(dim, physical != entity_physical_.end(),
                                 physical != entity_physical_.end() ? physical->second : 0, entity);
      for (std::size_t i = 0; i < count; ++i) {
        const long long tag = tokens_.next_integer("an element tag");
        nodes.resize(num_nodes);
        for (auto& n : nodes) n = node(tokens_.next_integer("a node tag"));
        add_element(type, tag, nodes, label);
      }
    }
    expect_end("$EndElements");
  }

  void read_elements22() {
    const std::size_t count = tokens_.next_count("the number of elements");
    std::vector<Index> nodes;
    for (std::size_t i = 0; i < count; ++i) {
      const long long tag = tokens_.next_integer("an element tag");
      const long long type = tokens_.next_integer("an element type");
      const std::size_t num_tags = tokens_.next_count("the number of element tags");
      long long physical = 0, entity = 0;
      for (std::size_t k = 0; k < num_tags; ++k) {
        const long long value = tokens_.next_integer("an element tag value");
        if (k == 0) physical = value;
        if (k == 1) entity = value;
      }
      const int num_nodes = nodes_of_type(type);
      if (num_nodes == 0) tokens_.fail(ErrorCode::Unsupported, "element type " + std::to_string(type));
      nodes.resize(num_nodes);
      for (auto& n : nodes) n = node(tokens_.next_integer("a node tag"));
      const long long dim = (type == 4 || type == 11) ? 3 : (type == 1 || type == 8) ? 1 : 2;
      // Gmsh 2.2 writes physical tag 0 for an element outside every physical group.
      add_element(type, tag, nodes, label_of(dim, num_tags > 0 && physical != 0, physical, entity));
    }
    expect_end("$EndElements");
  }

  TetMesh build() {
    const auto by_tag = [](const Element& a, const Element& b) { return a.tag < b.tag; };
    std::stable_sort(tets_.begin(), tets_.end(), by_tag);
    std::stable_sort(faces_.begin(), faces_.end(), by_tag);
    std::stable_sort(edges_.begin(), edges_.end(), by_tag);
    bool quadratic = !tets_.empty();
    for (const Element& e : tets_) quadratic = quadratic && e.type == 11;
    TetMesh mesh;
    mesh.points = std::move(points_);
    for (const Element& e : tets_) {
      const auto& n = e.nodes;
      mesh.tets.push_back({n[0], n[1], n[2], n[3]});
      mesh.tet_region.push_back(e.label);
      if (quadratic) mesh.tet_mid.push_back({n[4], n[5], n[6], n[7], n[9], n[8]});  // Gmsh: (2,3) before (1,3)
    }
    bool faces_quadratic = quadratic, edges_quadratic = quadratic;
    for (const Element& e : faces_) {
      const auto& n = e.nodes;
      mesh.faces.push_back({n[0], n[1], n[2]});
      mesh.face_facet.push_back(-1);
      mesh.face_marker.push_back(e.label);
      faces_quadratic = faces_quadratic && e.type == 9;
      if (faces_quadratic) mesh.face_mid.push_back({n[3], n[4], n[5]});
    }
    for (const Element& e : edges_) {
      mesh.edges.push_back({e.nodes[0], e.nodes[1]});
      mesh.edge_marker.push_back(e.label);
      edges_quadratic = edges_quadratic && e.type == 8;
      if (edges_quadratic) mesh.edge_mid.push_back(e.nodes[2]);
    }
    if (!faces_quadratic) mesh.face_mid.clear();
    if (!edges_quadratic) mesh.edge_mid.clear();
    if (quadratic) renumber_corners_first(mesh);
    return mesh;
  }

  Tokenizer tokens_;
  int version_ = 0;
  std::map<std::pair<long long, long long>, int> named_value_;           // (dim, physical tag) -> n of "Solid<n>"
  std::map<std::pair<long long, long long>, long long> entity_physical_;  // (dim, entity tag) -> first physical
  std::unordered_map<long long, Index> node_index_;
  std::vector<Point3> points_;
  std::vector<Element> tets_, faces_, edges_;
};

}  // namespace

TetMesh read_gmsh(const std::string& path) { return GmshReader(path).read(); }

}  // namespace qualmesh::io
