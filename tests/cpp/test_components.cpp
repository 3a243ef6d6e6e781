// Tests of separate closed surfaces meshed one by one (core/src/refine/components.h). Inputs are boxes built here:
// two boxes apart, a box inside a hollow box (a cavity's wall inside its solid's outer wall), a box inside another
// as an inclusion, and two boxes touching without shared vertices. Properties asserted:
//   - separation: two boxes a gap apart are two components, each facet mapped back to its input facet;
//   - the merged mesh is the two boxes' meshes: the same counts as each meshed alone, whatever the gap (a box
//     meshed next to another 0.01 away needs no node more), conforming to the whole input (check_mesh: volume,
//     every facet covered), each box's region attribute on its tets;
//   - nesting keeps the input whole: a hollow box and an inclusion are one mesh with the right volume;
//   - meshed_volumes_meet: false for boxes apart, true for a box inside another's volume and for boxes touching.
#include <gtest/gtest.h>

#include <cmath>

#include "qualmesh/mesh_check.h"
#include "qualmesh/mesher.h"
#include "refine/components.h"

namespace {

using qualmesh::Index;
using qualmesh::Plc;
using qualmesh::Point3;

// Appends the box [lo, hi] to `plc`: 8 vertices, 6 quad facets with markers first_marker.., and a region seed at
// its centre with `attribute` (none for 0; a hole seed for -1).
void add_box(Plc& plc, const Point3& lo, const Point3& hi, int first_marker, int attribute) {
  const Index base = Index(plc.vertices.size());
  for (int i = 0; i < 8; ++i)
    plc.vertices.push_back({i & 1 ? hi[0] : lo[0], (i >> 1) & 1 ? hi[1] : lo[1], (i >> 2) & 1 ? hi[2] : lo[2]});
  const int quads[6][4] = {{0, 2, 6, 4}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 5, 7, 6}};
  for (int f = 0; f < 6; ++f) {
    qualmesh::Facet facet;
    facet.polygons.push_back({base + Index(quads[f][0]), base + Index(quads[f][1]), base + Index(quads[f][2]),
                              base + Index(quads[f][3])});
    facet.marker = first_marker + f;
    plc.facets.push_back(facet);
  }
  const Point3 centre{(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2};
  if (attribute > 0) plc.regions.push_back({centre, attribute, 0});
  if (attribute < 0) plc.holes.push_back(centre);
}

qualmesh::MeshOptions options() {
  qualmesh::MeshOptions o;
  o.max_edge_length = 0.4;
  return o;
}

void expect_conforming(const qualmesh::MeshResult& r, const Plc& plc, double volume) {
  ASSERT_EQ(r.status, qualmesh::MeshStatus::Ok);
  const qualmesh::CheckReport c = qualmesh::check_mesh(r.mesh, &plc);
  EXPECT_EQ(c.num_nonpositive_tets + c.num_folded_faces + c.num_overshared_faces, 0u);
  EXPECT_NEAR(c.mesh_volume, volume, 1e-9 * volume);
  EXPECT_EQ(c.num_miscovered_facets, 0u);
  EXPECT_EQ(c.num_faces_off_input, 0u);
  ASSERT_EQ(r.mesh.face_facet.size(), r.mesh.faces.size());
  for (std::size_t f = 0; f < r.mesh.faces.size(); ++f) {
    // The face lies in its facet's plane (the facet index is the input's, not the component's).
    const int facet = r.mesh.face_facet[f];
    ASSERT_GE(facet, 0);
    const auto& loop = plc.facets[facet].polygons[0];
    for (Index v : r.mesh.faces[f]) {
      const Point3& p = r.mesh.points[v];
      int same = 0;
      for (int axis = 0; axis < 3; ++axis) {
        bool all = true;
        for (Index q : loop) all = all && plc.vertices[q][axis] == p[axis];
        same += all;
      }
      EXPECT_EQ(same, 1) << "face " << f << " off facet " << facet;
    }
  }
}

TEST(Components, TwoBoxesApartAreMeshedOneByOne) {
  for (double gap : {0.5, 0.01}) {
    Plc both;
    add_box(both, {0, 0, 0}, {1, 1, 1}, 1, 1);
    add_box(both, {1 + gap, 0, 0}, {2 + gap, 1, 1}, 7, 2);
    const auto parts = qualmesh::detail::separate_components(both);
    ASSERT_EQ(parts.size(), 2u) << gap;
    EXPECT_EQ(parts[0].facets, (std::vector<Index>{0, 1, 2, 3, 4, 5}));
    EXPECT_EQ(parts[1].facets, (std::vector<Index>{6, 7, 8, 9, 10, 11}));
    EXPECT_EQ(parts[1].plc.regions.size(), 2u) << "every seed goes to every component";

    Plc first, second;
    add_box(first, {0, 0, 0}, {1, 1, 1}, 1, 1);
    add_box(second, {1 + gap, 0, 0}, {2 + gap, 1, 1}, 7, 2);
    const auto r = qualmesh::mesh_plc(both, options());
    const auto r1 = qualmesh::mesh_plc(first, options());
    const auto r2 = qualmesh::mesh_plc(second, options());
    expect_conforming(r, both, 2.0);
    EXPECT_EQ(r.mesh.points.size(), r1.mesh.points.size() + r2.mesh.points.size()) << gap;
    EXPECT_EQ(r.mesh.tets.size(), r1.mesh.tets.size() + r2.mesh.tets.size()) << gap;
    EXPECT_EQ(r.stats.num_tets, r.mesh.tets.size());
    EXPECT_EQ(r.stats.min_dihedral_deg, std::min(r1.stats.min_dihedral_deg, r2.stats.min_dihedral_deg));
    ASSERT_EQ(r.mesh.tet_region.size(), r.mesh.tets.size());
    for (std::size_t t = 0; t < r.mesh.tets.size(); ++t) {
      double x = 0;
      for (Index v : r.mesh.tets[t]) x += r.mesh.points[v][0] / 4;
      EXPECT_EQ(r.mesh.tet_region[t], x < 1 + gap / 2 ? 1 : 2) << t;
    }
  }
}

TEST(Components, NestedBoxesAreMeshedWhole) {
  Plc hollow;
  add_box(hollow, {0, 0, 0}, {3, 3, 3}, 1, 0);
  add_box(hollow, {1, 1, 1}, {2, 2, 2}, 7, -1);  // the cavity
  EXPECT_TRUE(qualmesh::detail::separate_components(hollow).empty());
  expect_conforming(qualmesh::mesh_plc(hollow, options()), hollow, 26.0);

  Plc inclusion;
  add_box(inclusion, {0, 0, 0}, {3, 3, 3}, 1, 1);
  add_box(inclusion, {1, 1, 1}, {2, 2, 2}, 7, 2);
  inclusion.regions[0].point = {0.5, 0.5, 0.5};  // the host's seed outside the inclusion
  EXPECT_TRUE(qualmesh::detail::separate_components(inclusion).empty());
  const auto r = qualmesh::mesh_plc(inclusion, options());
  expect_conforming(r, inclusion, 27.0);
  std::size_t inner = 0;
  for (int region : r.mesh.tet_region) inner += region == 2;
  EXPECT_GT(inner, 0u);
}

TEST(Components, MeshedVolumesMeet) {
  Plc small, big, apart, touching;
  add_box(small, {1, 1, 1}, {2, 2, 2}, 1, 0);
  add_box(big, {0, 0, 0}, {3, 3, 3}, 1, 0);
  add_box(apart, {4, 0, 0}, {5, 1, 1}, 1, 0);
  add_box(touching, {3, 0, 0}, {4, 1, 1}, 1, 0);  // on big's face x = 3, no vertex shared
  const auto ms = qualmesh::mesh_plc(small, options()), mb = qualmesh::mesh_plc(big, options()),
             ma = qualmesh::mesh_plc(apart, options()), mt = qualmesh::mesh_plc(touching, options());
  EXPECT_FALSE(qualmesh::detail::meshed_volumes_meet({&mb.mesh, &ma.mesh}));
  EXPECT_FALSE(qualmesh::detail::meshed_volumes_meet({&ms.mesh, &ma.mesh}));
  EXPECT_TRUE(qualmesh::detail::meshed_volumes_meet({&ms.mesh, &mb.mesh}));
  EXPECT_TRUE(qualmesh::detail::meshed_volumes_meet({&ma.mesh, &mb.mesh, &ms.mesh}));
  EXPECT_TRUE(qualmesh::detail::meshed_volumes_meet({&mb.mesh, &mt.mesh}));
}

}  // namespace
