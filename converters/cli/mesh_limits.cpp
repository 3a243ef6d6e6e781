// Resource limits of `qualmesh mesh` (issue 18 item 3): see mesh_limits.h for what and why.
#include "mesh_limits.h"

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>

#include "qualmesh/size_estimate.h"

namespace qualmesh::cli {

namespace {

constexpr double kBytesPerTet = 250;    // peak resident set / tetrahedra: 480 MB for 2.1e6 tets (unit cube, L 0.025)
constexpr double kTetsPerEdgeCube = 33;  // tetrahedra per L^3 of volume: 2.1e6 for L = 0.025 on the unit cube
constexpr double kTetsPerMaxVolume = 2;  // tetrahedra per max-volume of volume (refinement stays below the cap)
constexpr double kTetsPerVertex = 6;
constexpr double kWarnTets = 1e7;  // about 2.3 GB and, at the engine's speed today, tens of minutes

std::string number(double x) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.2g", x);
  return buffer;
}

double resident_mb() {
  std::ifstream statm("/proc/self/statm");
  double size = 0, resident = 0;
  if (!(statm >> size >> resident)) return 0;
  return resident * double(sysconf(_SC_PAGESIZE)) / (1024.0 * 1024.0);
}

}  // namespace

void add_limit_options(CLI::App& command, MeshLimits& limits) {
  command.add_option("--time-limit", limits.time_limit_s,
                     "Stop after this many seconds of meshing (exit 4; default: none)");
  command.add_option("--max-memory", limits.max_memory_mb,
                     "Memory budget in MB: refuse a run estimated above it, stop one that grows past it (exit 4; "
                     "default 80% of the RAM)");
  command.add_flag("--allow-partial", limits.allow_partial,
                   "When a limit (time, memory, vertices) stops meshing, write the mesh as it stands (still exit 4)");
}

double default_memory_budget_mb() {
  const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
  if (pages <= 0 || page <= 0) return 4096;
  return 0.8 * double(pages) * double(page) / (1024.0 * 1024.0);
}

double memory_budget_mb(const MeshLimits& limits) {
  return limits.max_memory_mb > 0 ? limits.max_memory_mb : default_memory_budget_mb();
}

bool check_size_estimate(const Plc& plc, const std::string& file, const MeshOptions& options, const MeshLimits& limits,
                         bool verbose) {
  const BoundingBox box = bounding_box(plc);
  if (box.empty()) return true;
  const double volume = (box.max[0] - box.min[0]) * (box.max[1] - box.min[1]) * (box.max[2] - box.min[2]);
  double tets = 0;
  double l = options.max_edge_length > 0 ? options.max_edge_length : 0;
  if (options.target_edge_length > 0) {  // Rule 3's longest edge under a target (mesher.h), for the estimate
    const double from_target = kLongestEdgePerTarget * options.target_edge_length;
    l = l > 0 ? std::min(l, from_target) : from_target;
  }
  if (l > 0) tets = std::max(tets, kTetsPerEdgeCube * (volume / l) / (l * l));
  // (Regional volume limits apply to their region only: not counted, so that a small region does not refuse all.)
  if (options.max_volume > 0) tets = std::max(tets, kTetsPerMaxVolume * volume / options.max_volume);
  // The local feature size's share (size_estimate.h): what Rules 1 and 2 make at the boundary whatever the size
  // field; a slab 1e-4 thick asks for about 1e8 tets there with no size given.
  const FeatureSizeEstimate feature = estimate_from_feature_size(plc);
  if (verbose)
    std::cerr << "estimate: size field " << number(tets) << " tets; local feature size " << number(feature.tets)
              << " tets (integral dA/f^2 " << number(feature.surface_integral) << ", " << feature.samples
              << " samples)\n";
  const char* what = feature.tets > tets ? "the input's local feature size (its thinnest parts) asks for at least about "
                                         : "the size field asks for about ";
  tets = std::max(tets, feature.tets);
  if (!(tets > 0)) return true;
  const double needed_mb = tets * kBytesPerTet / (1024.0 * 1024.0);
  const double budget = memory_budget_mb(limits);
  if (needed_mb > budget) {
    std::cerr << "qualmesh: " << file << ": error[resource]: " << what << number(tets)
              << " tets (about " << number(tets / kTetsPerVertex) << " vertices), about "
              << number(needed_mb / 1024.0) << " GB needed, over the memory budget of " << number(budget / 1024.0)
              << " GB (--max-memory, default 80% of the RAM): nothing meshed, nothing written\n";
    return false;
  }
  if (tets >= kWarnTets)  // within the budget, but minutes of work and gigabytes: said before it starts
    std::cerr << "qualmesh: " << file << ": warning: " << what << number(tets) << " tets, about " << number(needed_mb / 1024.0)
              << " GB: this takes a while (--time-limit and --max-memory bound it)\n";
  return true;
}

std::function<bool()> make_cancel(const MeshLimits& limits) {
  const auto start = std::chrono::steady_clock::now();
  const double seconds = limits.time_limit_s, budget = memory_budget_mb(limits);
  auto stopped_by = limits.stopped_by;
  return [start, seconds, budget, stopped_by] {
    if (seconds > 0 && std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() > seconds) {
      *stopped_by = "the time limit (--time-limit " + number(seconds) + " s)";
      return true;
    }
    const double resident = resident_mb();
    if (resident > budget) {
      *stopped_by = "the memory budget (--max-memory " + number(budget) + " MB; " + number(resident) + " MB in use)";
      return true;
    }
    return false;
  };
}

bool report_limit_stop(const std::string& file, const MeshOptions& options, const MeshLimits& limits,
                       const MeshResult& result) {
  const char* partial = limits.allow_partial
                            ? "the partial mesh is written (--allow-partial); it may not conform to the input"
                            : "nothing written (--allow-partial writes the partial mesh)";
  if (result.status == MeshStatus::PrecisionExhausted) {
    std::cerr << "qualmesh: " << file << ": error[precision]: refinement reached the limit of double precision ("
              << result.message << "), with every fallback; the input has detail far below the requested size that "
              << "this size cannot resolve (a finer --size often does; `qualmesh info` lists the small angles): "
              << partial << "\n";
    return true;
  }
  std::string what;
  if (result.status == MeshStatus::Cancelled) what = *limits.stopped_by;
  else if (result.status == MeshStatus::VertexLimitReached)
    what = "the vertex limit (--max-vertices " + std::to_string(options.max_vertices) + ")";
  else return false;
  std::cerr << "qualmesh: " << file << ": error[resource]: " << what << " stopped meshing at "
            << result.mesh.points.size() << " vertices, " << result.mesh.tets.size() << " tets: " << partial << "\n";
  return true;
}

}  // namespace qualmesh::cli
