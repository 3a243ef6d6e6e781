// Independent check of a mesh against its CAD model (cad_import.h, distances_to_cad_faces): the distance from each
// given point to the CAD face it claims to lie on, measured by OpenCASCADE (BRepExtrema, which honours the face's
// trimming). FreeCAD's FEM finds a constraint's nodes the same way, so a boundary node farther from its face than
// the face's tolerance plus the deflection would silently lose its load there (shared/docs/FREECAD.md).
#include <BRepBuilderAPI_MakeVertex.hxx>
#include <BRepExtrema_DistShapeShape.hxx>
#include <Standard_Failure.hxx>
#include <TopExp.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS_Shape.hxx>

#include <limits>
#include <map>

#include "cad_private.h"
#include "qualmesh/error.h"

namespace qualmesh {

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
      const Point3& p = points[i];
      it->second.LoadS2(BRepBuilderAPI_MakeVertex(gp_Pnt(p[0], p[1], p[2])).Vertex());
      if (it->second.Perform() && it->second.IsDone()) result[i] = it->second.Value();
    }
  } catch (const Standard_Failure& failure) {
    throw InputError(ErrorCode::Parse, std::string("OpenCASCADE failed measuring distances: ") +
                                           failure.GetMessageString(), path);
  }
  return result;
}

}  // namespace qualmesh
