// Abaqus / CalculiX .inp reader (Abaqus Keywords Reference; CalculiX 2.20 manual, section 7), for the decks that
// QualMesh's writer, FreeCAD's FemMesh.write / CalculiX writer and Gmsh write:
//   *NODE [, NSET=n]                        "id, x, y[, z]";
//   *ELEMENT, TYPE=t [, ELSET=s]            C3D4*, C3D10* -> tetrahedra (C3D10: tet_mid, nodes 5..10 are the
//                                           mid-nodes of edges 1-2 2-3 1-3 1-4 2-4 3-4); triangles (S3, S3R, STRI3,
//                                           CPS3, CPE3, M3D3, S6, STRI65, CPS6, CPE6, M3D6) -> faces; lines (B31,
//                                           T3D2, B32, T3D3) -> edges; other element types are refused;
//   *ELSET / *NSET, ELSET|NSET=s [, GENERATE]  ids or set names, or "first, last[, step]";
//   *SURFACE, NAME=s [, TYPE=ELEMENT]        "element or elset, S<k>" -> faces (the corners of side k of the tet,
//                                           S1 = 1-2-3, S2 = 1-4-2, S3 = 2-4-3, S4 = 3-4-1, written reversed so that
//                                           the normal points out of a positively oriented tet);
//   *INCLUDE, INPUT=file                     read in place (relative to the including file);
//   every other keyword is skipped with its data lines. Keywords and parameters are case-insensitive, "**" starts
//   a comment line, a data line ending in ',' continues on the next one (elements).
// Region of a tetrahedron: n of the first set named Solid<n> / Region<n> (SolidM<n>: -n) that holds it, else the
// 1-based order of first appearance of its *ELEMENT block's ELSET, else 0. Face marker: n of the surface (or
// triangle ELSET) named Face<n>, else the surface's order of appearance. Edge marker: n of an ELSET Edge<n>.
// Node sets are not needed to rebuild the mesh (Face<n> / Edge<n> node sets follow from the faces and edges) and
// are only checked for missing nodes. A second-order mesh's points are renumbered corners first (TetMesh's rule);
// a linear mesh keeps the file's node order. Element node orders are kept as in the file.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cctype>
#include <filesystem>
#include <map>
#include <unordered_map>
#include <unordered_set>

#include "mesh_groups.h"
#include "mesh_io_internal.h"

namespace qualmesh::io {
namespace {

std::string upper(std::string s) {
  for (char& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return s;
}

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return {};
  return s.substr(b, s.find_last_not_of(" \t\r") - b + 1);
}

std::vector<std::string> split_commas(const std::string& line) {
  std::vector<std::string> fields;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    fields.push_back(trim(line.substr(start, comma == std::string::npos ? std::string::npos : comma - start)));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return fields;
}

// n of "<PREFIX><n>" / "<PREFIX>M<n>" (case-insensitive), or false.
bool numbered_name(const std::string& name, const char* prefix, int& value) {
  const std::string u = upper(name), p = upper(prefix);
  if (u.size() <= p.size() || u.compare(0, p.size(), p) != 0) return false;
  std::string digits = u.substr(p.size());
  bool negative = false;
  if (digits[0] == 'M') {
    negative = true;
    digits = digits.substr(1);
  }
  if (digits.empty() || digits.size() > 9 || !std::all_of(digits.begin(), digits.end(), ::isdigit)) return false;
  value = (negative ? -1 : 1) * std::stoi(digits);
  return true;
}

enum class Kind { Tet4, Tet10, Tri3, Tri6, Line2, Line3, Unknown };

Kind kind_of(const std::string& type) {
  if (type.rfind("C3D10", 0) == 0) return Kind::Tet10;
  if (type.rfind("C3D4", 0) == 0) return Kind::Tet4;
  for (const char* t : {"S3", "S3R", "STRI3", "CPS3", "CPE3", "M3D3", "CAX3", "DS3", "SFM3D3"}) {
    if (type == t) return Kind::Tri3;
  }
  for (const char* t : {"S6", "STRI65", "CPS6", "CPE6", "M3D6", "CAX6", "DS6", "SFM3D6"}) {
    if (type == t) return Kind::Tri6;
  }
  for (const char* t : {"B31", "T3D2", "B31R", "T2D2", "B21"}) {
    if (type == t) return Kind::Line2;
  }
  for (const char* t : {"B32", "T3D3", "B32R", "T2D3", "B22"}) {
    if (type == t) return Kind::Line3;
  }
  return Kind::Unknown;
}

int num_nodes(Kind k) {
  switch (k) {
    case Kind::Tet4: return 4;
    case Kind::Tet10: return 10;
    case Kind::Tri3: return 3;
    case Kind::Tri6: return 6;
    case Kind::Line2: return 2;
    case Kind::Line3: return 3;
    default: return 0;
  }
}

struct Element {
  Kind kind;
  std::vector<long long> nodes;  // node ids
  int block_set = 0;             // 1-based order of its *ELEMENT block's ELSET among the blocks' sets, 0 = none
  long line = 0;                 // of its data line
};

struct Set {
  std::string name;
  std::vector<long long> ids;            // in order of first appearance, each once
  std::unordered_set<long long> members;  // the same ids: a set that names an id again, or itself, gains nothing
};

// All sets together name at most this many ids per node and element defined, plus kSetMembersSlack: a set names
// each id once, but a few lines that copy sets into sets can otherwise ask for gigabytes (a fuzzing finding).
constexpr std::size_t kSetMembersPerEntity = 16;
constexpr std::size_t kSetMembersSlack = 1000000;

class AbaqusReader {
 public:
  explicit AbaqusReader(const std::string& path) : path_(path), file_(path) {}

  TetMesh read() {
    read_file(path_, 0);
    return build();
  }

 private:
  [[noreturn]] void fail(ErrorCode code, const std::string& message) const {
    throw InputError(code, message, file_, line_);
  }

  long long to_id(const std::string& field, const char* what) const {
    long long value = 0;
    const char* end = field.data() + field.size();
    const auto result = std::from_chars(field.data(), end, value);
    if (field.empty() || result.ec != std::errc() || result.ptr != end) {
      fail(ErrorCode::Parse, std::string("expected ") + what + " (an integer), got '" + field + "'");
    }
    return value;
  }

  double to_real(const std::string& field) const {
    std::string s = field;
    for (char& c : s) {
      if (c == 'd' || c == 'D') c = 'e';  // Fortran exponents
    }
    char* end = nullptr;
    const double value = std::strtod(s.c_str(), &end);
    if (s.empty() || *end != '\0') fail(ErrorCode::Parse, "expected a coordinate, got '" + field + "'");
    if (!std::isfinite(value)) fail(ErrorCode::NonFinite, "coordinate is not finite: '" + field + "'");
    return value;
  }

  void read_file(const std::string& path, int depth) {
    if (depth > 10) fail(ErrorCode::Parse, "*INCLUDE nested too deeply");
    const std::string text = read_whole_file(path);
    const std::string saved_file = file_;
    const long saved_line = line_;
    file_ = path;
    line_ = 0;
    std::size_t pos = 0;
    std::vector<std::string> lines;
    std::vector<long> numbers;
    long number = 0;
    while (pos < text.size()) {
      std::size_t end = text.find('\n', pos);
      if (end == std::string::npos) end = text.size();
      ++number;
      std::string line = trim(text.substr(pos, end - pos));
      pos = end + 1;
      if (line.empty() || line.rfind("**", 0) == 0) continue;
      lines.push_back(std::move(line));
      numbers.push_back(number);
    }
    std::size_t i = 0;
    while (i < lines.size()) {
      line_ = numbers[i];
      if (lines[i][0] != '*') fail(ErrorCode::Parse, "data line outside a keyword: '" + lines[i] + "'");
      const std::vector<std::string> fields = split_commas(lines[i].substr(1));
      const std::string keyword = upper(fields[0]);
      std::map<std::string, std::string> params;
      for (std::size_t k = 1; k < fields.size(); ++k) {
        const std::size_t eq = fields[k].find('=');
        if (eq == std::string::npos) params[upper(fields[k])] = "";
        else params[upper(trim(fields[k].substr(0, eq)))] = trim(fields[k].substr(eq + 1));
      }
      std::size_t next = i + 1;
      while (next < lines.size() && lines[next][0] != '*') ++next;
      if (keyword == "INCLUDE") {
        const auto input = params.find("INPUT");
        if (input == params.end() || input->second.empty()) fail(ErrorCode::Parse, "*INCLUDE without INPUT=");
        std::string name = input->second;
        if (name.size() > 1 && name.front() == '"' && name.back() == '"') name = name.substr(1, name.size() - 2);
        const std::filesystem::path included = std::filesystem::path(path).parent_path() / name;
        read_file(std::filesystem::path(name).is_absolute() ? name : included.string(), depth + 1);
        file_ = path;
      } else {
        for (std::size_t k = i + 1; k < next; ++k) {
          line_ = numbers[k];
          data(keyword, params, lines, numbers, k, next);
        }
      }
      i = next;
    }
    file_ = saved_file;
    line_ = saved_line;
  }

  std::string param(const std::map<std::string, std::string>& params, const char* key) const {
    const auto it = params.find(key);
    return it == params.end() ? std::string() : it->second;
  }

  // One data line (index k, possibly consuming continuation lines up to `end`) of keyword `keyword`.
  void data(const std::string& keyword, const std::map<std::string, std::string>& params,
            const std::vector<std::string>& lines, const std::vector<long>& numbers, std::size_t& k, std::size_t end) {
    std::vector<std::string> fields = split_commas(lines[k]);
    if (keyword == "NODE") {
      if (fields.size() < 3) fail(ErrorCode::Parse, "node line needs 'id, x, y[, z]'");
      const long long id = to_id(fields[0], "a node id");
      Point3 p{0, 0, 0};
      for (std::size_t c = 0; c < 3 && c + 1 < fields.size(); ++c) {
        if (!fields[c + 1].empty()) p[c] = to_real(fields[c + 1]);
      }
      if (!node_index_.emplace(id, static_cast<Index>(points_.size())).second) {
        fail(ErrorCode::Parse, "node " + std::to_string(id) + " defined twice");
      }
      points_.push_back(p);
      node_line_.push_back(line_);
    } else if (keyword == "ELEMENT") {
      const std::string type = upper(param(params, "TYPE"));
      const Kind kind = kind_of(type);
      if (kind == Kind::Unknown) {
        fail(ErrorCode::Unsupported, "element type '" + type +
                                         "' (only C3D4, C3D10, 3- and 6-node triangles and 2- and 3-node lines are read)");
      }
      const std::size_t want = static_cast<std::size_t>(num_nodes(kind)) + 1;
      // A line ending in ',' continues on the next one.
      while (fields.size() <= want && fields.back().empty() && k + 1 < end) {
        fields.pop_back();
        ++k;
        line_ = numbers[k];
        const auto more = split_commas(lines[k]);
        fields.insert(fields.end(), more.begin(), more.end());
      }
      while (!fields.empty() && fields.back().empty()) fields.pop_back();
      if (fields.size() != want) {
        fail(ErrorCode::Parse, type + " element needs " + std::to_string(want) + " entries (id and nodes), got " +
                                   std::to_string(fields.size()));
      }
      Element e{kind, {}, 0, line_};
      const long long id = to_id(fields[0], "an element id");
      for (std::size_t n = 1; n < fields.size(); ++n) e.nodes.push_back(to_id(fields[n], "a node id"));
      const std::string elset = param(params, "ELSET");
      if (!elset.empty()) {
        const std::string key = upper(elset);
        auto it = block_sets_.find(key);
        if (it == block_sets_.end()) it = block_sets_.emplace(key, static_cast<int>(block_sets_.size()) + 1).first;
        e.block_set = it->second;
      }
      if (!elements_.emplace(id, e).second) fail(ErrorCode::Parse, "element " + std::to_string(id) + " defined twice");
      element_order_.push_back(id);
      if (!elset.empty()) add_to_set(elsets_, elset, id);
    } else if (keyword == "ELSET" || keyword == "NSET") {
      const bool is_elset = keyword == "ELSET";
      const std::string name = param(params, is_elset ? "ELSET" : "NSET");
      if (name.empty()) fail(ErrorCode::Parse, "*" + keyword + " without " + keyword + "=");
      auto& sets = is_elset ? elsets_ : nsets_;
      if (params.count("GENERATE")) {
        if (fields.size() < 2 || fields.size() > 3) fail(ErrorCode::Parse, "GENERATE needs 'first, last[, step]'");
        const long long first = to_id(fields[0], "a first id"), last = to_id(fields[1], "a last id");
        const long long step = fields.size() == 3 ? to_id(fields[2], "a step") : 1;
        if (step <= 0 || last < first || (last - first) / step > 100000000) fail(ErrorCode::Parse, "bad GENERATE range");
        for (long long id = first; id <= last; id += step) add_to_set(sets, name, id);
      } else {
        for (const std::string& f : fields) {
          if (f.empty()) continue;
          if (std::isdigit(static_cast<unsigned char>(f[0])) || f[0] == '-') {
            add_to_set(sets, name, to_id(f, "an id"));
          } else {
            const auto other = sets.find(upper(f));
            if (other == sets.end()) fail(ErrorCode::Parse, "unknown set '" + f + "'");
            const std::vector<long long> ids = other->second.ids;
            for (long long id : ids) add_to_set(sets, name, id);
          }
        }
      }
    } else if (keyword == "SURFACE") {
      const std::string type = upper(param(params, "TYPE"));
      if (!type.empty() && type != "ELEMENT") return;  // nodal surfaces carry no faces
      const std::string name = param(params, "NAME");
      if (name.empty()) fail(ErrorCode::Parse, "*SURFACE without NAME=");
      if (fields.size() < 2) fail(ErrorCode::Parse, "surface line needs 'element or set, S<k>'");
      const std::string side = upper(fields[1]);
      if (side.size() != 2 || side[0] != 'S' || side[1] < '1' || side[1] > '4') {
        fail(ErrorCode::Parse, "surface side '" + fields[1] + "' (tetrahedra have S1..S4)");
      }
      auto it = surface_order_.find(upper(name));
      if (it == surface_order_.end()) {
        it = surface_order_.emplace(upper(name), static_cast<int>(surface_order_.size()) + 1).first;
      }
      int marker = it->second;
      numbered_name(name, "Face", marker);
      std::vector<long long> ids;
      if (std::isdigit(static_cast<unsigned char>(fields[0][0]))) {
        ids.push_back(to_id(fields[0], "an element id"));
      } else {
        const auto set = elsets_.find(upper(fields[0]));
        if (set == elsets_.end()) fail(ErrorCode::Parse, "unknown element set '" + fields[0] + "'");
        ids = set->second.ids;
      }
      for (long long id : ids) sides_.push_back({id, side[1] - '1', marker, line_});
    }
    // Every other keyword (*HEADING, *MATERIAL, *STEP, ...): its data lines are skipped.
  }

  // Adds id to set `name` of `sets` (elsets_ or nsets_). The id must name an element or node defined above.
  void add_to_set(std::map<std::string, Set>& sets, const std::string& name, long long id) {
    const bool of_elements = &sets == &elsets_;
    if (of_elements ? !elements_.count(id) : !node_index_.count(id)) {
      const char* what = of_elements ? "element" : "node";
      fail(ErrorCode::IndexOutOfRange, std::string(what) + " set " + name + " names missing " + what + " " +
                                           std::to_string(id) + " (a set names " + what + "s defined above it)");
    }
    auto& set = sets[upper(name)];
    if (set.name.empty()) {
      set.name = name;
      if (of_elements) elset_order_.push_back(&set);
    }
    if (!set.members.insert(id).second) return;
    const std::size_t most = kSetMembersPerEntity * (points_.size() + elements_.size()) + kSetMembersSlack;
    if (++num_set_members_ > most) {
      fail(ErrorCode::Parse, "absurd set sizes: the sets name more than " + std::to_string(most) +
                                 " ids in all, for " + std::to_string(points_.size()) + " nodes and " +
                                 std::to_string(elements_.size()) + " elements");
    }
    set.ids.push_back(id);
  }

  Index node(long long id, long line) const {
    const auto it = node_index_.find(id);
    if (it == node_index_.end()) {
      throw InputError(ErrorCode::IndexOutOfRange, "reference to missing node " + std::to_string(id), file_, line);
    }
    return it->second;
  }

  TetMesh build();

  struct Side {
    long long element;
    int side;
    int marker;
    long line;
  };

  std::string path_, file_;
  long line_ = 0;
  std::vector<Point3> points_;
  std::vector<long> node_line_;
  std::unordered_map<long long, Index> node_index_;
  std::unordered_map<long long, Element> elements_;
  std::vector<long long> element_order_;
  std::map<std::string, int> block_sets_, surface_order_;
  std::map<std::string, Set> elsets_, nsets_;
  std::vector<const Set*> elset_order_;  // element sets in order of first appearance
  std::size_t num_set_members_ = 0;      // over all sets (add_to_set)
  std::vector<Side> sides_;
};

TetMesh AbaqusReader::build() {
  // Labels from numbered sets, the first such set (in order of appearance) of an element winning.
  std::unordered_map<long long, int> region_of, marker_of, edge_marker_of;
  for (const Set* set : elset_order_) {
    int value = 0;
    if (numbered_name(set->name, "Solid", value) || numbered_name(set->name, "Region", value)) {
      for (long long id : set->ids) region_of.emplace(id, value);
    } else if (numbered_name(set->name, "Face", value)) {
      for (long long id : set->ids) marker_of.emplace(id, value);
    } else if (numbered_name(set->name, "Edge", value)) {
      for (long long id : set->ids) edge_marker_of.emplace(id, value);
    }
  }
  const auto label = [](const std::unordered_map<long long, int>& of, long long id, int fallback) {
    const auto it = of.find(id);
    return it == of.end() ? fallback : it->second;
  };

  TetMesh mesh;
  bool all_tet10 = true, any_tet = false;
  for (long long id : element_order_) {
    const Element& e = elements_.at(id);
    if (e.kind == Kind::Tet4 || e.kind == Kind::Tet10) {
      any_tet = true;
      all_tet10 = all_tet10 && e.kind == Kind::Tet10;
    }
  }
  const bool quadratic = any_tet && all_tet10;
  std::unordered_map<long long, std::size_t> tet_index;
  const auto nodes_of = [&](const Element& e) {
    std::vector<Index> v;
    for (long long n : e.nodes) v.push_back(node(n, e.line));
    return v;
  };
  for (long long id : element_order_) {
    const Element& e = elements_.at(id);
    const std::vector<Index> v = nodes_of(e);
    switch (e.kind) {
      case Kind::Tet4:
      case Kind::Tet10:
        tet_index[id] = mesh.tets.size();
        mesh.tets.push_back({v[0], v[1], v[2], v[3]});
        mesh.tet_region.push_back(label(region_of, id, e.block_set));
        if (quadratic) mesh.tet_mid.push_back({v[4], v[5], v[6], v[7], v[8], v[9]});
        break;
      case Kind::Tri3:
      case Kind::Tri6:
        mesh.faces.push_back({v[0], v[1], v[2]});
        mesh.face_facet.push_back(-1);
        mesh.face_marker.push_back(label(marker_of, id, 0));
        if (e.kind == Kind::Tri6) mesh.face_mid.push_back({v[3], v[4], v[5]});
        break;
      case Kind::Line2:
      case Kind::Line3:
        mesh.edges.push_back({v[0], v[1]});
        mesh.edge_marker.push_back(label(edge_marker_of, id, 0));
        if (e.kind == Kind::Line3) mesh.edge_mid.push_back(v[2]);
        break;
      default: break;
    }
  }
  // Element faces of the surfaces, reversed so that their normal points out of a positive tetrahedron.
  static const int kSides[4][3] = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {2, 0, 3}};
  for (const Side& s : sides_) {
    const auto it = tet_index.find(s.element);
    if (it == tet_index.end()) {
      throw InputError(ErrorCode::IndexOutOfRange,
                       "surface names element " + std::to_string(s.element) + ", which is not a tetrahedron", path_,
                       s.line);
    }
    const auto& t = mesh.tets[it->second];
    const int* c = kSides[s.side];
    mesh.faces.push_back({t[c[0]], t[c[1]], t[c[2]]});
    mesh.face_facet.push_back(-1);
    mesh.face_marker.push_back(s.marker);
    if (quadratic) {
      std::array<Index, 3> m{};
      for (int k = 0; k < 3; ++k) {
        const int a = c[k], b = c[(k + 1) % 3];
        for (int edge = 0; edge < 6; ++edge) {
          if ((kTetEdges[edge][0] == a && kTetEdges[edge][1] == b) || (kTetEdges[edge][0] == b && kTetEdges[edge][1] == a)) {
            m[k] = mesh.tet_mid[it->second][edge];
          }
        }
      }
      mesh.face_mid.push_back(m);
    }
  }
  if (!quadratic || mesh.face_mid.size() != mesh.faces.size()) mesh.face_mid.clear();
  if (!quadratic || mesh.edge_mid.size() != mesh.edges.size()) mesh.edge_mid.clear();
  mesh.points = std::move(points_);
  if (quadratic) renumber_corners_first(mesh);
  return mesh;
}

}  // namespace

TetMesh read_abaqus(const std::string& path) { return AbaqusReader(path).read(); }

}  // namespace qualmesh::io
