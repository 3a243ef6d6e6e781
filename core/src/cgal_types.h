// The one place where QualMesh chooses its CGAL kernel and triangulation types (DESIGN.md, "Key decisions").
//
// - Kernel: Epick, exact predicates (orientation, in-sphere, power tests) on double coordinates, inexact
//   constructions (circumcentres, midpoints). Robustness comes from the predicates; Steiner points are never
//   classified by a computed distance (refine/complex.h keeps their host element symbolically).
// - 3D: one Regular_triangulation_3 with all weights zero during refinement (paper Section 3.7, step 2), so that
//   pumping (step 3) can change weights in place. Hidden points are discarded (no per-cell lists). Each vertex
//   carries its QualMesh vertex id, each cell its region (component) id.
// - 2D: a Constrained_Delaunay_triangulation_2 per input facet, in an orthonormal frame of the facet's plane; the
//   subfacets of paper Section 3.2 are its in-domain triangles.
// - Determinism: every vertex, cell and face carries CGAL's time stamp (WithTimeStamp below), so that CGAL orders
//   and hashes handles by creation order, not by address. Without it CGAL compares addresses: e.g.
//   Triangulation_3::find_conflicts reports an internal facet from the cell of lower address (`c < test`), which
//   set the order of Rule 3's subfacet queue; addresses depend on what the process allocated before, so meshing
//   the same input twice in one process gave two meshes (house style, principle 7: same input, same mesh).
// Private header: never include it from core/include.
#pragma once

#include <cstddef>
#include <functional>

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Has_timestamp.h>
#include <CGAL/Regular_triangulation_3.h>
#include <CGAL/Regular_triangulation_cell_base_3.h>
#include <CGAL/Regular_triangulation_vertex_base_3.h>
#include <CGAL/Triangulation_cell_base_with_info_3.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_3.h>

#include "qualmesh/types.h"

namespace qualmesh::detail {

// Adds CGAL's time stamp (the Has_timestamp protocol of CGAL/Time_stamper.h, as Mesh_3's vertex and cell bases
// do) to a vertex, cell or face base. The triangulation's Compact_container stamps each element from its own
// counter when the element is created, so handle comparison (operator<) and std::hash follow the creation order
// within that triangulation, which only the input and options decide.
template <class Base>
class WithTimeStamp : public Base {
 public:
  using Base::Base;
  template <class Tds>
  struct Rebind_TDS {
    using Other = WithTimeStamp<typename Base::template Rebind_TDS<Tds>::Other>;
  };
  using Has_timestamp = CGAL::Tag_true;
  std::size_t time_stamp() const { return time_stamp_; }
  void set_time_stamp(const std::size_t& stamp) { time_stamp_ = stamp; }

 private:
  std::size_t time_stamp_ = std::size_t(-1);  // -1: not stamped yet (Time_stamper assigns the next one)
};

using Kernel = CGAL::Epick;
using KPoint3 = Kernel::Point_3;
using KWeightedPoint3 = Kernel::Weighted_point_3;
using KPoint2 = Kernel::Point_2;

// Region of a cell: >= 0 a component of the domain, kOutsideRegion outside the domain (or in a hole), and
// kUnknownRegion for a cell created since the regions were last flooded.
constexpr int kOutsideRegion = -1;
constexpr int kUnknownRegion = -2;

struct CellInfo {
  int region = kUnknownRegion;
  // For a cell of unknown region: the region of the destroyed cell it replaced across its outer face, used when no
  // known neighbour reaches its component (refine/regions.cpp).
  int guess = kUnknownRegion;
  // The cell's smallest dihedral angle in degrees, once measured (negative: not yet; refine_state.h
  // cell_min_dihedral_deg). A cell's vertices never move (a weight change replaces the cells around the vertex), so
  // it stays valid as long as the cell exists.
  double min_dihedral_deg = -1;
  // Its radius-edge ratio, once measured (negative: not yet; refine_state.h cell_radius_edge), valid as long.
  double radius_edge = -1;
};

using Vb3 = WithTimeStamp<
    CGAL::Triangulation_vertex_base_with_info_3<Index, Kernel, CGAL::Regular_triangulation_vertex_base_3<Kernel>>>;
using Cb3Base = CGAL::Regular_triangulation_cell_base_3<Kernel, CGAL::Triangulation_cell_base_3<Kernel>,
                                                        CGAL::Discard_hidden_points>;
using Cb3 = WithTimeStamp<CGAL::Triangulation_cell_base_with_info_3<CellInfo, Kernel, Cb3Base>>;
using Tds3 = CGAL::Triangulation_data_structure_3<Vb3, Cb3, CGAL::Sequential_tag>;
using RegularTriangulation3 = CGAL::Regular_triangulation_3<Kernel, Tds3>;
using Vh3 = RegularTriangulation3::Vertex_handle;
using Ch3 = RegularTriangulation3::Cell_handle;
using Facet3 = RegularTriangulation3::Facet;

// Hash of a cell handle by address, for unordered sets of cells (conflict zones, stars).
struct CellHash {
  std::size_t operator()(const Ch3& c) const { return std::hash<const void*>()(&*c); }
};

// In/out of a facet triangle (plc.h rule): covered by an odd number of the facet's polygons (parity), and not
// reached from a facet hole point without crossing a polygon edge (hole).
struct FaceInfo2 {
  bool parity = false;
  bool hole = false;
  bool in_domain() const { return parity && !hole; }
};

using Vb2 = WithTimeStamp<CGAL::Triangulation_vertex_base_with_info_2<Index, Kernel>>;
using Fb2 = WithTimeStamp<
    CGAL::Constrained_triangulation_face_base_2<Kernel, CGAL::Triangulation_face_base_with_info_2<FaceInfo2, Kernel>>>;
using Tds2 = CGAL::Triangulation_data_structure_2<Vb2, Fb2>;
using Cdt2 = CGAL::Constrained_Delaunay_triangulation_2<Kernel, Tds2, CGAL::No_constraint_intersection_requiring_constructions_tag>;
using Vh2 = Cdt2::Vertex_handle;
using Fh2 = Cdt2::Face_handle;

inline KPoint3 to_kpoint(const Point3& p) { return KPoint3(p[0], p[1], p[2]); }
inline Point3 to_point3(const KPoint3& p) { return {p.x(), p.y(), p.z()}; }

}  // namespace qualmesh::detail
