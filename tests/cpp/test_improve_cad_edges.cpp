// Tests of the improvement pass on the nodes of curved CAD edges (core/src/improve, VertexFreedom::OnCurve).
// The input stands in for what the CAD front end writes (brep_to_plc.cpp): a cylinder whose two planar ends are one
// polygon facet each (Face1, Face2), whose side is triangle facets all marked 3 (Face3), whose circles are chains of
// segments marked 1 and 2 (Edge1, Edge2) and whose seam is one segment marked 3 (Edge3). The projector puts a point
// on a circle (edges 1, 2) or on the side (face 3), as OpenCASCADE's would. Properties asserted:
//   - classification: in a CAD run, a node inside a circle (two segments of one edge) is OnCurve on that edge, its
//     chain's ends (where the seam meets: CAD vertices) are Fixed; in a user's PLC every input vertex is Fixed;
//   - the pass moves OnCurve nodes, each stays on its circle (to rounding), every tet stays positively oriented, the
//     boundary faces are the same list, and the minimum dihedral angle never drops.
#include <gtest/gtest.h>

#include <cmath>

#include "improve/improve.h"
#include "qualmesh/mesher.h"
#include "qualmesh/quality.h"

namespace {

using qualmesh::Index;
using qualmesh::Plc;
using qualmesh::Point3;
using qualmesh::detail::VertexFreedom;

constexpr double kRadius = 5, kHeight = 10;
constexpr int kAround = 16;

double radial(const Point3& p) { return std::hypot(p[0], p[1]); }

// Vertices 0..15 the bottom circle (z = 0), 16..31 the top one; vertex 0 and 16 are the seam's ends.
Plc cylinder() {
  Plc plc;
  for (double z : {0.0, kHeight})
    for (int i = 0; i < kAround; ++i) {
      const double a = 2 * M_PI * i / kAround;
      plc.vertices.push_back({kRadius * std::cos(a), kRadius * std::sin(a), z});
    }
  qualmesh::Facet bottom, top;
  bottom.marker = 1;
  top.marker = 2;
  bottom.polygons.emplace_back();
  top.polygons.emplace_back();
  for (int i = 0; i < kAround; ++i) {
    const Index b0 = Index(i), b1 = Index((i + 1) % kAround), t0 = b0 + kAround, t1 = b1 + kAround;
    bottom.polygons[0].push_back(Index(kAround - 1 - i));  // outward: -z
    top.polygons[0].push_back(t0);
    plc.facets.push_back({{{b0, b1, t1}}, {}, 3});
    plc.facets.push_back({{{b0, t1, t0}}, {}, 3});
    plc.segments.push_back({b0, b1, 1});
    plc.segments.push_back({t0, t1, 2});
  }
  plc.facets.push_back(bottom);
  plc.facets.push_back(top);
  plc.segments.push_back({0, kAround, 3});
  return plc;
}

// MeshOptions::project_to_boundary for that cylinder.
bool onto_cylinder(int edge, int face, Point3& p) {
  const double r = radial(p);
  if (!(r > 0)) return false;
  if (edge == 1 || edge == 2) {
    p = {kRadius * p[0] / r, kRadius * p[1] / r, edge == 1 ? 0.0 : kHeight};
    return true;
  }
  if (edge == 0 && face == 3) {
    p = {kRadius * p[0] / r, kRadius * p[1] / r, p[2]};
    return true;
  }
  return false;  // the seam (straight) and the two planes
}

TEST(ImproveCadEdges, NodesInsideACurvedEdgeMoveAlongIt) {
  const Plc plc = cylinder();
  qualmesh::MeshOptions options;
  options.improve = false;
  options.max_edge_length = 2.5;
  options.project_to_boundary = onto_cylinder;
  const qualmesh::MeshResult plain = qualmesh::mesh_plc(plc, options);
  ASSERT_EQ(plain.status, qualmesh::MeshStatus::Ok);
  ASSERT_EQ(plain.mesh.edges.size(), plain.mesh.edge_marker.size());

  const auto cad = qualmesh::detail::classify_vertices(plain.mesh, plc, true);
  const auto user = qualmesh::detail::classify_vertices(plain.mesh, plc, false);
  for (Index v = 0; v < 2 * kAround; ++v) {
    ASSERT_EQ(plain.mesh.points[v], plc.vertices[v]) << "the mesher keeps input vertices first";
    EXPECT_EQ(user[v].freedom, VertexFreedom::Fixed) << v;
    if (v % kAround == 0) {
      EXPECT_EQ(cad[v].freedom, VertexFreedom::Fixed) << "seam end " << v;
    } else {
      EXPECT_EQ(cad[v].freedom, VertexFreedom::OnCurve) << v;
      EXPECT_EQ(cad[v].cad_edge, v < kAround ? 1 : 2) << v;
    }
  }

  qualmesh::detail::ImproveOptions improve;
  improve.boundary_insertion = false;  // as for CAD meshes (MeshOptions::before_improve)
  improve.cap_removal = false;         // moves only: the boundary faces stay the same list
  improve.insertion = false;
  improve.flips = false;
  improve.sliver_angle_deg = 35;  // well above what the engine leaves, so that rim vertices are asked to move
  improve.project_to_boundary = onto_cylinder;
  qualmesh::TetMesh mesh = plain.mesh;
  const auto r = qualmesh::detail::improve_mesh(mesh, plc, improve);
  ASSERT_GT(r.num_below_before, 0u) << "nothing to improve: the test proves nothing";
  EXPECT_GE(r.num_on_curve, std::size_t(2 * (kAround - 1))) << "at least the input rim nodes";
  std::size_t moved_on_curve = 0;
  for (Index v = 0; v < mesh.points.size(); ++v) {
    if (cad[v].freedom != VertexFreedom::OnCurve) continue;
    const Point3 &p = mesh.points[v], &o = plain.mesh.points[v];
    EXPECT_NEAR(radial(p), kRadius, 1e-12) << v;
    EXPECT_EQ(p[2], o[2]) << v;
    moved_on_curve += p != o;
  }
  EXPECT_GT(moved_on_curve, 0u);
  EXPECT_EQ(mesh.faces, plain.mesh.faces);
  for (const auto& t : mesh.tets)
    EXPECT_GT(qualmesh::tet_signed_volume(mesh.points[t[0]], mesh.points[t[1]], mesh.points[t[2]], mesh.points[t[3]]),
              0);
  EXPECT_GE(r.min_dihedral_after_deg, r.min_dihedral_before_deg);
}

}  // namespace
