// Tests of the mesh checker's protection zones (mesh_check_protection.cpp, issue 16): the sharp input angles it
// finds, and the tetrahedra it counts inside the protecting balls, against figures worked out by hand.
//  - A cube has no input angle below 60 degrees; below 91 degrees every corner and edge is sharp.
//  - A prism with a house-shaped cross-section whose ridge has a 36.9-degree apex angle: the ridge is the one sharp
//    segment, its two ends the sharp vertices, and the local feature size along it is the distance to the eaves, so
//    the zone is the capsule of that radius around the ridge. QualMesh's mesh of the prism is counted against that
//    capsule directly, and `qualmesh mesh`'s summary line shows the checker's figures.
//  - A CAD model's zone (fill_cad_feature_protection: the tetrahedra with a vertex near a sharp feature, which the
//    CAD front end finds) and its default radius (median_edge_length) on Kuhn's cube, counted by hand. The features
//    themselves are tested end to end in tests/python/test_check_cad_features.py.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cmath>
#include <limits>

#include "qualmesh/mesh_check.h"
#include "qualmesh/mesh_io.h"
#include "qualmesh/mesher.h"
#include "qualmesh/plc_io.h"
#include "qualmesh/quality.h"
#include "sample_meshes.h"
#include "test_support.h"

namespace qualmesh {
namespace {

TEST(MeshCheckProtection, CubeHasNoSharpAngleBelowSixtyAndOnlySharpOnesBelowNinetyOne) {
  const Plc plc = unit_cube_plc();
  const TetMesh mesh = kuhn_unit_cube();
  const CheckReport at60 = check_mesh(mesh, &plc);
  ASSERT_TRUE(at60.ok);
  EXPECT_TRUE(at60.protection_checked);
  EXPECT_EQ(at60.num_sharp_vertices, 0u);
  EXPECT_EQ(at60.num_sharp_segments, 0u);
  EXPECT_EQ(at60.num_tets_in_protection_zone, 0u);
  EXPECT_EQ(at60.min_dihedral_outside_protection_deg, at60.min_dihedral_deg);
  EXPECT_EQ(at60.num_tets_outside_protection_below_15, at60.num_tets_min_dihedral_below_15);

  CheckOptions options;
  options.protection_angle_deg = 91;  // the right angles of the cube become sharp
  const CheckReport at91 = check_mesh(mesh, &plc, options);
  EXPECT_EQ(at91.num_sharp_vertices, 8u);
  EXPECT_EQ(at91.num_sharp_segments, 12u);
  EXPECT_EQ(at91.num_tets_in_protection_zone, 6u);  // every tetrahedron has a corner of the cube
  EXPECT_EQ(at91.min_dihedral_outside_protection_deg, 0);
  EXPECT_EQ(at91.num_tets_outside_protection_below_15, 0u);

  options.protection_angle_deg = 0;
  const CheckReport off = check_mesh(mesh, &plc, options);
  EXPECT_FALSE(off.protection_checked);
  EXPECT_EQ(to_json(off).find("num_tets_in_protection_zone"), std::string::npos);
  EXPECT_NE(to_json(at60).find("\"num_tets_in_protection_zone\": 0"), std::string::npos);
  EXPECT_NE(to_text(at91).find("8 sharp vertices, 12 sharp segments; 6 of 6 tets inside"), std::string::npos);
}

// A prism along z whose cross-section is a house: walls x = 0 and x = 20 from y = 0 to 40, and a roof whose ridge
// A-A' (A = (10, 70, 0)) has an apex angle of 2 atan(10 / 30) = 36.9 degrees. The eaves turn by 161.6 degrees,
// every other angle is a right one.
Plc house_prism(double length) {
  Plc plc;
  const double xy[5][2] = {{0, 0}, {20, 0}, {20, 40}, {10, 70}, {0, 40}};
  for (double z : {0.0, length})
    for (const auto& p : xy) plc.vertices.push_back({p[0], p[1], z});
  Facet cap, far_cap;
  cap.polygons.push_back({0, 1, 2, 3, 4});
  far_cap.polygons.push_back({5, 6, 7, 8, 9});
  plc.facets = {cap, far_cap};
  for (Index i = 0; i < 5; ++i) {
    Facet side;
    side.polygons.push_back({i, (i + 1) % 5, (i + 1) % 5 + 5, i + 5});
    plc.facets.push_back(side);
  }
  return plc;
}

TEST(MeshCheckProtection, ZoneIsTheCapsuleOfTheLocalFeatureSizeAroundTheSharpRidge) {
  const double length = 80;
  const Plc plc = house_prism(length);
  MeshOptions mesh_options;
  mesh_options.max_edge_length = 6;
  const MeshResult result = mesh_plc(plc, mesh_options);
  const TetMesh& mesh = result.mesh;
  ASSERT_GT(mesh.tets.size(), 500u);
  const CheckReport report = check_mesh(mesh, &plc);
  ASSERT_TRUE(report.ok) << to_text(report);
  ASSERT_TRUE(report.protection_checked);
  // The ridge's 36.9-degree corners of both caps (segment-segment, and the caps' roof edges against the other roof
  // face) have their apex at A or A'; the only facet-facet angle below 60 degrees is the ridge's.
  EXPECT_EQ(report.num_sharp_vertices, 2u);
  EXPECT_EQ(report.num_sharp_segments, 1u);

  // f at A, A' and along the ridge is h = sqrt(10^2 + 30^2), the distance to the eaves (every nearer element touches
  // the ridge; the caps, non-adjacent to each other, are both within 40 of the ridge's midpoint only): a point is in the zone exactly when it lies within h of the segment A-A', which holds the roof and
  // nothing below the eaves. Points within rounding of that distance may go either way.
  const double h = std::sqrt(1000.0);
  const auto distance_to_edge = [&](const Point3& p) {
    const double z = std::clamp(p[2], 0.0, length);
    return std::sqrt((p[0] - 10) * (p[0] - 10) + (p[1] - 70) * (p[1] - 70) + (p[2] - z) * (p[2] - z));
  };
  // The tets surely and maybe outside bound the reported outside set, its smallest angle and its count below 15.
  std::size_t surely_inside = 0, maybe_inside = 0, surely_outside_below_15 = 0, maybe_outside_below_15 = 0;
  const double inf = std::numeric_limits<double>::infinity();
  double surely_outside_min = inf, maybe_outside_min = inf;
  for (const auto& t : mesh.tets) {
    double nearest = inf;
    for (Index v : t) nearest = std::min(nearest, distance_to_edge(mesh.points[v]));
    surely_inside += nearest < h * (1 - 1e-9);
    maybe_inside += nearest <= h * (1 + 1e-9);
    const double angle =
        tet_quality(mesh.points[t[0]], mesh.points[t[1]], mesh.points[t[2]], mesh.points[t[3]]).min_dihedral_deg;
    if (nearest > h * (1 + 1e-9)) {
      surely_outside_min = std::min(surely_outside_min, angle);
      surely_outside_below_15 += angle < 15;
    }
    if (nearest >= h * (1 - 1e-9)) {
      maybe_outside_min = std::min(maybe_outside_min, angle);
      maybe_outside_below_15 += angle < 15;
    }
  }
  EXPECT_GE(report.num_tets_in_protection_zone, surely_inside);
  EXPECT_LE(report.num_tets_in_protection_zone, maybe_inside);
  ASSERT_LT(maybe_inside, mesh.tets.size()) << "the mesh has no tetrahedron away from the sharp ridge";
  EXPECT_GE(report.min_dihedral_outside_protection_deg, maybe_outside_min);
  EXPECT_LE(report.min_dihedral_outside_protection_deg, surely_outside_min);
  EXPECT_GE(report.num_tets_outside_protection_below_15, surely_outside_below_15);
  EXPECT_LE(report.num_tets_outside_protection_below_15, maybe_outside_below_15);
  // The eaves' own vertices lie on the capsule (about a hundred tets go either way); the roof is inside.
  EXPECT_GT(surely_inside, mesh.tets.size() / 10);

  // The mesher's summary computes the same figures without the other checks.
  const CheckReport alone = check_protection_zones(mesh, plc, 60);
  EXPECT_EQ(alone.num_sharp_vertices, report.num_sharp_vertices);
  EXPECT_EQ(alone.num_sharp_segments, report.num_sharp_segments);
  EXPECT_EQ(alone.num_tets_in_protection_zone, report.num_tets_in_protection_zone);
  EXPECT_EQ(alone.min_dihedral_outside_protection_deg, report.min_dihedral_outside_protection_deg);
  EXPECT_EQ(alone.num_tets_outside_protection_below_10, report.num_tets_outside_protection_below_10);
  EXPECT_EQ(alone.num_tets_outside_protection_below_15, report.num_tets_outside_protection_below_15);

  // Below 91 degrees the right angles become sharp too: all ten vertices (the eaves are apices of right angles
  // between the caps and the edges along z), the ten edges of the caps and the two bottom edges along z (the eaves
  // turn by 161.6 degrees): more tets inside.
  CheckOptions options;
  options.protection_angle_deg = 91;
  const CheckReport at91 = check_mesh(mesh, &plc, options);
  EXPECT_EQ(at91.num_sharp_vertices, 10u);
  EXPECT_EQ(at91.num_sharp_segments, 13u);
  EXPECT_GT(at91.num_tets_in_protection_zone, report.num_tets_in_protection_zone);
}

// Everything `command` prints on stdout, and its exit status.
std::string run(const std::string& command, int& status) {
  std::string out;
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return out;
  char buffer[4096];
  for (std::size_t n; (n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0;) out.append(buffer, n);
  status = pclose(pipe);
  return out;
}

TEST(MeshCheckProtection, MeshSummaryHasTheCheckersFigures) {
  const auto dir = test::temp_dir("protection-summary");
  const std::string poly = (dir / "house.poly").string(), vtu = (dir / "house.vtu").string();
  write_plc(house_prism(80), poly);
  int status = -1;
  const std::string summary = run(test::qualmesh_exe() + " mesh " + poly + " -o " + vtu + " --max-edge 6", status);
  ASSERT_EQ(status, 0) << summary;
  const Plc plc = house_prism(80);
  const CheckReport report = check_mesh(read_tet_mesh(vtu), &plc);
  char line[300];
  std::snprintf(line, sizeof line,
                "protection:  outside the zones of input angles < 60 deg (2 sharp vertices, 1 sharp segments; %zu of "
                "%zu tetrahedra inside): min dihedral %.4g deg, %zu/%zu tetrahedra below 10/15 deg\n",
                report.num_tets_in_protection_zone, report.num_tets, report.min_dihedral_outside_protection_deg,
                report.num_tets_outside_protection_below_10, report.num_tets_outside_protection_below_15);
  EXPECT_NE(summary.find(line), std::string::npos) << "expected: " << line << "in:\n" << summary;
}

// Kuhn's cube: each of its 6 tetrahedra (0, a, b, 7) has three edges of length 1, two of sqrt(2) and one of sqrt(3),
// dihedral angles 45, 60 and 90 degrees; vertex 1 = (1, 0, 0) is in 2 of them, vertex 0 in all 6.
TEST(MeshCheckProtection, CadFeatureZoneHoldsTheTetsWithANearVertex) {
  const TetMesh mesh = kuhn_unit_cube();
  EXPECT_DOUBLE_EQ(median_edge_length(mesh), std::sqrt(2.0));  // 18 of 36 edge entries are 1, then sqrt(2)

  CheckReport report;
  report.num_tets = mesh.tets.size();  // as check_mesh sets it before the CAD checks add the zone
  fill_cad_feature_protection(report, mesh, {1, 99}, 30, 0.25, 3, 2);  // 99: no such vertex, ignored
  EXPECT_TRUE(report.protection_checked);
  EXPECT_EQ(report.protection_zone, CheckReport::ProtectionZone::CadFeatureBalls);
  EXPECT_EQ(report.protection_angle_deg, 30);
  EXPECT_EQ(report.protection_radius, 0.25);
  EXPECT_EQ(report.num_sharp_vertices, 3u);
  EXPECT_EQ(report.num_sharp_segments, 2u);
  EXPECT_EQ(report.num_tets_in_protection_zone, 2u);
  EXPECT_NEAR(report.min_dihedral_outside_protection_deg, 45.0, 1e-9);
  EXPECT_EQ(report.num_tets_outside_protection_below_10, 0u);
  EXPECT_EQ(report.num_tets_outside_protection_below_15, 0u);
  EXPECT_NE(to_text(report).find("farther than 0.25 from sharp CAD features (angles < 30 deg: 3 sharp vertices, 2 "
                                 "sharp edges; 2 of 6 tets inside)"),
            std::string::npos)
      << to_text(report);
  EXPECT_NE(to_json(report).find("\"protection_zone\": \"cad_feature_balls\""), std::string::npos);

  CheckReport all;
  fill_cad_feature_protection(all, mesh, {0}, 30, 0.25, 1, 0);
  EXPECT_EQ(all.num_tets_in_protection_zone, 6u);
  EXPECT_EQ(all.min_dihedral_outside_protection_deg, 0);  // none outside
}

}  // namespace
}  // namespace qualmesh
