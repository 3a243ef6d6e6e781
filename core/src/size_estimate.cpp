// The mesh size an input asks for, from the local feature size alone (size_estimate.h). Beyond the paper, which
// bounds the output size by the integral of dV / f^3 (Theorem 7.4) without constants: this estimates the boundary's
// share, which the refinement cannot avoid. Rules 1 and 2 split every subsegment and subfacet whose diametral ball
// holds a vertex of another input element, so the boundary edges end up no longer than about f; a surface of area
// dA then carries about (4 / sqrt 3) dA / f^2 triangles, and the tetrahedra standing on them come on top.
//
// Calibration (`qualmesh mesh MODEL -v --no-improve`, the paper's rule, no size field): tets against the integral
// I = integral dA / f^2 that this file computes (8192 samples).
//   slabs 1 x 1 x t, t = 0.03, 0.01, 0.003:   I 2.5e3, 2.1e4, 2.2e5;  tets 3581, 31491, 352464  (1.4-1.6 I;
//                                              boundary faces 0.94-1.0 I)
//   ../shared/data/plc: joint 5.8e3 -> 11468, fandisk 2.2e4 -> 106277, elephant.off 1e4 -> 63258, anchor 8.4e3 ->
//   72664, lever 2.4e4 -> 162296, t13_data 1.5e4 -> 33723, example.poly 3.6e2 -> 24067   (2-12 I)
// So tets >= 0.5 I on every run above a thousand tets; below that a mesh may be coarser than f (slab t = 0.1: I 280,
// 96 tets; wedge-1.smesh: 350, 3 tets, its 1-degree angle exempt from splitting), where the estimate refuses nothing.
// No file of ../shared/data/plc or ../shared/data/cad is estimated above 1e5 tets (U_Joint_2.stp: 2e4; it meshes
// with about 8e5), so no model that meshes is refused; the slab 1e-4 thick gets I = 2e8, 1e8 tets, refused.
#include "qualmesh/size_estimate.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "local_feature_size.h"

namespace qualmesh {

namespace {

// Boundary triangles per unit of the integral dA / f^2, and tetrahedra per boundary triangle, at least: below the
// least ratios measured (this file's header; test_degenerate_geometry.py keeps the slabs' ratios in check).
constexpr double kTrianglesPerIntegral = 0.5;
constexpr double kTetsPerBoundaryTriangle = 1.0;
constexpr int kMaxLevel = 6;  // a facet triangle is split into at most 4^6 pieces

Point3 lerp3(const Point3& a, const Point3& b, const Point3& c, double u, double v) {
  const double w = 1 - u - v;
  return {w * a[0] + u * b[0] + v * c[0], w * a[1] + u * b[1] + v * c[1], w * a[2] + u * b[2] + v * c[2]};
}

double triangle_area(const Point3& a, const Point3& b, const Point3& c) {
  const double ux = b[0] - a[0], uy = b[1] - a[1], uz = b[2] - a[2];
  const double vx = c[0] - a[0], vy = c[1] - a[1], vz = c[2] - a[2];
  const double x = uy * vz - uz * vy, y = uz * vx - ux * vz, z = ux * vy - uy * vx;
  return 0.5 * std::sqrt(x * x + y * y + z * z);
}

}  // namespace

FeatureSizeEstimate estimate_from_feature_size(const Plc& plc, std::size_t max_samples) {
  FeatureSizeEstimate out;
  const auto triangles = plc_facet_triangles(plc);
  std::vector<std::array<Index, 3>> all;
  for (const auto& facet : triangles) all.insert(all.end(), facet.begin(), facet.end());
  if (all.empty() || max_samples == 0) return out;
  const LocalFeatureSize lfs(plc, triangles);
  double total_area = 0;
  for (const auto& t : all) total_area += triangle_area(plc.vertices[t[0]], plc.vertices[t[1]], plc.vertices[t[2]]);
  if (!(total_area > 0)) return out;
  // More triangles than samples: every stride-th triangle, its centroid only, scaled by area at the end.
  const std::size_t stride = std::max<std::size_t>(1, (all.size() + max_samples - 1) / max_samples);
  double sampled_area = 0, integral = 0;
  for (std::size_t i = 0; i < all.size(); i += stride) {
    const Point3 &a = plc.vertices[all[i][0]], &b = plc.vertices[all[i][1]], &c = plc.vertices[all[i][2]];
    const double area = triangle_area(a, b, c);
    if (!(area > 0)) continue;
    sampled_area += area;
    // Pieces in proportion to the triangle's share of the area: n x n sub-triangles of a regular split.
    int n = 1;
    if (stride == 1) {
      const double share = double(max_samples) * area / total_area;
      n = std::clamp(int(std::sqrt(std::max(share, 1.0))), 1, 1 << kMaxLevel);
    }
    const double piece = area / double(n * n);
    for (int r = 0; r < n; ++r)
      for (int s = 0; s + r < n; ++s) {
        // The upward sub-triangle (r, s) and, where there is one, the downward one beside it; their centroids.
        const double u0 = (r + 1.0 / 3.0) / n, v0 = (s + 1.0 / 3.0) / n;
        const double f0 = lfs(lerp3(a, b, c, u0, v0));
        ++out.samples;
        if (f0 > 0 && std::isfinite(f0)) integral += piece / (f0 * f0);
        if (r + s + 1 < n) {
          const double f1 = lfs(lerp3(a, b, c, (r + 2.0 / 3.0) / n, (s + 2.0 / 3.0) / n));
          ++out.samples;
          if (f1 > 0 && std::isfinite(f1)) integral += piece / (f1 * f1);
        }
      }
  }
  if (!(sampled_area > 0)) return out;
  out.surface_integral = integral * total_area / sampled_area;
  out.boundary_triangles = kTrianglesPerIntegral * out.surface_integral;
  out.tets = kTetsPerBoundaryTriangle * out.boundary_triangles;
  return out;
}

}  // namespace qualmesh
