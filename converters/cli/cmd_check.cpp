// `qualmesh check MESH [--ref INPUT] [--json] [--require-regular | --no-regularity] [--protection-angle DEG]
// [--protection-radius R] [--no-cad-distance]`: re-checks a tetrahedral mesh from scratch (ours or a peer's: TetGen,
// Gmsh, Medit): orientation, face matching, conformity to the input, the (weighted) Delaunay property (counted; a defect only with
// --require-regular), quality figures, over all tetrahedra and (with a reference) outside the protection zones of
// its sharp input angles (a PLC's) or sharp features (a CAD model's). Exit 3 on defects.
#include <cmath>
#include <cstdio>
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
  double protection_angle = -1;  // not given: kPlcProtectionAngle or kCadSharpAngleDeg, by the reference
  double protection_radius = -1;  // CAD reference; not given: median_edge_length of the mesh
  bool no_cad_distance = false;
};

// The default sharpness thresholds: issue 16's protection zones of a PLC, issue 15's goal for CAD models (no tet
// below 10 degrees anywhere the CAD dihedral angles are 30 degrees or more, cad_import.h).
constexpr double kPlcProtectionAngle = 60;

// A mesh of a CAD model has its boundary nodes on the CAD faces (fit_mesh_to_cad), not on the chords of the
// tessellation that the PLC holds: it is judged against the CAD model itself (measure_against_cad), with the
// checks that need no reference from check_mesh. Adds the findings to `report` and returns the text line.
std::string judge_against_cad(const CheckArgs& args, const TetMesh& mesh, CheckReport& report, std::string& json) {
  CadMeasureOptions measure;
  measure.distances = !args.no_cad_distance;
  measure.feature_angle_deg = args.protection_angle < 0 ? kCadSharpAngleDeg : args.protection_angle;
  measure.feature_radius = args.protection_radius < 0 ? median_edge_length(mesh) : args.protection_radius;
  const CadConformity c = measure_cad_input(args.reference, args.input_options, mesh, measure);
  if (c.features_checked)
    fill_cad_feature_protection(report, mesh, c.feature_nodes, measure.feature_angle_deg, measure.feature_radius,
                                c.num_sharp_vertices, c.num_sharp_edges);
  const double volume_error =
      c.cad_volume > 0 ? std::abs(report.mesh_volume - c.cad_volume) / c.cad_volume : std::nan("");
  char line[400];
  if (measure.distances) {
    std::snprintf(line, sizeof line,
                  "cad conformity: %zu boundary nodes measured, max distance %.3g to their CAD face (%.3g of its "
                  "tolerance), %zu beyond; volume %.10g, CAD volume %.10g, relative error %.3g\n",
                  c.num_nodes, c.max_distance, c.max_relative_to_tolerance, c.num_beyond, report.mesh_volume,
                  c.cad_volume, volume_error);
  } else {
    std::snprintf(line, sizeof line,
                  "cad conformity: boundary nodes not measured (--no-cad-distance); volume %.10g, CAD volume %.10g, "
                  "relative error %.3g\n",
                  report.mesh_volume, c.cad_volume, volume_error);
  }
  char fields[400];
  std::snprintf(fields, sizeof fields,
                "\"cad\": {\"distances_measured\": %s, \"num_nodes\": %zu, \"num_beyond_tolerance\": %zu, "
                "\"max_distance\": %.17g, \"cad_volume\": %.17g, \"volume_relative_error\": %.17g}",
                measure.distances ? "true" : "false", c.num_nodes, c.num_beyond, c.max_distance, c.cad_volume,
                std::isnan(volume_error) ? -1.0 : volume_error);
  json = fields;
  for (const std::string& p : c.problems) report.problems.push_back(p);
  report.num_problems += c.num_beyond;
  // A CAD model's curved faces are polygons in the mesh: the volume agrees to the chordal error, not exactly.
  if (!(volume_error <= 1e-2)) {
    ++report.num_problems;
    report.problems.push_back("mesh volume differs from the CAD volume by more than 1%");
  }
  report.ok = report.num_problems == 0;
  return line;
}

int run_check(const CheckArgs& args) {
  const TetMesh mesh = read_tet_mesh(args.mesh);
  const bool cad_reference = !args.reference.empty() && has_cad_faces(args.reference);
  std::optional<Plc> reference;
  if (!args.reference.empty() && !cad_reference) reference = load_input(args.reference, args.input_options);
  CheckOptions options;
  options.tolerance = args.tolerance;
  options.protection_angle_deg = args.protection_angle < 0 ? kPlcProtectionAngle : args.protection_angle;
  options.regularity = args.no_regularity     ? RegularityCheck::Skip
                       : args.require_regular ? RegularityCheck::Require
                                              : RegularityCheck::Report;
  CheckReport report = check_mesh(mesh, reference ? &*reference : nullptr, options);
  if (cad_reference) {
    std::string json;
    const std::string line = judge_against_cad(args, mesh, report, json);
    if (args.json) {
      std::string text = to_json(report);
      const std::size_t end = text.rfind('}');
      std::cout << text.substr(0, end) << ", " << json << text.substr(end);
    } else {
      std::cout << line << to_text(report);
    }
    std::cout.flush();
    return report.ok ? kExitOk : kExitCheckFailed;
  }
  std::cout << (args.json ? to_json(report) : to_text(report));
  std::cout.flush();
  return report.ok ? kExitOk : kExitCheckFailed;
}

}  // namespace

void register_check_command(CLI::App& app, int& exit_code) {
  auto args = std::make_shared<CheckArgs>();
  CLI::App* command = app.add_subcommand(
      "check", "Check a tetrahedral mesh: orientation, face matching, conformity to --ref, quality figures");
  command->add_option("mesh", args->mesh, "Mesh (.vtu, TetGen .node/.ele, Gmsh .msh, Medit .mesh, Abaqus/CalculiX .inp, UNV .unv)")->required();
  command->add_option("--ref", args->reference, "The input model the mesh must conform to");
  add_input_options(*command, args->input_options);
  command->add_flag("--json", args->json, "Print the report as JSON");
  command->add_option("--tolerance", args->tolerance,
                      "Distance tolerance for 'lies on a facet', relative to the bounding-box diagonal (1e-9)");
  auto* require = command->add_flag(
      "--require-regular", args->require_regular,
      "Count every locally non-regular face (weighted Delaunay test, point array 'weight' of a .vtu) as a defect");
  command->add_option("--protection-angle", args->protection_angle,
                      "With --ref: input angles below this (degrees) are sharp; quality is also reported outside "
                      "their protection zones (0: not). A CAD model's sharp features are its dihedral angles and "
                      "face corners below it (default 60 for a PLC, 30 for a CAD model)")
      ->check(CLI::Range(0.0, 180.0));
  command->add_option("--protection-radius", args->protection_radius,
                      "With a CAD --ref: the zone is the points within this distance (model units) of a sharp "
                      "feature (default: the mesh's median edge length; give the --size both meshers had to compare "
                      "two meshes of one model)")
      ->check(CLI::NonNegativeNumber);
  command->add_flag("--no-cad-distance", args->no_cad_distance,
                    "With a CAD --ref: do not measure boundary nodes against their CAD faces (for a mesh whose face "
                    "numbers are not the model's, e.g. Gmsh's); the volume and sharp features are still checked");
  command->add_flag("--no-regularity", args->no_regularity, "Skip the weighted Delaunay test")->excludes(require);
  command->callback([args, &exit_code] { exit_code = run_check(*args); });
}

}  // namespace qualmesh::cli
