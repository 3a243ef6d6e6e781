// Input loading shared by the subcommands.
#include "cli_common.h"

#include "qualmesh/error.h"
#include "qualmesh/plc_io.h"

namespace qualmesh::cli {

void add_input_options(CLI::App& command, InputOptions& options) {
  command.add_flag("--keep-triangles", options.keep_triangles,
                   "Surface inputs: keep every triangle as its own facet (default: merge adjacent coplanar "
                   "triangles into polygonal facets)");
}

Plc load_input(const std::string& path, const InputOptions& options) {
  if (is_plc_path(path)) {
    ReadOptions read_options;
    read_options.merge_coplanar = !options.keep_triangles;
    return read_plc(path, read_options);
  }
  throw InputError(ErrorCode::Unsupported,
                   "unknown input format (expected .poly, .smesh, .node, .off, .stl, .obj or .mesh)", path);
}

}  // namespace qualmesh::cli
