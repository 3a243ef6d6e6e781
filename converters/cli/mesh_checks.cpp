// The checks `qualmesh mesh` makes before meshing, and after it (mesh_checks.h).
#include "mesh_checks.h"

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <limits>

#include "qualmesh/error.h"
#include "qualmesh/mesh_io.h"
#include "qualmesh/plc_validate.h"

namespace qualmesh::cli {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// An allowed range [lo, hi], either end open; hi = inf means no upper bound (the value must still be finite).
struct Range {
  double lo;
  bool lo_open;
  double hi;
  bool hi_open;
  const char* why;  // appended to the message when a value is out of range (may be empty)
  // Lengths and volumes: smaller positive values are refused too, as too small to compute with (a length's square
  // would underflow to 0 and read as "no limit"); 0 = no such floor.
  double floor = 0;

  bool contains(double x) const {
    if (!std::isfinite(x)) return false;
    if (lo_open ? !(x > lo) : !(x >= lo)) return false;
    if (hi == kInf) return true;
    return hi_open ? x < hi : x <= hi;
  }
};

std::string format_number(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", x);
  return text;
}

// "> 0", ">= 1.1", "in (0, 1)", "in (0, 60)": what `--help` and the messages show.
std::string describe(const Range& r) {
  if (r.hi == kInf) return std::string(r.lo_open ? "> " : ">= ") + format_number(r.lo);
  return std::string("in ") + (r.lo_open ? "(" : "[") + format_number(r.lo) + ", " + format_number(r.hi) +
         (r.hi_open ? ")" : "]");
}

// `text` quoted, kept one printable line whatever the user typed (and short for option values).
std::string shown(const std::string& text, std::size_t max_size = 40) {
  std::string out = "'";
  for (const char c : text.substr(0, max_size)) out += (c >= 0x20 && c < 0x7f) ? c : '?';
  if (text.size() > max_size) out += "...";
  return out + "'";
}

std::string shown_path(const std::string& path) { return shown(path, 400); }

// A CLI11 check of a floating-point option: the text must be a number (strtod syntax), finite, in `r`.
// CLI11's own Range lets NaN through (every comparison with NaN is false); this one does not.
CLI::Validator real_in(const Range& r) {
  const std::string range_text = describe(r);
  return CLI::Validator(
      [r, range_text](std::string& text) -> std::string {
        const std::string expected = "expected a finite number " + range_text;
        if (text.empty()) return "an empty value is not a number: " + expected;
        char* end = nullptr;
        errno = 0;
        const double x = std::strtod(text.c_str(), &end);
        if (end == text.c_str() || *end != '\0') return shown(text) + " is not a number: " + expected;
        if (std::isnan(x)) return shown(text) + " is not a number (NaN): " + expected;
        if (!std::isfinite(x)) return shown(text) + " is not finite: " + expected;
        if (!r.contains(x)) {
          std::string message = shown(text) + " is out of range: " + expected;
          if (r.why[0] != '\0') message += std::string(" (") + r.why + ")";
          return message;
        }
        if (x < r.floor)
          return shown(text) + " is too small to compute with: expected a finite number >= " + format_number(r.floor);
        return {};
      },
      range_text);
}

// --max-vertices: a whole number >= 1 that fits in std::size_t.
CLI::Validator count_at_least_one() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        const std::string expected = "expected a whole number >= 1";
        bool digits = !text.empty();
        for (const char c : text) digits = digits && c >= '0' && c <= '9';
        if (!digits) return shown(text) + " is not a whole number: " + expected;
        errno = 0;
        const unsigned long long n = std::strtoull(text.c_str(), nullptr, 10);
        if (errno == ERANGE || n > std::numeric_limits<std::size_t>::max())
          return shown(text) + " is too large: " + expected + " that fits in 64 bits";
        if (n < 1) return shown(text) + " is out of range: " + expected;
        return {};
      },
      ">= 1");
}

const Range kRadiusEdge{1.1, false, kInf, false,
                        "below 1.1 refinement may not end; the theory needs more than 2, 1.5 works in practice"};
const Range kLength{0, true, kInf, false, "leave the option out for no limit", 1e-150};
const Range kVolume{0, true, kInf, false, "leave the option out for no limit", 1e-300};
const Range kSliverAngle{0, true, 60, true,
                         "the regular tetrahedron's dihedral angle is 70.53 degrees: from 60 up nearly every "
                         "tetrahedron counts as a sliver"};
const Range kOmega{0, true, 1, true, "omega0 of Cheng and Dey, Section 3.3"};
const Range kSliverBudget{0, false, 1, false, "a fraction of plain refinement's vertex count"};
const Range kDelta{0, true, 0.5, true, "delta below 1/2 keeps the weighted balls disjoint"};
const Range kDeflection{0, true, kInf, false, "leave the option out for a deflection relative to the diagonal",
                        1e-150};
const Range kRelativeDeflection{0, true, 1, true, "a fraction of the bounding-box diagonal"};
const Range kSewingTolerance{0, true, kInf, false, "model units; leave the option out for the automatic tolerance",
                             1e-150};

const Range kCoplanarTolerance{0, false, 1e-6, false,
                                "a fraction of the bounding-box diagonal, at most validation's planarity tolerance, "
                                "so that every merged facet stays a valid planar facet"};

void add_check(CLI::App& command, const std::string& name, const CLI::Validator& validator) {
  command.get_option(name)->check(validator);
}

}  // namespace

CLI::Validator coplanar_tolerance_check() { return real_in(kCoplanarTolerance); }

void add_mesh_option_checks(CLI::App& command) {
  add_check(command, "--radius-edge", real_in(kRadiusEdge));
  add_check(command, "--max-edge", real_in(kLength));
  add_check(command, "--max-volume", real_in(kVolume));
  add_check(command, "--max-vertices", count_at_least_one());
  add_check(command, "--sliver-angle", real_in(kSliverAngle));
  add_check(command, "--omega", real_in(kOmega));
  add_check(command, "--delta", real_in(kDelta));
  add_check(command, "--sliver-budget", real_in(kSliverBudget));
  add_check(command, "--deflection", real_in(kDeflection));
  add_check(command, "--relative-deflection", real_in(kRelativeDeflection));
  add_check(command, "--sewing-tolerance", real_in(kSewingTolerance));
  // Resource limits (mesh_limits.h): seconds > 0, a memory budget of at least 16 MB.
  add_check(command, "--time-limit", real_in({0, true, kInf, false, "seconds; leave the option out for no limit"}));
  add_check(command, "--max-memory", real_in({16, false, kInf, false, "MB; default 80% of the RAM"}));
  add_check(command, "--output", CLI::Validator([](std::string& text) { return output_path_problem(text); }, ""));
}

std::string output_path_problem(const std::string& output) {
  try {
    (void)mesh_format_from_path(output);
  } catch (const InputError& e) {
    return e.message() + ": " + shown_path(output);
  }
  const auto slash = output.rfind('/');
  const std::string dir = slash == std::string::npos ? "." : (slash == 0 ? "/" : output.substr(0, slash));
  struct stat st {};
  if (::stat(dir.c_str(), &st) != 0) return "the directory " + shown_path(dir) + " does not exist";
  if (!S_ISDIR(st.st_mode)) return shown_path(dir) + " is not a directory";
  if (::access(dir.c_str(), W_OK | X_OK) != 0) return "the directory " + shown_path(dir) + " is not writable";
  struct stat out {};
  // An Elmer mesh is a directory: an existing one is replaced whole once the new one is complete (atomic_file.h).
  if (::stat(output.c_str(), &out) == 0 && S_ISDIR(out.st_mode) && mesh_format_from_path(output) != MeshFormat::Elmer)
    return shown_path(output) + " is a directory";
  return {};
}

bool check_mesh_input(const Plc& plc, const std::string& file, const MeshOptions& options, bool verbose) {
  const auto start = std::chrono::steady_clock::now();
  const ValidationReport report = validate_plc(plc, ValidateOptions{});  // what `qualmesh info` runs
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (verbose) {
    std::cerr << "qualmesh: validation: " << (report.ok() ? "ok" : "INVALID") << " in " << format_number(seconds)
              << " s\n";
  }
  if (!report.ok()) {
    for (const Problem& p : report.problems)
      std::cerr << "qualmesh: " << file << ": error[" << to_string(p.code) << "]: " << p.message << "\n";
    std::size_t total = 0;
    for (const ProblemCount& pc : report.problem_counts) total += pc.count;
    std::cerr << "qualmesh: " << file << ": not a valid PLC (" << total << (total == 1 ? " problem" : " problems")
              << "; `qualmesh info` lists them): nothing meshed, nothing written\n";
    return false;
  }
  if (options.max_vertices < plc.vertices.size()) {
    std::cerr << "qualmesh: --max-vertices " << options.max_vertices << " is below the input's "
              << plc.vertices.size() << " vertices: nothing meshed, nothing written\n";
    return false;
  }
  return true;
}

bool check_mesh_result(const Plc& plc, const std::string& file, const MeshOptions& options, const MeshResult& result) {
  if (!result.mesh.tets.empty()) return true;
  std::cerr << "qualmesh: " << file << ": error[empty]: ";
  if (result.status == MeshStatus::VertexLimitReached) {
    std::cerr << "the vertex limit (--max-vertices " << options.max_vertices
              << ") stopped meshing before any tetrahedron was inside the domain";
  } else if (!plc.holes.empty()) {
    if (plc.holes.size() == 1)
      std::cerr << "the hole seed removes every region of the domain, so the mesh would be empty";
    else
      std::cerr << "the " << plc.holes.size()
                << " hole seeds remove every region of the domain, so the mesh would be empty";
  } else {
    std::cerr << "the mesh has no tetrahedron inside the domain";
  }
  std::cerr << ": nothing written\n";
  return false;
}

}  // namespace qualmesh::cli
