// Which input angles the engine calls acute (InputComplex::elements_meet_acute, complex.h): under the paper's
// encroachment rule every angle below 90 degrees; under the relaxed rule an angle between two edges (two segments,
// or a segment and a facet's corner edge) only below kSteinerCornerAcuteDeg (30), while dihedral angles keep 90
// (RefineParams::corner_acute_deg, refine_params.h). Counted by hand on triangular prisms.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "refine/complex.h"

namespace qualmesh {
namespace {

using detail::InputComplex;
using Kind = InputComplex::ElementKind;

// A prism of height 1 over the triangle A = (0, 0), B = (1, 0), C (counterclockwise). Vertices: A 0, B 1, C 2, then
// A' 3, B' 4, C' 5 above them. Facets: 0 bottom, 1 top, 2 the side on AB, 3 on BC, 4 on CA.
Plc triangular_prism(double cx, double cy) {
  Plc plc;
  const double base[3][2] = {{0, 0}, {1, 0}, {cx, cy}};
  for (double z : {0.0, 1.0})
    for (const auto& p : base) plc.vertices.push_back({p[0], p[1], z});
  plc.facets.push_back(Facet{{{2, 1, 0}}});
  plc.facets.push_back(Facet{{{3, 4, 5}}});
  for (Index i = 0; i < 3; ++i) {
    const Index j = (i + 1) % 3;
    plc.facets.push_back(Facet{{{i, j, j + 3, i + 3}}});
  }
  return plc;
}

InputComplex::ElementRef segment(const InputComplex& c, Index a, Index b) {
  const Index s = c.find_segment(a, b);
  EXPECT_NE(s, kNoIndex) << a << "-" << b;
  return {Kind::Segment, s};
}

// C = (1, 1): 45 degrees at A between AB and AC, 90 at B, and the sides on AB and CA meet at 45 degrees along AA'.
TEST(ComplexAngles, RelaxedRuleKeepsDihedralsButNotWideCorners) {
  const Plc plc = triangular_prism(1, 1);
  const InputComplex paper = detail::build_input_complex(plc);
  const InputComplex relaxed = detail::build_input_complex(plc, false, detail::kSteinerCornerAcuteDeg);
  EXPECT_DOUBLE_EQ(paper.corner_acute_deg, detail::kPaperAcuteDeg);
  EXPECT_DOUBLE_EQ(relaxed.corner_acute_deg, 30.0);
  for (const InputComplex* c : {&paper, &relaxed}) {
    const bool is_paper = c == &paper;
    // The 45-degree corner at A between two segments: acute only under the paper's rule.
    EXPECT_EQ(c->elements_meet_acute(segment(*c, 0, 1), segment(*c, 0, 2)), is_paper);
    // The right angle at B: under neither.
    EXPECT_FALSE(c->elements_meet_acute(segment(*c, 0, 1), segment(*c, 1, 2)));
    // The 45-degree dihedral angle along AA' between the sides on AB and CA: under both.
    EXPECT_TRUE(c->elements_meet_acute({Kind::Facet, 2}, {Kind::Facet, 4}));
    // The sides on AB and BC meet at 90 degrees along BB'.
    EXPECT_FALSE(c->elements_meet_acute({Kind::Facet, 2}, {Kind::Facet, 3}));
    // Input vertices B and C: the sides through them meet at the 45-degree dihedral, so both rules call them acute.
    EXPECT_TRUE(c->elements_meet_acute({Kind::Vertex, 1}, {Kind::Vertex, 2}));
    // Concentric shells (acute_vertex) keep the paper's 90 degrees under both rules: A and C are apices, B is not.
    EXPECT_TRUE(c->acute_vertex[0]);
    EXPECT_FALSE(c->acute_vertex[1]);
    EXPECT_TRUE(c->acute_vertex[2]);
  }
}

// C = (cos 20, sin 20): a 20-degree corner at A is acute under both rules.
TEST(ComplexAngles, SmallCornersStayAcuteUnderBothRules) {
  const double a = 20 * M_PI / 180;
  const Plc plc = triangular_prism(std::cos(a), std::sin(a));
  const InputComplex paper = detail::build_input_complex(plc);
  const InputComplex relaxed = detail::build_input_complex(plc, false, detail::kSteinerCornerAcuteDeg);
  for (const InputComplex* c : {&paper, &relaxed})
    EXPECT_TRUE(c->elements_meet_acute(segment(*c, 0, 1), segment(*c, 0, 2)));
  // The corner at B is 80 degrees: acute for the paper only.
  EXPECT_TRUE(paper.elements_meet_acute(segment(paper, 0, 1), segment(paper, 1, 2)));
  EXPECT_FALSE(relaxed.elements_meet_acute(segment(relaxed, 0, 1), segment(relaxed, 1, 2)));
}

// The answers are cached by element pair, and a facet pair's key once shared its bits with the next facet's:
// with the sides first (AB 0, BC 1, CA 2, bottom 3, top 4), the sides on AB and CA meet at 45 degrees, the side on
// AB and the bottom at 90, and asking for (0, 2) first made (0, 3) "acute" too.
TEST(ComplexAngles, CachedFacetPairsDoNotShareAnswers) {
  Plc plc = triangular_prism(1, 1);
  std::rotate(plc.facets.begin(), plc.facets.begin() + 2, plc.facets.end());
  for (double corner : {detail::kPaperAcuteDeg, detail::kSteinerCornerAcuteDeg}) {
    const InputComplex c = detail::build_input_complex(plc, false, corner);
    EXPECT_TRUE(c.elements_meet_acute({Kind::Facet, 0}, {Kind::Facet, 2}));
    EXPECT_FALSE(c.elements_meet_acute({Kind::Facet, 0}, {Kind::Facet, 3}));
    EXPECT_FALSE(c.elements_meet_acute({Kind::Facet, 3}, {Kind::Facet, 0}));
    EXPECT_TRUE(c.elements_meet_acute({Kind::Facet, 2}, {Kind::Facet, 0}));
  }
}

// The fast rejection of pairs with an input vertex (InputComplex::is_apex): two elements through a vertex meet at
// an acute angle there only at A and C, whose vertical edges carry the 45-degree dihedral angles; under the relaxed
// rule B's right angles make it no apex, yet B meets C at an acute angle (their sides meet along CC'), because
// every vertex of an element through B counts (reaches_apex). A cube has no apex: no two of its vertices meet acutely.
TEST(ComplexAngles, ApicesDecideThePairsWithAVertex) {
  const Plc prism = triangular_prism(1, 1);  // the complex keeps a pointer to its Plc
  const InputComplex c = detail::build_input_complex(prism, false, detail::kSteinerCornerAcuteDeg);
  EXPECT_TRUE(c.is_apex(0));
  EXPECT_FALSE(c.is_apex(1));
  EXPECT_TRUE(c.is_apex(2));
  EXPECT_TRUE(c.reaches_apex(1));
  EXPECT_TRUE(c.elements_meet_acute({Kind::Vertex, 1}, {Kind::Vertex, 2}));
  Plc cube;
  for (int i = 0; i < 8; ++i) cube.vertices.push_back({double(i & 1), double((i >> 1) & 1), double((i >> 2) & 1)});
  for (const std::array<Index, 4>& q : std::vector<std::array<Index, 4>>{
           {0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}})
    cube.facets.push_back(Facet{{{q[0], q[1], q[2], q[3]}}});
  const InputComplex box = detail::build_input_complex(cube);
  for (Index u = 0; u < 8; ++u) {
    EXPECT_FALSE(box.is_apex(u)) << u;
    for (Index w = 0; w < 8; ++w) EXPECT_FALSE(box.elements_meet_acute({Kind::Vertex, u}, {Kind::Vertex, w}));
  }
}

}  // namespace
}  // namespace qualmesh
