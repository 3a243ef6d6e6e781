// Entry point of the CAD and OpenSCAD front end (cad_import.h): picks the reader by file extension and runs the
// stages read -> heal -> PLC (see cad_private.h), and checks a sized surface mesh (validate_plc) before it goes out.
#include "qualmesh/cad_import.h"

#include <Standard_Failure.hxx>
#include <TopoDS_Shape.hxx>

#include "cad_private.h"
#include "qualmesh/error.h"
#include "qualmesh/plc_validate.h"

namespace qualmesh {

bool is_cad_path(const std::string& path) {
  const std::string ext = cad::lower_extension(path);
  for (const char* known : {".step", ".stp", ".iges", ".igs", ".brep", ".brp", ".fcstd", ".scad"})
    if (ext == known) return true;
  return false;
}

namespace cad {
namespace {

// The healed solids of the last CAD file read_cad() read in this process, for fit_mesh_to_cad() (cad_fit.cpp), which
// needs the CAD faces of the model just meshed. Keyed by the file and the healing options; one entry.
struct HealedCache {
  std::string path;
  bool heal = true;
  double sewing_tolerance = 0;
  TopoDS_Shape solids;
  std::string format;
};
HealedCache& healed_cache() {
  static HealedCache cache;
  return cache;
}

std::string cad_format(const std::string& path) {
  const std::string ext = lower_extension(path);
  if (ext == ".step" || ext == ".stp") return "STEP";
  if (ext == ".iges" || ext == ".igs") return "IGES";
  if (ext == ".brep" || ext == ".brp") return "BREP";
  if (ext == ".fcstd") return "FCStd";
  throw InputError(ErrorCode::Unsupported, "not a CAD file extension: '" + ext + "'", path);
}

}  // namespace

TopoDS_Shape read_healed_solids(const std::string& path, const CadOptions& options, std::vector<std::string>& log,
                                bool use_cache) {
  HealedCache& cache = healed_cache();
  if (use_cache && !cache.solids.IsNull() && cache.path == path && cache.heal == options.heal &&
      cache.sewing_tolerance == options.sewing_tolerance)
    return cache.solids;
  const std::string format = cad_format(path);
  TopoDS_Shape shape = format == "FCStd" ? read_fcstd_file(path, log) : read_occt_file(path, format);
  TopoDS_Shape solids = heal_into_solids(shape, options, path, log);
  cache = {path, options.heal, options.sewing_tolerance, solids, format};
  return solids;
}

}  // namespace cad

CadModel read_cad(const std::string& path, const CadOptions& options) {
  const std::string ext = cad::lower_extension(path);
  if (ext == ".scad") return cad::read_scad_file(path, options);
  std::vector<std::string> log;
  const TopoDS_Shape solids = cad::read_healed_solids(path, options, log, /*use_cache=*/false);
  CadModel model;
  std::string why;  // why the sized surface mesh is not used
  try {
    model = cad::convert_solids_to_plc(solids, options, path);
  } catch (const InputError& e) {
    // A bad option (a local size on an entity that does not exist) is the user's to fix, not a reason to fall back.
    if (options.surface_mesh != CadSurfaceMesh::Sized || e.code() == ErrorCode::IndexOutOfRange) throw;
    why = e.message();  // bottle.brep: no region seed clear of a thin wall by twice the chordal error
  }
  if (options.surface_mesh == CadSurfaceMesh::Sized) {
    // The sized surface mesh must be a valid PLC; where it is not (two curved faces' triangles cross where the
    // faces nearly touch, more than their chordal error apart from the CAD), or where it could not be made, the
    // model is tessellated as before, keeping the size for the volume mesh, and the summary says why.
    if (why.empty()) {
      const ValidationReport report = validate_plc(model.plc);
      if (!report.ok()) why = report.problems.front().message;
    }
    if (!why.empty()) {
      CadOptions fallback = options;
      fallback.surface_mesh = CadSurfaceMesh::Tessellation;
      const double size = model.summary.size_used > 0 ? model.summary.size_used : options.size;
      model = cad::convert_solids_to_plc(solids, fallback, path);
      model.summary.size_used = size;
      model.summary.surface_fallback = "no sized surface mesh (" + why +
                                       "): curved faces tessellated at the chordal deflection instead";
    }
  }
  model.summary.source_format = cad::cad_format(path);
  try {
    model.summary.sharp_features =
        cad::describe_sharp_features(cad::list_sharp_features(solids, kCadSharpAngleDeg), kCadSharpAngleDeg);
  } catch (const Standard_Failure&) {
    model.summary.sharp_features = "sharp features: not measured (OpenCASCADE failed)";
  }
  model.summary.healing_log.insert(model.summary.healing_log.begin(), log.begin(), log.end());
  return model;
}

}  // namespace qualmesh
