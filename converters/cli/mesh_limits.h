// Resource limits of `qualmesh mesh` (issue 18 item 3): a time limit, a memory budget, the vertex limit, and an
// estimate of the element count from the size field that refuses a run the budget cannot hold before it starts.
// Every limit ends with exit code 4 (kExitResource) and a message on stderr naming the limit; nothing is written
// unless --allow-partial, which writes the mesh as it stands (still exit 4). Out of memory (std::bad_alloc) is
// exit 4 too, not an internal error (main.cpp).
//
// The time limit and the memory budget are watched through MeshOptions::cancel (polled by the mesher every 64
// insertions and in the pumping passes): the wall clock against --time-limit, the resident set (/proc/self/statm)
// against --max-memory. The memory budget defaults to 80% of the machine's RAM.
#pragma once

#include <CLI/CLI.hpp>

#include <functional>
#include <memory>
#include <string>

#include "qualmesh/mesher.h"
#include "qualmesh/plc.h"

namespace qualmesh::cli {

constexpr int kExitResource = 4;

struct MeshLimits {
  double time_limit_s = 0;      // 0: none
  double max_memory_mb = 0;     // 0: the default, 80% of the RAM
  bool allow_partial = false;   // write the partial mesh when a limit stops meshing
  // Why the cancel callback said stop ("" while it has not).
  std::shared_ptr<std::string> stopped_by = std::make_shared<std::string>();
};

// --time-limit, --max-memory, --allow-partial on the `mesh` subcommand, range-checked at parse time.
void add_limit_options(CLI::App& command, MeshLimits& limits);

// 80% of the physical memory, in MB (4096 when it cannot be read).
double default_memory_budget_mb();
double memory_budget_mb(const MeshLimits& limits);

// Before meshing: the element count the size field (--max-edge, --max-volume) asks for over the input's bounding
// box, or the local feature size at the boundary (estimate_from_feature_size: thin parts), whichever is more, and
// the memory it needs (about 250 bytes per tetrahedron, measured on the unit cube).
// False, with "about 8e+12 tets, about 2e+06 GB needed, over the budget of ..." on stderr, when it exceeds the
// memory budget. An estimate of 1e7 tets or more within the budget is said on stderr as a warning (minutes of work).
// `verbose`: both estimates on stderr ("estimate: size field ... tets; local feature size ... tets").
bool check_size_estimate(const Plc& plc, const std::string& file, const MeshOptions& options, const MeshLimits& limits,
                         bool verbose = false);

// The cancel callback for MeshOptions::cancel: true once the time limit has passed or the resident set exceeds the
// budget (and records which in limits.stopped_by).
std::function<bool()> make_cancel(const MeshLimits& limits);

// After mesh_plc: when a limit stopped it, the message on stderr and true (the caller exits kExitResource, writing
// the mesh only with --allow-partial). MeshStatus::PrecisionExhausted counts as one: error[precision].
bool report_limit_stop(const std::string& file, const MeshOptions& options, const MeshLimits& limits,
                       const MeshResult& result);

}  // namespace qualmesh::cli
