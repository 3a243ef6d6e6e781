// Typed errors: names of the codes and the "FILE:LINE: error[CODE]: MESSAGE" text of InputError.
#include "qualmesh/error.h"

#include <cmath>
#include <utility>

namespace qualmesh {

const char* to_string(ErrorCode code) {
  switch (code) {
    case ErrorCode::Io: return "io";
    case ErrorCode::Parse: return "parse";
    case ErrorCode::Unsupported: return "unsupported";
    case ErrorCode::IndexOutOfRange: return "index-out-of-range";
    case ErrorCode::NonFinite: return "non-finite";
    case ErrorCode::Empty: return "empty";
    case ErrorCode::DuplicateVertex: return "duplicate-vertex";
    case ErrorCode::DegenerateSegment: return "degenerate-segment";
    case ErrorCode::DegenerateFacet: return "degenerate-facet";
    case ErrorCode::NonPlanarFacet: return "non-planar-facet";
    case ErrorCode::Intersection: return "intersection";
    case ErrorCode::OpenBoundary: return "open-boundary";
    case ErrorCode::InvalidMesh: return "invalid-mesh";
  }
  return "unknown";
}

namespace {
std::string format_error(ErrorCode code, const std::string& message, const std::string& file, long line) {
  std::string text;
  if (!file.empty()) {
    text += file;
    if (line > 0) text += ":" + std::to_string(line);
    text += ": ";
  }
  text += "error[";
  text += to_string(code);
  text += "]: ";
  text += message;
  return text;
}
}  // namespace

InputError::InputError(ErrorCode code, const std::string& message, const std::string& file, long line,
                       ElementIds ids)
    : std::runtime_error(format_error(code, message, file, line)),
      code_(code),
      message_(message),
      file_(file),
      line_(line),
      ids_(std::move(ids)) {}

double BoundingBox::diagonal() const {
  if (empty()) return 0.0;
  double sq = 0;
  for (int i = 0; i < 3; ++i) sq += (max[i] - min[i]) * (max[i] - min[i]);
  return std::sqrt(sq);
}

}  // namespace qualmesh
