// read_plc(): dispatch on the file extension, and the finishing step shared by the surface readers (exact
// duplicate vertex merge in first occurrence order, unused vertex drop, coplanar facet merge).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <utility>

#include "plc_read_formats.h"
#include "qualmesh/error.h"
#include "qualmesh/facet_merge.h"
#include "qualmesh/plc_io.h"
#include "qualmesh/plc_validate.h"
#include "text_scanner.h"

namespace qualmesh {

namespace plc_io {

std::string lower_extension(const std::string& path) {
  return to_lower(std::filesystem::path(path).extension().string());
}

bool repeats_a_vertex(const std::vector<Index>& loop) {
  std::vector<Index> sorted = loop;
  std::sort(sorted.begin(), sorted.end());
  return std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end();
}

// A face that may be degenerate: it repeats a vertex, or its corners are collinear up to rounding (every corner's
// cross product with the first edge tiny against the lengths). The exact verdict is validate_plc's.
bool is_degenerate_suspect(const std::vector<Point3>& vertices, const std::vector<Index>& loop) {
  if (loop.size() < 3 || repeats_a_vertex(loop)) return true;
  const Point3& a = vertices[loop[0]];
  const Point3& b = vertices[loop[1]];
  const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
  const double sq_u = u[0] * u[0] + u[1] * u[1] + u[2] * u[2];
  for (std::size_t k = 2; k < loop.size(); ++k) {
    const Point3& c = vertices[loop[k]];
    const double v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    const double w[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    const double sq_w = w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
    const double sq_v = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
    if (!(sq_w <= 1e-20 * sq_u * sq_v)) return false;  // clearly spans a plane (NaN-safe)
  }
  return true;
}

namespace {

// The tolerance the reader's note suggests: validate_plc's planarity tolerance, so a merged facet is always valid.
constexpr double kSuggestedCoplanarTolerance = 1e-6;

std::string point_text(const Point3& p) {
  char text[100];
  std::snprintf(text, sizeof text, "(%.17g, %.17g, %.17g)", p[0], p[1], p[2]);
  return text;
}

// Throws InputError(DegenerateFacet) naming soup face `f` when `loop` repeats a vertex or validate_plc finds it of
// zero area (exact predicates).
void refuse_if_degenerate(const std::vector<Point3>& vertices, const std::vector<Index>& loop,
                          const SurfaceSoup& soup, std::size_t f, const std::string& path) {
  const std::size_t o = f < soup.origin.size() ? soup.origin[f] : f;  // the file's face index
  const long line = o < soup.lines.size() ? soup.lines[o] : 0;
  const std::string name = std::string(soup.face_word) + " " + std::to_string(static_cast<long>(o) + soup.first_face_number);
  std::string corners;
  for (Index v : loop) corners += (corners.empty() ? "" : ", ") + point_text(vertices[v]);
  const ElementIds ids{{}, {}, {static_cast<Index>(o)}, {}};
  if (repeats_a_vertex(loop)) {
    std::vector<Index> sorted = loop;
    std::sort(sorted.begin(), sorted.end());
    const Index repeated = *std::adjacent_find(sorted.begin(), sorted.end());
    throw InputError(ErrorCode::DegenerateFacet,
                     name + " repeats the vertex at " + point_text(vertices[repeated]) + " (its corners: " + corners +
                         "): a facet needs 3 distinct corners" +
                         (loop.size() == 3 ? "" : "; only triangles are repaired (dropped)"),
                     path, line, ids);
  }
  if (has_zero_area(vertices, loop))
    throw InputError(ErrorCode::DegenerateFacet,
                     name + " has zero area: its corners " + corners + " are collinear" +
                         (loop.size() == 3 ? "; it is not repaired because no single face holds its long edge the "
                                             "other way round (a closed surface has exactly one)"
                                           : "; only triangles are repaired"),
                     path, line, ids);
}

}  // namespace

Plc finish_surface(SurfaceSoup soup, const std::string& path, const ReadOptions& options,
                   std::vector<std::string>* notes) {
  if (soup.faces.empty()) throw InputError(ErrorCode::Empty, "the file holds no facets", path);
  refuse_out_of_scale(soup.vertices, path);  // first: out of scale, every face looks degenerate
  // Exact duplicates: the first occurrence keeps its place.
  std::map<Point3, Index> first_index;
  std::vector<Index> merged(soup.vertices.size());
  for (std::size_t i = 0; i < soup.vertices.size(); ++i) {
    auto [it, inserted] = first_index.emplace(soup.vertices[i], static_cast<Index>(i));
    merged[i] = it->second;
  }
  for (auto& face : soup.faces)
    for (Index& v : face) v = merged[v];
  if (options.repair_degenerate) {
    const SurfaceRepairs repairs = repair_degenerate_triangles(soup);
    if (notes && !repairs.summary().empty()) notes->push_back(repairs.summary());
  }
  // Used vertices (after merging), renumbered in order of their (merged) position in the file.
  std::vector<char> used(soup.vertices.size(), 0);
  for (const auto& face : soup.faces) {
    for (Index v : face) used[v] = 1;
  }
  std::vector<Index> new_index(soup.vertices.size(), kNoIndex);
  Plc plc;
  for (std::size_t i = 0; i < soup.vertices.size(); ++i) {
    if (used[i]) {
      new_index[i] = static_cast<Index>(plc.vertices.size());
      plc.vertices.push_back(soup.vertices[i]);
    }
  }
  plc.facets.reserve(soup.faces.size());
  for (std::size_t f = 0; f < soup.faces.size(); ++f) {
    Facet facet;
    std::vector<Index> loop;
    loop.reserve(soup.faces[f].size());
    for (Index v : soup.faces[f]) loop.push_back(new_index[v]);
    facet.polygons.push_back(std::move(loop));
    facet.marker = soup.markers.empty() ? 0 : soup.markers[f];
    plc.facets.push_back(std::move(facet));
  }
  // Degenerate faces, found before merging (where each facet is still one face of the file) and refused only if
  // they are still facets of their own after it.
  std::map<std::vector<Index>, std::size_t> suspects;  // facet loop -> face index
  for (std::size_t f = 0; f < plc.facets.size(); ++f) {
    if (is_degenerate_suspect(plc.vertices, plc.facets[f].polygons[0])) suspects.emplace(plc.facets[f].polygons[0], f);
  }
  if (options.merge_coplanar) {
    Plc merged = merge_coplanar_facets(plc, options.coplanar_tolerance);
    if (notes && options.coplanar_tolerance == 0) {
      // Say when rounding alone keeps flat faces apart: their needle triangles stay sharp input angles.
      const std::size_t near = merge_coplanar_facets(plc, kSuggestedCoplanarTolerance).facets.size();
      if (near < merged.facets.size()) {
        notes->push_back(std::to_string(merged.facets.size()) + " facets after merging exactly coplanar ones; " +
                         std::to_string(near) + " with --coplanar-tolerance 1e-6 (faces flat to 1e-6 of the " +
                         "bounding-box diagonal, whose needle triangles are sharp input angles otherwise)");
      }
    }
    plc = std::move(merged);
  }
  if (!suspects.empty()) {
    for (const Facet& facet : plc.facets) {
      if (facet.polygons.size() != 1) continue;
      const auto it = suspects.find(facet.polygons[0]);
      if (it != suspects.end()) refuse_if_degenerate(plc.vertices, facet.polygons[0], soup, it->second, path);
    }
  }
  return plc;
}

void refuse_out_of_scale(const std::vector<Point3>& vertices, const std::string& path) {
  if (vertices.empty()) return;
  double largest = 0;
  const Point3* far = &vertices[0];
  Point3 lo = vertices[0], hi = vertices[0];
  for (const Point3& p : vertices) {
    for (int k = 0; k < 3; ++k) {
      if (std::fabs(p[k]) > largest) largest = std::fabs(p[k]), far = &p;
      lo[k] = std::min(lo[k], p[k]);
      hi[k] = std::max(hi[k], p[k]);
    }
  }
  char text[300];
  if (largest > kMaxCoordinate) {
    std::snprintf(text, sizeof text,
                  "the vertex at (%.6g, %.6g, %.6g) is too far out to compute with (overflow: areas and predicates "
                  "take up to fourth powers of coordinates, and double ends at 1.8e308): coordinates up to %.0e in "
                  "magnitude are meshed; scale the model down",
                  (*far)[0], (*far)[1], (*far)[2], kMaxCoordinate);
    throw InputError(ErrorCode::NonFinite, text, path);
  }
  const double extent = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
  if (extent < kMinExtent) {
    std::snprintf(text, sizeof text,
                  "the model spans only %.6g (its largest bounding-box side), too small to compute with (underflow: "
                  "fourth powers of its lengths fall below double's smallest normal number, 2.2e-308): at least %.0e "
                  "is meshed; scale the model up",
                  extent, kMinExtent);
    throw InputError(ErrorCode::NonFinite, text, path);
  }
}

}  // namespace plc_io

bool is_plc_path(const std::string& path) {
  const std::string ext = plc_io::lower_extension(path);
  return ext == ".poly" || ext == ".smesh" || ext == ".node" || ext == ".off" || ext == ".stl" || ext == ".obj" ||
         ext == ".mesh";
}

Plc read_plc(const std::string& path, const ReadOptions& options, std::vector<std::string>* notes) {
  const std::string ext = plc_io::lower_extension(path);
  Plc plc;
  if (ext == ".poly" || ext == ".smesh") {
    plc = plc_io::read_tetgen_poly(path);
    if (options.coplanar_tolerance > 0) plc = merge_coplanar_facets(plc, options.coplanar_tolerance);
  } else if (ext == ".node") {
    plc = plc_io::read_tetgen_node(path);
  } else if (ext == ".off") {
    plc = plc_io::read_off(path, options, notes);
  } else if (ext == ".stl") {
    plc = plc_io::read_stl(path, options, notes);
  } else if (ext == ".obj") {
    plc = plc_io::read_obj(path, options, notes);
  } else if (ext == ".mesh") {
    plc = plc_io::read_medit(path, options, notes);
  } else {
    throw InputError(ErrorCode::Unsupported,
                     "unknown PLC format '" + ext +
                         "' (expected .poly, .smesh, .node, .off, .stl, .obj or .mesh)",
                     path);
  }
  plc_io::refuse_out_of_scale(plc.vertices, path);
  plc.name = std::filesystem::path(path).filename().string();
  return plc;
}

}  // namespace qualmesh
