// Second-order tetrahedra and checked node moves (second_order.h), and fitting meshes onto their CAD model
// (cad_import.h, fit_mesh_to_cad): mid nodes at midpoints and shared, the ten-node Jacobian against the straight
// tet's 6V, inversions caught, moves relaxed instead of inverting, and on real CAD every boundary node and mid node
// on its CAD face (measured independently by OpenCASCADE's BRepExtrema through distances_to_cad_faces).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "qualmesh/cad_import.h"
#include "qualmesh/mesher.h"
#include "qualmesh/second_order.h"
#include "test_support.h"

namespace qualmesh {
namespace {

// The unit cube split into 6 tetrahedra around the diagonal (0,0,0)-(1,1,1), positively oriented, with its 12
// boundary triangles (marker = 1 + axis-face index) and the 12 cube edges (marker = 1 + edge index).
TetMesh cube_mesh() {
  TetMesh m;
  for (int i = 0; i < 8; ++i) m.points.push_back({double(i & 1), double((i >> 1) & 1), double((i >> 2) & 1)});
  const int paths[6][2] = {{1, 3}, {1, 5}, {2, 3}, {2, 6}, {4, 5}, {4, 6}};
  for (const auto& p : paths) {
    std::array<Index, 4> t{0, Index(p[0]), Index(p[0] | p[1]), 7};
    const Point3 &a = m.points[t[0]], &b = m.points[t[1]], &c = m.points[t[2]], &d = m.points[t[3]];
    const double ux = b[0] - a[0], uy = b[1] - a[1], uz = b[2] - a[2], vx = c[0] - a[0], vy = c[1] - a[1],
                 vz = c[2] - a[2], wx = d[0] - a[0], wy = d[1] - a[1], wz = d[2] - a[2];
    const double det = ux * (vy * wz - vz * wy) - uy * (vx * wz - vz * wx) + uz * (vx * wy - vy * wx);
    if (det < 0) std::swap(t[1], t[2]);
    m.tets.push_back(t);
  }
  // Boundary faces: every tet face used once.
  std::map<std::array<Index, 3>, int> count;
  for (const auto& t : m.tets)
    for (int k = 0; k < 4; ++k) {
      std::array<Index, 3> f{t[(k + 1) % 4], t[(k + 2) % 4], t[(k + 3) % 4]};
      std::sort(f.begin(), f.end());
      ++count[f];
    }
  for (const auto& [f, n] : count)
    if (n == 1) {
      m.faces.push_back(f);
      m.face_marker.push_back(1);
      m.face_facet.push_back(0);
    }
  for (Index a = 0; a < 8; ++a)
    for (int axis = 0; axis < 3; ++axis)
      if (!(a & (1 << axis))) {
        m.edges.push_back({a, Index(a | (1 << axis))});
        m.edge_marker.push_back(int(m.edges.size()));
      }
  return m;
}

TEST(SecondOrder, MidNodesAreSharedMidpoints) {
  TetMesh m = cube_mesh();
  make_second_order(m);
  ASSERT_TRUE(m.is_second_order());
  // 19 distinct edges in the 6-tet cube: 12 cube edges, 6 face diagonals, 1 body diagonal.
  EXPECT_EQ(m.points.size(), 8u + 19u);
  for (std::size_t t = 0; t < m.tets.size(); ++t)
    for (int k = 0; k < 6; ++k) {
      const Point3& a = m.points[m.tets[t][kTetEdges[k][0]]];
      const Point3& b = m.points[m.tets[t][kTetEdges[k][1]]];
      const Point3& x = m.points[m.tet_mid[t][k]];
      for (int c = 0; c < 3; ++c) EXPECT_DOUBLE_EQ(x[c], 0.5 * (a[c] + b[c]));
    }
  ASSERT_EQ(m.face_mid.size(), m.faces.size());
  ASSERT_EQ(m.edge_mid.size(), m.edges.size());
  for (std::size_t e = 0; e < m.edges.size(); ++e) {
    const Point3& x = m.points[m.edge_mid[e]];
    const Point3& a = m.points[m.edges[e][0]];
    const Point3& b = m.points[m.edges[e][1]];
    for (int c = 0; c < 3; ++c) EXPECT_DOUBLE_EQ(x[c], 0.5 * (a[c] + b[c]));
  }
  // Idempotent.
  make_second_order(m);
  EXPECT_EQ(m.points.size(), 27u);
}

TEST(SecondOrder, StraightTetJacobianIsSixVolumeEverywhere) {
  TetMesh m = cube_mesh();
  make_second_order(m);
  for (std::size_t t = 0; t < m.tets.size(); ++t) {
    const Tet10Jacobian j = tet10_jacobian(m, t);
    EXPECT_NEAR(j.min_det, 1.0, 1e-12);  // each tet has volume 1/6
    EXPECT_NEAR(j.max_det, 1.0, 1e-12);
    EXPECT_NEAR(j.ratio(), 1.0, 1e-12);
  }
}

TEST(SecondOrder, AMidNodePushedThroughTheOppositeFaceInvertsTheElement) {
  TetMesh m;
  m.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  m.tets = {{0, 1, 2, 3}};
  make_second_order(m);
  // Mid node of edge (0,1) moved far beyond the opposite face: the Jacobian turns negative at a corner.
  Point3& x = m.points[m.tet_mid[0][0]];
  x = {0.5, 0.9, 0.9};
  const Tet10Jacobian j = tet10_jacobian(m, 0);
  EXPECT_LT(j.min_det, 0);
  EXPECT_LE(j.ratio(), 0);
}

TEST(SecondOrder, MovesThatWouldInvertAreRelaxedOrRefused) {
  TetMesh m;
  m.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  m.tets = {{0, 1, 2, 3}};
  m.faces = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};  // all on the boundary: nothing to drag along
  make_second_order(m);
  const Index mid01 = m.tet_mid[0][0];
  // A small bulge is fine in full; a huge one is not made in full, and the element stays acceptable.
  NodeMoveReport small = move_nodes_checked(m, {{mid01, {0.5, -0.05, 0}}});
  EXPECT_EQ(small.num_full, 1u);
  EXPECT_EQ(small.num_bad_elements, 0u);
  NodeMoveReport big = move_nodes_checked(m, {{mid01, {0.5, 5, 5}}});
  EXPECT_EQ(big.num_full, 0u);
  EXPECT_EQ(big.num_partial + big.num_refused, 1u);
  EXPECT_GT(big.max_distance_left, 1);
  EXPECT_GE(tet10_jacobian(m, 0).ratio(), NodeMoveOptions{}.min_jacobian_ratio);
  // Linear: a corner moved through the opposite face is refused, the tet keeps a positive volume.
  TetMesh lin;
  lin.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  lin.tets = {{0, 1, 2, 3}};
  lin.faces = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};  // all on the boundary: nothing to drag along
  NodeMoveReport flip = move_nodes_checked(lin, {{3, {0, 0, -1}}});
  EXPECT_EQ(flip.num_full, 0u);
  EXPECT_EQ(flip.num_bad_elements, 0u);
  EXPECT_GT(lin.points[3][2], 0);
}

// Meshes a real CAD part, fits it, and measures each boundary node's distance to its CAD face independently.
void expect_fitted_onto_cad(const std::string& file, bool second_order) {
  const std::string path = test::shared_path("data/cad/" + file);
  QM_REQUIRE_FILE(path);
  const CadModel model = read_cad(path);
  // As `qualmesh mesh` meshes a CAD input (cmd_mesh.cpp): pumped (without pumping the mesh can hold near-flat
  // slivers, part.step: one of four coplanar corners, Jacobian ratio -0.31 once it had mid nodes, which the fit
  // leaves alone as flat elements), under the relaxed rule at the surface's size, with Rule 1 and 2 points put onto
  // the CAD surface as they are inserted.
  MeshOptions options;
  options.encroaching = MeshOptions::Encroaching::Steiner;
  options.sliver_insertion_budget = kCadSliverInsertionBudget;
  options.target_edge_length = model.summary.size_used;
  options.min_split_length = cad_min_split_length(CadOptions{}, options.target_edge_length);
  options.project_to_boundary = [path](int edge, int face, Point3& p) {
    return project_onto_cad(path, CadOptions{}, edge, face, p);
  };
  MeshResult result = mesh_plc(model.plc, options);
  TetMesh& mesh = result.mesh;
  CadFitOptions fit;
  fit.second_order = second_order;
  const CadFitReport report = fit_mesh_to_cad(path, CadOptions{}, mesh, fit);
  // The engine put every corner on the surface: the fit finds none to move but by rounding, and none blocked.
  EXPECT_LT(report.max_offset_before, 1e-6);
  EXPECT_EQ(report.corners.num_partial + report.corners.num_refused, 0u);
  // Every boundary node and mid node whose move was made in full lies on its CAD face within 1e-7 of the diagonal.
  BoundingBox box;
  for (const Point3& p : mesh.points) box.add(p);
  const double diagonal = std::sqrt((box.max[0] - box.min[0]) * (box.max[0] - box.min[0]) +
                                    (box.max[1] - box.min[1]) * (box.max[1] - box.min[1]) +
                                    (box.max[2] - box.min[2]) * (box.max[2] - box.min[2]));
  const std::vector<int> labels = face_labels(mesh);
  std::vector<Point3> points;
  std::vector<int> faces;
  std::set<std::pair<Index, int>> seen;
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    std::vector<Index> nodes(mesh.faces[f].begin(), mesh.faces[f].end());
    if (second_order) nodes.insert(nodes.end(), mesh.face_mid[f].begin(), mesh.face_mid[f].end());
    for (Index v : nodes)
      if (seen.insert({v, labels[f]}).second) {
        points.push_back(mesh.points[v]);
        faces.push_back(labels[f]);
      }
  }
  const std::vector<double> d = distances_to_cad_faces(path, points, faces);
  // A node on a CAD edge lies on the edge's curve, which is within the edge's tolerance of its faces (up to 1e-2 in
  // STEP files): it is judged against the face's tolerance raised to its edges' (CadSummary::node_tolerances), every
  // other node against 1e-7 of the diagonal.
  std::set<Point3> on_edge;
  for (std::size_t e = 0; e < mesh.edges.size(); ++e) {
    for (Index v : mesh.edges[e]) on_edge.insert(mesh.points[v]);
    if (second_order) on_edge.insert(mesh.points[mesh.edge_mid[e]]);
  }
  std::set<Point3> off_nodes;  // a node on a CAD edge is measured against both its faces: counted once
  double worst = 0;
  for (std::size_t i = 0; i < d.size(); ++i) {
    const double allowed = on_edge.count(points[i]) ? model.summary.node_tolerances[faces[i] - 1] : 1e-7 * diagonal;
    worst = std::max(worst, d[i]);
    if (d[i] > allowed) off_nodes.insert(points[i]);
  }
  const std::size_t off = off_nodes.size();
  const std::size_t not_full = report.corners.num_partial + report.corners.num_refused +
                               report.mids.num_partial + report.mids.num_refused;
  EXPECT_LE(off, not_full) << "worst distance " << worst;
  EXPECT_EQ(report.corners.num_bad_elements, 0u);
  if (second_order) {
    // Only moves at the last resort's ratio leave elements below min_jacobian_ratio, and none below its own.
    if (report.mids.num_last_resort == 0) EXPECT_EQ(report.mids.num_bad_elements, 0u);
    for (std::size_t t = 0; t < mesh.tets.size(); ++t)
      EXPECT_GE(tet10_jacobian(mesh, t).ratio(), fit.moves.last_resort_jacobian_ratio) << t;
  }
}

// The mesh's edges are the subsegments of the CAD edges: on the beam (a box), markers 1..12, every node of Edge<e>
// on the box edge it names, and together they cover each edge's length exactly.
TEST(CadEdges, TheBeamsTwelveCadEdgesAreChainsOfMeshEdges) {
  const std::string path = test::source_path("examples/cantilever/beam.step");
  QM_REQUIRE_FILE(path);
  const CadModel model = read_cad(path);
  MeshOptions options;
  options.max_edge_length = 8;
  const MeshResult result = mesh_plc(model.plc, options);
  const TetMesh& mesh = result.mesh;
  ASSERT_EQ(mesh.edges.size(), mesh.edge_marker.size());
  std::map<int, double> length;
  for (std::size_t e = 0; e < mesh.edges.size(); ++e) {
    const Point3& a = mesh.points[mesh.edges[e][0]];
    const Point3& b = mesh.points[mesh.edges[e][1]];
    length[mesh.edge_marker[e]] += std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                                             (a[2] - b[2]) * (a[2] - b[2]));
    int varying = 0;
    for (int c = 0; c < 3; ++c) varying += a[c] != b[c];
    EXPECT_EQ(varying, 1) << "edge " << e << " is not along a box edge";
  }
  ASSERT_EQ(length.size(), 12u);
  EXPECT_EQ(length.begin()->first, 1);
  EXPECT_EQ(length.rbegin()->first, 12);
  int long_edges = 0;
  for (const auto& [marker, total] : length) {
    const bool is_long = std::fabs(total - 100) < 1e-9;
    long_edges += is_long;
    EXPECT_TRUE(is_long || std::fabs(total - 10) < 1e-12) << "Edge" << marker << " length " << total;
  }
  EXPECT_EQ(long_edges, 4);
  // Refined: no mesh edge longer than the size asked for.
  for (const auto& edge : mesh.edges) {
    const Point3& a = mesh.points[edge[0]];
    const Point3& b = mesh.points[edge[1]];
    EXPECT_LE(std::fabs(a[0] - b[0]) + std::fabs(a[1] - b[1]) + std::fabs(a[2] - b[2]), 8 + 1e-9);
  }
}

TEST(CadFit, PartStepLinear) { expect_fitted_onto_cad("part.step", false); }
TEST(CadFit, PartStepSecondOrder) { expect_fitted_onto_cad("part.step", true); }

}  // namespace
}  // namespace qualmesh

namespace qualmesh {
namespace {

// Two tets sharing the face (0,1,2); a third, flat one (0,2,1,3)-like cap lies on top with two boundary faces in the
// same plane: removing it leaves its other two faces as the boundary, same label, outward.
TEST(FlatCaps, AFlatTetWithTwoBoundaryFacesOnOneFaceIsRemovedAndTheBoundaryStaysClosed) {
  TetMesh m;
  // A square (0,0,0)-(1,1,0) split along 0-2 into two tets with apex 4 below (z = -1); on top a flat tet
  // (0,1,2,3) with 3 = (0,1,0): the square's other diagonal 1-3.
  m.points = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.5, 0.5, -1}};
  m.tets = {{0, 2, 1, 4}, {0, 3, 2, 4}, {0, 1, 2, 3}};
  // Orient every tet positively except the flat one, whose volume is 0 either way.
  for (auto& t : m.tets) {
    const Point3 &a = m.points[t[0]], &b = m.points[t[1]], &c = m.points[t[2]], &d = m.points[t[3]];
    const double det = (b[0] - a[0]) * ((c[1] - a[1]) * (d[2] - a[2]) - (c[2] - a[2]) * (d[1] - a[1])) -
                       (b[1] - a[1]) * ((c[0] - a[0]) * (d[2] - a[2]) - (c[2] - a[2]) * (d[0] - a[0])) +
                       (b[2] - a[2]) * ((c[0] - a[0]) * (d[1] - a[1]) - (c[1] - a[1]) * (d[0] - a[0]));
    if (det < 0) std::swap(t[1], t[2]);
  }
  // Boundary: the flat tet's two upper faces (0,1,3) and (1,2,3) (the square split along 1-3), label 7, and the four
  // side faces of the pyramid, label 9.
  m.faces = {{0, 1, 3}, {1, 2, 3}, {0, 4, 1}, {1, 4, 2}, {2, 4, 3}, {3, 4, 0}};
  m.face_marker = {7, 7, 9, 9, 9, 9};
  m.face_facet = {0, 0, 1, 1, 1, 1};
  EXPECT_EQ(remove_flat_boundary_tets(m), 1u);
  ASSERT_EQ(m.tets.size(), 2u);
  ASSERT_EQ(m.faces.size(), 6u);
  // The new boundary on top is the square split along 0-2, label 7, normals up (+z).
  int top = 0;
  for (std::size_t f = 0; f < m.faces.size(); ++f) {
    if (m.face_marker[f] != 7) continue;
    ++top;
    const auto& v = m.faces[f];
    const Point3 &a = m.points[v[0]], &b = m.points[v[1]], &c = m.points[v[2]];
    const double nz = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    EXPECT_GT(nz, 0) << f;
    std::array<Index, 3> s = v;
    std::sort(s.begin(), s.end());
    EXPECT_TRUE(s == (std::array<Index, 3>{0, 1, 2}) || s == (std::array<Index, 3>{0, 2, 3}));
  }
  EXPECT_EQ(top, 2);
  EXPECT_EQ(remove_flat_boundary_tets(m), 0u);
}

}  // namespace
}  // namespace qualmesh

namespace qualmesh {
namespace {

// A boundary corner whose full move would invert its element drags the element's interior corner along, so it still
// reaches its target; a refused move leaves every node bit for bit where it was.
TEST(SecondOrder, AnInteriorNodeIsDraggedAlongAndRefusedMovesChangeNothing) {
  TetMesh m;
  m.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.1, 0.1, 0.3}};  // node 3 interior, just above the face 0-1-2
  m.tets = {{0, 1, 2, 3}};
  m.faces = {{0, 2, 1}};  // only the bottom face is boundary
  // Lift node 0 above node 3: alone it would invert the tet; with node 3 dragged by the same vector it does not.
  const NodeMoveReport r = move_nodes_checked(m, {{0, {0, 0, 0.5}}});
  EXPECT_EQ(r.num_full, 1u);
  EXPECT_EQ(r.num_dragged, 1u);
  EXPECT_EQ(m.points[0], (Point3{0, 0, 0.5}));
  EXPECT_DOUBLE_EQ(m.points[3][2], 0.8);
  // Everything on the boundary: the same kind of move is refused and nothing moves at all.
  TetMesh b;
  b.points = {{0.1, 0.2, 0.3}, {1.1, 0.2, 0.3}, {0.1, 1.2, 0.3}, {0.2, 0.3, 0.6}};
  b.tets = {{0, 1, 2, 3}};
  b.faces = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
  const std::vector<Point3> before = b.points;
  const NodeMoveReport refused = move_nodes_checked(b, {{0, {0.1, 0.2, 5.0}}});
  EXPECT_EQ(refused.num_full + refused.num_partial, 0u);
  EXPECT_EQ(b.points, before);
}

}  // namespace
}  // namespace qualmesh

namespace qualmesh {
namespace {

double six_volume(const TetMesh& m, const std::array<Index, 4>& t) {
  const Point3 &a = m.points[t[0]], &b = m.points[t[1]], &c = m.points[t[2]], &d = m.points[t[3]];
  return (b[0] - a[0]) * ((c[1] - a[1]) * (d[2] - a[2]) - (c[2] - a[2]) * (d[1] - a[1])) -
         (b[1] - a[1]) * ((c[0] - a[0]) * (d[2] - a[2]) - (c[2] - a[2]) * (d[0] - a[0])) +
         (b[2] - a[2]) * ((c[0] - a[0]) * (d[1] - a[1]) - (c[1] - a[1]) * (d[0] - a[0]));
}

// A hexagonal bipyramid: six tets around the axis c-d (c = (0,0,-1), d = (0,0,1)), each a boundary cap (its faces
// (c, p_i, p_i+1) and (d, p_i, p_i+1) on the hull, one label, its free edge c-d inside). remove_boundary_caps takes
// exactly the caps it is asked for (one per neighbourhood), keeps the boundary a closed manifold facing out, and
// the volume drops by the cap's; a cap whose free edge has become a boundary edge is left.
TEST(BoundaryCaps, RemovesTheCapsAskedForAndKeepsTheBoundaryClosedAndOutward) {
  TetMesh m;
  const Index c = 6, d = 7;
  for (int i = 0; i < 6; ++i) m.points.push_back({std::cos(i * M_PI / 3), std::sin(i * M_PI / 3), 0});
  m.points.push_back({0, 0, -1});
  m.points.push_back({0, 0, 1});
  for (Index i = 0; i < 6; ++i) {
    std::array<Index, 4> t{c, d, i, static_cast<Index>((i + 1) % 6)};
    if (six_volume(m, t) < 0) std::swap(t[2], t[3]);
    m.tets.push_back(t);
    const Index j = (i + 1) % 6;
    m.faces.push_back({c, j, i});  // outward below
    m.faces.push_back({d, i, j});  // outward above
    m.face_marker.push_back(3);
    m.face_marker.push_back(3);
    m.face_facet.push_back(0);
    m.face_facet.push_back(0);
  }
  double before = 0;
  for (const auto& t : m.tets) before += six_volume(m, t);
  EXPECT_EQ(remove_boundary_caps(m, [](std::size_t) { return false; }), 0u);
  ASSERT_EQ(m.tets.size(), 6u);
  const double cap = six_volume(m, m.tets[0]);
  EXPECT_EQ(remove_boundary_caps(m, [](std::size_t t) { return t == 0; }), 1u);
  ASSERT_EQ(m.tets.size(), 5u);
  ASSERT_EQ(m.faces.size(), 12u);
  double after = 0;
  for (const auto& t : m.tets) after += six_volume(m, t);
  EXPECT_NEAR(after, before - cap, 1e-12);
  // Closed and manifold: every boundary edge is on exactly two faces, used once each way.
  std::map<std::pair<Index, Index>, int> directed;
  for (const auto& f : m.faces)
    for (int k = 0; k < 3; ++k) ++directed[{f[k], f[(k + 1) % 3]}];
  for (const auto& [e, n] : directed) {
    EXPECT_EQ(n, 1);
    EXPECT_EQ(directed.count({e.second, e.first}), 1u);
  }
  // Outward: the faces' signed volumes add up to the mesh's (divergence theorem, 6V = sum of det(a, b, c)).
  double flux = 0;
  for (const auto& f : m.faces) {
    const Point3 &a = m.points[f[0]], &b = m.points[f[1]], &p = m.points[f[2]];
    flux += a[0] * (b[1] * p[2] - b[2] * p[1]) - a[1] * (b[0] * p[2] - b[2] * p[0]) + a[2] * (b[0] * p[1] - b[1] * p[0]);
  }
  EXPECT_NEAR(flux, after, 1e-12);
  // The free edge c-d is now on the boundary: no cap around it can go any more.
  EXPECT_EQ(remove_boundary_caps(m, [](std::size_t) { return true; }), 0u);
}

// move_nodes_checked names the elements that kept a move from its target.
TEST(BoundaryCaps, BlockingElementsAreReported) {
  TetMesh m;
  m.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  m.tets = {{0, 1, 2, 3}};
  m.faces = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
  make_second_order(m);
  const NodeMoveReport ok = move_nodes_checked(m, {{m.tet_mid[0][0], {0.5, -0.05, 0}}});
  EXPECT_TRUE(ok.blocking_elements.empty());
  const NodeMoveReport big = move_nodes_checked(m, {{m.tet_mid[0][0], {0.5, 5, 5}}});
  EXPECT_EQ(big.blocking_elements, (std::vector<std::size_t>{0}));
}

}  // namespace
}  // namespace qualmesh

namespace qualmesh {
namespace {

double signed_six_volume(const TetMesh& m, std::size_t t) { return six_volume(m, m.tets[t]); }

// Node 0 lifted to z = 0.5 flattens tet A = (0, 1, 2, 3) unless the interior node 3 rises above the plane through
// the new node 0 and nodes 1, 2; dragged by the same 0.5 it would cross the ceiling of tet B = (3, 5, 6, 7) at
// z = 0.5. Only a place found by the search (NodeMoveOptions::optimise_interior) between the two keeps both.
TEST(SecondOrder, TheSearchPlacesAnInteriorNodeWhereDraggingItFails) {
  TetMesh m;
  m.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.3, 0.3, 0.2}, {9, 9, 9}, {-1, -1, 0.5}, {2, -1, 0.5}, {-1, 2, 0.5}};
  m.tets = {{0, 1, 2, 3}, {3, 5, 6, 7}};
  m.faces = {{0, 2, 1}, {5, 6, 7}};  // node 3 is the only interior node (node 4 belongs to nothing)
  const std::vector<double> before{signed_six_volume(m, 0), signed_six_volume(m, 1)};
  NodeMoveOptions no_search;
  no_search.optimise_interior = false;
  TetMesh copy = m;
  const NodeMoveReport without = move_nodes_checked(copy, {{0, {0, 0, 0.5}, {}}}, no_search);
  EXPECT_EQ(without.num_full, 0u);
  const NodeMoveReport r = move_nodes_checked(m, {{0, {0, 0, 0.5}, {}}});
  EXPECT_EQ(r.num_full, 1u);
  EXPECT_EQ(r.num_optimised, 1u);
  EXPECT_EQ(r.num_dragged, 0u);
  EXPECT_EQ(m.points[0], (Point3{0, 0, 0.5}));
  EXPECT_NE(m.points[3], (Point3{0.3, 0.3, 0.2}));
  for (std::size_t t = 0; t < 2; ++t)
    EXPECT_GE(signed_six_volume(m, t), NodeMoveOptions{}.min_volume_fraction * before[t]) << t;
  EXPECT_EQ(r.num_bad_elements, 0u);
}

// A target no element allows is passed over for the first alternative that works (NodeMove::alternatives), and the
// node counts as moved in full: it is on its face or edge, where the alternatives are.
TEST(SecondOrder, AnAlternativeIsTakenWhenTheTargetIsRefused) {
  TetMesh b;
  b.points = {{0.1, 0.2, 0.3}, {1.1, 0.2, 0.3}, {0.1, 1.2, 0.3}, {0.2, 0.3, 0.6}};
  b.tets = {{0, 1, 2, 3}};
  b.faces = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
  const NodeMoveReport r =
      move_nodes_checked(b, {{0, {0.1, 0.2, 5.0}, {{0.1, 0.2, 4.0}, {0.0, 0.1, 0.3}, {0.05, 0.15, 0.3}}}});
  EXPECT_EQ(r.num_full, 1u);
  EXPECT_EQ(r.num_alternative, 1u);
  EXPECT_EQ(b.points[0], (Point3{0.0, 0.1, 0.3}));  // the first acceptable one, in order
  EXPECT_EQ(r.max_distance_left, 0);
  EXPECT_GT(signed_six_volume(b, 0), 0);
}

// A mid node whose full move leaves its element's Jacobian ratio between last_resort_jacobian_ratio and
// min_jacobian_ratio is relaxed part of the way without the last resort, and made in full with it.
TEST(SecondOrder, TheLastResortRatioPutsTheNodeOnItsTargetWithAValidElement) {
  TetMesh m;
  m.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  m.tets = {{0, 1, 2, 3}};
  m.faces = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};  // all on the boundary: nothing to drag along
  make_second_order(m);
  const Index mid = m.tet_mid[0][0];  // edge (0, 1), pushed into the element along (0, 1, 1)
  const auto ratio_at = [&](double s) {
    TetMesh c = m;
    c.points[mid] = {0.5, s, s};
    return tet10_jacobian(c, 0).ratio();
  };
  double lo = 0, hi = 1;  // ratio_at(lo) >= 0.05 > ratio_at(hi)
  ASSERT_LT(ratio_at(hi), 0.05);
  for (int i = 0; i < 60; ++i) (ratio_at(0.5 * (lo + hi)) >= 0.05 ? lo : hi) = 0.5 * (lo + hi);
  const Point3 target{0.5, lo, lo};
  ASSERT_GT(ratio_at(lo), 0.04);
  ASSERT_LT(ratio_at(lo), 0.1);
  NodeMoveOptions strict;
  strict.last_resort_jacobian_ratio = 0;
  TetMesh copy = m;
  const NodeMoveReport relaxed = move_nodes_checked(copy, {{mid, target, {}}}, strict);
  EXPECT_EQ(relaxed.num_full, 0u);
  EXPECT_GE(tet10_jacobian(copy, 0).ratio(), strict.min_jacobian_ratio);
  const NodeMoveReport r = move_nodes_checked(m, {{mid, target, {}}});
  EXPECT_EQ(r.num_full, 1u);
  EXPECT_EQ(r.num_last_resort, 1u);
  EXPECT_EQ(m.points[mid], target);
  EXPECT_GE(tet10_jacobian(m, 0).ratio(), NodeMoveOptions{}.last_resort_jacobian_ratio);
  EXPECT_EQ(r.num_bad_elements, 1u);  // below min_jacobian_ratio, and counted so
}

}  // namespace
}  // namespace qualmesh

namespace qualmesh {
namespace {

// Six times the mesh's volume, each tetrahedron checked positively oriented.
double positive_six_volume(const TetMesh& m) {
  double sum = 0;
  for (std::size_t t = 0; t < m.tets.size(); ++t) {
    EXPECT_GT(signed_six_volume(m, t), 0) << t;
    sum += signed_six_volume(m, t);
  }
  return sum;
}

// A cap across a CAD edge (faces 0-1-2 and 0-1-3 with two labels, the interior edge 2-3): its interior edge is split
// at its midpoint, both tetrahedra around it are halved, orientation, volume and faces are kept; the same cap with
// one label on both faces is remove_boundary_caps's and is left.
TEST(CapEdges, TheInteriorEdgeOfACapAcrossACadEdgeIsSplit) {
  TetMesh m;
  m.points = {{0, 0, 0}, {1, 0, 0}, {0.3, 1, 0.1}, {0.3, 0.1, 1}, {1.2, 1.2, 1.2}};
  m.tets = {{0, 1, 2, 3}, {1, 2, 3, 4}};
  m.tet_region = {1, 1};
  m.faces = {{0, 2, 1}, {0, 1, 3}};
  m.face_marker = {7, 8};
  const double before = signed_six_volume(m, 0) + signed_six_volume(m, 1);
  ASSERT_GT(signed_six_volume(m, 0), 0);
  ASSERT_GT(signed_six_volume(m, 1), 0);
  TetMesh same = m;
  same.face_marker = {7, 7};
  EXPECT_EQ(split_cap_interior_edges(same, [](std::size_t) { return true; }), 0u);
  EXPECT_EQ(same.tets.size(), 2u);
  EXPECT_EQ(split_cap_interior_edges(m, [](std::size_t t) { return t == 0; }), 1u);
  ASSERT_EQ(m.points.size(), 6u);
  EXPECT_EQ(m.points[5], (Point3{0.3, 0.55, 0.55}));
  ASSERT_EQ(m.tets.size(), 4u);
  EXPECT_EQ(m.tet_region, (std::vector<int>{1, 1, 1, 1}));
  EXPECT_NEAR(positive_six_volume(m), before, 1e-12);
  EXPECT_EQ(m.faces.size(), 2u);
}

// A boundary triangle a-c-b with a 171-degree corner at c (a straight CAD edge running into an arc at c, as on
// part.step's Face20): the edge a-b opposite that corner is split at its midpoint even though it is a CAD edge
// (TetMesh::edges), so the tetrahedron, the face and the edge entry each become two, with their labels, the
// orientation and the volume kept. A tetrahedron not selected, or whose faces have no corner above the bound, is
// left alone.
TEST(FlatFaceCorners, TheEdgeOppositeAFlatCornerIsSplit) {
  TetMesh m;
  m.points = {{0, 0, 0}, {2, 0, 0}, {4, -0.31, 0}, {2, -1, -2}};
  m.tets = {{0, 1, 2, 3}};
  if (signed_six_volume(m, 0) < 0) std::swap(m.tets[0][0], m.tets[0][1]);
  ASSERT_GT(signed_six_volume(m, 0), 0);
  m.tet_region = {1};
  m.faces = {{0, 1, 2}};
  m.face_marker = {20};
  m.edges = {{0, 1}, {1, 2}, {0, 2}};
  m.edge_marker = {3, 4, 5};
  const double before = signed_six_volume(m, 0);
  TetMesh unselected = m;
  EXPECT_EQ(split_flat_face_corners(unselected, [](std::size_t) { return false; }), 0u);
  TetMesh sharper = m;
  EXPECT_EQ(split_flat_face_corners(sharper, [](std::size_t) { return true; }, 175), 0u);  // 171 < 175
  EXPECT_EQ(sharper.points.size(), 4u);
  EXPECT_EQ(split_flat_face_corners(m, [](std::size_t) { return true; }), 1u);
  ASSERT_EQ(m.points.size(), 5u);
  EXPECT_EQ(m.points[4], (Point3{2, -0.155, 0}));
  ASSERT_EQ(m.tets.size(), 2u);
  EXPECT_EQ(m.tet_region, (std::vector<int>{1, 1}));
  EXPECT_NEAR(positive_six_volume(m), before, 1e-12);
  ASSERT_EQ(m.faces.size(), 2u);
  EXPECT_EQ(m.face_marker, (std::vector<int>{20, 20}));
  for (const auto& f : m.faces) EXPECT_EQ(std::count(f.begin(), f.end(), Index(4)), 1);
  ASSERT_EQ(m.edges.size(), 4u);
  EXPECT_EQ(m.edge_marker, (std::vector<int>{3, 4, 5, 5}));
  EXPECT_EQ(m.edges[2], (std::array<Index, 2>{0, 4}));
  EXPECT_EQ(m.edges[3], (std::array<Index, 2>{4, 2}));
}

}  // namespace
}  // namespace qualmesh
