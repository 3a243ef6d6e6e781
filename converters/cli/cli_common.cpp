// Input loading shared by the subcommands: PLC formats through read_plc, CAD and OpenSCAD through read_cad in the CAD
// front end plugin (cad_plugin_loader.h) when it was built.
#include "cli_common.h"

#include <cctype>

#include "qualmesh/error.h"
#include "qualmesh/plc_io.h"
#if QUALMESH_WITH_CAD
#include "cad_plugin_loader.h"
#endif

namespace qualmesh::cli {

namespace {

std::string lower_extension(const std::string& path) {
  const auto dot = path.rfind('.');
  if (dot == std::string::npos) return "";
  std::string ext = path.substr(dot + 1);
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

bool has_cad_extension(const std::string& path) {
  const std::string ext = lower_extension(path);
  for (const char* known : {"step", "stp", "iges", "igs", "brep", "brp", "fcstd", "scad"}) {
    if (ext == known) return true;
  }
  return false;
}

CadOptions cad_options_of(const InputOptions& options) {
  CadOptions cad_options;
  cad_options.deflection = options.deflection;
  cad_options.relative_deflection = options.relative_deflection;
  return cad_options;
}

}  // namespace

void add_input_options(CLI::App& command, InputOptions& options) {
  command.add_flag("--keep-triangles", options.keep_triangles,
                   "Surface inputs: keep every triangle as its own facet (default: merge adjacent coplanar "
                   "triangles into polygonal facets)");
  command.add_option("--deflection", options.deflection,
                     "CAD inputs: absolute chordal deflection of curved faces, in model units (default: relative)");
  command.add_option("--relative-deflection", options.relative_deflection,
                     "CAD inputs: chordal deflection relative to the bounding-box diagonal (default 0.001)");
}

Plc load_input(const std::string& path, const InputOptions& options, std::vector<std::string>* notes) {
  if (is_plc_path(path)) {
    ReadOptions read_options;
    read_options.merge_coplanar = !options.keep_triangles;
    return read_plc(path, read_options);
  }
  if (is_cad_input(path)) {
#if QUALMESH_WITH_CAD
    return read_cad_through_plugin(path, cad_options_of(options), notes);
#else
    (void)notes;
    throw InputError(ErrorCode::Unsupported,
                     "this qualmesh was built without the CAD front end (OpenCASCADE); install "
                     "libocct-data-exchange-dev and rebuild",
                     path);
#endif
  }
  throw InputError(ErrorCode::Unsupported,
                   "unknown input format (expected .poly .smesh .node .off .stl .obj .mesh, or CAD: .step .stp "
                   ".iges .igs .brep .fcstd .scad)",
                   path);
}

bool is_cad_input(const std::string& path) { return has_cad_extension(path); }

bool has_cad_faces(const std::string& path) { return has_cad_extension(path) && lower_extension(path) != "scad"; }

CadFitReport fit_to_cad_input(const std::string& path, const InputOptions& options, const CadFitOptions& fit_options,
                              TetMesh& mesh) {
#if QUALMESH_WITH_CAD
  return fit_mesh_through_plugin(path, cad_options_of(options), fit_options, mesh);
#else
  (void)options, (void)fit_options, (void)mesh;
  throw InputError(ErrorCode::Unsupported, "this qualmesh was built without the CAD front end (OpenCASCADE)", path);
#endif
}

CadConformity measure_cad_input(const std::string& path, const InputOptions& options, const TetMesh& mesh) {
#if QUALMESH_WITH_CAD
  return measure_through_plugin(path, cad_options_of(options), mesh);
#else
  (void)options, (void)mesh;
  throw InputError(ErrorCode::Unsupported, "this qualmesh was built without the CAD front end (OpenCASCADE)", path);
#endif
}

}  // namespace qualmesh::cli
