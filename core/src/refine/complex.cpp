// Input complex of the refinement engine: segments, facet frames and incidences (paper Section 2, "Incidence",
// "Adjacent elements"), and the acute input angles of Section 3.7's assumption (flagged, not rejected: the engine
// protects their apices, see small_angles.cpp).
#include "refine/complex.h"

#include <algorithm>
#include <cmath>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include "qualmesh/error.h"
#include "vec3.h"

namespace qualmesh::detail {

namespace {

using namespace vec3;
Point3 normalized(const Point3& a) {
  const double n = std::sqrt(dot(a, a));
  return n > 0 ? Point3{a[0] / n, a[1] / n, a[2] / n} : Point3{0, 0, 0};
}

// Angle in degrees between two directions.
double angle_deg(const Point3& a, const Point3& b) {
  const double c = dot(normalized(a), normalized(b));
  return std::acos(std::max(-1.0, std::min(1.0, c))) * 180.0 / M_PI;
}

// Newell normal of all the polygons of a facet (robust for non-convex polygons).
Point3 facet_normal(const Plc& plc, const Facet& facet) {
  Point3 n{0, 0, 0};
  for (const auto& loop : facet.polygons) {
    if (loop.size() < 3) continue;
    for (std::size_t i = 0; i < loop.size(); ++i) {
      const Point3& p = plc.vertices[loop[i]];
      const Point3& q = plc.vertices[loop[(i + 1) % loop.size()]];
      n[0] += (p[1] - q[1]) * (p[2] + q[2]);
      n[1] += (p[2] - q[2]) * (p[0] + q[0]);
      n[2] += (p[0] - q[0]) * (p[1] + q[1]);
    }
  }
  return normalized(n);
}

// Plane groups: facets joined through shared segments to facets exactly coplanar with them (exact orientation
// predicate on input vertices) share a group id. A flat cell of near-cocircular Steiner points may span two such
// facets (a CAD quad split into two triangles), so the engine asks about the plane, not one facet.
void compute_plane_groups(const Plc& plc, InputComplex& c) {
  const std::size_t nf = plc.facets.size();
  std::vector<Index> parent(nf);
  for (Index f = 0; f < nf; ++f) parent[f] = f;
  const auto find = [&](Index f) {
    while (parent[f] != f) f = parent[f] = parent[parent[f]];
    return f;
  };
  const auto kp = [&](Index v) {
    const Point3& p = plc.vertices[v];
    return CGAL::Epick::Point_3(p[0], p[1], p[2]);
  };
  // Three non-collinear input vertices of each facet (none: the facet stays alone).
  std::vector<std::array<Index, 3>> basis(nf, {kNoIndex, kNoIndex, kNoIndex});
  for (Index f = 0; f < nf; ++f) {
    const auto& vs = c.facet_vertices[f];
    if (vs.size() < 3) continue;
    for (std::size_t k = 2; k < vs.size(); ++k) {
      if (!CGAL::collinear(kp(vs[0]), kp(vs[1]), kp(vs[k]))) {
        basis[f] = {vs[0], vs[1], vs[k]};
        break;
      }
    }
  }
  const auto coplanar = [&](Index f, Index g) {
    if (basis[f][0] == kNoIndex || basis[g][0] == kNoIndex) return false;
    const auto a = kp(basis[f][0]), b = kp(basis[f][1]), d = kp(basis[f][2]);
    for (Index v : c.facet_vertices[g])
      if (CGAL::orientation(a, b, d, kp(v)) != CGAL::COPLANAR) return false;
    return true;
  };
  for (const auto& list : c.segment_facets) {
    for (std::size_t i = 0; i < list.size(); ++i)
      for (std::size_t j = i + 1; j < list.size(); ++j) {
        const Index f = find(list[i].facet), g = find(list[j].facet);
        if (f != g && coplanar(list[i].facet, list[j].facet)) parent[std::max(f, g)] = std::min(f, g);
      }
  }
  c.plane_group.resize(nf);
  for (Index f = 0; f < nf; ++f) c.plane_group[f] = find(f);
}

}  // namespace

std::array<double, 2> PlaneFrame::to_local(const Point3& p) const {
  const Point3 d = sub(p, origin);
  return {dot(d, e1), dot(d, e2)};
}

Point3 PlaneFrame::to_global(const std::array<double, 2>& uv) const {
  return {origin[0] + uv[0] * e1[0] + uv[1] * e2[0], origin[1] + uv[0] * e1[1] + uv[1] * e2[1],
          origin[2] + uv[0] * e1[2] + uv[1] * e2[2]};
}

bool InputComplex::facet_has_segment(Index facet, Index segment) const {
  return segment_in_facet(segment, facet) != nullptr;
}

const SegmentInFacet* InputComplex::segment_in_facet(Index segment, Index facet) const {
  for (const SegmentInFacet& s : segment_facets[segment])
    if (s.facet == facet) return &s;
  return nullptr;
}

bool InputComplex::elements_meet_at_acute_vertex(const std::vector<Index>& a, const std::vector<Index>& b) const {
  std::size_t i = 0, j = 0;
  while (i < a.size() && j < b.size()) {
    if (a[i] < b[j]) {
      ++i;
    } else if (b[j] < a[i]) {
      ++j;
    } else {
      if (acute_vertex[a[i]]) return true;
      ++i, ++j;
    }
  }
  return false;
}

double InputComplex::segment_facet_angle_deg(Index v, Index segment, Index facet, bool* corner) const {
  const Segment& seg = segments[segment];
  const Point3 d = sub(plc->vertices[seg.a == v ? seg.b : seg.a], plc->vertices[v]);
  const Point3& n = frames[facet].normal;
  const double h = dot(d, n);
  const Point3 proj{d[0] - h * n[0], d[1] - h * n[1], d[2] - h * n[2]};
  double best = 180;
  // The corners of the facet at v (in loop order), and whether the facet covers the ray: the same for each corner.
  const auto [first, last] = corners_at(facet, v);
  const int known = first == last || scan_rays ? 0 : indexed_corner_covers(facet, v, proj);
  const bool inside = known != 0 ? known > 0 : first != last && facet_covers_ray(facet, plc->vertices[v], proj, v, kNoIndex);
  if (corner) *corner = !inside;
  for (auto corner = first; corner != last; ++corner) {
    const auto& loop = plc->facets[facet].polygons[(*corner)[1]];
    const std::size_t k = (*corner)[2];
    const Point3 p = sub(plc->vertices[loop[(k + loop.size() - 1) % loop.size()]], plc->vertices[v]);
    const Point3 q = sub(plc->vertices[loop[(k + 1) % loop.size()]], plc->vertices[v]);
    const double angle = inside ? std::abs(90.0 - angle_deg(d, n)) : std::min(angle_deg(d, p), angle_deg(d, q));
    best = std::min(best, angle);
  }
  return best;
}

bool InputComplex::segment_facet_acute(Index v, Index segment, Index facet) const {
  bool corner = false;
  const double angle = segment_facet_angle_deg(v, segment, facet, &corner);
  return angle < (corner ? corner_acute_deg : kPaperAcuteDeg);
}

bool InputComplex::element_contains_vertex(ElementRef e, Index v) const {
  switch (e.kind) {
    case ElementKind::Vertex: return e.id == v;
    case ElementKind::Segment: return segments[e.id].a == v || segments[e.id].b == v;
    case ElementKind::Facet: return std::binary_search(facet_vertices[e.id].begin(), facet_vertices[e.id].end(), v);
  }
  return false;
}

bool InputComplex::is_apex(Index v) const {
  if (apex_state.empty()) apex_state.assign(vertex_segments.size(), 0);
  if (apex_state[v] == 0) {
    std::vector<ElementRef> through;
    for (Index s : vertex_segments[v]) through.push_back({ElementKind::Segment, s});
    for (Index f : vertex_facets[v]) through.push_back({ElementKind::Facet, f});
    bool apex = false;
    for (std::size_t i = 0; i < through.size() && !apex; ++i)
      for (std::size_t j = i + 1; j < through.size() && !apex; ++j) apex = elements_meet_acute(through[i], through[j]);
    apex_state[v] = apex ? 2 : 1;
  }
  return apex_state[v] == 2;
}

bool InputComplex::element_has_apex(ElementRef e) const {
  switch (e.kind) {
    case ElementKind::Vertex: return is_apex(e.id);
    case ElementKind::Segment: return is_apex(segments[e.id].a) || is_apex(segments[e.id].b);
    case ElementKind::Facet:
      if (facet_apex_state.empty()) facet_apex_state.assign(facet_vertices.size(), 0);
      if (facet_apex_state[e.id] == 0) {
        bool apex = false;
        for (Index v : facet_vertices[e.id])
          if ((apex = is_apex(v))) break;
        facet_apex_state[e.id] = apex ? 2 : 1;
      }
      return facet_apex_state[e.id] == 2;
  }
  return true;
}

bool InputComplex::reaches_apex(Index v) const {
  if (reach_state.empty()) reach_state.assign(vertex_segments.size(), 0);
  if (reach_state[v] == 0) {
    bool apex = is_apex(v);
    for (Index s : vertex_segments[v])
      if (!apex) apex = element_has_apex({ElementKind::Segment, s});
    for (Index f : vertex_facets[v])
      if (!apex) apex = element_has_apex({ElementKind::Facet, f});
    reach_state[v] = apex ? 2 : 1;
  }
  return reach_state[v] == 2;
}

bool InputComplex::elements_meet_acute(ElementRef a, ElementRef b) const {
  if (a.kind == ElementKind::Vertex && b.kind == ElementKind::Vertex && a.id == b.id) return false;
  if (b.kind == ElementKind::Vertex) std::swap(a, b);
  if (a.kind == ElementKind::Vertex) {
    // An input vertex: through the segments and facets incident to it, unless b contains it. Cached by the pair:
    // two input vertices cost (segments + facets)^2 element pairs, and on a CAD surface, where every node is an
    // input vertex of a dozen triangles and their edges, pumping and the improvement pass ask for the same pairs of
    // neighbours again and again (tet_touches_acute_angle).
    const std::uint64_t key = (std::uint64_t(a.id) << 32) | b.id;
    auto& cache = vertex_pair_cache[static_cast<int>(b.kind)];
    if (const std::uint8_t* cached = cache.find(key)) return *cached != 0;
    const bool acute = [&] {
      if (element_contains_vertex(b, a.id)) return false;
      if (!reaches_apex(a.id)) return false;  // exact: see is_apex
      if (b.kind == ElementKind::Vertex ? !reaches_apex(b.id) : !element_has_apex(b)) return false;
      for (Index s : vertex_segments[a.id])
        if (elements_meet_acute({ElementKind::Segment, s}, b)) return true;
      for (Index f : vertex_facets[a.id])
        if (elements_meet_acute({ElementKind::Facet, f}, b)) return true;
      return false;
    }();
    cache.insert(key, std::uint8_t(acute));
    return acute;
  }
  if (a.kind == b.kind && a.id == b.id) return false;
  if (b.kind < a.kind || (a.kind == b.kind && b.id < a.id)) std::swap(a, b);
  // The two low bits say which pair it is (segment-segment 0, segment-facet 1, facet-facet 2), below b's id. They
  // once held the kind's raw value shifted by one, so a facet-facet key set bit 2, b's lowest id bit: the pairs
  // (f, 2m) and (f, 2m + 1) shared one answer, and on bunny00.off two facets with no common vertex were answered
  // "acute" from their neighbour's entry.
  const std::uint64_t pair_code = a.kind == ElementKind::Facet ? 2 : b.kind == ElementKind::Facet ? 1 : 0;
  const std::uint64_t cache_key = (std::uint64_t(a.id) << 33) | (std::uint64_t(b.id) << 2) | pair_code;
  if (const std::uint8_t* cached = acute_pair_cache.find(cache_key)) return *cached != 0;
  bool acute = false;
  auto seg_dir = [&](Index s, Index v) {
    const Segment& seg = segments[s];
    return sub(plc->vertices[seg.a == v ? seg.b : seg.a], plc->vertices[v]);
  };
  if (a.kind == ElementKind::Segment && b.kind == ElementKind::Segment) {
    const Segment& sa = segments[a.id];
    const Segment& sb = segments[b.id];
    for (Index v : {sa.a, sa.b})
      if ((v == sb.a || v == sb.b) && angle_deg(seg_dir(a.id, v), seg_dir(b.id, v)) < corner_acute_deg) acute = true;
  } else if (a.kind == ElementKind::Segment) {  // segment a, facet b
    if (!facet_has_segment(b.id, a.id)) {
      const Segment& sa = segments[a.id];
      const auto& fv = facet_vertices[b.id];
      for (Index v : {sa.a, sa.b})
        if (std::binary_search(fv.begin(), fv.end(), v) && segment_facet_acute(v, a.id, b.id))
          acute = true;
    }
  } else {  // two facets
    // The common vertices in increasing order, walking the smaller of the two sorted sets.
    const bool a_smaller = facet_vertices[a.id].size() <= facet_vertices[b.id].size();
    const auto& fa = facet_vertices[a_smaller ? a.id : b.id];
    const auto& fb = facet_vertices[a_smaller ? b.id : a.id];
    for (Index v : fa) {
      if (acute) break;
      if (!std::binary_search(fb.begin(), fb.end(), v)) continue;
      bool share_segment = false;
      for (Index s : vertex_segments[v]) share_segment |= facet_has_segment(a.id, s) && facet_has_segment(b.id, s);
      for (Index s : vertex_segments[v]) {
        const bool in_a = facet_has_segment(a.id, s), in_b = facet_has_segment(b.id, s);
        if (share_segment && !(in_a && in_b)) continue;  // facets through a common segment: the dihedral decides
        if (in_a && in_b) {
          if (facets_acute_along(s, a.id, b.id)) acute = true;  // shared segment: the dihedral angle
        } else if (in_a && !in_b) {
          if (segment_facet_acute(v, s, b.id)) acute = true;
        } else if (in_b && !in_a) {
          if (segment_facet_acute(v, s, a.id)) acute = true;
        }
      }
    }
  }
  acute_pair_cache.insert(cache_key, std::uint8_t(acute));
  return acute;
}

bool InputComplex::facet_covers_ray(Index facet, const Point3& origin, const Point3& dir, Index skip,
                                    Index skip2) const {
  const PlaneFrame& fr = frames[facet];
  const double dx = dot(dir, fr.e1), dy = dot(dir, fr.e2);
  const auto local = [&](Index w) {
    const Point3 r = sub(plc->vertices[w], origin);
    const double u = dot(r, fr.e1), v = dot(r, fr.e2);
    return std::array<double, 2>{u * dx + v * dy, -u * dy + v * dx};  // along the ray, across it
  };
  bool inside = false;
  for (const auto& loop : plc->facets[facet].polygons) {
    if (loop.size() < 3) continue;
    for (std::size_t k = 0; k < loop.size(); ++k) {
      const Index a = loop[k], b = loop[(k + 1) % loop.size()];
      if (skip2 == kNoIndex ? (a == skip || b == skip) : ((a == skip && b == skip2) || (a == skip2 && b == skip)))
        continue;
      const auto p = local(a), q = local(b);
      if ((p[1] > 0) == (q[1] > 0)) continue;  // half-open rule: a vertex on the ray counts once
      const double x = p[0] + (q[0] - p[0]) * (0 - p[1]) / (q[1] - p[1]);
      if (x > 0) inside = !inside;
    }
  }
  return inside;
}

std::vector<Point3> InputComplex::inward_directions(Index facet, Index segment) const {
  const int side = scan_rays ? 0 : indexed_edge_side(facet, segment);
  if (side == 0) return scan_inward_directions(facet, segment);
  const Segment& seg = segments[segment];
  const Point3 d = normalized(cross(frames[facet].normal, sub(plc->vertices[seg.b], plc->vertices[seg.a])));
  return {side > 0 ? d : Point3{-d[0], -d[1], -d[2]}};
}

std::vector<Point3> InputComplex::scan_inward_directions(Index facet, Index segment) const {
  const Segment& seg = segments[segment];
  const Point3& a = plc->vertices[seg.a];
  const Point3& b = plc->vertices[seg.b];
  const Point3 mid{0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1]), 0.5 * (a[2] + b[2])};
  const Point3 d = normalized(cross(frames[facet].normal, sub(b, a)));
  const Point3 minus{-d[0], -d[1], -d[2]};
  std::vector<Point3> out;
  if (facet_covers_ray(facet, mid, d, seg.a, seg.b)) out.push_back(d);
  if (facet_covers_ray(facet, mid, minus, seg.a, seg.b)) out.push_back(minus);
  if (out.empty()) out = {d, minus};  // degenerate loops: both sides, so an acute side is not missed
  return out;
}

bool InputComplex::facets_acute_along(Index segment, Index f, Index g) const {
  for (const Point3& df : inward_directions(f, segment))
    for (const Point3& dg : inward_directions(g, segment))
      if (angle_deg(df, dg) < kPaperAcuteDeg) return true;
  return false;
}

InputComplex build_input_complex(const Plc& plc, bool scan_rays, double corner_acute_deg) {
  InputComplex c;
  c.plc = &plc;
  c.scan_rays = scan_rays;
  c.corner_acute_deg = corner_acute_deg;
  c.segments = collect_segments(plc);
  const std::size_t nv = plc.vertices.size();
  c.vertex_segments.resize(nv);
  c.vertex_facets.resize(nv);
  c.segment_facets.resize(c.segments.size());
  c.acute_vertex.assign(nv, 0);
  c.segment_index.reserve(c.segments.size());
  for (Index s = 0; s < c.segments.size(); ++s) {
    c.segment_index.insert(InputComplex::key(c.segments[s].a, c.segments[s].b), s);
    c.vertex_segments[c.segments[s].a].push_back(s);
    c.vertex_segments[c.segments[s].b].push_back(s);
  }

  c.frames.resize(plc.facets.size());
  c.facet_vertices.resize(plc.facets.size());
  for (Index f = 0; f < plc.facets.size(); ++f) {
    const Facet& facet = plc.facets[f];
    std::vector<Index>& verts = c.facet_vertices[f];
    // Count closed polygons per edge (parity) and note 2-vertex loops.
    std::unordered_map<std::uint64_t, int> polygon_count;
    std::vector<Index> inside_segments;
    for (const auto& loop : facet.polygons) {
      for (Index v : loop) verts.push_back(v);
      if (loop.size() >= 3) {
        for (std::size_t i = 0; i < loop.size(); ++i) {
          const Index a = loop[i], b = loop[(i + 1) % loop.size()];
          if (a != b) ++polygon_count[InputComplex::key(a, b)];
        }
      } else if (loop.size() == 2 && loop[0] != loop[1]) {
        inside_segments.push_back(c.find_segment(loop[0], loop[1]));
      }
    }
    std::sort(verts.begin(), verts.end());
    verts.erase(std::unique(verts.begin(), verts.end()), verts.end());
    for (Index v : verts) c.vertex_facets[v].push_back(f);
    for (const auto& [k, count] : polygon_count) {
      const Index s = c.find_segment(Index(k >> 32), Index(k & 0xffffffffu));
      c.segment_facets[s].push_back({f, true, (count % 2) == 1});
    }
    for (Index s : inside_segments) {
      if (s == kNoIndex || c.facet_has_segment(f, s)) continue;
      c.segment_facets[s].push_back({f, false, false});
    }

    PlaneFrame& frame = c.frames[f];
    Point3 n = facet_normal(plc, facet);
    if (dot(n, n) == 0) {
      throw InputError(ErrorCode::DegenerateFacet, "facet " + std::to_string(f) + " spans no plane", plc.name, 0,
                       ElementIds{{}, {}, {f}, {}});
    }
    frame.origin = plc.vertices[verts.front()];
    // Snap an axis-aligned normal (within rounding) to the exact axis so that grid inputs keep exact coordinates.
    int axis = -1;
    for (int i = 0; i < 3; ++i)
      if (std::abs(n[i]) > 1 - 1e-14) axis = i;
    if (axis >= 0) {
      const double s = n[axis] > 0 ? 1.0 : -1.0;
      n = {0, 0, 0};
      n[axis] = s;
      frame.e1 = {0, 0, 0};
      frame.e2 = {0, 0, 0};
      frame.e1[(axis + 1) % 3] = 1;
      frame.e2[(axis + 2) % 3] = 1;
    } else {
      const Point3 helper = std::abs(n[0]) < 0.6 ? Point3{1, 0, 0} : Point3{0, 1, 0};
      frame.e1 = normalized(cross(helper, n));
      frame.e2 = cross(n, frame.e1);
    }
    frame.normal = n;
  }
  for (auto& list : c.segment_facets)
    std::sort(list.begin(), list.end(), [](const SegmentInFacet& x, const SegmentInFacet& y) { return x.facet < y.facet; });
  c.facet_index.resize(plc.facets.size());
  for (Index f = 0; f < plc.facets.size(); ++f) c.build_facet_index(f);

  compute_plane_groups(plc, c);

  // Acute input angles (Section 3.7 assumes none): segment-segment at a shared vertex, segment-facet at a shared
  // vertex (segment not in the facet), facet-facet along a shared segment.
  for (Index v = 0; v < nv; ++v) {
    const auto& segs = c.vertex_segments[v];
    auto direction = [&](Index s) {
      const Segment& seg = c.segments[s];
      return sub(plc.vertices[seg.a == v ? seg.b : seg.a], plc.vertices[v]);
    };
    bool acute = false;
    for (std::size_t i = 0; i < segs.size() && !acute; ++i)
      for (std::size_t j = i + 1; j < segs.size() && !acute; ++j)
        if (angle_deg(direction(segs[i]), direction(segs[j])) < kPaperAcuteDeg) acute = true;
    for (std::size_t i = 0; i < segs.size() && !acute; ++i) {
      for (Index f : c.vertex_facets[v]) {
        if (acute || c.facet_has_segment(f, segs[i])) continue;
        // Angle between the segment and the facet at v: its elevation over the plane when it projects into the
        // facet's corner at v (convex or not), else the angle to the nearer corner edge.
        if (c.segment_facet_angle_deg(v, segs[i], f) < kPaperAcuteDeg) acute = true;
      }
    }
    c.acute_vertex[v] = acute;
  }
  for (Index s = 0; s < c.segments.size(); ++s) {
    const auto& fs = c.segment_facets[s];
    if (fs.size() < 2) continue;
    const Segment& seg = c.segments[s];
    for (std::size_t i = 0; i < fs.size(); ++i)
      for (std::size_t j = i + 1; j < fs.size(); ++j)
        if (c.facets_acute_along(s, fs[i].facet, fs[j].facet)) {
          c.acute_vertex[seg.a] = 1;
          c.acute_vertex[seg.b] = 1;
        }
  }
  return c;
}

}  // namespace qualmesh::detail
