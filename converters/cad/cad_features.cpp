// Sharp features of a CAD model, found on its geometry (cad_import.h, find_sharp_cad_features): what the mesh checker
// (`qualmesh check MESH --ref MODEL.step`) needs to report quality away from them, for any mesher's mesh (issue 15's
// goal: no tet below 10 degrees anywhere the CAD dihedral angles are 30 degrees or more). The zone around them is
// the mesh points within a radius of a sharp edge or vertex (the checker's --protection-radius): a radius, not a
// count of element layers, so that a mesher that refines near a feature does not shrink its own zone.
//
// The CAD counterpart of the PLC's sharp input angles (the paper's Section 2, which validate_plc measures):
//  - facet-facet becomes the interior dihedral angle along a CAD edge between its two faces. At a point of the edge
//    with tangent t, face i has the outward normal n_i (the surface normal, reversed on a REVERSED face) and leaves
//    the edge in the direction d_i = n_i x t_i, t_i being t turned as the edge runs in that face: OpenCASCADE keeps
//    a face on the left of its oriented edges seen from the side its normal points to. With alpha the angle between
//    d_1 and d_2, the edge is convex where d_2 dips below face 1 (d_2 . n_1 < 0) and the interior angle is alpha,
//    else it is reflex and the interior angle is 360 - alpha. It is measured at 9 points along the edge; the edge
//    is sharp when one of them is below the threshold (a fillet running out tangentially sharpens at one end).
//  - segment-segment becomes the angle at a CAD vertex between two edges of one face, from their tangents leaving
//    the vertex (a face corner that tapers to a point: part.step's plane between a cylinder and a nearly tangent
//    extruded face).
//  - segment-facet (an edge meeting a face that does not hold it at a vertex) is not measured.
// Only edges of exactly two distinct faces count: a seam (one face on both sides) is no feature, and an edge of
// three or more faces (where solids of an assembly meet) has no one interior angle.
#include <BRepAdaptor_Curve.hxx>
#include <BRepAdaptor_Curve2d.hxx>
#include <BRepAdaptor_Surface.hxx>
#include <BRepBndLib.hxx>
#include <BRepLProp_SLProps.hxx>
#include <BRep_Tool.hxx>
#include <Bnd_Box.hxx>
#include <Extrema_ExtPC.hxx>
#include <Standard_Failure.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopTools_IndexedDataMapOfShapeListOfShape.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopTools_MapOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Vertex.hxx>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "cad_private.h"
#include "qualmesh/error.h"

namespace qualmesh {

namespace {

constexpr int kSamples = 9;
constexpr double kDegrees = 180.0 / 3.14159265358979323846;

// The occurrence of `edge` in `face`, oriented as the face runs along it; none for a seam (two occurrences).
std::optional<TopoDS_Edge> occurrence_in(const TopoDS_Face& face, const TopoDS_Edge& edge) {
  std::optional<TopoDS_Edge> found;
  for (TopExp_Explorer ex(face, TopAbs_EDGE); ex.More(); ex.Next()) {
    if (!ex.Current().IsSame(edge)) continue;
    if (found) return std::nullopt;
    found = TopoDS::Edge(ex.Current());
  }
  return found;
}

// The smallest interior dihedral angle (degrees) between the two faces of `edge` over kSamples points inside it;
// +inf when no point gives one (undefined normals or tangents).
double smallest_dihedral(const TopoDS_Edge& edge, const TopoDS_Face (&faces)[2], const TopoDS_Edge (&in_face)[2]) {
  const BRepAdaptor_Curve curve(edge);
  const BRepAdaptor_Surface surfaces[2] = {BRepAdaptor_Surface(faces[0]), BRepAdaptor_Surface(faces[1])};
  const BRepAdaptor_Curve2d pcurves[2] = {BRepAdaptor_Curve2d(in_face[0], faces[0]),
                                          BRepAdaptor_Curve2d(in_face[1], faces[1])};
  double smallest = std::numeric_limits<double>::infinity();
  for (int k = 1; k <= kSamples; ++k) {
    const double t = curve.FirstParameter() + (curve.LastParameter() - curve.FirstParameter()) * k / (kSamples + 1);
    gp_Pnt p;
    gp_Vec tangent;
    curve.D1(t, p, tangent);
    if (!(tangent.Magnitude() > 1e-12)) continue;
    tangent.Normalize();
    gp_Vec normal[2], leaving[2];
    bool defined = true;
    for (int i = 0; i < 2 && defined; ++i) {
      const gp_Pnt2d uv = pcurves[i].Value(t);
      BRepLProp_SLProps props(surfaces[i], uv.X(), uv.Y(), 1, 1e-9);
      defined = props.IsNormalDefined();
      if (!defined) break;
      normal[i] = gp_Vec(props.Normal());
      if (faces[i].Orientation() == TopAbs_REVERSED) normal[i].Reverse();
      const gp_Vec along = in_face[i].Orientation() == TopAbs_REVERSED ? tangent.Reversed() : tangent;
      leaving[i] = normal[i].Crossed(along);
      defined = leaving[i].Magnitude() > 1e-12;
      if (defined) leaving[i].Normalize();
    }
    if (!defined) continue;
    const double alpha = leaving[0].Angle(leaving[1]) * kDegrees;
    smallest = std::min(smallest, leaving[1].Dot(normal[0]) < 0 ? alpha : 360 - alpha);
  }
  return smallest;
}

// The unit tangents leaving each vertex of `face` along its edges (one per edge end), by vertex index in `vertices`.
std::vector<std::pair<int, gp_Vec>> leaving_tangents(const TopoDS_Face& face,
                                                     const TopTools_IndexedMapOfShape& vertices) {
  std::vector<std::pair<int, gp_Vec>> out;
  TopTools_MapOfShape seen;
  for (TopExp_Explorer ex(face, TopAbs_EDGE); ex.More(); ex.Next()) {
    const TopoDS_Edge& edge = TopoDS::Edge(ex.Current());
    if (BRep_Tool::Degenerated(edge) || !seen.Add(edge)) continue;  // a seam once
    TopoDS_Vertex first, last;
    TopExp::Vertices(edge, first, last);  // at the curve's first and last parameters
    if (first.IsNull() || last.IsNull()) continue;
    const BRepAdaptor_Curve curve(edge);
    gp_Pnt p;
    gp_Vec d;
    curve.D1(curve.FirstParameter(), p, d);
    if (d.Magnitude() > 1e-12) out.push_back({vertices.FindIndex(first), d.Normalized()});
    curve.D1(curve.LastParameter(), p, d);
    if (d.Magnitude() > 1e-12) out.push_back({vertices.FindIndex(last), d.Reversed().Normalized()});
  }
  return out;
}

}  // namespace

namespace cad {

SharpFeatureList list_sharp_features(const TopoDS_Shape& solids, double angle_deg) {
  SharpFeatureList list;
  TopTools_IndexedMapOfShape edges, vertices, faces;
  TopExp::MapShapes(solids, TopAbs_EDGE, edges);
  TopExp::MapShapes(solids, TopAbs_VERTEX, vertices);
  TopExp::MapShapes(solids, TopAbs_FACE, faces);

  // Sharp edges: two faces meeting at a small interior dihedral angle.
  TopTools_IndexedDataMapOfShapeListOfShape edge_faces;
  TopExp::MapShapesAndUniqueAncestors(solids, TopAbs_EDGE, TopAbs_FACE, edge_faces);
  for (int e = 1; e <= edge_faces.Extent(); ++e) {
    const TopoDS_Edge& edge = TopoDS::Edge(edge_faces.FindKey(e));
    const TopTools_ListOfShape& around = edge_faces.FindFromIndex(e);
    if (BRep_Tool::Degenerated(edge) || around.Extent() != 2 || around.First().IsSame(around.Last())) continue;
    const TopoDS_Face pair[2] = {TopoDS::Face(around.First()), TopoDS::Face(around.Last())};
    const std::optional<TopoDS_Edge> first = occurrence_in(pair[0], edge), second = occurrence_in(pair[1], edge);
    if (!first || !second) continue;
    const TopoDS_Edge in_face[2] = {*first, *second};
    const double angle = smallest_dihedral(edge, pair, in_face);
    if (angle < angle_deg) list.edges.push_back({edge, edges.FindIndex(edge), angle, gp_Pnt()});
  }

  // Sharp vertices: two edges of one face leaving a vertex at a small angle.
  std::vector<double> corner(vertices.Extent() + 1, std::numeric_limits<double>::infinity());
  for (int f = 1; f <= faces.Extent(); ++f) {
    const std::vector<std::pair<int, gp_Vec>> tangents = leaving_tangents(TopoDS::Face(faces(f)), vertices);
    for (std::size_t a = 0; a < tangents.size(); ++a)
      for (std::size_t b = a + 1; b < tangents.size(); ++b)
        if (tangents[a].first > 0 && tangents[a].first == tangents[b].first)
          corner[tangents[a].first] = std::min(corner[tangents[a].first],
                                               tangents[a].second.Angle(tangents[b].second) * kDegrees);
  }
  for (int v = 1; v <= vertices.Extent(); ++v)
    if (corner[v] < angle_deg)
      list.vertices.push_back({vertices(v), v, corner[v], BRep_Tool::Pnt(TopoDS::Vertex(vertices(v)))});
  return list;
}

std::string describe_sharp_features(const SharpFeatureList& list, double angle_deg) {
  char line[300];
  const auto smallest = [](const std::vector<SharpFeature>& features) {
    return *std::min_element(features.begin(), features.end(),
                             [](const SharpFeature& a, const SharpFeature& b) { return a.angle_deg < b.angle_deg; });
  };
  std::string corners = std::to_string(list.vertices.size()) + " face corners";
  if (!list.vertices.empty()) {
    const SharpFeature v = smallest(list.vertices);
    std::snprintf(line, sizeof line, " (smallest %.2f deg at Vertex%d (%.6g, %.6g, %.6g))", v.angle_deg, v.number,
                  v.at.X(), v.at.Y(), v.at.Z());
    corners += line;
  }
  std::string edges = std::to_string(list.edges.size()) + " edges";
  if (!list.edges.empty()) {
    const SharpFeature e = smallest(list.edges);
    std::snprintf(line, sizeof line, " (smallest dihedral angle %.2f deg, along Edge%d)", e.angle_deg, e.number);
    edges += line;
  }
  std::snprintf(line, sizeof line, "sharp features below %g deg: ", angle_deg);
  return line + corners + ", " + edges;
}

}  // namespace cad

SharpCadFeatures find_sharp_cad_features(const std::string& path, const CadOptions& options,
                                         const std::vector<Point3>& points, double angle_deg, double radius) {
  if (cad::lower_extension(path) == ".scad")
    throw InputError(ErrorCode::Unsupported, "an OpenSCAD model has no CAD edges", path);
  SharpCadFeatures result;
  result.near_feature.assign(points.size(), 0);
  std::vector<std::string> log;
  // The shape read_cad read last, when it is this model (measure_against_cad reads it just before).
  const TopoDS_Shape solids = cad::read_healed_solids(path, options, log, /*use_cache=*/true);
  try {
    const cad::SharpFeatureList list = cad::list_sharp_features(solids, angle_deg);
    result.num_sharp_edges = list.edges.size();
    result.num_sharp_vertices = list.vertices.size();
    Bnd_Box box;
    BRepBndLib::Add(solids, box);
    const double diagonal = box.IsVoid() ? 0 : std::sqrt(box.SquareExtent());
    const auto near = [&](const gp_Pnt& a, std::size_t i, double tolerance) {
      return gp_Pnt(points[i][0], points[i][1], points[i][2]).Distance(a) <= tolerance;
    };
    for (const cad::SharpFeature& feature : list.edges) {
      const TopoDS_Edge& edge = TopoDS::Edge(feature.shape);
      const double tolerance = std::max({radius, BRep_Tool::Tolerance(edge), 1e-7 * diagonal});
      Bnd_Box edge_box;
      BRepBndLib::Add(edge, edge_box);
      edge_box.Enlarge(tolerance);
      const BRepAdaptor_Curve curve(edge);
      for (std::size_t i = 0; i < points.size(); ++i) {
        const gp_Pnt p(points[i][0], points[i][1], points[i][2]);
        if (result.near_feature[i] || edge_box.IsOut(p)) continue;
        bool on = near(curve.Value(curve.FirstParameter()), i, tolerance) ||
                  near(curve.Value(curve.LastParameter()), i, tolerance);
        const Extrema_ExtPC extrema(p, curve);
        for (int k = 1; !on && extrema.IsDone() && k <= extrema.NbExt(); ++k)
          on = std::sqrt(extrema.SquareDistance(k)) <= tolerance;
        result.near_feature[i] = on;
      }
    }
    for (const cad::SharpFeature& feature : list.vertices) {
      const TopoDS_Vertex& vertex = TopoDS::Vertex(feature.shape);
      const double tolerance = std::max({radius, BRep_Tool::Tolerance(vertex), 1e-7 * diagonal});
      for (std::size_t i = 0; i < points.size(); ++i)
        if (!result.near_feature[i] && near(feature.at, i, tolerance)) result.near_feature[i] = 1;
    }
  } catch (const Standard_Failure& failure) {
    throw InputError(ErrorCode::Parse,
                     std::string("OpenCASCADE failed measuring the model's sharp features: ") +
                         failure.GetMessageString(),
                     path);
  }
  return result;
}

}  // namespace qualmesh
