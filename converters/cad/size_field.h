// Size field of the sized CAD surface mesh (face_mesh.h): one target edge length per CAD face and per CAD edge, in
// model units, from the options an FEM user gives (CadOptions: Gmsh's and FreeCAD's vocabulary).
//
//   face size(f) = max(min_size, min(size, curvature size(f), local sizes on Face f and on the solids around it))
//   edge size(e) = min(the sizes of the faces that use e, 2 pi / (kappa_max(e) * curvature_elements), local size on
//                  Edge e), at least min_size
// where the curvature size of an analytic face is 2 pi / (k N) for its largest principal curvature k, that of a
// free-form face the uniform size with as many triangles as the pointwise 2 pi / (k(x) N) (face_curvature_size), and
// kappa_max(e) the largest curvature of the edge, sampled (Gmsh's MeshSizeFromCurvature, BackgroundMeshTools.cpp,
// takes the same 2 pi / (k N), point by point). Sizes are
// constant per entity: an edge is discretised uniformly in arc length (GCPnts_UniformAbscissa), a face is meshed to
// its own size. Gradation (> 1) then limits the ratio of the sizes of two faces sharing an edge. Private to
// converters/cad (OpenCASCADE types).
#pragma once

#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Face.hxx>

#include <string>
#include <vector>

#include "qualmesh/cad_import.h"

namespace qualmesh::cad {

class SizeField {
 public:
  // `faces`, `edges`, `solids`: the numbering of the healed shape (TopExp::MapShapes order, 1-based);
  // `diagonal`: of the model's bounding box. Throws InputError(IndexOutOfRange) for a local size on an entity that
  // does not exist, naming it.
  SizeField(const TopTools_IndexedMapOfShape& solids, const TopTools_IndexedMapOfShape& faces,
            const TopTools_IndexedMapOfShape& edges, const CadOptions& options, double diagonal,
            const std::string& file);

  double target() const { return target_; }      // CadOptions::size, or its default diag/10
  double min_size() const { return min_size_; }
  double face_size(int f) const { return face_sizes_[f]; }  // 1-based face number
  double edge_size(int e) const { return edge_sizes_[e]; }  // 1-based edge number

 private:
  double target_ = 0, min_size_ = 0;
  std::vector<double> face_sizes_, edge_sizes_;  // index 0 unused
};

// The curvature size of a face, in [min_size, target]: 2 pi / (k N) on a cylinder, sphere or torus (k their largest
// principal curvature, N `elements`), `target` on a plane; on a free-form face the one size that gives it as many
// triangles as the pointwise size 2 pi / (k(x) N) would (sampled). `target` when N is 0.
double face_curvature_size(const TopoDS_Face& face, double target, double min_size, double elements);
// Largest curvature of an edge's curve, sampled; 0 for a line or a degenerate edge.
double max_edge_curvature(const TopoDS_Edge& edge);

}  // namespace qualmesh::cad
