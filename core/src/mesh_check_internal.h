// Private to the mesh checker (mesh_check*.cpp; refine/components.cpp uses FacetGeometry too): the geometry of one input facet as the checker needs it (plane,
// 2D projection, loop nesting, area, point-in-facet test), the reference-volume computation, and the local
// regularity (weighted Delaunay) test, whose exact CGAL predicates stay in mesh_check_regularity.cpp.
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include "qualmesh/plc.h"

namespace qualmesh {
struct CheckReport;
}  // namespace qualmesh

namespace qualmesh::check {

using Point2 = std::array<double, 2>;

// One facet of the reference PLC, projected to 2D by dropping the coordinate axis closest to its normal.
struct FacetGeometry {
  Point3 normal{0, 0, 0};  // unit normal (Newell's method on the loop of largest area)
  double offset = 0;       // normal . x for every x on the plane
  // Largest distance of a loop vertex from that plane: rounding (about 1e-16 D) for a planar facet, up to
  // validate_plc's planarity tolerance for one that is flat only so (a user's polygon, facets merged with
  // --coplanar-tolerance). A mesher's plane for such a facet may lie up to twice that from this one.
  double flatness = 0;
  double perimeter = 0;  // total length of the loops
  int drop_axis = 2;       // the dropped axis; 2D coordinates are (x[(k+1)%3], x[(k+2)%3])
  std::vector<std::vector<Index>> loops;   // polygon loops of >= 3 vertices
  std::vector<std::vector<Point2>> loops_2d;
  std::vector<int> depth;                  // how many other loops enclose each loop
  std::vector<int> winding;                // +1 when the loop turns positively around `normal`, else -1
  std::vector<std::vector<char>> hole_enclosure;  // per facet hole point: which loops enclose it
  double area = 0;                         // filled area: even-odd rule, less the hole-point components
  BoundingBox box;
  bool degenerate = false;                 // no loop with area: cannot hold a face

  Point2 project(const Point3& p) const { return {p[(drop_axis + 1) % 3], p[(drop_axis + 2) % 3]}; }
  // True when the projection of p lies inside the facet's filled region (p assumed on the plane).
  bool contains(const Point3& p) const;
};

FacetGeometry make_facet_geometry(const Plc& plc, const Facet& facet);

// Coordinates relative to the centre of the input's bounding box (mesh_check_frame.cpp): the reference side of the
// checker works in them so that its results do not depend on where the model lies.
struct LocalFrame {
  Point3 origin{0, 0, 0};
  double max_abs_coordinate = 0;  // largest |coordinate| of the box, before shifting
  Point3 local(const Point3& p) const;
  std::vector<Point3> local(const std::vector<Point3>& points) const;
  Plc local(const Plc& plc) const;  // vertices, volume holes, facet holes and region seeds shifted
  // A distance below which two absolute positions cannot be told apart: 2 epsilon * max_abs_coordinate (2 to 4 ulps).
  double position_tolerance() const;
};

// The frame of `plc` (of `mesh_points` when the PLC has no vertex).
LocalFrame make_local_frame(const Plc& plc, const std::vector<Point3>& mesh_points);

struct ReferenceVolume {
  double volume = 0;   // NaN when unsupported
  std::string method;  // "closed-shells (...)" or "cells (...)"
  // Per facet (the "cells" method only; empty: every facet): 1 when a cell of the domain lies on at least one of its
  // sides. A facet with holes or the unbounded cell on both sides (a hole's face seen through a facet hole, as in
  // example.poly) bounds no tetrahedron: nothing is to cover it.
  std::vector<char> facet_bounds_domain;
};

// The volume the input encloses, by one of two methods:
//  - "closed-shells": when every polygon edge is used by exactly two facets and there is no volume hole seed (closed
//    surfaces: OFF, STL, ...). Each shell is oriented consistently by breadth-first search over shared edges, its
//    volume found by the divergence theorem (sum of offset * area / 3), made positive, and signed by its nesting
//    depth among the other shells (winding number of one of its vertices): even depth adds, odd depth (a cavity)
//    subtracts. This is the CAD reading of nested surfaces.
//  - "cells": otherwise (internal facets, multi-region .poly, volume hole seeds, open inputs): TetGen's reading.
//    The domain is every bounded cell of the arrangement of the facets less the cells holding a hole seed; cells
//    are found by sorting the facets around each edge by angle (see compute_cell_volume in the .cpp). An open input
//    encloses 0.
// Limits: facets must meet only along their polygon edges (no T-junctions, no facet ending inside another), and
// facet hole points are assumed not to open a passage between two cells.
ReferenceVolume compute_reference_volume(const Plc& plc, const std::vector<FacetGeometry>& facets);

// One local regularity test: is `vertex` (the fourth vertex of the tetrahedron across one face of `tet`) no closer
// than orthogonal to the orthosphere of `tet`?
struct RegularityTest {
  std::array<Index, 4> tet;  // vertex ids, any orientation
  Index vertex;
};

// Runs the tests with the exact power test (CGAL Epick, power_side_of_oriented_power_sphere_3) on the points and
// weights of `points` / `weights` (weights empty = all zero; else one per point). Returns the positions in `tests`
// of the violations (vertex strictly closer than orthogonal), in order. A flat tetrahedron (orientation zero) is
// never a violation: it has no orthosphere (the checker reports it as non-positive already).
// Preconditions: every id < points.size().
std::vector<std::size_t> find_non_regular(const std::vector<Point3>& points, const std::vector<double>& weights,
                                          const std::vector<RegularityTest>& tests);

// The protection zones of the sharp input angles of `plc` (mesh_check_protection.cpp): protecting balls of radius
// f (the local feature size) at every apex of a segment-segment or segment-facet angle below `angle_deg`, and
// along every segment with a facet-facet angle below it. `points` in the same frame as `plc`.
struct ProtectionZones {
  std::size_t num_sharp_vertices = 0;
  std::size_t num_sharp_segments = 0;
  std::vector<char> point_inside;  // per point: inside some protecting ball
};
ProtectionZones find_protection_zones(const Plc& plc, const std::vector<Point3>& points, double angle_deg);

// The zone counts of CheckReport (num_tets_in_protection_zone, and outside it the smallest dihedral angle and the
// tetrahedra below 10 and 15 degrees), for any zone: a valid tetrahedron with a vertex flagged in `point_inside` is
// inside. Shared by the PLC's protecting balls and the CAD model's feature zones.
void count_protection_zone(CheckReport& report, const std::vector<std::array<Index, 4>>& tets,
                           const std::vector<char>& valid, const std::vector<double>& tet_min_dihedral,
                           const std::vector<char>& point_inside);

}  // namespace qualmesh::check
