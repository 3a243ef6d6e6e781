// CAD and OpenSCAD front end: reads a B-rep model (STEP/STP, IGES/IGS, OCCT BREP, FreeCAD .FCStd) through
// OpenCASCADE, or renders an OpenSCAD .scad file with the `openscad` command, heals what a CAD user expects to be
// healed, and delivers the piecewise linear complex (plc.h) that the mesher consumes.
//
// What the PLC carries (numbers are 1-based and follow FreeCAD's naming, i.e. TopExp::MapShapes order of the healed
// shape: Face<i>, Edge<i>, Solid<i>):
//  - a planar CAD face is one polygonal facet, exact: its outer wire and inner wires are polygons (an inner loop is a
//    hole by the odd-count rule of plc.h); a curved face is a set of triangular facets, every node on the CAD
//    surface, sized by CadOptions' size field (or, with CadSurfaceMesh::Tessellation, OpenCASCADE's tessellation
//    with the chordal deflection of CadOptions). Facet::marker = CAD face number.
//  - every CAD edge is discretised once, and every facet that uses the edge uses exactly that vertex chain; the
//    chain's pieces are Plc segments with Segment::marker = CAD edge number (degenerate edges have none).
//  - every solid gets a RegionSeed strictly inside it with attribute = solid number; a face shared by two solids
//    appears once (an internal facet).
//  - facet polygons are oriented outward of the first solid that uses the face (CadSummary::face_solids[i][0]).
// For .scad files the PLC is OpenSCAD's rendered surface (facet marker 0, no CAD numbering and no region seed, as
// for any surface input), see read_cad().
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include "qualmesh/plc.h"
#include "qualmesh/second_order.h"
#include "qualmesh/tet_mesh.h"

namespace qualmesh {

// CadOptions::min_size's default, relative to the target size.
inline constexpr double kDefaultMinSizeFactor = 1.0 / 30;

// A target edge length on one named CAD entity (FreeCAD's names: Face<id>, Edge<id>, Solid<id>, numbered as in
// the PLC's markers and the output groups).
struct CadLocalSize {
  enum class Kind { Face, Edge, Solid };
  Kind kind = Kind::Face;
  int id = 0;        // 1-based
  double size = 0;   // model units, > 0
};

// How the faces of a CAD model become the PLC's facets.
enum class CadSurfaceMesh {
  // Sized surface mesh (face_mesh.cpp): every CAD edge discretised at the size field, planar faces as exact
  // polygons, curved faces as well-shaped triangles with every node on the CAD surface. The default.
  Sized,
  // OpenCASCADE's chordal tessellation (BRepMesh) at `deflection`: what QualMesh did before the size field.
  Tessellation,
};

struct CadOptions {
  CadSurfaceMesh surface_mesh = CadSurfaceMesh::Sized;
  // Size field of the sized surface mesh (size_field.h; Gmsh's vocabulary). All lengths in model units.
  // Target edge length (Gmsh's CharacteristicLengthMax); 0 = default: a tenth of the bounding-box diagonal (the size
  // Gmsh gives a CAD vertex without a prescribed size).
  double size = 0;
  // Smallest edge length the curvature and thin-face refinement may ask for (CharacteristicLengthMin); 0 = a 30th
  // of the target (kDefaultMinSizeFactor). Local sizes are not bounded by it.
  double min_size = 0;
  // Elements per full circle of a curved edge or face (Gmsh's MeshSizeFromCurvature): a face of radius R gets edges
  // of at most 2 pi R / curvature_elements; 0 disables the curvature refinement.
  double curvature_elements = 12;
  // Largest ratio of the sizes of two CAD faces that share an edge (or a face and its edges); <= 1 disables.
  double gradation = 0;
  std::vector<CadLocalSize> local_sizes;  // the smallest size on an entity wins
  // Absolute chordal deflection for curved faces, in model units; 0 = derive it from relative_deflection.
  double deflection = 0;
  // Chordal deflection relative to the diagonal of the model's bounding box, used when deflection == 0.
  double relative_deflection = 0.001;
  // Largest angle between the normals of neighbouring tessellation triangles on a curved face, in degrees.
  double angular_deflection_deg = 20;
  // Sew loose faces into shells and solids, fix small and degenerate edges (ShapeFix).
  bool heal = true;
  // Sewing tolerance in model units; 0 = automatic (1e-6 of the bounding-box diagonal, at least the largest
  // tolerance stored in the model's vertices, at most 1e-4 of the diagonal).
  double sewing_tolerance = 0;
  // OpenSCAD only: seconds the `openscad` command may run before it is stopped; <= 0: no limit.
  double openscad_timeout_s = 600;
  // OpenSCAD only: the command to run ("openscad" on PATH by default).
  std::string openscad_command = "openscad";
};

// The volume mesher's split floor (MeshOptions::min_split_length) for a CAD model meshed at target size `size`:
// half the smallest size asked for (options.min_size, or its default kDefaultMinSizeFactor * size, and any smaller
// local size), so that a cusp of the model does not draw Rules 1-2 down to rounding; 0 when `size` is not positive.
// `qualmesh mesh` sets it for every CAD input (cmd_mesh.cpp), and the tests mesh as the CLI does through it.
inline double cad_min_split_length(const CadOptions& options, double size) {
  double smallest = options.min_size > 0 ? options.min_size : kDefaultMinSizeFactor * size;
  for (const CadLocalSize& local : options.local_sizes) smallest = std::min(smallest, local.size);
  return smallest > 0 ? 0.5 * smallest : 0;
}

// The volume mesher's sliver insertion budget (MeshOptions::sliver_insertion_budget) for CAD inputs: points at the
// slivers pumping leaves may add 10% of plain refinement's vertex count, not the 4.8% of surfaces and PLCs. A CAD
// surface's small angles and thin walls leave far more slivers than the default budget reaches (pump carter at
// --size 44.12: 469 left without a point, "vertex budget spent"), and the node count is judged against Gmsh's at the
// same size rather than against --no-pump. Measured on pump carter, nodes / min dihedral / tets below 10 / below 15,
// 4.8% then 10%: 44.12: 8712 / 4.72 / 174 / 685 -> 8935 / 4.89 / 56 / 168; 22.06: 9094 / 6.24 / 62 / 470 -> 9338 /
// 7.04 / 7 / 45; 11.03: 11572 / 7.57 / 1 / 54 -> 11972 / 14.85 / 0 / 1 (Gmsh: 8461 / 3.56 / 112 / 800, 8914 / 1.39
// / 57 / 686, 12279 / 8.57 / 3 / 260). 15% gave the same figures within a few tets. `qualmesh mesh` sets it for every
// CAD input unless --sliver-budget is given (cmd_mesh.cpp).
constexpr double kCadSliverInsertionBudget = 0.10;

struct CadSummary {
  std::size_t num_solids = 0;    // solids of the healed shape = regions of the PLC
  std::size_t num_faces = 0;     // CAD faces = distinct facet markers of the PLC
  std::size_t num_edges = 0;     // CAD edges (seam and degenerate edges included, as FreeCAD counts them)
  std::size_t num_vertices = 0;  // CAD vertices
  std::vector<double> solid_volumes;  // OpenCASCADE's volume of each solid (solid_volumes[i] is Solid<i+1>)
  // For each face (face_solids[i] is Face<i+1>): the solid numbers on its two sides, 0 = outside. The facets of the
  // face are oriented outward of face_solids[i][0]; an internal face has both entries non-zero.
  std::vector<std::array<int, 2>> face_solids;
  // Bound on the distance from any point of a face's facets to the CAD face, per face, in model units: twice the
  // deflection used (OpenCASCADE controls the deflection at sample points only) plus the face's and its edges'
  // tolerances. Empty for .scad (the facets are the model).
  std::vector<double> face_tolerances;
  // How far a NODE of a face may lie from it, per face, in model units: OpenCASCADE's tolerance of the face, raised
  // to its edges' and vertices' (a node on an edge lies on the edge's curve, which the face's surface holds only to
  // the edge's tolerance). FreeCAD's node search (FemMesh::getNodesByFace) takes a node within the face's tolerance,
  // so a node farther off is a node whose load is lost. Empty for .scad.
  std::vector<double> node_tolerances;
  double deflection_used = 0;  // absolute chordal deflection actually used (Sized: largest measured), model units
  double size_used = 0;        // Sized: the target edge length used (CadOptions::size or its default), model units
  // Sized: non-empty when the sized surface mesh was refused by validate_plc and the model tessellated instead.
  std::string surface_fallback;
  std::vector<std::string> healing_log;  // what was healed, one line per action (empty: nothing needed)
  // Sized: how the curved faces were meshed (isotropic remeshing on the surface, and the faces that kept their
  // refinement triangles, with why), one line each.
  std::vector<std::string> surface_log;
  std::string source_format;             // "STEP", "IGES", "BREP", "FCStd", "OpenSCAD"
  // The sharp features below kCadSharpAngleDeg (find_sharp_cad_features' two kinds), their counts and the smallest
  // of each, one line (part.step: "sharp features below 30 deg: 6 face corners (smallest 0.00 deg at Vertex38
  // (85.725, 25.4, 42.8752)), 0 edges"); empty for .scad.
  std::string sharp_features;
};

struct CadModel {
  Plc plc;
  CadSummary summary;
};

// True when the file name ends with .step .stp .iges .igs .brep .brp .fcstd or .scad (case-insensitive).
bool is_cad_path(const std::string& path);

// Reads a CAD or OpenSCAD file into a PLC. Throws InputError (error.h) naming what is wrong: an unreadable file
// (ErrorCode::Io / Parse), no solid or face (Empty), a model that stays open after healing (OpenBoundary; the message
// names the open faces and edges as FaceN / EdgeN of the file as read), an OpenSCAD failure (Parse, with OpenSCAD's
// own message), an OpenSCAD render that cannot be repaired exactly (OpenBoundary / DegenerateFacet).
// Does not print; OpenCASCADE's own console messages are silenced.
CadModel read_cad(const std::string& path, const CadOptions& options = {});

// Checker for meshes of a CAD model: for each point, its distance (model units) to CAD face Face<face_numbers[i]>
// of the model at `path` read and healed with `options` (so with the numbering read_cad gives), measured by
// OpenCASCADE on the trimmed face; infinity for a face number out of range. Reads the file again; throws InputError
// as read_cad does, and for .scad files (no CAD faces). Mutates nothing.
std::vector<double> distances_to_cad_faces(const std::string& path, const std::vector<Point3>& points,
                                           const std::vector<int>& face_numbers, const CadOptions& options = {});

// Fitting a mesh to the CAD model it was made from (the mesher keeps boundary nodes on the PLC's facets, which on a
// curved face are chords of the surface; FreeCAD finds a constraint's nodes on the CAD surface itself, to ~1e-7).
struct CadFitOptions {
  // Make the mesh second order (make_second_order) after the corners are fitted, and put the mid nodes of edges on
  // curved CAD faces and edges onto them.
  bool second_order = false;
  NodeMoveOptions moves;  // what an element must stay like when a node moves (second_order.h)
};

struct CadFitReport {
  std::size_t num_corner_targets = 0;    // boundary corner nodes with a curved CAD face or edge to go to
  std::size_t num_mid_targets = 0;       // mid nodes of edges on curved CAD faces or edges
  double max_offset_before = 0;          // largest distance of a corner node from its CAD face or edge, before
  NodeMoveReport corners;                // the moves of the corner nodes (linear element checks)
  NodeMoveReport mids;                   // the moves of the mid nodes (Jacobian checks at the ten nodes)
  std::size_t num_fixed_vertices = 0;    // nodes on two or more CAD edges (CAD vertices): never moved
  std::size_t num_flat_caps_removed = 0; // flat tetrahedra against the boundary removed (remove_flat_boundary_tets)
  // Second order: boundary caps removed because they kept a mid node off its curved face (remove_boundary_caps).
  std::size_t num_curving_caps_removed = 0;
  // Second order: interior edges of caps across a CAD edge split for the same reason (split_cap_interior_edges).
  std::size_t num_cap_edges_split = 0;
  // Second order: edges of boundary triangles opposite a corner the curve makes flat, split for the same reason
  // (split_flat_face_corners).
  std::size_t num_flat_corners_split = 0;
};

// Moves every boundary node of `mesh` onto the CAD face or edge it lies on: a node on one marked edge (Edge<e>)
// onto CAD edge e, another node on faces of a single marker f onto CAD face f; a node on two or more edges (a CAD
// vertex) stays. `mesh` must come from meshing read_cad(path, options).plc (face markers = CAD face
// numbers, edge markers = CAD edge numbers). A node already on its face or edge to rounding (1e-12 of the
// diagonal) is not moved, so exact planar polygons stay exact. Moves are checked (move_nodes_checked): a node whose move would invert
// or badly distort an element goes part of the way or stays, and the report counts it. Then the nearly flat
// tetrahedra lying against a face are removed (remove_flat_boundary_tets: CalculiX refuses them). With
// options.second_order the mesh is made second order and the mid nodes are fitted the same way. Throws InputError
// as read_cad does (the model is read again unless it is the one read_cad read last in this process).
CadFitReport fit_mesh_to_cad(const std::string& path, const CadOptions& options, TetMesh& mesh,
                             const CadFitOptions& fit_options = {});

// Moves `p` onto CAD edge Edge<edge> (edge > 0), or else onto CAD face Face<face> (face > 0), of the model at
// `path` read and healed with `options` (the numbering read_cad gives): the nearest point, by OpenCASCADE's
// projection. False, and `p` unchanged, when the entity is straight or planar (nothing to move), out of range, or
// the projection fails. For the mesher's boundary points (MeshOptions::project_to_boundary); keeps the projector of
// the last model asked about. Throws InputError as read_cad does when the model must be read.
bool project_onto_cad(const std::string& path, const CadOptions& options, int edge, int face, Point3& p);

// Sharp features of a CAD model (issue 15's goal: no tet below 10 degrees anywhere the CAD dihedral angles are
// 30 degrees or more), found on the CAD geometry itself, so that any mesher's mesh of the model is judged alike:
//  - a sharp edge: a CAD edge shared by two faces whose interior dihedral angle (measured in the solid, 360 minus
//    it at a reflex edge) is below the threshold at one of 9 points along it;
//  - a sharp vertex: a CAD vertex where two edges of one face leave at an angle below the threshold (a corner of the
//    face that tapers to a point, as where two nearly tangent faces meet a plane).
// The default threshold of a sharp CAD feature: issue 15's goal is no tet below 10 degrees anywhere the CAD dihedral
// angles are 30 degrees or more (`qualmesh check --protection-angle`'s default for a CAD model, and `info`'s line).
inline constexpr double kCadSharpAngleDeg = 30;

struct SharpCadFeatures {
  std::size_t num_sharp_edges = 0;
  std::size_t num_sharp_vertices = 0;
  std::vector<char> near_feature;  // per point given: it lies within the radius of a sharp edge or vertex (at least
                                   // within the entity's tolerance and 1e-7 of the model's diagonal: on it)
};
// The sharp features of the model at `path` (read and healed with `options`) below `angle_deg`, and which of
// `points` lie within `radius` of them. Throws InputError as read_cad does (and Unsupported for .scad).
SharpCadFeatures find_sharp_cad_features(const std::string& path, const CadOptions& options,
                                         const std::vector<Point3>& points, double angle_deg, double radius);

// What measure_against_cad measures besides the volume.
struct CadMeasureOptions {
  // Every boundary node against the CAD face its boundary face's label names. Off for a mesh whose face numbers
  // are not the model's (Gmsh's own numbering): its distances would be to the wrong faces.
  bool distances = true;
  // > 0: the sharp features below this angle (find_sharp_cad_features), with the mesh vertices within
  // feature_radius (model units) of them.
  double feature_angle_deg = 0;
  double feature_radius = 0;
  // The shape this process read last, when it is this model (`qualmesh mesh`, right after read_cad), instead of
  // reading and healing the file again.
  bool reuse_shape = false;
};

// How well a mesh of a CAD model fits it (what `qualmesh check MESH --ref MODEL.step` reports): every node of every
// boundary face with label f is measured against CAD face Face<f> by distances_to_cad_faces, and the mesh volume
// against OpenCASCADE's volume of the solids.
struct CadConformity {
  std::size_t num_nodes = 0;         // boundary nodes measured (a node on k CAD faces counts k times)
  std::size_t num_beyond = 0;        // farther from their face than its tolerance (CadSummary::node_tolerances)
  double max_distance = 0;           // model units
  double max_relative_to_tolerance = 0;  // max over nodes of distance / that face's tolerance
  double cad_volume = 0;             // sum of CadSummary::solid_volumes
  std::vector<std::string> problems; // the first few nodes beyond their face's tolerance, with coordinates
  // With CadMeasureOptions::feature_angle_deg > 0: the sharp features, and the mesh vertices within
  // feature_radius of them (ascending).
  bool features_checked = false;
  std::size_t num_sharp_edges = 0;
  std::size_t num_sharp_vertices = 0;
  std::vector<Index> feature_nodes;
};
// Mutates nothing; reads and heals the model again (no surface mesh) unless measure.reuse_shape. Throws InputError as
// read_cad does (and Unsupported for .scad).
CadConformity measure_against_cad(const std::string& path, const CadOptions& options, const TetMesh& mesh,
                                  const CadMeasureOptions& measure = {});

}  // namespace qualmesh
