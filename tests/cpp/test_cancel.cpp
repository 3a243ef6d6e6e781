// MeshOptions::cancel (issue 18 item 3): the library's cancellation callback, which --time-limit, the memory budget
// and the FreeCAD task panel use. Polled every 64 insertions and in the pumping passes; once it says stop, mesh_plc
// returns MeshStatus::Cancelled with the mesh as it stands. A callback that never says stop changes nothing.
#include <gtest/gtest.h>

#include <cmath>

#include "qualmesh/mesher.h"
#include "sample_meshes.h"

namespace qualmesh {
namespace {

TEST(Cancel, StopsRefinementAndReportsCancelled) {
  const Plc plc = unit_cube_plc();
  MeshOptions options;
  options.max_edge_length = 0.05;
  std::size_t calls = 0;
  options.cancel = [&calls] { return ++calls >= 10; };
  const MeshResult r = mesh_plc(plc, options);
  EXPECT_EQ(r.status, MeshStatus::Cancelled);
  EXPECT_EQ(calls, 10u);  // not polled again once it said stop
  EXPECT_LT(r.mesh.points.size(), 2000u);
}

TEST(Cancel, ACallbackThatNeverStopsChangesNothing) {
  const Plc plc = unit_cube_plc();
  MeshOptions options;
  options.max_edge_length = 0.2;
  const MeshResult plain = mesh_plc(plc, options);
  std::size_t calls = 0;
  options.cancel = [&calls] { return ++calls, false; };
  const MeshResult polled = mesh_plc(plc, options);
  EXPECT_GT(calls, 0u);
  EXPECT_EQ(polled.status, MeshStatus::Ok);
  EXPECT_EQ(polled.mesh.points, plain.mesh.points);
  EXPECT_EQ(polled.mesh.tets, plain.mesh.tets);
  EXPECT_EQ(polled.mesh.weights, plain.mesh.weights);
}

TEST(Cancel, BeforeTheInputIsTriangulatedThrows) {
  // 201 input vertices (a cone over a 200-gon, no facets needed for the first stage), cancelled at the first poll.
  MeshOptions options;
  options.cancel = [] { return true; };
  Plc big;
  for (int i = 0; i < 200; ++i) big.vertices.push_back({std::cos(i * 0.0314159), std::sin(i * 0.0314159), 0.0});
  big.vertices.push_back({0, 0, 1});
  EXPECT_THROW(mesh_plc(big, options), MeshCancelled);
}

}  // namespace
}  // namespace qualmesh
