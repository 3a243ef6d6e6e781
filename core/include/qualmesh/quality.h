// Quality measures of a linear tetrahedron, as used by the refinement engine, the pumping stage and the checker.
// The paper (Cheng & Dey, "Quality Meshing with Weighted Delaunay Refinement", Section 2) measures a tetrahedron
// by its radius-edge ratio rho = R / L (circumradius over shortest edge) and, for slivers, by sigma = V / L^3
// (volume over the cube of the shortest edge). Dihedral angles are what FEM users read, so they are given too.
// All lengths are in model units, volumes in model units cubed, angles in degrees. Pure functions; nothing is
// mutated, nothing printed.
#pragma once

#include <array>

#include "qualmesh/types.h"

namespace qualmesh {

struct TetQuality {
  // The six interior dihedral angles in degrees, at edges (0,1), (0,2), (0,3), (1,2), (1,3), (2,3).
std::array<double, 6> tet_dihedral_angles_deg(const Point3& p0, const Point3& p1, const Point3& p2, const Point3& p3);

// Signed volume (p1-p0) x (p2-p0) . (p3-p0) / 6; positive for a positively oriented tetrahedron.
  double volume = 0;
  // Smallest and largest of the six interior dihedral angles, in degrees, in [0, 180].
  double min_dihedral_deg = 0;
  double max_dihedral_deg = 0;
  // Circumradius / shortest edge (the paper's rho). +infinity for a flat (zero-volume) tetrahedron.
  double radius_edge = 0;
  // |volume| / shortest_edge^3 (the paper's sigma). 0 when the shortest edge is 0.
  double sigma = 0;
  double shortest_edge = 0;
  double longest_edge = 0;
  // Radius of the circumscribed sphere; +infinity for a flat tetrahedron.
  double circumradius = 0;
};

// All measures of the tetrahedron (p0, p1, p2, p3).
TetQuality tet_quality(const Point3& p0, const Point3& p1, const Point3& p2, const Point3& p3);

// Smallest interior dihedral angle in degrees (0 for a flat tetrahedron).
double tet_min_dihedral_deg(const Point3& p0, const Point3& p1, const Point3& p2, const Point3& p3);

// Radius-edge ratio rho = circumradius / shortest edge; +infinity for a flat tetrahedron.
double tet_radius_edge(const Point3& p0, const Point3& p1, const Point3& p2, const Point3& p3);

// The six interior dihedral angles in degrees, at edges (0,1), (0,2), (0,3), (1,2), (1,3), (2,3).
std::array<double, 6> tet_dihedral_angles_deg(const Point3& p0, const Point3& p1, const Point3& p2, const Point3& p3);

// Signed volume (p1-p0) x (p2-p0) . (p3-p0) / 6.
double tet_signed_volume(const Point3& p0, const Point3& p1, const Point3& p2, const Point3& p3);

}  // namespace qualmesh
