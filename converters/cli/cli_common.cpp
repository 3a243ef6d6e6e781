// Input loading shared by the subcommands: PLC formats through read_plc, CAD and OpenSCAD through read_cad in the CAD
// front end plugin (cad_plugin_loader.h) when it was built.
#include "cli_common.h"

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <map>

#include "qualmesh/error.h"
#include "qualmesh/plc_io.h"
#if QUALMESH_WITH_CAD
#include "cad_plugin_loader.h"
#endif
#include "mesh_checks.h"

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

// "Face3=0.5" -> {Face, 3, 0.5}; what is wrong otherwise (empty when fine).
std::string local_size_problem(const std::string& text, CadLocalSize* out) {
  static const std::pair<const char*, CadLocalSize::Kind> kinds[] = {
      {"Face", CadLocalSize::Kind::Face}, {"Edge", CadLocalSize::Kind::Edge}, {"Solid", CadLocalSize::Kind::Solid}};
  const std::string usage = "expected NAME=SIZE with NAME Face<n>, Edge<n> or Solid<n> (FreeCAD's names, n >= 1) "
                            "and SIZE a finite length > 0, e.g. Face3=0.5; got '" + text + "'";
  const auto equals = text.find('=');
  if (equals == std::string::npos) return usage;
  const std::string name = text.substr(0, equals), value = text.substr(equals + 1);
  for (const auto& [prefix, kind] : kinds) {
    const std::string p = prefix;
    if (name.size() <= p.size() || name.compare(0, p.size(), p) != 0) continue;
    const std::string digits = name.substr(p.size());
    if (digits.size() > 9 || digits[0] == '0' ||
        digits.find_first_not_of("0123456789") != std::string::npos)
      return usage;
    char* end = nullptr;
    const double size = std::strtod(value.c_str(), &end);
    if (value.empty() || *end != '\0' || !std::isfinite(size) || !(size > 1e-150)) return usage;
    if (out) *out = {kind, std::stoi(digits), size};
    return {};
  }
  return usage;
}

CadLocalSize parse_local_size(const std::string& text) {
  CadLocalSize local;
  const std::string problem = local_size_problem(text, &local);
  if (!problem.empty()) throw InputError(ErrorCode::Unsupported, "--local-size: " + problem);
  return local;
}

// A finite number above `lo` (or at least `lo` when closed), for the size options.
CLI::Validator finite_above(double lo, bool closed, const std::string& what) {
  return CLI::Validator(
      [lo, closed, what](std::string& text) -> std::string {
        char* end = nullptr;
        const double x = std::strtod(text.c_str(), &end);
        if (text.empty() || *end != '\0' || !std::isfinite(x) || (closed ? x < lo : !(x > lo)))
          return "expected a finite number " + what + ", got '" + text + "'";
        return {};
      },
      "");
}

}  // namespace

CadOptions cad_options_of(const InputOptions& options) {
  CadOptions cad_options;
  cad_options.deflection = options.deflection;
  cad_options.relative_deflection = options.relative_deflection;
  cad_options.surface_mesh = options.cad_surface;
  cad_options.size = options.size;
  cad_options.min_size = options.min_size;
  cad_options.curvature_elements = options.curvature;
  cad_options.gradation = options.gradation;
  for (const std::string& text : options.local_sizes) cad_options.local_sizes.push_back(parse_local_size(text));
  cad_options.sewing_tolerance = options.sewing_tolerance;
  return cad_options;
}

void add_size_options(CLI::App& command, InputOptions& options);  // below

void add_input_options(CLI::App& command, InputOptions& options) {
  command.add_flag("--keep-triangles", options.keep_triangles,
                   "Surface inputs: keep every triangle as its own facet (default: merge adjacent coplanar "
                   "triangles into polygonal facets)");
  command
      .add_option("--coplanar-tolerance", options.coplanar_tolerance,
                  "Surface and TetGen inputs: also merge adjacent facets that are coplanar only up to this fraction of "
                  "the bounding-box diagonal, as TetGen merges triangles within 0.1 deg of coplanar (e.g. 1e-6, the "
                  "planarity tolerance of validation). Needle triangles of flat faces that rounding bent a hair then "
                  "stop being sharp input angles; the mesh boundary lies within that distance of the input instead "
                  "of exactly on it (default 0: exactly coplanar facets only)")
      ->check(coplanar_tolerance_check());
  command.add_option("--deflection", options.deflection,
                     "CAD inputs with --cad-surface tessellation: absolute chordal deflection of curved faces, in "
                     "model units (default: relative)");
  command.add_option("--relative-deflection", options.relative_deflection,
                     "CAD inputs with --cad-surface tessellation: chordal deflection relative to the bounding-box "
                     "diagonal (default 0.001)");
  add_size_options(command, options);
  command.add_option("--sewing-tolerance", options.sewing_tolerance,
                     "CAD inputs: sewing tolerance in model units, for a model whose faces do not quite meet "
                     "(default: automatic, 1e-6 of the bounding-box diagonal or the model's own vertex tolerance, "
                     "at most 1e-4 of the diagonal)");
}

void add_size_options(CLI::App& command, InputOptions& options) {
  command.add_option("--size", options.size,
                     "Target edge length in model units (Gmsh's CharacteristicLengthMax): CAD inputs get their "
                     "surface meshed at it, and the volume mesher splits tetrahedra with an edge above twice it "
                     "(about Gmsh's node count at the same value); default for CAD inputs a tenth of the "
                     "bounding-box diagonal (Gmsh's default at CAD vertices), none for surfaces")
      ->check(finite_above(1e-150, false, "> 0 (model units)"));
  command.add_option("--min-size", options.min_size,
                     "CAD inputs: smallest edge length the curvature refinement may ask for (Gmsh's "
                     "CharacteristicLengthMin; default a 30th of --size)")
      ->check(finite_above(1e-150, false, "> 0 (model units)"));
  command.add_option("--curvature", options.curvature,
                     "CAD inputs: elements per full circle of a curved edge or face (a hole or fillet of radius R "
                     "gets edges of at most 2 pi R / N); 0 disables (default 12)")
      ->check(finite_above(0, true, ">= 0 (elements per full circle; 0 disables)") &
              CLI::Validator([](std::string& text) {
                return std::strtod(text.c_str(), nullptr) > 10000 ? "at most 10000 elements per circle" : "";
              }, ""));
  command.add_option("--gradation", options.gradation,
                     "CAD inputs: largest ratio between the sizes of two faces that share an edge, > 1 (default: "
                     "no limit)")
      ->check(finite_above(1, false, "> 1 (a ratio of sizes)"));
  command.add_option("--local-size", options.local_sizes,
                     "CAD inputs, repeatable: NAME=SIZE, a target edge length on one CAD entity named as FreeCAD "
                     "and the output groups name it: Face<n>, Edge<n>, Solid<n> (e.g. --local-size Face3=0.5)")
      ->check(CLI::Validator([](std::string& text) { return local_size_problem(text, nullptr); }, "NAME=SIZE"));
  command
      .add_option("--cad-surface", options.cad_surface,
                   "CAD inputs: 'sized' (default: edges and faces meshed at the size field, every node on the CAD "
                   "surface) or 'tessellation' (OpenCASCADE's chordal tessellation at --deflection, as before "
                   "the size field; the size options are then ignored)")
      ->transform(CLI::CheckedTransformer(std::map<std::string, CadSurfaceMesh>{{"sized", CadSurfaceMesh::Sized},
                                                                                {"tessellation",
                                                                                 CadSurfaceMesh::Tessellation}},
                                          CLI::ignore_case));
}

Plc load_input(const std::string& path, const InputOptions& options, std::vector<std::string>* notes,
               double* cad_size_used) {
  if (cad_size_used) *cad_size_used = 0;
  if (is_plc_path(path)) {
    if (cad_size_used && options.size > 0) *cad_size_used = options.size;
    ReadOptions read_options;
    read_options.merge_coplanar = !options.keep_triangles;
    read_options.coplanar_tolerance = options.coplanar_tolerance;
    return read_plc(path, read_options, notes);
  }
  if (is_cad_input(path)) {
    require_regular_input_file(path);  // a directory or FIFO named .step is refused as the PLC readers refuse it
#if QUALMESH_WITH_CAD
    return read_cad_through_plugin(path, cad_options_of(options), notes, cad_size_used);
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

std::function<bool(int, int, Point3&)> cad_projector(const std::string& path, const InputOptions& options) {
#if QUALMESH_WITH_CAD
  return has_cad_faces(path) ? cad_projector_through_plugin(path, cad_options_of(options))
                             : std::function<bool(int, int, Point3&)>{};
#else
  (void)path, (void)options;
  return {};
#endif
}

CadConformity measure_cad_input(const std::string& path, const InputOptions& options, const TetMesh& mesh,
                                const CadMeasureOptions& measure) {
  require_regular_input_file(path);
#if QUALMESH_WITH_CAD
  return measure_through_plugin(path, cad_options_of(options), mesh, measure);
#else
  (void)options, (void)mesh, (void)measure;
  throw InputError(ErrorCode::Unsupported, "this qualmesh was built without the CAD front end (OpenCASCADE)", path);
#endif
}

}  // namespace qualmesh::cli
