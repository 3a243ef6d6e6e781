// Step 3 of QUALMESH, pumping (Cheng & Dey, Section 3.7 step 3 and Section 7.3, after the sliver exudation of
// Cheng, Dey, Edelsbrunner, Facello and Teng): each vertex v of a sliver gets a weight in
// [0, min(omega0^2 f(v)^2, delta^2 N(v)^2)] (f: local feature size, N(v): nearest-vertex distance, delta < 1/2 so
// the weighted balls stay disjoint and no vertex can become hidden) that maximises the smallest dihedral angle of
// its star, in the regular (weighted Delaunay) triangulation.
//
// This file holds the passes. The star of a vertex at a weight, the walk over its critical weights and the checked
// move are pump_star.cpp's, which lists what a move must keep (no vertex hidden, conformity, regions, quality).
// Order: slivers worst first, each time the best of its four vertices; passes repeat while some move is accepted.
// Then, for the slivers left, the vertices across their faces (a neighbour's star grown over the sliver), accepted
// only when the new star beats every cell the move destroys. Last, one log line says why the rest survive.
// pump_around() pumps the stars of the vertices sliver insertion adds (sliver_insertion.cpp).
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <string>
#include <unordered_map>

#include "qualmesh/quality.h"
#include "refine/pump_star.h"

namespace qualmesh::detail {

namespace {

const Kernel& kernel() {
  static const Kernel k;
  return k;
}

// One log line on the tetrahedra left below the sliver angle away from acute input angles: how many of their
// vertices lie on the boundary (segment, facet or input vertices) and how each vertex's last walk ended.
template <typename Bad>
void log_survivors(const MeshState& s, const std::vector<Bad>& bad, const std::vector<std::uint8_t>& last_end,
                   const std::vector<std::uint8_t>& last_refusal, std::uint8_t improved, std::uint8_t not_tried) {
  std::size_t by_boundary[5] = {0, 0, 0, 0, 0};
  std::map<std::string, std::size_t> ends;
  std::size_t num = 0;
  static const char* const kEnd[] = {"cap-delta", "cap-omega", "no-room", "events", "current-invalid", "refused"};
  static const char* const kRefusal[] = {"none", "hidden", "lost-subsegment", "lost-subfacet", "facet-not-retiled",
                                          "region", "bad-cell"};
  for (const auto& b : bad) {
    if (tet_touches_acute_angle(s, b.ids)) continue;
    ++num;
    int boundary = 0;
    for (const Index v : b.ids) {
      boundary += s.vertices[v].kind != VertexKind::Volume;
      const std::uint8_t e = last_end[v];
      const std::string key = e == not_tried  ? "not-tried"
                              : e == improved ? "improved-but-not-best"
                              : e == std::uint8_t(WalkEnd::Refused) ? std::string("refused:") + kRefusal[last_refusal[v]]
                                                                    : std::string(kEnd[e]);
      ++ends[key];
    }
    ++by_boundary[boundary];
  }
  std::string line = "pumping: " + std::to_string(num) + " tets below the sliver angle away from acute angles; by "
                     "boundary vertices 0/1/2/3/4: ";
  for (int k = 0; k < 5; ++k) line += (k ? "/" : "") + std::to_string(by_boundary[k]);
  line += "; vertex walks:";
  for (const auto& kv : ends) line += " " + kv.first + "=" + std::to_string(kv.second);
  s.log_line(line);
}

}  // namespace

void pump_slivers(MeshState& s) {
  s.stats.num_vertices_before_pumping = s.tr.number_of_vertices();
  s.sq_nearest.assign(s.vertices.size(), std::numeric_limits<double>::infinity());
  for (auto e = s.tr.finite_edges_begin(); e != s.tr.finite_edges_end(); ++e) {
    const Index a = e->first->vertex(e->second)->info(), b = e->first->vertex(e->third)->info();
    const double d = CGAL::squared_distance(s.kpoint(a), s.kpoint(b));
    s.sq_nearest[a] = std::min(s.sq_nearest[a], d);
    s.sq_nearest[b] = std::min(s.sq_nearest[b], d);
  }
  struct Bad {
    double angle;
    std::array<Index, 4> ids;
  };
  std::vector<Bad> bad;
  auto collect = [&]() {
    bad.clear();
    std::size_t slivers = 0;
    double min_angle = 180;
    for (auto c = s.tr.finite_cells_begin(); c != s.tr.finite_cells_end(); ++c) {
      if (c->info().region < 0) continue;
      double angle = 180;
      if (is_sliver(s, c, &angle)) ++slivers;
      min_angle = std::min(min_angle, angle);
      if (s.params.below_sliver_angle(angle))
        bad.push_back({angle, {c->vertex(0)->info(), c->vertex(1)->info(), c->vertex(2)->info(), c->vertex(3)->info()}});
    }
    std::sort(bad.begin(), bad.end(), [](const Bad& a, const Bad& b) {
      return a.angle < b.angle || (a.angle == b.angle && a.ids < b.ids);
    });
    return std::make_pair(slivers, min_angle);
  };
  const auto [slivers_before, min_before] = collect();
  s.stats.num_slivers_before_pumping = slivers_before;
  s.stats.min_dihedral_before_pumping_deg = min_before;

  // Passes: the first tries every vertex of every bad tetrahedron; a later one only vertices whose star changed
  // since they were last tried (an unchanged star gives the same answer).
  constexpr int kMaxPasses = 8;
  std::vector<std::uint8_t> dirty(s.vertices.size(), 1);
  std::vector<Index> touched;
  // Within a pass every move marks again all the vertices the pass's moves have touched so far (those walked since
  // with no improvement are tried again). Kept without rescanning `touched` at each move, which was quadratic in the
  // moves (3.6% of fandisk.off's run): a touched vertex is dirty when it was not cleaned after the last move.
  std::vector<std::uint8_t> in_touched(s.vertices.size(), 0);
  std::vector<std::uint32_t> cleaned_at(s.vertices.size(), 0);
  std::uint32_t move_count = 0;
  auto is_dirty = [&](Index v) { return in_touched[v] ? cleaned_at[v] < move_count : dirty[v] != 0; };
  auto clean = [&](Index v) {
    dirty[v] = 0;
    cleaned_at[v] = move_count;
  };
  std::size_t num_retiled = 0, num_retile_failures = 0;  // moves that changed subfacets; of those, not followed
  std::size_t num_neighbour_moves = 0;
  // Per vertex, how its last walk ended (WalkEnd, or kImproved; kNotTried: never walked) and why (Refusal).
  constexpr std::uint8_t kImproved = 200, kNotTried = 255;
  std::vector<std::uint8_t> last_end(s.vertices.size(), kNotTried), last_refusal(s.vertices.size(), 0);
  for (int pass = 0; pass < kMaxPasses && !bad.empty(); ++pass) {
    std::size_t moves = 0;
    for (const Index t : touched) in_touched[t] = 0;
    touched.clear();
    for (const Bad& b : bad) {
      if (s.poll_cancel()) break;
      Ch3 c;
      const auto& ids = b.ids;
      if (!current_cell(s, ids, c)) continue;  // already gone
      // The best of its four vertices.
      Index best_v = kNoIndex;
      PumpChoice best;
      for (const Index v : ids) {
        if (!is_dirty(v)) continue;
        const PumpChoice choice = best_weight(s, v);
        last_end[v] = std::uint8_t(choice.end);
        last_refusal[v] = std::uint8_t(choice.refusal);
        if (choice.improves) last_end[v] = kImproved;
        if (!choice.improves) clean(v);
        if (choice.improves && (best_v == kNoIndex || better(choice.best, best.best))) best = choice, best_v = v;
      }
      if (best_v == kNoIndex) continue;
      const std::size_t before = touched.size();
      if (apply_weight(s, best_v, best.weight, best.current, &touched, &num_retiled, &num_retile_failures)) {
        ++moves;
        ++s.stats.num_pump_moves;
        ++move_count;
        for (std::size_t k = before; k < touched.size(); ++k) in_touched[touched[k]] = 1;
      } else {
        ++s.stats.num_pump_rejected;
        clean(best_v);
      }
    }
    s.log_line("pumping pass " + std::to_string(pass + 1) + ": " + std::to_string(moves) + " weights changed");
    if (moves == 0) break;
    std::fill(dirty.begin(), dirty.end(), 0);
    for (const Index t : touched) dirty[t] = 1;
    collect();
  }

  // Slivers their own vertices could not remove: pump a neighbour, the vertex across one of the sliver's faces,
  // over it (the sliver joins that vertex's zone). Beyond the paper's step 3, which pumps sliver vertices only;
  // the same caps and checks apply, and the new star must beat every cell it destroys.
  // Only slivers away from acute input angles (issue 4's target; at an acute angle the shortest edge is forced and
  // pinion's thousands of such tets made this pass cost more than all the others), and a few passes.
  constexpr int kMaxNeighbourPasses = 3;
  for (int pass = 0; pass < kMaxNeighbourPasses && !bad.empty(); ++pass) {
    std::size_t moves = 0;
    for (const Bad& b : bad) {
      if (s.poll_cancel()) break;
      Ch3 c;
      const auto& ids = b.ids;
      if (!current_cell(s, ids, c)) continue;  // already gone
      if (tet_touches_acute_angle(s, ids)) continue;
      Index best_v = kNoIndex;
      PumpChoice best;
      for (int i = 0; i < 4; ++i) {
        const Ch3 n = c->neighbor(i);
        if (s.tr.is_infinite(n)) continue;
        const Index u = n->vertex(n->index(c))->info();
        if (u == kNoIndex) continue;
        const PumpChoice choice = best_weight(s, u, &c);
        if (choice.improves && (best_v == kNoIndex || better(choice.best, best.best))) best = choice, best_v = u;
      }
      if (best_v == kNoIndex) continue;
      touched.clear();
      if (apply_weight(s, best_v, best.weight, best.current, &touched, &num_retiled, &num_retile_failures, &c)) {
        ++moves;
        ++num_neighbour_moves;
        ++s.stats.num_pump_moves;
      } else {
        ++s.stats.num_pump_rejected;
      }
    }
    s.log_line("pumping neighbours pass " + std::to_string(pass + 1) + ": " + std::to_string(moves) +
               " weights changed");
    if (moves == 0) break;
    collect();
  }

  s.stats.num_vertices_after_pumping = s.tr.number_of_vertices();
  s.log_line("pumping: " + std::to_string(num_neighbour_moves) + " moves of sliver neighbours, " +
             std::to_string(num_retiled) + " moves changed subfacets" +
             (num_retile_failures ? ", " + std::to_string(num_retile_failures) + " facet triangulations not retiled (bug)"
                                  : std::string()));
  collect();
  log_survivors(s, bad, last_end, last_refusal, kImproved, kNotTried);
}

std::size_t pump_around(MeshState& s, const std::vector<Index>& vertices, WalkCache* cache) {
  // The bad cells (below the sliver angle, in the domain) among the stars of `around`, worst first.
  struct Bad {
    double angle;
    std::array<Index, 4> ids;
  };
  std::vector<Bad> bad;
  auto collect = [&](const std::vector<Index>& around) {
    std::vector<Ch3> cells;
    for (const Index v : around) s.tr.incident_cells(s.vertices[v].handle, std::back_inserter(cells));
    std::sort(cells.begin(), cells.end());
    cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
    bad.clear();
    for (const Ch3& c : cells) {
      if (s.tr.is_infinite(c) || c->info().region < 0) continue;
      std::array<Index, 4> ids{c->vertex(0)->info(), c->vertex(1)->info(), c->vertex(2)->info(), c->vertex(3)->info()};
      const double angle = cell_min_dihedral_deg(s, c);
      if (s.params.below_sliver_angle(angle)) bad.push_back({angle, ids});
    }
    std::sort(bad.begin(), bad.end(), [](const Bad& a, const Bad& b) {
      return a.angle < b.angle || (a.angle == b.angle && a.ids < b.ids);
    });
  };
  std::size_t moves = 0, num_retiled = 0, num_retile_failures = 0;
  std::vector<Index> touched, changed;
  // A vertex's walk, kept until a move changes its star (as pump_slivers' dirty flags): a vertex of several bad
  // cells is walked once, not once per cell (pinion: most of the time pumping took went to such repeats).
  std::unordered_map<Index, PumpChoice> walks;
  auto walk = [&](Index v) -> const PumpChoice& {
    auto it = walks.find(v);
    if (it == walks.end()) it = walks.emplace(v, cache ? cache->walk(s, v) : best_weight(s, v)).first;
    return it->second;
  };
  // The second pass looks only at the stars the first pass's moves changed: every other cell was there, with the
  // same neighbours, when the first pass (or pump_slivers before it) tried its vertices.
  std::vector<Index> around = vertices;
  constexpr int kMaxPasses = 2;
  for (int pass = 0; pass < kMaxPasses && !around.empty(); ++pass) {
    collect(around);
    changed.clear();
    std::size_t pass_moves = 0;
    for (const Bad& b : bad) {
      Ch3 c;
      if (!current_cell(s, b.ids, c)) continue;
      Index best_v = kNoIndex;
      PumpChoice best;
      for (const Index v : b.ids) {
        const PumpChoice& choice = walk(v);
        if (choice.improves && (best_v == kNoIndex || better(choice.best, best.best))) best = choice, best_v = v;
      }
      if (best_v == kNoIndex) continue;
      touched.clear();
      if (apply_weight(s, best_v, best.weight, best.current, &touched, &num_retiled, &num_retile_failures)) {
        ++pass_moves;
        ++s.stats.num_pump_moves;
        for (const Index t : touched) walks.erase(t);
        changed.insert(changed.end(), touched.begin(), touched.end());
      } else {
        ++s.stats.num_pump_rejected;
        walks[best_v].improves = false;  // the same walk would be refused again
      }
    }
    moves += pass_moves;
    std::sort(changed.begin(), changed.end());
    changed.erase(std::unique(changed.begin(), changed.end()), changed.end());
    around.swap(changed);
    walks.clear();
  }
  if (num_retile_failures)
    s.log_line("pumping: " + std::to_string(num_retile_failures) + " facet triangulations not retiled (bug)");
  return moves;
}

void pumping_statistics(MeshState& s) {
  std::size_t slivers = 0;
  for (auto c = s.tr.finite_cells_begin(); c != s.tr.finite_cells_end(); ++c) slivers += is_sliver(s, c, nullptr);
  s.stats.num_slivers_after_pumping = slivers;
  for (Index v = 0; v < s.vertices.size(); ++v) {
    if (s.vertices[v].handle == Vh3()) continue;
    const double w = s.vertices[v].handle->point().weight();
    if (w == 0) continue;
    ++s.stats.num_vertices_pumped;
    s.stats.max_weight = std::max(s.stats.max_weight, w);
    const double f = local_feature_size_at(s, v);
    const double cap = s.params.weight_cap(f, s.sq_nearest[v]);
    s.stats.max_weight_cap_ratio = std::max(s.stats.max_weight_cap_ratio, w / cap);
  }
}

std::pair<KPoint3, double> orthosphere(Ch3 c) {
  const auto& w0 = c->vertex(0)->point();
  const auto& w1 = c->vertex(1)->point();
  const auto& w2 = c->vertex(2)->point();
  const auto& w3 = c->vertex(3)->point();
  return {kernel().construct_weighted_circumcenter_3_object()(w0, w1, w2, w3),
          kernel().compute_squared_radius_smallest_orthogonal_sphere_3_object()(w0, w1, w2, w3)};
}

}  // namespace qualmesh::detail
