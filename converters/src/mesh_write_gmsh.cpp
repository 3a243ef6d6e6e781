// Gmsh .msh 4.1 ASCII writer (gmsh reference manual, "MSH file format"). One volume entity and one volume physical
// group "Region<attr>" per region attribute, one surface entity and one surface physical group "Face<m>" per facet
// label (face_labels()). The physical tag is the attribute / label itself when positive, else a fresh tag above
// all of them (Gmsh wants positive tags). All nodes sit in one block on the first volume entity, which Gmsh and
// meshio accept. Element tags: tetrahedron t is t+1, face f is num_tets+f+1, so a reader can restore the order.
#include <algorithm>
#include <map>
#include <ostream>

#include "atomic_file.h"
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
  std::vector<int> regions(mesh.tets.size());
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) regions[t] = tet_region_of(mesh, t);
  if (regions.empty()) regions.push_back(0);  // one (empty) volume to hold the nodes
  const std::vector<int> labels = face_labels(mesh);
  const std::map<int, int> volume_tags = physical_tags(regions);
  const std::map<int, int> surface_tags = physical_tags(labels);
  BoundingBox box;
  for (const Point3& p : mesh.points) box.add(p);
  if (box.empty()) box.min = box.max = Point3{0, 0, 0};

  write_file_atomically(path, [&](std::ostream& out) {
    out << "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n";
    out << "$PhysicalNames\n" << volume_tags.size() + surface_tags.size() << '\n';
    for (const auto& [label, tag] : surface_tags) out << "2 " << tag << " \"Face" << label << "\"\n";
    for (const auto& [region, tag] : volume_tags) out << "3 " << tag << " \"Region" << region << "\"\n";
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
    // Entity tags are 1, 2, ... in the order of the maps.
    out << "$Entities\n0 0 " << surface_tags.size() << ' ' << volume_tags.size() << '\n';
    int entity = 0;
    for (const auto& [label, tag] : surface_tags) {
      out << ++entity << ' ';
      put_box();
      out << "1 " << tag << " 0\n";
    }
    entity = 0;
    for (const auto& [region, tag] : volume_tags) {
      out << ++entity << ' ';
      put_box();
      out << "1 " << tag << " 0\n";
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

    // Element blocks: one per surface entity, one per volume entity.
    std::map<int, std::vector<std::size_t>> faces_by_label, tets_by_region;
    for (std::size_t f = 0; f < mesh.faces.size(); ++f) faces_by_label[labels[f]].push_back(f);
    for (std::size_t t = 0; t < mesh.tets.size(); ++t) tets_by_region[tet_region_of(mesh, t)].push_back(t);
    const std::size_t num_elements = mesh.tets.size() + mesh.faces.size();
    out << "$Elements\n"
        << surface_tags.size() + volume_tags.size() << ' ' << num_elements << ' ' << (num_elements ? 1 : 0) << ' '
        << num_elements << '\n';
    entity = 0;
    for (const auto& [label, tag] : surface_tags) {
      const auto& members = faces_by_label[label];
      out << "2 " << ++entity << " 2 " << members.size() << '\n';
      for (std::size_t f : members) {
        const auto& v = mesh.faces[f];
        out << mesh.tets.size() + f + 1 << ' ' << v[0] + 1 << ' ' << v[1] + 1 << ' ' << v[2] + 1 << '\n';
      }
    }
    entity = 0;
    for (const auto& [region, tag] : volume_tags) {
      const auto& members = tets_by_region[region];
      out << "3 " << ++entity << " 4 " << members.size() << '\n';
      for (std::size_t t : members) {
        const auto& v = mesh.tets[t];
        out << t + 1 << ' ' << v[0] + 1 << ' ' << v[1] + 1 << ' ' << v[2] + 1 << ' ' << v[3] + 1 << '\n';
      }
    }
    out << "$EndElements\n";
  });
}

}  // namespace qualmesh::io
