// Isotropic remeshing of a curved CAD face's triangles on the CAD surface (face_mesh.h, remesh_face_on_surface):
// the last stage of the sized surface mesh, after the Delaunay refinement in the parameter plane (face_mesh.cpp).
//
// Why: the refinement in (u, v) gives every node on the surface, but its triangles are judged in a stretched plane,
// so in space they are uneven (measured at --size 2: smallest corner 10-17 deg, mean smallest corner 40 deg, mean
// edge 0.65-0.75 of the size, 1.6-2.1x Gmsh's surface nodes on the cylinder, sphere and torus of tests/data/cad).
// The volume mesher then keeps every short edge and every poor corner. Gmsh's frontal-Delaunay surfaces have a mean
// edge of about the size and smallest corners above 30 deg.
//
// How: CGAL's Polygon_mesh_processing::isotropic_remeshing (Botsch & Kobbelt, "A remeshing approach to
// multiresolution modeling", SGP 2004: split edges above 4/3 L, collapse below 4/5 L, flip towards valence 6,
// tangential relaxation), on the face's triangles in space, with
//   - every piece of a CAD edge chain constrained and protected (never split, collapsed or moved): the chains are
//     shared with the neighbouring faces, which must see the same points; seams included;
//   - every CAD vertex and chain node fixed;
//   - the projection functor OpenCASCADE's point inversion onto the face's surface (ShapeAnalysis_Surface, from the
//     parameters of the node or of a neighbour): every node the remeshing moves or makes lies on the CAD surface.
// CGAL's remeshing knows the triangles, not the surface: a collapse onto a chain node can leave a triangle of three
// chain nodes standing across the surface (in a cylinder's cap plane, or the plane of a sphere's seam). So it runs
// round by round; after each round such triangles are flipped towards the surface where a flip helps (or split,
// split_standing), and a round that leaves one, or a corner below kSmallestCornerDeg that the refinement's triangles
// did not have, is undone and ends the remeshing (the rounds before it stay). FaceMeshStats says how many rounds
// were kept; with none the refinement's triangles stay, and remesh_refused says why. After the rounds, a curved
// face's edges are flipped to locally Delaunay ones (delaunay_flips).
// CGAL first: OpenCASCADE defines a Handle() macro that CGAL's own Handle templates would expand.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/remesh.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/boost/graph/Euler_operations.h>

#include "face_mesh.h"

#include <BRepAdaptor_Surface.hxx>
#include <BRepLProp_SLProps.hxx>
#include <BRep_Tool.hxx>
#include <ShapeAnalysis_Surface.hxx>
#include <Standard_Failure.hxx>
#include <gp_Pnt2d.hxx>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

namespace qualmesh::cad {

namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Mesh = CGAL::Surface_mesh<K::Point_3>;
using VertexD = Mesh::Vertex_index;
using EdgeD = Mesh::Edge_index;
using FaceD = Mesh::Face_index;
using HalfedgeD = Mesh::Halfedge_index;
namespace PMP = CGAL::Polygon_mesh_processing;

// Relaxation steps per round of split / collapse / flip / relaxation (kRemeshRounds rounds, face_mesh.h).
constexpr int kRelaxationSteps = 3;
// A triangle faces the surface when the cosine between its normal and the surface's is at least this (80 deg).
constexpr double kMinFacing = 0.17;
// A round may not leave a corner below this (degrees), or below the refinement's smallest corner when that is
// smaller (a corner the face's boundary makes): tiny corners are input angles the volume mesher must protect
// (part.step at --size 10: a 1.7 deg corner next to a chain made Rule 1 cascade without end).
constexpr double kSmallestCornerDeg = 5;

gp_Pnt to_gp(const K::Point_3& p) { return gp_Pnt(p.x(), p.y(), p.z()); }

// The angle at p of triangle p, q, r in radians; `degenerate` when an edge at p has no length.
double corner_rad(const K::Point_3& p, const K::Point_3& q, const K::Point_3& r, double degenerate) {
  const K::Vector_3 u = q - p, w = r - p;
  const double n = std::sqrt(u.squared_length() * w.squared_length());
  if (!(n > 0)) return degenerate;
  return std::acos(std::clamp(u * w / n, -1.0, 1.0));
}

double min_corner_deg(const K::Point_3& a, const K::Point_3& b, const K::Point_3& c) {
  auto angle = [](const K::Point_3& p, const K::Point_3& q, const K::Point_3& r) {
    return corner_rad(p, q, r, 0.0) * 180 / M_PI;
  };
  return std::min({angle(a, b, c), angle(b, c, a), angle(c, a, b)});
}

// The face's triangles as a Surface_mesh with, per node, its PLC id, whether it is fixed and its surface parameters
// (once projected), and per edge whether it is a protected chain piece.
class FaceRemesher {
 public:
  FaceRemesher(const TopoDS_Face& face, double size)
      : surface_(face, Standard_False), analysis_(new ShapeAnalysis_Surface(BRep_Tool::Surface(face))),
        precision_(1e-9 * size) {}

  // Builds the mesh; an empty string, or why the triangles cannot be remeshed.
  std::string build(const std::vector<SurfaceTriangle>& triangles, const std::function<bool(Index)>& fixed,
                    const std::function<bool(Index, Index)>& is_piece, const std::vector<Point3>& source) {
    std::vector<K::Point_3> points;
    std::vector<Index> ids;
    std::map<Index, std::size_t> local;
    std::vector<std::vector<std::size_t>> polygons;
    for (const SurfaceTriangle& t : triangles) {
      std::vector<std::size_t> polygon;
      for (Index id : t) {
        auto [it, added] = local.emplace(id, points.size());
        if (added) {
          points.emplace_back(source[id][0], source[id][1], source[id][2]);
          ids.push_back(id);
        }
        polygon.push_back(it->second);
      }
      polygons.push_back(std::move(polygon));
    }
    // Non-manifold corners (a face touching itself at a node) are split apart by the orientation pass; the copies
    // keep the PLC id (they are fixed nodes).
    if (!PMP::is_polygon_soup_a_polygon_mesh(polygons)) {
      const std::size_t num_original = points.size();
      PMP::orient_polygon_soup(points, polygons);
      std::map<std::array<double, 3>, Index> by_position;
      for (std::size_t i = 0; i < num_original; ++i)
        by_position.emplace(std::array<double, 3>{points[i].x(), points[i].y(), points[i].z()}, ids[i]);
      for (std::size_t i = num_original; i < points.size(); ++i) {
        auto it = by_position.find({points[i].x(), points[i].y(), points[i].z()});
        if (it == by_position.end() || !fixed(it->second)) return "a non-manifold interior node";
        ids.push_back(it->second);
      }
      if (!PMP::is_polygon_soup_a_polygon_mesh(polygons)) return "its triangles are no surface";
    }
    PMP::polygon_soup_to_polygon_mesh(points, polygons, mesh_);
    if (mesh_.number_of_faces() != polygons.size()) return "its triangles are no surface";
    mesh_.add_property_map<VertexD, Index>("v:plc", kNoIndex);
    mesh_.add_property_map<VertexD, bool>("v:fixed", false);
    mesh_.add_property_map<EdgeD, bool>("e:fixed", false);
    mesh_.add_property_map<VertexD, gp_Pnt2d>("v:uv", gp_Pnt2d());
    mesh_.add_property_map<VertexD, bool>("v:has_uv", false);
    fetch_maps();
    std::size_t k = 0;
    for (VertexD v : mesh_.vertices()) {  // polygon_soup_to_polygon_mesh adds the points in order
      plc_id_[v] = ids[k++];
      vertex_fixed_[v] = fixed(plc_id_[v]);
    }
    for (EdgeD e : mesh_.edges()) {
      const VertexD a = mesh_.source(mesh_.halfedge(e)), b = mesh_.target(mesh_.halfedge(e));
      if (mesh_.is_border(e) || (vertex_fixed_[a] && vertex_fixed_[b] && is_piece(plc_id_[a], plc_id_[b]))) {
        edge_fixed_[e] = true;
        longest_piece_ = std::max(longest_piece_, std::sqrt(CGAL::squared_distance(mesh_.point(a), mesh_.point(b))));
      }
    }
    floor_angle_deg_ = min_angle_deg();
    return "";
  }

  // The smallest corner angle of triangle f, in degrees.
  double smallest_corner(FaceD f) const {
    const std::array<VertexD, 3> v = corners(f);
    return min_corner_deg(mesh_.point(v[0]), mesh_.point(v[1]), mesh_.point(v[2]));
  }

  // The smallest corner angle of the triangles, in degrees.
  double min_angle_deg() const {
    double angle = 180;
    for (FaceD f : mesh_.faces()) angle = std::min(angle, smallest_corner(f));
    return angle;
  }

  // Protected edges must be at most 4/3 of the target (CGAL's precondition): a longer chain piece lifts it.
  double target_for(double size) const { return std::max(size, 0.76 * longest_piece_); }

  // One round of the remeshing towards edges of length `target`, then the mending flips. Empty, or why the round was
  // undone (the mesh is then as it was before it).
  std::string round(double target) {
    const Mesh before = mesh_;
    std::string why = "the remeshing failed";
    try {
      const auto project_node = [this](VertexD v) { return project(v); };
      // Splits first, then collapses, flips, relaxation and projection. On a plane the collapses hold the nodes
      // next to the face's border too (a collapse onto a border node is what stood triangles across the cylinder's
      // caps; the cantilever of examples/ needs 551 nodes for its C3D10 tip deflection within 0.5 % this way, 635
      // without). On a curved face they do not: a face a few elements wide kept the refinement's small triangles
      // along its whole border (t20_data.step's 30 mm cylindrical faces at --size 5.877: 141 triangles where Gmsh
      // makes 92; the cylinder of tests/data: corners down to 13 deg, 26.5 now). A collapse that stands a triangle
      // across the surface is mended, or its round undone (mend).
      PMP::isotropic_remeshing(faces(mesh_), target, mesh_,
                               CGAL::parameters::number_of_iterations(1)
                                   .do_collapse(false)
                                   .do_flip(false)
                                   .number_of_relaxation_steps(0)
                                   .protect_constraints(true)
                                   .edge_is_constrained_map(edge_fixed_)
                                   .vertex_is_constrained_map(vertex_fixed_)
                                   .projection_functor(project_node));
      auto held = mesh_.add_property_map<VertexD, bool>("v:held", false).first;
      for (VertexD v : mesh_.vertices()) held[v] = vertex_fixed_[v];
      if (surface_.GetType() == GeomAbs_Plane)  // the neighbours of nodes on the face's border
        for (VertexD v : mesh_.vertices())
          if (mesh_.is_border(v))
            for (VertexD w : CGAL::vertices_around_target(mesh_.halfedge(v), mesh_)) held[w] = true;
      PMP::isotropic_remeshing(faces(mesh_), target, mesh_,
                               CGAL::parameters::number_of_iterations(1)
                                   .do_split(false)
                                   .do_flip(false)
                                   .number_of_relaxation_steps(0)
                                   .do_project(false)
                                   .protect_constraints(true)
                                   .edge_is_constrained_map(edge_fixed_)
                                   .vertex_is_constrained_map(held));
      mesh_.remove_property_map(held);
      PMP::isotropic_remeshing(faces(mesh_), target, mesh_,
                               CGAL::parameters::number_of_iterations(1)
                                   .do_split(false)
                                   .do_collapse(false)
                                   .number_of_relaxation_steps(kRelaxationSteps)
                                   .protect_constraints(true)
                                   .edge_is_constrained_map(edge_fixed_)
                                   .vertex_is_constrained_map(vertex_fixed_)
                                   .projection_functor(project_node));
      if (CGAL::is_valid_polygon_mesh(mesh_) && all_triangles()) {
        if (!mend()) {
          why = "it left a triangle standing across the surface";
        } else {
          flip_small_corners();
          const double corner = min_angle_deg();
          if (corner >= std::min(floor_angle_deg_, kSmallestCornerDeg)) return "";
          char text[120];
          std::snprintf(text, sizeof text, "it made a corner of %.3g deg (the refinement's smallest: %.3g)", corner,
                        floor_angle_deg_);
          why = text;
        }
      }
    } catch (const Standard_Failure&) {
      why = "OpenCASCADE failed to project a node";
    } catch (const std::exception&) {
    }
    mesh_ = before;
    fetch_maps();
    return why;
  }

  // Flips h's edge and keeps the flip when it raises the smaller smallest corner of its two triangles, both still
  // face the surface, and `also_keep()` holds after it; otherwise flips back. Returns whether the flip stays. The
  // caller has checked that the other diagonal is no edge yet.
  template <class AlsoKeep>
  bool flip_if_better(HalfedgeD h, AlsoKeep also_keep) {
    const double was = std::min(smallest_corner(mesh_.face(h)), smallest_corner(mesh_.face(mesh_.opposite(h))));
    CGAL::Euler::flip_edge(h, mesh_);
    const FaceD f = mesh_.face(h), g = mesh_.face(mesh_.opposite(h));
    if (also_keep() && std::min(smallest_corner(f), smallest_corner(g)) > was && facing(f) > kMinFacing &&
        facing(g) > kMinFacing)
      return true;
    CGAL::Euler::flip_edge(h, mesh_);
    return false;
  }

  // How much the two triangles of halfedge h bend against each other: 1 - the cosine of the angle between their
  // normals (0: coplanar).
  double bend(HalfedgeD h) const {
    const auto normal = [&](HalfedgeD g) {
      const K::Point_3 &a = mesh_.point(mesh_.source(g)), &b = mesh_.point(mesh_.target(g)),
                       &c = mesh_.point(mesh_.target(mesh_.next(g)));
      const K::Vector_3 n = CGAL::cross_product(b - a, c - a);
      return n / std::sqrt(n.squared_length());
    };
    return 1 - normal(h) * normal(mesh_.opposite(h));
  }

  // Flips every free edge whose two opposite corners sum to more than 180 degrees (the edge is not locally
  // Delaunay), pass after pass until none flips (at most kFlipPasses), where the flip keeps both triangles facing
  // the surface, bends the two no more than before and raises their smallest corner (the max-min angle rule, which
  // in a plane is the Delaunay flip itself). Why: the volume mesher keeps every edge of a curved face as an input
  // segment and splits those missing from the Delaunay tetrahedralization of the surface's nodes (Rule 1's
  // conformity recovery); the remeshing's flips aim at valence 6, not at Delaunay edges (model1.igs at a tenth of
  // its diagonal: 77 of 3038 inner edges not locally Delaunay, 1 after). Without the bend condition, over the CAD
  // files of ../shared/data/cad at three sizes each, tets below 10 deg rose 252 -> 297 (creases between facets are
  // small input angles); with it they fell to 237, at 3.6% fewer nodes. Planar faces are left alone: the volume
  // mesher triangulates them itself. Returns the number of flips.
  std::size_t delaunay_flips() {
    if (surface_.GetType() == GeomAbs_Plane) return 0;
    constexpr int kFlipPasses = 8;
    auto corner = [&](VertexD p, VertexD q, VertexD r) {
      return corner_rad(mesh_.point(p), mesh_.point(q), mesh_.point(r), M_PI);
    };
    std::size_t total = 0;
    for (int pass = 0; pass < kFlipPasses; ++pass) {
      std::size_t flips = 0;
      for (EdgeD e : mesh_.edges()) {
        if (edge_fixed_[e] || mesh_.is_border(e)) continue;
        const HalfedgeD h = mesh_.halfedge(e);
        const VertexD a = mesh_.source(h), b = mesh_.target(h);
        const VertexD c = mesh_.target(mesh_.next(h)), d = mesh_.target(mesh_.next(mesh_.opposite(h)));
        if (corner(c, a, b) + corner(d, a, b) <= M_PI * (1 + 1e-9)) continue;
        if (mesh_.halfedge(c, d) != Mesh::null_halfedge()) continue;
        const double fold = bend(h);
        flips += flip_if_better(h, [&] { return bend(h) <= fold; });
      }
      total += flips;
      if (flips == 0) break;
    }
    return total;
  }

  // The triangles with PLC ids: fixed nodes keep theirs, the others are appended to `vertices`. Also the smallest
  // corner and the largest distance from the surface of a triangle's centroid or of the midpoint of an edge that is
  // not a chain piece (those are measured by brep_to_plc's sagitta): a skinny triangle strays furthest at its long
  // edge, and the face's tolerance must cover every point of its facets (bottle.brep's neck: points 0.056 off
  // Face6 against a tolerance of 0.043 from the centroids alone).
  std::vector<SurfaceTriangle> triangles(std::vector<Point3>& vertices, double* min_angle, double* chord_error) {
    std::vector<SurfaceTriangle> out;
    std::map<VertexD, Index> new_id;
    *min_angle = 180;
    *chord_error = 0;
    for (FaceD f : mesh_.faces()) {
      const std::array<VertexD, 3> v = corners(f);
      SurfaceTriangle t{};
      for (int i = 0; i < 3; ++i) {
        if (vertex_fixed_[v[i]]) {
          t[i] = plc_id_[v[i]];
          continue;
        }
        auto [it, inserted] = new_id.emplace(v[i], kNoIndex);
        if (inserted) {
          const K::Point_3& p = mesh_.point(v[i]);
          vertices.push_back({p.x(), p.y(), p.z()});
          it->second = static_cast<Index>(vertices.size() - 1);
        }
        t[i] = it->second;
      }
      const K::Point_3 &a = mesh_.point(v[0]), &b = mesh_.point(v[1]), &c = mesh_.point(v[2]);
      *min_angle = std::min(*min_angle, min_corner_deg(a, b, c));
      const auto stray = [&](const K::Point_3& p) {
        const gp_Pnt2d uv = parameters_near(p, v);
        *chord_error = std::max(*chord_error, surface_.Value(uv.X(), uv.Y()).Distance(to_gp(p)));
      };
      stray(CGAL::centroid(a, b, c));
      for (int i = 0; i < 3; ++i) {
        const HalfedgeD h = mesh_.halfedge(v[i], v[(i + 1) % 3]);  // each inner edge once, from its smaller end
        if (h != Mesh::null_halfedge() && !edge_fixed_[mesh_.edge(h)] && v[i] < v[(i + 1) % 3])
          stray(CGAL::midpoint(mesh_.point(v[i]), mesh_.point(v[(i + 1) % 3])));
      }
      out.push_back(t);
    }
    return out;
  }

 private:
  void fetch_maps() {
    plc_id_ = mesh_.property_map<VertexD, Index>("v:plc").first;
    vertex_fixed_ = mesh_.property_map<VertexD, bool>("v:fixed").first;
    edge_fixed_ = mesh_.property_map<EdgeD, bool>("e:fixed").first;
    uv_ = mesh_.property_map<VertexD, gp_Pnt2d>("v:uv").first;
    has_uv_ = mesh_.property_map<VertexD, bool>("v:has_uv").first;
  }

  std::array<VertexD, 3> corners(FaceD f) const {
    const HalfedgeD h = mesh_.halfedge(f);
    return {mesh_.source(h), mesh_.target(h), mesh_.target(mesh_.next(h))};
  }

  bool all_triangles() const {
    for (FaceD f : mesh_.faces())
      if (mesh_.next(mesh_.next(mesh_.next(mesh_.halfedge(f)))) != mesh_.halfedge(f)) return false;
    return true;
  }

  // The projection functor: the surface point nearest to a node, by OpenCASCADE's point inversion started from the
  // parameters of the node (when it has some) or of a neighbour; the parameters found are kept for the next call.
  K::Point_3 project(VertexD v) {
    const K::Point_3 p = mesh_.point(v);
    gp_Pnt2d hint;
    bool found = has_uv_[v];
    if (found) hint = uv_[v];
    for (HalfedgeD h : CGAL::halfedges_around_target(mesh_.halfedge(v), mesh_)) {
      if (found) break;
      const VertexD w = mesh_.source(h);
      if (has_uv_[w]) hint = uv_[w], found = true;
    }
    const gp_Pnt2d uv =
        found ? analysis_->NextValueOfUV(hint, to_gp(p), precision_) : analysis_->ValueOfUV(to_gp(p), precision_);
    if (!std::isfinite(uv.X()) || !std::isfinite(uv.Y())) return p;
    uv_[v] = uv;
    has_uv_[v] = true;
    const gp_Pnt q = surface_.Value(uv.X(), uv.Y());
    return K::Point_3(q.X(), q.Y(), q.Z());
  }

  // The surface parameters of the point nearest to p, a point of a triangle with corners v: OpenCASCADE's point
  // inversion started from a corner's parameters when one has some (a local search, against a global one whose
  // sampling grid took 70% of wrenchnut.stp's surface meshing), else the global one.
  gp_Pnt2d parameters_near(const K::Point_3& p, const std::array<VertexD, 3>& v) const {
    for (VertexD w : v)
      if (has_uv_[w]) return analysis_->NextValueOfUV(uv_[w], to_gp(p), precision_);
    return analysis_->ValueOfUV(to_gp(p), precision_);
  }

  // How triangle f lies against the surface: the cosine of the angle between its normal and the surface's normal at
  // the surface point nearest its centroid (the face is FORWARD: its triangles turn counter-clockwise about the
  // surface's normal, as mesh_curved_face makes them); 1 where the normal is not defined (a pole).
  double facing(FaceD f) const {
    const std::array<VertexD, 3> v = corners(f);
    const K::Point_3 &a = mesh_.point(v[0]), &b = mesh_.point(v[1]), &c = mesh_.point(v[2]);
    const K::Vector_3 normal = CGAL::cross_product(b - a, c - a);
    const double length = std::sqrt(normal.squared_length());
    if (!(length > 0)) return -1.0;
    const gp_Pnt2d uv = parameters_near(CGAL::centroid(a, b, c), v);
    BRepLProp_SLProps props(surface_, uv.X(), uv.Y(), 1, precision_);
    if (!props.IsNormalDefined()) return 1.0;
    const gp_Dir n = props.Normal();
    return (normal.x() * n.X() + normal.y() * n.Y() + normal.z() * n.Z()) / length;
  }

  // Triangles with a corner below kSmallestCornerDeg (a collapse or a relaxation next to a held node makes a few):
  // the free edge opposite their largest corner is flipped when that raises the smallest corner of the two
  // triangles and both still face the surface.
  void flip_small_corners() {
    for (int pass = 0; pass < 3; ++pass) {
      std::size_t flips = 0;
      for (FaceD f : mesh_.faces()) {
        if (smallest_corner(f) >= kSmallestCornerDeg) continue;
        HalfedgeD longest = Mesh::null_halfedge();
        double length = 0;
        const HalfedgeD h0 = mesh_.halfedge(f);
        for (HalfedgeD h : {h0, mesh_.next(h0), mesh_.prev(h0)}) {
          const double l = CGAL::squared_distance(mesh_.point(mesh_.source(h)), mesh_.point(mesh_.target(h)));
          if (l > length) length = l, longest = h;
        }
        const EdgeD e = mesh_.edge(longest);
        if (edge_fixed_[e] || mesh_.is_border(e)) continue;
        const VertexD c = mesh_.target(mesh_.next(longest)), d = mesh_.target(mesh_.next(mesh_.opposite(longest)));
        if (mesh_.halfedge(c, d) != Mesh::null_halfedge()) continue;
        flips += flip_if_better(longest, [] { return true; });
      }
      if (flips == 0) break;
    }
  }

  // Flips the free edges of triangles that stand across the surface while a flip turns both of its triangles
  // towards the surface. True when every triangle faces the surface at the end.
  bool mend() {
    for (int pass = 0; pass < 8; ++pass) {
      std::size_t left = 0, mended = 0;
      for (FaceD f : mesh_.faces()) {
        if (facing(f) > kMinFacing) continue;
        const HalfedgeD h0 = mesh_.halfedge(f);
        bool done = false;
        for (HalfedgeD h : {h0, mesh_.next(h0), mesh_.prev(h0)}) {
          const EdgeD e = mesh_.edge(h);
          if (edge_fixed_[e] || mesh_.is_border(e)) continue;
          const VertexD c = mesh_.target(mesh_.next(h)), d = mesh_.target(mesh_.next(mesh_.opposite(h)));
          if (mesh_.halfedge(c, d) != Mesh::null_halfedge()) continue;  // the flipped edge exists already
          const double was = std::min(facing(mesh_.face(h)), facing(mesh_.face(mesh_.opposite(h))));
          CGAL::Euler::flip_edge(h, mesh_);
          const double is = std::min(facing(mesh_.face(h)), facing(mesh_.face(mesh_.opposite(h))));
          if (is > was && is > 0) {
            done = true;
            break;
          }
          CGAL::Euler::flip_edge(h, mesh_);
        }
        if (!done) done = split_standing(f);
        done ? ++mended : ++left;
      }
      if (left == 0) return true;
      if (mended == 0) return false;
    }
    return false;
  }

  // A triangle of three fixed nodes standing across the surface (a collapse onto a chain node left it; so can a fan
  // of such triangles), which no flip mends: its longest free edge ac is split, and the new node m put on the
  // surface beside the opposite node b, across the chord in the tangent plane, at most as far from b as an equilateral
  // triangle on ac would put it, where the triangles around m face the surface best. True when they all face it.
  bool split_standing(FaceD f) {
    HalfedgeD free = Mesh::null_halfedge();
    double longest = 0;
    const HalfedgeD h0 = mesh_.halfedge(f);
    for (HalfedgeD h : {h0, mesh_.next(h0), mesh_.prev(h0)}) {
      if (!vertex_fixed_[mesh_.target(h)]) return false;
      const double length = std::sqrt(CGAL::squared_distance(mesh_.point(mesh_.source(h)), mesh_.point(mesh_.target(h))));
      if (!edge_fixed_[mesh_.edge(h)] && !mesh_.is_border(mesh_.edge(h)) && length > longest) free = h, longest = length;
    }
    if (free == Mesh::null_halfedge()) return false;
    const K::Point_3 pa = mesh_.point(mesh_.source(free)), pc = mesh_.point(mesh_.target(free));
    const K::Point_3 pb = mesh_.point(mesh_.target(mesh_.next(free)));
    const gp_Pnt2d uv = analysis_->ValueOfUV(to_gp(pb), precision_);
    BRepLProp_SLProps props(surface_, uv.X(), uv.Y(), 1, precision_);
    if (!props.IsNormalDefined()) return false;
    const K::Vector_3 n(props.Normal().X(), props.Normal().Y(), props.Normal().Z());
    const K::Vector_3 across = CGAL::cross_product(n, (pc - pa) / longest);  // in the tangent plane
    const HalfedgeD opposite = mesh_.opposite(free);
    const bool two_sided = !mesh_.is_border(opposite);
    const HalfedgeD added = CGAL::Euler::split_edge(free, mesh_);  // a -> m, then m -> c is `free`
    const VertexD m = mesh_.target(added);
    CGAL::Euler::split_face(added, mesh_.next(free), mesh_);  // m to b
    if (two_sided) CGAL::Euler::split_face(opposite, mesh_.next(mesh_.opposite(added)), mesh_);  // m to the far node
    auto worst_around_m = [&]() {
      double worst = 1;
      for (HalfedgeD h : CGAL::halfedges_around_target(mesh_.halfedge(m), mesh_))
        if (!mesh_.is_border(h)) worst = std::min(worst, facing(mesh_.face(h)));
      return worst;
    };
    double best = -2;
    K::Point_3 best_point = pb;
    for (double step : {0.866, -0.866, 0.5, -0.5, 0.25, -0.25}) {
      mesh_.point(m) = pb + across * (step * longest);
      has_uv_[m] = false;
      mesh_.point(m) = project(m);
      const double worst = worst_around_m();
      if (worst > best) best = worst, best_point = mesh_.point(m);
    }
    mesh_.point(m) = best_point;
    has_uv_[m] = false;
    return best > kMinFacing;
  }

  Mesh mesh_;
  Mesh::Property_map<VertexD, Index> plc_id_;
  Mesh::Property_map<VertexD, bool> vertex_fixed_;
  Mesh::Property_map<EdgeD, bool> edge_fixed_;
  Mesh::Property_map<VertexD, gp_Pnt2d> uv_;
  Mesh::Property_map<VertexD, bool> has_uv_;
  double longest_piece_ = 0;
  double floor_angle_deg_ = 0;  // the refinement's smallest corner
  BRepAdaptor_Surface surface_;
  Handle(ShapeAnalysis_Surface) analysis_;
  double precision_;
};

}  // namespace

std::vector<SurfaceTriangle> remesh_face_on_surface(const TopoDS_Face& face, double size,
                                                    const std::vector<SurfaceTriangle>& triangles,
                                                    const std::function<bool(Index)>& fixed,
                                                    const std::function<bool(Index, Index)>& is_piece,
                                                    const std::vector<Point3>& source, std::vector<Point3>& vertices,
                                                    FaceMeshStats& stats) {
  // The refinement's triangles as they were, their interior nodes appended to `vertices` anew.
  auto keep = [&](const std::string& why) {
    stats.remesh_refused = why;
    std::map<Index, Index> moved;
    std::vector<SurfaceTriangle> same = triangles;
    for (SurfaceTriangle& t : same)
      for (Index& id : t) {
        if (fixed(id)) continue;
        auto [it, inserted] = moved.emplace(id, static_cast<Index>(vertices.size()));
        if (inserted) vertices.push_back(source[id]);
        id = it->second;
      }
    return same;
  };
  FaceRemesher remesher(face, size);
  const std::string why = remesher.build(triangles, fixed, is_piece, source);
  if (!why.empty()) return keep(why);
  const double target = remesher.target_for(size);
  int kept = 0;
  std::string stop;
  while (kept < kRemeshRounds && (stop = remesher.round(target)).empty()) ++kept;
  if (kept == 0) return keep("the first round: " + stop);
  stats.num_delaunay_flips = remesher.delaunay_flips();
  stats.remeshed = true;
  stats.num_remesh_rounds = kept;
  stats.remesh_refused = stop;  // why it stopped early, if it did
  return remesher.triangles(vertices, &stats.min_angle_deg, &stats.max_chord_error);
}

}  // namespace qualmesh::cad
