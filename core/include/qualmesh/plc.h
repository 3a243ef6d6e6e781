// The piecewise linear complex (PLC) that QualMesh meshes (paper Section 2): vertices, segments, planar polygonal
// facets with holes, region seeds and hole seeds. A plain value type; readers build it, validate_plc() judges it,
// the mesher consumes it.
#pragma once

#include <string>
#include <vector>

#include "qualmesh/types.h"

namespace qualmesh {

// An input segment between two vertices. Every edge of every facet polygon is a segment too; `segments` holds only
// those given explicitly (TetGen .poly edge list, CAD edges), see collect_segments().
struct Segment {
  Index a = 0;
  Index b = 0;
  int marker = 0;  // boundary marker or CAD edge number (1-based, FreeCAD's EdgeN); 0 = none
};

// A planar facet. It is the region of its plane covered by an odd number of its closed polygons, less every part
// that a hole point reaches without crossing a polygon edge (TetGen's convention). So an outer loop with an inner
// loop is an annulus even without a hole point.
struct Facet {
  // Vertex loops. A loop of >= 3 vertices is a closed polygon (last vertex connects back to the first); a loop of
  // 2 vertices is a segment lying in the facet; a loop of 1 vertex is an isolated vertex in the facet.
  std::vector<std::vector<Index>> polygons;
  std::vector<Point3> holes;  // points in the facet's plane marking holes of the facet
  int marker = 0;             // boundary marker or CAD face number (1-based, FreeCAD's FaceN); 0 = none
};

// A region seed (TetGen .poly region list): the tetrahedra of the region containing `point` get `attribute`.
struct RegionSeed {
  Point3 point{};
  int attribute = 0;
  double max_volume = 0;  // maximum tetrahedron volume in this region, in model units cubed; <= 0: no limit
};

struct Plc {
  std::vector<Point3> vertices;
  std::vector<Segment> segments;    // explicit segments (facet polygon edges are implied, see collect_segments)
  std::vector<Facet> facets;
  std::vector<Point3> holes;        // volume hole seeds: the region containing each point is not meshed
  std::vector<RegionSeed> regions;  // region seeds
  std::string name;                 // where it came from (file name), for messages
};

BoundingBox bounding_box(const Plc& plc);

// Every segment of the PLC: the explicit segments plus every edge of every facet polygon (loops of >= 2 vertices),
// with a < b, sorted by (a, b), without duplicates. A marker of an explicit segment wins over 0.
std::vector<Segment> collect_segments(const Plc& plc);

// Number of triangles a facet would need at least (sum over polygons of (n - 2)); used for summaries.
std::size_t count_polygon_vertices(const Facet& facet);

}  // namespace qualmesh
