// Healing a CAD shape into closed solids that share their common faces (second stage of the CAD front end).
//
// What a CAD user expects to be healed, in this order:
//  1. faces that belong to no solid (IGES face soups, open shells) are sewn (BRepBuilderAPI_Sewing, the same tool as
//     FreeCAD's Part > Sew and gmsh's Geometry.OCCSewFaces) and every closed shell becomes a solid;
//  2. ShapeFix_Shape and ShapeFix_Wireframe fix tiny, degenerate and zero-length edges and wire gaps within the
//     sewing tolerance, and solids are turned outward;
//  3. several solids are glued by the general fuse (BRepAlgoAPI_BuilderAlgo, FreeCAD's BooleanFragments) so that a
//     face where two solids touch becomes one internal face.
// What cannot be closed is refused: the error names the open faces and edges with FreeCAD's numbers of the shape as
// read (FaceN, EdgeN), and where the open edges are.
#include <BRepAlgoAPI_BuilderAlgo.hxx>
#include <BRepBndLib.hxx>
#include <BRepBuilderAPI_MakeSolid.hxx>
#include <BRepBuilderAPI_Sewing.hxx>
#include <BRepClass3d_SolidClassifier.hxx>
#include <BRep_Builder.hxx>
#include <BRep_Tool.hxx>
#include <Bnd_Box.hxx>
#include <ShapeFix_Shape.hxx>
#include <ShapeFix_Wireframe.hxx>
#include <Standard_Failure.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopTools_IndexedDataMapOfShapeListOfShape.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopTools_ListOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Compound.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Shell.hxx>
#include <TopoDS_Solid.hxx>
#include <TopoDS_Vertex.hxx>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>

#include "cad_private.h"
#include "qualmesh/error.h"

namespace qualmesh::cad {
namespace {

double diagonal_of(const TopoDS_Shape& shape) {
  Bnd_Box box;
  BRepBndLib::Add(shape, box);
  if (box.IsVoid()) return 0;
  return std::sqrt(box.SquareExtent());
}

double largest_vertex_tolerance(const TopoDS_Shape& shape) {
  double tol = 0;
  for (TopExp_Explorer it(shape, TopAbs_VERTEX); it.More(); it.Next())
    tol = std::max(tol, BRep_Tool::Tolerance(TopoDS::Vertex(it.Current())));
  return tol;
}

// Edges of `shape` bounded by one face only (seams and degenerate edges excepted).
std::vector<TopoDS_Edge> find_free_edges(const TopoDS_Shape& shape) {
  TopTools_IndexedDataMapOfShapeListOfShape edge_faces;
  TopExp::MapShapesAndAncestors(shape, TopAbs_EDGE, TopAbs_FACE, edge_faces);
  std::vector<TopoDS_Edge> free_edges;
  for (int i = 1; i <= edge_faces.Extent(); ++i) {
    const TopoDS_Edge& edge = TopoDS::Edge(edge_faces.FindKey(i));
    if (BRep_Tool::Degenerated(edge)) continue;
    const TopTools_ListOfShape& faces = edge_faces.FindFromIndex(i);
    if (faces.Extent() == 1 && !BRep_Tool::IsClosed(edge, TopoDS::Face(faces.First()))) free_edges.push_back(edge);
  }
  return free_edges;
}

std::string format_point(const gp_Pnt& p) {
  char buffer[96];
  std::snprintf(buffer, sizeof buffer, "(%.6g, %.6g, %.6g)", p.X(), p.Y(), p.Z());
  return buffer;
}

std::string join_names(const std::set<int>& numbers, const char* prefix, std::size_t limit = 20) {
  std::string text;
  std::size_t count = 0;
  for (int n : numbers) {
    if (count == limit) {
      text += ", ... (" + std::to_string(numbers.size()) + " in all)";
      break;
    }
    if (count++) text += ", ";
    text += prefix + std::to_string(n);
  }
  return text;
}

// Makes the solid's normals point outward (a solid whose infinite point classifies IN is inside out).
TopoDS_Shape orient_outward(const TopoDS_Shape& solid, double tol, bool& reversed) {
  BRepClass3d_SolidClassifier classifier(solid);
  classifier.PerformInfinitePoint(tol);
  reversed = classifier.State() == TopAbs_IN;
  return reversed ? solid.Reversed() : solid;
}

}  // namespace

TopoDS_Shape heal_into_solids(const TopoDS_Shape& input, const CadOptions& options, const std::string& file,
                              std::vector<std::string>& log) {
  const double diag = diagonal_of(input);
  if (diag <= 0) throw InputError(ErrorCode::Empty, "the CAD model has no geometry", file);
  double tol = options.sewing_tolerance;
  if (tol <= 0) tol = std::min(std::max(1e-6 * diag, largest_vertex_tolerance(input)), 1e-4 * diag);

  TopTools_IndexedMapOfShape input_faces, input_edges;
  TopExp::MapShapes(input, TopAbs_FACE, input_faces);
  TopExp::MapShapes(input, TopAbs_EDGE, input_edges);
  if (input_faces.IsEmpty()) throw InputError(ErrorCode::Empty, "the CAD model has no faces (wires or points only)",
                                              file);

  try {
    // 1. Solids as given (closed ones), and loose faces (of no solid, or of an open solid).
    std::vector<TopoDS_Shape> solids;
    TopTools_IndexedMapOfShape faces_in_solids;
    std::size_t num_open_solids = 0;
    for (TopExp_Explorer it(input, TopAbs_SOLID); it.More(); it.Next()) {
      if (!find_free_edges(it.Current()).empty()) {
        ++num_open_solids;
        continue;
      }
      solids.push_back(it.Current());
      TopExp::MapShapes(it.Current(), TopAbs_FACE, faces_in_solids);
    }
    std::vector<TopoDS_Face> loose_faces;
    for (int i = 1; i <= input_faces.Extent(); ++i)
      if (!faces_in_solids.Contains(input_faces(i))) loose_faces.push_back(TopoDS::Face(input_faces(i)));

    if (!loose_faces.empty()) {
      if (!options.heal) {
        std::set<int> names;
        for (const auto& f : loose_faces) names.insert(input_faces.FindIndex(f));
        throw InputError(ErrorCode::OpenBoundary,
                         std::to_string(loose_faces.size()) + " faces belong to no closed solid (" +
                             join_names(names, "Face") + "); healing is off",
                         file);
      }
      BRepBuilderAPI_Sewing sewing(tol);
      for (const auto& f : loose_faces) sewing.Add(f);
      sewing.Perform();
      const TopoDS_Shape sewn = sewing.SewedShape();
      log.push_back("sewed " + std::to_string(loose_faces.size()) + " loose faces with tolerance " +
                    std::to_string(tol) + (num_open_solids ? " (from " + std::to_string(num_open_solids) +
                                                                 " open solids)"
                                                           : std::string()));
      // Map the sewn faces and edges back to their numbers in the shape as read.
      std::map<int, int> sewn_face_origin;  // index in sewn face map -> input face number
      TopTools_IndexedMapOfShape sewn_faces, sewn_edges;
      TopExp::MapShapes(sewn, TopAbs_FACE, sewn_faces);
      TopExp::MapShapes(sewn, TopAbs_EDGE, sewn_edges);
      for (const auto& f : loose_faces) {
        TopoDS_Shape image = sewing.IsModified(f) ? sewing.Modified(f) : TopoDS_Shape(f);
        int k = sewn_faces.FindIndex(image);
        if (k > 0) sewn_face_origin[k] = input_faces.FindIndex(f);
      }
      std::map<int, int> sewn_edge_origin;
      for (int j = 1; j <= input_edges.Extent(); ++j) {
        const TopoDS_Shape& e = input_edges(j);
        TopoDS_Shape image = sewing.IsModifiedSubShape(e) ? sewing.ModifiedSubShape(e) : e;
        int k = sewn_edges.FindIndex(image);
        if (k > 0 && !sewn_edge_origin.count(k)) sewn_edge_origin[k] = j;
      }

      std::set<int> open_faces, open_edges;
      std::vector<std::string> open_places;
      std::size_t num_open_shells = 0, num_new_solids = 0;
      std::vector<TopoDS_Shape> shells;
      for (TopExp_Explorer it(sewn, TopAbs_SHELL); it.More(); it.Next()) shells.push_back(it.Current());
      for (TopExp_Explorer it(sewn, TopAbs_FACE, TopAbs_SHELL); it.More(); it.Next()) shells.push_back(it.Current());
      for (const auto& shell : shells) {
        std::vector<TopoDS_Edge> free_edges = find_free_edges(shell);
        if (free_edges.empty() && shell.ShapeType() == TopAbs_SHELL) {
          BRepBuilderAPI_MakeSolid make_solid(TopoDS::Shell(shell));
          solids.push_back(make_solid.Solid());
          ++num_new_solids;
          continue;
        }
        ++num_open_shells;
        TopTools_IndexedDataMapOfShapeListOfShape edge_faces;
        TopExp::MapShapesAndAncestors(shell, TopAbs_EDGE, TopAbs_FACE, edge_faces);
        for (const auto& e : free_edges) {
          int k = sewn_edges.FindIndex(e);
          auto origin = sewn_edge_origin.find(k);
          if (origin != sewn_edge_origin.end()) open_edges.insert(origin->second);
          if (open_places.size() < 5) {
            double first, last;
            Handle(Geom_Curve) curve = BRep_Tool::Curve(e, first, last);
            if (!curve.IsNull()) open_places.push_back(format_point(curve->Value(0.5 * (first + last))));
          }
          for (const auto& f : edge_faces.FindFromKey(e)) {
            auto face_origin = sewn_face_origin.find(sewn_faces.FindIndex(f));
            if (face_origin != sewn_face_origin.end()) open_faces.insert(face_origin->second);
          }
        }
        if (free_edges.empty()) {  // a lone face with no free edge cannot happen; name it anyway
          auto face_origin = sewn_face_origin.find(sewn_faces.FindIndex(shell));
          if (face_origin != sewn_face_origin.end()) open_faces.insert(face_origin->second);
        }
      }
      if (num_open_shells > 0) {
        std::string message = "the model stays open after sewing with tolerance " + std::to_string(tol) + ": " +
                              std::to_string(num_open_shells) + " open shell(s); open faces " +
                              join_names(open_faces, "Face") + "; open edges " + join_names(open_edges, "Edge");
        if (!open_places.empty()) {
          message += "; e.g. at";
          for (const auto& p : open_places) message += " " + p;
        }
        char larger[32];
        std::snprintf(larger, sizeof larger, "%.3g", 10 * tol);
        message += std::string(" (a larger sewing tolerance, e.g. --sewing-tolerance ") + larger +
                   ", or repairing the model in the CAD system may close it)";
        throw InputError(ErrorCode::OpenBoundary, message, file);
      }
      if (num_new_solids) log.push_back("made " + std::to_string(num_new_solids) + " solid(s) of closed sewn shells");
    }
    if (solids.empty()) throw InputError(ErrorCode::Empty, "the CAD model has no solid", file);

    // 2. Fix small and degenerate edges and wire gaps, orient solids outward.
    BRep_Builder builder;
    TopoDS_Compound compound;
    builder.MakeCompound(compound);
    for (const auto& s : solids) builder.Add(compound, s);
    TopoDS_Shape shape = compound;
    if (options.heal) {
      TopTools_IndexedMapOfShape before_edges;
      TopExp::MapShapes(shape, TopAbs_EDGE, before_edges);
      Handle(ShapeFix_Wireframe) wireframe = new ShapeFix_Wireframe(shape);
      wireframe->SetPrecision(tol);
      wireframe->ModeDropSmallEdges() = Standard_True;
      bool small_fixed = wireframe->FixSmallEdges();
      bool gaps_fixed = wireframe->FixWireGaps();
      if (small_fixed || gaps_fixed) shape = wireframe->Shape();
      Handle(ShapeFix_Shape) fix = new ShapeFix_Shape(shape);
      fix->SetPrecision(tol);
      fix->SetMaxTolerance(std::max(tol, 1e-4 * diag));
      fix->Perform();
      if (fix->Status(ShapeExtend_DONE)) shape = fix->Shape();
      TopTools_IndexedMapOfShape after_edges;
      TopExp::MapShapes(shape, TopAbs_EDGE, after_edges);
      if (small_fixed) log.push_back("fixed small edges (" + std::to_string(before_edges.Extent()) + " -> " +
                                     std::to_string(after_edges.Extent()) + " edges)");
      if (gaps_fixed) log.push_back("closed gaps in wires");
      if (fix->Status(ShapeExtend_DONE)) log.push_back("ShapeFix repaired faces, wires or edges");
    }
    std::vector<TopoDS_Shape> fixed_solids;
    for (TopExp_Explorer it(shape, TopAbs_SOLID); it.More(); it.Next()) {
      bool reversed = false;
      fixed_solids.push_back(orient_outward(it.Current(), tol, reversed));
      if (reversed) log.push_back("turned solid " + std::to_string(fixed_solids.size()) + " outward");
    }
    if (fixed_solids.empty()) throw InputError(ErrorCode::Empty, "healing left no solid", file);

    // 3. Glue touching solids so that a shared face is one face.
    TopoDS_Compound result;
    builder.MakeCompound(result);
    if (fixed_solids.size() > 1) {
      BRepAlgoAPI_BuilderAlgo fuse;
      TopTools_ListOfShape arguments;
      for (const auto& s : fixed_solids) arguments.Append(s);
      fuse.SetArguments(arguments);
      fuse.SetRunParallel(Standard_False);
      fuse.Build();
      if (fuse.HasErrors()) {
        log.push_back("could not glue the " + std::to_string(fixed_solids.size()) +
                      " solids (general fuse failed); they are kept as they are");
        for (const auto& s : fixed_solids) builder.Add(result, s);
      } else {
        TopTools_IndexedMapOfShape before_faces, after_faces, after_solids;
        for (const auto& s : fixed_solids) TopExp::MapShapes(s, TopAbs_FACE, before_faces);
        TopExp::MapShapes(fuse.Shape(), TopAbs_FACE, after_faces);
        TopExp::MapShapes(fuse.Shape(), TopAbs_SOLID, after_solids);
        for (int i = 1; i <= after_solids.Extent(); ++i) builder.Add(result, after_solids(i));
        if (after_faces.Extent() != before_faces.Extent() ||
            after_solids.Extent() != static_cast<int>(fixed_solids.size()))
          log.push_back("glued " + std::to_string(fixed_solids.size()) + " solids (general fuse): " +
                        std::to_string(before_faces.Extent()) + " -> " + std::to_string(after_faces.Extent()) +
                        " faces, " + std::to_string(after_solids.Extent()) + " solids");
      }
    } else {
      builder.Add(result, fixed_solids.front());
    }
    return result;
  } catch (const Standard_Failure& failure) {
    throw InputError(ErrorCode::Parse, std::string("OpenCASCADE failed while healing the model: ") +
                                           failure.GetMessageString(), file);
  }
}

}  // namespace qualmesh::cad
