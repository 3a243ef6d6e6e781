// Size field of the sized CAD surface mesh (size_field.h).
#include "size_field.h"

#include <BRepAdaptor_Curve.hxx>
#include <BRepAdaptor_Surface.hxx>
#include <BRepGProp.hxx>
#include <GProp_GProps.hxx>
#include <BRepLProp_CLProps.hxx>
#include <BRepLProp_SLProps.hxx>
#include <BRepTools.hxx>
#include <BRep_Tool.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopTools_IndexedDataMapOfShapeListOfShape.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopTools_ListOfShape.hxx>
#include <TopoDS.hxx>

#include <algorithm>
#include <cmath>

#include "qualmesh/error.h"

namespace qualmesh::cad {

namespace {

constexpr int kSamples = 9;  // per parameter direction
// Default smallest size, relative to the target: a hole of radius target/30 still gets about 6 segments.
// Edge length on a narrow face relative to its width estimate 2 A / P (a square of side a gets 1.1 a: no split).
constexpr double kThinFaceFactor = 2.2;

const char* kind_name(CadLocalSize::Kind kind) {
  switch (kind) {
    case CadLocalSize::Kind::Face: return "Face";
    case CadLocalSize::Kind::Edge: return "Edge";
    case CadLocalSize::Kind::Solid: return "Solid";
  }
  return "?";
}

// 2 pi / (k N): the edge length that puts N elements on a full circle of curvature k; +inf when not asked.
double curvature_size(double curvature, double elements) {
  if (!(elements > 0) || !(curvature > 0)) return HUGE_VAL;
  return 2 * M_PI / (curvature * elements);
}

// The curvature size clamped to [min_size, target]: the size of a point of curvature k.
double clamped_curvature_size(double k, double target, double min_size, double elements) {
  return std::max(min_size, std::min(target, curvature_size(k, elements)));
}

// Distinct, non-degenerate edges of a face (a seam counts once).
int num_edges_of(const TopoDS_Face& face) {
  TopTools_IndexedMapOfShape edges;
  TopExp::MapShapes(face, TopAbs_EDGE, edges);
  int n = 0;
  for (int i = 1; i <= edges.Extent(); ++i) n += BRep_Tool::Degenerated(TopoDS::Edge(edges(i))) ? 0 : 1;
  return n;
}

}  // namespace

double face_curvature_size(const TopoDS_Face& face, double target, double min_size, double elements) {
  const auto size_at = [&](double k) { return clamped_curvature_size(k, target, min_size, elements); };
  BRepAdaptor_Surface surface(face, Standard_True);
  switch (surface.GetType()) {  // exact for the analytic surfaces, whose largest curvature is the same everywhere
    case GeomAbs_Plane: return target;
    case GeomAbs_Cylinder: return size_at(1 / surface.Cylinder().Radius());
    case GeomAbs_Sphere: return size_at(1 / surface.Sphere().Radius());
    case GeomAbs_Torus: return size_at(1 / surface.Torus().MinorRadius());
    default: break;
  }
  // Free-form faces: Gmsh sizes each point by its own curvature, and a face then gets about (integral of 1 / h^2
  // dA) triangles. A face here is meshed at one size, so it gets the size with that count: 1 / sqrt(the
  // area-weighted mean of 1 / h^2), sampled on a grid over the parameter box (weight |dS/du x dS/dv|). Before, the
  // upper quartile of the sampled curvatures set it, which on wrenchnut.stp's B-spline flanks gave 5.1 where
  // Gmsh's own mean edge is 2.9: 0.79x Gmsh's nodes at --size 40.61, 0.64x at 10.15 (1.12x and 0.93x now).
  double u0, u1, v0, v1;
  BRepTools::UVBounds(face, u0, u1, v0, v1);
  BRepLProp_SLProps props(surface, 2, 1e-9);
  double area = 0, sum = 0;
  for (int i = 0; i < kSamples; ++i)
    for (int j = 0; j < kSamples; ++j) {
      props.SetParameters(u0 + (u1 - u0) * (i + 0.5) / kSamples, v0 + (v1 - v0) * (j + 0.5) / kSamples);
      const double w = props.D1U().Crossed(props.D1V()).Magnitude();
      if (!(w > 0) || !std::isfinite(w)) continue;  // a pole or a degenerate patch
      double h = target;
      if (props.IsCurvatureDefined()) {
        const double k = std::max(std::fabs(props.MaxCurvature()), std::fabs(props.MinCurvature()));
        if (std::isfinite(k)) h = size_at(k);
      }
      area += w;
      sum += w / (h * h);
    }
  return area > 0 ? 1 / std::sqrt(sum / area) : target;
}

double max_edge_curvature(const TopoDS_Edge& edge) {
  if (BRep_Tool::Degenerated(edge)) return 0;
  BRepAdaptor_Curve curve(edge);
  switch (curve.GetType()) {
    case GeomAbs_Line: return 0;
    case GeomAbs_Circle: return 1 / curve.Circle().Radius();
    default: break;
  }
  BRepLProp_CLProps props(curve, 2, 1e-9);
  std::vector<double> samples;  // the upper quartile: one sample near a singular spot must not set the whole edge
  const double t0 = curve.FirstParameter(), t1 = curve.LastParameter();
  for (int i = 0; i <= 2 * kSamples; ++i) {
    props.SetParameter(t0 + (t1 - t0) * i / (2 * kSamples));
    if (props.IsTangentDefined() && std::isfinite(props.Curvature())) samples.push_back(std::fabs(props.Curvature()));
  }
  if (samples.empty()) return 0;
  std::sort(samples.begin(), samples.end());
  return samples[(samples.size() * 3) / 4];
}

SizeField::SizeField(const TopTools_IndexedMapOfShape& solids, const TopTools_IndexedMapOfShape& faces,
                     const TopTools_IndexedMapOfShape& edges, const CadOptions& options, double diagonal,
                     const std::string& file) {
  target_ = options.size > 0 ? options.size : diagonal / 10;
  min_size_ = options.min_size > 0 ? std::min(options.min_size, target_) : kDefaultMinSizeFactor * target_;
  const int num_faces = faces.Extent(), num_edges = edges.Extent(), num_solids = solids.Extent();
  std::vector<double> local_face(num_faces + 1, HUGE_VAL), local_edge(num_edges + 1, HUGE_VAL),
      local_solid(num_solids + 1, HUGE_VAL);
  for (const CadLocalSize& local : options.local_sizes) {
    std::vector<double>& slot = local.kind == CadLocalSize::Kind::Face   ? local_face
                                : local.kind == CadLocalSize::Kind::Edge ? local_edge
                                                                         : local_solid;
    if (local.id < 1 || local.id >= static_cast<int>(slot.size()))
      throw InputError(ErrorCode::IndexOutOfRange,
                       std::string("--local-size names ") + kind_name(local.kind) + std::to_string(local.id) +
                           ", but the model has " + std::to_string(slot.size() - 1) + " " +
                           kind_name(local.kind) + "s (numbered from 1)",
                       file);
    slot[local.id] = std::min(slot[local.id], local.size);
  }
  face_sizes_.assign(num_faces + 1, target_);
  for (int f = 1; f <= num_faces; ++f) {
    const TopoDS_Face face = TopoDS::Face(faces(f));
    double h = face_curvature_size(face, target_, min_size_, options.curvature_elements);
    // A narrow face (a strip between two long edges, a thin fillet) gets edges no longer than about its width,
    // 2 area / perimeter (the width of a long strip, the radius of a disc), so that its triangles are not needles.
    // Not a wedge: a three-sided face larger than its elements (perimeter above twice the size), whose 2 A / P is
    // the inradius its short side sets. Its narrowness is a corner that no refinement widens; refining the whole
    // face only spreads small elements into its neighbours (t20_data.step's six 16.8 x 1.9 mm triangular faces
    // at 5.877: 791 -> 579 nodes, tets below 10 deg 23 -> 5, min dihedral 2.45 -> 5.21 deg).
    GProp_GProps area, perimeter;
    BRepGProp::SurfaceProperties(face, area);
    BRepGProp::LinearProperties(face, perimeter);
    const bool wedge = num_edges_of(face) == 3 && perimeter.Mass() > 2 * h;
    if (perimeter.Mass() > 0 && area.Mass() > 0 && !wedge)
      h = std::min(h, kThinFaceFactor * 2 * area.Mass() / perimeter.Mass());
    h = std::max(h, min_size_);
    h = std::min(h, local_face[f]);
    face_sizes_[f] = h;
  }
  for (int s = 1; s <= num_solids; ++s) {
    if (!std::isfinite(local_solid[s])) continue;
    for (TopExp_Explorer it(solids(s), TopAbs_FACE); it.More(); it.Next()) {
      const int f = faces.FindIndex(it.Current());
      if (f > 0) face_sizes_[f] = std::min(face_sizes_[f], local_solid[s]);
    }
  }
  TopTools_IndexedDataMapOfShapeListOfShape edge_faces;
  for (int f = 1; f <= num_faces; ++f) TopExp::MapShapesAndAncestors(faces(f), TopAbs_EDGE, TopAbs_FACE, edge_faces);
  auto faces_of = [&](int e, auto&& visit) {
    const int k = edge_faces.FindIndex(edges(e));
    if (k == 0) return;
    for (const TopoDS_Shape& face : edge_faces(k)) {
      const int f = faces.FindIndex(face);
      if (f > 0) visit(f);
    }
  };
  // Gradation: the size of a face at most `gradation` times that of a face it shares an edge with.
  if (options.gradation > 1) {
    for (bool changed = true; changed;) {
      changed = false;
      for (int e = 1; e <= num_edges; ++e) {
        double smallest = HUGE_VAL;
        faces_of(e, [&](int f) { smallest = std::min(smallest, face_sizes_[f]); });
        faces_of(e, [&](int f) {
          if (face_sizes_[f] > options.gradation * smallest * (1 + 1e-12)) {
            face_sizes_[f] = options.gradation * smallest;
            changed = true;
          }
        });
      }
    }
  }
  edge_sizes_.assign(num_edges + 1, target_);
  for (int e = 1; e <= num_edges; ++e) {
    const TopoDS_Edge edge = TopoDS::Edge(edges(e));
    double h = clamped_curvature_size(max_edge_curvature(edge), target_, min_size_, options.curvature_elements);
    faces_of(e, [&](int f) { h = std::min(h, face_sizes_[f]); });
    edge_sizes_[e] = std::min(h, local_edge[e]);
  }
}

}  // namespace qualmesh::cad
