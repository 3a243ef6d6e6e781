// Sliver insertion, after step 3 (beyond the paper: Cheng & Dey remove every sliver by pumping alone, Theorem 7.3,
// with constants far too small for practice, Section 8). With the practical omega0 and delta the weight caps
// omega0^2 f(v)^2 and delta^2 N(v)^2 stop most walks before a sliver-free star is found (pump.cpp's survivors
// line: cap-delta), so the slivers pumping leaves get a point instead (those away from acute input angles first,
// then those at one: slivers_worst_first), as Rule 3 gives a skinny tetrahedron its circumcentre, and in the manner
// of sliver removal by point insertion (Li and Teng, "Generating well-shaped Delaunay meshes in 3D": a point in a
// small ball around the circumcentre, chosen so that it makes no new sliver).
//
// For each such sliver, worst first: candidate points are its orthocentre z (the centre of its orthosphere in the
// regular triangulation, radius R) and points 0.15 R and 0.3 R from z in 14 directions. A candidate p (weight
// zero) is accepted only when its insertion
//   - destroys the sliver (p is closer than orthogonal to its orthosphere) and hides no vertex;
//   - keeps the boundary: its conflict zone lies in the sliver's region, holds no subfacet inside it and loses no
//     subsegment, so every subsegment and subfacet stays an edge and a face, and conformity stays exact. Unlike
//     Rule 3, p may lie inside the diametral ball of a subsegment or subfacet on the zone's boundary: Rule 3's
//     rejection (split the encroached element instead) is what the paper's termination argument needs, while this
//     pass is bounded by its vertex budget and needs only that the elements stay, which is checked exactly;
//     splitting boundary elements here would reopen Rules 1-2 on a weighted triangulation and on facets that
//     pumping retiled. Measured: rejecting such points left most surviving slivers (those with vertices on the
//     boundary) without a candidate (t13_data.stl read directly: 256 slivers left away from acute angles, 130
//     without the rejection; joint 58 -> 55; fandisk, budget-limited, 432 -> 429);
//   - keeps Rule 3's radius-edge bound rho0 and the size field on every new cell (as pumping does, a cell may
//     exceed rho0 where an acute input angle forces its shortest edge, not beyond the worst cell destroyed);
//   - keeps every weight within its cap delta^2 N(v)^2 for the vertices around p (N(v) shrinks with p);
//   - improves the mesh locally: the new star's smallest dihedral angle is larger than that of the cells it
//     destroys (so the mesh's minimum dihedral angle never drops) and it has fewer cells below the sliver angle.
// Among the accepted candidates the one that removes the most cells below the sliver angle, then the one with the
// largest smallest angle, is inserted with the refinement engine's insertion (insertion.cpp insert_volume_vertex), and the
// vertices of the new star are pumped again (pump_around, step 3's caps and checks). The budget, not the
// candidates, is what limits the pass, so the first round inserts only points that remove at least three cells below
// the sliver angle, the second two, later rounds one (measured, slivers left away from acute angles at the same
// vertex count: any point in every round fandisk 473, joint 62; 2 then 1: 420, 52; 3, 2, then 1: 407, 50); rounds
// repeat while an insertion happens. A sliver refused in one round is not evaluated again while nothing its
// candidates read has changed (RefusedSliver; part.step at --size 21.25: 254 of the 4 rounds' slivers). The vertex count stays within RefineParams::sliver_insertion_budget of the count
// plain refinement ended with (before Rule 4): by default 4.8%, below issue 4's 1.05x; `qualmesh mesh` gives CAD inputs
// more (MeshOptions::sliver_insertion_budget).
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <string>
#include <tuple>

#include "qualmesh/quality.h"
#include "refine/pump_star.h"
#include "refine/refine_state.h"

namespace qualmesh::detail {

namespace {

constexpr int kMaxRounds = 4;

const Kernel& kernel() {
  static const Kernel k;
  return k;
}

// The quality of a set of in-domain cells: smallest dihedral angle, cells below the sliver angle.
struct StarQuality {
  double min_dihedral_deg = 180;
  std::size_t num_bad = 0;
};

void add_cell(const MeshState& s, double angle, StarQuality* q) {
  q->min_dihedral_deg = std::min(q->min_dihedral_deg, angle);
  q->num_bad += s.params.below_sliver_angle(angle);
}

struct Candidate {
  KPoint3 point;
  std::vector<Ch3> cells;
  std::vector<Facet3> boundary;
  StarQuality quality;
  std::size_t num_removed = 0;  // cells below the sliver angle destroyed minus those created
};

// Is `a` a better candidate than `b`: more cells below the sliver angle removed (the vertex budget is what limits
// the pass), then a larger smallest angle in the new star.
bool better(const Candidate& a, const Candidate& b) {
  if (a.num_removed != b.num_removed) return a.num_removed > b.num_removed;
  return a.quality.min_dihedral_deg > b.quality.min_dihedral_deg;
}

double sq_dist(const KPoint3& a, const KPoint3& b) { return CGAL::squared_distance(a, b); }

// The largest volume a cell of `region` may have (0: none), as Rule 3 judges it.
double max_volume_of(const MeshState& s, int region) {
  double v = s.params.max_volume;
  if (region >= 0 && s.regions[region].max_volume > 0)
    v = v > 0 ? std::min(v, s.regions[region].max_volume) : s.regions[region].max_volume;
  return v;
}

// Why a candidate point was refused, in the order evaluate() checks (a later one got further); counted per round
// for the slivers left without an acceptable point (the -v log).
enum class PointRefusal : std::uint8_t {
  NotInConflict,         // the point does not destroy the sliver (or is hidden)
  Region,                // the zone leaves the sliver's region or the domain
  SubfacetInside,        // a subfacet would vanish inside the zone
  Hidden,                // a vertex would be hidden
  LostSubsegment,        // a subsegment would vanish
  WeightCap,             // a neighbour's weight would exceed delta^2 N(v)^2
  BadCell,               // a new cell flat, inverted or beyond the size field
  RadiusEdge,            // a new cell above rho0
  NotBetter,             // the new star's smallest angle or its count of slivers is not better
  FewRemoved,            // accepted, but removes fewer cells below the sliver angle than the round asks
  None
};
constexpr const char* kRefusalNames[] = {"not-in-conflict", "region",    "subfacet-inside", "hidden",
                                         "lost-subsegment", "weight-cap", "bad-cell",        "radius-edge",
                                         "not-better",      "few-removed"};

// p's conflict zone from `start` (the cells connected to it whose power sphere p is inside, with CGAL's
// perturbation: the cells find_conflicts returns), its boundary facets (seen from inside) and its internal facets
// (each once). False, as soon as it is known, when the zone holds a cell that is infinite or of another region: a
// candidate beside a flat boundary sees every hull facet of that side (all infinite cells in conflict), and CGAL's
// full zone of it cost most of the pass (a slab 1 x 1 x 0.005: 80% of the run in find_conflicts). One walk, marked
// with the cells' conflict flags (cleared before returning) as find_conflicts marks them: the candidates of a sliver
// are 29 zones each, and walking each once for the region and again in find_conflicts, with a hash set of the cells
// seen, was a third of pump carter's sliver insertion. The cells come in another order than find_conflicts', which
// evaluate() does not depend on; the point inserted gets CGAL's zone (insert_at_sliver), so the mesh is the same.
bool conflict_zone(const MeshState& s, Ch3 start, const KWeightedPoint3& wp, int region, std::vector<Ch3>& cells,
                   std::vector<Facet3>& boundary, std::vector<Facet3>& internal) {
  cells.assign(1, start);
  boundary.clear();
  internal.clear();
  start->tds_data().mark_in_conflict();
  bool inside = !s.tr.is_infinite(start) && start->info().region == region;
  for (std::size_t i = 0; i < cells.size() && inside; ++i) {
    const Ch3 c = cells[i];
    for (int k = 0; k < 4; ++k) {
      const Ch3 n = c->neighbor(k);
      if (!n->tds_data().is_in_conflict()) {
        if (s.tr.side_of_power_sphere(n, wp, true) != CGAL::ON_BOUNDED_SIDE) {
          boundary.emplace_back(c, k);
          continue;
        }
        n->tds_data().mark_in_conflict();
        cells.push_back(n);
        if (s.tr.is_infinite(n) || n->info().region != region) {
          inside = false;
          break;
        }
      }
      // Seen from both sides (each cell of the zone is walked once it is marked): kept from the older cell's.
      if (c->time_stamp() < n->time_stamp()) internal.emplace_back(c, k);
    }
  }
  for (const Ch3& c : cells) c->tds_data().clear();
  return inside;
}

// evaluate()'s working data, kept across the candidates of a sliver (the marks across the whole pass), and the cells
// the candidates read.
struct Scratch {
  std::vector<Facet3> internal;
  // Link vertices of the current candidate: mark[v] == generation (one increment per candidate instead of clearing).
  std::vector<std::uint32_t> mark;
  std::uint32_t generation = 0;
  std::vector<Ch3> read;  // zone cells and the cells across the zone's boundary (side_of_power_sphere, weight caps)
};

// Is ab an edge of one of the zone's boundary facets (the link)? Asked only for the zone cells' subsegments: a scan of
// the link then costs less than sorting its edges for every candidate.
bool link_has_edge(const std::vector<Facet3>& boundary, Index a, Index b) {
  for (const Facet3& f : boundary) {
    int found = 0;
    for (int k = 1; k < 4; ++k) {
      const Index id = f.first->vertex((f.second + k) & 3)->info();
      found += id == a || id == b;
    }
    if (found == 2) return true;
  }
  return false;
}

// Checks candidate p against the sliver `sliver` (see the file comment); fills `out` when p is acceptable
// (PointRefusal::None). A candidate that cannot remove `min_removed` cells below the sliver angle (its zone holds fewer,
// or its new cells already leave fewer removed) is refused as FewRemoved as soon as that is known: the round would
// not insert it, so the mesh is the same as with every check run (only the -v log's refusal counts differ).
PointRefusal evaluate(MeshState& s, Ch3 sliver, const KPoint3& p, std::size_t min_removed, Candidate& out,
                      Scratch& scratch) {
  const KWeightedPoint3 wp(p, 0);
  const int region = sliver->info().region;
  // Destroys the sliver; then the zone is found from it, in one region inside the domain.
  if (s.tr.side_of_power_sphere(sliver, wp) != CGAL::ON_BOUNDED_SIDE) return PointRefusal::NotInConflict;
  std::vector<Facet3>& internal = scratch.internal;
  const bool in_region = conflict_zone(s, sliver, wp, region, out.cells, out.boundary, internal);
  scratch.read.insert(scratch.read.end(), out.cells.begin(), out.cells.end());
  for (const Facet3& f : out.boundary) scratch.read.push_back(f.first->neighbor(f.second));
  if (!in_region) return PointRefusal::Region;
  if (out.boundary.empty()) return PointRefusal::NotInConflict;
  StarQuality destroyed;
  double destroyed_max_radius_edge = 0;
  // Existing cells are measured once in their lifetime (CellInfo's caches): the zones of a sliver's candidates
  // overlap, and so do those of neighbouring slivers.
  for (const Ch3& c : out.cells) {
    add_cell(s, cell_min_dihedral_deg(s, c), &destroyed);
    destroyed_max_radius_edge = std::max(destroyed_max_radius_edge, cell_radius_edge(s, c));
  }
  if (destroyed.num_bad < min_removed) return PointRefusal::FewRemoved;
  // No subfacet inside the zone.
  for (const Facet3& f : internal)
    if (face_subfacet(s, f.first, f.second) != kNoIndex) return PointRefusal::SubfacetInside;
  // No vertex hidden (every vertex of the zone's cells is on its boundary); no subsegment lost (every subsegment
  // of the zone's cells is an edge of its boundary).
  if (++scratch.generation == 0) {  // wrapped: clear the marks
    std::fill(scratch.mark.begin(), scratch.mark.end(), 0);
    scratch.generation = 1;
  }
  scratch.mark.resize(s.vertices.size(), 0);
  for (const Facet3& f : out.boundary)
    for (int k = 1; k < 4; ++k) {
      const Index id = f.first->vertex((f.second + k) & 3)->info();
      if (id != kNoIndex) scratch.mark[id] = scratch.generation;
    }
  for (const Ch3& c : out.cells) {
    Index ids[4];
    bool ends[4];  // can_end_subsegment, read once per vertex instead of once per pair
    for (int k = 0; k < 4; ++k) {
      ids[k] = c->vertex(k)->info();
      if (ids[k] == kNoIndex || scratch.mark[ids[k]] != scratch.generation) return PointRefusal::Hidden;
      ends[k] = can_end_subsegment(s.vertices[ids[k]].kind);
    }
    for (int a = 0; a < 4; ++a)
      for (int b = a + 1; b < 4; ++b)
        if (ends[a] && ends[b] && subsegment_of(s, ids[a], ids[b]) != kNoIndex &&
            !link_has_edge(out.boundary, ids[a], ids[b]))
          return PointRefusal::LostSubsegment;
  }
  // Weight caps of the vertices around p: those of the link and those across it.
  const double sq_delta = s.params.sq_delta;
  auto cap_kept = [&](Vh3 u) {
    if (u == s.tr.infinite_vertex()) return true;
    return u->point().weight() <= sq_delta * sq_dist(p, u->point().point());
  };
  for (const Facet3& f : out.boundary) {
    const Ch3 n = f.first->neighbor(f.second);
    if (!cap_kept(n->vertex(n->index(f.first)))) return PointRefusal::WeightCap;
    for (int k = 1; k < 4; ++k)
      if (!cap_kept(f.first->vertex((f.second + k) & 3))) return PointRefusal::WeightCap;
  }
  // The new cells: positive, within rho0 and the size field, and better than what they replace.
  const double max_volume = max_volume_of(s, region);
  out.quality = StarQuality{};
  for (const Facet3& f : out.boundary) {
    std::array<Point3, 4> q;
    std::array<KPoint3, 4> kq;
    for (int k = 0; k < 4; ++k) {
      kq[k] = k == f.second ? p : f.first->vertex(k)->point().point();
      q[k] = to_point3(kq[k]);
    }
    if (kernel().orientation_3_object()(kq[0], kq[1], kq[2], kq[3]) != CGAL::POSITIVE) return PointRefusal::BadCell;
    if (s.params.sq_max_edge > 0)
      for (int k = 0; k < 4; ++k)
        if (k != f.second && sq_dist(p, kq[k]) > s.params.sq_max_edge) return PointRefusal::BadCell;
    if (max_volume > 0 && CGAL::volume(kq[0], kq[1], kq[2], kq[3]) > max_volume) return PointRefusal::BadCell;
    const TetQuality tq = tet_quality(q[0], q[1], q[2], q[3]);
    if (!(tq.radius_edge <= s.params.radius_edge_bound)) {
      // As for pumping: above rho0 only where an acute input angle forces the shortest edge (not one of p's), and
      // not beyond the worst cell destroyed.
      int ea = 0, eb = 1;
      for (int a = 0; a < 4; ++a)
        for (int b = a + 1; b < 4; ++b)
          if (sq_dist(kq[a], kq[b]) < sq_dist(kq[ea], kq[eb])) ea = a, eb = b;
      if (ea == f.second || eb == f.second || !(tq.radius_edge <= destroyed_max_radius_edge) ||
          !shortest_edge_forced_by_acute_angle(s, f.first->vertex(ea)->info(), f.first->vertex(eb)->info()))
        return PointRefusal::RadiusEdge;
    }
    add_cell(s, tq.min_dihedral_deg, &out.quality);
    if (out.quality.num_bad + min_removed > destroyed.num_bad) return PointRefusal::FewRemoved;
  }
  if (!(out.quality.min_dihedral_deg > destroyed.min_dihedral_deg)) return PointRefusal::NotBetter;
  if (!(out.quality.num_bad < destroyed.num_bad)) return PointRefusal::NotBetter;
  out.num_removed = destroyed.num_bad - out.quality.num_bad;
  out.point = p;
  return PointRefusal::None;
}

// The candidate points of the file comment around sliver c's orthocentre.
std::vector<KPoint3> candidate_points(Ch3 c) {
  const auto [z, sq_r] = orthosphere(c);
  std::vector<KPoint3> out{z};
  if (!(sq_r > 0)) return out;
  const double r = std::sqrt(sq_r);
  static const double kDirections[14][3] = {{1, 0, 0},  {-1, 0, 0}, {0, 1, 0},   {0, -1, 0},  {0, 0, 1},
                                            {0, 0, -1}, {1, 1, 1},  {1, 1, -1},  {1, -1, 1},  {1, -1, -1},
                                            {-1, 1, 1}, {-1, 1, -1}, {-1, -1, 1}, {-1, -1, -1}};
  for (const double t : {0.15, 0.3})
    for (const auto& d : kDirections) {
      const double scale = t * r / std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
      out.emplace_back(z.x() + scale * d[0], z.y() + scale * d[1], z.z() + scale * d[2]);
    }
  return out;
}

struct Bad {
  bool at_acute;  // touches an acute input angle (tet_touches_acute_angle)
  double angle;
  std::array<Index, 4> ids;
};

// In-domain cells below the sliver angle: those that touch no acute input angle first (the paper's quality claim is
// about them, so the budget goes to them first), then those that do, each group worst first. The second group is
// beyond the claim: on a tessellated surface every triangle corner is an acute input angle, so nearly every
// boundary sliver touches one (Gmsh's cylinder surface, 142 input vertices: 8 tets below 15 deg, min 7.4, left
// when the pass skipped them; 0, min 15.1, with 3 points inserted among them).
std::vector<Bad> slivers_worst_first(const MeshState& s, std::size_t* num_away) {
  std::vector<Bad> bad;
  *num_away = 0;
  for (auto c = s.tr.finite_cells_begin(); c != s.tr.finite_cells_end(); ++c) {
    if (c->info().region < 0) continue;
    const std::array<Index, 4> ids{c->vertex(0)->info(), c->vertex(1)->info(), c->vertex(2)->info(),
                                   c->vertex(3)->info()};
    const double angle = cell_min_dihedral_deg(s, c);
    if (!s.params.below_sliver_angle(angle)) continue;
    const bool at_acute = tet_touches_acute_angle(s, ids);
    *num_away += !at_acute;
    bad.push_back({at_acute, angle, ids});
  }
  std::sort(bad.begin(), bad.end(), [](const Bad& a, const Bad& b) {
    return std::tie(a.at_acute, a.angle, a.ids) < std::tie(b.at_acute, b.angle, b.ids);
  });
  return bad;
}

// A sliver none of whose candidates was inserted: what a later round needs to know that they would all be refused
// again. evaluate() reads only the cells of `footprint` (a weight change or an insertion recreates the cells it
// touches, with new time stamps) and the input's static data, and a refusal other than FewRemoved does not depend on
// min_removed (the FewRemoved checks come after the Region check, and a check passed for a larger min_removed is
// passed for a smaller one).
struct RefusedSliver {
  std::size_t min_removed = 0;
  bool few_removed = false;  // a candidate refused as FewRemoved or accepted: a smaller min_removed may insert one
  PointRefusal furthest = PointRefusal::None;
  CellFootprint footprint;  // the cells the candidates read
};

// Would `r` refuse the sliver again in a round asking for `min_removed`: the same cells, and the same request or no
// candidate that a smaller request could accept.
bool refused_again(const MeshState& s, const RefusedSliver& r, std::size_t min_removed) {
  return (r.min_removed == min_removed || !r.few_removed) && footprint_holds(s, r.footprint);
}

// Inserts the best candidate of `c` that removes at least `min_removed` cells below the sliver angle; otherwise
// returns the furthest refusal among the candidates and, with `refused`, what refused_again needs. `num_in_balls`
// counts the boundary elements whose diametral balls hold the inserted point. The new star is pumped again with
// `walks`.
PointRefusal insert_at_sliver(MeshState& s, Ch3 c, std::size_t min_removed, std::size_t* num_in_balls, WalkCache& walks,
                              Scratch& scratch, RefusedSliver* refused) {
  Candidate best, trial;
  bool found = false;
  PointRefusal furthest = PointRefusal::NotInConflict;
  scratch.read.assign(1, c);
  for (const KPoint3& p : candidate_points(c)) {
    // Once a candidate is accepted, one that removes fewer cells cannot be better: evaluate() drops it as FewRemoved
    // as soon as that is known. The choice is the same; only `furthest` could differ, and it is read when none is
    // accepted, when the request is min_removed.
    const std::size_t need = found ? std::max(min_removed, best.num_removed) : min_removed;
    const PointRefusal r = evaluate(s, c, p, need, trial, scratch);
    if (r != PointRefusal::None) {
      furthest = std::max(furthest, r);
      continue;
    }
    if (!found || better(trial, best)) {
      std::swap(best, trial);
      found = true;
    }
  }
  if (!found || best.num_removed < min_removed) {
    refused->min_removed = min_removed;
    refused->few_removed = found || furthest == PointRefusal::FewRemoved;
    refused->furthest = found ? PointRefusal::FewRemoved : furthest;
    // Each cell once, in the order first read, found with the conflict flags that conflict_zone clears after every
    // walk (the 29 candidates' zones overlap: sorting their cells to drop the repeats was 5% of pump carter's run).
    refused->footprint.clear();
    for (const Ch3& r : scratch.read)
      if (!r->tds_data().is_in_conflict()) {
        r->tds_data().mark_in_conflict();
        refused->footprint.emplace_back(r, r->time_stamp());
      }
    for (const auto& [r, stamp] : refused->footprint) r->tds_data().clear();
    return refused->furthest;
  }
  std::vector<Index> star;
  for (const Facet3& f : best.boundary)
    for (int k = 1; k < 4; ++k) star.push_back(f.first->vertex((f.second + k) & 3)->info());
  std::sort(star.begin(), star.end());
  star.erase(std::unique(star.begin(), star.end()), star.end());
  const int region = c->info().region;
  // CGAL's zone of the point, in find_conflicts' order (conflict_zone's is another): the insertion then destroys and
  // creates the cells in the same order as before conflict_zone, so the mesh is the same.
  best.cells.clear();
  best.boundary.clear();
  s.tr.find_conflicts(KWeightedPoint3(best.point, 0), c, std::back_inserter(best.boundary),
                      std::back_inserter(best.cells), CGAL::Emptyset_iterator());
  const Index w = insert_volume_vertex(s, to_point3(best.point), best.cells, best.boundary, region);
  // The pumping cap's N(v): the new vertex's, and its neighbours' (p may now be their nearest vertex).
  s.sq_nearest.resize(s.vertices.size(), std::numeric_limits<double>::infinity());
  for (const Index u : star) {
    const double d = sq_dist(best.point, s.kpoint(u));
    s.sq_nearest[u] = std::min(s.sq_nearest[u], d);
    s.sq_nearest[w] = std::min(s.sq_nearest[w], d);
  }
  // The engine's insertion queued the zone's subsegments and subfacets whose diametral balls hold p (allowed above:
  // they stay edges and faces, checked) and, never expected, new cells that Rule 3 would split. Both are dropped:
  // the triangulation is weighted now, and the engine's rules are unweighted.
  *num_in_balls += s.rule1.queue.size() + s.rule2.queue.size();
  if (!s.rule3.empty())
    s.log_line("sliver insertion: " + std::to_string(s.rule3.queue.size()) + " new cells queued by Rule 3 (unexpected)");
  s.rule1.queue.clear();
  s.rule2.queue.clear();
  s.rule3.queue.clear();
  star.push_back(w);
  pump_around(s, star, &walks);
  return PointRefusal::None;
}

template <std::size_t N>
std::string refusal_summary(const std::array<std::size_t, N>& why) {
  std::string out;
  for (std::size_t k = 0; k < N; ++k)
    if (why[k]) out += (out.empty() ? "; furthest refusals:" : "") + std::string(" ") + kRefusalNames[k] + "=" +
                       std::to_string(why[k]);
  return out;
}

}  // namespace

void insert_at_slivers(MeshState& s) {
  const std::size_t base = s.stats.num_vertices_before_pumping - s.stats.num_rule4_vertices;
  const auto limit = std::size_t((1 + s.params.sliver_insertion_budget) * double(base));
  std::size_t total = 0, refused = 0;
  bool budget_spent = false;
  WalkCache walks;
  std::map<std::array<Index, 4>, RefusedSliver> refusals;  // by sorted vertex ids
  std::size_t num_skipped = 0;
  Scratch scratch;
  for (int round = 0; round < kMaxRounds && !budget_spent; ++round) {
    const auto round_start = std::chrono::steady_clock::now();
    std::size_t inserted = 0, in_balls = 0;
    refused = 0;
    std::array<std::size_t, std::size_t(PointRefusal::None)> why{};
    std::size_t num_away = 0;
    const std::vector<Bad> bad = slivers_worst_first(s, &num_away);
    for (const Bad& b : bad) {
      if (s.tr.number_of_vertices() >= limit || s.vertex_limit_reached) {
        budget_spent = true;
        break;
      }
      Ch3 c;
      if (!s.tr.is_cell(s.vertices[b.ids[0]].handle, s.vertices[b.ids[1]].handle, s.vertices[b.ids[2]].handle,
                        s.vertices[b.ids[3]].handle, c))
        continue;  // gone with an earlier insertion
      const std::size_t min_removed = std::size_t(std::max(1, 3 - round));
      std::array<Index, 4> key = b.ids;
      std::sort(key.begin(), key.end());
      RefusedSliver& record = refusals[key];
      PointRefusal r;
      if (record.furthest != PointRefusal::None && refused_again(s, record, min_removed)) {
        r = record.furthest;  // evaluated in an earlier round; nothing it read has changed since
        ++num_skipped;
      } else {
        r = insert_at_sliver(s, c, min_removed, &in_balls, walks, scratch, &record);
      }
      if (r == PointRefusal::None) {
        refusals.erase(key);
        ++inserted;
      } else {
        ++refused;
        ++why[std::size_t(r)];
      }
    }
    total += inserted;
    s.log_line("sliver insertion round " + std::to_string(round + 1) + ": " + std::to_string(bad.size()) +
               " tets below the sliver angle (" + std::to_string(num_away) + " away from acute angles), " +
               std::to_string(inserted) +
               " points inserted (" + std::to_string(in_balls) +
               " subsegments and subfacets kept with a point in their diametral ball), " + std::to_string(refused) +
               " without an acceptable point" +
               (budget_spent ? " (vertex budget spent)" : "") + refusal_summary(why) + "; " +
               std::to_string(std::chrono::duration<double>(std::chrono::steady_clock::now() - round_start).count()) +
               " s");
    if (inserted == 0 && round >= 2) break;  // the rounds asking for more than one removal may insert nothing
  }
  s.log_line("sliver insertion: " + std::to_string(walks.misses()) + " vertex walks, " +
             std::to_string(walks.hits()) + " reused (their cells unchanged); " + std::to_string(num_skipped) +
             " slivers refused again without evaluating their candidates (nothing they read changed)");
  s.stats.num_sliver_insertions = total;
  s.stats.num_sliver_insertions_refused = refused;
}

}  // namespace qualmesh::detail
