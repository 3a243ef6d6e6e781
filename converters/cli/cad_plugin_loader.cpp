// Finds and dlopens the CAD front end plugin once, then calls its one entry point (cad_plugin_loader.h).
#include "cad_plugin_loader.h"

#include <dlfcn.h>

#include <cstdlib>
#include <filesystem>
#include <new>
#include <stdexcept>
#include <system_error>

#include "cad_plugin_abi.h"
#include "qualmesh/error.h"

namespace qualmesh::cli {

namespace {

namespace fs = std::filesystem;

struct PluginHandle {
  cad_plugin::LoadCadFn load_cad = nullptr;  // null when no candidate loaded
  cad_plugin::FitMeshFn fit_mesh = nullptr;
  cad_plugin::MeasureFn measure = nullptr;
  cad_plugin::ProjectFn project = nullptr;   // optional entry point
  std::string failure;                       // why, one "path: reason" per candidate tried
};

std::vector<fs::path> candidate_paths() {
  if (const char* override_path = std::getenv("QUALMESH_CAD_PLUGIN"); override_path && *override_path)
    return {fs::absolute(fs::path(override_path))};  // absolute: dlopen never searches the library path
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (ec) return {};
  const fs::path dir = exe.parent_path();
  return {dir / cad_plugin::kPluginFileName,
          (dir / ".." / "lib" / "qualmesh" / cad_plugin::kPluginFileName).lexically_normal()};
}

PluginHandle open_plugin() {
  PluginHandle handle;
  const std::vector<fs::path> candidates = candidate_paths();
  if (candidates.empty()) handle.failure = "cannot locate the running executable (/proc/self/exe)";
  for (const fs::path& candidate : candidates) {
    if (!handle.failure.empty()) handle.failure += "; ";
    std::error_code ec;
    if (!fs::exists(candidate, ec)) {
      handle.failure += candidate.string() + ": no such file";
      continue;
    }
    // Never closed: the plugin stays loaded for the rest of the run.
    void* library = dlopen(candidate.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!library) {
      handle.failure += dlerror();
      continue;
    }
    void* symbol = dlsym(library, cad_plugin::kLoadCadSymbol);
    void* fit_symbol = dlsym(library, cad_plugin::kFitMeshSymbol);
    void* measure_symbol = dlsym(library, cad_plugin::kMeasureSymbol);
    if (!symbol || !fit_symbol || !measure_symbol) {
      handle.failure += candidate.string() + ": no " +
                        (!symbol ? cad_plugin::kLoadCadSymbol : !fit_symbol ? cad_plugin::kFitMeshSymbol
                                                                            : cad_plugin::kMeasureSymbol) +
                        " (a plugin built from another version of QualMesh)";
      dlclose(library);
      continue;
    }
    handle.load_cad = reinterpret_cast<cad_plugin::LoadCadFn>(symbol);
    handle.fit_mesh = reinterpret_cast<cad_plugin::FitMeshFn>(fit_symbol);
    handle.measure = reinterpret_cast<cad_plugin::MeasureFn>(measure_symbol);
    handle.project = reinterpret_cast<cad_plugin::ProjectFn>(dlsym(library, cad_plugin::kProjectSymbol));
    handle.failure.clear();
    return handle;
  }
  return handle;
}

const PluginHandle& plugin_or_throw(const std::string& path) {
  static const PluginHandle plugin = open_plugin();
  if (!plugin.load_cad)
    throw InputError(ErrorCode::Unsupported,
                     "the CAD front end (OpenCASCADE) is not available: " + plugin.failure +
                         "; install libocct-data-exchange-dev and rebuild",
                     path);
  return plugin;
}

// Rethrows what the plugin caught (LoadResult's statuses); returns on Ok.
void rethrow(cad_plugin::LoadResult& result) {
  switch (result.status) {
    case cad_plugin::LoadStatus::Ok:
      return;
    case cad_plugin::LoadStatus::InputError:
      throw InputError(static_cast<ErrorCode>(result.error_code), result.message, result.file, result.line,
                       std::move(result.ids));
    case cad_plugin::LoadStatus::OutOfMemory:
      throw std::bad_alloc();
    case cad_plugin::LoadStatus::InternalError:
      break;
  }
  throw std::runtime_error(result.message);
}

}  // namespace

Plc read_cad_through_plugin(const std::string& path, const CadOptions& options, std::vector<std::string>* notes,
                            double* size_used) {
  const PluginHandle& plugin = plugin_or_throw(path);
  cad_plugin::LoadResult result;
  plugin.load_cad(path.c_str(), &options, &result);
  rethrow(result);
  if (notes) notes->insert(notes->end(), result.notes.begin(), result.notes.end());
  if (size_used) *size_used = result.size_used;
  return std::move(result.plc);
}

CadFitReport fit_mesh_through_plugin(const std::string& path, const CadOptions& options,
                                     const CadFitOptions& fit_options, TetMesh& mesh) {
  const PluginHandle& plugin = plugin_or_throw(path);
  cad_plugin::FitResult result;
  plugin.fit_mesh(path.c_str(), &options, &fit_options, &mesh, &result);
  rethrow(result.outcome);
  return result.report;
}

CadConformity measure_through_plugin(const std::string& path, const CadOptions& options, const TetMesh& mesh,
                                     const CadMeasureOptions& measure) {
  const PluginHandle& plugin = plugin_or_throw(path);
  cad_plugin::MeasureResult result;
  plugin.measure(path.c_str(), &options, &mesh, &measure, &result);
  rethrow(result.outcome);
  return result.conformity;
}

std::function<bool(int, int, Point3&)> cad_projector_through_plugin(const std::string& path,
                                                                   const CadOptions& options) {
  const PluginHandle& plugin = plugin_or_throw(path);
  if (!plugin.project) return {};
  const cad_plugin::ProjectFn project = plugin.project;
  return [project, path, options](int edge, int face, Point3& p) {
    return project(path.c_str(), &options, edge, face, p.data()) == 1;
  };
}

}  // namespace qualmesh::cli
