// Shared pieces of the `qualmesh` command line: how subcommands register, exit codes, input loading.
//
// Exit codes (documented in README.md and `qualmesh --help`):
//   0  success
//   1  internal error (a bug: please report it with the input)
//   2  bad input or bad usage: unreadable or malformed file, invalid PLC, unknown option; the message on stderr
//      names the file, the line and the element ids
//   3  `check` ran and found defects in the mesh (the report says which)
#pragma once

#include <CLI/CLI.hpp>

#include <functional>
#include <string>
#include <vector>

#include "qualmesh/cad_import.h"
#include "qualmesh/plc.h"
#include "qualmesh/tet_mesh.h"

namespace qualmesh::cli {

enum ExitCode : int { kExitOk = 0, kExitInternal = 1, kExitBadInput = 2, kExitCheckFailed = 3 };

// Every subcommand registers itself on the app; its callback runs the command and stores the exit code in
// `exit_code`. Errors are thrown (InputError -> 2, anything else -> 1) and mapped in main().
void register_info_command(CLI::App& app, int& exit_code);
void register_check_command(CLI::App& app, int& exit_code);
void register_convert_command(CLI::App& app, int& exit_code);
void register_mesh_command(CLI::App& app, int& exit_code);

// Options shared by the commands that read an input model.
struct InputOptions {
  bool keep_triangles = false;       // surface inputs: do not merge coplanar triangles into polygonal facets
  double coplanar_tolerance = 0;     // surface and TetGen inputs: merge facets coplanar up to this fraction of D
  double deflection = 0;             // CAD: absolute chordal deflection of curved faces (0 = relative)
  double relative_deflection = 0.001;  // CAD: deflection relative to the bounding-box diagonal
  // CAD size field (CadOptions; model units): --size, --min-size, --curvature, --gradation, --local-size NAME=H,
  // --cad-surface sized|tessellation.
  double size = 0;                   // 0 = default (a tenth of the bounding-box diagonal)
  double min_size = 0;               // 0 = default (a 30th of the size)
  double curvature = 12;             // elements per full circle; 0 disables
  double gradation = 0;              // 0 = none
  std::vector<std::string> local_sizes;  // "Face3=0.5", "Edge5=0.2", "Solid2=1" (checked at parse time)
  CadSurfaceMesh cad_surface = CadSurfaceMesh::Sized;
  double sewing_tolerance = 0;       // CAD: sewing tolerance in model units (0 = automatic; CadOptions)
};
void add_input_options(CLI::App& command, InputOptions& options);

// The CAD front end's options as the input options give them (--size, --min-size, --local-size, ...).
CadOptions cad_options_of(const InputOptions& options);

// Reads any input model the CLI accepts (PLC formats; CAD and OpenSCAD formats when built with the CAD front end)
// into a Plc. When `notes` is given, lines describing the source (CAD solids, faces, edges, healing) are appended;
// when `cad_size_used` is given, it receives the target edge length: a CAD input's (CadSummary::size_used), or
// --size for a surface or PLC (else 0).
// Throws InputError.
Plc load_input(const std::string& path, const InputOptions& options, std::vector<std::string>* notes = nullptr,
               double* cad_size_used = nullptr);

// True for the inputs load_input reads through the CAD front end (.step .stp .iges .igs .brep .brp .fcstd .scad).
bool is_cad_input(const std::string& path);
// A CAD input with CAD faces to measure against: is_cad_input, less OpenSCAD's rendered surfaces (.scad).
bool has_cad_faces(const std::string& path);

// fit_mesh_to_cad (cad_import.h) for a mesh of the CAD input at `path`, read with `options`, through the plugin.
// Throws InputError like load_input (Unsupported when built without the CAD front end).
CadFitReport fit_to_cad_input(const std::string& path, const InputOptions& options, const CadFitOptions& fit_options,
                              TetMesh& mesh);

// MeshOptions::project_to_boundary for the CAD input at `path` (project_onto_cad through the plugin); empty for
// other inputs.
std::function<bool(int, int, Point3&)> cad_projector(const std::string& path, const InputOptions& options);

// measure_against_cad (cad_import.h) for a mesh of the CAD input at `path`, through the plugin.
CadConformity measure_cad_input(const std::string& path, const InputOptions& options, const TetMesh& mesh,
                                const CadMeasureOptions& measure = {});

}  // namespace qualmesh::cli
