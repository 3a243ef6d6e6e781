// B-rep to PLC (third stage of the CAD front end): meshes the faces and writes the piecewise linear complex the
// mesher consumes. Two ways (CadOptions::surface_mesh):
//  - Sized (default): the size field (size_field.h) sets a length per CAD edge and face; every edge is discretised
//    once uniformly at its size, every face is meshed by Delaunay refinement on its surface and remeshed
//    (face_mesh.h), every node on the CAD surface. A planar face stays its exact wire polygons, with the interior
//    nodes of its mesh as isolated vertices of the facet (the volume mesher triangulates the facet through them).
//  - Tessellation: OpenCASCADE's BRepMesh at the chordal deflection, described below.
//
// Conformity between faces is by construction, not by tolerance: every CAD edge is discretised once (BRepMesh
// shares an edge's polygon between the faces that use it) and its vertex chain is given PLC vertex ids once; every
// face maps its boundary nodes onto those ids. So two facets that share a CAD edge share exactly the same vertex
// chain, and the seam of a periodic face closes on itself. A planar face becomes one facet whose polygons are its
// wires (exact up to the points where a neighbouring curved face's edge is discretised), plus its interior nodes in
// the sized way; a curved face becomes the triangles of its mesh, all with the face's number as marker.
#include <optional>

#include <BRepBndLib.hxx>
#include <BRepGProp.hxx>
#include <BRepMesh_IncrementalMesh.hxx>
#include <BRepAdaptor_Curve.hxx>
#include <BRepAdaptor_Surface.hxx>
#include <BRepTools.hxx>
#include <BRepTools_WireExplorer.hxx>
#include <BRep_Tool.hxx>
#include <Bnd_Box.hxx>
#include <GCPnts_AbscissaPoint.hxx>
#include <GProp_GProps.hxx>
#include <IMeshTools_Parameters.hxx>
#include <Poly_PolygonOnTriangulation.hxx>
#include <Poly_Triangulation.hxx>
#include <Standard_Failure.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Wire.hxx>

#include <algorithm>
#include <cmath>
#include <array>
#include <limits>
#include <set>

#include "cad_private.h"
#include "face_mesh.h"
#include "size_field.h"
#include "qualmesh/error.h"

namespace qualmesh::cad {
namespace {

// Height (relative to the model's diagonal) below which BRepMesh's flat triangles are removed (ten times below
// validate_plc's default planarity tolerance).
constexpr double kPlanarityTolerance = 1e-7;
// Largest distance of a planar face's polygon vertices from their mean plane, relative to the model's diagonal, for
// the face to become one polygonal facet: rounding only. The mesher keeps the 3D points of a facet where they are,
// so a polygon whose vertices stray by more (Zylkopf.stp: 1e-8 of the diagonal, healed edges) gives boundary faces
// off their facet; such a face uses its triangles instead, each planar by construction.
constexpr double kPolygonPlanarityTolerance = 1e-11;
// Sized surface mesh: relative deflection of the coarse BRepMesh run whose triangulation gives the bounding box.
constexpr double kBoxRelativeDeflection = 0.005;
// Sized surface mesh: the edge length the isotropic remeshing of a face aims at, relative to the face's size. Gmsh's
// surfaces at -clmax h have edges a little shorter than h on average (cylinder.brep at 5: 221 surface nodes against
// 161 with a target of h). 0.9 gives Gmsh's volume node count within 0.74-1.25x on tests/data/cad's cylinder at 5
// and 2.5 and torus at 2 (1.0: 0.66-1.08x; 0.85: 0.80-1.40x).
constexpr double kRemeshLengthFactor = 0.9;

Point3 to_point(const gp_Pnt& p) { return {p.X(), p.Y(), p.Z()}; }

double distance(const Point3& a, const Point3& b) {
  return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
}

// The distance of p from the segment [a, b].
double distance_to_segment(const Point3& p, const Point3& a, const Point3& b) {
  double ab2 = 0, dot = 0;
  for (int k = 0; k < 3; ++k) {
    ab2 += (b[k] - a[k]) * (b[k] - a[k]);
    dot += (p[k] - a[k]) * (b[k] - a[k]);
  }
  const double t = ab2 > 0 ? std::clamp(dot / ab2, 0.0, 1.0) : 0.0;
  return distance(p, {a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]), a[2] + t * (b[2] - a[2])});
}

// How far a node of `face` may lie from it: its tolerance, raised to its edges' and vertices' (CadSummary).
double node_tolerance(const TopoDS_Face& face) {
  double tolerance = BRep_Tool::Tolerance(face);
  for (TopExp_Explorer it(face, TopAbs_EDGE); it.More(); it.Next())
    tolerance = std::max(tolerance, BRep_Tool::Tolerance(TopoDS::Edge(it.Current())));
  for (TopExp_Explorer it(face, TopAbs_VERTEX); it.More(); it.Next())
    tolerance = std::max(tolerance, BRep_Tool::Tolerance(TopoDS::Vertex(it.Current())));
  return tolerance;
}

// OpenCASCADE's volume of one solid.
double volume_of(const TopoDS_Shape& solid) {
  GProp_GProps props;
  BRepGProp::VolumeProperties(solid, props);
  return props.Mass();
}

// Builds the PLC of one healed shape. Members are the conversion's state; convert() runs it once.
class PlcBuilder {
 public:
  PlcBuilder(const TopoDS_Shape& solids, const CadOptions& options, const std::string& file)
      : shape_(solids), options_(options), file_(file) {}

  CadModel convert() {
    TopExp::MapShapes(shape_, TopAbs_SOLID, solids_);
    TopExp::MapShapes(shape_, TopAbs_FACE, faces_);
    TopExp::MapShapes(shape_, TopAbs_EDGE, edges_);
    TopExp::MapShapes(shape_, TopAbs_VERTEX, vertices_);
    CadSummary& summary = model_.summary;
    summary.num_solids = solids_.Extent();
    summary.num_faces = faces_.Extent();
    summary.num_edges = edges_.Extent();
    summary.num_vertices = vertices_.Extent();
    face_triangles_.assign(faces_.Extent() + 1, {});
    for (int f = 1; f <= faces_.Extent(); ++f)
      summary.node_tolerances.push_back(node_tolerance(TopoDS::Face(faces_(f))));
    model_.plc.name = file_;
    if (options_.surface_mesh == CadSurfaceMesh::Sized) return convert_sized();

    tessellate();
    assign_face_sides();
    vertex_ids_.assign(vertices_.Extent() + 1, kNoIndex);
    edge_chains_.assign(edges_.Extent() + 1, {});
    for (int f = 1; f <= faces_.Extent(); ++f) add_face(f);
    add_segments();
    add_regions();
    return std::move(model_);
  }

 private:
  // The sized surface mesh (face_mesh.h): edges at the size field, every face refined and remeshed on its surface,
  // planar faces then written as polygons with their interior nodes. BRepMesh still runs, coarsely: the model's
  // bounding box (and so the default size) is that of its triangulation.
  CadModel convert_sized() {
    tessellate(kBoxRelativeDeflection);
    assign_face_sides();
    vertex_ids_.assign(vertices_.Extent() + 1, kNoIndex);
    edge_chains_.assign(edges_.Extent() + 1, {});
    edge_params_.assign(edges_.Extent() + 1, {});
    edge_spacing_.assign(edges_.Extent() + 1, 0);
    const SizeField field(solids_, faces_, edges_, options_, diagonal_, file_);
    model_.summary.size_used = field.target();
    for (int e = 1; e <= edges_.Extent(); ++e) {
      const TopoDS_Edge edge = TopoDS::Edge(edges_(e).Oriented(TopAbs_FORWARD));
      TopoDS_Vertex first, last;
      TopExp::Vertices(edge, first, last);
      if (BRep_Tool::Degenerated(edge)) continue;  // a pole: its faces give it points in (u, v) only
      std::vector<double> params = discretise_edge(edge, field.edge_size(e));
      BRepAdaptor_Curve curve(edge);
      std::vector<Index>& chain = edge_chains_[e];
      chain.push_back(vertex_id(first));
      for (std::size_t i = 1; i + 1 < params.size(); ++i) chain.push_back(add_vertex(to_point(curve.Value(params[i]))));
      chain.push_back(vertex_id(last));
      edge_spacing_[e] = GCPnts_AbscissaPoint::Length(curve) / static_cast<double>(params.size() - 1);
      edge_params_[e] = std::move(params);
    }
    mesh_sized_faces(field);
    add_segments();
    add_regions();
    return std::move(model_);
  }

  // Every face is meshed once on its edge chains as the size field cut them, then remeshed, and becomes its facets,
  // in face order: a planar face one polygonal facet with its interior nodes as isolated vertices (add_planar_face),
  // or its triangles when its wires make no planar polygon; a curved face its triangles. The chains are not split
  // for the faces' bad triangles: doing so (Chew's rule across faces, in up to 6 rounds of meshing again) cascaded
  // through the faces sharing an edge and made the volume mesh finer and worse (--size at Gmsh's default, same
  // run, 6 rounds -> none: t20_data.step 3412 -> 754 nodes and 172 -> 30 tets below 10 deg, Kurbelwelle.stp
  // 4251 -> 2887 and 134 -> 6, the pump carter 12593 -> 7911 and 1776 -> 463; part.step 1401 -> 1268 and 22 -> 24).
  // The volume mesher's Rules 1 and 2 split the boundary where its elements need it, onto the CAD surface.
  void mesh_sized_faces(const SizeField& field) {
    const int num_faces = faces_.Extent();
    std::vector<char> planar(num_faces + 1, 0);
    for (int f = 1; f <= num_faces; ++f)
      planar[f] = BRepAdaptor_Surface(TopoDS::Face(faces_(f)), Standard_False).GetType() == GeomAbs_Plane;
    std::vector<std::vector<SurfaceTriangle>> triangles(num_faces + 1);
    std::vector<FaceMeshStats> stats(num_faces + 1);
    std::vector<Point3>& vertices = model_.plc.vertices;
    const std::size_t boundary_end = vertices.size();
    for (int f = 1; f <= num_faces; ++f) triangles[f] = mesh_face_on_surface(f, field, stats[f]);
    remesh_faces(field, boundary_end, triangles, stats);
    std::vector<double> tolerances(num_faces + 1, 0);
    double max_chord_error = 0;
    for (int f = 1; f <= num_faces; ++f) {
      const TopoDS_Face face = TopoDS::Face(faces_(f).Oriented(TopAbs_FORWARD));
      double base_tolerance = BRep_Tool::Tolerance(face);
      for (TopExp_Explorer it(face, TopAbs_EDGE); it.More(); it.Next())
        base_tolerance = std::max(base_tolerance, BRep_Tool::Tolerance(face) + BRep_Tool::Tolerance(TopoDS::Edge(it.Current())));
      for (const SurfaceTriangle& t : triangles[f])
        face_triangles_[f].push_back({vertices[t[0]], vertices[t[1]], vertices[t[2]]});
      if (planar[f] && add_planar_face(face, f)) {
        add_interior_nodes(triangles[f], boundary_end, model_.plc.facets.back());
        triangles[f].clear();
        tolerances[f] = base_tolerance;
        continue;
      }
      if (triangles[f].empty())
        throw InputError(ErrorCode::DegenerateFacet, "Face" + std::to_string(f) + " gave no triangle", file_);
      // A point the volume mesher puts on a boundary piece (Rule 1) lies on the piece's chord, off the face by up to
      // the curved edge's sagitta: the face claims that as well (Zylkopf.stp, Face103: 0.9e-3 against a centroid
      // chord error of 0.8e-5).
      stats[f].max_chord_error = std::max(stats[f].max_chord_error, face_edge_sagitta(face));
      for (const SurfaceTriangle& t : triangles[f]) {
        Facet facet;
        facet.polygons.push_back(face_reversed_[f] ? std::vector<Index>{t[0], t[2], t[1]}
                                                   : std::vector<Index>{t[0], t[1], t[2]});
        facet.marker = f;
        model_.plc.facets.push_back(std::move(facet));
      }
      // Nodes are on the surface; the facets between them within the chordal error (sampled at the centroids, so
      // twice that is claimed, as for BRepMesh's deflection).
      tolerances[f] = 2 * stats[f].max_chord_error + base_tolerance;
      max_chord_error = std::max(max_chord_error, stats[f].max_chord_error);
    }
    // A plane face's nodes are its polygon's, exact; but a node of a neighbouring curved face's chord, which the
    // CAD fit may move only part of the way, can sit by its corner: the plane claims the model's chordal bound too
    // (as every face did with the tessellation's deflection).
    for (int f = 1; f <= num_faces; ++f)
      if (planar[f] && tolerances[f] > 0 && triangles[f].empty()) tolerances[f] += 2 * max_chord_error;
    model_.summary.face_tolerances.assign(tolerances.begin() + 1, tolerances.end());
    model_.summary.deflection_used = max_chord_error;
  }

  // The faces' triangles remeshed on their surfaces (face_remesh.cpp, isotropic remeshing towards
  // kRemeshLengthFactor times the face's size; the edge chains stay): nodes [0, boundary_end) are CAD vertices and
  // chain nodes, the rest the faces' interior nodes, made anew here face by face.
  void remesh_faces(const SizeField& field, std::size_t boundary_end,
                    std::vector<std::vector<SurfaceTriangle>>& triangles, std::vector<FaceMeshStats>& stats) {
    std::vector<Point3>& vertices = model_.plc.vertices;
    const std::vector<Point3> source = vertices;
    vertices.resize(boundary_end);
    std::set<std::pair<Index, Index>> pieces;
    for (const std::vector<Index>& chain : edge_chains_)
      for (std::size_t i = 0; i + 1 < chain.size(); ++i)
        pieces.emplace(std::min(chain[i], chain[i + 1]), std::max(chain[i], chain[i + 1]));
    const auto fixed = [boundary_end](Index id) { return id < boundary_end; };
    const auto is_piece = [&pieces](Index a, Index b) { return pieces.count({std::min(a, b), std::max(a, b)}) > 0; };
    std::size_t num_remeshed = 0, num_partial = 0, num_flips = 0;
    std::string refused;
    for (int f = 1; f < static_cast<int>(triangles.size()); ++f) {
      if (triangles[f].empty()) continue;
      const TopoDS_Face face = TopoDS::Face(faces_(f).Oriented(TopAbs_FORWARD));
      triangles[f] = remesh_face_on_surface(face, kRemeshLengthFactor * face_size(f, field), triangles[f], fixed,
                                            is_piece, source, vertices, stats[f]);
      num_remeshed += stats[f].remeshed;
      num_flips += stats[f].num_delaunay_flips;
      num_partial += stats[f].remeshed && stats[f].num_remesh_rounds < kRemeshRounds;
      if (!stats[f].remeshed)
        refused += (refused.empty() ? "" : ", ") + ("Face" + std::to_string(f)) + " (" + stats[f].remesh_refused + ")";
    }
    if (num_remeshed || !refused.empty())
      model_.summary.surface_log.push_back(
          std::to_string(num_remeshed) + " faces remeshed on the CAD surface (" + std::to_string(num_partial) +
          " of them stopped early: a round was undone; " + std::to_string(num_flips) +
          " edges of curved faces flipped to locally Delaunay ones)" +
          (refused.empty() ? "" : "; kept the refinement's triangles: " + refused));
  }

  // The largest distance between a chord of a face's edge chains (the sized discretisation) and its edge curve: the
  // largest distance of kSagittaSamples - 1 inner points of each piece from the piece's chord segment. Not the
  // distance at the middle parameter alone: on a B-spline edge far from arc-length parametrisation (bottle.brep's
  // edges 3, 6 and 18) the curve point at the middle parameter slides along the curve, and that distance is mostly
  // tangential (0.19 claimed there against a true 0.144 elsewhere on the face, which left no region seed in the
  // 0.6 wall).
  double face_edge_sagitta(const TopoDS_Face& face) const {
    constexpr int kSagittaSamples = 8;
    double sagitta = 0;
    for (TopExp_Explorer it(face, TopAbs_EDGE); it.More(); it.Next()) {
      const TopoDS_Edge edge = TopoDS::Edge(it.Current());
      const int e = edges_.FindIndex(edge);
      if (e <= 0 || BRep_Tool::Degenerated(edge)) continue;
      const std::vector<Index>& chain = edge_chains_[e];
      const std::vector<double>& params = edge_params_[e];
      if (chain.size() != params.size() || chain.size() < 2) continue;
      const BRepAdaptor_Curve curve(TopoDS::Edge(edge.Oriented(TopAbs_FORWARD)));
      const std::vector<Point3>& vertices = model_.plc.vertices;
      for (std::size_t i = 0; i + 1 < chain.size(); ++i) {
        const Point3 &a = vertices[chain[i]], &b = vertices[chain[i + 1]];
        for (int k = 1; k < kSagittaSamples; ++k) {
          const double t = params[i] + (params[i + 1] - params[i]) * k / kSagittaSamples;
          sagitta = std::max(sagitta, distance_to_segment(to_point(curve.Value(t)), a, b));
        }
      }
    }
    return sagitta;
  }

  // The size a face is meshed at: its size in the field, but no coarser than the coarsest of its edges as they were
  // discretised (edge_spacing_). A face all of whose edges are cut finer than its size (the 10 mm ends of a beam
  // meshed at 9.5, their edges in two pieces of 5) is meshed at that spacing inside too, as Gmsh's size extended
  // from the boundary does, instead of in a few triangles stretched across it; a face with one edge at its size
  // keeps its size, however fine its small holes are cut. On the cantilever of examples/ this made the C3D10 tip
  // deflection per node Gmsh's (551 nodes: 1.8965 mm, Gmsh 1.8964 mm).
  double face_size(int f, const SizeField& field) const {
    double coarsest = 0;
    for (TopExp_Explorer it(faces_(f), TopAbs_EDGE); it.More(); it.Next()) {
      const int e = edges_.FindIndex(it.Current());
      if (e > 0 && !BRep_Tool::Degenerated(TopoDS::Edge(it.Current()))) coarsest = std::max(coarsest, edge_spacing_[e]);
    }
    return coarsest > 0 ? std::min(field.face_size(f), coarsest) : field.face_size(f);
  }

  // One face's mesh on its surface (face_mesh.h).
  std::vector<SurfaceTriangle> mesh_face_on_surface(int f, const SizeField& field, FaceMeshStats& stats) {
    const TopoDS_Face face = TopoDS::Face(faces_(f).Oriented(TopAbs_FORWARD));
    return mesh_curved_face(face, f, face_size(f, field), chain_for(),
                            [this](const TopoDS_Vertex& v) { return vertex_id(v); }, model_.plc.vertices, file_,
                            stats);
  }

  // An edge's chain, as the face mesher asks for it.
  std::function<const EdgeChain&(const TopoDS_Edge&)> chain_for() {
    return [this](const TopoDS_Edge& edge) -> const EdgeChain& {
      const int e = edges_.FindIndex(edge);
      scratch_chain_.ids = edge_chains_[e];
      scratch_chain_.params = edge_params_[e];
      return scratch_chain_;
    };
  }

  void tessellate(double relative_deflection = -1) {
    // An earlier conversion of the same shape (the sized surface's coarse seed run, before read_cad falls back)
    // left its triangulation in the shape, which BRepMesh would refine rather than redo and BRepBndLib would box:
    // the tessellation must depend on the parameters only (bottle.brep's fallback gave 3196 input vertices on
    // which refinement ran for over 20 minutes, against 2769 and 6 s with --cad-surface tessellation).
    BRepTools::Clean(shape_);
    Bnd_Box box;
    BRepBndLib::Add(shape_, box);
    diagonal_ = std::sqrt(box.SquareExtent());
    double deflection = relative_deflection > 0 ? relative_deflection * diagonal_
                        : options_.deflection > 0 ? options_.deflection
                                                  : options_.relative_deflection * diagonal_;
    if (!(deflection > 0)) throw InputError(ErrorCode::Empty, "the CAD model has zero size", file_);
    model_.summary.deflection_used = deflection;
    IMeshTools_Parameters parameters;
    parameters.Deflection = deflection;
    parameters.Angle = options_.angular_deflection_deg * M_PI / 180.0;
    parameters.Relative = Standard_False;
    parameters.InParallel = Standard_False;  // deterministic and cheap enough; the mesher is the costly stage
    parameters.ControlSurfaceDeflection = Standard_True;
    BRepMesh_IncrementalMesh mesher(shape_, parameters);
    if (!mesher.IsDone()) throw InputError(ErrorCode::Parse, "OpenCASCADE could not tessellate the model", file_);
  }

  // Solid numbers on both sides of each face, and the volume of each solid.
  void assign_face_sides() {
    CadSummary& summary = model_.summary;
    summary.face_solids.assign(faces_.Extent(), {0, 0});
    face_reversed_.assign(faces_.Extent() + 1, false);
    for (int s = 1; s <= solids_.Extent(); ++s) {
      summary.solid_volumes.push_back(volume_of(solids_(s)));
      for (TopExp_Explorer it(solids_(s), TopAbs_FACE); it.More(); it.Next()) {
        int f = faces_.FindIndex(it.Current());
        auto& sides = summary.face_solids[f - 1];
        if (sides[0] == 0) {
          sides[0] = s;
          face_reversed_[f] = it.Current().Orientation() == TopAbs_REVERSED;
        } else if (sides[0] != s) {
          sides[1] = s;
        }
      }
    }
  }

  Index add_vertex(const Point3& p) {
    model_.plc.vertices.push_back(p);
    return static_cast<Index>(model_.plc.vertices.size() - 1);
  }

  Index vertex_id(const TopoDS_Vertex& v) {
    int k = vertices_.FindIndex(v);
    if (vertex_ids_[k] == kNoIndex) vertex_ids_[k] = add_vertex(to_point(BRep_Tool::Pnt(v)));
    return vertex_ids_[k];
  }

  // The PLC vertex chain of an edge, from its first to its last vertex (forward orientation), made the first time a
  // face's polygon of the edge is seen. `nodes` are triangulation node numbers along the edge's parameter.
  const std::vector<Index>& edge_chain(const TopoDS_Edge& edge, const Poly_PolygonOnTriangulation& polygon,
                                       const Poly_Triangulation& triangulation, const TopLoc_Location& location) {
    int e = edges_.FindIndex(edge);
    std::vector<Index>& chain = edge_chains_[e];
    if (!chain.empty()) return chain;
    TopoDS_Vertex first, last;
    TopExp::Vertices(TopoDS::Edge(edge.Oriented(TopAbs_FORWARD)), first, last);
    const int n = polygon.NbNodes();
    if (BRep_Tool::Degenerated(edge)) {
      chain.assign(n, vertex_id(first));
      return chain;
    }
    chain.resize(n);
    chain.front() = vertex_id(first);
    chain.back() = vertex_id(last);
    const gp_Trsf& transform = location.Transformation();
    // Polygon nodes run along the edge parameter; check which end is the first vertex.
    gp_Pnt start = triangulation.Node(polygon.Node(1)).Transformed(transform);
    bool reversed = start.Distance(BRep_Tool::Pnt(first)) > start.Distance(BRep_Tool::Pnt(last)) &&
                    !first.IsSame(last);
    for (int i = 2; i < n; ++i) {
      int node = polygon.Node(reversed ? n + 1 - i : i);
      chain[i - 1] = add_vertex(to_point(triangulation.Node(node).Transformed(transform)));
    }
    return chain;
  }

  void add_face(int f) {
    const TopoDS_Face face = TopoDS::Face(faces_(f).Oriented(TopAbs_FORWARD));
    TopLoc_Location location;
    Handle(Poly_Triangulation) triangulation = BRep_Tool::Triangulation(face, location);
    if (triangulation.IsNull())
      throw InputError(ErrorCode::Parse, "OpenCASCADE could not tessellate Face" + std::to_string(f), file_);
    const gp_Trsf& transform = location.Transformation();
    std::vector<Index> node_ids(triangulation->NbNodes() + 1, kNoIndex);
    const bool reversed_face = face_reversed_[f];
    const int marker = f;

    // Boundary nodes of the face's triangulation -> the shared vertex chains of its edges.
    double max_edge_tolerance = 0;
    for (TopExp_Explorer it(face, TopAbs_EDGE); it.More(); it.Next()) {
      const TopoDS_Edge edge = TopoDS::Edge(it.Current());
      max_edge_tolerance = std::max(max_edge_tolerance, BRep_Tool::Tolerance(edge));
      Handle(Poly_PolygonOnTriangulation) polygon = BRep_Tool::PolygonOnTriangulation(edge, triangulation, location);
      if (polygon.IsNull())
        throw InputError(ErrorCode::Parse,
                         "OpenCASCADE left Edge" + std::to_string(edges_.FindIndex(edge)) + " of Face" +
                             std::to_string(f) + " without a discretisation",
                         file_);
      const std::vector<Index>& chain = edge_chain(edge, *polygon, *triangulation, location);
      const int n = polygon->NbNodes();
      if (static_cast<int>(chain.size()) != n)
        throw InputError(ErrorCode::Parse,
                         "Edge" + std::to_string(edges_.FindIndex(edge)) + " is discretised differently in Face" +
                             std::to_string(f) + " than in another face",
                         file_);
      // Match orientation of this polygon with the chain by the first node's position.
      gp_Pnt start = triangulation->Node(polygon->Node(1)).Transformed(transform);
      const Point3 s = to_point(start);
      bool reversed = distance(s, model_.plc.vertices[chain.front()]) > distance(s, model_.plc.vertices[chain.back()]);
      for (int i = 1; i <= n; ++i) node_ids[polygon->Node(i)] = chain[reversed ? n - i : i - 1];
    }
    // BRepMesh controls the deflection at sample points (edge and triangle midpoints), not everywhere; 2x is the
    // bound we claim (measured: up to 1.09x on the B-spline faces of wrenchnut.stp).
    model_.summary.face_tolerances.push_back(2 * model_.summary.deflection_used + max_edge_tolerance +
                                             BRep_Tool::Tolerance(face));

    BRepAdaptor_Surface surface(face, Standard_False);
    if (surface.GetType() == GeomAbs_Plane && add_planar_face(face, f)) {
      // The polygon's region, for the seed search: BRepMesh's triangles, on the chain points at the boundary.
      for (int t = 1; t <= triangulation->NbTriangles(); ++t) {
        std::array<int, 3> corners;
        triangulation->Triangle(t).Get(corners[0], corners[1], corners[2]);
        SeedTriangle& seed_triangle = face_triangles_[f].emplace_back();
        for (int k = 0; k < 3; ++k)
          seed_triangle[k] = node_ids[corners[k]] != kNoIndex
                                 ? model_.plc.vertices[node_ids[corners[k]]]
                                 : to_point(triangulation->Node(corners[k]).Transformed(transform));
      }
      return;
    }

    for (int i = 1; i <= triangulation->NbNodes(); ++i)
      if (node_ids[i] == kNoIndex) node_ids[i] = add_vertex(to_point(triangulation->Node(i).Transformed(transform)));
    std::vector<SurfaceTriangle> triangles;
    for (int t = 1; t <= triangulation->NbTriangles(); ++t) {
      int a, b, c;
      triangulation->Triangle(t).Get(a, b, c);
      Index ia = node_ids[a], ib = node_ids[b], ic = node_ids[c];
      if (ia == ib || ib == ic || ia == ic) continue;  // collapsed on a degenerate edge
      triangles.push_back(reversed_face ? SurfaceTriangle{ia, ic, ib} : SurfaceTriangle{ia, ib, ic});
    }
    remove_flat_triangles(triangles, model_.plc.vertices, kPlanarityTolerance * diagonal_);
    remove_mirrored_pairs(triangles);
    for (const SurfaceTriangle& t : triangles) {
      const std::vector<Point3>& v = model_.plc.vertices;
      face_triangles_[f].push_back({v[t[0]], v[t[1]], v[t[2]]});
      Facet facet;
      facet.polygons.push_back({t[0], t[1], t[2]});
      facet.marker = marker;
      model_.plc.facets.push_back(std::move(facet));
    }
  }

  // A planar face as one facet: each wire is a polygon (the vertex chains of its edges, in wire order). Returns
  // false (and adds nothing) when a wire does not close, so that the caller falls back to the triangles.
  bool add_planar_face(const TopoDS_Face& face, int f) {
    Facet facet;
    facet.marker = f;
    TopLoc_Location location;
    Handle(Poly_Triangulation) triangulation = BRep_Tool::Triangulation(face, location);
    const TopoDS_Wire outer_wire = BRepTools::OuterWire(face);
    gp_Vec outward(BRepAdaptor_Surface(face, Standard_False).Plane().Axis().Direction());
    if (face_reversed_[f]) outward.Reverse();
    for (TopExp_Explorer wires(face, TopAbs_WIRE); wires.More(); wires.Next()) {
      std::vector<Index> loop;
      for (BRepTools_WireExplorer it(TopoDS::Wire(wires.Current()), face); it.More(); it.Next()) {
        const TopoDS_Edge& edge = it.Current();
        if (BRep_Tool::Degenerated(edge)) continue;
        const std::vector<Index>& chain = edge_chains_[edges_.FindIndex(edge)];
        if (chain.empty()) return false;
        const bool reversed = it.Orientation() == TopAbs_REVERSED;
        for (std::size_t i = 0; i < chain.size(); ++i) {
          Index v = reversed ? chain[chain.size() - 1 - i] : chain[i];
          if (loop.empty() || loop.back() != v) loop.push_back(v);
        }
      }
      if (loop.size() > 1 && loop.front() == loop.back()) loop.pop_back();
      if (loop.size() < 3) return false;
      // A wire that does not close, or visits a vertex twice, is not a simple polygon.
      std::vector<Index> sorted = loop;
      std::sort(sorted.begin(), sorted.end());
      if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end()) return false;
      // Orientation by geometry, not by the wire explorer's bookkeeping: the outer wire turns counter-clockwise
      // about the face's outward normal (the plane normal, flipped for a face reversed in its first solid), every
      // inner wire clockwise.
      const gp_Vec loop_normal = newell_normal(loop);
      const bool outer = wires.Current().IsSame(outer_wire);
      if ((loop_normal.Dot(outward) < 0) == outer) std::reverse(loop.begin(), loop.end());
      facet.polygons.push_back(std::move(loop));
    }
    if (facet.polygons.empty()) return false;
    // A plane face whose edges stray from its plane (vertex tolerances of 1e-2 occur in STEP files) is not a planar
    // polygon; its triangles are used instead, each planar by construction.
    const gp_Vec normal = newell_normal(facet.polygons.front());
    if (normal.Magnitude() <= 0) return false;
    const gp_Dir axis(normal);
    const Point3& origin = model_.plc.vertices[facet.polygons.front().front()];
    double centre = 0;
    std::size_t count = 0;
    for (const auto& loop : facet.polygons)
      for (Index v : loop) {
        const Point3& p = model_.plc.vertices[v];
        centre += (p[0] - origin[0]) * axis.X() + (p[1] - origin[1]) * axis.Y() + (p[2] - origin[2]) * axis.Z();
        ++count;
      }
    centre /= static_cast<double>(count);
    for (const auto& loop : facet.polygons)
      for (Index v : loop) {
        const Point3& p = model_.plc.vertices[v];
        double h = (p[0] - origin[0]) * axis.X() + (p[1] - origin[1]) * axis.Y() + (p[2] - origin[2]) * axis.Z();
        if (std::fabs(h - centre) > kPolygonPlanarityTolerance * diagonal_) return false;
      }
    model_.plc.facets.push_back(std::move(facet));
    return true;
  }

  // The interior nodes of a planar face's mesh (ids from boundary_end on: neither CAD vertex nor edge chain node)
  // as isolated vertices of its facet (1-vertex loops, plc.h), in id order. They are points of the plane up to
  // rounding, which the polygon test above allows for.
  static void add_interior_nodes(const std::vector<SurfaceTriangle>& triangles, std::size_t boundary_end,
                                 Facet& facet) {
    std::vector<Index> inner;
    for (const SurfaceTriangle& t : triangles)
      for (Index v : t)
        if (v >= boundary_end) inner.push_back(v);
    std::sort(inner.begin(), inner.end());
    inner.erase(std::unique(inner.begin(), inner.end()), inner.end());
    for (Index v : inner) facet.polygons.push_back({v});
  }

  // Twice the vector area of a closed polygon (Newell's method); its direction is the polygon's normal.
  gp_Vec newell_normal(const std::vector<Index>& loop) const {
    gp_Vec normal(0, 0, 0);
    for (std::size_t i = 0; i < loop.size(); ++i) {
      const Point3& p = model_.plc.vertices[loop[i]];
      const Point3& q = model_.plc.vertices[loop[(i + 1) % loop.size()]];
      normal += gp_Vec((p[1] - q[1]) * (p[2] + q[2]), (p[2] - q[2]) * (p[0] + q[0]), (p[0] - q[0]) * (p[1] + q[1]));
    }
    return normal;
  }

  void add_segments() {
    for (int e = 1; e <= edges_.Extent(); ++e) {
      const std::vector<Index>& chain = edge_chains_[e];
      if (BRep_Tool::Degenerated(TopoDS::Edge(edges_(e)))) continue;
      for (std::size_t i = 0; i + 1 < chain.size(); ++i)
        if (chain[i] != chain[i + 1]) model_.plc.segments.push_back({chain[i], chain[i + 1], e});
    }
  }

  // A seed strictly inside the PLC surface of each solid (region_seed.cpp): its faces' triangles.
  void add_regions() {
    for (int s = 1; s <= solids_.Extent(); ++s) {
      std::vector<SeedTriangle> surface;
      std::set<int> seen;
      for (TopExp_Explorer it(solids_(s), TopAbs_FACE); it.More(); it.Next()) {
        const int f = faces_.FindIndex(it.Current());
        if (seen.insert(f).second) surface.insert(surface.end(), face_triangles_[f].begin(), face_triangles_[f].end());
      }
      const std::optional<Point3> seed = region_seed(surface, diagonal_);
      if (!seed)
        throw InputError(ErrorCode::DegenerateFacet,
                         "found no point strictly inside Solid" + std::to_string(s) +
                             " (its faces' triangles do not close, or no ray from them found the inside)",
                         file_);
      model_.plc.regions.push_back({*seed, s, 0});
    }
  }

  const TopoDS_Shape shape_;
  const CadOptions& options_;
  const std::string file_;
  TopTools_IndexedMapOfShape solids_, faces_, edges_, vertices_;
  std::vector<bool> face_reversed_;               // by face number: REVERSED in its first solid
  std::vector<Index> vertex_ids_;                 // by CAD vertex number
  std::vector<std::vector<Index>> edge_chains_;   // by CAD edge number
  std::vector<std::vector<double>> edge_params_;  // Sized: curve parameters of the chain's points, by edge number
  std::vector<double> edge_spacing_;              // Sized: length / pieces of each edge as first discretised
  EdgeChain scratch_chain_;                       // Sized: the chain handed to the face mesher
  std::vector<std::vector<SeedTriangle>> face_triangles_;  // by face number: its PLC triangles, for add_regions
  double diagonal_ = 0;
  CadModel model_;
};

}  // namespace

std::vector<double> face_node_tolerances(const TopoDS_Shape& solids) {
  TopTools_IndexedMapOfShape faces;
  TopExp::MapShapes(solids, TopAbs_FACE, faces);
  std::vector<double> out;
  for (int f = 1; f <= faces.Extent(); ++f) out.push_back(node_tolerance(TopoDS::Face(faces(f))));
  return out;
}

std::vector<double> solid_volumes(const TopoDS_Shape& solids) {
  TopTools_IndexedMapOfShape map;
  TopExp::MapShapes(solids, TopAbs_SOLID, map);
  std::vector<double> out;
  for (int s = 1; s <= map.Extent(); ++s) out.push_back(volume_of(map(s)));
  return out;
}

CadModel convert_solids_to_plc(const TopoDS_Shape& solids, const CadOptions& options, const std::string& file) {
  try {
    return PlcBuilder(solids, options, file).convert();
  } catch (const Standard_Failure& failure) {
    throw InputError(ErrorCode::Parse,
                     std::string("OpenCASCADE failed while tessellating the model: ") + failure.GetMessageString(),
                     file);
  }
}

}  // namespace qualmesh::cad
