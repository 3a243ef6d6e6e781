// How big a mesh the input asks for, before any refinement (issue 18 item 3: "an estimate of the element count from
// the size field and the local feature size before refinement starts"). The CLI refuses a run whose estimate is over
// the memory budget (mesh_limits.cpp) instead of letting it grow until it is killed (a slab 1e-4 thick).
#pragma once

#include <cstddef>

#include "qualmesh/plc.h"

namespace qualmesh {

struct FeatureSizeEstimate {
  // The integral over the PLC's facets of dA / f(x)^2, f the local feature size (Section 2 of the paper): a
  // surface of that area meshed with triangles of edge f has about this many of them, times 4 / sqrt(3).
  double surface_integral = 0;
  // The boundary triangles and tetrahedra the refinement is expected to make, at least (see the calibration in
  // size_estimate.cpp): the refinement's boundary edges are not longer than about the local feature size, since
  // Rules 1 and 2 split every subsegment and subfacet whose diametral ball holds another input element.
  double boundary_triangles = 0;
  double tets = 0;
  std::size_t samples = 0;  // local feature size queries made
};

// Samples f over the facets (each facet triangle split into pieces, at most about `max_samples` queries in all;
// a surface with more triangles than that is sampled at a deterministic stride and scaled by its area). Linear in
// the number of facet triangles, n log n with the bounding-volume tree; deterministic.
FeatureSizeEstimate estimate_from_feature_size(const Plc& plc, std::size_t max_samples = 8192);

}  // namespace qualmesh
