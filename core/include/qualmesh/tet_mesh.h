// The output of QualMesh, and what the mesh readers load from foreign meshes (TetGen, Gmsh, Medit, Abaqus, UNV) so
// that the checker can judge them: tetrahedra (linear, or quadratic with one mid-edge node per edge) with a region
// id per tetrahedron, the triangles on input facets (CAD faces) with the facet each one lies on, and the edges on
// marked input segments (CAD edges).
//
// Group names (every writer uses these, FreeCAD's naming of CAD entities; group_name() below):
//   Solid<r>  the tetrahedra of region label r (tet_region_label());
//   Face<m>   the boundary / internal faces with label m (face_labels()), and their nodes;
//   Edge<e>   the nodes of the edges with marker e (edge_marker).
#pragma once

#include <array>
#include <string>
#include <vector>

#include "qualmesh/types.h"

namespace qualmesh {

struct TetMesh {
  // Corner nodes first, then (second order only) the mid-edge nodes.
  std::vector<Point3> points;
  // Weight of each point (the paper's X^2, squared radius in model units squared). Empty = all weights zero.
  // Never holds mid-edge nodes: when non-empty, weights.size() is the number of corner nodes.
  std::vector<double> weights;
  // Tetrahedra. QualMesh writes them positively oriented: (p1-p0) x (p2-p0) . (p3-p0) > 0.
  std::vector<std::array<Index, 4>> tets;
  // Region attribute per tetrahedron (RegionSeed::attribute, or the solid number for CAD). Empty = all 0.
  std::vector<int> tet_region;
  // Triangles on the domain boundary and on internal facets.
  std::vector<std::array<Index, 3>> faces;
  // For each face: the 0-based index of the input facet it lies on; -1 when unknown (foreign meshes).
  std::vector<int> face_facet;
  // For each face: the marker of that facet (boundary marker, CAD face number); empty = none.
  std::vector<int> face_marker;
  // Mesh edges on input segments whose marker is non-zero (CAD edges), each once, in no particular orientation,
  // with that marker (Edge<marker>). Empty when the input has no marked segment.
  std::vector<std::array<Index, 2>> edges;
  std::vector<int> edge_marker;

  // Second order (10-node tetrahedra). Empty for a linear mesh; otherwise one entry per tet / face / edge:
  //   tet_mid[t]:  the mid-edge nodes of tet t's edges (0,1) (1,2) (0,2) (0,3) (1,3) (2,3), the order of VTK's
  //                quadratic tetrahedron and of CalculiX's C3D10 (nodes 5..10);
  //   face_mid[f]: of face f's edges (0,1) (1,2) (2,0);
  //   edge_mid[e]: of edge e.
  // A mid-edge node is shared by every element that has the edge. It lies at the edge's midpoint inside the domain;
  // on a curved CAD face or edge it lies on that face or edge (fit_mesh_to_cad in cad_import.h).
  std::vector<std::array<Index, 6>> tet_mid;
  std::vector<std::array<Index, 3>> face_mid;
  std::vector<Index> edge_mid;

  bool is_second_order() const { return !tet_mid.empty(); }
};

// Tet edge k of the 10-node numbering joins corners kTetEdges[k][0] and kTetEdges[k][1].
inline constexpr int kTetEdges[6][2] = {{0, 1}, {1, 2}, {0, 2}, {0, 3}, {1, 3}, {2, 3}};
// Face edge k joins corners k and (k + 1) % 3.

// Region label of tetrahedron t: its attribute, or 1 for a mesh whose attributes are all 0 (a single unlabelled
// region is Solid1, as FreeCAD names the one solid of a part).
int tet_region_label(const TetMesh& mesh, std::size_t t);
// tet_region_label of every tetrahedron, in one pass (a loop over tet_region_label is quadratic on an unlabelled
// mesh: 162k tets took 18 s to write as .inp, .msh, .unv or .elmer).
std::vector<int> tet_region_labels(const TetMesh& mesh);

// Group label of each face: its facet marker when the mesh carries markers and any is non-zero, else its input
// facet index + 1 (so a marker-less input still gets one group per facet), else 0.
std::vector<int> face_labels(const TetMesh& mesh);

// "Solid3", "Face12", "Edge5"; a negative label n is written "SolidM<-n>" (no minus sign in a set name).
std::string group_name(const char* kind, int label);

}  // namespace qualmesh
