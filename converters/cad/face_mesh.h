// Sized surface mesh of the CAD faces (second stage of the sized CAD front end, after size_field.h): each CAD edge
// is discretised once, uniformly in arc length at its size, and shared by the faces that use it; a face is meshed
// by Delaunay refinement in its parameter plane (u, v) under 3D criteria, so that every node lies on the CAD surface
// and the triangles are well shaped in space. brep_to_plc.cpp assembles the PLC from these pieces (a planar face
// stays its exact polygons there, with its mesh's interior nodes in it). Private to converters/cad; no CGAL type
// here.
#pragma once

#include <TopoDS_Edge.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Vertex.hxx>

#include <array>
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "qualmesh/plc.h"

namespace qualmesh::cad {

// The discretisation of one CAD edge: PLC vertex ids and the edge's curve parameters of its points, from the
// edge's FORWARD first vertex to its last (ids.front() and ids.back() are the CAD vertices' ids).
struct EdgeChain {
  std::vector<Index> ids;
  std::vector<double> params;
};

// Curve parameters of n + 1 points that cut `edge` into n pieces of equal arc length (GCPnts_UniformAbscissa),
// n = ceil(length / size) (at least 3 on a closed edge, 1 otherwise), ends included, increasing. `size` > 0.
std::vector<double> discretise_edge(const TopoDS_Edge& edge, double size);

struct FaceMeshStats {
  std::size_t num_inserted = 0;       // interior nodes added by the refinement
  std::size_t num_rejected = 0;       // bad triangles left: their centre encroached a CAD edge or left the face
  bool capped = false;                // the refinement stopped at its insertion budget
  double max_chord_error = 0;         // largest distance from a triangle's centroid to the surface (sampled)
  double min_angle_deg = 180;         // smallest 3D corner angle of the face's triangles
  // remesh_face_on_surface: whether its triangles replaced the refinement's, after how many rounds, and why not (or
  // why it stopped before kRemeshRounds).
  bool remeshed = false;
  int num_remesh_rounds = 0;
  std::string remesh_refused;
  std::size_t num_delaunay_flips = 0;  // remesh_face_on_surface's flips to locally Delaunay edges
};

using SurfaceTriangle = std::array<Index, 3>;

// Triangles of one face, counter-clockwise about the surface normal of `face` taken FORWARD. The face's boundary
// nodes are the chains of its edges (chain_of; degenerate edges need none: their nodes are the vertex's id); new
// interior nodes are appended to `vertices` (their ids follow). `size`: the face's target edge length. Triangles
// that collapse on a degenerate edge are left out. The boundary is never split: a bad triangle whose centre
// encroaches it stays (stats.num_rejected). Throws InputError(Parse) naming the face when an edge has no curve on
// the face. Deterministic.
std::vector<SurfaceTriangle> mesh_curved_face(const TopoDS_Face& face, int face_number, double size,
                                              const std::function<const EdgeChain&(const TopoDS_Edge&)>& chain_of,
                                              const std::function<Index(const TopoDS_Vertex&)>& vertex_id,
                                              std::vector<Point3>& vertices, const std::string& file,
                                              FaceMeshStats& stats);

// Rounds of isotropic remeshing a face gets (fewer when a round would stand a triangle across the surface).
inline constexpr int kRemeshRounds = 6;

// Isotropic remeshing of one face's triangles (face_remesh.cpp) on its CAD surface, towards edges of length `size`:
// `triangles` (mesh_curved_face's, counter-clockwise about the normal of `face` taken FORWARD) use ids into
// `source`; nodes with fixed(id) (CAD vertices and edge chain nodes, the same ids in `vertices`) stay, pieces of edge
// chains (is_piece(a, b)) are neither split, collapsed nor flipped, every other node is moved or made on the
// surface. Returns the new triangles, their interior nodes appended to `vertices`; or, with stats.remesh_refused
// saying why (the first round failed, or left a triangle standing across the surface), `triangles` with their
// interior nodes appended to `vertices` as they were. Deterministic.
std::vector<SurfaceTriangle> remesh_face_on_surface(const TopoDS_Face& face, double size,
                                                    const std::vector<SurfaceTriangle>& triangles,
                                                    const std::function<bool(Index)>& fixed,
                                                    const std::function<bool(Index, Index)>& is_piece,
                                                    const std::vector<Point3>& source, std::vector<Point3>& vertices,
                                                    FaceMeshStats& stats);

}  // namespace qualmesh::cad
