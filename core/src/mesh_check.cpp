// check_mesh: re-checks a tetrahedral mesh from scratch (DESIGN.md "How we know it works").
//  1. Every tetrahedron: indices valid and distinct, signed volume > 0, quality figures (quality.h).
//  2. Faces: the four faces of every tetrahedron are sorted and grouped. A face of one tetrahedron is on the hull;
//     of two, interior (the two opposite vertices must lie on opposite sides, else the tetrahedra overlap); of more,
//     a defect. Faces of two tetrahedra of different regions are boundary faces too (internal facets).
//  3. Weighted Delaunay (regular) property, locally: across every face of two tetrahedra, the vertex of one opposite
//     the face against the other's orthosphere, by the exact power test (mesh_check_regularity.cpp).
//  4. With a reference PLC: every boundary face must lie on an input facet (its three vertices within tolerance of
//     the facet's plane, its centroid inside the facet's region), the faces on each facet must cover its area,
//     and the mesh volume must equal the volume the input encloses (mesh_check_reference.cpp). A facet whose
//     vertices lie up to d off its plane (flat only to validate_plc's tolerance; d is its "flatness") widens these
//     tests by 2 d: a face within 2 d of the plane lies on it; volume and area may differ by 2 d times its area and
//     perimeter. This part works relative to the input's bounding-box centre, with a distance tolerance of the
//     model's size and position (mesh_check_frame.cpp), so that a model far from the origin checks as it does at
//     the origin.
// Facet candidates for a face are found through a uniform grid over the facets' bounding boxes.
#include "qualmesh/mesh_check.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

#include "mesh_check_internal.h"
#include "qualmesh/quality.h"
#include "vec3.h"

namespace qualmesh {
namespace {

using check::FacetGeometry;

struct FaceUse {
  std::array<Index, 3> key;  // sorted vertex ids
  Index tet;
  Index opposite;            // the tet's fourth vertex
};

class ProblemList {
 public:
  ProblemList(CheckReport& report, std::size_t max) : report_(report), max_(max) {}
  void add(const std::string& text) {
    ++report_.num_problems;
    if (report_.problems.size() < max_) report_.problems.push_back(text);
  }

 private:
  CheckReport& report_;
  std::size_t max_;
};

std::string face_name(const std::array<Index, 3>& f) {
  return "face (" + std::to_string(f[0]) + ", " + std::to_string(f[1]) + ", " + std::to_string(f[2]) + ")";
}

std::string number(double value) {
  char buffer[40];
  std::snprintf(buffer, sizeof buffer, "%.6g", value);
  return buffer;
}

using namespace vec3;

// Uniform grid over the facets' bounding boxes, about two cells per facet.
class FacetGrid {
 public:
  FacetGrid(const std::vector<FacetGeometry>& facets, double margin) {
    for (const auto& f : facets) {
      if (!f.degenerate) {
        box_.add(f.box.min);
        box_.add(f.box.max);
      }
    }
    if (box_.empty()) return;
    for (int k = 0; k < 3; ++k) {
      box_.min[k] -= margin;
      box_.max[k] += margin;
    }
    const double target = std::max<double>(1, 2.0 * static_cast<double>(facets.size()));
    const double volume = (box_.max[0] - box_.min[0]) * (box_.max[1] - box_.min[1]) * (box_.max[2] - box_.min[2]);
    const double cell = std::cbrt(volume / target);
    for (int k = 0; k < 3; ++k) {
      const double extent = box_.max[k] - box_.min[k];
      dims_[k] = cell > 0 ? std::clamp(static_cast<int>(extent / cell) + 1, 1, 512) : 1;
      size_[k] = extent / dims_[k];
    }
    cells_.resize(static_cast<std::size_t>(dims_[0]) * dims_[1] * dims_[2]);
    for (std::size_t f = 0; f < facets.size(); ++f) {
      if (facets[f].degenerate) continue;
      std::array<int, 3> lo, hi;
      for (int k = 0; k < 3; ++k) {
        lo[k] = coordinate(facets[f].box.min[k] - margin, k);
        hi[k] = coordinate(facets[f].box.max[k] + margin, k);
      }
      for (int i = lo[0]; i <= hi[0]; ++i)
        for (int j = lo[1]; j <= hi[1]; ++j)
          for (int l = lo[2]; l <= hi[2]; ++l) cells_[index(i, j, l)].push_back(static_cast<Index>(f));
    }
  }

  // Facets whose (inflated) box may contain p.
  const std::vector<Index>& candidates(const Point3& p) const {
    static const std::vector<Index> none;
    if (cells_.empty()) return none;
    for (int k = 0; k < 3; ++k) {
      if (p[k] < box_.min[k] || p[k] > box_.max[k]) return none;
    }
    return cells_[index(coordinate(p[0], 0), coordinate(p[1], 1), coordinate(p[2], 2))];
  }

 private:
  int coordinate(double x, int k) const {
    if (!(size_[k] > 0)) return 0;
    return std::clamp(static_cast<int>((x - box_.min[k]) / size_[k]), 0, dims_[k] - 1);
  }
  std::size_t index(int i, int j, int l) const {
    return (static_cast<std::size_t>(l) * dims_[1] + j) * dims_[0] + i;
  }

  BoundingBox box_;
  std::array<int, 3> dims_{1, 1, 1};
  std::array<double, 3> size_{0, 0, 0};
  std::vector<std::vector<Index>> cells_;
};

// CheckReport's protection figures (the reference and the points in one frame; valid: tets with sound indices).
void fill_protection(CheckReport& report, const Plc& plc, const std::vector<Point3>& points,
                     const std::vector<std::array<Index, 4>>& tets, const std::vector<char>& valid,
                     const std::vector<double>& tet_min_dihedral, double angle_deg) {
  const check::ProtectionZones zones = check::find_protection_zones(plc, points, angle_deg);
  report.protection_checked = true;
  report.protection_angle_deg = angle_deg;
  report.num_sharp_vertices = zones.num_sharp_vertices;
  report.num_sharp_segments = zones.num_sharp_segments;
  check::count_protection_zone(report, tets, valid, tet_min_dihedral, zones.point_inside);
}

}  // namespace

CheckReport check_mesh(const TetMesh& mesh, const Plc* reference, const CheckOptions& options) {
  CheckReport report;
  ProblemList problems(report, options.max_problems);
  const std::size_t num_points = mesh.points.size();
  report.num_points = num_points;
  report.num_tets = mesh.tets.size();
  report.num_faces_given = mesh.faces.size();
  const auto region = [&mesh](std::size_t t) { return mesh.tet_region.empty() ? 0 : mesh.tet_region[t]; };
  report.num_regions = std::set<int>(mesh.tet_region.begin(), mesh.tet_region.end()).size();
  if (mesh.tet_region.empty() && !mesh.tets.empty()) report.num_regions = 1;
  if (!mesh.tet_region.empty() && mesh.tet_region.size() != mesh.tets.size()) {
    problems.add("tet_region has " + std::to_string(mesh.tet_region.size()) + " entries for " +
                 std::to_string(mesh.tets.size()) + " tets");
  }

  // 1. Tetrahedra: indices, orientation, quality.
  const int num_bins = static_cast<int>(std::lround(180 / report.dihedral_histogram_bin_deg));
  report.dihedral_histogram.assign(num_bins, 0);
  report.min_dihedral_histogram.assign(num_bins, 0);
  const auto bin_of = [&](double angle_deg) {
    return std::clamp(static_cast<int>(angle_deg / report.dihedral_histogram_bin_deg), 0, num_bins - 1);
  };
  const double inf = std::numeric_limits<double>::infinity();
  report.min_dihedral_deg = inf;
  report.max_dihedral_deg = -inf;
  report.min_sigma = inf;
  report.min_volume = inf;
  std::vector<char> valid(mesh.tets.size(), 1);
  std::vector<double> tet_min_dihedral(mesh.tets.size(), 0);  // for the protection figures
  std::vector<char> used(num_points, 0);
  std::vector<FaceUse> face_uses;
  face_uses.reserve(4 * mesh.tets.size());
  static const int kFaces[4][4] = {{1, 2, 3, 0}, {0, 2, 3, 1}, {0, 1, 3, 2}, {0, 1, 2, 3}};
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
    const auto& v = mesh.tets[t];
    bool bad = false;
    for (int i = 0; i < 4; ++i) {
      bad = bad || v[i] >= num_points;
      for (int j = 0; j < i; ++j) bad = bad || v[i] == v[j];
    }
    if (bad) {
      valid[t] = 0;
      ++report.num_bad_indices;
      problems.add("tet " + std::to_string(t) + ": missing or repeated vertex");
      continue;
    }
    for (Index i : v) used[i] = 1;
    const TetQuality q = tet_quality(mesh.points[v[0]], mesh.points[v[1]], mesh.points[v[2]], mesh.points[v[3]]);
    report.mesh_volume += q.volume;
    report.min_volume = std::min(report.min_volume, q.volume);
    if (!(q.volume > 0)) {
      ++report.num_nonpositive_tets;
      problems.add("tet " + std::to_string(t) + ": non-positive volume " + number(q.volume));
    }
    tet_min_dihedral[t] = q.min_dihedral_deg;
    report.min_dihedral_deg = std::min(report.min_dihedral_deg, q.min_dihedral_deg);
    report.max_dihedral_deg = std::max(report.max_dihedral_deg, q.max_dihedral_deg);
    report.max_radius_edge = std::max(report.max_radius_edge, q.radius_edge);
    report.min_sigma = std::min(report.min_sigma, q.sigma);
    if (q.min_dihedral_deg < 5) ++report.num_tets_min_dihedral_below_5;
    if (q.min_dihedral_deg < 10) ++report.num_tets_min_dihedral_below_10;
    if (q.min_dihedral_deg < 15) ++report.num_tets_min_dihedral_below_15;
    ++report.min_dihedral_histogram[bin_of(q.min_dihedral_deg)];
    for (double angle : tet_dihedral_angles_deg(mesh.points[v[0]], mesh.points[v[1]], mesh.points[v[2]],
                                                 mesh.points[v[3]])) {
      ++report.dihedral_histogram[bin_of(angle)];
    }
    for (const auto& f : kFaces) {
      FaceUse use{{v[f[0]], v[f[1]], v[f[2]]}, static_cast<Index>(t), v[f[3]]};
      std::sort(use.key.begin(), use.key.end());
      face_uses.push_back(use);
    }
  }
  if (report.num_tets == 0) {
    report.min_dihedral_deg = report.max_dihedral_deg = report.min_sigma = report.min_volume = 0;
    problems.add("the mesh has no tetrahedra");
  }
  for (char u : used) report.num_unused_points += !u;

  // Duplicate tetrahedra.
  {
    std::vector<std::pair<std::array<Index, 4>, Index>> sorted;
    for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
      if (!valid[t]) continue;
      auto key = mesh.tets[t];
      std::sort(key.begin(), key.end());
      sorted.push_back({key, static_cast<Index>(t)});
    }
    std::sort(sorted.begin(), sorted.end());
    for (std::size_t i = 1; i < sorted.size(); ++i) {
      if (sorted[i].first == sorted[i - 1].first) {
        ++report.num_duplicate_tets;
        problems.add("tet " + std::to_string(sorted[i].second) + ": duplicate of tet " +
                     std::to_string(sorted[i - 1].second));
      }
    }
  }

  // 2. Faces.
  std::sort(face_uses.begin(), face_uses.end(), [](const FaceUse& a, const FaceUse& b) {
    return a.key != b.key ? a.key < b.key : a.tet < b.tet;
  });
  std::vector<std::pair<std::array<Index, 3>, Index>> boundary;  // face, a tet that has it
  std::vector<std::pair<std::array<Index, 3>, Index>> interior;  // faces between two tets of the same region
  std::vector<check::RegularityTest> regularity_tests;            // one per face of two valid tets
  std::vector<std::pair<std::array<Index, 3>, Index>> regularity_faces;  // the face and the other tet, per test
  const bool test_regularity = options.regularity != RegularityCheck::Skip;
  for (std::size_t i = 0; i < face_uses.size();) {
    std::size_t j = i;
    while (j < face_uses.size() && face_uses[j].key == face_uses[i].key) ++j;
    const std::size_t count = j - i;
    ++report.num_faces;
    const auto& key = face_uses[i].key;
    if (count == 1) {
      ++report.num_hull_faces;
      boundary.push_back({key, face_uses[i].tet});
    } else if (count == 2) {
      const Point3& a = mesh.points[key[0]];
      const Point3 normal = cross(sub(mesh.points[key[1]], a), sub(mesh.points[key[2]], a));
      const double side_1 = dot(normal, sub(mesh.points[face_uses[i].opposite], a));
      const double side_2 = dot(normal, sub(mesh.points[face_uses[i + 1].opposite], a));
      if ((side_1 > 0 && side_2 > 0) || (side_1 < 0 && side_2 < 0)) {
        ++report.num_folded_faces;
        problems.add(face_name(key) + ": tets " + std::to_string(face_uses[i].tet) + " and " +
                     std::to_string(face_uses[i + 1].tet) + " lie on the same side (overlap)");
      }
      if (test_regularity) {
        regularity_tests.push_back({mesh.tets[face_uses[i].tet], face_uses[i + 1].opposite});
        regularity_faces.push_back({key, face_uses[i + 1].tet});
      }
      if (region(face_uses[i].tet) != region(face_uses[i + 1].tet)) {
        ++report.num_region_interface_faces;
        boundary.push_back({key, face_uses[i].tet});
      } else {
        interior.push_back({key, face_uses[i].tet});
      }
    } else {
      ++report.num_overshared_faces;
      std::string tets;
      for (std::size_t k = i; k < j; ++k) tets += (k > i ? ", " : "") + std::to_string(face_uses[k].tet);
      problems.add(face_name(key) + ": shared by " + std::to_string(count) + " tets (" + tets + ")");
    }
    i = j;
  }
  report.num_boundary_faces = boundary.size();

  // 3. Weighted Delaunay (regular) property, locally across the faces of two tetrahedra.
  bool weights_ok = mesh.weights.empty() || mesh.weights.size() == num_points;
  if (!weights_ok) {
    problems.add("weights has " + std::to_string(mesh.weights.size()) + " entries for " +
                 std::to_string(num_points) + " points");
  } else {
    for (std::size_t i = 0; i < mesh.weights.size(); ++i) {
      const double w = mesh.weights[i];
      if (!std::isfinite(w)) {
        weights_ok = false;
        problems.add("point " + std::to_string(i) + ": weight " + number(w) + " is not finite");
        continue;
      }
      report.num_weighted_points += w != 0;
      report.max_weight = std::max(report.max_weight, w);
    }
  }
  if (test_regularity && weights_ok) {
    report.weighted_delaunay_checked = true;
    report.num_regularity_tested_faces = regularity_tests.size();
    const std::vector<std::size_t> violations = check::find_non_regular(mesh.points, mesh.weights, regularity_tests);
    report.num_non_regular_faces = violations.size();
    if (options.regularity == RegularityCheck::Require) {
      for (std::size_t k : violations) {
        problems.add(face_name(regularity_faces[k].first) + ": vertex " + std::to_string(regularity_tests[k].vertex) +
                     " of tet " + std::to_string(regularity_faces[k].second) +
                     " is closer than orthogonal to the orthosphere of the tet across it (not weighted Delaunay)");
      }
    }
  }

  // 4. Conformity to the reference.
  if (reference) {
    report.has_reference = true;
    // Everything below works relative to the input's bounding-box centre (mesh_check_frame.cpp).
    const check::LocalFrame frame = check::make_local_frame(*reference, mesh.points);
    const Plc plc = frame.local(*reference);
    const std::vector<Point3> points = frame.local(mesh.points);
    std::vector<FacetGeometry> facets;
    facets.reserve(plc.facets.size());
    for (const Facet& facet : plc.facets) facets.push_back(check::make_facet_geometry(plc, facet));
    const check::ReferenceVolume volume = check::compute_reference_volume(plc, facets);
    report.reference_volume = volume.volume;
    report.reference_volume_method = volume.method;
    // A facet flat only to some distance d has no one plane: a mesher's plane for it may be any plane within d of its
    // vertices, up to 2 d from the checker's. Its faces are accepted within 2 d of the plane, and it encloses the
    // volume only to 2 d times its area.
    const auto allowance = [](const FacetGeometry& g) { return 2 * g.flatness; };
    double max_allowance = 0, unflat_volume = 0;
    for (const FacetGeometry& g : facets) {
      if (g.degenerate) continue;
      max_allowance = std::max(max_allowance, allowance(g));
      unflat_volume += allowance(g) * g.area;
    }
    if (std::isnan(volume.volume)) {
      report.volume_relative_error = volume.volume;
    } else {
      report.volume_relative_error = std::fabs(report.mesh_volume - volume.volume) / std::fabs(volume.volume);
      const double volume_tolerance = options.relative_volume_tolerance + unflat_volume / std::fabs(volume.volume);
      if (!(report.volume_relative_error <= volume_tolerance)) {
        problems.add("mesh volume " + number(report.mesh_volume) + " differs from the input's " +
                     number(volume.volume) + " (relative error " + number(report.volume_relative_error) + ")");
      }
    }

    double diagonal = bounding_box(plc).diagonal();
    if (!(diagonal > 0)) {
      BoundingBox box;
      for (const Point3& p : points) box.add(p);
      diagonal = box.diagonal();
    }
    // Relative to the model's size, and at least a few ulps of where it lies (a unit cube at 1e15 has its
    // coordinates 0.125 apart).
    const double tolerance = options.tolerance * diagonal + frame.position_tolerance();
    const FacetGrid grid(facets, tolerance + max_allowance);
    std::vector<double> covered(facets.size(), 0);
    // The input facet a face lies on: its three vertices within tolerance of the plane, its centroid inside.
    const auto find_facet = [&](const std::array<Index, 3>& key, double& area) {
      const Point3& a = points[key[0]];
      const Point3& b = points[key[1]];
      const Point3& c = points[key[2]];
      const Point3 centroid{(a[0] + b[0] + c[0]) / 3, (a[1] + b[1] + c[1]) / 3, (a[2] + b[2] + c[2]) / 3};
      const Point3 n = cross(sub(b, a), sub(c, a));
      area = std::sqrt(dot(n, n)) / 2;
      // The nearest such facet: with a tolerance of a few ulps far from the origin, more than one plane can pass.
      Index best = kNoIndex;
      double best_distance = inf;
      for (Index f : grid.candidates(centroid)) {
        const FacetGeometry& g = facets[f];
        const auto distance = [&](const Point3& p) { return std::fabs(dot(g.normal, p) - g.offset); };
        const double d = std::max({distance(a), distance(b), distance(c)});
        if (d > tolerance + allowance(g) || !(d < best_distance)) continue;
        if (g.contains(centroid)) best = f, best_distance = d;
      }
      return best;
    };
    for (const auto& [key, tet] : boundary) {
      double area = 0;
      const Index found = find_facet(key, area);
      if (found == kNoIndex) {
        ++report.num_faces_off_input;
        problems.add(face_name(key) + " of tet " + std::to_string(tet) + ": boundary face on no input facet");
      } else {
        covered[found] += area;
        report.covered_area += area;
      }
    }
    // An internal facet inside one region has tetrahedra of that region on both sides: its faces are interior
    // faces that lie on it. A facet that boundary faces cover is not such a facet: an interior face found on it
    // (within the tolerance) is a face of a flat tetrahedron, not coverage.
    const std::vector<double> boundary_covered = covered;
    for (const auto& [key, tet] : interior) {
      double area = 0;
      const Index found = find_facet(key, area);
      if (found != kNoIndex && boundary_covered[found] == 0) {
        ++report.num_interior_faces_on_input;
        covered[found] += area;
        report.covered_area += area;
      }
    }
    // Rounding of the coordinates (magnitude D, the bounding box's diagonal) perturbs a facet's covered area by
    // about 1e-16 D times its perimeter, whatever its area: a facet's error is taken relative to its area but at
    // least 1e-6 D^2, so a CAD sliver face of 1e-8 D^2 is not failed for an absolute error of 1e-13 D^2 while a
    // missing or doubled face of any size still is.
    double diagonal2 = 0;
    if (!plc.vertices.empty()) {
      Point3 lo = plc.vertices.front(), hi = lo;
      for (const Point3& p : plc.vertices)
        for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], p[k]), hi[k] = std::max(hi[k], p[k]);
      for (int k = 0; k < 3; ++k) diagonal2 += (hi[k] - lo[k]) * (hi[k] - lo[k]);
    }
    const double area_floor = 1e-6 * diagonal2;
    for (std::size_t f = 0; f < facets.size(); ++f) {
      FacetCoverage coverage;
      coverage.facet = static_cast<Index>(f);
      coverage.marker = plc.facets[f].marker;
      coverage.bounds_domain = volume.facet_bounds_domain.empty() || volume.facet_bounds_domain[f];
      coverage.area = facets[f].degenerate ? 0 : facets[f].area;
      coverage.covered_area = covered[f];
      // A facet with no cell of the domain on either side is to be covered by nothing.
      const double to_cover = coverage.bounds_domain ? coverage.area : 0;
      coverage.relative_error = coverage.area > 0
                                    ? std::fabs(covered[f] - to_cover) / std::max(coverage.area, area_floor)
                                    : (covered[f] > 0 ? inf : 0);
      report.facet_area += to_cover;
      report.max_facet_area_relative_error = std::max(report.max_facet_area_relative_error, coverage.relative_error);
      // A facet flat only to d has its area defined to about 2 d times its perimeter (the tilt of its loops).
      const double unflat_area =
          coverage.area > 0 ? allowance(facets[f]) * facets[f].perimeter / std::max(coverage.area, area_floor) : 0;
      if (!(coverage.relative_error <= options.relative_area_tolerance + unflat_area)) {
        ++report.num_miscovered_facets;
        problems.add("facet " + std::to_string(f) + " (marker " + std::to_string(coverage.marker) + "): covered area " +
                     number(coverage.covered_area) + " vs area " +
                     (coverage.bounds_domain ? number(coverage.area)
                                             : "0 (holes or the outside on both sides: no tetrahedron touches it)") +
                     " (relative error " +
                     number(coverage.relative_error) + ")");
      }
      report.facets.push_back(coverage);
    }

    // 5. Quality outside the protection zones of the sharp input angles.
    if (options.protection_angle_deg > 0)
      fill_protection(report, plc, points, mesh.tets, valid, tet_min_dihedral, options.protection_angle_deg);
  }
  report.ok = report.num_problems == 0;
  return report;
}

CheckReport check_protection_zones(const TetMesh& mesh, const Plc& reference, double angle_deg) {
  CheckReport report;
  report.num_points = mesh.points.size();
  report.num_tets = mesh.tets.size();
  if (!(angle_deg > 0)) return report;
  const check::LocalFrame frame = check::make_local_frame(reference, mesh.points);
  const std::vector<Point3> points = frame.local(mesh.points);
  std::vector<char> valid(mesh.tets.size(), 1);
  std::vector<double> tet_min_dihedral(mesh.tets.size(), 0);
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
    const auto& v = mesh.tets[t];
    for (int i = 0; i < 4; ++i) valid[t] = valid[t] && v[i] < points.size();
    // The angle alone (the same value as tet_quality's): the circumradius, exact for a flat tet, is not needed here.
    if (valid[t])
      tet_min_dihedral[t] =
          tet_min_dihedral_deg(mesh.points[v[0]], mesh.points[v[1]], mesh.points[v[2]], mesh.points[v[3]]);
  }
  fill_protection(report, frame.local(reference), points, mesh.tets, valid, tet_min_dihedral, angle_deg);
  return report;
}

}  // namespace qualmesh
