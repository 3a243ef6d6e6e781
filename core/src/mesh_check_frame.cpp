// The mesh checker's local frame (issue 18 item 5): the reference side of check_mesh (facet planes, projected
// areas, enclosed volume, point-on-facet tests) works on coordinates relative to the centre of the input's bounding
// box, so that a model far from the origin checks as it does at the origin. In absolute coordinates a unit cube at
// 1e9 has facet areas (cross products of 1e9-sized coordinates) and plane offsets (n . x ~ 1e9) that cancel to
// nothing: it "enclosed 0", and joint.off at 1e6 "enclosed 4.45" instead of 0.3595. Shifting costs one rounding of
// each coordinate (exact when the point and the centre are within a factor of 2 of each other, Sterbenz), which is
// below the half ulp the coordinate already carries; the distance tolerance gets a term for that (2 to 4 ulps of the
// largest absolute coordinate), so that a tolerance relative to the model's size alone cannot be smaller than the
// spacing of the doubles where the model lies.
#include <algorithm>
#include <cmath>
#include <limits>

#include "mesh_check_internal.h"

namespace qualmesh::check {

LocalFrame make_local_frame(const Plc& plc, const std::vector<Point3>& mesh_points) {
  BoundingBox box = bounding_box(plc);
  if (box.empty()) {
    for (const Point3& p : mesh_points) box.add(p);
  }
  LocalFrame frame;
  if (box.empty()) return frame;
  for (int k = 0; k < 3; ++k) {
    frame.origin[k] = box.min[k] / 2 + box.max[k] / 2;  // halves first: no overflow near the largest doubles
    frame.max_abs_coordinate = std::max({frame.max_abs_coordinate, std::fabs(box.min[k]), std::fabs(box.max[k])});
  }
  return frame;
}

Point3 LocalFrame::local(const Point3& p) const {
  return {p[0] - origin[0], p[1] - origin[1], p[2] - origin[2]};
}

std::vector<Point3> LocalFrame::local(const std::vector<Point3>& points) const {
  std::vector<Point3> out;
  out.reserve(points.size());
  for (const Point3& p : points) out.push_back(local(p));
  return out;
}

Plc LocalFrame::local(const Plc& plc) const {
  Plc out = plc;
  out.vertices = local(plc.vertices);
  out.holes = local(plc.holes);
  for (Facet& f : out.facets) f.holes = local(f.holes);
  for (RegionSeed& r : out.regions) r.point = local(r.point);
  return out;
}

double LocalFrame::position_tolerance() const {
  return 2 * std::numeric_limits<double>::epsilon() * max_abs_coordinate;
}

}  // namespace qualmesh::check
