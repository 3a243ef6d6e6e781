// Private pieces of validate_plc() shared by its files: the capped problem list, the per-facet triangulations, and
// the two heavy stages (the PLC intersection rule in plc_validate_intersections.cpp, the input angles in
// plc_validate_angles.cpp). See qualmesh/plc_validate.h for what is checked and why.
#pragma once

#include <cstddef>
#include <map>
#include <string>
#include <vector>

#include "facet_triangulation.h"
#include "qualmesh/plc_validate.h"

namespace qualmesh::detail {

// Collects problems, listing at most `cap` of each code while counting all of them.
class ProblemSink {
 public:
  explicit ProblemSink(std::size_t cap) : cap_(cap) {}
  void add(ErrorCode code, std::string message, ElementIds ids) {
    if (counts_[code]++ < cap_) problems_.push_back({code, std::move(message), std::move(ids)});
  }
  std::size_t count(ErrorCode code) const {
    auto it = counts_.find(code);
    return it == counts_.end() ? 0 : it->second;
  }
  void move_into(ValidationReport& report) {
    report.problems = std::move(problems_);
    report.problem_counts.clear();
    for (const auto& [code, n] : counts_) report.problem_counts.push_back({code, n});
  }

 private:
  std::size_t cap_;
  std::vector<Problem> problems_;
  std::map<ErrorCode, std::size_t> counts_;
};

// What the heavy stages need: the PLC, its segments (collect_segments), a representative per vertex (the first of
// its exact duplicates, so that duplicates count as shared) and the triangulation of each facet that passed the
// structural checks (`facet_usable[f]`).
struct ValidationInput {
  const Plc* plc = nullptr;
  std::vector<Segment> segments;
  std::vector<Index> representative;
  std::vector<FacetTriangulation> triangulations;  // one per facet; empty for unusable facets
  std::vector<char> facet_usable;
};

// The PLC rule of Section 2 between facets (through their triangles) and segments that lie in no facet.
void check_intersections(const ValidationInput& input, ProblemSink& sink);

// Segment-segment, segment-facet and facet-facet input angles (Section 2) into `report`.
void measure_input_angles(const ValidationInput& input, const ValidateOptions& options, ValidationReport& report);

// "12" style formatting helpers for messages.
std::string format_point(const Point3& p);

}  // namespace qualmesh::detail
