// OpenSCAD front end: renders a .scad file with the `openscad` command into an OFF surface and reads it as a PLC.
//
// OpenSCAD 2021.01 renders are known to be defective at times (zero-area facets standing in for T-junctions, cracks,
// see shared/data/MANIFEST.md). They are repaired only when the repair is exact, with exact predicates:
//  1. vertices with bit-identical coordinates are merged; facets left with fewer than 3 distinct vertices dropped;
//  2. facets whose vertices are exactly collinear (zero area) are dropped;
//  3. an edge then used by one facet only that has vertices exactly on its interior (a T-junction) gets them
//     inserted in that facet's polygon (the facet stays the same point set).
// If an edge is still used by other than two facets, the model is refused (OpenBoundary) with where it is open; a
// render whose facets intersect (validate_plc) is refused too (Intersection), naming the facets.
// OpenSCAD's own error messages (syntax errors, empty top-level object) reach the user in the InputError.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <thread>

#include "cad_private.h"
#include "qualmesh/error.h"
#include "qualmesh/plc_validate.h"

namespace qualmesh::cad {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;

Kernel::Point_3 cgal_point(const Point3& p) { return {p[0], p[1], p[2]}; }

std::string read_text(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// While openscad renders (issue 18 item 4): SIGINT, SIGTERM or SIGHUP kill it and remove the temporary folder, then
// go on to the handler that was there before (the CLI's removes its own temporaries and ends the process). Only
// async-signal-safe calls, on state in static storage. A SIGKILL of qualmesh cannot be caught: openscad then gets
// SIGKILL from the kernel (PR_SET_PDEATHSIG) and only the folder's few files stay.
struct RenderInFlight {
  static constexpr int kSignals[3] = {SIGINT, SIGTERM, SIGHUP};
  static inline volatile sig_atomic_t pid = 0;
  static inline char files[3][4096];  // render.off, console.txt, then the folder
  static inline struct sigaction previous[3];

  static void on_signal(int signal_number) {
    if (pid > 0) {
      kill(pid, SIGKILL);
      waitpid(pid, nullptr, 0);
    }
    unlink(files[0]);
    unlink(files[1]);
    rmdir(files[2]);
    for (int i = 0; i < 3; ++i)
      if (kSignals[i] == signal_number) sigaction(signal_number, &previous[i], nullptr);
    raise(signal_number);  // delivered to the previous handler once this one returns
  }
  RenderInFlight(const std::filesystem::path& dir, const std::filesystem::path& output,
                 const std::filesystem::path& console) {
    const std::string paths[3] = {output.string(), console.string(), dir.string()};
    for (int i = 0; i < 3; ++i) std::snprintf(files[i], sizeof files[i], "%s", paths[i].c_str());
    struct sigaction action {};
    action.sa_handler = on_signal;
    sigemptyset(&action.sa_mask);
    for (int i = 0; i < 3; ++i) sigaction(kSignals[i], &action, &previous[i]);
  }
  ~RenderInFlight() {
    for (int i = 0; i < 3; ++i) sigaction(kSignals[i], &previous[i], nullptr);
    pid = 0;
  }
};

// Runs `command -o out in` with a time limit; returns OpenSCAD's console output (stdout and stderr).
std::string run_openscad(const CadOptions& options, const std::string& input, const std::filesystem::path& output,
                         const std::filesystem::path& console, int& status, bool& timed_out) {
  const pid_t parent = getpid();
  pid_t pid = fork();
  if (pid < 0) throw InputError(ErrorCode::Io, "cannot start openscad (fork failed)", input);
  if (pid == 0) {
    prctl(PR_SET_PDEATHSIG, SIGKILL);  // qualmesh gone, openscad goes too
    if (getppid() != parent) _exit(127);
    int fd = open(console.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
    if (fd >= 0) {
      dup2(fd, 1);
      dup2(fd, 2);
    }
    execlp(options.openscad_command.c_str(), options.openscad_command.c_str(), "-o", output.c_str(), input.c_str(),
           static_cast<char*>(nullptr));
    _exit(127);
  }
  RenderInFlight::pid = pid;
  const auto start = std::chrono::steady_clock::now();
  timed_out = false;
  while (true) {
    pid_t done = waitpid(pid, &status, WNOHANG);
    if (done == pid) break;
    if (options.openscad_timeout_s > 0 &&
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() > options.openscad_timeout_s) {
      kill(pid, SIGKILL);
      waitpid(pid, &status, 0);
      timed_out = true;
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  RenderInFlight::pid = 0;
  return read_text(console);
}

// OpenSCAD's lines that say what went wrong (ERROR/WARNING), or the whole console output when none does.
std::string openscad_complaints(const std::string& console) {
  std::istringstream lines(console);
  std::string line, picked;
  while (std::getline(lines, line))
    if (line.find("ERROR") != std::string::npos || line.find("WARNING") != std::string::npos)
      picked += (picked.empty() ? "" : " | ") + line;
  if (!picked.empty()) return picked;
  // No ERROR or WARNING line: what is left once OpenSCAD's cache and timing statistics are taken out.
  std::istringstream again(console);
  while (std::getline(again, line)) {
    if (line.rfind("Geometries in cache", 0) == 0 || line.rfind("Geometry cache size", 0) == 0 ||
        line.rfind("CGAL Polyhedrons in cache", 0) == 0 || line.rfind("CGAL cache size", 0) == 0 ||
        line.rfind("Total rendering time", 0) == 0 || line.find_first_not_of(" \t\r") == std::string::npos)
      continue;
    picked += (picked.empty() ? "" : " | ") + line;
  }
  if (picked.empty()) picked = "(no message)";
  return picked.substr(0, 2000);
}

// Minimal OFF reader for OpenSCAD's output (header "OFF", counts, coordinates, polygons).
Plc parse_off(const std::string& text, const std::string& file) {
  std::istringstream in(text);
  std::string magic;
  in >> magic;
  if (magic != "OFF") throw InputError(ErrorCode::Parse, "openscad wrote no OFF file", file);
  long nv = -1, nf = -1, ne = 0;
  in >> nv >> nf >> ne;
  if (!in || nv < 0 || nf < 0) throw InputError(ErrorCode::Parse, "openscad's OFF output has a bad header", file);
  Plc plc;
  plc.vertices.resize(nv);
  for (auto& v : plc.vertices) in >> v[0] >> v[1] >> v[2];
  for (long f = 0; f < nf; ++f) {
    long n = 0;
    in >> n;
    Facet facet;
    facet.polygons.emplace_back(n);
    for (auto& i : facet.polygons[0]) {
      long k = -1;
      in >> k;
      if (k < 0 || k >= nv) throw InputError(ErrorCode::Parse, "openscad's OFF output has a bad index", file);
      i = static_cast<Index>(k);
    }
    plc.facets.push_back(std::move(facet));
  }
  if (!in) throw InputError(ErrorCode::Parse, "openscad's OFF output is truncated", file);
  return plc;
}

// OpenSCAD 2021.01 writes the same render with its vertices and facets in a different order from run to run (CGAL
// Nef polyhedra iterate in address order): CSG.scad gave three orders in six runs, the same points and polygons each
// time. The mesh depends on that order (the triangulation's insertion order), so the render is put in one canonical
// order: vertices sorted by coordinates, each polygon rotated to start at its smallest vertex (orientation kept),
// facets sorted. Same .scad, same PLC, same mesh.
void canonical_order(Plc& plc) {
  std::vector<Index> order(plc.vertices.size());
  for (Index i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](Index a, Index b) { return plc.vertices[a] < plc.vertices[b]; });
  std::vector<Index> new_id(order.size());
  std::vector<Point3> vertices(order.size());
  for (Index k = 0; k < order.size(); ++k) {
    new_id[order[k]] = k;
    vertices[k] = plc.vertices[order[k]];
  }
  plc.vertices.swap(vertices);
  for (Facet& facet : plc.facets)
    for (auto& polygon : facet.polygons) {
      for (Index& i : polygon) i = new_id[i];
      if (!polygon.empty()) std::rotate(polygon.begin(), std::min_element(polygon.begin(), polygon.end()), polygon.end());
    }
  std::stable_sort(plc.facets.begin(), plc.facets.end(),
                   [](const Facet& a, const Facet& b) { return a.polygons < b.polygons; });
}

using EdgeKey = std::pair<Index, Index>;
EdgeKey edge_key(Index a, Index b) { return a < b ? EdgeKey{a, b} : EdgeKey{b, a}; }

std::map<EdgeKey, int> count_edge_uses(const Plc& plc) {
  std::map<EdgeKey, int> uses;
  for (const auto& facet : plc.facets) {
    const auto& loop = facet.polygons[0];
    for (std::size_t i = 0; i < loop.size(); ++i) ++uses[edge_key(loop[i], loop[(i + 1) % loop.size()])];
  }
  return uses;
}

// The exact repairs described at the top; appends what it did to `log`.
void repair_exactly(Plc& plc, std::vector<std::string>& log, const std::string& file) {
  // 1. Merge bit-identical vertices.
  std::map<Point3, Index> first_at;
  std::vector<Index> remap(plc.vertices.size());
  std::vector<Point3> merged;
  for (std::size_t i = 0; i < plc.vertices.size(); ++i) {
    auto [it, inserted] = first_at.emplace(plc.vertices[i], static_cast<Index>(merged.size()));
    if (inserted) merged.push_back(plc.vertices[i]);
    remap[i] = it->second;
  }
  if (merged.size() != plc.vertices.size())
    log.push_back("merged " + std::to_string(plc.vertices.size() - merged.size()) + " coincident vertices");
  plc.vertices = std::move(merged);
  std::size_t num_collapsed = 0, num_zero_area = 0;
  std::vector<Facet> kept;
  std::vector<Index> zero_area_vertices;
  for (auto& facet : plc.facets) {
    std::vector<Index> loop;
    for (Index i : facet.polygons[0]) {
      Index v = remap[i];
      if (loop.empty() || loop.back() != v) loop.push_back(v);
    }
    while (loop.size() > 1 && loop.front() == loop.back()) loop.pop_back();
    std::vector<Index> sorted = loop;
    std::sort(sorted.begin(), sorted.end());
    if (loop.size() < 3 || std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end()) {
      ++num_collapsed;
      continue;
    }
    // 2. Exactly collinear: every vertex on the line of the first two.
    bool all_collinear = true;
    for (std::size_t k = 2; k < loop.size() && all_collinear; ++k)
      all_collinear = CGAL::collinear(cgal_point(plc.vertices[loop[0]]), cgal_point(plc.vertices[loop[1]]),
                                      cgal_point(plc.vertices[loop[k]]));
    if (all_collinear) {
      ++num_zero_area;
      zero_area_vertices.insert(zero_area_vertices.end(), loop.begin(), loop.end());
      continue;
    }
    facet.polygons[0] = std::move(loop);
    kept.push_back(std::move(facet));
  }
  plc.facets = std::move(kept);
  if (num_collapsed) log.push_back("dropped " + std::to_string(num_collapsed) + " facets with repeated vertices");
  if (num_zero_area) log.push_back("dropped " + std::to_string(num_zero_area) + " zero-area facets");

  // 3. T-junctions: insert vertices lying exactly inside an edge that only one facet uses.
  std::sort(zero_area_vertices.begin(), zero_area_vertices.end());
  zero_area_vertices.erase(std::unique(zero_area_vertices.begin(), zero_area_vertices.end()), zero_area_vertices.end());
  std::map<EdgeKey, int> uses = count_edge_uses(plc);
  std::size_t num_inserted = 0;
  if (!zero_area_vertices.empty()) {
    for (auto& facet : plc.facets) {
      auto& loop = facet.polygons[0];
      std::vector<Index> out;
      for (std::size_t i = 0; i < loop.size(); ++i) {
        Index a = loop[i], b = loop[(i + 1) % loop.size()];
        out.push_back(a);
        if (uses[edge_key(a, b)] != 1) continue;
        const auto pa = cgal_point(plc.vertices[a]), pb = cgal_point(plc.vertices[b]);
        std::vector<std::pair<double, Index>> inside;
        for (Index c : zero_area_vertices) {
          if (c == a || c == b) continue;
          const auto pc = cgal_point(plc.vertices[c]);
          if (CGAL::collinear(pa, pb, pc) && CGAL::collinear_are_strictly_ordered_along_line(pa, pc, pb))
            inside.push_back({CGAL::squared_distance(pa, pc), c});
        }
        std::sort(inside.begin(), inside.end());
        for (const auto& [d, c] : inside) out.push_back(c), ++num_inserted;
      }
      loop = std::move(out);
    }
    if (num_inserted)
      log.push_back("closed " + std::to_string(num_inserted) + " T-junctions by inserting exact edge points");
  }

  uses = count_edge_uses(plc);
  std::size_t num_open = 0, num_nonmanifold = 0;
  std::string where;
  for (const auto& [edge, n] : uses) {
    if (n == 2) continue;
    (n == 1 ? num_open : num_nonmanifold) += 1;
    if (num_open + num_nonmanifold <= 3) {
      const Point3& p = plc.vertices[edge.first];
      const Point3& q = plc.vertices[edge.second];
      char buffer[200];
      std::snprintf(buffer, sizeof buffer, " (%.6g, %.6g, %.6g)-(%.6g, %.6g, %.6g)", p[0], p[1], p[2], q[0], q[1],
                    q[2]);
      where += buffer;
    }
  }
  if (num_open || num_nonmanifold)
    throw InputError(ErrorCode::OpenBoundary,
                     "OpenSCAD's render is not a closed surface and cannot be repaired exactly: " +
                         std::to_string(num_open) + " edges used by one facet, " + std::to_string(num_nonmanifold) +
                         " by more than two, e.g." + where,
                     file);
}

// A render that intersects itself (candleStand.scad with OpenSCAD 2021.01) has no exact repair: refused here, with
// the facets named, rather than downstream as an anonymous PLC.
void refuse_self_intersection(const Plc& plc, const std::string& file) {
  ValidateOptions options;
  options.require_closed = false;  // closedness was settled by repair_exactly
  options.max_problems_per_kind = 3;
  const ValidationReport report = validate_plc(plc, options);
  const std::size_t count = report.num_problems(ErrorCode::Intersection);
  if (count == 0) return;
  std::string examples;
  ElementIds ids;
  for (const Problem& problem : report.problems) {
    if (problem.code != ErrorCode::Intersection) continue;
    examples += (examples.empty() ? "" : "; ") + problem.message;
    ids.facets.insert(ids.facets.end(), problem.ids.facets.begin(), problem.ids.facets.end());
  }
  throw InputError(ErrorCode::Intersection,
                   "OpenSCAD's render intersects itself (" + std::to_string(count) +
                       " facet pairs) and cannot be repaired exactly: " + examples +
                       " (facet numbers: 0-based, among the facets left by the exact repair)",
                   file, 0, ids);
}

}  // namespace

CadModel read_scad_file(const std::string& path, const CadOptions& options) {
  if (!std::filesystem::exists(path)) throw InputError(ErrorCode::Io, "no such file", path);
  if (!std::filesystem::is_regular_file(path)) throw InputError(ErrorCode::Io, "is not a regular file", path);
  const std::string source = read_text(path);
  if (source.find_first_not_of(" \t\r\n\f\v") == std::string::npos)
    throw InputError(ErrorCode::Empty, "the file is empty: it describes no object", path);
  static std::atomic<int> counter{0};
  const auto dir = std::filesystem::temp_directory_path() /
                   ("qualmesh-scad-" + std::to_string(getpid()) + "-" + std::to_string(counter++));
  std::filesystem::create_directories(dir);
  struct Cleanup {
    std::filesystem::path dir;
    ~Cleanup() {
      std::error_code ignored;
      std::filesystem::remove_all(dir, ignored);
    }
  } cleanup{dir};
  const auto output = dir / "render.off";
  const RenderInFlight in_flight(dir, output, dir / "console.txt");
  int status = 0;
  bool timed_out = false;
  const std::string console =
      run_openscad(options, std::filesystem::absolute(path).string(), output, dir / "console.txt", status, timed_out);
  if (timed_out)
    throw InputError(ErrorCode::Io, "openscad did not finish within " + std::to_string(options.openscad_timeout_s) +
                                        " s", path);
  if (WIFEXITED(status) && WEXITSTATUS(status) == 127 && !std::filesystem::exists(output))
    throw InputError(ErrorCode::Io, "cannot run '" + options.openscad_command +
                                        "' (install OpenSCAD, Debian package openscad)", path);
  if (console.find("Current top level object is empty.") != std::string::npos)
    throw InputError(ErrorCode::Empty, "the file describes no object (OpenSCAD: \"Current top level object is "
                                       "empty.\"); only comments, or only modules and functions that are never "
                                       "called?", path);
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || !std::filesystem::exists(output))
    throw InputError(ErrorCode::Parse, "openscad failed: " + openscad_complaints(console), path);

  CadModel model;
  model.plc = parse_off(read_text(output), path);
  canonical_order(model.plc);
  model.plc.name = path;
  if (model.plc.facets.empty())
    throw InputError(ErrorCode::Empty, "openscad rendered an empty model: " + openscad_complaints(console), path);
  repair_exactly(model.plc, model.summary.healing_log, path);
  refuse_self_intersection(model.plc, path);
  model.summary.source_format = "OpenSCAD";
  model.summary.num_faces = model.plc.facets.size();
  model.summary.num_vertices = model.plc.vertices.size();
  model.summary.num_edges = count_edge_uses(model.plc).size();
  return model;
}

}  // namespace qualmesh::cad
