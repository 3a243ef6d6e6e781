// The engine's parameters, derived once from MeshOptions (RefineParams::from, refine_params.cpp) when meshing
// starts, and the encroachment rule of Rules 1-2 as a policy object (EncroachmentPolicy). MeshOptions holds what
// the user gave; every stage reads these derived values instead, so that each bound has one form:
//   - rho0 of Rule 3 (paper Section 3.7) is radius_edge_bound; the squared form for circumradius-to-shortest-edge
//     tests is derived from it (sq_radius_edge_bound), never stored apart;
//   - "sliver" has one predicate (is_sliver): radius-edge ratio at most rho0 and smallest dihedral angle below the
//     sliver angle, the practical form of the paper's sigma = V/L^3 <= sigma0 (Section 3.1). Pumping and sliver
//     insertion work on every in-domain cell below the sliver angle (below_sliver_angle), a superset;
//   - the weight caps of Rule 4 and pumping, omega0^2 f(v)^2 and delta^2 N(v)^2 (Sections 3.3 and 7.3).
#pragma once

#include <algorithm>
#include <cstddef>

#include "qualmesh/mesher.h"
#include "qualmesh/types.h"
#include "refine/complex.h"

namespace qualmesh::detail {

struct MeshState;

// The rounding floor of Rules 1-2, relative to the input's bounding-box diagonal: a present subsegment shorter than
// twice it, or subfacet of circumradius below it, stays when merely encroached (missing ones are still split, so
// conformity is exact). Below it the vertices of one segment no longer lie on one line in doubles: on bottle.brep's
// sized surface without MeshOptions::min_split_length, concentric shells at a 1.66 deg apex reached 1e-9 (1e-11 of
// the diagonal), three chain vertices off one line by rounding made a sliver triangle in the facet's 2D
// triangulation, the next split point landed outside it, and CGAL's 2D flips crashed on the fold (under the paper's
// rule, the folds left no tetrahedron inside the domain). It applies under either encroachment rule.
inline constexpr double kRoundingSplitFloor = 1e-9;

// Which vertices inside the diametral ball of a present subsegment or subfacet make Rules 1 and 2 split it
// (MeshOptions::encroaching). Missing elements are always split, whatever the policy, and so are elements that a
// rejected Rule 2 or Rule 3 centre encroaches.
//   - Paper: every vertex encroaches, Rules 1 and 2 as written (Cheng & Dey, Section 3.7, step 2).
//   - Steiner (beyond the paper): input vertices do not (an obtuse input triangle puts input vertices in the
//     diametral balls of neighbouring input edges all over a tessellated surface), nor does a vertex of a segment
//     for the subsegments of another segment sharing an input vertex with its own (Shewchuk's small-angle rule).
//     Because tolerated encroachers leave elements non-Gabriel, a subfacet centre beyond a subsegment is rejected
//     by a walk in the facet's plane (Rule 2) and a tetrahedron centre's conflict zone is first grown inside its
//     region (Rule 3): walks_to_centres().
class EncroachmentPolicy {
 public:
  EncroachmentPolicy() = default;
  explicit EncroachmentPolicy(MeshOptions::Encroaching rule) : rule_(rule) {}

  // The paper's rule (every vertex encroaches)?
  bool paper() const { return rule_ == MeshOptions::Encroaching::All; }
  // Whether vertex v, strictly inside the diametral ball of a present subsegment of `segment` (kNoIndex: of a
  // subfacet), makes Rule 1 (Rule 2) split it (encroachment.cpp).
  bool counts(const MeshState& s, Index v, Index segment = kNoIndex) const;
  // Steiner mode's extra centre tests (Rule 2: subsegment_towards; Rule 3: conflict_zone_in_region).
  bool walks_to_centres() const { return !paper(); }

 private:
  MeshOptions::Encroaching rule_ = MeshOptions::Encroaching::All;
};

struct RefineParams {
  // rho0 of Rule 3: circumradius / shortest edge bound of tetrahedra inside the domain (dimensionless).
  double radius_edge_bound = 2.0;
  // Size field: squared longest edge allowed (model units squared; 0 = none): the smaller of max_edge_length and
  // kLongestEdgePerTarget * target_edge_length; and the largest volume (0 = none; a region seed may lower it,
  // MeshState::regions).
  double sq_max_edge = 0;
  double max_volume = 0;
  // A tetrahedron below this smallest dihedral angle (degrees) is below the sliver angle.
  double sliver_angle_deg = 15.0;
  // omega0^2 and delta^2 of the weight caps omega0^2 f(v)^2 (Rule 4, pumping) and delta^2 N(v)^2 (pumping).
  double sq_omega = 0.25;
  double sq_delta = 0.2025;
  // Sliver insertion's vertex budget: the pass stops once the vertex count exceeds plain refinement's (before Rule 4)
  // by this fraction (MeshOptions::sliver_insertion_budget; never negative).
  double sliver_insertion_budget = 0.048;
  // The triangulation's vertex count at which every stage stops (MeshStatus::VertexLimitReached).
  std::size_t max_vertices = 50'000'000;
  // Rules 1-2's encroachment rule.
  EncroachmentPolicy encroachment;
  // Below which angle between two edges (two segments, or a segment and a facet's corner edge) the input complex
  // calls elements acute (InputComplex::corner_acute_deg): the paper's 90 degrees, but kSteinerCornerAcuteDeg (30)
  // under the relaxed rule on a surface or PLC. There input vertices do not encroach, nor do segment vertices the
  // subsegments of segments through a common input vertex, so such a corner no longer drives Rules 1-2 to split
  // each other's elements; called acute, it only kept Rule 3 (its skip of the tetrahedra whose shortest edge it
  // forces) from grading the mesh away from the surface: on bunny00.off, where every input vertex is the apex of a
  // triangle corner below 90 degrees, 54603 tetrahedra stayed above rho0, radius-edge ratios up to 12.7, smallest
  // dihedral angle 0.35 degrees (with 30: 15.0 degrees, 3.4 times faster). Dihedral angles and elevations keep 90:
  // with them at 30 too, Rule 3's splits between facets at 45 degrees (t13_data.stl) and 30.1 degrees (cheese.off)
  // did not finish in 400 s. CAD inputs whose boundary points are projected onto the CAD surface
  // (MeshOptions::project_to_boundary) keep 90: bench_cad_gmsh.py with 30 there, all 12 files at 3 sizes, gave the
  // pump carter and Kurbelwelle 13.4-15.0 degrees at every size (90: 5.4-15.0), but t20_data.step at 1.469 fell from
  // 4.3 to 1.8 degrees (11 -> 39 tets below 10), wrenchnut at 20.3 and model1 at 378.9 from 15.0 to 11.0 and 12.7, and
  // node counts grew by up to 36% (pump carter) and 11% (Zylkopf, already 1.7x Gmsh's), taking t20_data at 5.877
  // and wrenchnut at 20.3 past 1.3x Gmsh's nodes (1.30 -> 1.36, 1.18 -> 1.35); of the quality targets against Gmsh
  // only part.step's count below 10 degrees at 10.63 changed sides (20 -> 17, Gmsh 17).
  double corner_acute_deg = kPaperAcuteDeg;
  // MeshOptions::min_split_length, squared (0 = none): the user's floor, applied under the relaxed rule only. The
  // relaxed rule's conflict-zone budget (scheduler.cpp) applies where it is 0.
  double sq_min_split = 0;
  // The floor Rules 1-2 apply, squared: the user's, raised to the rounding floor (set_rounding_floor) when that is
  // larger. 0 = none.
  double sq_split_floor = 0;
  // Raises the floor to kRoundingSplitFloor x `diagonal` (the input's bounding-box diagonal).
  void set_rounding_floor(double diagonal);
  // Whether an encroached, present subsegment of squared length sq_length (subfacet of squared circumradius
  // sq_radius) is below the floor and stays.
  bool subsegment_below_floor(double sq_length) const { return sq_length < 4 * sq_split_floor; }
  bool subfacet_below_floor(double sq_radius) const { return sq_radius < sq_split_floor; }

  // Derives every value from the user's options (the only place that reads them for the engine).
  static RefineParams from(const MeshOptions& options);

  double sq_radius_edge_bound() const { return radius_edge_bound * radius_edge_bound; }
  // Rule 3's quality test in squared form: circumradius^2 > rho0^2 * shortest edge^2.
  bool sq_radius_edge_above_bound(double sq_circumradius, double sq_shortest_edge) const {
    return sq_circumradius > sq_radius_edge_bound() * sq_shortest_edge;
  }
  bool below_sliver_angle(double min_dihedral_deg) const { return min_dihedral_deg < sliver_angle_deg; }
  // The one sliver predicate: smallest dihedral angle below the sliver angle and radius-edge ratio at most rho0.
  bool is_sliver(double min_dihedral_deg, double radius_edge) const {
    return below_sliver_angle(min_dihedral_deg) && radius_edge <= radius_edge_bound;
  }
  // How far a cell is from the sliver angle (degrees, 0 when not below it): pumping's tie-break.
  double sliver_deficit_deg(double min_dihedral_deg) const {
    return std::max(0.0, sliver_angle_deg - min_dihedral_deg);
  }
  // Rule 4's weight omega0^2 f^2 for local feature size f.
  double omega_cap(double f) const { return sq_omega * f * f; }
  // Pumping's cap min(omega0^2 f^2, delta^2 N^2) (f infinite: delta^2 N^2 only); *by_omega (may be null) tells
  // whether omega0^2 f^2 is the smaller.
  double weight_cap(double f, double sq_nearest, bool* by_omega = nullptr) const;
};

}  // namespace qualmesh::detail
