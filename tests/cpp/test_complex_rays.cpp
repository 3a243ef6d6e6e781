// The input complex's ray queries (issue 18 item 6, core/src/refine/complex_rays.cpp): answered from a per-facet
// index in O(log n) instead of scanning the facet's n edges, with the same answers as the scan. A prism with
// 20000-gon caps builds its complex in well under a second (the scan took minutes: 39 s at 8000), and on every
// model of ../shared/data/plc and on hand-made non-convex facets with holes the index agrees with the scan on every
// query building the complex makes, and on the acute-vertex flags.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>

#include "qualmesh/plc_io.h"
#include "refine/complex.h"
#include "test_support.h"

namespace qualmesh {
namespace {

// A prism over the polygon `base` (counterclockwise in z = 0) of height h: caps facets 0 (bottom) and 1 (top).
Plc prism(const std::vector<std::array<double, 2>>& base, double h, const std::vector<std::vector<std::array<double, 2>>>& holes = {}) {
  Plc plc;
  std::vector<std::vector<std::array<double, 2>>> loops{base};
  loops.insert(loops.end(), holes.begin(), holes.end());
  Facet bottom, top;
  std::vector<Facet> sides;
  for (const auto& loop : loops) {
    const Index first = static_cast<Index>(plc.vertices.size());
    const Index n = static_cast<Index>(loop.size());
    for (const auto& p : loop) plc.vertices.push_back({p[0], p[1], 0});
    for (const auto& p : loop) plc.vertices.push_back({p[0], p[1], h});
    std::vector<Index> b, t;
    for (Index i = 0; i < n; ++i) b.push_back(first + n - 1 - i), t.push_back(first + n + i);
    bottom.polygons.push_back(b);
    top.polygons.push_back(t);
    for (Index i = 0; i < n; ++i) {
      Facet side;
      const Index j = (i + 1) % n;
      side.polygons.push_back({first + i, first + j, first + n + j, first + n + i});
      sides.push_back(side);
    }
  }
  plc.facets.push_back(bottom);
  plc.facets.push_back(top);
  plc.facets.insert(plc.facets.end(), sides.begin(), sides.end());
  return plc;
}

std::vector<std::array<double, 2>> regular_polygon(int n, double r = 1, double cx = 0, double cy = 0, bool reverse = false) {
  std::vector<std::array<double, 2>> p;
  for (int i = 0; i < n; ++i) {
    const double a = 2 * M_PI * (reverse ? n - i : i) / n;
    p.push_back({cx + r * std::cos(a), cy + r * std::sin(a)});
  }
  return p;
}

// Every query that building the complex makes, answered by the index and by the scan, and the acute flags.
void expect_index_matches_scan(const Plc& plc, const std::string& what) {
  const detail::InputComplex fast = detail::build_input_complex(plc);
  const detail::InputComplex scan = detail::build_input_complex(plc, true);
  EXPECT_EQ(fast.acute_vertex, scan.acute_vertex) << what;
  std::size_t edges = 0, corners = 0, mismatches = 0, indexed = 0;
  for (Index f = 0; f < plc.facets.size(); ++f) {
    for (Index v : fast.facet_vertices[f]) {
      for (Index s : fast.vertex_segments[v]) {
        if (fast.facet_has_segment(f, s)) {
          ++edges;
          const auto a = fast.inward_directions(f, s), b = scan.inward_directions(f, s);
          indexed += fast.indexed_edge_side(f, s) != 0;
          if (a != b) ++mismatches;
        } else {
          ++corners;
          const Segment& seg = fast.segments[s];
          const Point3 d = {plc.vertices[seg.a == v ? seg.b : seg.a][0] - plc.vertices[v][0],
                            plc.vertices[seg.a == v ? seg.b : seg.a][1] - plc.vertices[v][1],
                            plc.vertices[seg.a == v ? seg.b : seg.a][2] - plc.vertices[v][2]};
          indexed += fast.indexed_corner_covers(f, v, d) != 0;
          if (fast.segment_facet_angle_deg(v, s, f) != scan.segment_facet_angle_deg(v, s, f)) ++mismatches;
        }
      }
    }
  }
  EXPECT_EQ(mismatches, 0u) << what << ": " << edges << " edge and " << corners << " corner queries";
  // The index answers most of them itself. The rest go to the scan: corners used twice, and rays that graze an edge
  // (a prism's side quad asked about the next cap edge, whose projection runs along the quad's own bottom edge).
  EXPECT_GT(indexed, 0.75 * double(edges + corners)) << what << ": " << indexed << " of " << edges + corners;
}

TEST(ComplexRays, PrismWith20000GonCapsBuildsQuickly) {
  const Plc plc = prism(regular_polygon(20000), 1);
  const auto start = std::chrono::steady_clock::now();
  const detail::InputComplex c = detail::build_input_complex(plc);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("build_input_complex, prism with 20000-gon caps (40000 vertices, 20002 facets): %.3f s\n", seconds);
  EXPECT_LT(seconds, 5.0);  // about 0.1 s here; the scan needed minutes
  EXPECT_EQ(c.segments.size(), 60000u);
  // Right dihedral angles everywhere, the caps' corners are 179.98 degrees: nothing acute.
  for (std::uint8_t a : c.acute_vertex) ASSERT_EQ(a, 0);
}

TEST(ComplexRays, IndexMatchesScanOnHandMadeFacets) {
  expect_index_matches_scan(prism(regular_polygon(300), 1), "300-gon prism");
  // Non-convex: a star (reflex corners), and a comb.
  std::vector<std::array<double, 2>> star;
  for (int i = 0; i < 40; ++i) {
    const double a = 2 * M_PI * i / 40, r = i % 2 ? 0.4 : 1;
    star.push_back({r * std::cos(a), r * std::sin(a)});
  }
  expect_index_matches_scan(prism(star, 0.3), "star prism");
  std::vector<std::array<double, 2>> comb{{0, 0}, {10, 0}, {10, 1}};
  for (int i = 9; i >= 0; --i) comb.push_back({i + 0.6, 1}), comb.push_back({i + 0.6, 3}), comb.push_back({i + 0.4, 3}), comb.push_back({i + 0.4, 1});
  comb.push_back({0, 1});
  expect_index_matches_scan(prism(comb, 0.5), "comb prism");
  // Caps with holes (the holes' loops run clockwise), and a slanted prism (sides not axis-aligned).
  expect_index_matches_scan(prism(regular_polygon(64, 3), 1, {regular_polygon(16, 0.5, 1, 0, true),
                                                               regular_polygon(5, 0.5, -1, 0.5, true)}),
                            "caps with holes");
  Plc slanted = prism(star, 1);
  for (Point3& p : slanted.vertices) p = {p[0] + 0.3 * p[2], p[1] * 0.8 + 0.6 * p[2], p[2] * 0.8 - 0.6 * p[1]};
  expect_index_matches_scan(slanted, "slanted star prism");
  // An acute prism (a thin wedge): its acute flags must come out the same.
  expect_index_matches_scan(prism({{0, 0}, {1, 0}, {0.999, 0.05}}, 1), "thin wedge");
}

TEST(ComplexRays, IndexMatchesScanOnTheSharedModels) {
  std::size_t models = 0;
  for (const char* name : {"anchor.off", "cheese.off", "couplingdown.off", "cow.off", "cubes.off", "elephant.off",
                           "example.poly", "fandisk.off", "joint.off", "lever.stl", "pinion.off", "slit-1.smesh",
                           "spike-1-10.smesh", "wedge-1.smesh", "turbine.off", "t13_data.stl"}) {
    const std::string path = test::shared_path(std::string("data/plc/") + name);
    if (!std::filesystem::exists(path)) continue;
    ++models;
    expect_index_matches_scan(read_plc(path), name);
  }
  for (const char* name : {"box.poly", "box_hole.off"}) {
    ++models;
    expect_index_matches_scan(read_plc(test::source_path(std::string("tests/data/small/") + name)), name);
  }
  if (models == 2) GTEST_SKIP() << "../shared/data/plc missing";
}

}  // namespace
}  // namespace qualmesh
