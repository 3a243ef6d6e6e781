// Private interface between the stages of the CAD front end (cad_import.cpp drives them in this order):
// read a shape (occt_read.cpp, fcstd_read.cpp) -> heal it into solids (shape_heal.cpp) -> turn it into a PLC
// (brep_to_plc.cpp). OpenSCAD files take their own path (scad_read.cpp). OpenCASCADE types appear only here and in
// these files, never in a public header.
#pragma once

#include <TopoDS_Shape.hxx>
#include <gp_Pnt.hxx>

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "qualmesh/cad_import.h"

namespace qualmesh::cad {

// Reads a STEP, IGES or OCCT BREP file; `format` is "STEP", "IGES" or "BREP". Throws InputError.
TopoDS_Shape read_occt_file(const std::string& path, const std::string& format);

// Reads the visible solids of a FreeCAD document (see fcstd_read.cpp for the rule). Appends what it chose to `log`.
TopoDS_Shape read_fcstd_file(const std::string& path, std::vector<std::string>& log);

// Turns any shape into a compound of closed solids that share their common faces: sews loose faces (when
// options.heal), fixes small and degenerate edges, makes solids of closed shells, glues touching solids (general
// fuse) so that a face between two solids is one face. Throws InputError(OpenBoundary) naming the faces and edges of
// `shape` (numbered as in `shape`) that stay open. Appends what it did to `log`.
TopoDS_Shape heal_into_solids(const TopoDS_Shape& shape, const CadOptions& options, const std::string& file,
                              std::vector<std::string>& log);

// read_occt_file / read_fcstd_file, then heal_into_solids, by the file's extension. The result is also kept for
// the next call in this process (one entry, keyed by path and healing options); use_cache = true returns that kept
// shape when the key matches instead of reading again (fit_mesh_to_cad right after read_cad).
TopoDS_Shape read_healed_solids(const std::string& path, const CadOptions& options, std::vector<std::string>& log,
                                bool use_cache);

// Tessellates the solids of `solids` (output of heal_into_solids) and builds the PLC and summary.
CadModel convert_solids_to_plc(const TopoDS_Shape& solids, const CadOptions& options, const std::string& file);

// CadSummary::node_tolerances and CadSummary::solid_volumes of the healed shape `solids`, by face and solid number
// (TopExp::MapShapes order, the PLC's Face<n> and Solid<n>): what convert_solids_to_plc puts in its summary, without
// meshing anything (measure_against_cad).
std::vector<double> face_node_tolerances(const TopoDS_Shape& solids);
std::vector<double> solid_volumes(const TopoDS_Shape& solids);

// BRepMesh's triangles of one face, by PLC vertex ids, repaired before they become facets (tessellation_repair.cpp).
// Two triangles on the same three vertices with opposite orientations (a flat fold) are both removed.
void remove_mirrored_pairs(std::vector<std::array<Index, 3>>& triangles);
// A triangle whose third vertex lies within `flat` of its longest edge is removed, and the triangle across that
// edge split at the vertex (the surface stays closed).
void remove_flat_triangles(std::vector<std::array<Index, 3>>& triangles, const std::vector<Point3>& vertices,
                           double flat);

// One triangle of a solid's PLC surface, by its corners (a planar facet enters as the triangles of its face mesh).
using SeedTriangle = std::array<Point3, 3>;

// A point strictly inside the closed surface of `triangles` (one solid's PLC facets), as far from them as a short
// search finds (region_seed.cpp); nothing when the triangles do not close or no point is found.
std::optional<Point3> region_seed(const std::vector<SeedTriangle>& triangles, double diagonal);

// Renders an OpenSCAD file with `openscad` and reads the result, repairing only exactly.
CadModel read_scad_file(const std::string& path, const CadOptions& options);

// One sharp feature of a CAD model (cad_features.cpp): an edge (Edge<number>, with its smallest interior dihedral
// angle) or a vertex (Vertex<number>, with the smallest angle between two edges of one face leaving it, and its
// point), numbered as TopExp::MapShapes numbers the healed shape's edges and vertices (FreeCAD's names).
struct SharpFeature {
  TopoDS_Shape shape;  // the TopoDS_Edge or TopoDS_Vertex
  int number = 0;
  double angle_deg = 0;
  gp_Pnt at;  // vertices only
};
struct SharpFeatureList {
  std::vector<SharpFeature> edges, vertices;
};
// The sharp edges and vertices of `solids` below `angle_deg` (cad_import.h, find_sharp_cad_features, says which).
SharpFeatureList list_sharp_features(const TopoDS_Shape& solids, double angle_deg);
// One line for the model's summary (part.step): "sharp features below 30 deg: 6 face corners (smallest 0.00 deg at
// Vertex38 (85.725, 25.4, 42.8752)), 0 edges".
std::string describe_sharp_features(const SharpFeatureList& list, double angle_deg);

// Silences OpenCASCADE's default console printers (library code never prints). Idempotent.
void silence_occt_messages();

// Lower-case file extension with the dot (".step"), "" when none.
std::string lower_extension(const std::string& path);

}  // namespace qualmesh::cad
