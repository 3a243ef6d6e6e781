// Group labels and names of a TetMesh (tet_mesh.h): the one place that decides what Solid<r>, Face<m> and Edge<e>
// mean, so that every writer and reader names the same groups.
#include <string>

#include "qualmesh/tet_mesh.h"

namespace qualmesh {

int tet_region_label(const TetMesh& mesh, std::size_t t) {
  bool any = false;
  for (int r : mesh.tet_region) {
    if (r != 0) {
      any = true;
      break;
    }
  }
  if (!any) return 1;
  return mesh.tet_region[t];
}

std::vector<int> tet_region_labels(const TetMesh& mesh) {
  bool any = false;
  for (int r : mesh.tet_region) any = any || r != 0;
  std::vector<int> labels(mesh.tets.size(), 1);
  if (any)
    for (std::size_t t = 0; t < labels.size(); ++t) labels[t] = mesh.tet_region[t];
  return labels;
}

std::vector<int> face_labels(const TetMesh& mesh) {
  std::vector<int> labels(mesh.faces.size(), 0);
  bool any_marker = false;
  for (int m : mesh.face_marker) any_marker = any_marker || m != 0;
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    if (any_marker && f < mesh.face_marker.size()) {
      labels[f] = mesh.face_marker[f];
    } else if (!any_marker && f < mesh.face_facet.size() && mesh.face_facet[f] >= 0) {
      labels[f] = mesh.face_facet[f] + 1;
    }
  }
  return labels;
}

std::string group_name(const char* kind, int label) {
  return std::string(kind) + (label < 0 ? "M" + std::to_string(-static_cast<long long>(label)) : std::to_string(label));
}

}  // namespace qualmesh
