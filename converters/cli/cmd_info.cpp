// `qualmesh info INPUT`: what the input holds (counts, bounding box), whether it is a valid PLC (paper Section 2)
// and which input angles are acute. Exit 2 when the input cannot be read or is not a valid PLC.
#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

#include "cli_common.h"
#include "qualmesh/error.h"
#include "qualmesh/plc_validate.h"

namespace qualmesh::cli {

namespace {

struct InfoArgs {
  std::string input;
  InputOptions input_options;
  double acute_threshold_deg = 90.0;
  std::size_t max_listed = 10;
};

std::string format_point(const Point3& p) {
  char text[96];
  std::snprintf(text, sizeof text, "(%.6g, %.6g, %.6g)", p[0], p[1], p[2]);
  return text;
}

const char* angle_kind_name(AngleKind kind) {
  switch (kind) {
    case AngleKind::SegmentSegment: return "segment-segment";
    case AngleKind::SegmentFacet: return "segment-facet";
    case AngleKind::FacetFacet: return "facet-facet";
  }
  return "?";
}

std::string describe_angle(const InputAngle& angle) {
  char text[200];
  switch (angle.kind) {
    case AngleKind::SegmentSegment:
      std::snprintf(text, sizeof text, "segments %u and %u at vertex %u", angle.first, angle.second,
                    angle.apex_vertex);
      break;
    case AngleKind::SegmentFacet:
      std::snprintf(text, sizeof text, "segment %u and facet %u at vertex %u", angle.first, angle.second,
                    angle.apex_vertex);
      break;
    case AngleKind::FacetFacet:
      std::snprintf(text, sizeof text, "facets %u and %u along a segment at vertex %u", angle.first, angle.second,
                    angle.apex_vertex);
      break;
  }
  return text;
}

int run_info(const InfoArgs& args) {
  std::vector<std::string> notes;
  const Plc plc = load_input(args.input, args.input_options, &notes);
  std::size_t num_polygons = 0, num_facet_holes = 0;
  for (const Facet& f : plc.facets) {
    num_polygons += f.polygons.size();
    num_facet_holes += f.holes.size();
  }
  const BoundingBox box = bounding_box(plc);
  std::cout << "file:         " << args.input << "\n";
  for (const std::string& note : notes) std::cout << "source:       " << note << "\n";
  std::cout             << "vertices:     " << plc.vertices.size() << "\n"
            << "segments:     " << collect_segments(plc).size() << " (" << plc.segments.size() << " explicit)\n"
            << "facets:       " << plc.facets.size() << " (" << num_polygons << " polygons, " << num_facet_holes
            << " facet hole points)\n"
            << "regions:      " << plc.regions.size() << " seeds, " << plc.holes.size() << " hole seeds\n";
  if (!box.empty()) {
    std::printf("bounding box: %s - %s, diagonal %.6g\n", format_point(box.min).c_str(),
                format_point(box.max).c_str(), box.diagonal());
  }
  std::cout.flush();

  ValidateOptions options;
  options.acute_threshold_deg = args.acute_threshold_deg;
  const ValidationReport report = validate_plc(plc, options);
  std::printf("closed:       %s\n", report.closed ? "yes" : "no");
  if (report.ok()) {
    std::printf("validation:   ok\n");
  } else {
    std::printf("validation:   INVALID:");
    for (const ProblemCount& pc : report.problem_counts) std::printf(" %zu %s", pc.count, to_string(pc.code));
    std::printf("\n");
    for (const Problem& p : report.problems) std::printf("  %s: %s\n", to_string(p.code), p.message.c_str());
  }
  // Per kind first: on triangulated surfaces every triangle corner is a segment-segment input angle, so the
  // facet-facet figure is the one that says whether the model has sharp edges.
  std::printf("input angles: min %.4g deg; %zu below %.4g deg\n", report.min_input_angle_deg,
              report.num_acute_angles, args.acute_threshold_deg);
  for (AngleKind kind : {AngleKind::FacetFacet, AngleKind::SegmentFacet, AngleKind::SegmentSegment}) {
    const auto k = static_cast<std::size_t>(kind);
    std::printf("  %-15s min %8.4f deg, %zu below %.4g deg\n", angle_kind_name(kind),
                report.min_angle_deg_by_kind[k], report.num_acute_by_kind[k], args.acute_threshold_deg);
  }
  std::size_t listed = 0;
  for (const InputAngle& angle : report.acute_angles) {
    if (listed == args.max_listed) break;
    ++listed;
    std::printf("  %-15s %8.4f deg  %s\n", angle_kind_name(angle.kind), angle.angle_deg,
                describe_angle(angle).c_str());
  }
  if (report.num_acute_angles > listed) std::printf("  ... (%zu more)\n", report.num_acute_angles - listed);
  std::fflush(stdout);
  if (!report.ok()) {
    for (const Problem& p : report.problems) {
      std::cerr << "qualmesh: " << args.input << ": error[" << to_string(p.code) << "]: " << p.message << "\n";
    }
    return kExitBadInput;
  }
  return kExitOk;
}

}  // namespace

void register_info_command(CLI::App& app, int& exit_code) {
  auto args = std::make_shared<InfoArgs>();
  CLI::App* command = app.add_subcommand("info", "Counts, bounding box, PLC validation and acute input angles");
  command->add_option("input", args->input, "Input model (.poly .smesh .node .off .stl .obj .mesh .step .iges .brep .fcstd .scad)")
      ->required();
  add_input_options(*command, args->input_options);
  command->add_option("--acute-below", args->acute_threshold_deg,
                      "Report input angles below this many degrees (default 90, the paper's bound)");
  command->add_option("--list", args->max_listed, "How many acute angles to list (default 10)");
  command->callback([args, &exit_code] { exit_code = run_info(*args); });
}

}  // namespace qualmesh::cli
