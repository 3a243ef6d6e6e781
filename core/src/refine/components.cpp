// Separate closed surfaces meshed one by one (components.h).
#include "refine/components.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <algorithm>
#include <array>
#include <map>
#include <numeric>
#include <stdexcept>

#include "mesh_check_internal.h"

namespace qualmesh::detail {

namespace {

struct UnionFind {
  std::vector<Index> parent;
  explicit UnionFind(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), Index(0)); }
  Index find(Index x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  }
  void join(Index a, Index b) {
    a = find(a);
    b = find(b);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);  // the root is the smallest vertex
  }
};

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Triangles = std::vector<K::Triangle_3>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, CGAL::AABB_triangle_primitive<K, Triangles::const_iterator>>>;

// The faces of `mesh`'s tets that belong to one tet only: the boundary of its volume.
Triangles hull_triangles(const TetMesh& mesh) {
  std::vector<std::array<Index, 3>> faces;
  faces.reserve(4 * mesh.tets.size());
  for (const auto& t : mesh.tets)
    for (int k = 0; k < 4; ++k) {
      std::array<Index, 3> f{t[(k + 1) % 4], t[(k + 2) % 4], t[(k + 3) % 4]};
      std::sort(f.begin(), f.end());
      faces.push_back(f);
    }
  std::sort(faces.begin(), faces.end());
  Triangles out;
  const auto point = [&](Index v) { return K::Point_3(mesh.points[v][0], mesh.points[v][1], mesh.points[v][2]); };
  for (std::size_t i = 0; i < faces.size();) {
    std::size_t j = i + 1;
    while (j < faces.size() && faces[j] == faces[i]) ++j;
    if (j - i == 1) out.emplace_back(point(faces[i][0]), point(faces[i][1]), point(faces[i][2]));
    i = j;
  }
  return out;
}

// Directions of no special slope, so that a ray through an edge or a vertex of a surface is unlikely; a vote of the
// three settles the rare one that is.
constexpr double kRayDirections[3][3] = {
    {0.5773, 0.6113, 0.5417}, {-0.6211, 0.2973, 0.7251}, {0.3187, -0.8719, 0.3717}};

// Whether `p` is inside the closed surface made of `facets` by ray parity: a ray crosses a facet where it meets the
// facet's plane at a point of the facet (FacetGeometry::contains: the even-odd rule of its loops, less its hole
// points). Internal facets make extra crossings, so a component with some may be taken for containing a point it
// does not: then the input is only meshed whole, as before.
bool surface_contains(const std::vector<check::FacetGeometry>& facets, const Point3& p) {
  int odd = 0;
  for (const auto& d : kRayDirections) {
    int crossings = 0;
    for (const check::FacetGeometry& g : facets) {
      const Point3& n = g.normal;
      const double denom = n[0] * d[0] + n[1] * d[1] + n[2] * d[2];
      if (g.degenerate || denom == 0) continue;
      const double t = (g.offset - (n[0] * p[0] + n[1] * p[1] + n[2] * p[2])) / denom;
      if (t > 0 && g.contains({p[0] + t * d[0], p[1] + t * d[1], p[2] + t * d[2]})) ++crossings;
    }
    odd += crossings % 2;
  }
  return odd >= 2;
}

}  // namespace

std::vector<PlcComponent> separate_components(const Plc& plc) {
  const std::size_t n = plc.vertices.size();
  UnionFind uf(n);
  std::vector<std::uint8_t> used(n, 0);
  std::map<std::pair<Index, Index>, int> edge_use;
  for (const Segment& s : plc.segments) {
    uf.join(s.a, s.b);
    used[s.a] = used[s.b] = 1;
  }
  for (const Facet& f : plc.facets) {
    Index first = kNoIndex;
    for (const auto& loop : f.polygons) {
      for (Index v : loop) {
        used[v] = 1;
        if (first == kNoIndex) first = v;
        uf.join(first, v);
      }
      if (loop.size() >= 3)
        for (std::size_t i = 0; i < loop.size(); ++i)
          ++edge_use[std::minmax(loop[i], loop[(i + 1) % loop.size()])];
    }
  }
  if (std::find(used.begin(), used.end(), 0) != used.end()) return {};
  for (const auto& [e, count] : edge_use)
    if (count < 2) return {};
  std::map<Index, std::size_t> component_of_root;  // ordered by root: by the smallest vertex of each component
  for (Index v = 0; v < n; ++v) component_of_root.emplace(uf.find(v), 0);
  if (component_of_root.size() < 2) return {};
  std::vector<PlcComponent> parts(component_of_root.size());
  std::size_t k = 0;
  for (auto& [root, index] : component_of_root) index = k++;
  std::vector<Index> local(n);
  for (Index v = 0; v < n; ++v) {
    Plc& part = parts[component_of_root[uf.find(v)]].plc;
    local[v] = Index(part.vertices.size());
    part.vertices.push_back(plc.vertices[v]);
  }
  for (const Segment& s : plc.segments)
    parts[component_of_root[uf.find(s.a)]].plc.segments.push_back({local[s.a], local[s.b], s.marker});
  for (Index fi = 0; fi < plc.facets.size(); ++fi) {
    const Facet& f = plc.facets[fi];
    if (f.polygons.empty() || f.polygons.front().empty()) continue;  // no vertex: no component (and no mesh face)
    PlcComponent& part = parts[component_of_root[uf.find(f.polygons.front().front())]];
    Facet g = f;
    for (auto& loop : g.polygons)
      for (Index& v : loop) v = local[v];
    part.plc.facets.push_back(std::move(g));
    part.facets.push_back(fi);
  }
  // One inside another's closed surface (a cavity's wall inside its solid's outer wall, an inclusion): whole.
  for (std::size_t i = 0; i < parts.size(); ++i) {
    std::vector<check::FacetGeometry> facets;
    for (const Facet& f : parts[i].plc.facets) facets.push_back(check::make_facet_geometry(parts[i].plc, f));
    for (std::size_t j = 0; j < parts.size(); ++j)
      if (i != j && surface_contains(facets, parts[j].plc.vertices.front())) return {};
  }
  for (PlcComponent& part : parts) {
    part.plc.holes = plc.holes;
    part.plc.regions = plc.regions;
    part.plc.name = plc.name;
  }
  return parts;
}

bool meshed_volumes_meet(const std::vector<const TetMesh*>& meshes) {
  for (std::size_t i = 0; i < meshes.size(); ++i) {
    const Triangles hull = hull_triangles(*meshes[i]);
    if (hull.empty()) continue;
    Tree tree(hull.begin(), hull.end());
    tree.accelerate_distance_queries();
    const CGAL::Bbox_3 box = tree.bbox();
    const double dx = box.xmax() - box.xmin(), dy = box.ymax() - box.ymin(), dz = box.zmax() - box.zmin();
    const double sq_touch = 1e-18 * (dx * dx + dy * dy + dz * dz);
    for (std::size_t j = 0; j < meshes.size(); ++j) {
      if (j == i) continue;
      const std::vector<Point3>& points = meshes[j]->points;
      const std::size_t step = std::max<std::size_t>(1, points.size() / 16);
      for (std::size_t v = 0; v < points.size(); v += step) {
        const K::Point_3 p(points[v][0], points[v][1], points[v][2]);
        if (p.x() < box.xmin() || p.x() > box.xmax() || p.y() < box.ymin() || p.y() > box.ymax() ||
            p.z() < box.zmin() || p.z() > box.zmax())
          continue;
        if (tree.squared_distance(p) <= sq_touch) return true;
        int odd = 0;
        for (const auto& d : kRayDirections)
          odd += tree.number_of_intersected_primitives(K::Ray_3(p, K::Vector_3(d[0], d[1], d[2]))) % 2;
        if (odd >= 2) return true;
      }
    }
  }
  return false;
}

namespace {

void merge_stats(MeshStats& a, const MeshStats& b) {
  for (auto field : {&MeshStats::num_input_vertices, &MeshStats::num_steiner_vertices,
                     &MeshStats::num_rule1_insertions, &MeshStats::num_rule2_insertions,
                     &MeshStats::num_rule3_insertions, &MeshStats::num_rejected_circumcenters,
                     &MeshStats::num_subfacet_flips, &MeshStats::num_skipped_small_angle,
                     &MeshStats::num_skipped_floor, &MeshStats::num_tets, &MeshStats::num_boundary_faces,
                     &MeshStats::num_tets_above_bound, &MeshStats::num_above_bound_acute,
                     &MeshStats::num_above_bound_rejected, &MeshStats::num_above_bound_other,
                     &MeshStats::num_rule4_encroachments, &MeshStats::num_rule4_vertices,
                     &MeshStats::num_vertices_before_pumping, &MeshStats::num_vertices_after_pumping,
                     &MeshStats::num_sliver_insertions, &MeshStats::num_sliver_insertions_refused,
                     &MeshStats::num_slivers_before_pumping, &MeshStats::num_slivers_after_pumping,
                     &MeshStats::num_vertices_pumped, &MeshStats::num_pump_moves, &MeshStats::num_pump_rejected,
                     &MeshStats::num_tets_improved, &MeshStats::num_improve_vertex_moves,
                     &MeshStats::num_improve_flips, &MeshStats::num_improve_insertions,
                     &MeshStats::num_improve_caps_removed, &MeshStats::num_tets_below_sliver_angle_away_from_acute,
                     &MeshStats::num_region_refloods})
    a.*field += b.*field;
  for (auto field : {&MeshStats::seconds_initial, &MeshStats::seconds_boundary, &MeshStats::seconds_regions,
                     &MeshStats::seconds_refinement, &MeshStats::seconds_pumping, &MeshStats::seconds_extraction,
                     &MeshStats::seconds_improve})
    a.*field += b.*field;
  for (auto field : {&MeshStats::max_radius_edge, &MeshStats::max_radius_edge_away_from_acute,
                     &MeshStats::max_weight_cap_ratio, &MeshStats::max_weight})
    a.*field = std::max(a.*field, b.*field);
  for (auto field : {&MeshStats::min_dihedral_deg, &MeshStats::min_dihedral_before_pumping_deg,
                     &MeshStats::min_dihedral_before_improve_deg, &MeshStats::min_dihedral_away_from_acute_deg})
    a.*field = std::min(a.*field, b.*field);
  a.encroaching_fell_back = a.encroaching_fell_back || b.encroaching_fell_back;
  a.boundary_projection_dropped = a.boundary_projection_dropped || b.boundary_projection_dropped;
}

// `values` of a mesh with `count` entries, or `count` zeros when it has none (an empty list means all zero).
template <typename T>
void append_or_zero(std::vector<T>& out, const std::vector<T>& values, std::size_t count) {
  if (values.empty()) out.insert(out.end(), count, T{});
  else out.insert(out.end(), values.begin(), values.end());
}

}  // namespace

MeshResult merge_component_results(const std::vector<PlcComponent>& parts, std::vector<MeshResult>& results) {
  MeshResult out;
  TetMesh& m = out.mesh;
  bool weights = false, regions = false, markers = false;
  for (const MeshResult& r : results) {
    weights = weights || !r.mesh.weights.empty();
    regions = regions || !r.mesh.tet_region.empty();
    markers = markers || !r.mesh.face_marker.empty();
    if (!r.mesh.tet_mid.empty() || !r.mesh.face_mid.empty() || !r.mesh.edge_mid.empty())
      throw std::logic_error("merge_component_results: a second-order mesh");
  }
  for (std::size_t k = 0; k < results.size(); ++k) {
    const TetMesh& r = results[k].mesh;
    const Index shift = Index(m.points.size());
    m.points.insert(m.points.end(), r.points.begin(), r.points.end());
    if (weights) append_or_zero(m.weights, r.weights, r.points.size());
    for (auto t : r.tets) {
      for (Index& v : t) v += shift;
      m.tets.push_back(t);
    }
    if (regions) append_or_zero(m.tet_region, r.tet_region, r.tets.size());
    for (std::size_t f = 0; f < r.faces.size(); ++f) {
      auto face = r.faces[f];
      for (Index& v : face) v += shift;
      m.faces.push_back(face);
      const int local = f < r.face_facet.size() ? r.face_facet[f] : -1;
      m.face_facet.push_back(local >= 0 ? int(parts[k].facets[local]) : -1);
    }
    if (markers) append_or_zero(m.face_marker, r.face_marker, r.faces.size());
    for (auto e : r.edges) {
      for (Index& v : e) v += shift;
      m.edges.push_back(e);
    }
    m.edge_marker.insert(m.edge_marker.end(), r.edge_marker.begin(), r.edge_marker.end());
    out.tet_touches_acute_angle.insert(out.tet_touches_acute_angle.end(), results[k].tet_touches_acute_angle.begin(),
                                       results[k].tet_touches_acute_angle.end());
    if (k == 0) out.stats = results[k].stats;
    else merge_stats(out.stats, results[k].stats);
    if (out.status == MeshStatus::Ok) {
      out.status = results[k].status;
      out.message = results[k].message;
    }
  }
  return out;
}

}  // namespace qualmesh::detail
