// Gmsh .msh 4.1 ASCII writer (gmsh reference manual, "MSH file format"). One volume entity and one volume physical
// group "Solid<r>" per region label (tet_region_label), one surface entity and physical "Face<m>" per face label
// (face_labels()), one curve entity and physical "Edge<e>" per edge marker, the edges written as line elements. The
// physical tag is the label itself when positive, else a fresh tag above all of them (Gmsh wants positive tags).
// All nodes sit in one block on the first volume entity, which Gmsh and meshio accept. Element tags: tetrahedron t
// is t+1, face f is num_tets+f+1, edge e follows the faces, so a reader can restore the order.
// Element types and node orders (manual, "Node ordering"): linear 4 (tet), 2 (triangle), 1 (line); second order
// 11 (tet10: corners, then edges (0,1) (1,2) (2,0) (3,0) (3,2) (3,1): nodes 8 and 9 are edges (2,3) and (1,3),
// swapped against VTK / TetMesh::tet_mid, as meshio's gmsh permutation [0..7, 9, 8] says), 9 (triangle6: edges
// (0,1) (1,2) (2,0)), 8 (line3: ends, then the mid-node).
#include <algorithm>
#include <map>
#include <ostream>

#include "atomic_file.h"
#include "mesh_groups.h"
#include "mesh_io_internal.h"

namespace qualmesh::io {
namespace {

// Distinct values, sorted, each with its positive physical tag.
std::map<int, int> physical_tags(const std::vector<int>& values) {
  std::map<int, int> tags;
  int max_tag = 0;
  for (int v : values) {
    tags.emplace(v, 0);
    max_tag = std::max(max_tag, v);
  }
  for (auto& [value, tag] : tags) tag = value > 0 ? value : ++max_tag;
  return tags;
}

}  // namespace

void write_gmsh41(const TetMesh& mesh, const std::string& path) {
  const MidNodes mids = mid_nodes(mesh);
  const MeshGroups groups = mesh_groups(mesh, mids);
  const bool quadratic = mids.tet != nullptr;
  std::vector<int> regions, labels, markers;
  for (const auto& [r, members] : groups.solids) regions.push_back(r);
  if (regions.empty()) regions.push_back(1);  // one (empty) volume to hold the nodes
  for (const auto& [m, members] : groups.faces) labels.push_back(m);
  for (const auto& [e, members] : groups.edges) markers.push_back(e);
  const std::map<int, int> volume_tags = physical_tags(regions);
  const std::map<int, int> surface_tags = physical_tags(labels);
  const std::map<int, int> curve_tags = physical_tags(markers);
  BoundingBox box;
  for (const Point3& p : mesh.points) box.add(p);
  if (box.empty()) box.min = box.max = Point3{0, 0, 0};

  write_file_atomically(path, [&](std::ostream& out) {
    out << "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n";
    out << "$PhysicalNames\n" << volume_tags.size() + surface_tags.size() + curve_tags.size() << '\n';
    for (const auto& [marker, tag] : curve_tags) out << "1 " << tag << " \"" << group_name("Edge", marker) << "\"\n";
    for (const auto& [label, tag] : surface_tags) out << "2 " << tag << " \"" << group_name("Face", label) << "\"\n";
    for (const auto& [region, tag] : volume_tags) out << "3 " << tag << " \"" << group_name("Solid", region) << "\"\n";
    out << "$EndPhysicalNames\n";

    const auto put_box = [&out, &box]() {
      for (int i = 0; i < 3; ++i) {
        put_double(out, box.min[i]);
        out << ' ';
      }
      for (int i = 0; i < 3; ++i) {
        put_double(out, box.max[i]);
        out << ' ';
      }
    };
    // Entity tags are 1, 2, ... in the order of the maps, per dimension.
    out << "$Entities\n0 " << curve_tags.size() << ' ' << surface_tags.size() << ' ' << volume_tags.size() << '\n';
    for (const auto* tags : {&curve_tags, &surface_tags, &volume_tags}) {
      int entity = 0;
      for (const auto& [value, tag] : *tags) {
        out << ++entity << ' ';
        put_box();
        out << "1 " << tag << " 0\n";
      }
    }
    out << "$EndEntities\n";

    const std::size_t num_points = mesh.points.size();
    out << "$Nodes\n1 " << num_points << ' ' << (num_points ? 1 : 0) << ' ' << num_points << '\n';
    out << "3 1 0 " << num_points << '\n';
    for (std::size_t i = 0; i < num_points; ++i) out << i + 1 << '\n';
    for (const Point3& p : mesh.points) {
      put_double(out, p[0]);
      out << ' ';
      put_double(out, p[1]);
      out << ' ';
      put_double(out, p[2]);
      out << '\n';
    }
    out << "$EndNodes\n";

    // Element blocks: one per curve, surface and volume entity.
    const std::size_t first_face = mesh.tets.size() + 1, first_edge = first_face + mesh.faces.size();
    const std::size_t num_elements = mesh.tets.size() + mesh.faces.size() + mesh.edges.size();
    out << "$Elements\n"
        << curve_tags.size() + surface_tags.size() + volume_tags.size() << ' ' << num_elements << ' '
        << (num_elements ? 1 : 0) << ' ' << num_elements << '\n';
    int entity = 0;
    for (const auto& [marker, tag] : curve_tags) {
      const auto& members = groups.edges.at(marker);
      out << "1 " << ++entity << (quadratic ? " 8 " : " 1 ") << members.size() << '\n';
      for (std::size_t e : members) {
        const auto& v = mesh.edges[e];
        out << first_edge + e << ' ' << v[0] + 1 << ' ' << v[1] + 1;
        if (quadratic) out << ' ' << mids.edge[e] + 1;
        out << '\n';
      }
    }
    entity = 0;
    for (const auto& [label, tag] : surface_tags) {
      const auto& members = groups.faces.at(label);
      out << "2 " << ++entity << (quadratic ? " 9 " : " 2 ") << members.size() << '\n';
      for (std::size_t f : members) {
        const auto& v = mesh.faces[f];
        out << first_face + f << ' ' << v[0] + 1 << ' ' << v[1] + 1 << ' ' << v[2] + 1;
        if (quadratic) {
          for (Index m : mids.face[f]) out << ' ' << m + 1;
        }
        out << '\n';
      }
    }
    entity = 0;
    static const std::vector<std::size_t> kNone;
    for (const auto& [region, tag] : volume_tags) {
      const auto it = groups.solids.find(region);
      const auto& members = it == groups.solids.end() ? kNone : it->second;
      out << "3 " << ++entity << (quadratic ? " 11 " : " 4 ") << members.size() << '\n';
      for (std::size_t t : members) {
        const auto& v = mesh.tets[t];
        out << t + 1 << ' ' << v[0] + 1 << ' ' << v[1] + 1 << ' ' << v[2] + 1 << ' ' << v[3] + 1;
        if (quadratic) {
          const auto& m = (*mids.tet)[t];
          for (int k : {0, 1, 2, 3, 5, 4}) out << ' ' << m[k] + 1;  // Gmsh: (2,3) before (1,3)
        }
        out << '\n';
      }
    }
    out << "$EndElements\n";
  });
}

}  // namespace qualmesh::io
