// Entry point of the CAD and OpenSCAD front end (cad_import.h): picks the reader by file extension and runs the
// stages read -> heal -> PLC (see cad_private.h).
#include "qualmesh/cad_import.h"

#include <TopoDS_Shape.hxx>

#include "cad_private.h"
#include "qualmesh/error.h"

namespace qualmesh {

bool is_cad_path(const std::string& path) {
  const std::string ext = cad::lower_extension(path);
  for (const char* known : {".step", ".stp", ".iges", ".igs", ".brep", ".brp", ".fcstd", ".scad"})
    if (ext == known) return true;
  return false;
}

CadModel read_cad(const std::string& path, const CadOptions& options) {
  const std::string ext = cad::lower_extension(path);
  if (ext == ".scad") return cad::read_scad_file(path, options);
  std::string format;
  if (ext == ".step" || ext == ".stp") format = "STEP";
  else if (ext == ".iges" || ext == ".igs") format = "IGES";
  else if (ext == ".brep" || ext == ".brp") format = "BREP";
  else if (ext == ".fcstd") format = "FCStd";
  else throw InputError(ErrorCode::Unsupported, "not a CAD file extension: '" + ext + "'", path);

  std::vector<std::string> log;
  TopoDS_Shape shape = format == "FCStd" ? cad::read_fcstd_file(path, log) : cad::read_occt_file(path, format);
  TopoDS_Shape solids = cad::heal_into_solids(shape, options, path, log);
  CadModel model = cad::convert_solids_to_plc(solids, options, path);
  model.summary.source_format = format;
  model.summary.healing_log.insert(model.summary.healing_log.begin(), log.begin(), log.end());
  return model;
}

}  // namespace qualmesh
