// Private to the PLC readers: one reader per format family (plc_read_<family>.cpp), and the shared finishing step of
// surface readers (exact duplicate vertex merge, unused vertex drop, coplanar facet merge).
#pragma once

#include <string>
#include <vector>

#include "qualmesh/plc.h"
#include "qualmesh/plc_io.h"

namespace qualmesh::plc_io {

// What a surface reader collects before finishing: raw vertices and polygon faces referring to them (0-based,
// already checked to be in range), each with a marker.
struct SurfaceSoup {
  std::vector<Point3> vertices;
  std::vector<std::vector<Index>> faces;
  std::vector<int> markers;  // one per face
};

// Merges exactly duplicated vertices (first occurrence order), drops unused vertices, builds one facet per face
// and, when options.merge_coplanar, merges coplanar facets. Throws InputError(Empty) naming `path` when there is no
// face.
Plc finish_surface(SurfaceSoup soup, const std::string& path, const ReadOptions& options);

Plc read_tetgen_poly(const std::string& path);   // .poly and .smesh (by extension)
Plc read_tetgen_node(const std::string& path);   // .node
Plc read_off(const std::string& path, const ReadOptions& options);
Plc read_stl(const std::string& path, const ReadOptions& options);
Plc read_obj(const std::string& path, const ReadOptions& options);
Plc read_medit(const std::string& path, const ReadOptions& options);

// Lower-case extension with the dot (".poly"), or "".
std::string lower_extension(const std::string& path);

}  // namespace qualmesh::plc_io
