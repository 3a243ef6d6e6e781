// Local feature size f(x) of a PLC, exactly as Cheng & Dey define it (Section 2): the radius of the smallest ball
// centred at x that meets two non-adjacent elements of the PLC. Rule 4 and pumping (Sections 3.3, 3.7) scale the
// weights by f(v)^2.
//
// Elements are the PLC's vertices, segments (collect_segments) and facets. In a valid PLC two elements meet only in
// a shared sub-element, and every sub-element contains a vertex, so two elements are adjacent (incident, or with
// intersecting closures) exactly when they share a vertex. f(x) = min over non-adjacent pairs (A, B) of
// max(d(x, A), d(x, B)). We visit elements in increasing distance from x (best-first search in a bounding-volume
// tree over the elements' points, segments and triangles); the first element that is non-adjacent to an element
// visited before it fixes f(x) = its distance (all earlier pairs were adjacent and every later pair is further).
//
// Private header of qualmesh_core (no CGAL types, but not part of the public API either).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "qualmesh/plc.h"

namespace qualmesh {

// The PLC's facets as triangles of PLC vertex ids (a constrained Delaunay triangulation of each facet; a facet that
// spans no plane gets none), as LocalFeatureSize's constructor takes them.
std::vector<std::vector<std::array<Index, 3>>> plc_facet_triangles(const Plc& plc);

class LocalFeatureSize {
 public:
  // `facet_triangles[i]` triangulates facet i of `plc` with PLC vertex ids (any triangulation of the facet's region
  // works; d(x, facet) is the distance to the union of its triangles). The Plc must outlive nothing: data is copied.
  LocalFeatureSize(const Plc& plc, const std::vector<std::vector<std::array<Index, 3>>>& facet_triangles);

  // f(x) in model units; +infinity when the PLC has no two non-adjacent elements.
  double operator()(const Point3& x) const;

  // Reference O(E^2) evaluation straight from the definition (every non-adjacent pair), for tests.
  double brute_force(const Point3& x) const;

  std::size_t num_elements() const { return elements_.size(); }

 private:
  enum class PrimitiveKind : std::uint8_t { Point, Segment, Triangle };
  struct Primitive {
    PrimitiveKind kind;
    std::array<Index, 3> vertices;  // PLC vertex ids (1, 2 or 3 used)
    Index element;                  // owning element
    Point3 centroid{};              // the build's split key, computed once
  };
  struct Element {
    std::vector<Index> vertices;  // sorted vertex ids: adjacency = non-empty intersection
  };
  struct Node {
    Point3 box_min, box_max;
    std::uint32_t first, count;  // leaf: primitives [first, first + count); inner: count == 0
    std::uint32_t left, right;   // inner node children
  };

  double sq_distance(const Primitive& primitive, const Point3& x) const;
  bool adjacent(Index a, Index b) const;
  std::uint32_t build(std::uint32_t first, std::uint32_t count);

  std::vector<Point3> points_;
  std::vector<Element> elements_;
  std::vector<Primitive> primitives_;
  std::vector<Node> nodes_;
};

}  // namespace qualmesh
