// `qualmesh convert IN OUT`: any reader to any writer that fits. PLC to PLC (.poly .smesh .off), mesh to mesh
// (.vtu .node/.ele .msh .mesh .inp). Nothing is written when reading fails; writers replace OUT atomically.
#include <iostream>
#include <memory>
#include <string>

#include "cli_common.h"
#include "qualmesh/error.h"
#include "qualmesh/mesh_io.h"
#include "qualmesh/plc_io.h"

namespace qualmesh::cli {

namespace {

struct ConvertArgs {
  std::string input;
  std::string output;
  InputOptions input_options;
};

bool is_plc_output(const std::string& path) {
  const auto dot = path.rfind('.');
  if (dot == std::string::npos) return false;
  std::string ext = path.substr(dot);
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".poly" || ext == ".smesh" || ext == ".off";
}

int run_convert(const ConvertArgs& args) {
  if (is_plc_output(args.output)) {
    const Plc plc = load_input(args.input, args.input_options);
    write_plc(plc, args.output);
  } else if (is_mesh_path(args.output)) {
    if (!is_mesh_path(args.input)) {
      throw InputError(ErrorCode::Unsupported,
                       "a volume mesh output needs a volume mesh input; to mesh a model use `qualmesh mesh`",
                       args.input);
    }
    const TetMesh mesh = read_tet_mesh(args.input);
    write_tet_mesh(mesh, args.output);
  } else {
    throw InputError(ErrorCode::Unsupported,
                     "unknown output format (PLC: .poly .smesh .off; mesh: .vtu .ele .msh .mesh .inp)", args.output);
  }
  std::cerr << "qualmesh: wrote " << args.output << "\n";
  return kExitOk;
}

}  // namespace

void register_convert_command(CLI::App& app, int& exit_code) {
  auto args = std::make_shared<ConvertArgs>();
  CLI::App* command = app.add_subcommand("convert", "Convert between PLC formats or between mesh formats");
  command->add_option("input", args->input, "Input file")->required();
  command->add_option("output", args->output, "Output file (format from its extension)")->required();
  add_input_options(*command, args->input_options);
  command->callback([args, &exit_code] { exit_code = run_convert(*args); });
}

}  // namespace qualmesh::cli
