// The input PLC as the refinement engine sees it (paper Section 2): its segments (every facet edge included), its
// facets with an orthonormal frame of their plane, and the incidences the engine asks about symbolically:
// which segments and facets contain an input vertex, which facets contain a segment, which elements are adjacent,
// and which input vertices are apices of acute input angles (they get Shewchuk's concentric shells, see
// subsegments.cpp). No CGAL here.
#pragma once

#include <array>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "qualmesh/plc.h"

namespace qualmesh::detail {

// Orthonormal frame of a facet's plane: local coordinates (u, v) = ((p - origin).e1, (p - origin).e2). Axis-aligned
// planes get exact axis vectors, so grid inputs keep exact local coordinates.
struct PlaneFrame {
  Point3 origin{};
  Point3 e1{}, e2{}, normal{};
  std::array<double, 2> to_local(const Point3& p) const;
  Point3 to_global(const std::array<double, 2>& uv) const;
};

// A facet that contains a segment: as a polygon edge (odd coverage toggles the in/out parity across it) or as a
// segment inside the facet (2-vertex loop).
struct SegmentInFacet {
  Index facet = 0;
  bool polygon_edge = false;  // lies on a closed polygon of the facet (a barrier for facet hole points)
  bool toggles = false;       // lies on an odd number of the facet's closed polygons
};

struct InputComplex {
  const Plc* plc = nullptr;
  std::vector<Segment> segments;                           // collect_segments(plc)
  std::unordered_map<std::uint64_t, Index> segment_index;  // key(a, b) with a < b -> segment id
  std::vector<std::vector<Index>> vertex_segments;         // input vertex -> incident segments (sorted)
  std::vector<std::vector<Index>> vertex_facets;           // input vertex -> facets containing it (sorted)
  std::vector<std::vector<SegmentInFacet>> segment_facets; // segment -> facets containing it (sorted by facet)
  std::vector<PlaneFrame> frames;                          // per facet
  std::vector<std::vector<Index>> facet_vertices;          // per facet, sorted input vertex ids
  std::vector<std::uint8_t> acute_vertex;                  // input vertex is the apex of an acute input angle

  static std::uint64_t key(Index a, Index b) {
    if (a > b) std::swap(a, b);
    return (std::uint64_t(a) << 32) | b;
  }
  Index find_segment(Index a, Index b) const {
    auto it = segment_index.find(key(a, b));
    return it == segment_index.end() ? kNoIndex : it->second;
  }
  bool facet_has_segment(Index facet, Index segment) const;
  const SegmentInFacet* segment_in_facet(Index segment, Index facet) const;
  // Two elements (segment or facet) share an input vertex whose angle between them is acute.
  bool elements_meet_at_acute_vertex(const std::vector<Index>& vertices_a, const std::vector<Index>& vertices_b) const;
};

// Builds the complex. Throws InputError for a facet whose vertices span no plane.
InputComplex build_input_complex(const Plc& plc);

}  // namespace qualmesh::detail
