// `qualmesh check MESH [--ref INPUT] [--json] [--require-regular | --no-regularity]`: re-checks a tetrahedral mesh
// from scratch (ours or a peer's: TetGen, Gmsh, Medit): orientation, face matching, conformity to the input, the
// (weighted) Delaunay property (counted; a defect only with --require-regular), quality figures. Exit 3 on defects.
#include <iostream>
#include <memory>
#include <optional>
#include <string>

#include "cli_common.h"
#include "qualmesh/mesh_check.h"
#include "qualmesh/mesh_io.h"

namespace qualmesh::cli {

namespace {

struct CheckArgs {
  std::string mesh;
  std::string reference;
  InputOptions input_options;
  bool json = false;
  double tolerance = 1e-9;
  bool require_regular = false;
  bool no_regularity = false;
};

int run_check(const CheckArgs& args) {
  const TetMesh mesh = read_tet_mesh(args.mesh);
  std::optional<Plc> reference;
  if (!args.reference.empty()) reference = load_input(args.reference, args.input_options);
  CheckOptions options;
  options.tolerance = args.tolerance;
  options.regularity = args.no_regularity     ? RegularityCheck::Skip
                       : args.require_regular ? RegularityCheck::Require
                                              : RegularityCheck::Report;
  const CheckReport report = check_mesh(mesh, reference ? &*reference : nullptr, options);
  std::cout << (args.json ? to_json(report) : to_text(report));
  std::cout.flush();
  return report.ok ? kExitOk : kExitCheckFailed;
}

}  // namespace

void register_check_command(CLI::App& app, int& exit_code) {
  auto args = std::make_shared<CheckArgs>();
  CLI::App* command = app.add_subcommand(
      "check", "Check a tetrahedral mesh: orientation, face matching, conformity to --ref, quality figures");
  command->add_option("mesh", args->mesh, "Mesh (.vtu, TetGen .node/.ele, Gmsh .msh, Medit .mesh)")->required();
  command->add_option("--ref", args->reference, "The input model the mesh must conform to");
  add_input_options(*command, args->input_options);
  command->add_flag("--json", args->json, "Print the report as JSON");
  command->add_option("--tolerance", args->tolerance,
                      "Distance tolerance for 'lies on a facet', relative to the bounding-box diagonal (1e-9)");
  auto* require = command->add_flag(
      "--require-regular", args->require_regular,
      "Count every locally non-regular face (weighted Delaunay test, point array 'weight' of a .vtu) as a defect");
  command->add_flag("--no-regularity", args->no_regularity, "Skip the weighted Delaunay test")->excludes(require);
  command->callback([args, &exit_code] { exit_code = run_check(*args); });
}

}  // namespace qualmesh::cli
