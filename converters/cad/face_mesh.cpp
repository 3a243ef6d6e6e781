// Sized surface mesh of the CAD faces (face_mesh.h).
//
// Edges: uniform in arc length (GCPnts_UniformAbscissa), so that a chain depends on the edge and its size only and
// the faces on both sides see the same points.
//
// Curved faces: Delaunay refinement in the parameter plane, with the quality measured in space (Chew's second
// algorithm, "Guaranteed-quality mesh generation for curved surfaces", SoCG 1993, run on the surface through its
// parametrisation). The boundary nodes (the edge chains, mapped into (u, v) by each edge's curve on the face, a seam
// edge twice) are the constrained edges of a 2D constrained Delaunay triangulation of the plane (s(u), t(v)), s and
// t the face's mean arc length along u and v (exact isometry on cylinders, a bounded stretch on tori and cones, an
// unbounded one at a sphere's poles). A triangle is bad when its 3D circumradius exceeds kRadiusFactor * size or its
// smallest angle in the plane is below kMinAngleDeg; its plane circumcentre is inserted (the surface point over it,
// wrapped into the face's period across a seam; try_insert can also project a 3D centre, unused). A centre outside the
// face or in the diametral circle of a boundary piece is not inserted, and the edge chains stay as the size field cut
// them: splitting the pieces such centres encroach (Chew's rule, shared by every face of the edge and meshed again)
// cascaded across faces, and the volume mesh then had 1.1-4.5x the nodes and mostly more bad tets (brep_to_plc.cpp,
// kMaxSplitPasses, removed). New nodes are points of the surface, exactly.
// CGAL first: OpenCASCADE defines a Handle() macro that CGAL's own Handle templates would expand.
#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include "face_mesh.h"

#include <BRepAdaptor_Curve.hxx>
#include <BRepAdaptor_Surface.hxx>
#include <BRepGProp.hxx>
#include <BRepTools.hxx>
#include <BRep_Tool.hxx>
#include <GCPnts_AbscissaPoint.hxx>
#include <GCPnts_UniformAbscissa.hxx>
#include <GProp_GProps.hxx>
#include <Geom2d_Curve.hxx>
#include <Geom_Surface.hxx>
#include <ShapeAnalysis_Surface.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <gp_Pnt2d.hxx>

#include <algorithm>
#include <cmath>
#include <deque>
#include <map>

#include "qualmesh/error.h"

namespace qualmesh::cad {

namespace {

// Circumradius of a good triangle at most this times the face size: an equilateral triangle of side 1.21 * size,
// which with the shorter edges at the boundary gives Gmsh's node count at equal size (measured on part.step).
constexpr double kRadiusFactor = 0.7;
// Smallest 3D corner angle the refinement aims at (Chew's algorithm reaches 30 away from the boundary).
constexpr double kMinAngleDeg = 25;
// Shape refinement stops at triangles this small relative to the size (no cascade towards a corner the boundary
// makes acute: those keep the angle the boundary gives them).
constexpr double kSmallestRadiusFactor = 0.2;
constexpr int kMaxRounds = 60;
constexpr int kGrid = 7;  // samples across, for each knot of the stretch tables
constexpr int kStretchKnots = 32;

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
struct VertexInfo {
  Index id = kNoIndex;  // PLC id (boundary nodes) or kNoIndex (interior, numbered at the end)
  gp_Pnt point;         // 3D position
  double u = 0, v = 0;  // unscaled parameters
};
struct FaceInfo {
  int nesting = -1;  // number of constrained edges crossed from the outside; odd = inside the face
  bool inside() const { return nesting % 2 == 1; }
};
using Vb = CGAL::Triangulation_vertex_base_with_info_2<VertexInfo, K>;
using Fbi = CGAL::Triangulation_face_base_with_info_2<FaceInfo, K>;
using Fb = CGAL::Constrained_triangulation_face_base_2<K, Fbi>;
using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
using Cdt = CGAL::Constrained_Delaunay_triangulation_2<K, Tds, CGAL::Exact_predicates_tag>;
using Point2 = K::Point_2;

double angle_deg(const gp_Pnt& a, const gp_Pnt& b, const gp_Pnt& c) {  // at a
  const gp_Vec u(a, b), w(a, c);
  if (u.Magnitude() <= 0 || w.Magnitude() <= 0) return 0;
  return u.Angle(w) * 180 / M_PI;
}

// Circumcentre of a 3D triangle (in its plane) and its radius; false for a degenerate triangle.
bool circumcentre(const gp_Pnt& a, const gp_Pnt& b, const gp_Pnt& c, gp_Pnt& centre, double& radius) {
  const gp_Vec ab(a, b), ac(a, c);
  const gp_Vec n = ab.Crossed(ac);
  const double sq_n = n.SquareMagnitude();
  if (!(sq_n > 0)) return false;
  const gp_Vec offset = (n.Crossed(ab) * ac.SquareMagnitude() + ac.Crossed(n) * ab.SquareMagnitude()) / (2 * sq_n);
  centre = a.Translated(offset);
  radius = offset.Magnitude();
  return true;
}

// Marks each face with its nesting level (the CGAL 2D polygon-triangulation example's flood fill).
void mark_nesting(Cdt& cdt) {
  for (auto f = cdt.all_faces_begin(); f != cdt.all_faces_end(); ++f) f->info().nesting = -1;
  std::deque<std::pair<Cdt::Face_handle, int>> border{{cdt.infinite_face(), 0}};
  while (!border.empty()) {
    auto [start, level] = border.front();
    border.pop_front();
    if (start->info().nesting != -1) continue;
    std::deque<Cdt::Face_handle> queue{start};
    while (!queue.empty()) {
      Cdt::Face_handle f = queue.front();
      queue.pop_front();
      if (f->info().nesting != -1) continue;
      f->info().nesting = level;
      for (int i = 0; i < 3; ++i) {
        Cdt::Face_handle n = f->neighbor(i);
        if (n->info().nesting != -1) continue;
        if (cdt.is_constrained({f, i})) border.push_back({n, level + 1});
        else queue.push_back(n);
      }
    }
  }
}

class FaceMesher {
 public:
  FaceMesher(const TopoDS_Face& face, int face_number, double size, std::vector<Point3>& vertices,
             const std::string& file)
      : face_(face), number_(face_number), size_(size), vertices_(vertices), file_(file),
        surface_(face, Standard_False), analysis_(new ShapeAnalysis_Surface(BRep_Tool::Surface(face))) {
    BRepTools::UVBounds(face, u0_, u1_, v0_, v1_);
    build_stretch();
  }

  void add_boundary(const std::function<const EdgeChain&(const TopoDS_Edge&)>& chain_of,
                    const std::function<Index(const TopoDS_Vertex&)>& vertex_id) {
    for (TopExp_Explorer it(face_, TopAbs_EDGE); it.More(); it.Next()) {
      const TopoDS_Edge edge = TopoDS::Edge(it.Current());
      double first = 0, last = 0;
      Handle(Geom2d_Curve) pcurve = BRep_Tool::CurveOnSurface(edge, face_, first, last);
      if (pcurve.IsNull())
        throw InputError(ErrorCode::Parse, "Face" + std::to_string(number_) + " has an edge without a curve on it",
                         file_);
      std::vector<Index> ids;
      std::vector<double> params;
      if (BRep_Tool::Degenerated(edge)) {
        // A pole or apex: one 3D point, a segment in (u, v). Cut it at about the face's size in the scaled plane.
        TopoDS_Vertex a, b;
        TopExp::Vertices(edge, a, b);
        const gp_Pnt2d p = pcurve->Value(first), q = pcurve->Value(last);
        const double length = std::sqrt(CGAL::squared_distance(plane_point(p.X(), p.Y()), plane_point(q.X(), q.Y())));
        const int n = std::max(2, static_cast<int>(std::ceil(length / size_)));
        for (int i = 0; i <= n; ++i) params.push_back(first + (last - first) * i / n), ids.push_back(vertex_id(a));
      } else {
        const EdgeChain& chain = chain_of(edge);
        ids = chain.ids;
        params = chain.params;
      }
      Cdt::Vertex_handle previous;
      for (std::size_t i = 0; i < ids.size(); ++i) {
        const gp_Pnt2d uv = pcurve->Value(params[i]);
        const Point2 scaled = plane_point(uv.X(), uv.Y());
        // The ends of two edges at one CAD vertex meet in (u, v) only to the edges' tolerances: the first point of
        // that vertex near this one (a seam keeps its two sides a period apart) serves both.
        const bool end = i == 0 || i + 1 == ids.size();
        Cdt::Vertex_handle v;
        if (end) {
          double best = 0.2 * size_;
          for (const Cdt::Vertex_handle& w : corners_[ids[i]]) {
            const double d = std::sqrt(CGAL::squared_distance(w->point(), scaled));
            if (d < best) best = d, v = w;
          }
        }
        if (v == Cdt::Vertex_handle()) {
          v = cdt_.insert(scaled);
          if (end) corners_[ids[i]].push_back(v);
        }
        if (v->info().id == kNoIndex) {
          const Point3& p = vertices_[ids[i]];
          v->info() = {ids[i], gp_Pnt(p[0], p[1], p[2]), uv.X(), uv.Y()};
        }
        if (previous != Cdt::Vertex_handle() && previous != v) cdt_.insert_constraint(previous, v);
        previous = v;
      }
    }
    // Every boundary point got its info when first inserted; a constraint crossing (Exact_predicates_tag) would add
    // a point without one: the face's curves on the surface intersect, which is bad input.
    for (auto v = cdt_.finite_vertices_begin(); v != cdt_.finite_vertices_end(); ++v)
      if (v->info().id == kNoIndex)
        throw InputError(ErrorCode::Intersection,
                         "the boundary curves of Face" + std::to_string(number_) + " cross in its parameter plane",
                         file_);
    mark_nesting(cdt_);
    GProp_GProps props;
    BRepGProp::SurfaceProperties(face_, props);
    const double area = std::fabs(props.Mass());
    budget_ = static_cast<std::size_t>(std::min(2e6, 20 * area / (0.4 * size_ * size_) + 2000));
  }

  void refine(FaceMeshStats& stats) {
    for (int round = 0; round < kMaxRounds; ++round) {
      struct Candidate {
        double priority;
        gp_Pnt centre;
        double radius;
        Point2 hint;
        double u, v;
        bool shape_only;       // good size, bad shape: insert the plane circumcentre
        Point2 plane_centre;
      };
      std::vector<Candidate> candidates;
      for (auto f = cdt_.finite_faces_begin(); f != cdt_.finite_faces_end(); ++f) {
        if (!f->info().inside()) continue;
        const VertexInfo &a = f->vertex(0)->info(), &b = f->vertex(1)->info(), &c = f->vertex(2)->info();
        if (collapsed(a, b, c)) continue;
        gp_Pnt centre;
        double radius = 0;
        if (!circumcentre(a.point, b.point, c.point, centre, radius)) continue;
        // Shape is judged in the plane, where circumcentres improve it (Ruppert, Chew); in space an anisotropic
        // stretch (a torus's inner and outer sides, a sphere's poles) would make refinement cascade without end.
        const Point2 &pa = f->vertex(0)->point(), &pb = f->vertex(1)->point(), &pc = f->vertex(2)->point();
        const double min_angle = plane_min_angle_deg(pa, pb, pc);
        const bool too_big = radius > kRadiusFactor * size_;
        if (!too_big && (min_angle >= kMinAngleDeg || radius < kSmallestRadiusFactor * size_)) continue;
        candidates.push_back({too_big ? radius / size_ + 10 : 1 / std::max(min_angle, 1e-3), centre, radius,
                              CGAL::centroid(pa, pb, pc), (a.u + b.u + c.u) / 3, (a.v + b.v + c.v) / 3, !too_big,
                              CGAL::circumcenter(pa, pb, pc)});
      }
      std::stable_sort(candidates.begin(), candidates.end(),
                       [](const Candidate& x, const Candidate& y) { return x.priority > y.priority; });
      std::size_t inserted = 0, rejected = 0;
      for (const Candidate& c : candidates) {
        if (stats.num_inserted >= budget_) {
          stats.capped = true;
          break;
        }
        // The plane circumcentre for both criteria: a projected 3D centre sits off the plane's circumcircle and
        // leaves plane slivers that shape refinement then chases (torus.brep: 2990 nodes instead of 1446).
        const Outcome outcome = try_insert(c.centre, c.radius, c.hint, c.u, c.v, &c.plane_centre);
        if (outcome == Outcome::Inserted) ++inserted, ++stats.num_inserted;
        else ++rejected;
      }
      stats.num_rejected = rejected;
      if (inserted == 0 || stats.capped) break;
    }
  }

  std::vector<SurfaceTriangle> triangles(FaceMeshStats& stats) {
    for (auto v = cdt_.finite_vertices_begin(); v != cdt_.finite_vertices_end(); ++v) {
      if (v->info().id != kNoIndex) continue;
      const gp_Pnt& p = v->info().point;
      vertices_.push_back({p.X(), p.Y(), p.Z()});
      v->info().id = static_cast<Index>(vertices_.size() - 1);
    }
    std::vector<SurfaceTriangle> out;
    for (auto f = cdt_.finite_faces_begin(); f != cdt_.finite_faces_end(); ++f) {
      if (!f->info().inside()) continue;
      const VertexInfo &a = f->vertex(0)->info(), &b = f->vertex(1)->info(), &c = f->vertex(2)->info();
      if (a.id == b.id || b.id == c.id || a.id == c.id) continue;
      out.push_back({a.id, b.id, c.id});
      stats.min_angle_deg = std::min({stats.min_angle_deg, angle_deg(a.point, b.point, c.point),
                                      angle_deg(b.point, c.point, a.point), angle_deg(c.point, a.point, b.point)});
      const gp_Pnt on_surface = surface_.Value((a.u + b.u + c.u) / 3, (a.v + b.v + c.v) / 3);
      const gp_Pnt centroid((a.point.XYZ() + b.point.XYZ() + c.point.XYZ()) / 3);
      stats.max_chord_error = std::max(stats.max_chord_error, on_surface.Distance(centroid));
    }
    return out;
  }

 private:
  static bool collapsed(const VertexInfo& a, const VertexInfo& b, const VertexInfo& c) {
    auto same = [](const VertexInfo& x, const VertexInfo& y) { return x.id != kNoIndex && x.id == y.id; };
    return same(a, b) || same(b, c) || same(a, c);
  }

  // Brings a parameter found by the projection into [low - a little, low + period) on a periodic surface.
  static double wrap(double value, double low, bool periodic, double period) {
    if (!periodic || !(period > 0)) return value;
    const double slack = 1e-9 * period;
    return value - period * std::floor((value - low + slack) / period);
  }

  enum class Outcome { Inserted, Outside, Encroaching, Crowded };

  // Inserts the surface point nearest to `centre` (a 3D circumcentre), or with `plane_target` the surface point over
  // that point of the plane.
  Outcome try_insert(const gp_Pnt& centre, double radius, const Point2& hint, double hint_u, double hint_v,
                     const Point2* plane_target) {
    double u = 0, v = 0;
    if (plane_target) {
      u = wrap(unstretch(plane_target->x(), u0_, u1_, s_of_u_, su_), u0_, surface_.IsUPeriodic(),
               surface_.IsUPeriodic() ? surface_.UPeriod() : 0);
      v = wrap(unstretch(plane_target->y(), v0_, v1_, t_of_v_, sv_), v0_, surface_.IsVPeriodic(),
               surface_.IsVPeriodic() ? surface_.VPeriod() : 0);
    } else {
      const gp_Pnt2d uv = analysis_->NextValueOfUV(gp_Pnt2d(hint_u, hint_v), centre, 1e-9 * (radius + size_));
      // Into the face's period: a centre across a seam is a point of the face on the seam's other side.
      u = wrap(uv.X(), u0_, surface_.IsUPeriodic(), surface_.IsUPeriodic() ? surface_.UPeriod() : 0);
      v = wrap(uv.Y(), v0_, surface_.IsVPeriodic(), surface_.IsVPeriodic() ? surface_.VPeriod() : 0);
    }
    if (!std::isfinite(u) || !std::isfinite(v)) return Outcome::Outside;
    const gp_Pnt point = surface_.Value(u, v);
    if (!plane_target && point.Distance(centre) > radius) return Outcome::Outside;  // surface far from the plane
    const Point2 p = plane_point(u, v);
    Cdt::Locate_type type;
    int li = 0;
    Cdt::Face_handle located = cdt_.locate(p, type, li, cdt_.locate(hint));
    if (type != Cdt::FACE || cdt_.is_infinite(located) || !located->info().inside()) return Outcome::Outside;
    const int located_nesting = located->info().nesting;
    std::vector<Cdt::Face_handle> zone;
    std::vector<Cdt::Edge> boundary;
    cdt_.get_conflicts_and_boundary(p, std::back_inserter(zone), std::back_inserter(boundary), located);
    for (const Cdt::Edge& e : boundary) {
      // A boundary edge of the conflict zone on the face's border (constrained): is the point in its diametral ball?
      if (!cdt_.is_constrained(e)) continue;
      // In the plane, where the triangulation is Delaunay (a 3D test would split edges for the stretch alone).
      const Point2& a = e.first->vertex(Cdt::cw(e.second))->point();
      const Point2& b = e.first->vertex(Cdt::ccw(e.second))->point();
      if (CGAL::squared_distance(p, CGAL::midpoint(a, b)) <= 0.25 * CGAL::squared_distance(a, b))
        return Outcome::Encroaching;
    }
    for (const Cdt::Face_handle& f : zone)
      for (int i = 0; i < 3; ++i)
        if (!cdt_.is_infinite(f->vertex(i)) && f->vertex(i)->info().point.Distance(point) < 0.25 * radius)
          return Outcome::Crowded;  // a point inserted this round already serves this triangle
    Cdt::Vertex_handle vertex = cdt_.insert(p, located);
    vertex->info() = {kNoIndex, point, u, v};
    // The new faces lie in the located face's conflict zone, which no constrained edge crosses: inside the face.
    Cdt::Face_circulator around = cdt_.incident_faces(vertex), done = around;
    do {
      around->info().nesting = located_nesting;
    } while (++around != done);
    return Outcome::Inserted;
  }

  const TopoDS_Face face_;
  const int number_;
  const double size_;
  std::vector<Point3>& vertices_;
  const std::string& file_;
  BRepAdaptor_Surface surface_;
  Handle(ShapeAnalysis_Surface) analysis_;
  double u0_ = 0, u1_ = 0, v0_ = 0, v1_ = 0, su_ = 1, sv_ = 1;
  // The plane the triangulation lives in: (s(u), t(v)), s and t piecewise linear with slopes the mean |dS/du| and
  // |dS/dv| over the other parameter (arc length along u and v, averaged): exact on cylinders, and an arc-length
  // reparametrisation of extrusions and revolutions whatever their curves' parametrisations.
  std::array<double, kStretchKnots + 1> s_of_u_{}, t_of_v_{};

  void build_stretch() {
    std::array<double, kStretchKnots> mean_u{}, mean_v{};
    for (int i = 0; i < kStretchKnots; ++i)
      for (int j = 0; j < kGrid; ++j) {
        gp_Pnt p;
        gp_Vec du, dv;
        surface_.D1(u0_ + (u1_ - u0_) * (i + 0.5) / kStretchKnots, v0_ + (v1_ - v0_) * (j + 0.5) / kGrid, p, du, dv);
        mean_u[i] += du.Magnitude() / kGrid;
        surface_.D1(u0_ + (u1_ - u0_) * (j + 0.5) / kGrid, v0_ + (v1_ - v0_) * (i + 0.5) / kStretchKnots, p, du, dv);
        mean_v[i] += dv.Magnitude() / kGrid;
      }
    double total_u = 0, total_v = 0;
    for (int i = 0; i < kStretchKnots; ++i) total_u += mean_u[i] / kStretchKnots, total_v += mean_v[i] / kStretchKnots;
    const double floor_u = 1e-3 * std::max(total_u, 1e-300), floor_v = 1e-3 * std::max(total_v, 1e-300);
    const double du = (u1_ - u0_) / kStretchKnots, dv = (v1_ - v0_) / kStretchKnots;
    for (int i = 0; i < kStretchKnots; ++i) {
      s_of_u_[i + 1] = s_of_u_[i] + std::max(mean_u[i], floor_u) * du;
      t_of_v_[i + 1] = t_of_v_[i] + std::max(mean_v[i], floor_v) * dv;
    }
    su_ = std::max(total_u, 1e-300);  // slopes beyond the box (pcurves may stick out by a tolerance)
    sv_ = std::max(total_v, 1e-300);
  }

  static double stretch(double x, double x0, double x1, const std::array<double, kStretchKnots + 1>& table,
                        double slope) {
    if (!(x1 > x0)) return slope * (x - x0);
    const double f = (x - x0) / (x1 - x0) * kStretchKnots;
    if (f <= 0) return table[0] + slope * (x - x0);
    if (f >= kStretchKnots) return table[kStretchKnots] + slope * (x - x1);
    const int i = std::min(static_cast<int>(f), kStretchKnots - 1);
    return table[i] + (table[i + 1] - table[i]) * (f - i);
  }

  // The inverse of stretch (the tables increase strictly).
  static double unstretch(double y, double x0, double x1, const std::array<double, kStretchKnots + 1>& table,
                          double slope) {
    if (!(x1 > x0)) return x0 + y / slope;
    if (y <= table[0]) return x0 + (y - table[0]) / slope;
    if (y >= table[kStretchKnots]) return x1 + (y - table[kStretchKnots]) / slope;
    const int i = static_cast<int>(std::upper_bound(table.begin(), table.end(), y) - table.begin()) - 1;
    const double f = (y - table[i]) / (table[i + 1] - table[i]);
    return x0 + (x1 - x0) * (i + f) / kStretchKnots;
  }

  static double plane_min_angle_deg(const Point2& a, const Point2& b, const Point2& c) {
    auto angle = [](const Point2& p, const Point2& q, const Point2& r) {
      const double x1 = q.x() - p.x(), y1 = q.y() - p.y(), x2 = r.x() - p.x(), y2 = r.y() - p.y();
      return std::atan2(std::fabs(x1 * y2 - y1 * x2), x1 * x2 + y1 * y2) * 180 / M_PI;
    };
    return std::min({angle(a, b, c), angle(b, c, a), angle(c, a, b)});
  }

  Point2 plane_point(double u, double v) const {
    return Point2(stretch(u, u0_, u1_, s_of_u_, su_), stretch(v, v0_, v1_, t_of_v_, sv_));
  }
  std::size_t budget_ = 0;
  Cdt cdt_;
  std::map<Index, std::vector<Cdt::Vertex_handle>> corners_;  // CAD vertex id -> its points in (u, v)
};

}  // namespace

std::vector<double> discretise_edge(const TopoDS_Edge& edge, double size) {
  BRepAdaptor_Curve curve(edge);
  const double t0 = curve.FirstParameter(), t1 = curve.LastParameter();
  const double length = GCPnts_AbscissaPoint::Length(curve, t0, t1);
  TopoDS_Vertex a, b;
  TopExp::Vertices(edge, a, b);
  const bool closed = !a.IsNull() && a.IsSame(b);
  const double pieces = std::ceil(length / size - 1e-6);
  int n = static_cast<int>(std::min(std::max(pieces, 1.0), 1e7));
  if (closed) n = std::max(n, 3);
  std::vector<double> params;
  if (n > 1) {
    GCPnts_UniformAbscissa uniform(curve, n + 1, t0, t1);
    if (uniform.IsDone() && uniform.NbPoints() == n + 1)
      for (int i = 1; i <= n + 1; ++i) params.push_back(uniform.Parameter(i));
  }
  if (params.size() != static_cast<std::size_t>(n + 1)) {
    params.clear();
    for (int i = 0; i <= n; ++i) params.push_back(t0 + (t1 - t0) * i / n);
  }
  params.front() = t0, params.back() = t1;
  return params;
}

std::vector<SurfaceTriangle> mesh_curved_face(const TopoDS_Face& face, int face_number, double size,
                                              const std::function<const EdgeChain&(const TopoDS_Edge&)>& chain_of,
                                              const std::function<Index(const TopoDS_Vertex&)>& vertex_id,
                                              std::vector<Point3>& vertices, const std::string& file,
                                              FaceMeshStats& stats) {
  FaceMesher mesher(face, face_number, size, vertices, file);
  mesher.add_boundary(chain_of, vertex_id);
  mesher.refine(stats);
  return mesher.triangles(stats);
}

}  // namespace qualmesh::cad
