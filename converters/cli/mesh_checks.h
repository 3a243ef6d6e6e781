// What `qualmesh mesh` checks before it meshes (issue 18, part 1), and the one check it makes after: every numeric
// option against its documented range at parse time, the output path (format from the extension, directory), the
// input PLC by the same validation `qualmesh info` runs, and a result with no tetrahedron. Every refusal is exit 2
// (kExitBadInput) with the allowed range, or the defect as `info` names it, on stderr; nothing is written then.
//
// Option ranges (README.md, "The command line"; each validator's text also shows in `qualmesh mesh --help`):
//   --radius-edge          finite, >= 1.1 (the theory needs > 2; below 1.1 refinement may not end: 1.0 runs
//                          without end on examples/l_bracket.poly, 1.05 needs 100000 vertices there)
//   --max-edge             finite, > 0 (leave the option out for no limit); below 1e-150 refused as too small to
//                          compute with (its square underflows to 0, which read as no limit)
//   --max-volume           finite, > 0 (leave the option out for no limit); below 1e-300 refused likewise
//   --max-vertices         integer >= 1, and at least the input's vertex count
//   --sliver-angle         finite, in (0, 60) degrees (the regular tetrahedron's dihedral angle is 70.53: at 60
//                          almost every tetrahedron is a sliver, joint.off's pumping takes 20 times as long and
//                          gains nothing)
//   --omega                in (0, 1) (omega0 of the paper, Section 3.3)
//   --delta                in (0, 0.5) (delta < 1/2 keeps the weighted balls disjoint)
//   --deflection           finite, > 0 (CAD inputs; leave it out for the relative deflection); below 1e-150 refused
//   --relative-deflection  in (0, 1) (CAD inputs)
// NaN, infinities and anything that is not a number (for --max-vertices: a whole number) are refused.
#pragma once

#include <CLI/CLI.hpp>

#include <string>

#include "qualmesh/mesher.h"
#include "qualmesh/plc.h"

namespace qualmesh::cli {

// Attaches the range checks above to the options of the `mesh` subcommand (looked up by name, so the option
// definitions stay as they are) and the output-path check to -o.
void add_mesh_option_checks(CLI::App& command);

// The range check of --coplanar-tolerance (every command that reads an input): a number in [0, 1e-6].
CLI::Validator coplanar_tolerance_check();

// Empty when `output` names a mesh format (mesh_format_from_path) in an existing directory, else what is wrong.
std::string output_path_problem(const std::string& output);

// Runs validate_plc on `plc` exactly as `qualmesh info` does; on problems prints each one on stderr in `info`'s
// words ("qualmesh: FILE: error[CODE]: MESSAGE") plus a closing line, and returns false. Also refuses a
// --max-vertices below the input's vertex count. With `verbose`, logs how long validation took.
bool check_mesh_input(const Plc& plc, const std::string& file, const MeshOptions& options, bool verbose);

// After mesh_plc: false (with a message on stderr) when the mesh has no tetrahedron (hole seeds that remove the
// whole domain, or a vertex limit reached before any tetrahedron was inside it); nothing must be written then.
bool check_mesh_result(const Plc& plc, const std::string& file, const MeshOptions& options, const MeshResult& result);

}  // namespace qualmesh::cli
