// Readers and writers of piecewise linear complexes (PLCs): TetGen .poly/.smesh/.node, OFF, STL (ASCII and binary),
// Wavefront OBJ and Medit .mesh surfaces in; .poly, .smesh and .off out.
//
// Why here: every front end (CLI, Python, FreeCAD) loads its input through read_plc(), so that a malformed file gets
// the same typed error everywhere: InputError with the file, the 1-based line (text formats; 0 for binary STL) and a
// message naming the offending element as the file numbers it (TetGen: from its first node index; OBJ, Medit: from
// 1; OFF: from 0, like its vertex indices; STL facets: from 1). InputError::ids() holds 0-based ids where one
// element is at fault. Readers check syntax and references only; geometric validity
// (duplicates, closedness, intersections, planarity) is judged by validate_plc().
#pragma once

#include <string>
#include <vector>

#include "qualmesh/plc.h"

namespace qualmesh {

struct ReadOptions {
  // Surface readers (OFF, STL, OBJ, Medit): merge adjacent, exactly coplanar facets into polygonal facets
  // (merge_coplanar_facets() of facet_merge.h), so that an STL box becomes six squares. TetGen files are never
  // merged.
  bool merge_coplanar = true;
  // > 0: facets coplanar up to this fraction of the bounding-box diagonal merge too (merge_coplanar_facets'
  // relative_tolerance), in surfaces (with merge_coplanar) and, only when asked for so, in TetGen .poly/.smesh files.
  // The boundary of a mesh then lies within that distance of the input triangles instead of on them.
  double coplanar_tolerance = 0;
  // Surface readers: repair degenerate triangles exactly, as TetGen meshes such files (issue 18): drop a triangle
  // that repeats a vertex; drop one with three collinear corners (a T-junction in disguise) and split the face across
  // its long edge at the middle corner. The surface and its volume are unchanged. read_plc's `notes` say what was
  // done. A degenerate face that cannot be repaired so is refused (InputError DegenerateFacet, with its number,
  // line and corners).
  bool repair_degenerate = true;
};

// Reads a PLC, choosing the reader by extension (case-insensitive):
//  .poly, .smesh  TetGen PLC (0- or 1-based, decided by the first node index; a node count of 0 reads the sibling
//                 .node file); facets with several polygons, facet holes, volume holes and regions are kept;
//  .node          TetGen points only (no facets);
//  .off .stl .obj .mesh  surfaces (STL ASCII or binary, told apart by the file size; Medit: Triangles and
//                 Quadrilaterals, Tetrahedra ignored). Exactly duplicated vertices are merged (first occurrence
//                 order) and vertices used by no facet are dropped.
// Plc::name is set to the file name. Throws InputError (Io, Parse, IndexOutOfRange, NonFinite, Empty, Unsupported).
// `notes`, when given, receives a line for each repair made ("repaired: ...").
Plc read_plc(const std::string& path, const ReadOptions& options = {}, std::vector<std::string>* notes = nullptr);

// True when the extension of `path` is one that read_plc() accepts.
bool is_plc_path(const std::string& path);

// Throws InputError(Io) naming `path` unless it is a regular file (symbolic links followed): a directory, a FIFO, a
// device is refused by what it is ("is a directory, not a file", ...), as read_plc() refuses it, without blocking
// and without reading. For front ends whose own reader opens the file (the CAD formats).
void require_regular_input_file(const std::string& path);

// Writes `plc` as .poly, .smesh or .off (chosen by extension, case-insensitive) through a temporary file renamed
// into place, so a failure leaves no partial file. Coordinates are written with round-trip precision.
// What a format cannot hold throws InputError(Unsupported) naming the element, and nothing is written:
//  .smesh: a facet with more than one polygon or with hole points;
//  .off:   the same, a facet polygon of fewer than 3 vertices, volume holes and region seeds;
//  all:    an explicit segment that is not an edge of some facet polygon.
void write_plc(const Plc& plc, const std::string& path);

}  // namespace qualmesh
