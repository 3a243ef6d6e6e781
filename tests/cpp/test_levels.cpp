// Tests of the refinement levels (core/src/refine/levels.h; Cheng & Dey, Section 3.7, Rules 1-3) on small
// constructed cases, through the engine's private interface:
//   - Rule 1: a subsegment with an input vertex in its diametral ball is encroached under the paper's rule and not
//     under the Steiner policy; its split point is accepted (Conflict::None), a point on a vertex dropped;
//   - Rule 2: the circumcentre of an obtuse subfacet encroaches its long edge (Conflict::SplitSubsegment, the
//     subsegment queued, forced); a centre on a vertex is dropped; a centre away from the facet's boundary accepted;
//   - Rule 3: a point near a cube's edge asks for a subsegment split, the cube's centre for subfacet splits, a
//     point next to an interior vertex is accepted, a point on an interior vertex dropped;
//   - the after-insertion hooks queue what a new vertex encroaches, and every insertion reaches every level (the
//     boundary stage recovers every subsegment and subfacet);
//   - RefineParams and EncroachmentPolicy derive what the options say;
//   - the same input gives the same mesh twice in one process, under either encroachment rule;
//   - re-refining a refined mesh adds nothing (CGAL Mesh_3's test_meshing_utilities property);
//   - under the Steiner policy, region labels that cross no subfacet are flooded again (reflood_regions);
//   - boundary points projected onto a curved surface (MeshOptions::project_to_boundary) land on it;
//   - the split floor keeps small encroached elements, and splits below it past a budget stop a projected run; it is
//     the user's or the rounding floor, whichever is larger;
//   - a boundary point whose place in a facet's 2D triangulation is already a vertex is refused, and the stop at the
//     limit of double precision ends refinement.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <vector>

#include "qualmesh/mesher.h"
#include "qualmesh/plc_io.h"
#include "qualmesh/quality.h"
#include "refine/refine_state.h"
#include "test_support.h"

namespace {

using qualmesh::Index;
using qualmesh::kNoIndex;
using qualmesh::MeshOptions;
using qualmesh::Plc;
using qualmesh::Point3;
namespace d = qualmesh::detail;

Plc tetrahedron(const Point3& a, const Point3& b, const Point3& c, const Point3& e) {
  Plc plc;
  plc.vertices = {a, b, c, e};
  for (const std::vector<Index>& t : std::vector<std::vector<Index>>{{0, 1, 2}, {0, 1, 3}, {0, 2, 3}, {1, 2, 3}}) {
    qualmesh::Facet f;
    f.polygons.push_back(t);
    plc.facets.push_back(f);
  }
  return plc;
}

Plc box(const Point3& lo, const Point3& hi) {
  Plc plc;
  for (int k = 0; k < 8; ++k)
    plc.vertices.push_back({k & 1 ? hi[0] : lo[0], k & 2 ? hi[1] : lo[1], k & 4 ? hi[2] : lo[2]});
  const std::vector<std::vector<Index>> quads{{0, 1, 3, 2}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                              {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    qualmesh::Facet f;
    f.polygons.push_back(q);
    plc.facets.push_back(f);
  }
  return plc;
}

// The engine's state after step 1 (the Delaunay triangulation of the input vertices and the facets' 2D
// triangulations), as mesh_plc() builds it; refine() runs the boundary, regions and refinement stages.
struct Engine {
  Plc plc;
  std::unique_ptr<d::MeshState> state = std::make_unique<d::MeshState>();
  d::MeshState& s = *state;

  explicit Engine(Plc input, const MeshOptions& options = {}) : plc(std::move(input)) {
    s.plc = &plc;
    s.set_options(options);
    s.complex = d::build_input_complex(plc, false, s.params.corner_acute_deg);
    d::insert_input_vertices(s);
    d::build_facet_meshes(s);
  }
  void boundary_and_regions() {
    d::enqueue_initial_boundary(s);
    d::run_refinement(s, false);
    d::compute_regions(s);
  }
  void refine() {
    boundary_and_regions();
    d::enqueue_all_tets(s);
    d::run_refinement(s, true);
    std::vector<d::Ch3> assigned;
    if (!s.region_pending.empty()) d::flood_pending_regions(s, assigned);
  }
  Index segment(Index a, Index b) const { return s.complex.find_segment(a, b); }
  d::Ch3 cell_containing(const Point3& p) const { return s.tr.locate(d::KWeightedPoint3(d::to_kpoint(p), 0)); }
  // An interior volume vertex at least `clearance` from the box [lo, hi]'s faces.
  Index interior_vertex(const Point3& lo, const Point3& hi, double clearance) const {
    for (Index v = 0; v < s.vertices.size(); ++v) {
      if (s.vertices[v].kind != d::VertexKind::Volume) continue;
      const Point3& p = s.point(v);
      bool inside = true;
      for (int k = 0; k < 3; ++k) inside = inside && p[k] > lo[k] + clearance && p[k] < hi[k] - clearance;
      if (inside) return v;
    }
    return kNoIndex;
  }
};

// Tetrahedron whose face ABC is obtuse at C: C lies inside the diametral ball of AB (input edge, segment 0-1).
Plc obtuse_tetrahedron() { return tetrahedron({0, 0, 0}, {2, 0, 0}, {1, 0.2, 0}, {1, 0.1, 1}); }

MeshOptions papers_rule() {
  MeshOptions options;
  options.encroaching = MeshOptions::Encroaching::All;
  return options;
}

TEST(Levels, Rule1EncroachedUnderThePapersRuleOnly) {
  Engine paper(obtuse_tetrahedron(), papers_rule());
  const Index ab = paper.segment(0, 1);
  ASSERT_NE(ab, kNoIndex);
  Index enc = kNoIndex;
  EXPECT_TRUE(paper.s.rule1.encroached(paper.s, ab, 0, 1, &enc));
  EXPECT_EQ(enc, 2u) << "C is the vertex in AB's diametral ball";
  // A present edge with no other vertex in its diametral ball: CD.
  const Index cd = paper.segment(2, 3);
  ASSERT_NE(cd, kNoIndex);
  EXPECT_FALSE(paper.s.rule1.encroached(paper.s, cd, 2, 3, &enc));

  MeshOptions steiner;
  steiner.encroaching = MeshOptions::Encroaching::Steiner;
  Engine relaxed(obtuse_tetrahedron(), steiner);
  EXPECT_FALSE(relaxed.s.rule1.encroached(relaxed.s, ab, 0, 1, &enc))
      << "an input vertex does not encroach a present input edge under the Steiner policy";
}

TEST(Levels, Rule1SplitPointAcceptedAndPointOnVertexDropped) {
  Engine e(obtuse_tetrahedron());
  d::MeshState& s = e.s;
  const Index ab = e.segment(0, 1);
  double t = -1;
  const Point3 p = s.rule1.refinement_point(s, ab, 0, 1, &t);
  EXPECT_DOUBLE_EQ(t, 0.5) << "an input edge between two acute apices is halved first";
  EXPECT_DOUBLE_EQ(p[0], 1.0);
  d::ConflictZone cz;
  EXPECT_EQ(s.rule1.conflict(s, p, d::hint_of(s, 0), cz), d::Conflict::None);
  EXPECT_FALSE(cz.cells.empty());
  EXPECT_EQ(s.rule1.conflict(s, s.point(3), d::hint_of(s, 0), cz), d::Conflict::Drop);
}

TEST(Levels, Rule2CentreOfObtuseSubfacetSplitsItsLongEdge) {
  // ABC obtuse at C (96 degrees): its circumcentre (1, -0.106, 0) lies in AB's diametral ball.
  for (const auto rule : {MeshOptions::Encroaching::All, MeshOptions::Encroaching::Steiner}) {
    MeshOptions options;
    options.encroaching = rule;
    Engine e(tetrahedron({0, 0, 0}, {2, 0, 0}, {1, 0.9, 0}, {1, 0.3, 1}), options);
    d::MeshState& s = e.s;
    const std::array<Index, 3> abc{0, 1, 2};
    const Index facet = d::subfacet_of(s, 0, 1, 2);
    ASSERT_NE(facet, kNoIndex);
    const d::KPoint3 centre = s.rule2.refinement_point(s, abc);
    EXPECT_NEAR(centre.y(), -0.10556, 1e-4);
    d::ConflictZone cz;
    d::Candidates cand;
    s.rule1.queue.clear();
    EXPECT_EQ(s.rule2.conflict(s, facet, abc, centre, cz, cand), d::Conflict::SplitSubsegment);
    ASSERT_EQ(s.rule1.queue.size(), 1u);
    EXPECT_EQ(s.rule1.queue.front().segment, e.segment(0, 1));
    EXPECT_TRUE(s.rule1.queue.front().forced);
  }
}

TEST(Levels, Rule2CentreOnVertexDroppedAndInnerCentreAccepted) {
  MeshOptions options;
  options.max_edge_length = 0.5;
  options.pump = false;
  const Point3 lo{0, 0, 0}, hi{3, 3, 1};
  Engine e(box(lo, hi), options);
  e.refine();
  d::MeshState& s = e.s;
  // A subfacet of the bottom face (facet 0, z = 0) well inside it: no subsegment near its centre.
  const Index bottom = 0;
  std::vector<std::array<Index, 3>> faces;
  d::collect_subfacets(s, bottom, faces);
  ASSERT_FALSE(faces.empty());
  for (Index v : faces.front()) ASSERT_EQ(s.point(v)[2], 0.0);
  std::optional<std::array<Index, 3>> inner;
  for (const auto& f : faces) {
    bool far = true;
    for (Index v : f) {
      const Point3& p = s.point(v);
      far = far && p[0] > 1 && p[0] < 2 && p[1] > 1 && p[1] < 2;
    }
    if (far) inner = f;
  }
  ASSERT_TRUE(inner) << "a refined 3x3 face has subfacets in its middle square";
  const d::KPoint3 centre = s.rule2.refinement_point(s, *inner);
  d::ConflictZone cz;
  d::Candidates cand;
  EXPECT_EQ(s.rule2.conflict(s, bottom, *inner, centre, cz, cand), d::Conflict::None);
  EXPECT_FALSE(cz.cells.empty());
  EXPECT_EQ(s.rule2.conflict(s, bottom, *inner, s.kpoint((*inner)[0]), cz, cand), d::Conflict::Drop);
}

TEST(Levels, Rule3CubeCentreSplitsSubfacetsAndEdgePointSplitsSubsegment) {
  Engine e(box({0, 0, 0}, {1, 1, 1}));
  e.boundary_and_regions();
  d::MeshState& s = e.s;
  ASSERT_EQ(s.vertices.size(), 8u) << "the cube's boundary conforms with its corners alone";
  const d::TetEntry entry{};
  {
    const Point3 z{0.5, 0.04, 0.04};  // 0.06 from the midpoint of the edge 0-1, whose diametral ball has radius 0.5
    const d::Ch3 c = e.cell_containing(z);
    ASSERT_GE(c->info().region, 0);
    d::ConflictZone cz;
    d::Candidates cand;
    EXPECT_EQ(s.rule3.conflict(s, entry, c, d::to_kpoint(z), cz, cand), d::Conflict::SplitSubsegment);
    EXPECT_FALSE(s.rule1.empty());
  }
  s.rule1.queue.clear();
  s.rule2.queue.clear();
  {
    // The cube's centre: 0.5 from each face's centre, inside every subfacet's diametral ball (radius 0.707), and
    // 0.707 from each edge's midpoint, outside every subsegment's (radius 0.5).
    const Point3 z{0.5, 0.5, 0.5};
    const d::Ch3 c = e.cell_containing(z);
    d::ConflictZone cz;
    d::Candidates cand;
    EXPECT_EQ(s.rule3.conflict(s, entry, c, d::to_kpoint(z), cz, cand), d::Conflict::SplitSubfacet);
    EXPECT_TRUE(s.rule1.empty());
    EXPECT_FALSE(s.rule2.empty());
    for (const d::SubfacetEntry& f : s.rule2.queue) {
      EXPECT_TRUE(f.has_point) << "Rule 2 gets the point, for Lemma 3.5's projection";
      EXPECT_TRUE(f.forced);
    }
  }
}

TEST(Levels, Rule3AcceptsAPointInsideAndDropsOneOnAVertex) {
  MeshOptions options;
  options.max_edge_length = 0.3;
  options.pump = false;
  const Point3 lo{0, 0, 0}, hi{3, 3, 3};
  Engine e(box(lo, hi), options);
  e.refine();
  d::MeshState& s = e.s;
  const Index v = e.interior_vertex(lo, hi, 1.0);
  ASSERT_NE(v, kNoIndex);
  const Point3 p = s.point(v);
  const d::TetEntry entry{};
  {
    const Point3 z{p[0] + 0.01, p[1] + 0.005, p[2] - 0.007};
    const d::Ch3 c = e.cell_containing(z);
    d::ConflictZone cz;
    d::Candidates cand;
    EXPECT_EQ(s.rule3.conflict(s, entry, c, d::to_kpoint(z), cz, cand), d::Conflict::None);
    EXPECT_TRUE(cand.subsegments.empty());
    EXPECT_TRUE(cand.subfacets.empty());
  }
  {
    const d::Ch3 c = s.vertices[v].handle->cell();
    d::ConflictZone cz;
    d::Candidates cand;
    s.rule2.queue.clear();
    EXPECT_EQ(s.rule3.conflict(s, entry, c, d::to_kpoint(p), cz, cand), d::Conflict::Drop)
        << "a point on an interior vertex, in a cell with no subfacet: nothing to split";
    EXPECT_TRUE(s.rule2.empty());
  }
}

TEST(Levels, AfterInsertionHooksQueueWhatTheNewVertexEncroaches) {
  Engine e(box({0, 0, 0}, {1, 1, 1}));
  e.boundary_and_regions();
  d::MeshState& s = e.s;
  ASSERT_TRUE(s.rule1.empty());
  ASSERT_TRUE(s.rule2.empty());
  // A volume vertex 0.1 from the midpoint of edge 0-1 (in its diametral ball) and 0.1 above the bottom face
  // (in the diametral balls of the bottom's subfacets that hold its projection).
  const Point3 p{0.5, 0.1, 0.1};
  d::ConflictZone cz;
  ASSERT_TRUE(d::find_conflict_zone(s, d::to_kpoint(p), e.cell_containing(p), cz));
  const int region = e.cell_containing(p)->info().region;
  d::insert_volume_vertex(s, p, cz.cells, cz.boundary, region);
  bool edge_queued = false;
  for (const d::SubsegmentEntry& q : s.rule1.queue) edge_queued = edge_queued || q.segment == e.segment(0, 1);
  EXPECT_TRUE(edge_queued);
  EXPECT_FALSE(s.rule2.empty());
}

// Every insertion reaches every level's hook (scheduler.cpp notify_insertion): a Rule 1 split must queue the new
// subfacets of its facets for Rule 2, or the boundary stage ends with elements missing (a regression: the levels
// once called only their own hook).
TEST(Levels, BoundaryStageRecoversEverySubsegmentAndSubfacet) {
  for (const double cy : {0.2, 0.9, 0.05}) {
    // The paper's rule: the obtuse corner's vertex encroaches the long edge, so Rule 1 splits it.
    Engine e(tetrahedron({0, 0, 0}, {2, 0, 0}, {1, cy, 0}, {1, 0.1, 0.7}), papers_rule());
    e.boundary_and_regions();
    d::MeshState& s = e.s;
    EXPECT_GT(s.stats.num_rule1_insertions, 0u) << cy;
    EXPECT_TRUE(d::boundary_present(s)) << cy;
    EXPECT_TRUE(d::region_boundaries_are_subfacets(s)) << cy;
    std::size_t in_domain = 0;
    for (auto c = s.tr.finite_cells_begin(); c != s.tr.finite_cells_end(); ++c) in_domain += c->info().region >= 0;
    EXPECT_GT(in_domain, 0u) << cy;
  }
}

// The same on a real tessellated model (joint.off: the regression left its boundary with subfacets missing, and
// the flood found no region inside).
TEST(Levels, BoundaryStageRecoversEverythingOnJoint) {
  const std::string path = qualmesh::test::shared_path("data/plc/joint.off");
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " missing";
  Engine e(qualmesh::read_plc(path));
  e.boundary_and_regions();
  EXPECT_GT(e.s.stats.num_rule2_insertions, 0u);
  EXPECT_TRUE(d::boundary_present(e.s));
  EXPECT_TRUE(d::region_boundaries_are_subfacets(e.s));
  std::size_t in_domain = 0;
  for (auto c = e.s.tr.finite_cells_begin(); c != e.s.tr.finite_cells_end(); ++c) in_domain += c->info().region >= 0;
  EXPECT_GT(in_domain, 0u);
}

TEST(Levels, ParamsDerivedOnceFromTheOptions) {
  MeshOptions options;
  options.radius_edge_bound = 1.5;
  options.max_edge_length = 3;
  options.max_volume = -1;
  options.sliver_angle_deg = 12;
  options.omega = 0.4;
  options.delta = 0.3;
  const d::RefineParams p = d::RefineParams::from(options);
  EXPECT_DOUBLE_EQ(p.sq_radius_edge_bound(), 2.25);
  EXPECT_DOUBLE_EQ(p.sq_max_edge, 9);
  EXPECT_EQ(p.max_volume, 0) << "a non-positive volume bound is none";
  EXPECT_TRUE(p.sq_radius_edge_above_bound(2.26, 1));
  EXPECT_FALSE(p.sq_radius_edge_above_bound(2.25, 1));
  EXPECT_TRUE(p.is_sliver(11.9, 1.5));
  EXPECT_FALSE(p.is_sliver(11.9, 1.51)) << "above rho0: a skinny tetrahedron (Rule 3), not a sliver";
  EXPECT_FALSE(p.is_sliver(12, 1.0));
  EXPECT_TRUE(p.below_sliver_angle(11.9));
  EXPECT_DOUBLE_EQ(p.sliver_deficit_deg(10), 2);
  EXPECT_DOUBLE_EQ(p.sliver_deficit_deg(20), 0);
  bool by_omega = false;
  EXPECT_DOUBLE_EQ(p.weight_cap(1.0, 4.0, &by_omega), 0.4 * 0.4);  // omega0^2 f^2 below delta^2 N^2 = 0.36
  EXPECT_TRUE(by_omega);
  EXPECT_DOUBLE_EQ(p.weight_cap(std::numeric_limits<double>::infinity(), 1.0, &by_omega), 0.3 * 0.3);
  EXPECT_FALSE(by_omega);
  // The relaxed rule is the default (issue 16), with corners below 30 degrees acute on a surface or PLC; the
  // paper's rule keeps 90, and so does a CAD input with boundary projection.
  EXPECT_FALSE(p.encroachment.paper());
  EXPECT_TRUE(p.encroachment.walks_to_centres());
  EXPECT_DOUBLE_EQ(p.corner_acute_deg, d::kSteinerCornerAcuteDeg);
  options.project_to_boundary = [](int, int, Point3&) { return false; };
  EXPECT_DOUBLE_EQ(d::RefineParams::from(options).corner_acute_deg, d::kPaperAcuteDeg);
  options.project_to_boundary = nullptr;
  options.encroaching = MeshOptions::Encroaching::All;
  EXPECT_TRUE(d::RefineParams::from(options).encroachment.paper());
  EXPECT_DOUBLE_EQ(d::RefineParams::from(options).corner_acute_deg, d::kPaperAcuteDeg);
}

// The split floor of Rules 1-2 (refine_params.h): the user's MeshOptions::min_split_length (relaxed rule only),
// raised to the rounding floor kRoundingSplitFloor x the input's diagonal under either rule. The user's value stays
// apart, since the relaxed rule's conflict-zone budget applies only where the user gave no floor.
TEST(Levels, SplitFloorIsTheUsersOrTheRoundingFloor) {
  MeshOptions options;
  options.encroaching = MeshOptions::Encroaching::Steiner;
  d::RefineParams p = d::RefineParams::from(options);
  EXPECT_EQ(p.sq_split_floor, 0);
  p.set_rounding_floor(1000);
  EXPECT_DOUBLE_EQ(p.sq_split_floor, 1e-12);  // (1e-9 x 1000)^2
  EXPECT_EQ(p.sq_min_split, 0);
  EXPECT_TRUE(p.subsegment_below_floor(3.9e-12));  // a subsegment shorter than twice the floor
  EXPECT_FALSE(p.subsegment_below_floor(4.1e-12));
  EXPECT_TRUE(p.subfacet_below_floor(0.9e-12));
  EXPECT_FALSE(p.subfacet_below_floor(1.1e-12));
  options.min_split_length = 0.5;  // a larger floor of the user's stays
  p = d::RefineParams::from(options);
  p.set_rounding_floor(1000);
  EXPECT_DOUBLE_EQ(p.sq_split_floor, 0.25);
  EXPECT_DOUBLE_EQ(p.sq_min_split, 0.25);
  options.encroaching = MeshOptions::Encroaching::All;  // the paper's rule ignores the user's floor, not rounding's
  p = d::RefineParams::from(options);
  EXPECT_EQ(p.sq_split_floor, 0);
  p.set_rounding_floor(1000);
  EXPECT_DOUBLE_EQ(p.sq_split_floor, 1e-12);
}

// Determinism (house style, principle 7): the same input meshed twice in one process, with another input meshed in
// between (a different heap), gives the same vertices, weights and tetrahedra under either encroachment rule.
TEST(Levels, SameMeshTwiceInOneProcessUnderEitherRule) {
  for (const auto rule : {MeshOptions::Encroaching::All, MeshOptions::Encroaching::Steiner}) {
    MeshOptions options;
    options.max_edge_length = 0.3;
    options.encroaching = rule;
    const Plc input = box({0, 0, 0}, {1, 2, 1});
    const auto first = qualmesh::mesh_plc(input, options);
    const auto other = qualmesh::mesh_plc(obtuse_tetrahedron(), options);
    const auto second = qualmesh::mesh_plc(input, options);
    ASSERT_FALSE(first.mesh.tets.empty());
    EXPECT_EQ(first.mesh.points, second.mesh.points);
    EXPECT_EQ(first.mesh.weights, second.mesh.weights);
    EXPECT_EQ(first.mesh.tets, second.mesh.tets);
    EXPECT_FALSE(other.mesh.tets.empty());
  }
}

// The options of the refined-box tests below: edges up to 0.35, no pumping, the given encroachment rule.
MeshOptions box_refinement(MeshOptions::Encroaching rule) {
  MeshOptions options;
  options.max_edge_length = 0.35;
  options.pump = false;
  options.encroaching = rule;
  return options;
}

TEST(Levels, ReRefiningARefinedMeshAddsNothing) {
  for (const auto rule : {MeshOptions::Encroaching::All, MeshOptions::Encroaching::Steiner}) {
    Engine e(box({0, 0, 0}, {1, 2, 1}), box_refinement(rule));
    e.refine();
    d::MeshState& s = e.s;
    const std::size_t num_vertices = s.tr.number_of_vertices();
    ASSERT_GT(num_vertices, 8u);
    d::enqueue_initial_boundary(s);
    d::run_refinement(s, false);
    EXPECT_TRUE(s.rule1.empty() && s.rule2.empty());
    d::enqueue_all_tets(s);
    d::run_refinement(s, true);
    EXPECT_EQ(s.tr.number_of_vertices(), num_vertices);
    EXPECT_EQ(s.vertices.size(), num_vertices);
    EXPECT_TRUE(d::boundary_present(s));
  }
}

// reflood_regions (regions.cpp): under the Steiner policy, a refined mesh whose region labels went wrong (one
// interior cell labelled outside, as a label handed on through a subfacet missing at that moment would leave it) is
// flooded again: every cell inside the box is in the domain again and every region boundary is a subfacet. Under
// the paper's rule it is left alone (steiner_holds has nothing to do with it there). No CAD model of the bench needs
// it any more (session 30), so this constructed case is its test.
TEST(Levels, RegionsFloodedAgainWhenALabelCrossesNoSubfacet) {
  for (const auto rule : {MeshOptions::Encroaching::All, MeshOptions::Encroaching::Steiner}) {
    Engine e(box({0, 0, 0}, {1, 2, 1}), box_refinement(rule));
    e.refine();
    d::MeshState& s = e.s;
    ASSERT_TRUE(d::region_boundaries_are_subfacets(s));
    // The first finite cell with no face on the boundary: labelling it outside puts a region boundary on faces
    // that are no subfacets.
    d::Ch3 wrong;
    for (auto c = s.tr.finite_cells_begin(); c != s.tr.finite_cells_end() && wrong == d::Ch3(); ++c) {
      bool inner = c->info().region >= 0;
      for (int i = 0; i < 4; ++i) inner = inner && d::face_subfacet(s, c, i) == kNoIndex;
      if (inner) wrong = c;
    }
    ASSERT_NE(wrong, d::Ch3());
    wrong->info().region = d::kOutsideRegion;
    ASSERT_FALSE(d::region_boundaries_are_subfacets(s));
    const std::size_t num_vertices = s.tr.number_of_vertices();
    d::reflood_regions(s);
    if (rule == MeshOptions::Encroaching::All) {
      EXPECT_EQ(s.stats.num_region_refloods, 0u);
      EXPECT_FALSE(d::region_boundaries_are_subfacets(s));
      continue;
    }
    EXPECT_EQ(s.stats.num_region_refloods, 1u);
    EXPECT_TRUE(d::region_boundaries_are_subfacets(s));
    EXPECT_EQ(s.tr.number_of_vertices(), num_vertices) << "the refined mesh needed no new vertex";
    std::size_t inside = 0;
    for (auto c = s.tr.finite_cells_begin(); c != s.tr.finite_cells_end(); ++c) {
      Point3 centroid{0, 0, 0};
      for (int k = 0; k < 4; ++k)
        for (int j = 0; j < 3; ++j) centroid[j] += s.point(c->vertex(k)->info())[j] / 4;
      const bool in_box = centroid[0] > 0 && centroid[0] < 1 && centroid[1] > 0 && centroid[1] < 2 &&
                          centroid[2] > 0 && centroid[2] < 1;
      EXPECT_EQ(c->info().region >= 0, in_box);
      inside += in_box;
    }
    EXPECT_GT(inside, 0u);
  }
}

}  // namespace

namespace {

// A 12-gon prism standing for a cylinder of radius 1 (z in [0, 2]), as the CAD front end hands one over: the side
// quads carry CAD face 1, the caps faces 2 and 3 (planes), the cap circles CAD edges 10 (z = 0) and 11 (z = 2).
Plc cylinder_prism() {
  Plc plc;
  const int n = 12;
  for (int z = 0; z < 2; ++z)
    for (int i = 0; i < n; ++i)
      plc.vertices.push_back({std::cos(2 * M_PI * i / n), std::sin(2 * M_PI * i / n), 2.0 * z});
  qualmesh::Facet bottom, top;
  bottom.marker = 2;
  top.marker = 3;
  bottom.polygons.emplace_back();
  top.polygons.emplace_back();
  for (int i = 0; i < n; ++i) {
    const Index j = (i + 1) % n;
    qualmesh::Facet side;
    side.marker = 1;
    side.polygons.push_back({Index(i), j, Index(n + j), Index(n + i)});
    plc.facets.push_back(side);
    bottom.polygons[0].push_back(Index(n - 1 - i));
    top.polygons[0].push_back(Index(n + i));
    plc.segments.push_back({Index(i), j, 10});
    plc.segments.push_back({Index(n + i), Index(n + j), 11});
  }
  plc.facets.push_back(bottom);
  plc.facets.push_back(top);
  return plc;
}

// The exact cylinder: CAD edges 10 and 11 are its circles, face 1 its side; the planes are not projected.
bool onto_cylinder(int edge, int face, Point3& p) {
  if (edge != 10 && edge != 11 && face != 1) return false;
  const double r = std::hypot(p[0], p[1]);
  if (r == 0) return false;
  p = {p[0] / r, p[1] / r, edge == 10 ? 0.0 : edge == 11 ? 2.0 : p[2]};
  return true;
}

// Largest distance from the cylinder of a node on a side face, and how many side nodes there are.
std::pair<double, std::size_t> off_cylinder(const Plc& plc, const qualmesh::TetMesh& mesh) {
  std::vector<char> side(mesh.points.size(), 0);
  for (std::size_t f = 0; f < mesh.faces.size(); ++f)
    if (mesh.face_facet[f] >= 0 && plc.facets[mesh.face_facet[f]].marker == 1)
      for (Index v : mesh.faces[f]) side[v] = 1;
  double worst = 0;
  std::size_t count = 0;
  for (std::size_t v = 0; v < mesh.points.size(); ++v)
    if (side[v]) {
      ++count;
      worst = std::max(worst, std::fabs(std::hypot(mesh.points[v][0], mesh.points[v][1]) - 1));
    }
  return {worst, count};
}

}  // namespace

// MeshOptions::project_to_boundary (boundary_projection.cpp): the points Rules 1 and 2 put on the prism's side
// subsegments and subfacets go onto the cylinder, so every node of the side lies on it, and the mesh's volume is
// closer to the cylinder's (2 pi) than the prism's; without the projection they stay on the chords.
TEST(Levels, BoundaryPointsProjectedOntoTheCurvedSurface) {
  const Plc input = cylinder_prism();
  MeshOptions options;
  options.encroaching = MeshOptions::Encroaching::Steiner;
  options.target_edge_length = 0.25;
  const auto plain = qualmesh::mesh_plc(input, options);
  options.project_to_boundary = onto_cylinder;
  const auto projected = qualmesh::mesh_plc(input, options);
  ASSERT_FALSE(projected.mesh.tets.empty());
  EXPECT_FALSE(projected.stats.boundary_projection_dropped);
  EXPECT_FALSE(projected.stats.encroaching_fell_back);
  const auto [plain_off, plain_nodes] = off_cylinder(input, plain.mesh);
  const auto [off, nodes] = off_cylinder(input, projected.mesh);
  EXPECT_GT(plain_off, 1e-3) << "the unprojected side nodes sit on the chords";
  EXPECT_GT(nodes, 100u);
  EXPECT_LT(off, 1e-12) << nodes << " side nodes";
  double volume = 0, prism = 0;
  for (const auto& t : projected.mesh.tets) volume += qualmesh::tet_signed_volume(projected.mesh.points[t[0]],
      projected.mesh.points[t[1]], projected.mesh.points[t[2]], projected.mesh.points[t[3]]);
  for (const auto& t : plain.mesh.tets) prism += qualmesh::tet_signed_volume(plain.mesh.points[t[0]],
      plain.mesh.points[t[1]], plain.mesh.points[t[2]], plain.mesh.points[t[3]]);
  EXPECT_NEAR(prism, 2 * 12 * 0.5 * std::sin(2 * M_PI / 12), 1e-9);  // conforming: exactly the prism
  EXPECT_GT(volume, prism + 0.5 * (2 * M_PI - prism));  // more than half of the way to the cylinder
  EXPECT_LT(volume, 2 * M_PI);
}

namespace {

double mesh_volume(const qualmesh::TetMesh& mesh) {
  double v = 0;
  for (const auto& t : mesh.tets)
    v += qualmesh::tet_signed_volume(mesh.points[t[0]], mesh.points[t[1]], mesh.points[t[2]], mesh.points[t[3]]);
  return v;
}

double shortest_mesh_edge(const qualmesh::TetMesh& mesh) {
  double sq = std::numeric_limits<double>::infinity();
  for (const auto& t : mesh.tets)
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) {
        const Point3 &a = mesh.points[t[i]], &b = mesh.points[t[j]];
        sq = std::min(sq, (a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
      }
  return std::sqrt(sq);
}

// MeshOptions::min_split_length: on a 1-degree wedge, the relaxed rule splits encroached subsegments and subfacets
// down towards its sharp edge; with the floor it keeps the present ones below it and ends with fewer vertices, and
// conforms exactly all the same (the volume is the input's: missing elements are still split). The shortest edges
// of both meshes are printed.
TEST(Levels, SplitFloorKeepsSmallEncroachedElementsAndConformity) {
  // A wedge: a triangular prism of height 1 over a triangle with a 1-degree corner at the origin.
  Plc needle;
  const double w = 10 * std::tan(M_PI / 180);
  needle.vertices = {{0, 0, 0}, {10, 0, 0}, {10, w, 0}, {0, 0, 1}, {10, 0, 1}, {10, w, 1}};
  for (const std::vector<Index>& loop : std::vector<std::vector<Index>>{
           {0, 2, 1}, {3, 4, 5}, {0, 1, 4, 3}, {1, 2, 5, 4}, {2, 0, 3, 5}}) {
    qualmesh::Facet f;
    f.polygons.push_back(loop);
    needle.facets.push_back(f);
  }
  const double exact = 0.5 * 10 * w;
  MeshOptions options;
  options.pump = false;
  options.improve = false;
  options.encroaching = MeshOptions::Encroaching::Steiner;  // the floor is the relaxed rule's
  options.max_edge_length = 1;  // refinement inside, whose points encroach the boundary near the sharp edge
  const auto plain = qualmesh::mesh_plc(needle, options);
  options.min_split_length = 0.5;
  const auto floored = qualmesh::mesh_plc(needle, options);
  ASSERT_EQ(plain.status, qualmesh::MeshStatus::Ok);
  ASSERT_EQ(floored.status, qualmesh::MeshStatus::Ok);
  EXPECT_NEAR(mesh_volume(plain.mesh), std::fabs(exact), 1e-12);
  EXPECT_NEAR(mesh_volume(floored.mesh), std::fabs(exact), 1e-12);
  EXPECT_EQ(plain.stats.num_skipped_floor, 0u);
  EXPECT_GT(floored.stats.num_skipped_floor, 0u);
  EXPECT_LT(floored.mesh.points.size(), plain.mesh.points.size());
  // The paper's rule stays as written, floor or not.
  options.encroaching = MeshOptions::Encroaching::All;
  const auto paper = qualmesh::mesh_plc(needle, options);
  EXPECT_EQ(paper.stats.num_skipped_floor, 0u);
  std::printf("wedge: %zu vertices, shortest edge %.3g without the floor; %zu, %.3g with it (%zu kept)\n",
              plain.mesh.points.size(), shortest_mesh_edge(plain.mesh), floored.mesh.points.size(),
              shortest_mesh_edge(floored.mesh), floored.stats.num_skipped_floor);
}

}  // namespace

// MeshOptions::project_to_boundary's safety net in Rules 1-2 (refine_state.h, count_below_floor_split): splits below
// the split floor are counted, and past kBelowFloorSplitBudget plus the input's vertex count, with a projector only,
// every stage stops as at the vertex limit and mesh_plc() meshes again without the projection. (The runaway it
// catches: part.step with a surface made without brep_to_plc.cpp's cross-face edge splits and the OCC projector,
// where one subsegment was split to 2e-4 against a floor of 0.35; a synthetic projector did not reproduce it.)
TEST(Levels, SplitsBelowTheFloorPastTheBudgetStopAProjectedRun) {
  for (const bool projected : {false, true}) {
    MeshOptions options;
    options.min_split_length = 0.01;
    if (projected) options.project_to_boundary = [](int, int, Point3&) { return false; };
    Engine e(box({0, 0, 0}, {1, 1, 1}), options);
    const std::size_t budget = d::kBelowFloorSplitBudget + e.plc.vertices.size();
    for (std::size_t n = 0; n < budget; ++n) e.s.count_below_floor_split();
    EXPECT_FALSE(e.s.projection_runaway);
    EXPECT_FALSE(e.s.vertex_limit_reached);
    e.s.count_below_floor_split();
    EXPECT_EQ(e.s.projection_runaway, projected);
    EXPECT_EQ(e.s.vertex_limit_reached, projected);
  }
}

// Refinement at the limit of double precision (MeshState::stop_at_precision): a boundary point whose place in a
// facet's 2D triangulation is already a vertex cannot be inserted there. CGAL's insert would return the old vertex
// and QualMesh would overwrite its id: bottle.brep at --size 80 crashed in CGAL's flips after 28 such merges.
// facet_accepts_point() says so before anything is inserted, and Rule 2 then stops every stage.
TEST(Levels, FacetPointOnATwoDimensionalVertexIsRefusedAndStopsRefinement) {
  MeshOptions options;
  options.max_edge_length = 0.5;
  options.pump = false;
  Engine e(box({0, 0, 0}, {3, 3, 1}), options);
  e.refine();
  d::MeshState& s = e.s;
  const Index bottom = 0;  // z = 0
  std::vector<std::array<Index, 3>> faces;
  d::collect_subfacets(s, bottom, faces);
  std::optional<std::array<Index, 3>> inner;
  for (const auto& f : faces) {
    bool far = true;
    for (Index v : f) far = far && s.point(v)[0] > 1 && s.point(v)[0] < 2 && s.point(v)[1] > 1 && s.point(v)[1] < 2;
    if (far) inner = f;
  }
  ASSERT_TRUE(inner);
  const Point3 corner = s.point((*inner)[0]);
  d::VertexRecord r;
  r.kind = d::VertexKind::Facet;
  r.host = bottom;
  r.point = {corner[0], corner[1], 1e-9};  // another point in 3D, the same one in the facet's plane
  EXPECT_FALSE(d::facet_accepts_point(s, r));
  r.point = d::to_point3(s.rule2.refinement_point(s, *inner));
  EXPECT_TRUE(d::facet_accepts_point(s, r));

  // A segment point on its chain neighbour, at its neighbour's parameter: no place on the constrained edge.
  const Index ab = e.segment(0, 1);
  ASSERT_NE(ab, kNoIndex);
  d::VertexRecord q;
  q.kind = d::VertexKind::Segment;
  q.host = ab;
  q.prev = s.complex.segments[ab].a;
  q.next = d::next_on_segment(s, ab, q.prev);
  q.t = d::segment_parameter(s, ab, q.prev);
  q.point = s.point(q.prev);
  EXPECT_FALSE(d::facet_accepts_point(s, q));
  q.t = 0.5 * (d::segment_parameter(s, ab, q.prev) + d::segment_parameter(s, ab, q.next));
  for (int k = 0; k < 3; ++k) q.point[k] = 0.5 * (s.point(q.prev)[k] + s.point(q.next)[k]);
  EXPECT_TRUE(d::facet_accepts_point(s, q));

  // The stop: the first reason is kept, and the scheduler takes nothing more from the queues.
  s.stop_at_precision("facet 0", 1e-15, r.point);
  s.stop_at_precision("segment 3", 1e-16, q.point);
  EXPECT_TRUE(s.vertex_limit_reached);
  EXPECT_NE(s.precision_stop.find("an element of facet 0 (size 1e-15) at ("), std::string::npos)
      << s.precision_stop;
  EXPECT_EQ(s.precision_stop.find("segment 3"), std::string::npos) << s.precision_stop;
  const std::size_t vertices = s.vertices.size();
  s.rule2.push({bottom, *inner, false, {}, true});
  d::run_refinement(s, true);
  EXPECT_EQ(s.vertices.size(), vertices);
  EXPECT_EQ(s.rule2.queue.size(), 1u);
}
