// The interface between the `qualmesh` command line and its CAD front end plugin, libqualmesh_cad_plugin.so (the
// CAD and OpenSCAD readers of cad_import.h with OpenCASCADE behind them). The CLI dlopens the plugin on its first
// CAD input only, so that every other run is spared the dynamic linker's ~70 ms of OpenCASCADE relocations.
//
// Private to converters/: the CLI and the plugin are built together from one source tree by one compiler against one
// libstdc++, so C++ objects (Plc, std::string, std::vector) pass by pointer. The entry point is extern "C" and its
// name carries the interface version: change any type below (or what the plugin does with it) and bump the version,
// so that a stale plugin fails to load by name instead of misreading memory. v2: CadOptions carries the size field
// (size, min_size, curvature_elements, gradation, local_sizes, surface_mesh) and LoadResult the size used. measure v3:
// CadMeasureOptions, and CadConformity's sharp features; v4: CadMeasureOptions::reuse_shape.
#pragma once

#include <string>
#include <vector>

#include "qualmesh/cad_import.h"
#include "qualmesh/error.h"
#include "qualmesh/plc.h"

namespace qualmesh::cad_plugin {

// File name of the plugin, looked for next to the executable (see cad_plugin_loader.h for the search order).
inline constexpr const char* kPluginFileName = "libqualmesh_cad_plugin.so";
// Name of the entry point (load_cad_fn) in the plugin.
inline constexpr const char* kLoadCadSymbol = "qualmesh_cad_plugin_load_cad_v2";
// Names of the other entry points: fit_mesh_to_cad (FitMeshFn), measure_against_cad (MeasureFn).
inline constexpr const char* kFitMeshSymbol = "qualmesh_cad_plugin_fit_mesh_v3";
inline constexpr const char* kMeasureSymbol = "qualmesh_cad_plugin_measure_v4";
// project_onto_cad (ProjectFn); optional: a plugin without it leaves the mesher's boundary points on the facets.
inline constexpr const char* kProjectSymbol = "qualmesh_cad_plugin_project_v2";

enum class LoadStatus : int {
  Ok = 0,             // plc and notes are filled
  InputError = 1,     // read_cad threw InputError: error_code, message, file, line and ids hold its fields
  OutOfMemory = 2,    // std::bad_alloc
  InternalError = 3,  // any other exception (a bug): message holds its what()
};

// What one call fills. Owned by the caller; the plugin only assigns to it.
struct LoadResult {
  LoadStatus status = LoadStatus::InternalError;
  Plc plc;                         // Ok: the model's PLC (read_cad's CadModel::plc)
  std::vector<std::string> notes;  // Ok: summary lines (format, solids and their volumes, deflection, healing)
  double size_used = 0;            // Ok: CadSummary::size_used (the sized surface mesh's target edge length)
  int error_code = 0;              // InputError: static_cast<int>(ErrorCode)
  std::string message;             // InputError: InputError::message(); InternalError: what()
  std::string file;                // InputError: InputError::file()
  long line = 0;                   // InputError: InputError::line()
  ElementIds ids;                  // InputError: InputError::ids()
};

// read_cad(path, *options) into *result. Never throws: every outcome is a LoadStatus. Mutates *result only.
using LoadCadFn = void (*)(const char* path, const CadOptions* options, LoadResult* result) noexcept;

// What one fit call fills (status and error fields as in LoadResult; plc and notes unused).
struct FitResult {
  LoadResult outcome;
  CadFitReport report;  // Ok: fit_mesh_to_cad's report
};

// fit_mesh_to_cad(path, *options, *mesh, *fit_options) into *mesh and *result. Never throws. Mutates *mesh and
// *result only.
using FitMeshFn = void (*)(const char* path, const CadOptions* options, const CadFitOptions* fit_options,
                           TetMesh* mesh, FitResult* result) noexcept;

struct MeasureResult {
  LoadResult outcome;
  CadConformity conformity;  // Ok: measure_against_cad's result
};
using MeasureFn = void (*)(const char* path, const CadOptions* options, const TetMesh* mesh,
                           const CadMeasureOptions* measure, MeasureResult* result) noexcept;

// project_onto_cad(path, *options, edge, face, xyz as a Point3): 1 when xyz was moved onto the CAD edge or face, 0
// when not (nothing to move, or any failure: the point stays where the mesher put it). Never throws.
using ProjectFn = int (*)(const char* path, const CadOptions* options, int edge, int face, double* xyz) noexcept;

}  // namespace qualmesh::cad_plugin
