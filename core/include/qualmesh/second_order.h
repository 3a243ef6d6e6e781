// Second-order (10-node) tetrahedra and checked node moves: what turns QualMesh's linear mesh into the quadratic
// mesh a structural solver wants (linear tets are far too stiff in bending), and what lets the CAD front end move
// boundary nodes onto curved CAD faces without inverting or badly distorting an element.
//
// The 10-node tetrahedron (TetMesh::tet_mid) maps barycentric coordinates L0..L3 to
//   x(L) = sum_i L_i (2 L_i - 1) x_i + sum_{i<j} 4 L_i L_j x_ij,
// and its Jacobian determinant det(dx/d(L1, L2, L3)) equals 6 times the volume of the straight tetrahedron when
// every mid node sits at its edge's midpoint. The checks below evaluate it at the ten nodes, as pre-processors do
// (ANSYS's "Jacobian ratio"), and at the four integration points and the centroid, where CalculiX and Abaqus need it
// positive: a ratio fine at the nodes can hide a negative Jacobian at an integration point.
#pragma once

#include <cstddef>
#include <functional>
#include <vector>

#include "qualmesh/tet_mesh.h"

namespace qualmesh {

// Adds one node at the midpoint of every distinct edge of the tetrahedra (shared between the elements that have
// it) and fills tet_mid, face_mid and edge_mid (tet_mesh.h). Mid nodes are appended to `points` after the corners,
// numbered in the order of first appearance over the tets' edges, so the result is deterministic. A mesh that is
// already second order is left as it is. Throws std::invalid_argument when a face or edge is not an edge set of
// the tetrahedra (a face whose edges no tet has).
void make_second_order(TetMesh& mesh);

// Jacobian determinant of 10-node tetrahedron t at its ten nodes, four integration points and centroid (tet_mid
// must be filled).
struct Tet10Jacobian {
  double min_det = 0;
  double max_det = 0;
  // min_det / max_det when max_det > 0, else 0 (-inf.. for inverted ones is clamped: a non-positive min gives a
  // ratio <= 0).
  double ratio() const { return max_det > 0 ? min_det / max_det : 0; }
};
Tet10Jacobian tet10_jacobian(const TetMesh& mesh, std::size_t t);

struct NodeMove {
  Index node = 0;
  Point3 target{};
  // Other places as good as the target (on the same CAD face or edge), tried in order, each in full, when the
  // target cannot be reached in full.
  std::vector<Point3> alternatives;
};

struct NodeMoveOptions {
  // A second-order element is acceptable when its Jacobian (Tet10Jacobian) is positive and
  // min/max >= min_jacobian_ratio.
  double min_jacobian_ratio = 0.1;
  // A linear element is acceptable when its volume stays positive and at least this fraction of its volume before
  // the move. A move onto a curved face is at most about the chordal deflection, so only elements already nearly
  // flat against the face lose much: measured on part.step, 0.2 left 35 boundary nodes part way, 0.01 leaves 12.
  double min_volume_fraction = 0.01;
  // When the full move of a boundary node would make an element unacceptable, first try moving that element's
  // interior nodes (nodes on no face of TetMesh::faces) by the same displacement too, so that the boundary node
  // still reaches its target; only then relax it part of the way.
  bool drag_interior = true;
  // When dragging them by the same displacement does not do, search other positions for those interior nodes that
  // keep every element around them acceptable, the node at its target (the untangling of Gmsh's high-order
  // optimiser, in miniature: a compass search on the worst element's margin). Only with drag_interior.
  bool optimise_interior = true;
  // When no full move keeps every element at min_jacobian_ratio, try them all again asking only this ratio of the
  // elements around the node (0: never) before relaxing the node part of the way: a node off its CAD face is a
  // load FreeCAD drops without a word, a low but positive Jacobian ratio an element CalculiX still takes.
  double last_resort_jacobian_ratio = 0.01;
};

struct NodeMoveReport {
  std::size_t num_requested = 0;  // moves asked for
  std::size_t num_full = 0;       // made in full: the node is at its target
  std::size_t num_partial = 0;    // made part of the way (an element would have been unacceptable at the target)
  std::size_t num_refused = 0;    // not made at all
  std::size_t num_dragged = 0;    // full moves made by also moving interior nodes (NodeMoveOptions::drag_interior)
  std::size_t num_optimised = 0;  // full moves made by searching new places for them (optimise_interior)
  std::size_t num_last_resort = 0;  // full moves made at last_resort_jacobian_ratio (counted in the above too)
  std::size_t num_alternative = 0;  // full moves made to one of NodeMove::alternatives
  double max_distance_left = 0;   // largest distance between a node and its target after the moves, model units
  std::size_t num_bad_elements = 0;  // elements unacceptable after all moves, not counting the flat ones below
  // Elements that cannot be judged by their Jacobian ratio: corners (nearly) flat, |6V| <= 1e-6 of the longest edge
  // cubed, or so small against their distance from the origin that their straight version fails the ratio by
  // rounding. No move made them so (a move never makes an element worse than acceptable): the straight mesh had them.
  std::size_t num_flat_elements = 0;
  double min_jacobian_ratio = 1;  // over the second-order elements that are not flat (1 for a linear mesh)
  // The elements that kept a move from being made in full (unacceptable at its target, the interior drag
  // included), sorted, each once.
  std::vector<std::size_t> blocking_elements;
};

// Moves each node towards its target, in the order given, keeping every element that has the node acceptable
// (NodeMoveOptions). For the target, then each alternative: the full move alone, else dragging the interior nodes
// of the elements it spoils, else placing them by the search; all of that again at last_resort_jacobian_ratio;
// else the largest of 3/4, 1/2, 1/4 of the move to the target that is acceptable, else none. An element that was
// unacceptable before a move only has to get no worse. Mutates mesh.points only. `alternatives_of`, when given,
// supplies the alternatives of a move that has none, only once its target fails (they may be costly to find).
NodeMoveReport move_nodes_checked(TetMesh& mesh, const std::vector<NodeMove>& moves,
                                  const NodeMoveOptions& options = {},
                                  const std::function<std::vector<Point3>(const NodeMove&)>& alternatives_of = {});

// Removes the nearly flat tetrahedra (|6V| <= flat L^3, L the longest edge) that lie against the boundary: a
// tetrahedron with exactly two faces in mesh.faces, both with the same face label, whose common edge is no
// TetMesh::edges entry. Its two other faces become boundary faces in their place (the boundary's diagonal flips;
// all four corners stay on the same CAD face, and the volume changes by |V|, next to nothing). Repeats until none is
// left, since a neighbour can become such a tetrahedron. CalculiX refuses a flat element ("nonpositive jacobian");
// the mesher leaves such caps where a curved CAD face's tessellation triangles are nearly coplanar. Linear meshes
// only (before make_second_order). Returns how many tetrahedra were removed.
std::size_t remove_flat_boundary_tets(TetMesh& mesh, double flat = 1e-6);

// Removes the boundary caps `select(t)` picks, as remove_flat_boundary_tets does for flat ones: a tetrahedron t with
// exactly two faces in mesh.faces, both on the hull (of no other tetrahedron), with the same face label, whose common
// edge is no TetMesh::edges entry, whose other two faces are in mesh.faces nowhere and whose opposite edge lies on
// no face of mesh.faces (so the boundary stays a manifold). Its two other faces become boundary faces in their
// place; the volume changes by its |V|. One pass (indices are those of `mesh` as given); returns how many were
// removed. Linear meshes only. fit_mesh_to_cad removes the caps that keep a mid node off its curved face: such a
// cap's two boundary faces meet at a corner whose three edges all lie on the face, so no interior node can keep its
// Jacobian positive once they follow the surface.
std::size_t remove_boundary_caps(TetMesh& mesh, const std::function<bool(std::size_t)>& select);

// Splits at its midpoint the one interior edge (on no face of mesh.faces) of each tetrahedron `select(t)` picks
// whose four corners all lie on faces and whose other five edges all lie on faces, unless it is a cap with two faces
// of one label (remove_boundary_caps's): a boundary cap across a CAD edge,
// whose only interior node, that edge's mid node, cannot keep its Jacobian positive once the mid nodes of both
// curved faces follow the surface. Every tetrahedron around the edge is split in two; the new vertex is interior,
// so a later curving may drag it or place it by a search (move_nodes_checked). Faces, edges and the volume are
// unchanged; tetrahedron t stays at index t (the half at the edge's smaller end) and the other halves are appended,
// so indices from before the split still name the tetrahedra that were not split. Linear meshes only. Returns how
// many edges were split.
std::size_t split_cap_interior_edges(TetMesh& mesh, const std::function<bool(std::size_t)>& select);

// Splits at its midpoint, in each tetrahedron `select(t)` picks, the edge of a boundary face (mesh.faces) that lies
// opposite a corner of more than flat_deg, a TetMesh::edges entry too. A boundary triangle whose two edges at a
// corner follow one smooth CAD curve, a straight edge running tangentially into an arc, has that corner at 180
// degrees once its mid nodes follow the curve, and no element on it keeps a positive Jacobian (part.step's Face20 at
// --size 10: 171 degrees, a triangle bounded by three CAD edges, when CAD inputs were tried with the 30-degree corner
// bound). Every tetrahedron, face and edge entry on the edge is split in two (the halves at the edge's first end
// keep their indices, the others are appended); the new vertex lies on the edge's chord, on a planar face or a
// straight edge exactly (fit_mesh_to_cad projects it onto a curved one). Linear meshes only. Returns how many edges
// were split; the new vertices are appended.
std::size_t split_flat_face_corners(TetMesh& mesh, const std::function<bool(std::size_t)>& select,
                                    double flat_deg = 150);

}  // namespace qualmesh
