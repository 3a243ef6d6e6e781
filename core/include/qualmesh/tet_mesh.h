// The output of QualMesh, and what the mesh readers load from foreign meshes (TetGen, Gmsh, Medit) so that the
// checker can judge them: linear tetrahedra with a region id per tetrahedron and, for boundary and internal faces,
// the input facet each one lies on.
#pragma once

#include <array>
#include <vector>

#include "qualmesh/types.h"

namespace qualmesh {

struct TetMesh {
  std::vector<Point3> points;
  // Weight of each point (the paper's X^2, squared radius in model units squared). Empty = all weights zero.
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
};

}  // namespace qualmesh
