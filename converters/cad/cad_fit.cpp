// Fitting a mesh to its CAD model (cad_import.h, fit_mesh_to_cad): the boundary nodes the mesher placed on the
// chords of a curved face's tessellation (Rules 1 and 2 split subsegments and subfacets of the PLC, which is flat),
// and the mid nodes of second-order elements, are moved onto the CAD surface itself, so that FreeCAD's geometric
// node search (shared/docs/FREECAD.md: distance to the face within its BRep tolerance, ~1e-7) finds every one of
// them and the mesh volume converges to the CAD volume.
//
// Projection: ShapeAnalysis_Surface::ValueOfUV (robust on periodic and singular surfaces) for faces, after a Newton
// step from an earlier projection nearby for a point already on the surface (Projector::FaceData::project),
// ShapeAnalysis_Curve::Project within the edge's parameter range for edges, and on a free-form curve
// GeomAPI_ProjectPointOnCurve's global search as well. A node within the chordal deflection of its face moves at
// most about that far, but a move is always checked against the elements around the node (move_nodes_checked,
// second_order.h): relaxed part of the way, or not made, rather than inverting an element.
#include <BRepBndLib.hxx>
#include <BRepBuilderAPI_MakeVertex.hxx>
#include <BRepClass_FaceClassifier.hxx>
#include <BRepExtrema_DistShapeShape.hxx>
#include <BRep_Tool.hxx>
#include <Bnd_Box.hxx>
#include <GeomAPI_ProjectPointOnCurve.hxx>
#include <GeomAdaptor_Curve.hxx>
#include <GeomAdaptor_Surface.hxx>
#include <Geom_Curve.hxx>
#include <Geom_Surface.hxx>
#include <ShapeAnalysis_Curve.hxx>
#include <ShapeAnalysis_Surface.hxx>
#include <Standard_Failure.hxx>
#include <TopExp.hxx>
#include <TopTools_IndexedDataMapOfShapeListOfShape.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopTools_ListOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Face.hxx>
#include <gp_Pnt2d.hxx>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <unordered_map>
#include <vector>

#include "cad_private.h"
#include "qualmesh/cad_import.h"
#include "qualmesh/error.h"

namespace qualmesh {
namespace {

constexpr int kNone = 0;
constexpr int kSeveral = -1;
// Rounds of boundary-cap removal for the mid nodes (fit_mesh_to_cad).
constexpr int kMaxCapRounds = 6;

// The one CAD entity (marker > 0) a node lies on, kNone, or kSeveral.
void note(std::vector<int>& on, Index node, int marker) {
  if (marker <= 0) return;
  int& slot = on[node];
  if (slot == kNone) slot = marker;
  else if (slot != marker) slot = kSeveral;
}

// Projects points onto the faces and edges of one healed shape. Planar faces are included: a plane face whose
// edges stray from its plane is meshed from its triangles (brep_to_plc.cpp), whose Steiner points are then off the
// CAD plane; a node already on the plane projects onto itself and is not moved (targets()).
class Projector {
 public:
  explicit Projector(const TopoDS_Shape& solids) {
    TopExp::MapShapes(solids, TopAbs_FACE, faces_);
    TopExp::MapShapes(solids, TopAbs_EDGE, edges_);
    TopExp::MapShapesAndAncestors(solids, TopAbs_EDGE, TopAbs_FACE, edge_faces_);
  }

  // Whether FreeCAD's geometric node search can find a node at p on CAD face f / edge e (on each face of the
  // edge): FemMesh::getNodesByFace (0.20) looks only inside BRepBndLib::Add(face, box, false) enlarged by the face's
  // tolerance, and that box can be tighter than the surface (part.step's Face23 bulges 0.003 mm out of it).
  bool face_findable(int f, const Point3& p) {
    const FaceData* data = face(f);
    return !data || !data->search_box.IsOut(gp_Pnt(p[0], p[1], p[2]));
  }
  bool edge_findable(int e, const Point3& p) {
    if (e < 1 || e > edge_faces_.Extent()) return true;
    for (const TopoDS_Shape& f : edge_faces_.FindFromIndex(e))
      if (!face_findable(faces_.FindIndex(f), p)) return false;
    return true;
  }

  // Whether CAD face f / edge e is curved (a plane or a line needs no projection of points on its facets).
  bool face_curved(int f) {
    const FaceData* data = face(f);
    return data && !data->planar;
  }
  bool edge_curved(int e) {
    const EdgeData* data = edge(e);
    return data && !data->straight;
  }

  // Target of a point on CAD face f; false when there is none to go to.
  bool onto_face(int f, const Point3& p, Point3& target) {
    FaceData* data = face(f);
    if (!data) return false;
    const gp_Pnt local = gp_Pnt(p[0], p[1], p[2]).Transformed(data->to_local);
    const gp_Pnt q = data->project(local).Transformed(data->to_global);
    target = {q.X(), q.Y(), q.Z()};
    return true;
  }

  // A point inside the trimmed CAD face f for `target`, a point of its surface: `target` itself where it lies in the
  // face (BRepClass_FaceClassifier, to the face's tolerance), else its mirror image across the face's boundary
  // (through the nearest boundary point, BRepExtrema), projected onto the surface, or one a quarter as far inside;
  // the boundary point itself only when neither is inside. The chord between two points of a face's boundary can
  // leave the face where that boundary bends into it, and so can its midpoint's projection onto the surface:
  // part.step's planar Face20 at --size 10 had a mid node 0.0155 outside its B-spline edge, where FreeCAD's node
  // search did not find it (with the 30-degree corner bound tried on CAD inputs; refine_params.h). A node on the boundary itself would be found on the edge and the neighbouring face too.
  // Planar faces only: on a periodic face that winds more than once around its axis the classifier misjudges points
  // inside it as outside (bottle.brep's thread: 204 mid nodes were sent to mirror images and relaxed part way, and
  // the curving took twice as long), as BRepExtrema does (face_distance.cpp).
  void into_trimmed_face(int f, Point3& target) {
    const FaceData* data = face(f);
    if (!data || !data->planar) return;
    const TopoDS_Face& face = TopoDS::Face(faces_(f));
    const double tolerance = BRep_Tool::Tolerance(face);
    const auto inside = [&](const Point3& x) {
      return BRepClass_FaceClassifier(face, gp_Pnt(x[0], x[1], x[2]), tolerance).State() == TopAbs_IN;
    };
    const gp_Pnt p(target[0], target[1], target[2]);
    if (BRepClass_FaceClassifier(face, p, tolerance).State() != TopAbs_OUT) return;
    BRepExtrema_DistShapeShape nearest(face, BRepBuilderAPI_MakeVertex(p).Vertex());
    if (!nearest.IsDone() || nearest.NbSolution() < 1) return;
    const gp_Pnt q = nearest.PointOnShape1(1);
    for (double beyond : {1.0, 0.25}) {
      const Point3 mirror{q.X() + beyond * (q.X() - p.X()), q.Y() + beyond * (q.Y() - p.Y()),
                          q.Z() + beyond * (q.Z() - p.Z())};
      Point3 on{};
      if (onto_face(f, mirror, on) && inside(on)) {
        target = on;
        return;
      }
    }
    target = {q.X(), q.Y(), q.Z()};
  }

  bool onto_edge(int e, const Point3& p, Point3& target) {
    EdgeData* data = edge(e);
    if (!data) return false;
    const gp_Pnt local = gp_Pnt(p[0], p[1], p[2]).Transformed(data->to_local);
    gp_Pnt projected;
    double parameter = 0;
    ShapeAnalysis_Curve().Project(data->curve, local, data->precision, projected, parameter, data->first,
                                  data->last);
    // ShapeAnalysis_Curve::Project can stop at a local minimum of a free-form curve: on bottle.brep's thread, Edge10
    // (a B-spline of degree 12 over two turns of a helix), it answered 1.25 away, a turn off, where the curve
    // passes 0.0016 from the point. Extrema's global search (GeomAPI_ProjectPointOnCurve) finds the interior
    // extrema; the nearer answer wins (an end of the range, where there is no extremum, is ShapeAnalysis's).
    if (data->free_form) {
      GeomAPI_ProjectPointOnCurve global(local, data->curve, data->first, data->last);
      if (global.NbPoints() > 0 && global.LowerDistance() < projected.Distance(local))
        projected = global.NearestPoint();
    }
    const gp_Pnt q = projected.Transformed(data->to_global);
    target = {q.X(), q.Y(), q.Z()};
    return true;
  }

 private:
  // On a B-spline, extrusion, revolution or offset surface ValueOfUV searches a grid over the whole surface
  // (Extrema_GenExtPS): wrenchnut.stp spent 19% of its run there, mostly on nodes already on the surface (the fit
  // checks every boundary node; the mesher projects a point again). So each face keeps the projections it made,
  // hashed by a grid of cells (32 across the face), and starts Newton's method (NextValueOfUV) from the parameters
  // of the nearest one in p's cell or a neighbour; where that does not land on p (local_projection), ValueOfUV's
  // global search answers as before. Analytic surfaces project in closed form either way.
  struct UvSample {
    gp_Pnt point;  // on the surface, in the surface's frame
    gp_Pnt2d uv;
  };
  struct FaceData {
    std::unique_ptr<ShapeAnalysis_Surface> analysis;
    gp_Trsf to_local, to_global;
    double precision = 1e-9;
    bool planar = false;
    Bnd_Box search_box;  // face_findable
    double cell = 0;     // edge of the sample grid's cells (0: no samples kept)
    std::unordered_map<std::uint64_t, std::vector<UvSample>> samples;

    std::array<std::int64_t, 3> cell_of(const gp_Pnt& p) const {
      return {std::int64_t(std::floor(p.X() / cell)), std::int64_t(std::floor(p.Y() / cell)),
              std::int64_t(std::floor(p.Z() / cell))};
    }
    static std::uint64_t key_of(const std::array<std::int64_t, 3>& c) {
      return (std::uint64_t(c[0]) * 73856093u) ^ (std::uint64_t(c[1]) * 19349663u) ^ (std::uint64_t(c[2]) * 83492791u);
    }

    // Newton's method from `hint` (NextValueOfUV): true when it lands within `precision` of p, so that p is on the
    // surface to that precision and the answer is its nearest point whatever else the surface does. Elsewhere Newton
    // may stop at a local extremum, which no local test tells apart: on bottle.brep's B-spline faces it stopped 0.006
    // and 1.25 from p, along the surface normal, where ValueOfUV found the surface 1e-4 away. `sample` gets the
    // answer, its point evaluated once.
    bool local_projection(const gp_Pnt2d& hint, double hint_distance, const gp_Pnt& p, UvSample& sample) {
      sample.uv = analysis->NextValueOfUV(hint, p, precision, hint_distance + precision);
      sample.point = analysis->Value(sample.uv);
      return sample.point.Distance(p) <= precision;
    }

    // The point of the surface nearest to p (both in the surface's frame).
    gp_Pnt project(const gp_Pnt& p) {
      if (cell <= 0) return analysis->Value(analysis->ValueOfUV(p, precision));
      const std::array<std::int64_t, 3> c = cell_of(p);
      const UvSample* nearest = nullptr;
      double best = std::numeric_limits<double>::infinity();
      for (std::int64_t dx = -1; dx <= 1; ++dx)
        for (std::int64_t dy = -1; dy <= 1; ++dy)
          for (std::int64_t dz = -1; dz <= 1; ++dz) {
            auto it = samples.find(key_of({c[0] + dx, c[1] + dy, c[2] + dz}));
            if (it == samples.end()) continue;
            for (const UvSample& sample : it->second) {
              const double d = sample.point.SquareDistance(p);
              if (d < best) best = d, nearest = &sample;
            }
          }
      UvSample found;
      if (!nearest || !local_projection(nearest->uv, std::sqrt(best), p, found)) {
        found.uv = analysis->ValueOfUV(p, precision);
        found.point = analysis->Value(found.uv);
      }
      std::vector<UvSample>& bucket = samples[key_of(c)];
      if (bucket.size() < kSamplesPerCell) bucket.push_back(found);
      return found.point;
    }
  };
  static constexpr std::size_t kSamplesPerCell = 8;
  struct EdgeData {
    Handle(Geom_Curve) curve;
    double first = 0, last = 0;
    gp_Trsf to_local, to_global;
    double precision = 1e-9;
    bool straight = false;
    bool free_form = false;  // not a line, circle, ellipse, hyperbola or parabola (onto_edge)
  };

  FaceData* face(int f) {
    if (f < 1 || f > faces_.Extent()) return nullptr;
    auto it = face_data_.find(f);
    if (it == face_data_.end()) {
      std::unique_ptr<FaceData> data;
      const TopoDS_Face face = TopoDS::Face(faces_(f));
      {
        TopLoc_Location location;
        Handle(Geom_Surface) surface = BRep_Tool::Surface(face, location);
        if (!surface.IsNull()) {
          data = std::make_unique<FaceData>();
          data->analysis = std::make_unique<ShapeAnalysis_Surface>(surface);
          data->to_global = location.Transformation();
          data->to_local = location.Transformation().Inverted();
          data->precision = std::max(1e-12, 1e-3 * BRep_Tool::Tolerance(face));
          const GeomAbs_SurfaceType type = GeomAdaptor_Surface(surface).GetType();
          data->planar = type == GeomAbs_Plane;
          BRepBndLib::Add(face, data->search_box, Standard_False);
          data->search_box.Enlarge(BRep_Tool::Tolerance(face));
          if (!data->search_box.IsVoid() && (type == GeomAbs_BSplineSurface || type == GeomAbs_BezierSurface ||
                                             type == GeomAbs_SurfaceOfExtrusion ||
                                             type == GeomAbs_SurfaceOfRevolution || type == GeomAbs_OffsetSurface))
            data->cell = std::sqrt(data->search_box.SquareExtent()) / 32;
        }
      }
      it = face_data_.emplace(f, std::move(data)).first;
    }
    return it->second.get();
  }

  EdgeData* edge(int e) {
    if (e < 1 || e > edges_.Extent()) return nullptr;
    auto it = edge_data_.find(e);
    if (it == edge_data_.end()) {
      std::unique_ptr<EdgeData> data;
      const TopoDS_Edge edge = TopoDS::Edge(edges_(e));
      if (!BRep_Tool::Degenerated(edge)) {
        TopLoc_Location location;
        double first = 0, last = 0;
        Handle(Geom_Curve) curve = BRep_Tool::Curve(edge, location, first, last);
        if (!curve.IsNull()) {
          data = std::make_unique<EdgeData>();
          data->curve = curve;
          data->first = first;
          data->last = last;
          data->to_global = location.Transformation();
          data->to_local = location.Transformation().Inverted();
          data->precision = std::max(1e-12, 1e-3 * BRep_Tool::Tolerance(edge));
          const GeomAbs_CurveType type = GeomAdaptor_Curve(curve).GetType();
          data->straight = type == GeomAbs_Line;
          data->free_form = type != GeomAbs_Line && type != GeomAbs_Circle && type != GeomAbs_Ellipse &&
                            type != GeomAbs_Hyperbola && type != GeomAbs_Parabola;
        }
      }
      it = edge_data_.emplace(e, std::move(data)).first;
    }
    return it->second.get();
  }

  TopTools_IndexedMapOfShape faces_, edges_;
  TopTools_IndexedDataMapOfShapeListOfShape edge_faces_;
  std::map<int, std::unique_ptr<FaceData>> face_data_;
  std::map<int, std::unique_ptr<EdgeData>> edge_data_;
};

double distance(const Point3& a, const Point3& b) {
  return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
}

// Where along its edge a mid node may go instead (NodeMove::alternatives): the projections of these points of the
// chord. A 10-node element needs its mid node on the surface, not at the projection of the chord's midpoint, and a
// point nearer one end unfolds the curved face of a thin triangle whose midpoint projection folds it.
constexpr double kAlongEdge[] = {0.4, 0.6, 0.3, 0.7};

// Targets for the nodes listed in on_edge / on_face (by node index): an edge wins over a face; a node on several
// edges (a CAD vertex) or several faces and no edge stays. A node on a face for which `trimmed(node)` holds gets
// a point inside the trimmed face (Projector::into_trimmed_face).
std::vector<NodeMove> targets(Projector& projector, const TetMesh& mesh, const std::vector<int>& on_edge,
                              const std::vector<int>& on_face, Index first_node, std::size_t& num_fixed,
                              double* max_offset, const std::function<bool(Index)>& trimmed = {}) {
  BoundingBox box;
  for (const Point3& p : mesh.points) box.add(p);
  const double still = box.empty() ? 0 : 1e-12 * distance(box.min, box.max);
  std::vector<NodeMove> moves;
  for (Index v = first_node; v < on_edge.size(); ++v) {
    Point3 target{};
    bool found = false;
    if (on_edge[v] == kSeveral) {
      ++num_fixed;
      continue;
    }
    if (on_edge[v] > 0) found = projector.onto_edge(on_edge[v], mesh.points[v], target);
    else if (on_face[v] > 0) found = projector.onto_face(on_face[v], mesh.points[v], target);
    if (!found) continue;
    if (on_edge[v] <= 0 && trimmed && trimmed(v)) projector.into_trimmed_face(on_face[v], target);
    if (distance(target, mesh.points[v]) <= still) continue;  // on it already (to rounding): stays exact
    if (max_offset) *max_offset = std::max(*max_offset, distance(target, mesh.points[v]));
    moves.push_back({v, target, {}});
  }
  return moves;
}

// Mid node `move.node` of the edge a-b, on CAD edge `edge` (> 0) or else face `face`: its move with the places
// along the edge as alternatives (in the trimmed face when `trimmed`), and a target FreeCAD's node search cannot see
// put after those it can.
NodeMove along_edge(Projector& projector, NodeMove move, const Point3& a, const Point3& b, int edge, int face,
                    bool trimmed) {
  for (double t : kAlongEdge) {
    const Point3 p{a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]), a[2] + t * (b[2] - a[2])};
    Point3 q{};
    if (!(edge > 0 ? projector.onto_edge(edge, p, q) : projector.onto_face(face, p, q))) continue;
    if (edge <= 0 && trimmed) projector.into_trimmed_face(face, q);
    move.alternatives.push_back(q);
  }
  const auto findable = [&](const Point3& q) {
    return edge > 0 ? projector.edge_findable(edge, q) : projector.face_findable(face, q);
  };
  if (findable(move.target)) return move;
  std::vector<Point3> all{move.target};
  all.insert(all.end(), move.alternatives.begin(), move.alternatives.end());
  std::stable_partition(all.begin(), all.end(), findable);
  move.target = all.front();
  move.alternatives.assign(all.begin() + 1, all.end());
  return move;
}

// Moves the boundary corner nodes from `first` on onto the CAD face or edge they lie on (fit_mesh_to_cad); counts
// the nodes on several CAD edges into num_fixed, and reports the largest offset and the number of targets when asked.
NodeMoveReport fit_corner_nodes(Projector& projector, TetMesh& mesh, Index first, const NodeMoveOptions& options,
                                std::size_t& num_fixed, double* max_offset, std::size_t* num_targets) {
  const std::vector<int> labels = face_labels(mesh);
  std::vector<int> on_edge(mesh.points.size(), kNone), on_face(mesh.points.size(), kNone);
  for (std::size_t e = 0; e < mesh.edges.size(); ++e)
    for (Index v : mesh.edges[e]) note(on_edge, v, mesh.edge_marker[e]);
  for (std::size_t f = 0; f < mesh.faces.size(); ++f)
    for (Index v : mesh.faces[f]) note(on_face, v, labels[f]);
  const std::vector<NodeMove> moves = targets(projector, mesh, on_edge, on_face, first, num_fixed, max_offset);
  if (num_targets) *num_targets = moves.size();
  return move_nodes_checked(mesh, moves, options);
}

}  // namespace

bool project_onto_cad(const std::string& path, const CadOptions& options, int edge, int face, Point3& p) {
  // One projector, for the model last asked about (the mesher asks about one model, point after point).
  static std::string cached_path;
  static std::unique_ptr<Projector> cached;
  if (!cached || cached_path != path) {
    std::vector<std::string> log;
    cached = std::make_unique<Projector>(cad::read_healed_solids(path, options, log, /*use_cache=*/true));
    cached_path = path;
  }
  Point3 target{};
  try {
    if (edge > 0) {
      if (!cached->edge_curved(edge) || !cached->onto_edge(edge, p, target)) return false;
    } else if (face > 0) {
      if (!cached->face_curved(face) || !cached->onto_face(face, p, target)) return false;
    } else {
      return false;
    }
  } catch (const Standard_Failure&) {
    return false;
  }
  if (!std::isfinite(target[0]) || !std::isfinite(target[1]) || !std::isfinite(target[2])) return false;
  p = target;
  return true;
}

CadFitReport fit_mesh_to_cad(const std::string& path, const CadOptions& options, TetMesh& mesh,
                             const CadFitOptions& fit_options) {
  CadFitReport report;
  if (cad::lower_extension(path) == ".scad") {
    if (fit_options.second_order) make_second_order(mesh);
    return report;  // the rendered surface is the model: nothing to fit to
  }
  std::vector<std::string> log;
  const TopoDS_Shape solids = cad::read_healed_solids(path, options, log, /*use_cache=*/true);
  try {
    Projector projector(solids);
    // Corner nodes.
    report.corners = fit_corner_nodes(projector, mesh, 0, fit_options.moves, report.num_fixed_vertices,
                                      &report.max_offset_before, &report.num_corner_targets);
    report.num_flat_caps_removed = remove_flat_boundary_tets(mesh);
    if (!fit_options.second_order) return report;
    // Mid nodes. A boundary cap (a tetrahedron with two boundary faces) has corners whose edges all lie on the
    // boundary: where the surface bends towards the cap no interior node can keep its Jacobian positive, and every
    // mid node it blocks would be left part way. Such caps are removed from the linear mesh when both faces are on
    // one CAD face (its boundary diagonal flips, the volume changes by the cap's), and the mid nodes are placed
    // again, for a few rounds. Caps across a CAD edge cannot be removed: their interior edge is split instead
    // (split_cap_interior_edges), which the search of interior positions makes pay off (wrenchnut, model1).
    // A last round, when caps are all that could be removed and some mid nodes still fall short, asks the elements
    // only for NodeMoveOptions::last_resort_jacobian_ratio.
    NodeMoveOptions strict = fit_options.moves;
    strict.last_resort_jacobian_ratio = 0;
    bool last = false;
    TetMesh linear;  // the linear mesh the rounds start from (make_second_order keeps the tets' order)
    for (int round = 0;; ++round) {
      if (round > 0) mesh = linear;
      else linear = mesh;
      const Index first_mid = static_cast<Index>(mesh.points.size());
      make_second_order(mesh);
      const std::vector<int> mid_labels = face_labels(mesh);  // the faces changed: flat caps were removed
      std::vector<int> on_edge(mesh.points.size(), kNone), on_face(mesh.points.size(), kNone);
      for (std::size_t e = 0; e < mesh.edges.size(); ++e) note(on_edge, mesh.edge_mid[e], mesh.edge_marker[e]);
      for (std::size_t f = 0; f < mesh.faces.size(); ++f)
        for (Index v : mesh.face_mid[f]) note(on_face, v, mid_labels[f]);
      std::vector<std::array<Index, 2>> ends(mesh.points.size() - first_mid);
      for (std::size_t t = 0; t < mesh.tets.size(); ++t)
        for (int k = 0; k < 6; ++k)
          ends[mesh.tet_mid[t][k] - first_mid] = {mesh.tets[t][kTetEdges[k][0]], mesh.tets[t][kTetEdges[k][1]]};
      // A mid node of an edge across a face, between two nodes on CAD edges, gets a target inside the trimmed face
      // (a thin part of the face, or one whose boundary bends into it); elsewhere the projection is inside already.
      std::vector<std::uint8_t> on_cad_edge(first_mid, 0);
      for (const auto& e : mesh.edges) on_cad_edge[e[0]] = on_cad_edge[e[1]] = 1;
      const auto trimmed = [&](Index v) {
        const auto& e = ends[v - first_mid];
        return on_edge[v] <= 0 && on_cad_edge[e[0]] && on_cad_edge[e[1]];
      };
      std::size_t unused = 0;
      const std::vector<NodeMove> moves =
          targets(projector, mesh, on_edge, on_face, first_mid, unused, nullptr, trimmed);
      report.num_mid_targets = moves.size();
      // The places along a node's edge are projected only when its target fails (OpenCASCADE's projection is most
      // of the curving's time); a target FreeCAD's node search cannot see gets them at once, and goes after them.
      const auto along = [&](const NodeMove& m) {
        const auto& e = ends[m.node - first_mid];
        return along_edge(projector, m, mesh.points[e[0]], mesh.points[e[1]], on_edge[m.node], on_face[m.node],
                          trimmed(m.node));
      };
      std::vector<NodeMove> placed;
      for (const NodeMove& m : moves) {
        const bool seen = on_edge[m.node] > 0 ? projector.edge_findable(on_edge[m.node], m.target)
                                              : projector.face_findable(on_face[m.node], m.target);
        placed.push_back(seen ? m : along(m));
      }
      report.mids = move_nodes_checked(mesh, placed, last ? fit_options.moves : strict,
                                       [&](const NodeMove& m) { return along(m).alternatives; });
      if (report.mids.num_full == report.mids.num_requested || last) break;
      const std::vector<std::size_t>& blocking = report.mids.blocking_elements;
      const auto blocked = [&](std::size_t t) { return std::binary_search(blocking.begin(), blocking.end(), t); };
      // Boundary triangles with a corner that the curve makes flat have their opposite edge split, and the new
      // vertex goes onto its face; caps across a CAD edge cannot be removed: their interior edge is split, so that
      // its new vertex can move (both first: the splits keep the indices of the tetrahedra `blocking` names).
      const Index first_new = static_cast<Index>(linear.points.size());
      const std::size_t flat = round == kMaxCapRounds ? 0 : split_flat_face_corners(linear, blocked);
      if (flat > 0) {
        std::size_t fixed = 0;
        fit_corner_nodes(projector, linear, first_new, fit_options.moves, fixed, nullptr, nullptr);
      }
      const std::size_t split = round == kMaxCapRounds ? 0 : split_cap_interior_edges(linear, blocked);
      const std::size_t removed = round == kMaxCapRounds ? 0 : remove_boundary_caps(linear, blocked);
      report.num_flat_corners_split += flat;
      report.num_cap_edges_split += split;
      report.num_curving_caps_removed += removed;
      if (removed == 0 && split == 0 && flat == 0) {
        if (fit_options.moves.last_resort_jacobian_ratio <= 0) break;
        last = true;
      }
    }
  } catch (const Standard_Failure& failure) {
    throw InputError(ErrorCode::Parse,
                     std::string("OpenCASCADE failed projecting nodes onto the model: ") + failure.GetMessageString(),
                     path);
  }
  return report;
}

}  // namespace qualmesh
