// I-DEAS Universal (.unv) reader for the datasets a tetrahedral mesh needs (see mesh_write_unv.cpp for the layouts
// and node orders): 2411 nodes (D or E exponents), 2412 elements (111 / 118 tetrahedra, 41 / 91 / 42 / 92 and the
// other triangle ids SMESH knows, 11 / 21 / 22 beams; other volume or face elements are refused), 2467 and the older
// group datasets 2417 / 2429 / 2430 / 2432 / 2435 / 2452 / 2477. Every other dataset (164 units, 2420 coordinate
// systems, ...) is skipped; coordinates are taken as written (no unit scaling, no coordinate system transform).
// Element groups give the labels: region = n of a group Solid<n> (or Region<n>, "_Volumes" suffix allowed) holding
// the tetrahedron, else the order of first appearance of a group holding volumes, else 0; face marker = n of
// Face<n> (or Face<n>_Faces), else 0; edge marker = n of Edge<n> (or Edge<n>_Edges). Node groups are ignored.
// Node orders are converted to TetMesh's (111 as written; 118 (c0 m01 c1 m12 c2 m02 m03 m13 m23 c3) -> corners +
// tet_mid); a second-order mesh's points are renumbered corners first.
#include <algorithm>
#include <cctype>
#include <map>
#include <unordered_map>

#include "mesh_groups.h"
#include "mesh_io_internal.h"

namespace qualmesh::io {
namespace {

struct Element {
  int fe_id;
  std::vector<long long> nodes;
  long line;
};

enum class Kind { Tet4, Tet10, Tri3, Tri6, Line2, Line3, Other };

Kind kind_of(int fe_id, std::size_t num_nodes) {
  switch (fe_id) {
    case 111: return Kind::Tet4;
    case 118: return Kind::Tet10;
    case 41: case 51: case 61: case 74: case 81: case 91: return Kind::Tri3;
    case 42: case 52: case 62: case 72: case 82: case 92: return Kind::Tri6;
    case 11: case 21: return num_nodes == 3 ? Kind::Line3 : Kind::Line2;
    case 22: case 23: case 24: return num_nodes == 3 ? Kind::Line3 : Kind::Line2;
    default: return Kind::Other;
  }
}

bool is_beam(int fe_id) { return fe_id == 11 || (fe_id >= 21 && fe_id <= 25); }

// n of "<prefix><n>[suffix]" (SolidM<n>: -n).
bool numbered(std::string name, const char* prefix, const char* suffix, int& value) {
  const std::string s(suffix);
  if (name.size() > s.size() && name.compare(name.size() - s.size(), s.size(), s) == 0) name.resize(name.size() - s.size());
  const std::string p(prefix);
  if (name.size() <= p.size() || name.compare(0, p.size(), p) != 0) return false;
  std::string digits = name.substr(p.size());
  int sign = 1;
  if (digits[0] == 'M') {
    sign = -1;
    digits = digits.substr(1);
  }
  if (digits.empty() || digits.size() > 9 || !std::all_of(digits.begin(), digits.end(), ::isdigit)) return false;
  value = sign * std::stoi(digits);
  return true;
}

class UnvReader {
 public:
  explicit UnvReader(const std::string& path) : path_(path) {
    const std::string text = read_whole_file(path);
    std::size_t pos = 0;
    while (pos < text.size()) {
      std::size_t end = text.find('\n', pos);
      if (end == std::string::npos) end = text.size();
      std::string line = text.substr(pos, end - pos);
      if (!line.empty() && line.back() == '\r') line.pop_back();
      lines_.push_back(std::move(line));
      pos = end + 1;
    }
  }

  TetMesh read() {
    bool have_nodes = false, have_elements = false;
    std::size_t i = 0;
    while (i < lines_.size()) {
      if (trimmed(i) != "-1") {
        if (trimmed(i).empty()) {
          ++i;
          continue;
        }
        fail(i, ErrorCode::Parse, "expected '-1' opening a dataset, got '" + trimmed(i) + "'");
      }
      if (i + 1 >= lines_.size()) break;
      const std::string id = trimmed(i + 1);
      std::size_t end = i + 2;
      while (end < lines_.size() && trimmed(end) != "-1") ++end;
      if (end >= lines_.size()) fail(i + 1, ErrorCode::Parse, "dataset " + id + " is not closed by '-1'");
      if (id == "2411") {
        read_nodes(i + 2, end);
        have_nodes = true;
      } else if (id == "2412") {
        read_elements(i + 2, end);
        have_elements = true;
      } else if (id == "2467" || id == "2417" || id == "2429" || id == "2430" || id == "2432" || id == "2435" ||
                 id == "2452" || id == "2477") {
        read_groups(i + 2, end, id == "2417" || id == "2429" || id == "2430" || id == "2432" ? 2 : 4);
      }
      i = end + 1;
    }
    if (!have_nodes || !have_elements) fail(0, ErrorCode::Parse, "no 2411 (nodes) or 2412 (elements) dataset");
    return build();
  }

 private:
  std::string trimmed(std::size_t i) const {
    const std::string& s = lines_[i];
    const auto b = s.find_first_not_of(" \t");
    return b == std::string::npos ? std::string() : s.substr(b, s.find_last_not_of(" \t") - b + 1);
  }

  [[noreturn]] void fail(std::size_t line_index, ErrorCode code, const std::string& message) const {
    throw InputError(code, message, path_, static_cast<long>(line_index) + 1);
  }

  // Whitespace-separated fields of line i.
  std::vector<std::string> fields(std::size_t i) const {
    std::vector<std::string> out;
    const std::string& s = lines_[i];
    std::size_t p = 0;
    while (true) {
      p = s.find_first_not_of(" \t", p);
      if (p == std::string::npos) break;
      const std::size_t e = s.find_first_of(" \t", p);
      out.push_back(s.substr(p, e == std::string::npos ? std::string::npos : e - p));
      if (e == std::string::npos) break;
      p = e;
    }
    return out;
  }

  long long integer(const std::string& field, std::size_t line, const char* what) const {
    char* end = nullptr;
    const long long value = std::strtoll(field.c_str(), &end, 10);
    if (field.empty() || *end != '\0') fail(line, ErrorCode::Parse, std::string("expected ") + what + ", got '" + field + "'");
    return value;
  }

  // Integers of the lines from `i` on until `count` are read; returns the line after the last one used.
  std::size_t integers(std::size_t i, std::size_t end, std::size_t count, std::vector<long long>& out, const char* what) const {
    out.clear();
    while (out.size() < count) {
      if (i >= end) fail(end, ErrorCode::Parse, std::string("dataset ends inside a record, expected ") + what);
      for (const std::string& f : fields(i)) out.push_back(integer(f, i, what));
      ++i;
    }
    if (out.size() != count) fail(i - 1, ErrorCode::Parse, std::string("too many values, expected ") + what);
    return i;
  }

  void read_nodes(std::size_t i, std::size_t end) {
    std::vector<long long> head;
    while (i < end) {
      if (trimmed(i).empty()) {
        ++i;
        continue;
      }
      i = integers(i, end, 4, head, "a node record 'label cs cs color'");
      if (i >= end) fail(end, ErrorCode::Parse, "node " + std::to_string(head[0]) + " has no coordinates");
      const std::vector<std::string> c = fields(i);
      if (c.size() != 3) fail(i, ErrorCode::Parse, "expected three coordinates");
      Point3 p{};
      for (int k = 0; k < 3; ++k) {
        std::string s = c[k];
        for (char& ch : s) {
          if (ch == 'D' || ch == 'd') ch = 'E';
        }
        char* stop = nullptr;
        p[k] = std::strtod(s.c_str(), &stop);
        if (*stop != '\0') fail(i, ErrorCode::Parse, "expected a coordinate, got '" + c[k] + "'");
        if (!std::isfinite(p[k])) fail(i, ErrorCode::NonFinite, "coordinate is not finite: '" + c[k] + "'");
      }
      if (!node_index_.emplace(head[0], static_cast<Index>(points_.size())).second) {
        fail(i - 1, ErrorCode::Parse, "node " + std::to_string(head[0]) + " defined twice");
      }
      points_.push_back(p);
      ++i;
    }
  }

  void read_elements(std::size_t i, std::size_t end) {
    std::vector<long long> head, extra;
    while (i < end) {
      if (trimmed(i).empty()) {
        ++i;
        continue;
      }
      const std::size_t line = i;
      i = integers(i, end, 6, head, "an element record 'label type phys mat color n'");
      const int fe_id = static_cast<int>(head[1]);
      if (head[5] < 1 || head[5] > 100) fail(line, ErrorCode::Parse, "absurd node count " + std::to_string(head[5]));
      if (is_beam(fe_id)) i = integers(i, end, 3, extra, "the beam record 'orientation fore aft'");
      Element e{fe_id, {}, static_cast<long>(line)};
      i = integers(i, end, static_cast<std::size_t>(head[5]), e.nodes, "node labels");
      const Kind kind = kind_of(fe_id, e.nodes.size());
      const std::size_t want[] = {4, 10, 3, 6, 2, 3, 0};
      if (kind == Kind::Other) {
        fail(line, ErrorCode::Unsupported, "element type " + std::to_string(fe_id) +
                                               " (only tetrahedra 111/118, triangles and beams are read)");
      }
      if (e.nodes.size() != want[static_cast<int>(kind)]) {
        fail(line, ErrorCode::Parse, "element type " + std::to_string(fe_id) + " with " +
                                         std::to_string(e.nodes.size()) + " nodes");
      }
      if (!elements_.emplace(head[0], e).second) fail(line, ErrorCode::Parse, "element " + std::to_string(head[0]) + " defined twice");
      order_.push_back(head[0]);
    }
  }

  void read_groups(std::size_t i, std::size_t end, int per_entity) {
    std::vector<long long> head, entities;
    while (i < end) {
      if (trimmed(i).empty()) {
        ++i;
        continue;
      }
      i = integers(i, end, 8, head, "a group record (8 integers)");
      if (i >= end) fail(end, ErrorCode::Parse, "group without a name");
      const std::string name = trimmed(i++);
      if (head[7] < 0) fail(i - 2, ErrorCode::Parse, "negative group size");
      i = integers(i, end, static_cast<std::size_t>(head[7]) * per_entity, entities, "group entities");
      std::vector<long long> elements;
      for (std::size_t k = 0; k < entities.size(); k += per_entity) {
        if (entities[k] == 8) elements.push_back(entities[k + 1]);
      }
      if (!elements.empty()) groups_.emplace_back(name, std::move(elements));
    }
  }

  Index node(long long label, long line) const {
    const auto it = node_index_.find(label);
    if (it == node_index_.end()) fail(static_cast<std::size_t>(line), ErrorCode::IndexOutOfRange, "missing node " + std::to_string(label));
    return it->second;
  }

  TetMesh build() {
    std::unordered_map<long long, int> region_of, marker_of, edge_marker_of, volume_group_of;
    int volume_groups = 0;
    for (const auto& [name, members] : groups_) {
      int value = 0;
      bool has_volume = false;
      for (long long id : members) {
        const auto it = elements_.find(id);
        if (it == elements_.end()) {
          throw InputError(ErrorCode::IndexOutOfRange, "group " + name + " names missing element " + std::to_string(id), path_);
        }
        const Kind k = kind_of(it->second.fe_id, it->second.nodes.size());
        has_volume = has_volume || k == Kind::Tet4 || k == Kind::Tet10;
      }
      if (numbered(name, "Solid", "_Volumes", value) || numbered(name, "Region", "_Volumes", value)) {
        for (long long id : members) region_of.emplace(id, value);
      } else if (numbered(name, "Face", "_Faces", value)) {
        for (long long id : members) marker_of.emplace(id, value);
      } else if (numbered(name, "Edge", "_Edges", value)) {
        for (long long id : members) edge_marker_of.emplace(id, value);
      } else if (has_volume) {
        ++volume_groups;
        for (long long id : members) volume_group_of.emplace(id, volume_groups);
      }
    }
    const auto label = [](const std::unordered_map<long long, int>& of, long long id, int fallback) {
      const auto it = of.find(id);
      return it == of.end() ? fallback : it->second;
    };
    bool any_tet4 = false, any_tet10 = false;
    for (const auto& [id, e] : elements_) {
      any_tet4 = any_tet4 || e.fe_id == 111;
      any_tet10 = any_tet10 || e.fe_id == 118;
    }
    if (any_tet4 && any_tet10) throw InputError(ErrorCode::Unsupported, "mixed linear and quadratic tetrahedra", path_);
    TetMesh mesh;
    for (long long id : order_) {
      const Element& e = elements_.at(id);
      std::vector<Index> u;
      for (long long n : e.nodes) u.push_back(node(n, e.line));
      switch (kind_of(e.fe_id, u.size())) {
        case Kind::Tet4:
          mesh.tets.push_back({u[0], u[1], u[2], u[3]});
          mesh.tet_region.push_back(label(region_of, id, label(volume_group_of, id, 0)));
          break;
        case Kind::Tet10:
          mesh.tets.push_back({u[0], u[2], u[4], u[9]});
          mesh.tet_mid.push_back({u[1], u[3], u[5], u[6], u[7], u[8]});
          mesh.tet_region.push_back(label(region_of, id, label(volume_group_of, id, 0)));
          break;
        case Kind::Tri3:
        case Kind::Tri6:
          if (u.size() == 6) {
            mesh.faces.push_back({u[0], u[2], u[4]});
            mesh.face_mid.push_back({u[1], u[3], u[5]});
          } else {
            mesh.faces.push_back({u[0], u[1], u[2]});
          }
          mesh.face_facet.push_back(-1);
          mesh.face_marker.push_back(label(marker_of, id, 0));
          break;
        case Kind::Line2:
        case Kind::Line3:
          if (u.size() == 3) {
            mesh.edges.push_back({u[0], u[2]});
            mesh.edge_mid.push_back(u[1]);
          } else {
            mesh.edges.push_back({u[0], u[1]});
          }
          mesh.edge_marker.push_back(label(edge_marker_of, id, 0));
          break;
        case Kind::Other: break;
      }
    }
    const bool quadratic = !mesh.tet_mid.empty();
    if (!quadratic || mesh.face_mid.size() != mesh.faces.size()) mesh.face_mid.clear();
    if (!quadratic || mesh.edge_mid.size() != mesh.edges.size()) mesh.edge_mid.clear();
    mesh.points = std::move(points_);
    if (quadratic) renumber_corners_first(mesh);
    return mesh;
  }

  std::string path_;
  std::vector<std::string> lines_;
  std::vector<Point3> points_;
  std::unordered_map<long long, Index> node_index_;
  std::unordered_map<long long, Element> elements_;
  std::vector<long long> order_;
  std::vector<std::pair<std::string, std::vector<long long>>> groups_;
};

}  // namespace

TetMesh read_unv(const std::string& path) { return UnvReader(path).read(); }

}  // namespace qualmesh::io
