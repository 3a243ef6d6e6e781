// `qualmesh mesh IN -o OUT [--radius-edge 2.0] [--max-edge L] [--max-volume V] [--sliver-angle 15] [--omega 0.5]
// [--delta 0.45] [--encroaching all|steiner] [--no-pump] [--no-sliver-insertion] [--sliver-budget F] [--no-improve]`:
// weighted Delaunay refinement of the input PLC (Cheng & Dey, QUALMESH: Rules 1-4, then pumping, then points at the
// slivers pumping left, then the conformity-keeping improvement of the slivers left (beyond the paper, issue 16;
// --no-improve skips it);
// --no-pump stops after Rules 1-3, --no-sliver-insertion after pumping), written to OUT in the format its extension
// names. A CAD input's boundary nodes then go onto its CAD faces and edges (fit_mesh_to_cad), and `--order 2` makes
// 10-node tetrahedra whose mid nodes follow the curved faces. A progress bar on stderr when stderr is a terminal
// (silent otherwise), then a short summary on stdout: counts, quality figures, the CAD fit and time per stage.
// Exit 2 for bad input or usage, 4 for a resource limit; nothing is written then.
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <string>

#include "cli_common.h"
#include "mesh_checks.h"
#include "mesh_limits.h"
#include "qualmesh/error.h"
#include "qualmesh/mesh_check.h"
#include "qualmesh/mesh_io.h"
#include "qualmesh/mesher.h"
#include "qualmesh/plc_io.h"
#include "qualmesh/second_order.h"

namespace qualmesh::cli {

namespace {

struct MeshArgs {
  std::string input;
  std::string output;
  InputOptions input_options;
  MeshOptions options;
  bool verbose = false;
  bool no_pump = false;
  bool no_sliver_insertion = false;
  bool no_improve = false;
  int order = 1;  // 1: 4-node tetrahedra, 2: 10-node (second_order.h)
  MeshLimits limits;  // --time-limit, --max-memory, --allow-partial (mesh_limits.h)
  CLI::Option* sliver_budget = nullptr;  // likewise
};

// After meshing: CAD inputs get their boundary nodes (and mid nodes) onto the CAD faces and edges
// (fit_mesh_to_cad); other inputs are made second order when asked. Returns the summary lines of the fit.
// `corner_fit`: the fit of the corner nodes, when mesh_plc already made it (MeshOptions::before_improve, so that
// the improvement pass works on the fitted mesh); then only the mid nodes are fitted here.
std::string finish_mesh(const MeshArgs& args, TetMesh& mesh, const std::optional<CadFitReport>& corner_fit) {
  const bool cad = has_cad_faces(args.input);
  if (!cad) {
    if (args.order == 2) make_second_order(mesh);
    return "";
  }
  CadFitOptions fit;
  fit.second_order = args.order == 2;
  CadFitReport r;
  if (!corner_fit || fit.second_order) r = fit_to_cad_input(args.input, args.input_options, fit, mesh);
  if (corner_fit) {  // the corners were fitted before the improvement pass: that fit is the one to report
    const CadFitReport mids = r;
    r = *corner_fit;
    r.num_mid_targets = mids.num_mid_targets;
    r.mids = mids.mids;
    r.num_flat_caps_removed += mids.num_flat_caps_removed;
    r.num_curving_caps_removed = mids.num_curving_caps_removed;
    r.num_cap_edges_split = mids.num_cap_edges_split;
    r.num_flat_corners_split = mids.num_flat_corners_split;
  }
  char line[800];
  std::snprintf(line, sizeof line,
                "cad fit:     %zu boundary nodes onto their CAD faces/edges (max offset %.3g): %zu in full (%zu moving "
                "interior nodes too, %zu placing them by a search), %zu part way, %zu not moved (an element would "
                "invert); %zu flat tetrahedra against the boundary removed\n",
                r.num_corner_targets, r.max_offset_before, r.corners.num_full, r.corners.num_dragged,
                r.corners.num_optimised, r.corners.num_partial, r.corners.num_refused, r.num_flat_caps_removed);
  std::string lines = line;
  if (fit.second_order) {
    const double bar = fit.moves.min_jacobian_ratio;
    std::snprintf(line, sizeof line,
                  "curving:     %zu mid nodes onto their CAD faces/edges: %zu in full (%zu moving interior nodes "
                  "too, %zu placing them by a search, %zu elsewhere along their edge, %zu leaving an element below "
                  "%.2g), %zu relaxed toward straight, %zu left straight; min Jacobian ratio %.3g, %zu elements "
                  "below %.2g; %zu flat elements (flat in the straight mesh already); %zu boundary caps removed, "
                  "%zu interior edges of caps and %zu edges opposite flat face corners split so that mid nodes reach "
                  "the surface\n",
                  r.num_mid_targets, r.mids.num_full, r.mids.num_dragged, r.mids.num_optimised,
                  r.mids.num_alternative, r.mids.num_last_resort, bar, r.mids.num_partial, r.mids.num_refused,
                  r.mids.min_jacobian_ratio, r.mids.num_bad_elements, bar, r.mids.num_flat_elements,
                  r.num_curving_caps_removed, r.num_cap_edges_split, r.num_flat_corners_split);
    lines += line;
  }
  return lines;
}

int run_mesh(MeshArgs& args) {
  if (args.no_pump) args.options.pump = false;
  if (args.no_sliver_insertion) args.options.sliver_insertion = false;
  if (args.no_improve) args.options.improve = false;
  double size = 0;  // the target edge length (--size, or a CAD input's default): the engine's too
  std::vector<std::string> notes;  // a surface's repairs (CAD inputs' notes are `info`'s)
  const Plc plc = load_input(args.input, args.input_options, &notes, &size);
  args.options.target_edge_length = size;
  const bool cad = has_cad_faces(args.input);
  // MeshOptions' default encroachment rule is the relaxed one (issue 16's decision; `--encroaching all` keeps the
  // paper's): a CAD input's surface is made for the volume mesher (at equal size about Gmsh's node count instead of
  // 4-7x), and on the 16 surfaces and PLCs of ../shared/data/plc it needs 0.17-1.0x the paper's rule's vertices,
  // mostly less time, and meets every TetGen quality target (minimum dihedral, tets below 10 degrees) the paper's rule
  // meets (README).
  // More points at the slivers pumping leaves: a CAD surface leaves many more (cad_import.h).
  if (cad && args.sliver_budget->count() == 0)
    args.options.sliver_insertion_budget = kCadSliverInsertionBudget;
  // A CAD surface has nothing finer than the smallest size asked for: encroachment splits stop at half of it
  // (MeshOptions::min_split_length), so that a cusp of the model does not draw refinement down to rounding.
  if (cad && size > 0)
    args.options.min_split_length = cad_min_split_length(cad_options_of(args.input_options), size);
  args.options.project_to_boundary = cad_projector(args.input, args.input_options);  // curved CAD faces and edges
  if (!check_mesh_input(plc, args.input, args.options, args.verbose)) return kExitBadInput;  // as `info` validates
  if (!check_size_estimate(plc, args.input, args.options, args.limits, args.verbose)) return kExitResource;  // mesh_limits.h
  args.options.cancel = make_cancel(args.limits);
  std::optional<CadFitReport> corner_fit;
  if (cad)
    args.options.before_improve = [&](TetMesh& mesh) {  // once per solid meshed apart (components.h): summed
      const CadFitReport r = fit_to_cad_input(args.input, args.input_options, CadFitOptions{}, mesh);
      if (!corner_fit) {
        corner_fit = r;
        return;
      }
      CadFitReport& sum = *corner_fit;
      sum.num_corner_targets += r.num_corner_targets;
      sum.max_offset_before = std::max(sum.max_offset_before, r.max_offset_before);
      sum.corners.num_requested += r.corners.num_requested;
      sum.corners.num_full += r.corners.num_full;
      sum.corners.num_dragged += r.corners.num_dragged;
      sum.corners.num_optimised += r.corners.num_optimised;
      sum.corners.num_partial += r.corners.num_partial;
      sum.corners.num_refused += r.corners.num_refused;
      sum.num_fixed_vertices += r.num_fixed_vertices;
      sum.num_flat_caps_removed += r.num_flat_caps_removed;
    };
  const bool tty = isatty(fileno(stderr)) != 0;
  ProgressCallback progress;
  if (tty) {
    progress = [](const ProgressEvent& e) {
      const int width = 30;
      const int filled = int(e.fraction * width + 0.5);
      std::fprintf(stderr, "\r%-10s [%.*s%*s] %3d%% %zu vertices", to_string(e.stage), filled,
                   "##############################", width - filled, "", int(e.fraction * 100 + 0.5),
                   e.num_vertices);
      std::fflush(stderr);
    };
  }
  LogCallback log;
  if (args.verbose) log = [](const std::string& line) { std::cerr << "qualmesh: " << line << "\n"; };
  MeshResult result;
  try {
    result = mesh_plc(plc, args.options, progress, log);
  } catch (const MeshCancelled&) {
    if (tty) std::fprintf(stderr, "\r%70s\r", "");
    std::cerr << "qualmesh: " << args.input << ": error[resource]: " << *args.limits.stopped_by
              << " stopped meshing before the input vertices were triangulated: nothing written\n";
    return kExitResource;
  }
  const bool stopped = report_limit_stop(args.input, args.options, args.limits, result);  // exit 4 below
  if (stopped && !args.limits.allow_partial) return kExitResource;
  if (tty) std::fprintf(stderr, "\r%70s\r", "");
  if (!check_mesh_result(plc, args.input, args.options, result)) return kExitBadInput;  // no tetrahedron
  const std::string fit_lines = finish_mesh(args, result.mesh, corner_fit);
  write_tet_mesh(result.mesh, args.output);
  const MeshStats& st = result.stats;
  std::printf("input:       %zu vertices, %zu facets\n", plc.vertices.size(), plc.facets.size());
  if (is_plc_path(args.input))
    for (const std::string& note : notes) std::printf("source:      %s\n", note.c_str());
  std::printf("output:      %zu vertices (%zu Steiner), %zu tetrahedra, %zu boundary faces\n",
              result.mesh.points.size(), st.num_steiner_vertices, result.mesh.tets.size(), result.mesh.faces.size());
  std::fputs(fit_lines.c_str(), stdout);
  if (st.boundary_projection_dropped)
    std::printf("projection:  meshing with boundary points projected onto the CAD surface gave up (-v says why); "
                "meshed again with them on the facets (the CAD fit moves them)\n");
  if (st.encroaching_fell_back)
    std::printf("encroaching: steiner mode gave up (-v says why); meshed again with the paper's rule\n");
  std::printf("insertions:  rule 1 %zu, rule 2 %zu, rule 3 %zu; %zu centres rejected; %zu small-angle skips; %zu "
              "encroached elements below the split floor kept\n",
              st.num_rule1_insertions, st.num_rule2_insertions, st.num_rule3_insertions,
              st.num_rejected_circumcenters, st.num_skipped_small_angle, st.num_skipped_floor);
  std::printf("quality:     max radius-edge %.4g (bound %.4g), %.4g away from acute input angles; min dihedral %.4g deg\n",
              st.max_radius_edge, args.options.radius_edge_bound, st.max_radius_edge_away_from_acute,
              st.min_dihedral_deg);
  // The reasons are those of the tets the engine left; the improvement pass recounts only the total.
  const std::size_t engine_above = st.num_above_bound_acute + st.num_above_bound_rejected + st.num_above_bound_other;
  if (engine_above == st.num_tets_above_bound)
    std::printf("above bound: %zu tetrahedra: %zu at acute input angles, %zu given up (centre rejected), %zu other\n",
                st.num_tets_above_bound, st.num_above_bound_acute, st.num_above_bound_rejected,
                st.num_above_bound_other);
  else
    std::printf("above bound: %zu tetrahedra after the improvement pass; the engine left %zu: %zu at acute input "
                "angles, %zu given up (centre rejected), %zu other\n",
                st.num_tets_above_bound, engine_above, st.num_above_bound_acute, st.num_above_bound_rejected,
                st.num_above_bound_other);
  std::printf("away from acute input angles: min dihedral %.4g deg, %zu tetrahedra below %.4g deg\n",
              st.min_dihedral_away_from_acute_deg, st.num_tets_below_sliver_angle_away_from_acute,
              args.options.sliver_angle_deg);
  if (is_plc_path(args.input)) {
    // The checker's second line (`qualmesh check --ref`): the same figures for every mesher's output.
    const CheckReport zones = check_protection_zones(result.mesh, plc, 60);
    std::printf("protection:  outside the zones of input angles < 60 deg (%zu sharp vertices, %zu sharp segments; %zu "
                "of %zu tetrahedra inside): min dihedral %.4g deg, %zu/%zu tetrahedra below 10/15 deg\n",
                zones.num_sharp_vertices, zones.num_sharp_segments, zones.num_tets_in_protection_zone,
                zones.num_tets, zones.min_dihedral_outside_protection_deg, zones.num_tets_outside_protection_below_10,
                zones.num_tets_outside_protection_below_15);
  }
  if (cad && size > 0) {
    // The same for a CAD input, around the model's own sharp features (CAD dihedral and face-corner angles below
    // kCadSharpAngleDeg), with --size as the radius: issue 15's goal, no tet below 10 deg outside them, as `qualmesh
    // check MESH --ref MODEL --protection-radius SIZE` and bench_cad_gmsh.py measure it.
    CadMeasureOptions measure;
    measure.distances = false;
    measure.feature_angle_deg = kCadSharpAngleDeg;
    measure.feature_radius = size;
    measure.reuse_shape = true;
    CadConformity c;
    try {
      c = measure_cad_input(args.input, args.input_options, result.mesh, measure);
    } catch (const InputError& e) {  // the mesh is written: a figure of the summary is not worth failing the run for
      std::printf("cad zones:   not measured (%s)\n", e.message().c_str());
    }
    if (c.features_checked) {
      CheckReport zones;
      zones.num_tets = result.mesh.tets.size();
      fill_cad_feature_protection(zones, result.mesh, c.feature_nodes, measure.feature_angle_deg, size,
                                  c.num_sharp_vertices, c.num_sharp_edges);
      std::printf("cad zones:   farther than %.4g from the sharp CAD features (angles < %.4g deg: %zu vertices, %zu "
                  "edges; %zu of %zu tetrahedra inside): min dihedral %.4g deg, %zu/%zu tetrahedra below 10/15 deg\n",
                  size, measure.feature_angle_deg, zones.num_sharp_vertices, zones.num_sharp_segments,
                  zones.num_tets_in_protection_zone, zones.num_tets, zones.min_dihedral_outside_protection_deg,
                  zones.num_tets_outside_protection_below_10, zones.num_tets_outside_protection_below_15);
    }
  }
  if (args.options.pump) {
    std::printf("rule 4:      %zu weighted-encroached elements split, %zu vertices added\n",
                st.num_rule4_encroachments, st.num_rule4_vertices);
    std::printf("pumping:     slivers (min dihedral < %.4g deg) %zu before, %zu after; min dihedral %.4g -> %.4g deg\n",
                args.options.sliver_angle_deg, st.num_slivers_before_pumping, st.num_slivers_after_pumping,
                st.min_dihedral_before_pumping_deg,
                st.seconds_improve > 0 ? st.min_dihedral_before_improve_deg : st.min_dihedral_deg);
    if (args.options.sliver_insertion)
      std::printf("insertion:   %zu points at slivers left by pumping (%zu vertices before pumping, %zu after it); "
                  "%zu slivers without an acceptable point\n",
                  st.num_sliver_insertions, st.num_vertices_before_pumping, st.num_vertices_after_pumping,
                  st.num_sliver_insertions_refused);
    std::printf("weights:     %zu vertices pumped (%zu moves, %zu refused); max weight %.4g, max weight/cap %.4g\n",
                st.num_vertices_pumped, st.num_pump_moves, st.num_pump_rejected, st.max_weight,
                st.max_weight_cap_ratio);
    if (st.seconds_improve > 0)
      std::printf("improve:     %zu tets touched (%zu vertex moves, %zu flips, %zu edge splits), %zu caps removed, min "
                  "dihedral %.4g -> %.4g deg, %.3f s\n",
                  st.num_tets_improved, st.num_improve_vertex_moves, st.num_improve_flips,
                  st.num_improve_insertions, st.num_improve_caps_removed, st.min_dihedral_before_improve_deg,
                  st.min_dihedral_deg,
                  st.seconds_improve);
  }
  std::printf("time (s):    initial %.3f, boundary %.3f, regions %.3f, refinement %.3f, pumping %.3f, extraction %.3f\n",
              st.seconds_initial, st.seconds_boundary, st.seconds_regions, st.seconds_refinement,
              st.seconds_pumping, st.seconds_extraction);
  if (result.status == MeshStatus::VertexLimitReached)
    std::printf("status:      stopped at the vertex limit (%zu)\n", args.options.max_vertices);
  std::fflush(stdout);
  return stopped ? kExitResource : kExitOk;
}

}  // namespace

void register_mesh_command(CLI::App& app, int& exit_code) {
  auto args = std::make_shared<MeshArgs>();
  CLI::App* command = app.add_subcommand("mesh", "Quality tetrahedral mesh of a PLC (weighted Delaunay refinement, Rules 1-4 and pumping)");
  command->add_option("input", args->input, "Input model: CAD (.step .stp .iges .igs .brep .fcstd), OpenSCAD (.scad), or a surface/PLC (.poly .smesh .off .stl .obj .mesh)")->required();
  command->add_option("-o,--output", args->output, "Output mesh, format by extension (.inp .unv .msh .vtu .elmer .mesh .node)")->required();
  add_input_options(*command, args->input_options);
  command->add_option("--radius-edge", args->options.radius_edge_bound,
                      "Radius-edge ratio bound rho0 (default 2.0)");
  command->add_option("--max-edge", args->options.max_edge_length,
                      "Longest edge allowed (default: none; for CAD inputs the --size, or its default)");
  command->add_option("--max-volume", args->options.max_volume, "Largest tetrahedron volume (default: none)");
  command->add_option("--max-vertices", args->options.max_vertices, "Safety stop (default 50,000,000)");
  command->add_option("--sliver-angle", args->options.sliver_angle_deg,
                      "A tetrahedron with a smaller dihedral angle (degrees) is a sliver (default 15)");
  command->add_option("--omega", args->options.omega,
                      "omega0: Rule 4 tests, and pumping caps, weights at omega0^2 f(v)^2 (default 0.5)");
  command->add_option("--delta", args->options.delta,
                      "Pumping caps weights at delta^2 N(v)^2, N: nearest-vertex distance; below 0.5 (default 0.45)");
  command
      ->add_option("--encroaching", args->options.encroaching,
                   "Which vertices inside the diametral ball of a present subsegment or subfacet make Rules 1-2 "
                   "split it: 'steiner' (default: input vertices do not, nor segment vertices near a common input "
                   "vertex) or 'all' (the paper's Rules 1-2 as written, the reference that follows its proofs)")
      ->transform(CLI::CheckedTransformer(
          std::map<std::string, MeshOptions::Encroaching>{{"steiner", MeshOptions::Encroaching::Steiner},
                                                          {"all", MeshOptions::Encroaching::All}},
          CLI::ignore_case));
  command->add_flag("--no-pump", args->no_pump,
                    "Plain Delaunay refinement: no Rule 4, no pumping (all weights zero)");
  command->add_flag("--no-sliver-insertion", args->no_sliver_insertion,
                    "Pumping alone: no points inserted at the slivers it leaves");
  args->sliver_budget = command->add_option(
      "--sliver-budget", args->options.sliver_insertion_budget,
      "Points at the slivers pumping leaves add at most this fraction of plain refinement's vertex count (default "
      "0.048 for surfaces and PLCs, 0.1 for CAD inputs)");
  command->add_flag("--no-improve", args->no_improve,
                    "The engine's weighted Delaunay mesh as is: no vertex moves or flips at the slivers it leaves");
  command->add_option("--order", args->order,
                      "Element order: 1 (4-node tetrahedra, default) or 2 (10-node; mid nodes on curved CAD faces)")
      ->check(CLI::IsMember({1, 2}));
  command->add_flag("-v,--verbose", args->verbose, "Log the stages on stderr");
  add_limit_options(*command, args->limits);  // --time-limit, --max-memory, --allow-partial (mesh_limits.h)
  add_mesh_option_checks(*command);  // ranges and the output format, at parse time (mesh_checks.h)
  command->callback([args, &exit_code] { exit_code = run_mesh(*args); });
}

}  // namespace qualmesh::cli
