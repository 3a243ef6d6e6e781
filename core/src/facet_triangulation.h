// Private helper: the plane of a PLC facet and a triangulation of the facet.
//
// What: a facet (plc.h) is the part of its plane covered by an odd number of its closed polygons, less every part a
// hole point reaches without crossing a loop edge (polygon edges and 2-vertex loops both stop a hole, as in TetGen); 2-vertex loops are segments inside it and 1-vertex loops
// isolated vertices in it. triangulate_facet() turns that into triangles: a constrained Delaunay triangulation
// (CGAL Constrained_Delaunay_triangulation_2, exact predicates) of every loop in the facet's plane, projected along
// the dominant axis of the normal, keeping the triangles of odd coverage that no hole point reaches.
// Why: validate_plc() checks the PLC rule of the paper's Section 2 (two elements meet only in a shared element) and
// measures input angles on these triangles; the refinement engine can start its subfacet triangulations from them.
// The header carries no CGAL type, so it can be included anywhere inside core/src.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "qualmesh/plc.h"
#include "qualmesh/types.h"

namespace qualmesh::detail {

// The plane of a facet: a point on it, its unit normal and the coordinate dropped to project it into 2D (the largest
// component of the normal, so the projection is one-to-one on the plane).
struct FacetFrame {
  Point3 origin{};
  Point3 normal{};    // unit length; the direction follows the first three non-collinear vertices found
  int drop_axis = 2;  // 0, 1 or 2
};

// The frame of a facet from the vertices of all its loops, or nullopt when they are all collinear (decided with
// exact predicates) or there are fewer than three distinct positions. Preconditions: every vertex id of the facet is
// < vertices.size() and every coordinate is finite.
std::optional<FacetFrame> compute_facet_frame(const std::vector<Point3>& vertices, const Facet& facet);

// Signed distance of `p` from the plane of `frame`, in model units.
double signed_distance(const FacetFrame& frame, const Point3& p);

// The triangles of one facet.
struct FacetTriangulation {
  // Points the triangulation had to add where two loops of the facet cross (or a loop runs through a vertex of
  // another loop), lifted onto the facet's plane. Valid facets have none.
  std::vector<Point3> steiner_points;
  // Triangles as vertex ids: an id < num_plc_vertices is a PLC vertex, id num_plc_vertices + k is steiner_points[k].
  // Each triangle is counter-clockwise seen from the side the frame's normal points to.
  std::vector<std::array<Index, 3>> triangles;
  // Per triangle, bit i set when the edge opposite corner i lies on a loop of the facet (a polygon edge or a
  // 2-vertex loop); the other edges are interior diagonals of the facet.
  std::vector<std::uint8_t> constrained_edges;
  Index num_plc_vertices = 0;

  bool is_plc_vertex(Index id) const { return id < num_plc_vertices; }
  const Point3& point(const std::vector<Point3>& vertices, Index id) const {
    return id < num_plc_vertices ? vertices[id] : steiner_points[id - num_plc_vertices];
  }
};

// Triangulates `facet` in the plane of `frame` (from compute_facet_frame; vertices slightly off the plane are
// projected onto it for the 2D work and keep their own 3D position in the result). Does not print or throw for
// geometric reasons; a facet whose loops enclose no area gives no triangle. Same preconditions as
// compute_facet_frame.
FacetTriangulation triangulate_facet(const std::vector<Point3>& vertices, const Facet& facet,
                                     const FacetFrame& frame);

}  // namespace qualmesh::detail
