// Independent check of a mesh against its CAD model (cad_import.h, distances_to_cad_faces): the distance from each
// given point to the CAD face it claims to lie on, measured by OpenCASCADE (BRepExtrema, which honours the face's
// trimming). FreeCAD's FEM finds a constraint's nodes the same way, so a boundary node farther from its face than
// the face's tolerance (CadSummary::node_tolerances) silently loses its load there (shared/docs/FREECAD.md).
//
// BRepExtrema misjudges points inside a periodic face that winds more than once around its axis: bottle.brep's
// thread, Face6, is a band on a cylinder over u in [0.12, 12.45]. Nodes of that band that lie on the cylinder to
// 4e-9, between its two edges, were reported 0.0086-0.063 from it (the distance to the nearer edge), as if outside.
// So where BRepExtrema's answer exceeds the face's tolerance, a second measure projects the point onto its surface
// (GeomAPI_ProjectPointOnSurf) and classifies that foot in the face's parameter plane at every period shift inside
// its UV bounds (BRepClass_FaceClassifier); a foot inside the face gives its distance. The result is the smaller of
// the two, each a distance to a point of the trimmed face, so it is never below the true distance.
// FreeCAD itself (BRepExtrema) would still miss such nodes for a constraint on that face, as it would Gmsh's.
#include <BRepBuilderAPI_MakeVertex.hxx>
#include <BRepClass_FaceClassifier.hxx>
#include <BRepExtrema_DistShapeShape.hxx>
#include <BRepTools.hxx>
#include <BRep_Tool.hxx>
#include <GeomAPI_ProjectPointOnSurf.hxx>
#include <Geom_Surface.hxx>
#include <ShapeAnalysis_Surface.hxx>
#include <Standard_Failure.hxx>
#include <TopExp.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Shape.hxx>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <vector>

#include "cad_private.h"
#include "qualmesh/error.h"

namespace qualmesh {

namespace {

// The values x + k period (k an integer; k = 0 only when period is 0) within [lo, hi], up to rounding.
std::vector<double> shifts_within(double x, double lo, double hi, double period) {
  const double slack = 1e-9;
  if (!(period > 0)) return x >= lo - slack && x <= hi + slack ? std::vector<double>{x} : std::vector<double>{};
  std::vector<double> out;
  for (double k = std::ceil((lo - slack - x) / period); x + k * period <= hi + slack; ++k) out.push_back(x + k * period);
  return out;
}

// The distance from p to the nearest foot of p on the face's surface that lies inside the trimmed face, trying
// every period shift of the foot's parameters that stays within the face's UV bounds; +inf when there is none.
double distance_through_surface(const TopoDS_Face& face, const gp_Pnt& p) {
  const Handle(Geom_Surface) surface = BRep_Tool::Surface(face);
  if (surface.IsNull()) return HUGE_VAL;
  GeomAPI_ProjectPointOnSurf projection(p, surface);
  if (!projection.IsDone()) return HUGE_VAL;
  double u0, u1, v0, v1;
  BRepTools::UVBounds(face, u0, u1, v0, v1);
  const double tolerance = BRep_Tool::Tolerance(face);
  const double u_period = surface->IsUPeriodic() ? surface->UPeriod() : 0;
  const double v_period = surface->IsVPeriodic() ? surface->VPeriod() : 0;
  double best = HUGE_VAL;
  const auto try_foot = [&](double u, double v, double distance) {
    if (!(distance < best)) return;
    for (const double uu : shifts_within(u, u0, u1, u_period))
      for (const double vv : shifts_within(v, v0, v1, v_period)) {
        const TopAbs_State state = BRepClass_FaceClassifier(face, gp_Pnt2d(uu, vv), tolerance).State();
        if (state == TopAbs_IN || state == TopAbs_ON) best = std::min(best, distance);
      }
  };
  for (int i = 1; i <= projection.NbPoints(); ++i) {
    double u, v;
    projection.Parameters(i, u, v);
    try_foot(u, v, projection.Distance(i));
  }
  // ShapeAnalysis_Surface's inversion as well: near a face corner that the surface folds around (bottle.brep's
  // thread, Face4 by its 0.9 deg corner at (7.445, -0.904, 53.726)), GeomAPI's extrema held only a foot outside the
  // face while a foot inside it lies 0.014 away.
  ShapeAnalysis_Surface analysis(surface);
  const gp_Pnt2d uv = analysis.ValueOfUV(p, 1e-9 * std::max(1.0, p.XYZ().Modulus()));
  if (std::isfinite(uv.X()) && std::isfinite(uv.Y())) try_foot(uv.X(), uv.Y(), surface->Value(uv.X(), uv.Y()).Distance(p));
  return best;
}

}  // namespace

std::vector<double> distances_to_cad_faces(const std::string& path, const std::vector<Point3>& points,
                                           const std::vector<int>& face_numbers, const CadOptions& options) {
  if (points.size() != face_numbers.size())
    throw InputError(ErrorCode::IndexOutOfRange, "one face number per point is needed", path);
  if (cad::lower_extension(path) == ".scad")
    throw InputError(ErrorCode::Unsupported, "an OpenSCAD model has no CAD faces", path);
  std::vector<std::string> log;
  const TopoDS_Shape solids = cad::read_healed_solids(path, options, log, /*use_cache=*/false);
  TopTools_IndexedMapOfShape faces;
  TopExp::MapShapes(solids, TopAbs_FACE, faces);

  std::vector<double> result(points.size(), std::numeric_limits<double>::infinity());
  try {
    std::map<int, BRepExtrema_DistShapeShape> by_face;
    for (std::size_t i = 0; i < points.size(); ++i) {
      const int f = face_numbers[i];
      if (f < 1 || f > faces.Extent()) continue;
      auto it = by_face.find(f);
      if (it == by_face.end()) {
        it = by_face.try_emplace(f).first;
        it->second.LoadS1(faces(f));
      }
      const gp_Pnt p(points[i][0], points[i][1], points[i][2]);
      it->second.LoadS2(BRepBuilderAPI_MakeVertex(p).Vertex());
      if (it->second.Perform() && it->second.IsDone()) result[i] = it->second.Value();
      const TopoDS_Face& face = TopoDS::Face(faces(f));
      if (!(result[i] <= BRep_Tool::Tolerance(face))) result[i] = std::min(result[i], distance_through_surface(face, p));
    }
  } catch (const Standard_Failure& failure) {
    throw InputError(ErrorCode::Parse, std::string("OpenCASCADE failed measuring distances: ") +
                                           failure.GetMessageString(), path);
  }
  return result;
}

CadConformity measure_against_cad(const std::string& path, const CadOptions& options, const TetMesh& mesh,
                                  const CadMeasureOptions& measure) {
  if (cad::lower_extension(path) == ".scad")
    throw InputError(ErrorCode::Unsupported, "an OpenSCAD model has no CAD faces", path);
  // The healed shape as read_cad sees it (its face and solid numbers), read once: its volumes and node tolerances
  // (these only when distances are measured) need no surface mesh (read_cad's whole conversion was most of `qualmesh
  // check`'s time on a CAD model), and the sharp features below take it from read_healed_solids' cache.
  std::vector<std::string> log;
  std::vector<double> tolerances;
  CadConformity result;
  try {
    const TopoDS_Shape solids = cad::read_healed_solids(path, options, log, measure.reuse_shape);
    for (double v : cad::solid_volumes(solids)) result.cad_volume += v;
    if (measure.distances) tolerances = cad::face_node_tolerances(solids);
  } catch (const Standard_Failure& failure) {
    throw InputError(ErrorCode::Parse, std::string("OpenCASCADE failed measuring the model: ") +
                                           failure.GetMessageString(), path);
  }
  if (measure.feature_angle_deg > 0) {
    const SharpCadFeatures features =
        find_sharp_cad_features(path, options, mesh.points, measure.feature_angle_deg, measure.feature_radius);
    result.features_checked = true;
    result.num_sharp_edges = features.num_sharp_edges;
    result.num_sharp_vertices = features.num_sharp_vertices;
    for (std::size_t i = 0; i < mesh.points.size(); ++i)
      if (features.near_feature[i]) result.feature_nodes.push_back(Index(i));
  }
  if (!measure.distances) return result;
  const std::vector<int> labels = face_labels(mesh);
  // Each (node, CAD face) pair once, by face: a node is a corner of about six boundary triangles of one face, and
  // OpenCASCADE's distance to a face costs up to a millisecond (1385_Laufrad_1000.stp's 254k corners took minutes).
  std::vector<std::pair<int, Index>> pairs;
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    for (Index v : mesh.faces[f]) pairs.push_back({labels[f], v});
    if (mesh.is_second_order())
      for (Index v : mesh.face_mid[f]) pairs.push_back({labels[f], v});
  }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  std::vector<Point3> points;
  std::vector<int> faces;
  for (const auto& [face, v] : pairs) {
    points.push_back(mesh.points[v]);
    faces.push_back(face);
  }
  const std::vector<double> d = distances_to_cad_faces(path, points, faces, options);
  result.num_nodes = d.size();
  for (std::size_t i = 0; i < d.size(); ++i) {
    const int f = faces[i];
    const double tolerance = f >= 1 && std::size_t(f) <= tolerances.size() ? tolerances[f - 1] : 0;
    result.max_distance = std::max(result.max_distance, d[i]);
    if (tolerance > 0) result.max_relative_to_tolerance = std::max(result.max_relative_to_tolerance, d[i] / tolerance);
    if (!(d[i] <= tolerance)) {
      ++result.num_beyond;
      if (result.problems.size() < 20) {
        char line[200];
        std::snprintf(line, sizeof line, "node at (%.9g, %.9g, %.9g) is %.3g from Face%d (tolerance %.3g)",
                      points[i][0], points[i][1], points[i][2], d[i], f, tolerance);
        result.problems.push_back(line);
      }
    }
  }
  return result;
}

}  // namespace qualmesh
