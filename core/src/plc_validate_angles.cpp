// PLC validation: the input angles of the paper's Section 2 ("the angle between two segments sharing a vertex, a
// segment and a facet sharing one vertex, or two facets sharing ... a segment"). The paper's guarantees assume none
// is below 90 degrees (Lemma 3.3 and 3.4 rely on it); QualMesh lists the acute ones so that feature protection can
// cover them.
//  - segment-segment: every pair of segments (collect_segments) at a vertex, the angle between their directions;
//  - segment-facet: a segment uv and a facet that contains u but not v: the smallest angle between the ray u->v and
//    the facet near u, taken over the facet's triangles at u (the angle to the plane when the ray projects into a
//    corner, else to the nearer corner edge);
//  - facet-facet: at each segment, every facet side (a facet triangle on that edge) is sorted by its angle about
//    the segment; each angular gap between consecutive sides of different facets is an input angle. A segment on
//    two facets gives both the interior and the exterior dihedral angle (they sum to 360), because the paper
//    boxes non-convex domains, so both sides are meshed. Coplanar neighbours give 180.
// Facet-facet angles at a shared vertex only are not measured. All in double precision; cost linear in the sum of
// squared vertex degrees.
#include <algorithm>
#include <cmath>
#include <queue>
#include <unordered_map>
#include <vector>

#include "plc_validate_internal.h"
#include "vec3.h"

namespace qualmesh::detail {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = 180.0 / kPi;
constexpr double kSlackDeg = 1e-7;

using namespace vec3;

// Angle between two vectors in degrees, [0, 180]; robust near 0 and 180 (atan2 of |cross| and dot).
double angle_deg(const Point3& a, const Point3& b) { return std::atan2(norm(cross(a, b)), dot(a, b)) * kDeg; }

std::uint64_t edge_key(Index a, Index b) {
  if (a > b) std::swap(a, b);
  return (static_cast<std::uint64_t>(a) << 32) | b;
}

// Keeps counts, minima and the `cap` smallest acute angles of each kind.
class AngleCollector {
 public:
  AngleCollector(const ValidateOptions& options, ValidationReport& report)
      : threshold_(options.acute_threshold_deg - kSlackDeg), cap_(options.max_problems_per_kind), report_(report) {}

  void add(const InputAngle& angle) {
    const auto k = static_cast<std::size_t>(angle.kind);
    report_.min_angle_deg_by_kind[k] = std::min(report_.min_angle_deg_by_kind[k], angle.angle_deg);
    report_.min_input_angle_deg = std::min(report_.min_input_angle_deg, angle.angle_deg);
    if (!(angle.angle_deg < threshold_)) return;
    ++report_.num_acute_by_kind[k];
    ++report_.num_acute_angles;
    auto& heap = smallest_[k];
    if (heap.size() < cap_) {
      heap.push(angle);
    } else if (cap_ > 0 && angle.angle_deg < heap.top().angle_deg) {
      heap.pop();
      heap.push(angle);
    }
  }

  void finish() {
    report_.acute_angles.clear();
    for (auto& heap : smallest_) {
      while (!heap.empty()) {
        report_.acute_angles.push_back(heap.top());
        heap.pop();
      }
    }
    std::stable_sort(report_.acute_angles.begin(), report_.acute_angles.end(),
                     [](const InputAngle& x, const InputAngle& y) {
                       if (x.angle_deg != y.angle_deg) return x.angle_deg < y.angle_deg;
                       if (x.kind != y.kind) return x.kind < y.kind;
                       if (x.apex_vertex != y.apex_vertex) return x.apex_vertex < y.apex_vertex;
                       if (x.first != y.first) return x.first < y.first;
                       return x.second < y.second;
                     });
  }

 private:
  struct Larger {
    bool operator()(const InputAngle& x, const InputAngle& y) const { return x.angle_deg < y.angle_deg; }
  };
  double threshold_;
  std::size_t cap_;
  ValidationReport& report_;
  std::priority_queue<InputAngle, std::vector<InputAngle>, Larger> smallest_[3];  // max-heaps
};

// Compressed lists: items of key k are items[start[k] .. start[k+1]).
template <class T>
struct Csr {
  std::vector<std::size_t> start;
  std::vector<T> items;
};

template <class T, class Emit>
Csr<T> build_csr(std::size_t num_keys, Emit emit_all) {
  Csr<T> csr;
  csr.start.assign(num_keys + 1, 0);
  emit_all([&](std::size_t key, const T&) { ++csr.start[key + 1]; });
  for (std::size_t k = 0; k < num_keys; ++k) csr.start[k + 1] += csr.start[k];
  csr.items.resize(csr.start[num_keys]);
  std::vector<std::size_t> fill(csr.start.begin(), csr.start.end() - 1);
  emit_all([&](std::size_t key, const T& item) { csr.items[fill[key]++] = item; });
  return csr;
}

struct Corner {
  Index facet;
  Index triangle;
  int corner;  // 0..2 in the triangle
};

class AngleMeter {
 public:
  AngleMeter(const ValidationInput& input, AngleCollector& collector)
      : input_(input), plc_(*input.plc), out_(collector) {}

  void run() {
    const std::size_t nv = plc_.vertices.size();
    segments_at_ = build_csr<Index>(nv, [this](auto&& emit) {
      for (std::size_t s = 0; s < input_.segments.size(); ++s) {
        emit(input_.segments[s].a, static_cast<Index>(s));
        emit(input_.segments[s].b, static_cast<Index>(s));
      }
    });
    corners_at_ = build_csr<Corner>(nv, [this](auto&& emit) {
      for (std::size_t f = 0; f < input_.triangulations.size(); ++f) {
        if (!input_.facet_usable[f]) continue;
        const FacetTriangulation& tri = input_.triangulations[f];
        for (std::size_t t = 0; t < tri.triangles.size(); ++t)
          for (int c = 0; c < 3; ++c)
            if (tri.is_plc_vertex(tri.triangles[t][c]))
              emit(tri.triangles[t][c], Corner{static_cast<Index>(f), static_cast<Index>(t), c});
      }
    });
    // Sorted vertex ids of each facet, for "does facet F contain vertex w".
    facet_vertices_.resize(plc_.facets.size());
    for (std::size_t f = 0; f < plc_.facets.size(); ++f) {
      auto& ids = facet_vertices_[f];
      for (const auto& loop : plc_.facets[f].polygons) ids.insert(ids.end(), loop.begin(), loop.end());
      std::sort(ids.begin(), ids.end());
      ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
    }
    for (Index v = 0; v < nv; ++v) {
      measure_segment_pairs(v);
      measure_segment_facets(v);
    }
    measure_dihedrals();
  }

 private:
  const Point3& p(Index v) const { return plc_.vertices[v]; }
  Index other_end(Index s, Index v) const {
    return input_.segments[s].a == v ? input_.segments[s].b : input_.segments[s].a;
  }

  void measure_segment_pairs(Index v) {
    const std::size_t begin = segments_at_.start[v], end = segments_at_.start[v + 1];
    for (std::size_t i = begin; i < end; ++i) {
      const Index si = segments_at_.items[i];
      const Point3 di = sub(p(other_end(si, v)), p(v));
      if (dot(di, di) == 0) continue;
      for (std::size_t j = i + 1; j < end; ++j) {
        const Index sj = segments_at_.items[j];
        const Point3 dj = sub(p(other_end(sj, v)), p(v));
        if (dot(dj, dj) == 0) continue;
        InputAngle angle;
        angle.kind = AngleKind::SegmentSegment;
        angle.angle_deg = angle_deg(di, dj);
        angle.apex_vertex = v;
        angle.first = std::min(si, sj);
        angle.second = std::max(si, sj);
        out_.add(angle);
      }
    }
  }

  // Smallest angle between the ray `r` from corner c of triangle (facet, t) and that triangle.
  double ray_to_corner_deg(const Corner& corner, const Point3& r) const {
    const FacetTriangulation& tri = input_.triangulations[corner.facet];
    const auto& t = tri.triangles[corner.triangle];
    const Point3& apex = tri.point(plc_.vertices, t[corner.corner]);
    const Point3 e1 = sub(tri.point(plc_.vertices, t[(corner.corner + 1) % 3]), apex);
    const Point3 e2 = sub(tri.point(plc_.vertices, t[(corner.corner + 2) % 3]), apex);
    Point3 n = cross(e1, e2);
    const double len = norm(n);
    if (len > 0) {
      for (double& x : n) x /= len;
      const double height = dot(r, n);
      const Point3 flat = {r[0] - height * n[0], r[1] - height * n[1], r[2] - height * n[2]};
      if (dot(flat, flat) == 0) return 90.0;
      if (dot(cross(e1, flat), n) >= 0 && dot(cross(flat, e2), n) >= 0)
        return std::atan2(std::abs(height), norm(flat)) * kDeg;
    }
    return std::min(angle_deg(r, e1), angle_deg(r, e2));
  }

  bool facet_has_vertex(Index f, Index w) const {
    return std::binary_search(facet_vertices_[f].begin(), facet_vertices_[f].end(), w);
  }

  void measure_segment_facets(Index v) {
    const std::size_t cbegin = corners_at_.start[v], cend = corners_at_.start[v + 1];
    if (cbegin == cend) return;
    for (std::size_t i = segments_at_.start[v]; i < segments_at_.start[v + 1]; ++i) {
      const Index s = segments_at_.items[i];
      const Index w = other_end(s, v);
      const Point3 r = sub(p(w), p(v));
      if (dot(r, r) == 0) continue;
      // Corners are grouped by facet (emitted facet by facet).
      for (std::size_t c = cbegin; c < cend;) {
        const Index f = corners_at_.items[c].facet;
        double best = 180;
        std::size_t next = c;
        for (; next < cend && corners_at_.items[next].facet == f; ++next)
          best = std::min(best, ray_to_corner_deg(corners_at_.items[next], r));
        if (!facet_has_vertex(f, w)) {
          InputAngle angle;
          angle.kind = AngleKind::SegmentFacet;
          angle.angle_deg = best;
          angle.apex_vertex = v;
          angle.first = s;
          angle.second = f;
          out_.add(angle);
        }
        c = next;
      }
    }
  }

  void measure_dihedrals() {
    // Facet sides at each segment: a facet triangle having the segment as an edge, with its third corner.
    std::unordered_map<std::uint64_t, Index> segment_of;
    segment_of.reserve(input_.segments.size() * 2);
    for (std::size_t s = 0; s < input_.segments.size(); ++s)
      segment_of.emplace(edge_key(input_.segments[s].a, input_.segments[s].b), static_cast<Index>(s));
    struct Side {
      Index facet;
      Point3 third;
    };
    const Csr<Side> sides = build_csr<Side>(input_.segments.size(), [&](auto&& emit) {
      for (std::size_t f = 0; f < input_.triangulations.size(); ++f) {
        if (!input_.facet_usable[f]) continue;
        const FacetTriangulation& tri = input_.triangulations[f];
        for (const auto& t : tri.triangles) {
          for (int c = 0; c < 3; ++c) {
            const Index a = t[(c + 1) % 3], b = t[(c + 2) % 3];
            if (!tri.is_plc_vertex(a) || !tri.is_plc_vertex(b)) continue;
            auto it = segment_of.find(edge_key(a, b));
            if (it != segment_of.end()) emit(it->second, Side{static_cast<Index>(f), tri.point(plc_.vertices, t[c])});
          }
        }
      }
    });
    struct Direction {
      double theta;
      Index facet;
    };
    std::vector<Direction> around;
    for (std::size_t s = 0; s < input_.segments.size(); ++s) {
      const std::size_t begin = sides.start[s], end = sides.start[s + 1];
      if (end - begin < 2) continue;
      const Segment& seg = input_.segments[s];
      Point3 axis = sub(p(seg.b), p(seg.a));
      const double len = norm(axis);
      if (len == 0) continue;
      for (double& x : axis) x /= len;
      auto perpendicular = [&](const Point3& q) {
        const Point3 d = sub(q, p(seg.a));
        const double along = dot(d, axis);
        return Point3{d[0] - along * axis[0], d[1] - along * axis[1], d[2] - along * axis[2]};
      };
      Point3 b1 = perpendicular(sides.items[begin].third);
      const double l1 = norm(b1);
      if (l1 == 0) continue;
      for (double& x : b1) x /= l1;
      const Point3 b2 = cross(axis, b1);
      around.clear();
      for (std::size_t i = begin; i < end; ++i) {
        const Point3 d = perpendicular(sides.items[i].third);
        double theta = std::atan2(dot(d, b2), dot(d, b1));
        if (theta < 0) theta += 2 * kPi;
        around.push_back({theta, sides.items[i].facet});
      }
      std::sort(around.begin(), around.end(), [](const Direction& x, const Direction& y) {
        return x.theta != y.theta ? x.theta < y.theta : x.facet < y.facet;
      });
      for (std::size_t i = 0; i < around.size(); ++i) {
        const Direction& from = around[i];
        const Direction& to = around[(i + 1) % around.size()];
        if (from.facet == to.facet) continue;  // one facet continuing through the segment
        double gap = to.theta - from.theta;
        if (i + 1 == around.size()) gap += 2 * kPi;
        InputAngle angle;
        angle.kind = AngleKind::FacetFacet;
        angle.angle_deg = gap * kDeg;
        angle.apex_vertex = seg.a;
        angle.first = from.facet;
        angle.second = to.facet;
        angle.segment = static_cast<Index>(s);
        out_.add(angle);
      }
    }
  }

  const ValidationInput& input_;
  const Plc& plc_;
  AngleCollector& out_;
  Csr<Index> segments_at_;
  Csr<Corner> corners_at_;
  std::vector<std::vector<Index>> facet_vertices_;
};

}  // namespace

void measure_input_angles(const ValidationInput& input, const ValidateOptions& options, ValidationReport& report) {
  AngleCollector collector(options, report);
  AngleMeter meter(input, collector);
  meter.run();
  collector.finish();
}

}  // namespace qualmesh::detail
