// The mesh checker's protection zones (issue 16): where the reference PLC has input angles below a threshold (60
// degrees by default), the tetrahedra near them are counted apart, so that quality "outside the protection zones"
// is a second line beside the figures over all tetrahedra, measured the same way for every mesher (ours, TetGen,
// Gmsh, Netgen, CGAL).
//
// The zone is a union of protecting balls, as in Cheng, Dey and Ramos ("Delaunay refinement for piecewise smooth
// complexes") and CGAL Mesh_3's sharp features, sized by the paper's local feature size f (Section 2; the radius of
// the smallest ball centred at x that meets two non-adjacent elements, local_feature_size.h):
//  - sharp input angles: those validate_plc measures (Section 2's three kinds: segment-segment and segment-facet at
//    a vertex, facet-facet along a segment) below the threshold;
//  - a sharp vertex is the apex of a sharp segment-segment or segment-facet angle; its ball is centred at the
//    vertex v with radius f(v), the distance from v to the nearest element not containing it;
//  - a sharp segment carries a sharp facet-facet angle; its balls are centred all along the segment ab, with one
//    radius min(f(a), f(b), f(midpoint)): their union is a capsule around ab.
// A mesh point is inside the zone when it lies in some ball (closed); a tetrahedron is inside when one of its
// vertices is. f(v) is about the spacing of the input's own vertices near v, so around an isolated sharp feature the
// zone is a layer of elements a few deep. On a tessellated curved surface, though, most vertices are apices of
// triangle corners below 60 degrees, and the zones hold most tetrahedra near the surface (fandisk.off: 77% of
// QualMesh's, 68% of TetGen's): the report says how many, and the figures over all tetrahedra stay the headline.
//
// Candidate (point, ball) pairs come from CGAL's box_intersection_d over the balls' bounding boxes and the points
// (O(n log n + pairs)); each pair is then tested exactly by distance.
//
// A CAD model has no PLC whose local feature size could size the balls. Its zone (fill_cad_feature_protection) is
// the mesh points within a radius of its sharp features, which the CAD front end finds on the CAD geometry
// (cad_features.cpp); the radius is the caller's (the checker's --protection-radius, by default one median mesh
// edge, which does not shrink where a mesher refines).
#include <CGAL/box_intersection_d.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "local_feature_size.h"
#include "mesh_check_internal.h"
#include "qualmesh/mesh_check.h"
#include "qualmesh/plc_validate.h"
#include "qualmesh/quality.h"

namespace qualmesh::check {
namespace {

using Box = CGAL::Box_intersection_d::Box_with_info_d<double, 3, std::size_t>;

// A ball (a == b) or a capsule around segment ab, of radius r.
struct ProtectingBalls {
  Point3 a, b;
  double radius;
};

double sq_distance_to_segment(const Point3& p, const Point3& a, const Point3& b) {
  const Point3 ab{b[0] - a[0], b[1] - a[1], b[2] - a[2]};
  const Point3 ap{p[0] - a[0], p[1] - a[1], p[2] - a[2]};
  const double length2 = ab[0] * ab[0] + ab[1] * ab[1] + ab[2] * ab[2];
  double t = length2 > 0 ? (ap[0] * ab[0] + ap[1] * ab[1] + ap[2] * ab[2]) / length2 : 0;
  t = std::clamp(t, 0.0, 1.0);
  double d2 = 0;
  for (int k = 0; k < 3; ++k) {
    const double d = ap[k] - t * ab[k];
    d2 += d * d;
  }
  return d2;
}

}  // namespace

ProtectionZones find_protection_zones(const Plc& plc, const std::vector<Point3>& points, double angle_deg) {
  ProtectionZones zones;
  zones.point_inside.assign(points.size(), 0);
  if (!(angle_deg > 0) || plc.vertices.empty()) return zones;

  ValidateOptions options;
  options.acute_threshold_deg = angle_deg;
  options.check_intersections = false;
  options.require_closed = false;
  options.max_problems_per_kind = std::numeric_limits<std::size_t>::max();  // every sharp angle, not the smallest
  const ValidationReport angles = validate_plc(plc, options);
  std::vector<char> sharp_vertex(plc.vertices.size(), 0);
  std::vector<char> sharp_segment(angles.num_segments, 0);
  for (const InputAngle& angle : angles.acute_angles) {
    if (angle.kind == AngleKind::FacetFacet) {
      if (angle.segment < sharp_segment.size()) sharp_segment[angle.segment] = 1;
    } else if (angle.apex_vertex < sharp_vertex.size()) {
      sharp_vertex[angle.apex_vertex] = 1;
    }
  }
  for (char s : sharp_vertex) zones.num_sharp_vertices += s;
  for (char s : sharp_segment) zones.num_sharp_segments += s;
  if (zones.num_sharp_vertices == 0 && zones.num_sharp_segments == 0) return zones;

  const LocalFeatureSize lfs(plc, plc_facet_triangles(plc));
  const double diagonal = bounding_box(plc).diagonal();
  // f is infinite only when every two elements are adjacent; the whole model is then one feature's neighbourhood.
  const auto f = [&](const Point3& x) {
    const double value = lfs(x);
    return std::isfinite(value) ? value : diagonal;
  };
  std::vector<ProtectingBalls> balls;
  for (std::size_t v = 0; v < plc.vertices.size(); ++v) {
    if (sharp_vertex[v]) balls.push_back({plc.vertices[v], plc.vertices[v], f(plc.vertices[v])});
  }
  const std::vector<Segment> segments = collect_segments(plc);
  for (std::size_t s = 0; s < segments.size() && s < sharp_segment.size(); ++s) {
    if (!sharp_segment[s]) continue;
    const Point3& a = plc.vertices[segments[s].a];
    const Point3& b = plc.vertices[segments[s].b];
    const Point3 mid{(a[0] + b[0]) / 2, (a[1] + b[1]) / 2, (a[2] + b[2]) / 2};
    balls.push_back({a, b, std::min({f(a), f(b), f(mid)})});
  }

  std::vector<Box> ball_boxes, point_boxes;
  ball_boxes.reserve(balls.size());
  for (std::size_t i = 0; i < balls.size(); ++i) {
    const ProtectingBalls& z = balls[i];
    const double r = z.radius;
    const CGAL::Bbox_3 box(std::min(z.a[0], z.b[0]) - r, std::min(z.a[1], z.b[1]) - r, std::min(z.a[2], z.b[2]) - r,
                           std::max(z.a[0], z.b[0]) + r, std::max(z.a[1], z.b[1]) + r, std::max(z.a[2], z.b[2]) + r);
    ball_boxes.emplace_back(box, i);
  }
  point_boxes.reserve(points.size());
  for (std::size_t p = 0; p < points.size(); ++p) {
    const Point3& x = points[p];
    point_boxes.emplace_back(CGAL::Bbox_3(x[0], x[1], x[2], x[0], x[1], x[2]), p);
  }
  CGAL::box_intersection_d(
      ball_boxes.begin(), ball_boxes.end(), point_boxes.begin(), point_boxes.end(),
      [&](const Box& ball_box, const Box& point_box) {
        const std::size_t p = point_box.info();
        if (zones.point_inside[p]) return;
        const ProtectingBalls& z = balls[ball_box.info()];
        if (sq_distance_to_segment(points[p], z.a, z.b) <= z.radius * z.radius) zones.point_inside[p] = 1;
      },
      std::ptrdiff_t(10), CGAL::Box_intersection_d::CLOSED);
  return zones;
}

void count_protection_zone(CheckReport& report, const std::vector<std::array<Index, 4>>& tets,
                           const std::vector<char>& valid, const std::vector<double>& tet_min_dihedral,
                           const std::vector<char>& point_inside) {
  report.num_tets_in_protection_zone = report.num_tets_outside_protection_below_10 =
      report.num_tets_outside_protection_below_15 = 0;
  double min_outside = std::numeric_limits<double>::infinity();
  for (std::size_t t = 0; t < tets.size(); ++t) {
    if (!valid[t]) continue;
    const auto& v = tets[t];
    if (point_inside[v[0]] || point_inside[v[1]] || point_inside[v[2]] || point_inside[v[3]]) {
      ++report.num_tets_in_protection_zone;
      continue;
    }
    min_outside = std::min(min_outside, tet_min_dihedral[t]);
    if (tet_min_dihedral[t] < 10) ++report.num_tets_outside_protection_below_10;
    if (tet_min_dihedral[t] < 15) ++report.num_tets_outside_protection_below_15;
  }
  report.min_dihedral_outside_protection_deg = std::isfinite(min_outside) ? min_outside : 0;
}

}  // namespace qualmesh::check

namespace qualmesh {

void fill_cad_feature_protection(CheckReport& report, const TetMesh& mesh,
                                 const std::vector<Index>& near_feature_nodes, double angle_deg, double radius,
                                 std::size_t num_sharp_vertices, std::size_t num_sharp_edges) {
  report.protection_checked = true;
  report.protection_zone = CheckReport::ProtectionZone::CadFeatureBalls;
  report.protection_angle_deg = angle_deg;
  report.protection_radius = radius;
  report.num_sharp_vertices = num_sharp_vertices;
  report.num_sharp_segments = num_sharp_edges;
  const std::size_t n = mesh.points.size();
  std::vector<char> near(n, 0), valid(mesh.tets.size(), 0);
  for (Index v : near_feature_nodes)
    if (v < n) near[v] = 1;
  std::vector<double> tet_min_dihedral(mesh.tets.size(), 0);
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
    const auto& v = mesh.tets[t];
    valid[t] = v[0] < n && v[1] < n && v[2] < n && v[3] < n;
    if (valid[t])
      tet_min_dihedral[t] =
          tet_min_dihedral_deg(mesh.points[v[0]], mesh.points[v[1]], mesh.points[v[2]], mesh.points[v[3]]);
  }
  check::count_protection_zone(report, mesh.tets, valid, tet_min_dihedral, near);
}

double median_edge_length(const TetMesh& mesh) {
  const std::size_t n = mesh.points.size();
  std::vector<double> lengths;
  lengths.reserve(6 * mesh.tets.size());
  for (const auto& t : mesh.tets)
    for (int a = 0; a < 4; ++a)
      for (int b = a + 1; b < 4; ++b) {
        if (!(t[a] < n && t[b] < n)) continue;
        const Point3 &p = mesh.points[t[a]], &q = mesh.points[t[b]];
        lengths.push_back(std::sqrt((p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) +
                                    (p[2] - q[2]) * (p[2] - q[2])));
      }
  if (lengths.empty()) return 0;
  auto mid = lengths.begin() + std::ptrdiff_t(lengths.size() / 2);
  std::nth_element(lengths.begin(), mid, lengths.end());
  return *mid;
}

}  // namespace qualmesh
