// Small queries on the Plc value type (bounding box, the full segment set).
#include "qualmesh/plc.h"

#include <algorithm>
#include <utility>

namespace qualmesh {

BoundingBox bounding_box(const Plc& plc) {
  BoundingBox box;
  for (const Point3& p : plc.vertices) box.add(p);
  return box;
}

std::vector<Segment> collect_segments(const Plc& plc) {
  std::vector<Segment> all;
  auto add = [&all](Index a, Index b, int marker) {
    if (a == b) return;  // degenerate; reported by validate_plc
    if (a > b) std::swap(a, b);
    all.push_back({a, b, marker});
  };
  for (const Segment& s : plc.segments) add(s.a, s.b, s.marker);
  for (const Facet& f : plc.facets) {
    for (const auto& loop : f.polygons) {
      if (loop.size() == 2) {
        add(loop[0], loop[1], 0);
      } else if (loop.size() >= 3) {
        for (std::size_t i = 0; i < loop.size(); ++i) add(loop[i], loop[(i + 1) % loop.size()], 0);
      }
    }
  }
  // Sort by (a, b), explicit markers (non-zero) first so that unique() keeps them.
  std::sort(all.begin(), all.end(), [](const Segment& x, const Segment& y) {
    if (x.a != y.a) return x.a < y.a;
    if (x.b != y.b) return x.b < y.b;
    return (x.marker != 0) > (y.marker != 0);
  });
  all.erase(std::unique(all.begin(), all.end(),
                        [](const Segment& x, const Segment& y) { return x.a == y.a && x.b == y.b; }),
            all.end());
  return all;
}

std::size_t count_polygon_vertices(const Facet& facet) {
  std::size_t n = 0;
  for (const auto& loop : facet.polygons) n += loop.size();
  return n;
}

}  // namespace qualmesh
