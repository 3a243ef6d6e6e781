// The QualMesh mesher, steps 1-3 of QUALMESH (Cheng & Dey, "Quality Meshing with Weighted Delaunay
// Refinement", Section 3.7): the Delaunay triangulation of the input vertices, then Delaunay refinement by Rule 1
// (encroached subsegments), Rule 2 (encroached subfacets) and Rule 3 (tetrahedra of radius-edge ratio above rho0),
// plus a size field (maximum edge length and volume). The result conforms to the input: every input segment and
// facet is a union of mesh edges and faces (Theorem 7.2). Then Rule 4 (weighted encroachment) and step 3, pumping:
// vertices of slivers get weights that remove slivers without adding points (Theorem 7.3); the mesh is weighted
// Delaunay (regular) with TetMesh::weights, and plain Delaunay with MeshOptions::pump = false.
//
// mesh_plc() mutates nothing but its result; it never prints and never exits: progress and log lines go through the
// callbacks. Bad input (a PLC whose vertices span no volume, constraints that cross) throws InputError.
#pragma once

#include <cstddef>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>
#include <cstdint>

#include "qualmesh/plc.h"
#include "qualmesh/tet_mesh.h"

namespace qualmesh {

// What the user asked for. Derived values (squared bounds, acute-vertex flags) live in the engine's state.
// The radius-edge bound of the tetrahedra the improvement pass changes (MeshOptions::improve), relative to rho0.
// Measured on fandisk.off: 1.0 leaves min dihedral 5.4 deg, 1.5 reaches 15.0 deg; unbounded, joint.off's changed
// tets reached radius-edge 85 away from acute input angles. 2.0 (was 1.5): a sliver often has a small radius-edge
// ratio itself (a flat tet of four nearly cocircular points: wrenchnut.stp at --size 20.3, a 0.62 deg cap between
// two CAD faces meeting at 178.8 deg, ratio 3.54), so a 3-2 flip that removes it makes tets a hair above 1.5 rho0
// (3.61) and was refused; with 2.0 it is made (min 0.62 -> 12.1 deg). Over the 36 CAD runs of the bench's sizes,
// tets below 10 deg 1803 -> 1626 and below 15 deg 3032 -> 2581; on 11 surfaces of ../shared/data/plc the count of
// tets below 10 deg fell on 9 (couplingdown 1099 -> 631, pinion 7001 -> 5700) and stayed 0 on 2, at up to 15% more
// vertices (pinion's interior edge splits), more tets above rho0 (pinion 21641 -> 27861) and one lower minimum
// (joint.off 1.31 -> 1.24 deg). 3.0 (was 2.0): the guard, not the angles, stopped the pass at the last slivers
// (wrenchnut.stp at --size 20.3 on an experimental Delaunay-flipped surface: a 4.6-4.8 deg tet left at 2.0, none
// below 15 deg at 3.0).
// Over the 42 runs of every file of ../shared/data/cad (but U_Joint_2) at diag/10, /20 and /40: tets below 10 deg
// 252 -> 175, below 15 deg 580 -> 437, the minimum higher in 19 runs and lower in 5 (Zylkopf.stp at diag/40
// 6.42 -> 4.52 deg), nodes +0.1%. On fandisk, joint, elephant, pinion, couplingdown and anchor: below 10 deg
// 0/55/0/5700/631/1019 -> 0/28/0/3785/342/709, joint's minimum 1.24 -> 2.81 deg, at up to 30% more vertices
// (pinion 16477 -> 21381: interior edge splits) and anchor's minimum 0.039 -> 0.038 deg.
inline constexpr double kImproveRadiusEdgeFactor = 3.0;
// The longest edge Rule 3 allows, relative to MeshOptions::target_edge_length.
inline constexpr double kLongestEdgePerTarget = 2.0;

struct MeshOptions {
  // rho0 of Rule 3: circumradius / shortest edge bound for tetrahedra inside the domain. Values below about 1.1
  // may not terminate (the theory needs rho0 > 2; 1.5 works in practice on non-acute inputs).
  double radius_edge_bound = 2.0;
  // Longest edge allowed in a tetrahedron inside the domain, in model units. 0 = no limit.
  double max_edge_length = 0;
  // Target edge length h, in model units (Gmsh's CharacteristicLengthMax; the CLI's --size, whose default for CAD
  // inputs is a tenth of the bounding-box diagonal). 0 = none. Rule 3 splits a tetrahedron inside the domain whose
  // longest edge exceeds kLongestEdgePerTarget * h: Delaunay refinement under that bound gives about Gmsh's node
  // count at CharacteristicLengthMax = h, whose tetrahedra have edges of 1.25 h on average and up to 2.1 h
  // (measured on tests/data/cad/cylinder.brep at h = 2.06). max_edge_length, when set, is a hard bound besides.
  double target_edge_length = 0;
  // Floor of the encroachment splits under Encroaching::Steiner, in model units (Gmsh's MeshSizeMin in spirit; the
  // CLI gives CAD inputs half their smallest size, --min-size or a 30th of --size). 0 = none, and ignored under the
  // paper's rule (Encroaching::All, the fallback included), which stays as written. Rules 1 and 2 do
  // not split a subsegment shorter than twice this, nor a subfacet whose circumradius is below it, when it is merely
  // encroached (or named by a rejected centre): near input angles of a few hundredths of a degree (U_Joint_2.stp's
  // surface has them) encroachment splitting otherwise runs down towards rounding (1.8e-13 edges in its paper's-rule
  // mesh, an element ccx refused); on wrenchnut.stp at its default size it saves a quarter of the nodes. A missing
  // subsegment or subfacet is split whatever its size, so conformity is kept; the tetrahedra around a floored one
  // may stay above the radius-edge bound (they touch an acute input angle). Whatever this says, and under either
  // rule, the engine keeps a rounding floor of 1e-9 of the input's bounding-box diagonal (refine_params.h
  // kRoundingSplitFloor): below it a segment's vertices no longer lie on one line in doubles, and a facet's 2D
  // triangulation folded (bottle.brep's sized surface without a floor crashed in CGAL's flips).
  double min_split_length = 0;
  // Largest volume allowed for a tetrahedron inside the domain, in model units cubed. 0 = no limit. Region seeds
  // (RegionSeed::max_volume) may lower it per region.
  double max_volume = 0;
  // Safety stop: refinement ends (MeshStatus::VertexLimitReached) when the triangulation holds this many vertices.
  std::size_t max_vertices = 50'000'000;
  // Which vertices make Rules 1 and 2 split a subsegment or subfacet that is present in the triangulation
  // (missing ones are always split, and so are those a rejected Rule 2 or 3 centre encroaches).
  enum class Encroaching {
    // Every vertex: the paper's Rules 1 and 2 as written (the reference that follows the paper's proofs; `qualmesh
    // mesh --encroaching all`).
    All,
    // Steiner vertices only (beyond the paper; the default since issue 16's decision, in the CLI too): an input
    // vertex inside the diametral ball of an input edge or face of the same tessellation (an obtuse input triangle) is
    // left there while the element is present, and so is a segment vertex in the diametral ball of a subsegment of a
    // segment sharing an input vertex with its own (the acute corners of every input triangle). On a surface or PLC
    // (not with project_to_boundary), an angle between two edges (two segments, or a segment and a facet's corner edge)
    // then counts as an acute input angle only below 30 degrees; dihedral angles and elevations keep 90. Conformity
    // stays exact and Rule 3's bound holds as before; triangulated surfaces need far fewer vertices (no pumping:
    // fandisk.off 7424 instead of 28003, anchor.off 5360 instead of 18411; with pumping fandisk.off has 8599 vertices
    // and none below 15 degrees, as under the paper's rule). Where it would leave an element missing, or
    // (with no min_split_length) its conflict zones grow large, the input is meshed again with the paper's rule
    // (MeshStats::encroaching_fell_back; bottle.brep's tessellation).
    Steiner,
  };
  Encroaching encroaching = Encroaching::Steiner;

  // Sliver removal (paper Section 3.7: Rule 4 and step 3, pumping; Theorem 7.3).
  // pump = false gives plain Delaunay refinement (Rules 1-3 only, all weights zero), for comparison.
  bool pump = true;
  // A tetrahedron inside the domain is a sliver when its radius-edge ratio is at most rho0 and its smallest
  // dihedral angle is below this many degrees (the practical form of the paper's sigma = V/L^3 <= sigma0). Rule 4
  // and pumping work on the vertices of slivers. Default chosen by measurement (issue 4).
  double sliver_angle_deg = 15.0;
  // omega0 of Section 3.3: a vertex v is tested for weighted encroachment (Rule 4) with weight omega0^2 f(v)^2,
  // and pumped within [0, omega0^2 f(v)^2] (f: local feature size). Dimensionless, in (0, 1).
  double omega = 0.5;
  // Pumping also keeps each weight at most delta^2 N(v)^2 (N(v): distance from v to its nearest vertex);
  // delta < 1/2 keeps the weighted balls disjoint, so no vertex is ever hidden. Dimensionless, in (0, 0.5).
  double delta = 0.45;
  // After pumping (beyond the paper): a point near the orthocentre of each sliver pumping left away from acute input
  // angles, when one keeps the boundary, rho0 and the weight caps and improves its neighbourhood; the new stars are
  // pumped again. Adds at most sliver_insertion_budget of plain refinement's vertex count. false: pumping alone (for
  // comparison).
  bool sliver_insertion = true;
  // Sliver insertion stops once the vertex count exceeds plain refinement's (Rules 1-3, before Rule 4) by this
  // fraction. The default keeps the whole of step 3 within issue 4's 1.05x of --no-pump. `qualmesh mesh` gives CAD
  // inputs kCadSliverInsertionBudget (cad_import.h) instead: there the slivers sit in thin walls and at the many
  // small angles of the CAD surface, and the node count is judged against Gmsh's at the same size.
  double sliver_insertion_budget = 0.048;
  // Last, beyond the paper (issue 16): where tetrahedra below sliver_angle_deg are left after extraction, their
  // vertices are moved (input vertices never; segment vertices along their segment, facet vertices within their
  // facet, and with project_to_boundary a vertex inside a curved CAD face on that face), flips are made inside
  // regions away from boundary and internal faces, and interior edges of slivers are split (a free vertex added),
  // each only when the smallest dihedral angle of what it changes grows.
  // Conformity stays exact; the touched tetrahedra (MeshStats::num_tets_improved) are no longer weighted Delaunay,
  // and their radius-edge bound away from acute input angles is kImproveRadiusEdgeFactor * radius_edge_bound
  // instead of rho0 (a changed tet above that is allowed only where its shortest edge is forced by an acute input
  // angle, and never above the worst tet it replaces). Runs only with pump = true. false: the engine's mesh as is,
  // with rho0 everywhere away from acute input angles (Cheng & Dey's guarantee).
  bool improve = true;

  // Cancellation (issue 18, for --time-limit, a memory budget and the FreeCAD task panel): when set, polled every
  // 64 vertex insertions and in the pumping passes; once it returns true, meshing stops as at the vertex limit
  // (MeshStatus::Cancelled) and mesh_plc() returns the mesh as it stands. Empty: never polled, no cost.
  std::function<bool()> cancel;

  // CAD inputs (beyond the paper): moves a point onto CAD edge `edge` (> 0) or else CAD face `face` (> 0) and
  // returns true, or leaves it and returns false (a straight edge, a plane, a failure). Rule 1 points on a segment
  // with a CAD edge number (Segment::marker), or inside one curved face, and Rule 2 points on a facet with a CAD face
  // number (Facet::marker) go through it before their conflict test, so they lie on the CAD surface rather than on
  // its chords; a move above a quarter of the split element is refused. Empty: points stay on the PLC (the paper).
  // The CLI binds it to OpenCASCADE (project_onto_cad, cad_import.h).
  std::function<bool(int edge, int face, Point3& p)> project_to_boundary;

  // Called once on the extracted mesh, before the improvement pass (when meshing ended Ok): the CLI fits a CAD
  // input's boundary nodes onto the CAD surface here (fit_mesh_to_cad), so that the pass works on the mesh that is
  // written, and never moves a fitted node off its face (a boundary node off its facet's plane is Fixed there).
  // It may move points and remove tetrahedra (with their boundary faces); it must not add or renumber points.
  std::function<void(TetMesh&)> before_improve;
};

enum class MeshStage { Initial, Boundary, Refinement, Regions, Pumping, Extraction };

// Short lower-case name of a stage ("boundary", ...).
const char* to_string(MeshStage stage);

struct ProgressEvent {
  MeshStage stage = MeshStage::Initial;
  double fraction = 0;  // estimated fraction of this stage done, in [0, 1]
  std::size_t num_vertices = 0;
};

using ProgressCallback = std::function<void(const ProgressEvent&)>;  // may be empty
using LogCallback = std::function<void(const std::string&)>;         // may be empty

struct MeshStats {
  std::size_t num_input_vertices = 0;
  std::size_t num_steiner_vertices = 0;       // vertices added by Rules 1-3 and sliver insertion
  std::size_t num_rule1_insertions = 0;       // subsegment splits (midpoints or concentric-shell points)
  std::size_t num_rule2_insertions = 0;       // subfacet circumcentres
  std::size_t num_rule3_insertions = 0;       // tetrahedron circumcentres
  std::size_t num_rejected_circumcenters = 0; // Rule 2 and Rule 3 centres rejected because they encroach
  std::size_t num_subfacet_flips = 0;         // 2D flips made to match a cocircular choice of the 3D triangulation
  std::size_t num_skipped_small_angle = 0;    // Rule 3 skips: shortest edge forced by an acute input angle
  std::size_t num_skipped_floor = 0;          // Rules 1-2 skips: encroached, but below the split floor
  // Encroaching::Steiner only: it left a subsegment or subfacet missing, or its conflict zones grew too large, so
  // the input was meshed again from the start with the paper's rule (Encroaching::All); the figures are that run's.
  bool encroaching_fell_back = false;
  // Encroaching::Steiner only: times the regions were flooded again after refinement because a region's boundary
  // crossed a face that is no subfacet while every subfacet was present (mesher.cpp reflood_regions).
  std::size_t num_region_refloods = 0;
  // MeshOptions::project_to_boundary was set and meshing gave up with it (the relaxed rule gave up, or pumping added
  // more than a tenth of the vertices it started with plus 200): the input was meshed again without it (before falling
  // back to the paper's rule), so Rule 1 and 2 points stayed on the facets.
  bool boundary_projection_dropped = false;
  std::size_t num_tets = 0;                   // tetrahedra in the output
  std::size_t num_boundary_faces = 0;         // faces in the output that lie on input facets
  double max_radius_edge = 0;                 // over the output tetrahedra
  // Output tetrahedra whose radius-edge ratio exceeds rho0, and why each was left (they add up, unless the
  // improvement pass changed tets: num_tets_above_bound is then recounted over the output, and the three reasons
  // stay those of the tets the engine left):
  //   acute:    it touches an acute input angle (MeshResult::tet_touches_acute_angle), Rule 3 skips it;
  //   rejected: Rule 3 gave up on it: its circumcentre encroaches a subsegment or subfacet whose split was
  //             refused or capped (8 rejected attempts);
  //   other:    anything else (numerical: flat on a facet, conflict zone across regions).
  std::size_t num_tets_above_bound = 0;
  std::size_t num_above_bound_acute = 0;
  std::size_t num_above_bound_rejected = 0;
  std::size_t num_above_bound_other = 0;
  double max_radius_edge_away_from_acute = 0;  // over the output tetrahedra not touching an acute input angle
  double min_dihedral_deg = 0;                // over the output tetrahedra
  // Rule 4 and pumping (zero when MeshOptions::pump is false). Slivers: MeshOptions::sliver_angle_deg.
  std::size_t num_rule4_encroachments = 0;    // subsegments/subfacets Rule 4 found weighted-encroached and queued
  std::size_t num_rule4_vertices = 0;         // vertices inserted (Rules 1-3) while draining those
  std::size_t num_vertices_before_pumping = 0; // triangulation vertices when pumping starts (after Rule 4)
  std::size_t num_vertices_after_pumping = 0;  // and when it ends: pumping adds and removes none
  std::size_t num_sliver_insertions = 0;        // points inserted at slivers after pumping (MeshOptions::sliver_insertion)
  std::size_t num_sliver_insertions_refused = 0; // slivers of the last insertion round with no acceptable point
  std::size_t num_slivers_before_pumping = 0; // in-domain slivers after refinement (Rules 1-4)
  std::size_t num_slivers_after_pumping = 0;  // in-domain slivers in the output
  std::size_t num_vertices_pumped = 0;        // vertices whose weight ended nonzero
  std::size_t num_pump_moves = 0;             // accepted weight changes (a vertex may be pumped more than once)
  std::size_t num_pump_rejected = 0;          // best weights refused (conformity, region or hidden-vertex check)
  double max_weight_cap_ratio = 0;            // max over vertices of weight / min(omega0^2 f^2, delta^2 N^2)
  double max_weight = 0;                      // largest weight (model units squared)
  double min_dihedral_before_pumping_deg = 0; // over in-domain tetrahedra after refinement
  // The improvement pass (MeshOptions::improve; zero when it did not run).
  std::size_t num_tets_improved = 0;          // output tetrahedra it changed (new by a flip, or a vertex moved)
  std::size_t num_improve_vertex_moves = 0;   // accepted vertex moves
  std::size_t num_improve_flips = 0;          // 2-3 flips and edge removals (n-to-2n-4, n = 3: 3-2 flips)
  std::size_t num_improve_insertions = 0;     // edges split at a sliver (one vertex added each; in the volume, or
                                              // inside a planar facet, whose two faces are split with it)
  std::size_t num_improve_caps_removed = 0;   // caps on CAD faces removed (two boundary faces on one face:
                                              // their shared edge flipped to the other diagonal)
  double min_dihedral_before_improve_deg = 0; // over all tetrahedra as extracted, before the pass
  // Output tetrahedra not touching an acute input angle (MeshResult::tet_touches_acute_angle): the smallest
  // dihedral angle among them, and how many have one below MeshOptions::sliver_angle_deg.
  double min_dihedral_away_from_acute_deg = 0;
  std::size_t num_tets_below_sliver_angle_away_from_acute = 0;
  // Wall-clock seconds per stage.
  double seconds_initial = 0;
  double seconds_boundary = 0;
  double seconds_regions = 0;
  double seconds_refinement = 0;
  double seconds_pumping = 0;  // Rule 4 rounds, pumping and sliver insertion
  double seconds_extraction = 0;
  double seconds_improve = 0;
};

enum class MeshStatus {
  Ok,
  VertexLimitReached,  // MeshOptions::max_vertices stopped refinement; the mesh is conforming only if the
                       // boundary stage had finished
  Cancelled,           // MeshOptions::cancel returned true; the same partial mesh as at the vertex limit
  PrecisionExhausted,  // Rules 1-2 split an element down to the limit of double precision (a split point fell on a
                       // vertex), with every fallback; the partial mesh does not conform (MeshResult::message)
};

struct MeshResult {
  MeshStatus status = MeshStatus::Ok;
  TetMesh mesh;  // positively oriented tets, region attribute per tet, input facet id per boundary/internal face
  // Per tet of `mesh`: 1 when it touches an acute input angle, i.e. its shortest edge joins two vertices lying on
  // input elements (input vertex, segment or facet; the smallest one holding the vertex) that meet at an acute
  // input angle. The one definition is InputComplex::elements_meet_acute (core/src/refine/complex.h): two
  // elements, neither containing the other, sharing an input vertex where the segment-segment or segment-facet
  // angle, or the facet-facet dihedral angle, is below 90 degrees; an input vertex counts through the segments and
  // facets incident to it. Rule 3 does not split these (the short edge is forced by the input).
  std::vector<std::uint8_t> tet_touches_acute_angle;
  MeshStats stats;
  std::string message;  // PrecisionExhausted: where refinement stopped (the input element, its size, the point)
};

// Thrown by mesh_plc() when MeshOptions::cancel stops it before the input vertices are triangulated (no partial mesh).
struct MeshCancelled : std::runtime_error {
  MeshCancelled() : std::runtime_error("meshing cancelled before the input vertices were triangulated") {}
};

// Meshes the volume bounded by `plc` (regions separated by internal facets; hole seeds remove regions; the outside
// of the closed boundary is not meshed). Deterministic: the same input and options give the same mesh, bit for bit.
// Closed surfaces that share no vertex and lie outside each other (solids of an assembly that do not touch) are
// meshed one by one and the meshes joined, each component's points after the previous one's (the statistics are
// summed); so a small gap between two solids draws no refinement. Progress then runs through the stages once per
// component.
MeshResult mesh_plc(const Plc& plc, const MeshOptions& options = {}, const ProgressCallback& progress = {},
                    const LogCallback& log = {});

}  // namespace qualmesh
