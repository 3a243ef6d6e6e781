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
  // Where each face is in the file, for messages: its 1-based line (empty or 0: not known, binary STL), and the
  // number the format gives the first face (OFF counts from 0, the others from 1) and the word for a face.
  std::vector<long> lines;
  long first_face_number = 1;
  const char* face_word = "face";
  // The file's face index of each face (empty: face f is the file's face f); set by repair_degenerate_triangles(),
  // which drops and splits faces. `lines` stays indexed by the file's face index.
  std::vector<std::size_t> origin;
};

// What repair_degenerate_triangles() did.
struct SurfaceRepairs {
  std::size_t num_dropped = 0;        // triangles repeating a vertex, dropped
  std::size_t num_split = 0;          // collinear triangles dropped by splitting their neighbour
  std::vector<std::string> examples;  // the first three, naming the faces as the file numbers them, with lines
  std::string summary() const;        // "" when nothing was repaired
};

// Exact repairs of degenerate triangles (issue 18), on faces given in merged vertex indices: a triangle that repeats
// a vertex is dropped; a triangle whose three distinct corners are exactly collinear is dropped and the one face
// holding its long edge the other way round gets the middle corner in that edge (a triangle neighbour is split in
// two). Both keep the surface's directed edges, so a closed oriented surface stays so, with the same volume. A
// collinear triangle with no single such neighbour is left for the reader to refuse. Polygons of 4 or more vertices
// are never repaired. Sets soup.origin.
SurfaceRepairs repair_degenerate_triangles(SurfaceSoup& soup);

// True when `loop` names a vertex twice.
bool repeats_a_vertex(const std::vector<Index>& loop);

// A face that may be degenerate: fewer than 3 vertices, a repeated vertex, or corners collinear up to rounding. The
// exact verdict is has_zero_area's.
bool is_degenerate_suspect(const std::vector<Point3>& vertices, const std::vector<Index>& loop);

// True when validate_plc finds the polygon `loop` (indices into vertices) degenerate: exact predicates.
bool has_zero_area(const std::vector<Point3>& vertices, const std::vector<Index>& loop);

// Merges exactly duplicated vertices (first occurrence order), drops unused vertices, builds one facet per face
// and, when options.merge_coplanar, merges coplanar facets. Throws InputError(Empty) naming `path` when there is no
// face, and InputError(DegenerateFacet) for a face that stays a facet of its own (not merged away) although it
// repeats a vertex or has all its corners exactly collinear (zero area), naming the face as the file numbers it,
// its line and its corners' coordinates (issue 18 item 7: validation would name it by its merged facet id).
// Degenerate triangles are first repaired (repair_degenerate_triangles) when options.repair_degenerate; what was done
// is appended to `notes` ("repaired: ...").
Plc finish_surface(SurfaceSoup soup, const std::string& path, const ReadOptions& options,
                   std::vector<std::string>* notes);

Plc read_tetgen_poly(const std::string& path);   // .poly and .smesh (by extension)
Plc read_tetgen_node(const std::string& path);   // .node
Plc read_off(const std::string& path, const ReadOptions& options, std::vector<std::string>* notes);
Plc read_stl(const std::string& path, const ReadOptions& options, std::vector<std::string>* notes);
Plc read_obj(const std::string& path, const ReadOptions& options, std::vector<std::string>* notes);
Plc read_medit(const std::string& path, const ReadOptions& options, std::vector<std::string>* notes);

// Lower-case extension with the dot (".poly"), or "".
std::string lower_extension(const std::string& path);

// The scale QualMesh computes at (issue 18 item 7): facet areas, normals and the refinement's constructions take up
// to fourth powers of coordinates, so beyond these a model's numbers overflow to infinity or underflow to zero and
// every facet "encloses no area". A vertex farther than kMaxCoordinate from the origin in any coordinate, or a model
// whose largest bounding-box side is below kMinExtent, is refused: InputError(NonFinite) naming the vertex (by its
// coordinates) or the extent, the limit and "overflow" or "underflow". Measured: a unit cube scaled to 1e70 or 1e-80
// meshes; 1e80 or 1e-90 "enclose no area".
inline constexpr double kMaxCoordinate = 1e70;
inline constexpr double kMinExtent = 1e-80;
void refuse_out_of_scale(const std::vector<Point3>& vertices, const std::string& path);

}  // namespace qualmesh::plc_io
