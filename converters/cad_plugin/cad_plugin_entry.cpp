// Entry point of libqualmesh_cad_plugin.so (cad_plugin_abi.h): runs read_cad and turns its outcome, the PLC and the
// summary lines or the exception, into a LoadResult, so that no exception crosses the dlopen boundary. The CLI
// rebuilds an identical InputError from the fields, so messages and exit codes are those of a statically linked
// front end.
#include <cstdio>
#include <exception>
#include <new>
#include <type_traits>

#include "cad_plugin_abi.h"

namespace qualmesh::cad_plugin {

namespace {

// The lines `qualmesh info` prints about a CAD source.
std::vector<std::string> summary_notes(const CadSummary& s) {
  std::vector<std::string> notes;
  char line[200];
  std::snprintf(line, sizeof line, "%s model: %zu solids, %zu faces, %zu edges, %zu vertices",
                s.source_format.c_str(), s.num_solids, s.num_faces, s.num_edges, s.num_vertices);
  notes.push_back(line);
  for (std::size_t i = 0; i < s.solid_volumes.size(); ++i) {
    std::snprintf(line, sizeof line, "Solid%zu: volume %.10g", i + 1, s.solid_volumes[i]);
    notes.push_back(line);
  }
  if (!s.surface_fallback.empty()) {
    std::snprintf(line, sizeof line, "curved faces tessellated with chordal deflection %.4g (target edge length %.4g)",
                  s.deflection_used, s.size_used);
    notes.push_back(line);
    notes.push_back("note: " + s.surface_fallback);
  } else if (s.size_used > 0) {
    std::snprintf(line, sizeof line, "sized surface mesh: target edge length %.4g, largest chordal error %.4g",
                  s.size_used, s.deflection_used);
    notes.push_back(line);
  } else if (s.deflection_used > 0) {
    std::snprintf(line, sizeof line, "curved faces tessellated with chordal deflection %.4g", s.deflection_used);
    notes.push_back(line);
  }
  if (!s.sharp_features.empty()) notes.push_back(s.sharp_features);
  for (const std::string& line : s.surface_log) notes.push_back("surface: " + line);
  for (const std::string& healed : s.healing_log) notes.push_back("healed: " + healed);
  return notes;
}

}  // namespace

}  // namespace qualmesh::cad_plugin

namespace qualmesh::cad_plugin {
namespace {

// Runs `work` and turns what it throws into the fields of `result` (LoadResult's statuses).
template <class Work>
void guarded(LoadResult* result, Work&& work) noexcept {
  try {
    work();
    result->status = LoadStatus::Ok;
  } catch (const InputError& e) {
    result->status = LoadStatus::InputError;
    result->error_code = static_cast<int>(e.code());
    result->message = e.message();
    result->file = e.file();
    result->line = e.line();
    result->ids = e.ids();
  } catch (const std::bad_alloc&) {
    result->status = LoadStatus::OutOfMemory;
  } catch (const std::exception& e) {
    result->status = LoadStatus::InternalError;
    result->message = e.what();
  } catch (...) {
    result->status = LoadStatus::InternalError;
    result->message = "the CAD front end threw an exception that is not a std::exception";
  }
}

}  // namespace
}  // namespace qualmesh::cad_plugin

extern "C" __attribute__((visibility("default"))) void qualmesh_cad_plugin_load_cad_v2(
    const char* path, const qualmesh::CadOptions* options, qualmesh::cad_plugin::LoadResult* result) noexcept {
  using namespace qualmesh;
  // Checked against the declaration the CLI uses: a changed signature must change the versioned name too.
  static_assert(std::is_same_v<decltype(&qualmesh_cad_plugin_load_cad_v2), cad_plugin::LoadCadFn>);
  cad_plugin::guarded(result, [&] {
    CadModel model = read_cad(path, *options);
    result->notes = cad_plugin::summary_notes(model.summary);
    result->size_used = model.summary.size_used;
    result->plc = std::move(model.plc);
  });
}

extern "C" __attribute__((visibility("default"))) void qualmesh_cad_plugin_fit_mesh_v3(
    const char* path, const qualmesh::CadOptions* options, const qualmesh::CadFitOptions* fit_options,
    qualmesh::TetMesh* mesh, qualmesh::cad_plugin::FitResult* result) noexcept {
  using namespace qualmesh;
  static_assert(std::is_same_v<decltype(&qualmesh_cad_plugin_fit_mesh_v3), cad_plugin::FitMeshFn>);
  cad_plugin::guarded(&result->outcome, [&] { result->report = fit_mesh_to_cad(path, *options, *mesh, *fit_options); });
}

extern "C" __attribute__((visibility("default"))) void qualmesh_cad_plugin_measure_v4(
    const char* path, const qualmesh::CadOptions* options, const qualmesh::TetMesh* mesh,
    const qualmesh::CadMeasureOptions* measure, qualmesh::cad_plugin::MeasureResult* result) noexcept {
  using namespace qualmesh;
  static_assert(std::is_same_v<decltype(&qualmesh_cad_plugin_measure_v4), cad_plugin::MeasureFn>);
  cad_plugin::guarded(&result->outcome,
                      [&] { result->conformity = measure_against_cad(path, *options, *mesh, *measure); });
}

extern "C" __attribute__((visibility("default"))) int qualmesh_cad_plugin_project_v2(
    const char* path, const qualmesh::CadOptions* options, int edge, int face, double* xyz) noexcept {
  using namespace qualmesh;
  static_assert(std::is_same_v<decltype(&qualmesh_cad_plugin_project_v2), cad_plugin::ProjectFn>);
  try {
    Point3 p{xyz[0], xyz[1], xyz[2]};
    if (!project_onto_cad(path, *options, edge, face, p)) return 0;
    xyz[0] = p[0], xyz[1] = p[1], xyz[2] = p[2];
    return 1;
  } catch (...) {
    return 0;
  }
}
