// Elmer mesh directory writer (ElmerSolver manual, appendix "Format of mesh files"; ElmerGrid manual): the output
// path (extension .elmer) names a directory holding
//   mesh.header    "nodes elements boundary_elements", the number of element types, then "type count" per type;
//   mesh.nodes     "id -1 x y z" (partition -1 = none);
//   mesh.elements  "id body type n1 .. nk": body = region label (Solid<r> is body r), type 504 (linear tetrahedron)
//                  or 510 (quadratic: corners, then the mid-nodes of (1,2) (2,3) (3,1) (1,4) (2,4) (3,4), VTK's and
//                  TetMesh::tet_mid's order);
//   mesh.boundary  "id tag parent1 parent2 type n1 .. nk": tag = face label (Face<m> is boundary m), the parents
//                  are the one or two tetrahedra having the face (0 = none), type 303 or 306 (mid-nodes of (1,2)
//                  (2,3) (3,1));
//   mesh.names     as ElmerGrid writes it: "! ----- names for bodies -----", "$ Solid<r> = r", then
//                  "! ----- names for boundaries -----", "$ Face<m> = m".
// Bodies and boundary tags must be positive: a label <= 0 gets a fresh number above every positive label (its name
// in mesh.names still says which group it is). Edges (Edge<e>) are not written: a 3D Elmer mesh's boundary elements
// are its faces. Ids are 1-based; nodes keep TetMesh's order. The directory is one OutputSet (atomic_file.h): written
// under a temporary name and renamed into place; an existing directory of that name is replaced only once the new one
// is complete, and stays as it was when anything fails (or a signal stops the run).
#include <algorithm>
#include <filesystem>
#include <functional>
#include <map>

#include "atomic_file.h"
#include "mesh_groups.h"
#include "mesh_io_internal.h"

namespace qualmesh::io {
namespace {

namespace fs = std::filesystem;

// label -> positive Elmer number (labels > 0 keep theirs).
std::map<int, int> elmer_numbers(const std::vector<int>& labels) {
  std::map<int, int> numbers;
  int max_label = 0;
  for (int l : labels) {
    numbers.emplace(l, 0);
    max_label = std::max(max_label, l);
  }
  for (auto& [label, number] : numbers) number = label > 0 ? label : ++max_label;
  return numbers;
}

}  // namespace

void write_elmer(const TetMesh& mesh, const std::string& path) {
  std::string clean = path;
  while (clean.size() > 1 && clean.back() == '/') clean.pop_back();
  const fs::path target(clean);
  if (target.has_parent_path() && !fs::is_directory(target.parent_path())) {
    throw InputError(ErrorCode::Io, "folder '" + target.parent_path().string() + "' does not exist", path);
  }
  if (fs::exists(target) && !fs::is_directory(target)) {
    throw InputError(ErrorCode::Io, "exists and is not a directory (an Elmer mesh is a directory)", path);
  }
  const MidNodes mids = mid_nodes(mesh);
  const bool quadratic = mids.tet != nullptr;
  const std::vector<int> regions = tet_region_labels(mesh);
  const std::vector<int> labels = face_labels(mesh);
  const std::map<int, int> bodies = elmer_numbers(regions), tags = elmer_numbers(labels);

  // Parents of each face: the tetrahedra having its three corners.
  std::map<std::array<Index, 3>, std::pair<std::size_t, std::size_t>> parents;
  const auto key = [](Index a, Index b, Index c) {
    std::array<Index, 3> k{a, b, c};
    std::sort(k.begin(), k.end());
    return k;
  };
  for (const auto& f : mesh.faces) parents.emplace(key(f[0], f[1], f[2]), std::make_pair(0, 0));
  for (std::size_t t = 0; t < mesh.tets.size() && !parents.empty(); ++t) {
    const auto& v = mesh.tets[t];
    for (int skip = 0; skip < 4; ++skip) {
      Index c[3];
      for (int i = 0, k = 0; i < 4; ++i) {
        if (i != skip) c[k++] = v[i];
      }
      const auto it = parents.find(key(c[0], c[1], c[2]));
      if (it == parents.end()) continue;
      (it->second.first == 0 ? it->second.first : it->second.second) = t + 1;
    }
  }

  OutputSet output;
  const std::string temp = output.write_directory(clean);
  {
    const int tet_type = quadratic ? 510 : 504, tri_type = quadratic ? 306 : 303;
    output.write_inside(temp, "mesh.header", path, [&](std::ostream& out) {
      out << mesh.points.size() << ' ' << mesh.tets.size() << ' ' << mesh.faces.size() << '\n';
      const int num_types = (mesh.tets.empty() ? 0 : 1) + (mesh.faces.empty() ? 0 : 1);
      out << num_types << '\n';
      if (!mesh.tets.empty()) out << tet_type << ' ' << mesh.tets.size() << '\n';
      if (!mesh.faces.empty()) out << tri_type << ' ' << mesh.faces.size() << '\n';
    });
    output.write_inside(temp, "mesh.nodes", path, [&](std::ostream& out) {
      for (std::size_t i = 0; i < mesh.points.size(); ++i) {
        out << i + 1 << " -1";
        for (double c : mesh.points[i]) {
          out << ' ';
          put_double(out, c);
        }
        out << '\n';
      }
    });
    output.write_inside(temp, "mesh.elements", path, [&](std::ostream& out) {
      for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
        out << t + 1 << ' ' << bodies.at(regions[t]) << ' ' << tet_type;
        for (Index v : mesh.tets[t]) out << ' ' << v + 1;
        if (quadratic) {
          for (Index m : (*mids.tet)[t]) out << ' ' << m + 1;
        }
        out << '\n';
      }
    });
    output.write_inside(temp, "mesh.boundary", path, [&](std::ostream& out) {
      for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
        const auto& v = mesh.faces[f];
        const auto& p = parents.at(key(v[0], v[1], v[2]));
        out << f + 1 << ' ' << tags.at(labels[f]) << ' ' << p.first << ' ' << p.second << ' ' << tri_type;
        for (Index c : v) out << ' ' << c + 1;
        if (quadratic) {
          for (Index m : mids.face[f]) out << ' ' << m + 1;
        }
        out << '\n';
      }
    });
    output.write_inside(temp, "mesh.names", path, [&](std::ostream& out) {
      out << "! ----- names for bodies -----\n";
      for (const auto& [label, number] : bodies) out << "$ " << group_name("Solid", label) << " = " << number << '\n';
      out << "! ----- names for boundaries -----\n";
      for (const auto& [label, number] : tags) out << "$ " << group_name("Face", label) << " = " << number << '\n';
    });
  }
  output.commit();
}

}  // namespace qualmesh::io
