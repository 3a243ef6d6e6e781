// Conformity-preserving mesh improvement (issue 16, "Quality, measured honestly": the last pass that perturbs the
// vertices of slivers and keeps conformity). Beyond the paper: it runs AFTER QUALMESH (Cheng & Dey, steps 1-3,
// extraction included) on the extracted TetMesh, only where the weighted framework (pumping, sliver insertion)
// left tetrahedra whose smallest dihedral angle is below a threshold. The tetrahedra it touches are no longer
// claimed to be weighted Delaunay (regular); every other output tetrahedron is the engine's.
//
// Models: CGAL Mesh_3's perturb_mesh_3 (Sliver_perturber: gradient and random moves of a sliver's vertices,
// accepted when the worst tetrahedron of the star gets better) and exude_mesh_3 (Slivers_exuder); the topological
// moves follow Shewchuk, "Two discrete optimization algorithms for the topological improvement of tetrahedral
// meshes" (2002: edge removal by Klincsek's dynamic programme over the ring of an edge) and Klingner & Shewchuk,
// "Aggressive tetrahedral mesh improvement" (2007: smoothing of the star's minimum quality plus flips; where both
// fail, an interior edge of the sliver is split and the new free vertex smoothed, their vertex insertion; an edge
// inside a planar facet is split too, its new vertex on the facet: issue 16's sliver-removing points on the boundary).
//
// Conformity is exact by construction: an input vertex never moves (but a CAD front end's mesh node inside a CAD
// edge or face, no CAD vertex, moves as a Steiner vertex there does); a vertex on an input segment moves only along
// that segment's line, a vertex inside an input facet only within the facet's plane, with every tetrahedron of its
// star positively oriented and every boundary triangle of its star keeping its orientation; flips touch no boundary
// or internal-facet face, no segment edge, and join only tetrahedra of one region; a split inside a facet puts its
// vertex on the facet and splits the two faces holding the edge, each half keeping the facet. So the boundary
// surface, every input facet (as a union of mesh faces) and each region's volume are those of the input mesh.
// The exceptions are on CAD inputs (ImproveOptions::project_to_boundary), where the mesh is already fitted to the
// CAD surface, not the PLC's chords: a vertex inside a curved CAD face (OnSurface) moves on that surface, one inside
// a curved CAD edge (OnCurve) along that curve, and a cap (a sliver with two boundary faces on one CAD face) is
// removed by flipping their shared edge (cap_removal.cpp); the boundary stays a mesh of the same CAD faces and
// edges with every node on its face or edge.
// Deterministic: ordered iteration, no global random generator; the same mesh in gives the same mesh out.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "qualmesh/plc.h"
#include "qualmesh/tet_mesh.h"

namespace qualmesh::detail {

// How a vertex may move.
enum class VertexFreedom : std::uint8_t {
  Fixed,      // an input vertex, or a boundary vertex whose constraint is not one line or one plane
  OnSegment,  // on an input segment: along VertexConstraint::direction only
  InFacet,    // inside one input facet (or one planar internal interface): orthogonal to direction (the normal)
  OnSurface,  // inside one curved CAD face (ImproveOptions::project_to_boundary): on that surface, moved in its
              // tangent plane (direction: the normal of the faces around it) and projected back onto it
  OnCurve,    // inside one curved CAD edge (ImproveOptions::project_to_boundary): on that curve, moved along its
              // tangent (direction: the chord between its two neighbours on the edge) and projected back onto it
  Interior,   // on no boundary or internal face: free
};

struct VertexConstraint {
  VertexFreedom freedom = VertexFreedom::Fixed;
  Point3 direction{0, 0, 0};  // unit: the line's direction (OnSegment, OnCurve) or the plane's normal (InFacet,
                              // OnSurface)
  int cad_face = 0;           // OnSurface: the CAD face number (TetMesh::face_marker) it stays on
  int cad_edge = 0;           // OnCurve: the CAD edge number (TetMesh::edge_marker) it stays on
};

// The freedom of every vertex of `mesh` (points, tets, faces with face_facet, edges), judged from the mesh's faces
// and the input `plc` (its vertices are the fixed points; its facets give the planes, its segments the lines):
//   input vertex (coordinates equal to a PLC vertex; with `curved`, a CAD run, not a surface mesh node of the CAD
//     front end: one that appears only alone in facet loops (inside a planar face), one on no segment whose loops
//     all belong to facets that share their marker > 0 (inside a curved face), or one on exactly two segments of
//     one marker > 0 (inside a CAD edge); those are judged as below)   -> Fixed;
//   on a crease (an edge of boundary faces that is shared by faces of two input facets, or by one or three faces),
//     on a marked TetMesh edge, or on an explicit PLC segment off the facet polygons, with exactly two such
//     collinear edges                                                  -> OnSegment;
//   all incident boundary faces on one input facet, coplanar with it   -> InFacet;
//   no incident boundary face                                          -> Interior;
//   with `curved`, a vertex that would be Fixed, on no marked TetMesh edge (a CAD edge), whose incident faces all
//     carry one face marker > 0 (inside a curved CAD face, which the CAD front end writes as triangle facets)
//                                                                      -> OnSurface;
//   with `curved`, a vertex that would be Fixed, not an input vertex, on exactly two marked TetMesh edges that carry
//     one edge marker > 0 (inside a curved CAD edge)                   -> OnCurve;
//   anything else                                                      -> Fixed.
std::vector<VertexConstraint> classify_vertices(const TetMesh& mesh, const Plc& plc, bool curved = false);

struct ImproveOptions {
  // Tetrahedra whose smallest dihedral angle is below this (degrees) are worked on.
  double sliver_angle_deg = 15.0;
  // Rounds over the bad tetrahedra; a round that changes nothing ends the pass.
  int max_rounds = 6;
  // Which operations run (both by default; tests switch one off to show the other works alone).
  bool smoothing = true;
  bool flips = true;
  // > 0 (the mesher passes kImproveRadiusEdgeFactor * rho0): no flip, move or split leaves a new or changed
  // tetrahedron above this radius-edge ratio, unless its shortest edge is forced by an acute input angle
  // (shortest_edge_forced, so the output flags it as touching one) and it is no worse than the worst it replaces.
  // So away from acute input angles the output's radius-edge ratio stays bounded (rho0 for the engine's tets,
  // this bound for changed ones).
  double radius_edge_bound = 0;
  // Where flips and moves leave a tet below the threshold: split one of its interior edges at its midpoint and move
  // the new (free) vertex to the best place in its star; kept only when the smallest angle around the edge grows.
  bool insertion = true;
  // With `insertion`: also split edges inside one planar input facet, the new vertex on the facet and the two
  // boundary faces holding the edge split with it (improve.cpp split_edge). Off for meshes fitted to a CAD surface
  // (MeshOptions::before_improve), where a point on the chord between two surface nodes would be off the surface.
  bool boundary_insertion = true;
  // With project_to_boundary: a tet below the threshold with two boundary faces on one CAD face (a cap) is
  // removed, its shared boundary edge flipped to the other diagonal (cap_removal.cpp).
  bool cap_removal = true;
  // Largest ring of an edge removal (the n-to-2n-4 flip); 3 is the 3-2 flip.
  int max_edge_ring = 7;
  // MeshOptions::project_to_boundary (the mesher passes it): moves p onto curved CAD edge `edge` (a
  // TetMesh::edge_marker; face 0) or curved CAD face `face` (a TetMesh::face_marker; edge 0) and returns true, or
  // returns false (a line, a plane, a failure). Set, the vertices inside one curved face are OnSurface and those
  // inside one curved edge OnCurve, smoothed on it: every position tried is this projection of a point of the
  // tangent plane or line, so the vertex stays on the CAD surface. Empty: they are Fixed. (With only the Rule 1
  // points of a curved edge free, and the front end's edge nodes Fixed, moving along the edge made no measured
  // difference; with both free, wrenchnut.stp at --size 10.15 went from 4 tets below 10 degrees to 0.)
  std::function<bool(int edge, int face, Point3& p)> project_to_boundary;
  // Polled once per bad tetrahedron; true stops the pass (the mesh stays valid).
  std::function<bool()> cancel;
  // Given one line per round (may be empty): the mesher's verbose log.
  std::function<void(const std::string&)> log;
};

struct ImproveResult {
  std::size_t num_tets_touched = 0;    // output tetrahedra that are new (flips) or have a moved vertex
  std::size_t num_vertex_moves = 0;    // accepted vertex moves (a vertex may move more than once)
  std::size_t num_vertices_moved = 0;  // distinct vertices moved
  std::size_t num_insertions = 0;      // edges split (a new vertex each, appended to the points)
  std::size_t num_boundary_insertions = 0;  // of which inside a facet (two boundary faces split each)
  std::size_t num_caps_removed = 0;    // caps on CAD faces removed (their boundary edge flipped)
  std::size_t num_flips = 0;           // 2-3 flips plus edge removals
  std::size_t num_flips23 = 0;
  std::size_t num_edge_removals = 0;   // of which n = 3 are 3-2 flips
  std::size_t num_fixed = 0, num_on_segment = 0, num_in_facet = 0, num_on_surface = 0, num_on_curve = 0,
              num_interior = 0;  // classification counts
  double min_dihedral_before_deg = 0;  // over all tetrahedra
  double min_dihedral_after_deg = 0;
  std::size_t num_below_before = 0;    // tetrahedra below ImproveOptions::sliver_angle_deg
  std::size_t num_below_after = 0;
};

// Improves `mesh` in place: vertex moves within each vertex's freedom, flips inside regions and interior edge splits,
// each accepted only when the smallest dihedral angle of the tetrahedra it changes strictly increases (so the mesh's
// minimum never decreases). Points keep their indices (split vertices are appended, with weight 0 when the mesh has
// weights); edges are unchanged, and so are faces except where a split inside a facet replaced a face by its two
// halves (the first keeps the face's index, the second is appended with its facet and marker); tets are renumbered in
// extract.cpp's canonical order when a flip or split happened, with tet_region following.
// `touches_acute` (may be null; one flag per tet) is kept aligned: a tet left as it was keeps its flag, a changed
// one gets `shortest_edge_forced(u, w)` for its shortest edge uw (extract.cpp's criterion: that edge joins vertices
// on input elements meeting at an acute angle), or 0 without the callback.
ImproveResult improve_mesh(TetMesh& mesh, const Plc& plc, const ImproveOptions& options,
                           std::vector<std::uint8_t>* touches_acute = nullptr,
                           const std::function<bool(Index, Index)>& shortest_edge_forced = {});

}  // namespace qualmesh::detail
