// Region seeds of the CAD front end (brep_to_plc.cpp's last step): a point strictly inside a solid, far enough
// from every wall that it stays inside the PLC, whose facets stray from the CAD surface by the chordal error.
#include <BRepBuilderAPI_MakeVertex.hxx>
#include <BRepClass3d_SolidClassifier.hxx>
#include <BRepExtrema_DistShapeShape.hxx>
#include <BRep_Tool.hxx>
#include <IntCurvesFace_ShapeIntersector.hxx>
#include <Poly_Triangulation.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Vertex.hxx>
#include <gp_Lin.hxx>

#include <algorithm>
#include <limits>
#include <vector>

#include "cad_private.h"

namespace qualmesh::cad {

// From the centroid of one of the solid's larger tessellation triangles, go inward half-way to the next hit of the
// inward ray with the solid; the first such point that OpenCASCADE classifies IN and that lies more than `margin`
// from every wall (BRepExtrema) is the seed.
std::optional<Point3> region_seed(const TopoDS_Shape& solid, double margin, double diagonal) {
  struct Candidate {
    double area;
    gp_Pnt centroid;
    gp_Dir inward;
  };
  std::vector<Candidate> candidates;
  for (TopExp_Explorer it(solid, TopAbs_FACE); it.More(); it.Next()) {
    const TopoDS_Face& face = TopoDS::Face(it.Current());
    TopLoc_Location location;
    Handle(Poly_Triangulation) triangulation = BRep_Tool::Triangulation(face, location);
    if (triangulation.IsNull()) continue;
    const bool flip = face.Orientation() == TopAbs_REVERSED;
    for (int t = 1; t <= triangulation->NbTriangles(); ++t) {
      int a, b, c;
      triangulation->Triangle(t).Get(a, b, c);
      gp_Pnt pa = triangulation->Node(a).Transformed(location), pb = triangulation->Node(b).Transformed(location),
             pc = triangulation->Node(c).Transformed(location);
      gp_Vec normal = gp_Vec(pa, pb).Crossed(gp_Vec(pa, pc));
      double area = 0.5 * normal.Magnitude();
      if (area <= 0) continue;
      if (!flip) normal.Reverse();  // outward normal of a forward face is the surface normal; go inward
      gp_Pnt centroid((pa.XYZ() + pb.XYZ() + pc.XYZ()) / 3.0);
      candidates.push_back({area, centroid, gp_Dir(normal)});
    }
  }
  std::stable_sort(candidates.begin(), candidates.end(),
                   [](const Candidate& x, const Candidate& y) { return x.area > y.area; });
  IntCurvesFace_ShapeIntersector intersector;
  intersector.Load(solid, 1e-9 * diagonal);
  BRepClass3d_SolidClassifier classifier(solid);
  const std::size_t tries = std::min<std::size_t>(candidates.size(), 200);
  for (std::size_t k = 0; k < tries; ++k) {
    const Candidate& c = candidates[k];
    gp_Pnt start = c.centroid.Translated(gp_Vec(c.inward) * 1e-7 * diagonal);
    intersector.Perform(gp_Lin(start, c.inward), 0, 2 * diagonal);
    if (!intersector.IsDone() || intersector.NbPnt() == 0) continue;
    double nearest = std::numeric_limits<double>::infinity();
    for (int i = 1; i <= intersector.NbPnt(); ++i) nearest = std::min(nearest, intersector.WParameter(i));
    if (!(nearest > 2 * margin)) continue;
    gp_Pnt seed = start.Translated(gp_Vec(c.inward) * (0.5 * nearest));
    classifier.Perform(seed, 1e-9 * diagonal);
    if (classifier.State() != TopAbs_IN) continue;
    // The ray measured one direction; the seed keeps the margin from every wall (the solid's shells: a solid
    // itself is at distance 0 from a point inside it).
    const TopoDS_Vertex point = BRepBuilderAPI_MakeVertex(seed).Vertex();
    bool clear = true;
    for (TopExp_Explorer shells(solid, TopAbs_SHELL); shells.More() && clear; shells.Next()) {
      BRepExtrema_DistShapeShape distance(point, shells.Current());
      clear = distance.IsDone() && distance.Value() > margin;
    }
    if (!clear) continue;
    return Point3{seed.X(), seed.Y(), seed.Z()};
  }
  return std::nullopt;
}

}  // namespace qualmesh::cad
