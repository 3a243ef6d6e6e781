// The checker's local regularity test (mesh_check.h, CheckReport::num_non_regular_faces): the weighted Delaunay
// property of the paper (Section 3.1: a triangulation is regular when every tetrahedron's orthosphere is further
// than orthogonal from every other weighted vertex) tested across each face shared by two tetrahedra. Lifting the
// weighted points to (x, |x|^2 - w), a tetrahedron t and the opposite vertex v across one of its faces are locally
// regular when v lifts on or above the hyperplane through t's lifted vertices; the sign of that 5x5 determinant is
// CGAL's power_side_of_oriented_power_sphere_3, exact on double input (Epick: interval filter, exact fallback).
// The test is symmetric in the two tetrahedra of a face, so one test per face suffices.
// With all weights zero it is the empty-circumsphere (Delaunay) test.
#include <algorithm>

#include "cgal_types.h"
#include "mesh_check_internal.h"

namespace qualmesh::check {

std::vector<std::size_t> find_non_regular(const std::vector<Point3>& points, const std::vector<double>& weights,
                                          const std::vector<RegularityTest>& tests) {
  using detail::Kernel;
  using detail::KWeightedPoint3;
  const Kernel kernel;
  const auto orientation = kernel.orientation_3_object();
  const auto power_side = kernel.power_side_of_oriented_power_sphere_3_object();
  const auto weighted = [&](Index i) {
    return KWeightedPoint3(detail::to_kpoint(points[i]), weights.empty() ? 0.0 : weights[i]);
  };
  std::vector<std::size_t> violations;
  for (std::size_t k = 0; k < tests.size(); ++k) {
    const RegularityTest& test = tests[k];
    KWeightedPoint3 p = weighted(test.tet[0]), q = weighted(test.tet[1]);
    const KWeightedPoint3 r = weighted(test.tet[2]), s = weighted(test.tet[3]);
    const CGAL::Orientation o = orientation(p.point(), q.point(), r.point(), s.point());
    if (o == CGAL::COPLANAR) continue;
    if (o == CGAL::NEGATIVE) std::swap(p, q);  // the predicate wants a positively oriented tetrahedron
    // ON_POSITIVE_SIDE: the vertex lies inside the orthosphere's orthogonality sphere (closer than orthogonal).
    if (power_side(p, q, r, s, weighted(test.vertex)) == CGAL::ON_POSITIVE_SIDE) violations.push_back(k);
  }
  return violations;
}

}  // namespace qualmesh::check
