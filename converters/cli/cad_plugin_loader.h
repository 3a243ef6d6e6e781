// Loads the CAD front end plugin (cad_plugin_abi.h) the first time a CAD or OpenSCAD input is read, and reads
// through it. The `qualmesh` executable does not link OpenCASCADE, so runs on other inputs start in milliseconds.
//
// Where the plugin is looked for, in order:
//  1. $QUALMESH_CAD_PLUGIN, the full path of the plugin, when set (then nowhere else: an override that silently fell
//     back would hide a wrong path);
//  2. the directory of the running executable (/proc/self/exe), where the build tree puts it;
//  3. <that directory>/../lib/qualmesh/, an installed layout.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "qualmesh/cad_import.h"
#include "qualmesh/plc.h"

namespace qualmesh::cli {

// read_cad(path, options) through the plugin; appends the summary lines to *notes when notes is given, and stores
// the sized surface mesh's target edge length (CadSummary::size_used, 0 for a tessellation) in *size_used when given.
// Throws InputError: read_cad's own, rebuilt field by field (same what()), or ErrorCode::Unsupported naming the paths
// tried when the plugin cannot be loaded. Throws std::bad_alloc, or std::runtime_error with the plugin's what() for
// an internal error.
Plc read_cad_through_plugin(const std::string& path, const CadOptions& options, std::vector<std::string>* notes,
                            double* size_used = nullptr);

// fit_mesh_to_cad(path, options, mesh, fit_options) through the plugin (same errors as read_cad_through_plugin).
CadFitReport fit_mesh_through_plugin(const std::string& path, const CadOptions& options,
                                     const CadFitOptions& fit_options, TetMesh& mesh);

// measure_against_cad(path, options, mesh, measure) through the plugin.
CadConformity measure_through_plugin(const std::string& path, const CadOptions& options, const TetMesh& mesh,
                                     const CadMeasureOptions& measure);

// project_onto_cad(path, options, edge, face, p) through the plugin, as MeshOptions::project_to_boundary wants it;
// empty when the plugin has no such entry point.
std::function<bool(int, int, Point3&)> cad_projector_through_plugin(const std::string& path,
                                                                   const CadOptions& options);

}  // namespace qualmesh::cli
