// The scheduler of the refinement levels (levels.h): drains Rules 1, 2 and 3 in the paper's priority order (Cheng
// & Dey, Section 3.7, step 2: a rule applies only when no rule before it does), as CGAL Mesh_3's Mesher_level chain
// does, flattened into one loop: a subsegment first, else a subfacet, else (refinement stage only) the regions of
// the cells that boundary insertions created since the last flood, else a tetrahedron. Each level validates its
// entries when it pops them (stale ones cost nothing). Also here: every level's after-insertion hook, the initial
// queues of the boundary stage, progress reports, Encroaching::Steiner's work budget, and the global audits that
// mesher.cpp runs after the Steiner mode's stages.
#include <algorithm>
#include <string>

#include "refine/refine_state.h"

namespace qualmesh::detail {

namespace {

void report(MeshState& s, double fraction) {
  if (!s.progress) return;
  ProgressEvent event;
  event.stage = s.stage;
  event.fraction = std::max(0.0, std::min(1.0, fraction));
  event.num_vertices = s.tr.number_of_vertices();
  s.progress(event);
}

// Average conflict-zone size (cells) over a window of insertions above which Encroaching::Steiner gives way to the
// paper's rule. Measured averages: 17-70 on the benchmark models in either mode.
constexpr std::size_t kSteinerZoneBudget = 250;

}  // namespace

void notify_insertion(MeshState& s, const InsertionResult& r) {
  s.rule3.after_insertion(s, r);
  s.rule1.after_insertion(s, r);
  s.rule2.after_insertion(s, r);
}

void enqueue_initial_boundary(MeshState& s) {
  for (Index seg = 0; seg < s.complex.segments.size(); ++seg) {
    const Segment& sg = s.complex.segments[seg];
    s.rule1.enqueue_if_encroached(s, seg, std::min(sg.a, sg.b), std::max(sg.a, sg.b));
  }
  std::vector<std::array<Index, 3>> faces;
  for (Index f = 0; f < s.facets.size(); ++f) {
    faces.clear();
    collect_subfacets(s, f, faces);
    s.rule2.enqueue_if_encroached(s, f, faces);
  }
}

void enqueue_all_tets(MeshState& s) { s.rule3.enqueue_all(s); }

void run_refinement(MeshState& s, bool with_rule3) {
  std::size_t steps = 0;
  std::vector<Ch3> assigned;
  while (!s.vertex_limit_reached) {
    if (++steps % 4096 == 0) {
      const double queued = double(s.rule1.queue.size() + s.rule2.queue.size() + s.rule3.queue.size());
      const double done = double(s.stats.num_steiner_vertices);
      report(s, done / (done + queued + 1));
      // Encroaching::Steiner's work budget: where tolerated encroachers leave the boundary far from Gabriel, cells
      // near it get huge circumspheres and every insertion's conflict zone becomes large (U_Joint_2.stp: averages
      // of 300-700 cells, against 20-60 on the same model with the paper's rule). Then mesh_plc() starts again with
      // the paper's rule. Not under a split floor (MeshOptions::min_split_length, the CLI's CAD inputs): there
      // Rules 1-2 stop at the floor, and large zones only cost time. On U_Joint_2.stp at its default size the
      // budget sent the run to the paper's rule, which split down to 1.8e-13 edges (276 s, 1517385 nodes at
      // order 2, a deck ccx refused); the relaxed rule under the floor finishes in 153 s (132531 nodes, 382 MB)
      // with zones of about 450 cells, and ccx runs its deck.
      if (!s.params.encroachment.paper() && s.params.sq_min_split == 0 && s.zone_count >= 4096) {
        if (s.zone_cells > kSteinerZoneBudget * s.zone_count) {
          s.steiner_abandoned = "conflict zones of " + std::to_string(s.zone_cells / s.zone_count) +
                                " cells on average";
          return;
        }
        s.zone_cells = s.zone_count = 0;
      }
      if (steps % (1u << 18) == 0)
        s.log_line("refinement: " + std::to_string(steps) + " steps, " + std::to_string(s.tr.number_of_vertices()) +
                   " vertices (rule 1 " + std::to_string(s.stats.num_rule1_insertions) + ", rule 2 " +
                   std::to_string(s.stats.num_rule2_insertions) + ", rule 3 " +
                   std::to_string(s.stats.num_rule3_insertions) + "), queued " +
                   std::to_string(s.rule1.queue.size()) + "/" + std::to_string(s.rule2.queue.size()) + "/" +
                   std::to_string(s.rule3.queue.size()) + ", " + std::to_string(s.stats.num_rejected_circumcenters) +
                   " centres rejected, " + std::to_string(s.stats.num_skipped_small_angle) + " small-angle skips");
    }
    if (!s.rule1.empty()) {
      s.rule1.refine_one(s);
      continue;
    }
    if (!s.rule2.empty()) {
      s.rule2.refine_one(s);
      continue;
    }
    if (!with_rule3) break;
    if (!s.region_pending.empty()) {
      assigned.clear();
      flood_pending_regions(s, assigned);
      for (const Ch3& c : assigned) s.rule3.enqueue_if_bad(s, c);
      continue;
    }
    if (!s.rule3.empty()) {
      s.rule3.refine_one(s);
      continue;
    }
    break;
  }
  report(s, 1.0);
}

bool region_boundaries_are_subfacets(const MeshState& s) {
  for (auto c = s.tr.finite_cells_begin(); c != s.tr.finite_cells_end(); ++c) {
    const int region = c->info().region;
    if (region < 0) continue;
    for (int i = 0; i < 4; ++i) {
      const Ch3 n = c->neighbor(i);
      const int other = s.tr.is_infinite(n) ? kOutsideRegion : n->info().region;
      if (other != region && face_subfacet(s, c, i) == kNoIndex) return false;
    }
  }
  return true;
}

bool boundary_present(const MeshState& s) {
  for (Index seg = 0; seg < s.complex.segments.size(); ++seg) {
    const Index end = s.complex.segments[seg].b;
    for (Index u = s.complex.segments[seg].a, v; u != end; u = v) {
      v = next_on_segment(s, seg, u);
      Ch3 c;
      int i = 0, j = 0;
      if (!s.tr.is_edge(s.vertices[u].handle, s.vertices[v].handle, c, i, j)) return false;
    }
  }
  std::vector<std::array<Index, 3>> faces;
  for (Index f = 0; f < s.facets.size(); ++f) {
    faces.clear();
    collect_subfacets(s, f, faces);
    for (const auto& abc : faces) {
      Ch3 c;
      int i = 0, j = 0, k = 0;
      if (!s.tr.is_facet(s.vertices[abc[0]].handle, s.vertices[abc[1]].handle, s.vertices[abc[2]].handle, c, i, j, k))
        return false;
    }
  }
  return true;
}

}  // namespace qualmesh::detail
