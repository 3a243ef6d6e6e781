// read_plc(): dispatch on the file extension, and the finishing step shared by the surface readers (exact
// duplicate vertex merge in first occurrence order, unused vertex drop, coplanar facet merge).
#include <filesystem>
#include <map>
#include <utility>

#include "plc_read_formats.h"
#include "qualmesh/error.h"
#include "qualmesh/facet_merge.h"
#include "qualmesh/plc_io.h"
#include "text_scanner.h"

namespace qualmesh {

namespace plc_io {

std::string lower_extension(const std::string& path) {
  return to_lower(std::filesystem::path(path).extension().string());
}

Plc finish_surface(SurfaceSoup soup, const std::string& path, const ReadOptions& options) {
  if (soup.faces.empty()) throw InputError(ErrorCode::Empty, "the file holds no facets", path);
  // Exact duplicates: the first occurrence keeps its place.
  std::map<Point3, Index> first_index;
  std::vector<Index> merged(soup.vertices.size());
  for (std::size_t i = 0; i < soup.vertices.size(); ++i) {
    auto [it, inserted] = first_index.emplace(soup.vertices[i], static_cast<Index>(i));
    merged[i] = it->second;
  }
  // Used vertices (after merging), renumbered in order of their (merged) position in the file.
  std::vector<char> used(soup.vertices.size(), 0);
  for (const auto& face : soup.faces) {
    for (Index v : face) used[merged[v]] = 1;
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
    for (Index v : soup.faces[f]) loop.push_back(new_index[merged[v]]);
    facet.polygons.push_back(std::move(loop));
    facet.marker = soup.markers.empty() ? 0 : soup.markers[f];
    plc.facets.push_back(std::move(facet));
  }
  if (options.merge_coplanar) plc = merge_coplanar_facets(plc);
  return plc;
}

}  // namespace plc_io

bool is_plc_path(const std::string& path) {
  const std::string ext = plc_io::lower_extension(path);
  return ext == ".poly" || ext == ".smesh" || ext == ".node" || ext == ".off" || ext == ".stl" || ext == ".obj" ||
         ext == ".mesh";
}

Plc read_plc(const std::string& path, const ReadOptions& options) {
  const std::string ext = plc_io::lower_extension(path);
  Plc plc;
  if (ext == ".poly" || ext == ".smesh") {
    plc = plc_io::read_tetgen_poly(path);
  } else if (ext == ".node") {
    plc = plc_io::read_tetgen_node(path);
  } else if (ext == ".off") {
    plc = plc_io::read_off(path, options);
  } else if (ext == ".stl") {
    plc = plc_io::read_stl(path, options);
  } else if (ext == ".obj") {
    plc = plc_io::read_obj(path, options);
  } else if (ext == ".mesh") {
    plc = plc_io::read_medit(path, options);
  } else {
    throw InputError(ErrorCode::Unsupported,
                     "unknown PLC format '" + ext +
                         "' (expected .poly, .smesh, .node, .off, .stl, .obj or .mesh)",
                     path);
  }
  plc.name = std::filesystem::path(path).filename().string();
  return plc;
}

}  // namespace qualmesh
