// Typed errors. Three failure classes are kept apart (STYLE.md, principle 4):
//  - bad input: InputError, carrying an ErrorCode, the file and line when known, and the offending element ids;
//  - a bug: an assertion (QM_ASSERT in private code);
//  - an internal "try again" signal: a result enum of the stage concerned, never an exception.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include "qualmesh/types.h"

namespace qualmesh {

enum class ErrorCode {
  Io,                 // a file is missing, unreadable or cannot be written
  Parse,              // syntax error, truncated file, wrong or absurd count, garbage
  Unsupported,        // unknown format or a feature of a format that QualMesh does not read
  IndexOutOfRange,    // an element refers to a vertex (or other element) that does not exist
  NonFinite,          // NaN or infinite coordinate
  Empty,              // nothing to work on (no vertices, no facets)
  DuplicateVertex,    // two vertices at the same position
  DegenerateSegment,  // a segment whose two ends coincide
  DegenerateFacet,    // a facet with zero area, repeated vertices or fewer than three distinct vertices
  NonPlanarFacet,     // a facet whose vertices are not coplanar (tolerance relative to the bounding box)
  Intersection,       // two elements meet other than in a shared sub-element (PLC rule, paper Section 2)
  OpenBoundary,       // the facets do not enclose a volume: an edge used by one facet only
  InvalidMesh,        // a tetrahedral mesh that breaks a structural rule (for `check`)
};

// Short, stable, machine-readable name of a code ("open-boundary", ...).
const char* to_string(ErrorCode code);

// Ids of the elements an error is about. 0-based, as inside the library.
struct ElementIds {
  std::vector<Index> vertices;
  std::vector<Index> segments;
  std::vector<Index> facets;
  std::vector<Index> elements;  // tetrahedra (mesh files)
};

// Bad input. what() reads "FILE:LINE: error[CODE]: MESSAGE" (file and line omitted when unknown).
class InputError : public std::runtime_error {
 public:
  InputError(ErrorCode code, const std::string& message, const std::string& file = {}, long line = 0,
             ElementIds ids = {});

  ErrorCode code() const { return code_; }
  const std::string& message() const { return message_; }
  const std::string& file() const { return file_; }
  long line() const { return line_; }  // 1-based line number, 0 when not applicable (binary files)
  const ElementIds& ids() const { return ids_; }

 private:
  ErrorCode code_;
  std::string message_;
  std::string file_;
  long line_;
  ElementIds ids_;
};

}  // namespace qualmesh
