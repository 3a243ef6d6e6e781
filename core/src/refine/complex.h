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
#include "refine/flat_map.h"

namespace qualmesh::detail {

// The paper's acute input angle (Section 2: Lemmas 3.3 and 3.4 assume none below 90 degrees), less rounding.
inline constexpr double kPaperAcuteDeg = 90.0 - 1e-6;
// Under the relaxed encroachment rule, angles between edges (two segments, or a segment and a facet's corner edge)
// count as acute only below this. Chosen by measurement on ../shared/data (20, 30 and 45 were tried; 30 did best on
// the smooth surfaces and no worse elsewhere); it is also the smallest corner the CAD front end's surface aims at.
inline constexpr double kSteinerCornerAcuteDeg = 30.0;

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
  FlatMap<Index> segment_index;  // key(a, b) with a < b -> segment id
  std::vector<std::vector<Index>> vertex_segments;         // input vertex -> incident segments (sorted)
  std::vector<std::vector<Index>> vertex_facets;           // input vertex -> facets containing it (sorted)
  std::vector<std::vector<SegmentInFacet>> segment_facets; // segment -> facets containing it (sorted by facet)
  std::vector<PlaneFrame> frames;                          // per facet
  std::vector<std::vector<Index>> facet_vertices;          // per facet, sorted input vertex ids
  std::vector<std::uint8_t> acute_vertex;                  // input vertex is the apex of an acute input angle
  std::vector<Index> plane_group;  // per facet: smallest facet id of its exactly coplanar, segment-connected group
  double corner_acute_deg = kPaperAcuteDeg;  // see elements_meet_acute

  static std::uint64_t key(Index a, Index b) {
    if (a > b) std::swap(a, b);
    return (std::uint64_t(a) << 32) | b;
  }
  Index find_segment(Index a, Index b) const {
    const Index* s = segment_index.find(key(a, b));
    return s ? *s : kNoIndex;
  }
  bool facet_has_segment(Index facet, Index segment) const;
  const SegmentInFacet* segment_in_facet(Index segment, Index facet) const;
  // Two elements (segment or facet) share an input vertex whose angle between them is acute.
  bool elements_meet_at_acute_vertex(const std::vector<Index>& vertices_a, const std::vector<Index>& vertices_b) const;

  // THE definition of "two input elements meet at an acute input angle" (issue 3; used by Rule 3's skip and by the
  // output classification, small_angles.cpp). Elements: an input vertex, a segment or a facet. They meet at an
  // acute angle when neither contains the other (an element never meets itself) and they share an input vertex v
  // at which:
  //   segment-segment: the angle between them is below corner_acute_deg;
  //   segment-facet:   the segment's elevation over the facet's plane is below 90 degrees when it projects into the
  //                    facet's corner at v; otherwise its angle to the nearer corner edge is below corner_acute_deg;
  //   facet-facet:     they share a segment through v with a dihedral angle below 90 degrees, or (sharing no
  //                    segment through v) a corner edge of one at v meets the other at an acute segment-facet angle.
  // An input vertex u meets an element E that does not contain it at an acute angle when a segment or facet
  // incident to u does (two input vertices: when an element of each does), so that the short input edges that a
  // small angle forces between input vertices count too.
  // corner_acute_deg, the bound on angles measured between edges (two segments, or a segment and a facet's corner
  // edge), is the paper's 90 degrees, or kSteinerCornerAcuteDeg under the relaxed encroachment rule on a surface or
  // PLC (RefineParams::corner_acute_deg). Dihedral angles and elevations keep 90 always.
  enum class ElementKind : std::uint8_t { Vertex, Segment, Facet };
  struct ElementRef {
    ElementKind kind;
    Index id;
  };
  bool elements_meet_acute(ElementRef a, ElementRef b) const;
  bool element_contains_vertex(ElementRef e, Index v) const;
  // Angle (degrees) between segment s and facet f at their common input vertex v (s not in f).
  // *corner (may be null): whether that is the angle to a corner edge (the segment does not project into the
  // corner) rather than the elevation.
  double segment_facet_angle_deg(Index v, Index segment, Index facet, bool* corner = nullptr) const;
  // Whether that angle is acute in the sense above (corner_acute_deg for a corner edge, 90 for an elevation).
  bool segment_facet_acute(Index v, Index segment, Index facet) const;
  // Does facet f cover the points just beyond `origin` (on f's plane) in the in-plane direction `dir`? Even-odd
  // parity of the crossings of the ray origin + t dir (t > 0) with f's closed-polygon edges, skipping the edges
  // through `origin`: those incident to input vertex `skip` (origin = that vertex), or edge (skip, skip2) (origin =
  // its midpoint). No epsilon: the far end of the ray is outside, so an odd count means the near end is inside,
  // whatever the facet's shape (non-convex, with holes, sliver triangles of a CAD tessellation).
  bool facet_covers_ray(Index facet, const Point3& origin, const Point3& dir, Index skip, Index skip2) const;
  // Directions in facet f's plane, perpendicular to segment s (in f), that point into f next to s: one for a
  // boundary edge of f, two for a segment inside f.
  std::vector<Point3> inward_directions(Index facet, Index segment) const;
  // Dihedral angle below 90 degrees between facets f and g along their common segment s, on some pair of sides.
  bool facets_acute_along(Index segment, Index f, Index g) const;
  mutable FlatMap<std::uint8_t> acute_pair_cache;  // 1: acute
  // Pairs with an input vertex (elements_meet_acute), by the other element's kind: (vertex id << 32 | other id).
  mutable std::array<FlatMap<std::uint8_t>, 3> vertex_pair_cache;
  // An exact fast rejection for the pairs with an input vertex. Two elements that meet at an acute angle do so at a
  // common input vertex y, and then y is an "apex": two of the elements through y meet at an acute angle. So an
  // input vertex u meets an element E at an acute angle only if some vertex of an element through u (u's reach)
  // is an apex and so is some vertex of E. On a smooth tessellated surface under the relaxed rule few vertices are
  // apices, and most pairs are answered here without the (segments x facets)^2 element pairs. Lazy, cached:
  // 0 not known yet, 1 no, 2 yes.
  bool is_apex(Index v) const;             // two elements through v meet at an acute angle
  bool reaches_apex(Index v) const;        // some vertex of an element through v (v included) is an apex
  bool element_has_apex(ElementRef e) const;  // some vertex of e is an apex
  mutable std::vector<std::uint8_t> apex_state, reach_state, facet_apex_state;

  // Ray queries at a facet's own corners and edges in O(log n) instead of a scan of its n edges (issue 18 item 6:
  // an 8000-gon took 39 s; complex_rays.cpp). For polygons that do not cross, the parity that facet_covers_ray counts
  // equals which side of the one edge or corner at the origin the ray leaves by; each closed polygon's interior side
  // is found once by a scan from its longest edge. Where that is not decisive (an edge or corner used twice, a
  // direction within 1e-9 rad of an edge, a polygon whose side the scan cannot tell) the scan answers, as before.
  struct FacetIndex {
    std::vector<std::array<Index, 3>> corners;                       // (vertex, loop, position), sorted
    std::vector<std::pair<std::uint64_t, std::array<Index, 2>>> edges;  // (key(a, b), {loop, position}), sorted
    std::vector<std::int8_t> loop_side;  // +1: interior on the cross(normal, edge) side, -1: the other, 0: unknown
  };
  std::vector<FacetIndex> facet_index;  // per facet (complex_rays.cpp)
  bool scan_rays = false;               // tests: answer every query by the scan, the reference the index must match
  void build_facet_index(Index facet);
  // The side of facet f next to its polygon edge s that f covers: +1 the cross(normal, b - a) side (a < b the
  // segment's vertices), -1 the other, 0 not known from the index.
  int indexed_edge_side(Index facet, Index segment) const;
  // Whether f covers the points just beyond its corner v in the in-plane direction dir: +1 yes, -1 no, 0 not known.
  int indexed_corner_covers(Index facet, Index v, const Point3& dir) const;
  // The corners of f at v, as (vertex, loop, position) entries of facet_index[f].corners.
  std::pair<const std::array<Index, 3>*, const std::array<Index, 3>*> corners_at(Index facet, Index v) const;
  std::vector<Point3> scan_inward_directions(Index facet, Index segment) const;  // by facet_covers_ray
};

// Builds the complex. Throws InputError for a facet whose vertices span no plane.
// scan_rays: answer every ray query by the scan (tests compare it with the index; same results, O(n^2) per facet).
// corner_acute_deg: InputComplex::corner_acute_deg.
InputComplex build_input_complex(const Plc& plc, bool scan_rays = false, double corner_acute_deg = kPaperAcuteDeg);

}  // namespace qualmesh::detail
