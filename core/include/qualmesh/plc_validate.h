// PLC validation and the input-angle report (paper Section 2).
//
// What: validate_plc() judges whether a Plc is a piecewise linear complex the mesher can take: finite coordinates,
// no duplicate vertices, no degenerate segment or facet, planar facets, no two elements meeting other than in a
// shared element (the PLC rule of Section 2), and a closed boundary. It also measures the input angles of Section 2
// (segment-segment, segment-facet, facet-facet) and lists the acute ones, since the paper's guarantees assume none
// is below 90 degrees and QualMesh protects the sharp features it finds.
// Why: bad input must get a typed error naming the offending elements before any meshing starts (DESIGN.md).
// The call does not mutate its input, never prints and never throws for bad input (throw_if_invalid does).
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include "qualmesh/error.h"
#include "qualmesh/plc.h"
#include "qualmesh/types.h"

namespace qualmesh {

// One thing wrong with the input.
struct Problem {
  // DuplicateVertex, DegenerateSegment, DegenerateFacet, NonPlanarFacet, Intersection, OpenBoundary, NonFinite,
  // IndexOutOfRange or Empty.
  ErrorCode code = ErrorCode::Empty;
  // What is wrong, naming the ids, e.g. "facets 12 and 40 intersect (not in a shared vertex or edge)".
  std::string message;
  // The offending vertex / segment / facet ids (0-based). Segment ids index collect_segments(plc).
  ElementIds ids;
};

enum class AngleKind { SegmentSegment, SegmentFacet, FacetFacet };
const char* to_string(AngleKind kind);

// An input angle of the paper's Section 2.
struct InputAngle {
  AngleKind kind = AngleKind::SegmentSegment;
  double angle_deg = 180;  // degrees, in [0, 180] for SegmentSegment and SegmentFacet, [0, 360) for FacetFacet
  Index apex_vertex = kNoIndex;  // the shared vertex (for FacetFacet: one end of the shared segment)
  // SegmentSegment: two segment ids; SegmentFacet: segment id, facet id; FacetFacet: two facet ids (the angle is
  // swept from `first` to `second` around the segment). Segment ids index collect_segments(plc).
  Index first = kNoIndex;
  Index second = kNoIndex;
  Index segment = kNoIndex;  // FacetFacet: the shared segment (index into collect_segments(plc)); else kNoIndex
};

struct ValidateOptions {
  // Largest distance of a facet vertex from the facet's plane, relative to the bounding-box diagonal. 1e-6 accepts
  // files written with 7 significant digits (%g, single-precision STL) and still rejects any bend that a mesh of
  // useful size could see.
  double planarity_tolerance = 1e-6;
  // Input angles below this (degrees) are listed as acute (the paper assumes none below 90 degrees). Angles within
  // 1e-7 degrees of the threshold count as not acute, so exact right angles never show up through rounding.
  double acute_threshold_deg = 90.0;
  bool check_intersections = true;  // the PLC rule (facet-facet, segment-facet, segment-segment)
  bool require_closed = true;       // report OpenBoundary for every facet boundary edge on no other facet
  // Listing cap: at most this many problems of each ErrorCode and this many acute angles of each AngleKind are
  // listed; the counts (problem_counts, num_acute_angles, num_acute_by_kind) stay exact.
  std::size_t max_problems_per_kind = 20;
};

struct ProblemCount {
  ErrorCode code;
  std::size_t count;
};

struct ValidationReport {
  std::vector<Problem> problems;          // empty = valid; in the order of the checks, capped per code
  std::vector<ProblemCount> problem_counts;  // exact number of problems per code (codes that occurred only)
  std::vector<InputAngle> acute_angles;   // the smallest acute angles of each kind, sorted by angle ascending
  std::size_t num_acute_angles = 0;       // total count (acute_angles may be capped)
  std::array<std::size_t, 3> num_acute_by_kind{};          // indexed by AngleKind
  std::array<double, 3> min_angle_deg_by_kind{180, 180, 180};  // indexed by AngleKind; 180 when none measured
  double min_input_angle_deg = 180;       // smallest input angle of any kind
  bool closed = false;                    // every facet boundary edge lies on at least two facets
  std::size_t num_segments = 0;           // size of collect_segments(plc)

  bool ok() const { return problems.empty(); }
  // Exact number of problems with `code` (also those beyond the listing cap).
  std::size_t num_problems(ErrorCode code) const;
};

// Validates `plc` (see the file comment). Geometric checks that need sound coordinates (planarity,
// intersections, angles) are skipped when a coordinate is non-finite or an index is out of range.
ValidationReport validate_plc(const Plc& plc, const ValidateOptions& options = {});

// Throws InputError of the first problem (code, message, ids; `file` goes into the error) if the report is not ok.
void throw_if_invalid(const ValidationReport& report, const std::string& file);

}  // namespace qualmesh
