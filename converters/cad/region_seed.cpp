// Region seeds of the CAD front end (brep_to_plc.cpp's last step): a point strictly inside the PLC surface of a
// solid. The seed is tested against the triangles the mesher will receive, not against the CAD solid: the PLC's
// curved facets are chords of the CAD surface, so a point inside the CAD solid can lie outside the PLC (between a
// chord and its face), and a margin of twice the chordal error from every CAD wall left no point at all in a thin
// wall meshed coarsely (bottle.brep at --size 40: a 1.4 mm wall, chordal error 0.18; the sized surface was dropped
// for OpenCASCADE's tessellation, on which the volume mesh had a 1.9e-14 deg tet after 110 s).
#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Surface_mesh.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <vector>

#include "cad_private.h"

namespace qualmesh::cad {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Mesh = CGAL::Surface_mesh<K::Point_3>;
using Inside = CGAL::Side_of_triangle_mesh<Mesh, K>;
using Tree = Inside::AABB_tree;
using FaceIndex = Mesh::Face_index;

// How many candidate triangles (largest first) are tried, and how many seeds found before the clearest is taken.
constexpr std::size_t kMaxCandidates = 400;
constexpr std::size_t kEnoughSeeds = 16;

// The triangles as one closed triangle mesh (equal points merged; a vertex where the surface pinches is
// duplicated by orient_polygon_soup); nothing when they do not close.
std::optional<Mesh> closed_mesh(const std::vector<SeedTriangle>& triangles) {
  std::vector<K::Point_3> points;
  std::map<Point3, std::size_t> ids;
  std::vector<std::vector<std::size_t>> polygons;
  for (const SeedTriangle& t : triangles) {
    std::vector<std::size_t> polygon;
    for (const Point3& p : t) {
      const auto [it, added] = ids.emplace(p, points.size());
      if (added) points.emplace_back(p[0], p[1], p[2]);
      polygon.push_back(it->second);
    }
    if (polygon[0] == polygon[1] || polygon[1] == polygon[2] || polygon[0] == polygon[2]) continue;
    polygons.push_back(std::move(polygon));
  }
  namespace PMP = CGAL::Polygon_mesh_processing;
  if (!PMP::is_polygon_soup_a_polygon_mesh(polygons)) PMP::orient_polygon_soup(points, polygons);
  if (!PMP::is_polygon_soup_a_polygon_mesh(polygons)) return std::nullopt;
  Mesh mesh;
  PMP::polygon_soup_to_polygon_mesh(points, polygons, mesh);
  if (mesh.is_empty() || !CGAL::is_closed(mesh)) return std::nullopt;
  return mesh;
}

}  // namespace

// From the centroid of each of the larger triangles, a ray along either normal to the next triangle it meets; the
// midpoint is a seed when Side_of_triangle_mesh puts it inside. Of the first kEnoughSeeds seeds, the one furthest
// from the surface (AABB tree distance) is returned, so that rounding cannot put it on the other side of a facet.
std::optional<Point3> region_seed(const std::vector<SeedTriangle>& triangles, double diagonal) {
  const std::optional<Mesh> closed = closed_mesh(triangles);
  if (!closed) return std::nullopt;
  const Mesh& mesh = *closed;
  Tree tree(faces(mesh).first, faces(mesh).second, mesh);
  tree.accelerate_distance_queries();
  const Inside inside(tree);

  std::vector<FaceIndex> order(faces(mesh).begin(), faces(mesh).end());
  std::vector<double> area(mesh.number_of_faces());
  const auto triangle = [&mesh](FaceIndex f) {
    const Mesh::Halfedge_index h = mesh.halfedge(f);
    return K::Triangle_3(mesh.point(mesh.source(h)), mesh.point(mesh.target(h)),
                         mesh.point(mesh.target(mesh.next(h))));
  };
  for (FaceIndex f : order) area[f.idx()] = std::sqrt(triangle(f).squared_area());
  std::stable_sort(order.begin(), order.end(),
                   [&area](FaceIndex a, FaceIndex b) { return area[a.idx()] > area[b.idx()]; });

  std::optional<K::Point_3> best;
  double best_clearance = 1e-9 * diagonal;  // a seed closer than this to a facet is rounding's, not the domain's
  std::size_t seeds = 0;
  for (std::size_t k = 0; k < std::min(order.size(), kMaxCandidates) && seeds < kEnoughSeeds; ++k) {
    const FaceIndex face = order[k];
    const K::Triangle_3 t = triangle(face);
    const K::Vector_3 normal = CGAL::normal(t[0], t[1], t[2]);
    if (!(normal.squared_length() > 0)) continue;
    const K::Point_3 centroid = CGAL::centroid(t);
    for (const K::Vector_3 direction : {normal, -normal}) {
      const auto hit = tree.first_intersection(K::Ray_3(centroid, direction),
                                               [face](FaceIndex f) { return f == face; });
      if (!hit) continue;
      const K::Point_3* far = boost::get<K::Point_3>(&hit->first);
      if (far == nullptr) continue;  // the ray runs along a triangle
      const K::Point_3 seed = CGAL::midpoint(centroid, *far);
      if (inside(seed) != CGAL::ON_BOUNDED_SIDE) continue;
      ++seeds;
      const double clearance = std::sqrt(tree.squared_distance(seed));
      if (clearance > best_clearance) {
        best_clearance = clearance;
        best = seed;
      }
    }
  }
  if (!best) return std::nullopt;
  return Point3{best->x(), best->y(), best->z()};
}

}  // namespace qualmesh::cad
