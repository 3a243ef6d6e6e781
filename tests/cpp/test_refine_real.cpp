// The refinement engine (mesh_plc, Rules 1-3 of Cheng & Dey Section 3) on the real models of ../shared/data/plc
// (issue 3, "Must show"): each closed valid model read through read_plc() meshes with status Ok, no non-positive
// tetrahedron, exact conformity to the input (check_mesh with the input as reference: volume and per-facet area
// relative errors below 1e-9, no boundary face off its facet), and radius-edge ratio <= rho0 = 2 for every
// tetrahedron that does not touch an acute input angle (kImproveRadiusEdgeFactor * rho0 for those the improvement
// pass changed, which runs by default), by the engine's own classification
// (MeshResult::tet_touches_acute_angle, defined once by InputComplex::elements_meet_acute). The engine's statistics
// must agree: no tetrahedron above the bound is left for a reason other than an acute input angle.
//
// t13_data.stl and cheese.off (RealModelsSlow) did not terminate before the acute-angle fixes of complex.cpp
// (inward facet directions) and subsegments.cpp (dyadic shells). aorta2.stl, elephant.mesh and cow.off are invalid
// inputs.
#include <gtest/gtest.h>

#include <cstdlib>
#include <set>
#include <string>

#include "qualmesh/mesh_check.h"
#include "qualmesh/mesher.h"
#include "qualmesh/plc_io.h"
#include "qualmesh/quality.h"
#include "test_support.h"

namespace qualmesh {
namespace {

std::string plc_path(const std::string& name) { return test::shared_path("data/plc/" + name); }

// Returns the number of mesh vertices. The caller skips the test when the file is missing (QM_REQUIRE_FILE).
std::size_t expect_quality_mesh(const std::string& name, MeshOptions options = {}) {
  const std::string path = plc_path(name);
  const Plc plc = read_plc(path);
  options.max_vertices = 2'000'000;
  const MeshResult result = mesh_plc(plc, options);
  EXPECT_EQ(result.status, MeshStatus::Ok) << name;
  const TetMesh& mesh = result.mesh;
  EXPECT_EQ(result.tet_touches_acute_angle.size(), mesh.tets.size());
  if (result.status != MeshStatus::Ok || result.tet_touches_acute_angle.size() != mesh.tets.size()) return 0;

  const CheckReport report = check_mesh(mesh, &plc);
  EXPECT_EQ(report.num_nonpositive_tets, 0u) << name;
  EXPECT_EQ(report.num_bad_indices + report.num_duplicate_tets + report.num_overshared_faces +
                report.num_folded_faces, 0u) << name;
  EXPECT_TRUE(report.has_reference) << name;
  EXPECT_LT(report.volume_relative_error, 1e-9) << name << " " << report.reference_volume_method;
  EXPECT_EQ(report.num_faces_off_input, 0u) << name;
  // Every facet covered to its area, and a facet bounding no region (example.poly's hole face behind its facet
  // hole) by nothing.
  EXPECT_LT(report.max_facet_area_relative_error, 1e-9) << name;
  EXPECT_EQ(report.num_miscovered_facets, 0u) << name;

  // rho0 (Rule 3) for the engine's tets; the improvement pass (on by default with pumping) may change tets up to
  // kImproveRadiusEdgeFactor * rho0 away from acute input angles (mesher.h).
  const double rho0 = options.radius_edge_bound;
  const bool improved = options.improve && options.pump && result.stats.num_tets_improved > 0;
  const double bound = improved ? kImproveRadiusEdgeFactor * rho0 : rho0;
  std::size_t above = 0, above_acute = 0, beyond = 0;
  double worst = 0;
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
    const auto& v = mesh.tets[t];
    const double rho = tet_radius_edge(mesh.points[v[0]], mesh.points[v[1]], mesh.points[v[2]], mesh.points[v[3]]);
    if (rho <= rho0) continue;
    if (result.tet_touches_acute_angle[t]) {
      ++above_acute;
    } else {
      ++above;
      beyond += rho > bound;
      worst = std::max(worst, rho);
    }
  }
  EXPECT_EQ(beyond, 0u) << name << ": tets above " << bound << " away from acute input angles, worst " << worst;
  if (!improved) EXPECT_EQ(above, 0u) << name;
  const MeshStats& st = result.stats;
  // The engine's own account agrees (up to rounding of rho at the bound).
  EXPECT_NEAR(double(st.num_tets_above_bound), double(above + above_acute), 1e-4 * double(mesh.tets.size()) + 2);
  EXPECT_EQ(st.num_above_bound_rejected + st.num_above_bound_other, 0u) << name;
  EXPECT_LE(st.max_radius_edge_away_from_acute, bound) << name;
  return mesh.points.size();
}

class RealModels : public ::testing::TestWithParam<const char*> {};

TEST_P(RealModels, QualityConformingMesh) {
  QM_REQUIRE_FILE(plc_path(GetParam()));
  expect_quality_mesh(GetParam());
}

INSTANTIATE_TEST_SUITE_P(SharedPlc, RealModels,
                         ::testing::Values("wedge-1.smesh", "spike-1-10.smesh", "slit-1.smesh", "cubes.off",
                                           "joint.off", "anchor.off", "pinion.off", "couplingdown.off",
                                           "elephant.off", "fandisk.off", "lever.stl", "turbine.off"),
                         [](const ::testing::TestParamInfo<const char*>& info) {
                           std::string name = info.param;
                           for (char& ch : name)
                             if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
                           return name;
                         });

// MeshOptions::encroaching: the paper's Rules 1-2 (every vertex encroaches) and the Steiner mode (the default:
// input vertices do not encroach present elements) both give conforming meshes within rho0 away from
// acute input angles; on elephant.off, whose obtuse input triangles encroach their neighbours everywhere, Steiner
// mode needs far fewer vertices (measured 2776 against 17863 without pumping).
TEST(RealModels, InputVerticesEncroachingIsAnOption) {
  QM_REQUIRE_FILE(plc_path("elephant.off"));
  QM_REQUIRE_FILE(plc_path("joint.off"));
  MeshOptions paper;
  paper.pump = false;
  paper.encroaching = MeshOptions::Encroaching::All;
  MeshOptions steiner = paper;
  steiner.encroaching = MeshOptions::Encroaching::Steiner;
  for (const char* name : {"elephant.off", "joint.off"}) {
    const std::size_t all = expect_quality_mesh(name, paper);
    const std::size_t fewer = expect_quality_mesh(name, steiner);
    EXPECT_LE(fewer, all) << name;
    if (std::string(name) == "elephant.off") EXPECT_LT(3 * fewer, all) << name;
  }
}

// Steiner mode on tessellated surfaces whose segments meet at acute angles everywhere (every input vertex is an
// acute apex): a segment vertex does not encroach the subsegments of a segment sharing an endpoint with its own, a
// vertex that keeps a subfacet out stops being tolerated, and a subfacet centre beyond a subsegment splits that
// subsegment. Before those rules anchor and pinion did not finish in 300 s. Measured without pumping (paper's rule /
// Steiner): anchor 18411 / 5360, pinion 12002 / 7094, fandisk 28003 / 7424 vertices; none falls back.
TEST(RealModels, SteinerModeOnTessellatedSurfaces) {
  MeshOptions paper;
  paper.pump = false;
  paper.encroaching = MeshOptions::Encroaching::All;
  MeshOptions steiner = paper;
  steiner.encroaching = MeshOptions::Encroaching::Steiner;
  for (const char* name : {"anchor.off", "pinion.off", "fandisk.off"}) {
    QM_REQUIRE_FILE(plc_path(name));
    const std::size_t all = expect_quality_mesh(name, paper);
    const std::size_t fewer = expect_quality_mesh(name, steiner);
    EXPECT_LT(fewer, all * 7 / 10) << name;
    const MeshResult again = mesh_plc(read_plc(plc_path(name)), steiner);
    EXPECT_FALSE(again.stats.encroaching_fell_back) << name;
    EXPECT_EQ(again.mesh.points.size(), fewer) << name << ": not deterministic";
  }
}

// Under the relaxed rule, a corner between two edges counts as an acute input angle only below 30 degrees
// (RefineParams::corner_acute_deg). elephant.off's triangles have corners below 90 degrees at every input
// vertex; with the paper's 90 there, Rule 3 skipped the tetrahedra along the whole surface and left 454 above rho0
// (radius-edge up to 5.1), with a smallest dihedral angle of 12.61 degrees over all tetrahedra. Measured with 30:
// none left above rho0 by the engine, 15.01 degrees.
TEST(RealModels, SteinerModeGradesAwayFromSmoothSurfaces) {
  QM_REQUIRE_FILE(plc_path("elephant.off"));
  MeshOptions steiner;
  steiner.encroaching = MeshOptions::Encroaching::Steiner;
  expect_quality_mesh("elephant.off", steiner);
  const MeshResult result = mesh_plc(read_plc(plc_path("elephant.off")), steiner);
  ASSERT_EQ(result.status, MeshStatus::Ok);
  EXPECT_FALSE(result.stats.encroaching_fell_back);
  EXPECT_EQ(result.stats.num_above_bound_acute, 0u);
  EXPECT_GE(result.stats.min_dihedral_deg, 15.0);
}

TEST(RealModelsSlow, SlowBunny) {
  QM_REQUIRE_FILE(plc_path("bunny00.off"));
  expect_quality_mesh("bunny00.off");
}
TEST(RealModelsSlow, SlowCheese) {
  QM_REQUIRE_FILE(plc_path("cheese.off"));
  expect_quality_mesh("cheese.off");
}
TEST(RealModelsSlow, T13) {
  QM_REQUIRE_FILE(plc_path("t13_data.stl"));
  expect_quality_mesh("t13_data.stl");
}

// example.poly: two regions (attributes from the region seeds), two volume holes, one internal facet.
TEST(RealModels, ExamplePolyRegionsAndHoles) {
  const std::string path = test::shared_path("data/plc/example.poly");
  QM_REQUIRE_FILE(path);
  const Plc plc = read_plc(path);
  ASSERT_EQ(plc.regions.size(), 2u);
  ASSERT_EQ(plc.holes.size(), 2u);
  expect_quality_mesh("example.poly");
  const MeshResult result = mesh_plc(plc);
  ASSERT_EQ(result.status, MeshStatus::Ok);
  const TetMesh& mesh = result.mesh;
  std::set<int> want, got(mesh.tet_region.begin(), mesh.tet_region.end());
  for (const RegionSeed& r : plc.regions) want.insert(r.attribute);
  EXPECT_EQ(got, want);
  // The tet containing each region seed carries its attribute; no tet contains a hole seed.
  auto contains = [&](const std::array<Index, 4>& v, const Point3& p) {
    const Point3* q[4] = {&mesh.points[v[0]], &mesh.points[v[1]], &mesh.points[v[2]], &mesh.points[v[3]]};
    for (int i = 0; i < 4; ++i) {
      const Point3* r[4] = {q[0], q[1], q[2], q[3]};
      r[i] = &p;
      if (tet_signed_volume(*r[0], *r[1], *r[2], *r[3]) < 0) return false;
    }
    return true;
  };
  for (const Point3& h : plc.holes)
    for (const auto& tet : mesh.tets) EXPECT_FALSE(contains(tet, h)) << "a tet covers a hole seed";
  for (const RegionSeed& r : plc.regions) {
    int found = 0;
    for (std::size_t t = 0; t < mesh.tets.size(); ++t)
      if (contains(mesh.tets[t], r.point)) {
        ++found;
        EXPECT_EQ(mesh.tet_region[t], r.attribute);
      }
    EXPECT_GE(found, 1);
  }
}

}  // namespace
}  // namespace qualmesh
