// I-DEAS Universal (.unv) writer, the mesh format FreeCAD imports natively (SMESH's DriverUNV; dataset layouts from
// the SDRL "Universal File Format" storehouse, as SMESH reads them):
//   164  units (SI, factors 1: SMESH scales coordinates by the length factor);
//   2420 coordinate system (the global Cartesian one, identity);
//   2411 nodes: "label 1 1 11" then the coordinates, FORMAT(1P3D25.16) (17 significant digits: exact);
//   2412 elements: "label fe_id 2 1 7 n" then the node labels, 8 per line, FORMAT(8I10); beams (11, 22) have the
//        extra record "0 0 0" (orientation node, fore and aft cross sections) before their nodes;
//   2467 groups: "id 0 0 0 0 0 0 count", the name, then "type tag 0 0" twice per line (type 7 node, 8 element).
// Element ids: tetrahedra 1..T, then faces, then edges (one id space, as SMESH wants).
// Node orders (SMESH's DriverUNV_R_SMDS_Mesh maps UNV to SMESH, whose tetrahedron is NEGATIVELY oriented):
//   111 linear tet   = (c0, c1, c2, c3) of our positive tet; SMESH takes (u0, u2, u1, u3), negative as it wants;
//   118 quad. tet    = (c0, m01, c1, m12, c2, m02, m03, m13, m23, c3): corners and mid-nodes of the base
//                      interleaved, then the three mid-nodes to the apex, then the apex (SMESH: u0 u4 u2 u9, then
//                      u5 u3 u1 u6 u8 u7);
//   91 / 92 triangle = (f0, f1, f2) / (f0, m01, f1, m12, f2, m20) (SMESH: u0 u2 u4 u1 u3 u5);
//   11 / 22 beam     = (e0, e1) / (e0, m, e1).
// These orders were checked by reading FreeCAD 0.20's own UNV export of a hand-built SMESH tet10 (tests/python/
// test_writers_groups.py reads ours with FreeCAD and re-exports it as .inp to check orientation and mid-nodes).
// Groups: Solid<r> (volume elements), Face<m> (face elements), Face<m>_Nodes (their nodes, mid-nodes included),
// Edge<e> (beam elements), Edge<e>_Nodes. Node and element groups are separate records: SMESH would rename a record
// holding both kinds to "<name>_Nodes" and "<name>_Faces".
#include <cstdio>
#include <ostream>

#include "atomic_file.h"
#include "mesh_groups.h"
#include "mesh_io_internal.h"

namespace qualmesh::io {
namespace {

void put_int(std::ostream& out, long long value) {
  char buffer[32];
  const int n = std::snprintf(buffer, sizeof buffer, "%10lld", value);
  out.write(buffer, n);
}

void put_coordinate(std::ostream& out, double value) {
  char buffer[64];
  const int n = std::snprintf(buffer, sizeof buffer, "%25.16E", value);
  out.write(buffer, n);
}

// One 2412 record; `nodes` 0-based.
void put_element(std::ostream& out, std::size_t label, int fe_id, const std::vector<Index>& nodes) {
  put_int(out, static_cast<long long>(label));
  put_int(out, fe_id);
  put_int(out, 2);
  put_int(out, 1);
  put_int(out, 7);
  put_int(out, static_cast<long long>(nodes.size()));
  out << '\n';
  if (fe_id == 11 || fe_id == 22) {
    put_int(out, 0);
    put_int(out, 0);
    put_int(out, 0);
    out << '\n';
  }
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    put_int(out, static_cast<long long>(nodes[i]) + 1);
    if (i % 8 == 7 || i + 1 == nodes.size()) out << '\n';
  }
}

// One 2467 group record of `type` (7 nodes, 8 elements) with 1-based `tags`.
void put_group(std::ostream& out, int id, const std::string& name, int type, const std::vector<std::size_t>& tags) {
  put_int(out, id);
  for (int i = 0; i < 6; ++i) put_int(out, 0);
  put_int(out, static_cast<long long>(tags.size()));
  out << '\n' << name << '\n';
  for (std::size_t i = 0; i < tags.size(); ++i) {
    put_int(out, type);
    put_int(out, static_cast<long long>(tags[i]));
    put_int(out, 0);
    put_int(out, 0);
    if (i % 2 == 1 || i + 1 == tags.size()) out << '\n';
  }
}

}  // namespace

void write_unv(const TetMesh& mesh, const std::string& path) {
  const MidNodes mids = mid_nodes(mesh);
  const MeshGroups groups = mesh_groups(mesh, mids);
  const bool quadratic = mids.tet != nullptr;
  const std::size_t first_face = mesh.tets.size() + 1, first_edge = first_face + mesh.faces.size();

  write_file_atomically(path, [&](std::ostream& out) {
    out << "    -1\n   164\n         1  SI: Meter (newton)         2\n"
           "    1.0000000000000000E+0    1.0000000000000000E+0    1.0000000000000000E+0\n"
           "    2.7314999999999998E+2\n    -1\n";
    out << "    -1\n  2420\n         1\nQualMesh\n         1         0         0\n"
           "Global Cartesian Coordinate System\n"
           "    1.0000000000000000E+0    0.0000000000000000E+0    0.0000000000000000E+0\n"
           "    0.0000000000000000E+0    1.0000000000000000E+0    0.0000000000000000E+0\n"
           "    0.0000000000000000E+0    0.0000000000000000E+0    1.0000000000000000E+0\n"
           "    0.0000000000000000E+0    0.0000000000000000E+0    0.0000000000000000E+0\n    -1\n";
    out << "    -1\n  2411\n";
    for (std::size_t i = 0; i < mesh.points.size(); ++i) {
      put_int(out, static_cast<long long>(i) + 1);
      put_int(out, 1);
      put_int(out, 1);
      put_int(out, 11);
      out << '\n';
      for (double c : mesh.points[i]) put_coordinate(out, c);
      out << '\n';
    }
    out << "    -1\n    -1\n  2412\n";
    std::vector<Index> nodes;
    for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
      const auto& c = mesh.tets[t];
      if (quadratic) {
        const auto& m = (*mids.tet)[t];
        nodes = {c[0], m[0], c[1], m[1], c[2], m[2], m[3], m[4], m[5], c[3]};
        put_element(out, t + 1, 118, nodes);
      } else {
        nodes.assign(c.begin(), c.end());
        put_element(out, t + 1, 111, nodes);
      }
    }
    for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
      const auto& c = mesh.faces[f];
      if (quadratic) {
        const auto& m = mids.face[f];
        nodes = {c[0], m[0], c[1], m[1], c[2], m[2]};
        put_element(out, first_face + f, 92, nodes);
      } else {
        nodes.assign(c.begin(), c.end());
        put_element(out, first_face + f, 91, nodes);
      }
    }
    for (std::size_t e = 0; e < mesh.edges.size(); ++e) {
      const auto& c = mesh.edges[e];
      if (quadratic) {
        nodes = {c[0], mids.edge[e], c[1]};
        put_element(out, first_edge + e, 22, nodes);
      } else {
        nodes.assign(c.begin(), c.end());
        put_element(out, first_edge + e, 11, nodes);
      }
    }
    out << "    -1\n";
    if (groups.solids.empty() && groups.faces.empty() && groups.edges.empty()) return;
    out << "    -1\n  2467\n";
    int id = 0;
    std::vector<std::size_t> tags;
    for (const auto& [label, members] : groups.solids) {
      tags.clear();
      for (std::size_t t : members) tags.push_back(t + 1);
      put_group(out, ++id, group_name("Solid", label), 8, tags);
    }
    for (const auto& [label, members] : groups.faces) {
      tags.clear();
      for (std::size_t f : members) tags.push_back(first_face + f);
      put_group(out, ++id, group_name("Face", label), 8, tags);
      tags.clear();
      for (Index v : groups.face_nodes.at(label)) tags.push_back(static_cast<std::size_t>(v) + 1);
      put_group(out, ++id, group_name("Face", label) + "_Nodes", 7, tags);
    }
    for (const auto& [marker, members] : groups.edges) {
      tags.clear();
      for (std::size_t e : members) tags.push_back(first_edge + e);
      put_group(out, ++id, group_name("Edge", marker), 8, tags);
      tags.clear();
      for (Index v : groups.edge_nodes.at(marker)) tags.push_back(static_cast<std::size_t>(v) + 1);
      put_group(out, ++id, group_name("Edge", marker) + "_Nodes", 7, tags);
    }
    out << "    -1\n";
  });
}

}  // namespace qualmesh::io
