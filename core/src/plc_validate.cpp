// PLC validation, driver and structural checks (paper Section 2: the PLC definition; DESIGN.md: typed errors that
// name the offending ids). Order of the checks: empty input, index range, finite coordinates, duplicate vertices,
// degenerate segments and facets, planarity, facet triangulation, closedness, then the PLC intersection rule
// (plc_validate_intersections.cpp) and the input angles (plc_validate_angles.cpp). Geometric stages run only on
// sound data (finite coordinates, indices in range) and only on the facets that passed the structural checks.
#include "qualmesh/plc_validate.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <unordered_map>
#include <unordered_set>

#include "cgal_types.h"
#include "facet_triangulation.h"
#include "plc_validate_internal.h"

namespace qualmesh {
namespace detail {

std::string format_point(const Point3& p) {
  char text[96];
  std::snprintf(text, sizeof text, "(%.17g, %.17g, %.17g)", p[0], p[1], p[2]);
  return text;
}

}  // namespace detail

namespace {

using detail::ProblemSink;
using detail::Kernel;  // cgal_types.h: the one place the kernel is chosen

bool is_finite(const Point3& p) { return std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]); }

std::string str(std::size_t i) { return std::to_string(i); }

std::uint64_t edge_key(Index a, Index b) {
  if (a > b) std::swap(a, b);
  return (static_cast<std::uint64_t>(a) << 32) | b;
}

// Index range; returns false when anything refers to a vertex that does not exist.
bool check_indices(const Plc& plc, ProblemSink& sink) {
  const std::size_t nv = plc.vertices.size();
  bool ok = true;
  for (std::size_t s = 0; s < plc.segments.size(); ++s) {
    for (Index v : {plc.segments[s].a, plc.segments[s].b}) {
      if (v < nv) continue;
      ok = false;
      ElementIds ids;
      ids.vertices = std::vector<Index>{v};
      sink.add(ErrorCode::IndexOutOfRange,
               "explicit segment " + str(s) + " refers to vertex " + str(v) + ", but there are " + str(nv) +
                   " vertices",
               ids);
    }
  }
  for (std::size_t f = 0; f < plc.facets.size(); ++f) {
    for (const auto& loop : plc.facets[f].polygons) {
      for (Index v : loop) {
        if (v < nv) continue;
        ok = false;
        ElementIds ids;
        ids.vertices = std::vector<Index>{v};
        ids.facets = std::vector<Index>{static_cast<Index>(f)};
        sink.add(ErrorCode::IndexOutOfRange,
                 "facet " + str(f) + " refers to vertex " + str(v) + ", but there are " + str(nv) + " vertices",
                 ids);
      }
    }
  }
  return ok;
}

bool check_finite(const Plc& plc, ProblemSink& sink) {
  bool ok = true;
  for (std::size_t v = 0; v < plc.vertices.size(); ++v) {
    if (is_finite(plc.vertices[v])) continue;
    ok = false;
    ElementIds ids;
    ids.vertices = std::vector<Index>{static_cast<Index>(v)};
    sink.add(ErrorCode::NonFinite, "vertex " + str(v) + " has a non-finite coordinate " +
                                       detail::format_point(plc.vertices[v]), ids);
  }
  for (std::size_t f = 0; f < plc.facets.size(); ++f) {
    for (std::size_t h = 0; h < plc.facets[f].holes.size(); ++h) {
      if (is_finite(plc.facets[f].holes[h])) continue;
      ok = false;
      ElementIds ids;
      ids.facets = std::vector<Index>{static_cast<Index>(f)};
      sink.add(ErrorCode::NonFinite, "hole point " + str(h) + " of facet " + str(f) + " is not finite", ids);
    }
  }
  for (std::size_t h = 0; h < plc.holes.size(); ++h) {
    if (is_finite(plc.holes[h])) continue;
    ok = false;
    sink.add(ErrorCode::NonFinite, "volume hole point " + str(h) + " is not finite", {});
  }
  for (std::size_t r = 0; r < plc.regions.size(); ++r) {
    if (is_finite(plc.regions[r].point)) continue;
    ok = false;
    sink.add(ErrorCode::NonFinite, "region seed " + str(r) + " is not finite", {});
  }
  return ok;
}

// Exact duplicates: sort by coordinates, compare neighbours. Returns each vertex's representative (the smallest id
// at its position).
std::vector<Index> check_duplicates(const Plc& plc, ProblemSink& sink) {
  const std::size_t nv = plc.vertices.size();
  std::vector<Index> order(nv), representative(nv);
  std::iota(order.begin(), order.end(), Index{0});
  std::iota(representative.begin(), representative.end(), Index{0});
  std::vector<Index> finite;
  finite.reserve(nv);
  for (Index v : order)
    if (is_finite(plc.vertices[v])) finite.push_back(v);
  std::sort(finite.begin(), finite.end(), [&plc](Index a, Index b) {
    if (plc.vertices[a] != plc.vertices[b]) return plc.vertices[a] < plc.vertices[b];
    return a < b;
  });
  for (std::size_t i = 1; i < finite.size(); ++i) {
    const Index prev = finite[i - 1], cur = finite[i];
    if (plc.vertices[prev] != plc.vertices[cur]) continue;
    representative[cur] = representative[prev];
    ElementIds ids;
    ids.vertices = std::vector<Index>{representative[prev], cur};
    sink.add(ErrorCode::DuplicateVertex,
             "vertices " + str(representative[prev]) + " and " + str(cur) + " are at the same position " +
                 detail::format_point(plc.vertices[cur]),
             ids);
  }
  return representative;
}

void check_degenerate_segments(const Plc& plc, ProblemSink& sink) {
  for (std::size_t s = 0; s < plc.segments.size(); ++s) {
    if (plc.segments[s].a != plc.segments[s].b) continue;
    ElementIds ids;
    ids.vertices = std::vector<Index>{plc.segments[s].a};
    sink.add(ErrorCode::DegenerateSegment,
             "explicit segment " + str(s) + " has both ends at vertex " + str(plc.segments[s].a), ids);
  }
  for (std::size_t f = 0; f < plc.facets.size(); ++f) {
    for (const auto& loop : plc.facets[f].polygons) {
      if (loop.size() != 2 || loop[0] != loop[1]) continue;
      ElementIds ids;
      ids.vertices = std::vector<Index>{loop[0]};
      ids.facets = std::vector<Index>{static_cast<Index>(f)};
      sink.add(ErrorCode::DegenerateSegment,
               "a segment of facet " + str(f) + " has both ends at vertex " + str(loop[0]), ids);
    }
  }
}

// Structural checks of one facet (indices known to be in range). Returns false when a problem was reported.
bool check_facet_loops(const Plc& plc, Index f, bool coordinates_ok, ProblemSink& sink) {
  const Facet& facet = plc.facets[f];
  ElementIds ids;
  ids.facets = std::vector<Index>{f};
  bool has_polygon = false;
  for (std::size_t k = 0; k < facet.polygons.size(); ++k) {
    const auto& loop = facet.polygons[k];
    if (loop.size() < 3) continue;
    has_polygon = true;
    std::vector<Index> sorted(loop);
    std::sort(sorted.begin(), sorted.end());
    auto repeat = std::adjacent_find(sorted.begin(), sorted.end());
    if (repeat != sorted.end()) {
      ElementIds with_vertex = ids;
      with_vertex.vertices = std::vector<Index>{*repeat};
      const std::size_t distinct = static_cast<std::size_t>(
          std::distance(sorted.begin(), std::unique(sorted.begin(), sorted.end())));
      sink.add(ErrorCode::DegenerateFacet,
               "polygon " + str(k) + " of facet " + str(f) + " repeats vertex " + str(*repeat) +
                   (distinct < 3 ? " (fewer than 3 distinct vertices)" : ""),
               with_vertex);
      return false;
    }
    if (!coordinates_ok) continue;
    // Zero area: every vertex on the line through the first two (exact predicate).
    const Point3& p = plc.vertices[loop[0]];
    const Point3& q = plc.vertices[loop[1]];
    const Kernel::Point_3 kp(p[0], p[1], p[2]), kq(q[0], q[1], q[2]);
    bool collinear = kp != kq;
    for (std::size_t i = 2; i < loop.size() && collinear; ++i) {
      const Point3& r = plc.vertices[loop[i]];
      collinear = CGAL::collinear(kp, kq, Kernel::Point_3(r[0], r[1], r[2]));
    }
    if (collinear) {
      ElementIds with_vertices = ids;
      with_vertices.vertices = loop;
      sink.add(ErrorCode::DegenerateFacet,
               "polygon " + str(k) + " of facet " + str(f) + " has zero area (all its vertices are collinear)",
               with_vertices);
      return false;
    }
  }
  if (!has_polygon) {
    sink.add(ErrorCode::DegenerateFacet, "facet " + str(f) + " has no polygon of 3 or more vertices", ids);
    return false;
  }
  return true;
}

// Closedness. An edge bounds a facet when the facet's polygons use it an odd number of times (an edge used twice
// by one facet is interior to it, plc.h's odd-coverage rule). The boundary is closed when every such edge bounds at
// least two facets. Not "an even number": a multi-region PLC (example.poly, or a box split by an internal facet)
// has edges on three facets, and cubes.off an edge on four; only an edge on a single facet is a rim that leaves
// the volume open.
bool check_closed(const Plc& plc, const ValidateOptions& options, ProblemSink& sink) {
  struct Use {
    std::uint32_t count = 0;
    Index first_facet = kNoIndex;
  };
  std::unordered_map<std::uint64_t, Use> uses;
  std::vector<std::uint64_t> edges;
  for (std::size_t f = 0; f < plc.facets.size(); ++f) {
    edges.clear();
    for (const auto& loop : plc.facets[f].polygons) {
      if (loop.size() < 3) continue;
      for (std::size_t i = 0; i < loop.size(); ++i) {
        const Index a = loop[i], b = loop[(i + 1) % loop.size()];
        if (a != b) edges.push_back(edge_key(a, b));
      }
    }
    std::sort(edges.begin(), edges.end());
    for (std::size_t i = 0; i < edges.size();) {
      std::size_t j = i;
      while (j < edges.size() && edges[j] == edges[i]) ++j;
      if ((j - i) % 2 == 1) {
        Use& use = uses[edges[i]];
        ++use.count;
        if (use.first_facet == kNoIndex) use.first_facet = static_cast<Index>(f);
      }
      i = j;
    }
  }
  std::vector<std::pair<std::uint64_t, Use>> rims;
  for (const auto& entry : uses)
    if (entry.second.count == 1) rims.push_back(entry);
  if (rims.empty()) return true;
  if (!options.require_closed) return false;
  std::sort(rims.begin(), rims.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
  for (const auto& [key, use] : rims) {
    const Index a = static_cast<Index>(key >> 32), b = static_cast<Index>(key & 0xffffffffu);
    ElementIds ids;
    ids.vertices = std::vector<Index>{a, b};
    ids.facets = std::vector<Index>{use.first_facet};
    sink.add(ErrorCode::OpenBoundary,
             "edge (" + str(a) + ", " + str(b) + ") of facet " + str(use.first_facet) +
                 " is on no other facet: the boundary is not closed",
             ids);
  }
  return false;
}

}  // namespace

const char* to_string(AngleKind kind) {
  switch (kind) {
    case AngleKind::SegmentSegment: return "segment-segment";
    case AngleKind::SegmentFacet: return "segment-facet";
    case AngleKind::FacetFacet: return "facet-facet";
  }
  return "unknown";
}

std::size_t ValidationReport::num_problems(ErrorCode code) const {
  for (const ProblemCount& c : problem_counts)
    if (c.code == code) return c.count;
  return 0;
}

ValidationReport validate_plc(const Plc& plc, const ValidateOptions& options) {
  ValidationReport report;
  ProblemSink sink(options.max_problems_per_kind);
  if (plc.vertices.empty() || plc.facets.empty()) {
    sink.add(ErrorCode::Empty,
             plc.vertices.empty() ? std::string("the PLC has no vertex") : std::string("the PLC has no facet"), {});
  }
  const bool indices_ok = check_indices(plc, sink);
  const bool finite_ok = check_finite(plc, sink);
  detail::ValidationInput input;
  input.plc = &plc;
  input.representative = check_duplicates(plc, sink);
  check_degenerate_segments(plc, sink);

  // Facets: loops, plane, planarity, triangulation.
  const double tolerance = options.planarity_tolerance * bounding_box(plc).diagonal();
  input.facet_usable.assign(plc.facets.size(), 0);
  input.triangulations.resize(plc.facets.size());
  if (indices_ok) {
    for (std::size_t fi = 0; fi < plc.facets.size(); ++fi) {
      const Index f = static_cast<Index>(fi);
      if (!check_facet_loops(plc, f, finite_ok, sink) || !finite_ok) continue;
      const Facet& facet = plc.facets[f];
      ElementIds ids;
      ids.facets = std::vector<Index>{f};
      const auto frame = detail::compute_facet_frame(plc.vertices, facet);
      if (!frame) {
        sink.add(ErrorCode::DegenerateFacet, "facet " + str(f) + " has zero area (all its vertices are collinear)",
                 ids);
        continue;
      }
      double worst = 0;
      Index worst_vertex = kNoIndex;
      for (const auto& loop : facet.polygons) {
        for (Index v : loop) {
          const double d = std::abs(detail::signed_distance(*frame, plc.vertices[v]));
          if (d > worst) worst = d, worst_vertex = v;
        }
      }
      if (worst > tolerance) {
        ids.vertices = std::vector<Index>{worst_vertex};
        char text[200];
        std::snprintf(text, sizeof text,
                      "facet %u is not planar: vertex %u is %.3g from the facet's plane (tolerance %.3g = %.3g of "
                      "the bounding-box diagonal)",
                      f, worst_vertex, worst, tolerance, options.planarity_tolerance);
        sink.add(ErrorCode::NonPlanarFacet, text, ids);
        continue;
      }
      input.triangulations[f] = detail::triangulate_facet(plc.vertices, facet, *frame);
      if (input.triangulations[f].triangles.empty()) {
        sink.add(ErrorCode::DegenerateFacet, "facet " + str(f) + " encloses no area (its polygons cancel out)", ids);
        continue;
      }
      input.facet_usable[f] = 1;
    }
  }

  report.closed = indices_ok && !plc.facets.empty() && check_closed(plc, options, sink);

  if (indices_ok && finite_ok) {
    input.segments = collect_segments(plc);
    report.num_segments = input.segments.size();
    if (options.check_intersections) detail::check_intersections(input, sink);
    detail::measure_input_angles(input, options, report);
  }
  sink.move_into(report);
  return report;
}

void throw_if_invalid(const ValidationReport& report, const std::string& file) {
  if (report.ok()) return;
  const Problem& first = report.problems.front();
  std::string message = first.message;
  const std::size_t total = [&report] {
    std::size_t n = 0;
    for (const ProblemCount& c : report.problem_counts) n += c.count;
    return n;
  }();
  if (total > 1) message += " (and " + std::to_string(total - 1) + " more problems)";
  throw InputError(first.code, message, file, 0, first.ids);
}

}  // namespace qualmesh
