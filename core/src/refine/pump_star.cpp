// Star evaluation for step 3 of QUALMESH, pumping (Cheng & Dey, Section 3.7 step 3 and Section 7.3, after the
// sliver exudation of Cheng, Dey, Edelsbrunner, Facello and Teng): each vertex v of a sliver gets a weight in
// [0, min(omega0^2 f(v)^2, delta^2 N(v)^2)] (f: local feature size, N(v): nearest-vertex distance, delta < 1/2 so
// the weighted balls stay disjoint and no vertex can become hidden) that maximises the smallest dihedral angle of
// its star, in the regular (weighted Delaunay) triangulation.
//
// The walk over critical weights. Raising v's weight from w0 only enlarges v's star: the star at weight w is the
// cone from v over the boundary of the union of the cells of the triangulation without v whose orthosphere v^(w)
// is closer than orthogonal to, i.e. whose critical weight |v - z|^2 - R^2 (z, R^2: orthocentre and squared
// orthoradius of the cell) is below w. Cells not incident to v are cells of that triangulation, so, starting from
// v's current star, the next cell to join is the cell beyond a link facet with the smallest critical weight. We
// walk these events up to the cap, score each intermediate star (as a cone over the link, nothing is modified),
// and keep the best. The chosen weight (the middle of its interval, away from degeneracies) is then re-checked
// with CGAL's exact conflict zone and applied with Regular_triangulation_3::insert_in_hole, which replaces v's
// vertex; the triangulation is regular by construction.
//
// What a move must keep (checked on the exact conflict zone before anything changes, so nothing is ever undone):
//   - no vertex hidden (every vertex of the zone but v stays on its boundary), so pumping adds and removes none;
//   - conformity: every subsegment that was an edge of the zone is an edge of the new star; a subfacet of the zone
//     is either a face of the new star or, when v lies on its facet F, replaced: the faces of the new star on F
//     cover what the zone's subfacets of F covered (Section 7.2: after pumping, a facet is tiled by its
//     weighted-subfacets, the 2D weighted Delaunay triangulation of its vertices, which v's weight changes). The
//     facet's 2D triangulation is then flipped to match (retile_facets). Theorem 7.2 promises conformity under the
//     paper's conditions; we check rather than trust;
//   - regions: a new cell takes the region of the zone cell it was carved from (the cell on v's side of its link
//     facet); a volume vertex's zone must lie in one region;
//   - quality: the new star's smallest in-domain dihedral angle is strictly larger than the old one, so the mesh's
//     minimum dihedral angle never decreases; and no new cell exceeds rho0 unless it touches an acute input angle
//     (then not beyond the old star's worst), so Rule 3's radius-edge bound survives pumping.
// Which vertices are walked, and in which order, is pump.cpp's.
#include "refine/pump_star.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <unordered_map>
#include <unordered_set>

#include "qualmesh/quality.h"
#include "refine/star_keys.h"

namespace qualmesh::detail {

// The cell on vertices `ids`, if the triangulation still has it.
bool current_cell(const MeshState& s, const std::array<Index, 4>& ids, Ch3& c) {
  return s.tr.is_cell(s.vertices[ids[0]].handle, s.vertices[ids[1]].handle, s.vertices[ids[2]].handle,
                      s.vertices[ids[3]].handle, c);
}

// Is star `a` better than star `b`: a larger smallest dihedral angle, or the same one (never smaller: the mesh's
// minimum dihedral angle must not drop) and less sliver deficit.
bool better(const StarScore& a, const StarScore& b) {
  if (a.min_dihedral_deg > b.min_dihedral_deg + 1e-9) return true;
  return a.min_dihedral_deg >= b.min_dihedral_deg && a.sliver_deficit_deg < b.sliver_deficit_deg - 1e-9;
}

// A new star may not raise the largest radius-edge ratio above what Rule 3 promised (rho0) or, for cells at acute
// input angles (the only ones allowed above rho0, StarEvaluator), above the old star's.
bool keeps_radius_edge(const MeshState& s, const StarScore& candidate, const StarScore& current) {
  return candidate.max_radius_edge <= std::max(s.params.radius_edge_bound, current.max_radius_edge);
}

namespace {

const Kernel& kernel() {
  static const Kernel k;
  return k;
}

// A facet of the zone's boundary: the zone cell on v's side and the index of the facet in it.
struct LinkFacet {
  Ch3 inner;
  int index;
};

// Subsegments and subfacets among the edges and faces of one zone cell (vertex ids; kNoIndex-free).
struct CellElements {
  std::vector<Key2> subsegments;
  std::vector<Key3> subfacets;
  std::vector<Index> subfacet_facets;  // the input facet of each subfacet
};

CellElements elements_of(const MeshState& s, Ch3 c) {
  CellElements e;
  Index ids[4];
  for (int k = 0; k < 4; ++k) ids[k] = c->vertex(k)->info();
  for (int a = 0; a < 4; ++a)
    for (int b = a + 1; b < 4; ++b) {
      if (ids[a] == kNoIndex || ids[b] == kNoIndex) continue;
      if (subsegment_of(s, ids[a], ids[b]) != kNoIndex)
        e.subsegments.push_back({std::min(ids[a], ids[b]), std::max(ids[a], ids[b])});
    }
  for (int i = 0; i < 4; ++i) {
    const Index a = ids[(i + 1) & 3], b = ids[(i + 2) & 3], cc = ids[(i + 3) & 3];
    if (a == kNoIndex || b == kNoIndex || cc == kNoIndex) continue;
    const Index facet = subfacet_of(s, a, b, cc);
    if (facet == kNoIndex) continue;
    e.subfacets.push_back(sorted3(a, b, cc));
    e.subfacet_facets.push_back(facet);
  }
  return e;
}

// What StarEvaluator measures of a cell of a new star.
struct NewCell {
  bool positive = false;
  bool in_domain = false;
  bool touches_acute = false;
  double min_dihedral_deg = 0;
  double radius_edge = 0;
};

// Scores the star v would have over `link` (the boundary of zone `cells`, with `elements` their subsegments and
// subfacets): invalid when a vertex would be hidden, a sub-element would vanish, a new cell would not be
// positively oriented, or (volume vertex) the zone spans more than one region.
class StarEvaluator {
 public:
  StarEvaluator(const MeshState& s, Index v) : s_(s), v_(v), p_(s.kpoint(v)) {
    volume_vertex_ = s.vertices[v].kind == VertexKind::Volume;
  }

  // The vertex ids of link facet f (kNoIndex for the infinite vertex); true when one is infinite.
  static bool link_facet_ids(const LinkFacet& f, Index ids[3]) {
    bool infinite = false;
    for (int k = 0; k < 3; ++k) {
      ids[k] = f.inner->vertex((f.index + 1 + k) & 3)->info();
      infinite = infinite || ids[k] == kNoIndex;
    }
    return infinite;
  }

  StarScore score(const std::vector<Ch3>& cells, const std::vector<LinkFacet>& link,
                  const std::vector<const CellElements*>& elements) {
    if (volume_vertex_ && spans_regions(cells)) return refused(Refusal::Region);
    StarScore result = quality(link);
    check(cells, link, elements, false, &result);
    return result;
  }

  // score() of v's present star (`cells`, all of them incident to v, and their link). Every edge and face of a
  // star cell is either v's or an edge or face of its link, so check() can refuse nothing there (no vertex
  // hidden, no subsegment or subfacet lost, nothing to retile) and the zone's subsegments and subfacets need not be
  // read: only a volume vertex's regions and quality()'s verdict on the cells (flat, inverted, above rho0) apply.
  StarScore score_current(const std::vector<Ch3>& cells, const std::vector<LinkFacet>& link) {
    if (volume_vertex_ && spans_regions(cells)) return refused(Refusal::Region);
    StarScore result = quality(link);
    if (invalid_for_now_) {
      result.final = false;
      result.refusal = Refusal::BadCell;
    } else {
      result.valid = true;
    }
    return result;
  }

  // The first half of score(): the new cells' angles and radius-edge ratios only (memoised per link facet, cheap),
  // enough to compare stars (better(), keeps_radius_edge()); `valid` stays false until check() runs.
  StarScore quality(const std::vector<LinkFacet>& link) {
    StarScore result;
    invalid_for_now_ = false;
    for (const LinkFacet& f : link) {
      Index ids[3];
      if (link_facet_ids(f, ids)) continue;  // infinite
      add_new_cell(new_cell(f, sorted3(ids[0], ids[1], ids[2])), &result);
    }
    return result;
  }

  // The same over a walk's link, entries with sorted ids `key` (kNoIndex last), a LinkFacet `facet` and a `cell`
  // pointer (null until measured), in which each facet keeps its measured new cell across events.
  template <typename Link>
  StarScore quality_of_walk(Link& link) {
    StarScore result;
    invalid_for_now_ = false;
    for (auto& entry : link) {
      if (entry.key[2] == kNoIndex) continue;  // infinite
      if (!entry.cell) entry.cell = &new_cell(entry.facet, entry.key);
      add_new_cell(*entry.cell, &result);
    }
    return result;
  }

  // The second half of score(), after quality() on the same link: hidden vertices, lost subsegments and
  // subfacets, flat or inverted cells; sets `valid`, or `refusal` and `final`. `incremental`: the caller (the walk)
  // checks hidden vertices itself as cells join the zone.
  void check(const std::vector<Ch3>& cells, const std::vector<LinkFacet>& link,
             const std::vector<const CellElements*>& elements, bool incremental, StarScore* score) {
    StarScore& result = *score;
    link_faces_.clear();
    link_edges_.clear();
    link_vertices_.clear();
    bool has_elements = false;
    for (const CellElements* e : elements)
      has_elements = has_elements || !e->subsegments.empty() || !e->subfacets.empty();
    for (const LinkFacet& f : link) {
      Index ids[3];
      const bool infinite = link_facet_ids(f, ids);
      for (int k = 0; k < 3; ++k) {
        if (ids[k] != kNoIndex && !incremental) link_vertices_.push_back(ids[k]);
        if (!has_elements) continue;
        const Index a = ids[k], b = ids[(k + 1) % 3];
        if (a != kNoIndex && b != kNoIndex) link_edges_.insert({std::min(a, b), std::max(a, b)});
      }
      if (infinite) continue;
      if (has_elements) link_faces_.insert(sorted3(ids[0], ids[1], ids[2]));
    }
    // No vertex hidden.
    std::sort(link_vertices_.begin(), link_vertices_.end());
    if (!incremental)
      for (const Ch3& c : cells)
      for (int k = 0; k < 4; ++k) {
        const Index id = c->vertex(k)->info();
        if (id != kNoIndex && id != v_ && !std::binary_search(link_vertices_.begin(), link_vertices_.end(), id)) {
          result.refusal = Refusal::Hidden;
          return;
        }
      }
    // Conformity (Section 7.2, Theorem 7.2). Every subsegment of the zone stays an edge. The subfacets of an input
    // facet F may change, as the paper's weighted-subfacets do (the 2D weighted Delaunay triangulation of the
    // vertices on F, which a facet vertex's weight changes): a subfacet of the zone that is not a face of the new
    // star is accepted when v lies on F and the new star's faces on F, (v, a, b) over link edges ab on F, tile what
    // the zone's subfacets of F tiled. Those faces lie in the zone and do not overlap, so equal area means the same
    // part of F. Across a facet v is not on, a lost subfacet stays lost for every larger weight (the zone only
    // grows): final.
    lost_subfacets_.clear();
    for (const CellElements* e : elements) {
      for (const Key2& seg : e->subsegments) {
        if (seg[0] == v_ || seg[1] == v_) continue;  // v's edges to link vertices all exist
        if (!link_edges_.count(seg)) {
          result.refusal = Refusal::LostSubsegment;
          return;
        }
      }
      for (std::size_t i = 0; i < e->subfacets.size(); ++i) {
        const Key3& t = e->subfacets[i];
        bool kept = false;
        if (t[0] == v_ || t[1] == v_ || t[2] == v_) {
          Key2 rest{};
          int n = 0;
          for (Index id : t)
            if (id != v_) rest[n++] = id;
          kept = link_edges_.count(rest) > 0;
        } else {
          kept = link_faces_.count(t) > 0;
        }
        if (kept) continue;
        const Index facet = e->subfacet_facets[i];
        if (!vertex_on_facet(s_, v_, facet)) {
          result.refusal = Refusal::LostSubfacet;
          return;
        }
        lost_subfacets_.push_back({facet, t});
      }
    }
    std::sort(lost_subfacets_.begin(), lost_subfacets_.end());
    lost_subfacets_.erase(std::unique(lost_subfacets_.begin(), lost_subfacets_.end()), lost_subfacets_.end());
    if (!lost_subfacets_.empty() && !facets_retiled(elements)) {
      result.final = false;
      result.refusal = Refusal::FacetNotRetiled;
      return;
    }
    if (invalid_for_now_) {
      result.final = false;
      result.refusal = Refusal::BadCell;
      return;
    }
    result.valid = true;
  }

  // The subfacets (facet, sorted ids) of the zone last scored that are not faces of the new star (empty: the
  // boundary is unchanged); apply_weight brings those facets' 2D triangulations in line after the move.
  const std::vector<std::pair<Index, Key3>>& lost_subfacets() const { return lost_subfacets_; }

 private:
  static StarScore refused(Refusal why) {
    StarScore result;
    result.refusal = why;
    return result;
  }

  // A volume vertex's star must lie in one region of the domain.
  static bool spans_regions(const std::vector<Ch3>& cells) {
    int region = kUnknownRegion;
    for (const Ch3& c : cells) {
      const int r = c->info().region;
      if (region == kUnknownRegion) region = r;
      if (r != region || r < 0) return true;
    }
    return false;
  }

  static double area(const KPoint3& a, const KPoint3& b, const KPoint3& c) {
    return std::sqrt(CGAL::to_double(CGAL::squared_area(a, b, c)));
  }

  // For each facet F with a lost subfacet: the area of the zone's subfacets of F that are not link faces (the part
  // of F inside the zone) equals the area of the new star's faces on F.
  bool facets_retiled(const std::vector<const CellElements*>& elements) const {
    std::vector<Index> facets;
    for (const auto& l : lost_subfacets_) facets.push_back(l.first);
    facets.erase(std::unique(facets.begin(), facets.end()), facets.end());
    for (const Index facet : facets) {
      std::unordered_set<Key3, KeyHash, KeyEq> inside;
      double before = 0;
      for (const CellElements* e : elements)
        for (std::size_t i = 0; i < e->subfacets.size(); ++i) {
          const Key3& t = e->subfacets[i];
          if (e->subfacet_facets[i] != facet || link_faces_.count(t) || !inside.insert(t).second) continue;
          before += area(s_.kpoint(t[0]), s_.kpoint(t[1]), s_.kpoint(t[2]));
        }
      double after = 0;
      for (const Key2& ab : link_edges_) {
        if (!vertex_on_facet(s_, ab[0], facet) || !vertex_on_facet(s_, ab[1], facet)) continue;
        after += area(p_, s_.kpoint(ab[0]), s_.kpoint(ab[1]));
      }
      if (!(std::abs(after - before) <= 1e-9 * before)) return false;
    }
    return true;
  }

  // The new cell (v, f) does not depend on the weight: measured once per walk (memo_'s nodes never move).
  const NewCell& new_cell(const LinkFacet& f, const Key3& key) {
    auto it = memo_.find(key);
    if (it == memo_.end()) it = memo_.emplace(key, measure(f)).first;
    return it->second;
  }

  void add_new_cell(const NewCell& cell, StarScore* result) {
    if (!cell.positive) invalid_for_now_ = true;
    if (!cell.in_domain) return;
    result->min_dihedral_deg = std::min(result->min_dihedral_deg, cell.min_dihedral_deg);
    result->sliver_deficit_deg += s_.params.sliver_deficit_deg(cell.min_dihedral_deg);
    if (cell.radius_edge > s_.params.radius_edge_bound) {
      // Rule 3's promise stands: above rho0 only where an acute input angle forces the shortest edge.
      if (!cell.touches_acute) invalid_for_now_ = true;
      result->max_radius_edge = std::max(result->max_radius_edge, cell.radius_edge);
    }
  }

  // The cell of the new star over link facet f: f's inner cell with its vertex f.index replaced by v (same
  // orientation), region from the inner cell.
  NewCell measure(const LinkFacet& f) const {
    NewCell cell;
    std::array<KPoint3, 4> q;
    for (int k = 0; k < 4; ++k) q[k] = k == f.index ? p_ : f.inner->vertex(k)->point().point();
    cell.positive = kernel().orientation_3_object()(q[0], q[1], q[2], q[3]) == CGAL::POSITIVE;
    cell.in_domain = f.inner->info().region >= 0;
    if (!cell.in_domain) return cell;
    const TetQuality tq = tet_quality(to_point3(q[0]), to_point3(q[1]), to_point3(q[2]), to_point3(q[3]));
    cell.min_dihedral_deg = tq.min_dihedral_deg;
    cell.radius_edge = tq.radius_edge;
    if (tq.radius_edge > s_.params.radius_edge_bound) {
      std::array<Index, 4> cell_ids;
      for (int k = 0; k < 4; ++k) cell_ids[k] = k == f.index ? v_ : f.inner->vertex(k)->info();
      cell.touches_acute = tet_touches_acute_angle(s_, cell_ids);
    }
    return cell;
  }

  const MeshState& s_;
  Index v_;
  KPoint3 p_;
  bool volume_vertex_ = false;
  bool invalid_for_now_ = false;  // quality(): a new cell flat, inverted, or above rho0 off acute angles
  std::unordered_map<Key3, NewCell, KeyHash, KeyEq> memo_;
  std::unordered_set<Key3, KeyHash, KeyEq> link_faces_;
  std::unordered_set<Key2, KeyHash, KeyEq> link_edges_;
  std::vector<Index> link_vertices_;
  std::vector<std::pair<Index, Key3>> lost_subfacets_;
};

// Critical weight of cell c for v: the weight above which v^ is closer than orthogonal to c's orthosphere.
double critical_weight(const MeshState& s, const KPoint3& p, Ch3 c) {
  if (s.tr.is_infinite(c)) return std::numeric_limits<double>::infinity();
  const auto [z, sq_r] = orthosphere(c);
  return CGAL::squared_distance(p, z) - sq_r;
}

// The score of cells a move destroys (in-domain ones): their smallest dihedral angle and sliver deficit.
void add_destroyed_cell(const MeshState& s, Ch3 c, StarScore* score) {
  if (s.tr.is_infinite(c) || c->info().region < 0) return;
  const double angle = cell_min_dihedral_deg(s, c);
  score->min_dihedral_deg = std::min(score->min_dihedral_deg, angle);
  score->sliver_deficit_deg += s.params.sliver_deficit_deg(angle);
}

}  // namespace

// Walks the critical weights of v from its current weight up to its cap (see the file comment).
// `target` (optional): a sliver v is not a vertex of, to be removed by growing v's star over it (a neighbour of the
// sliver, after its own vertices failed). Then a star is acceptable when the sliver is in the zone and the new star
// beats every cell it destroys (the zone, not only v's old star: the sliver is not in v's star), so the mesh's
// smallest dihedral angle still cannot drop.
PumpChoice best_weight(MeshState& s, Index v, const Ch3* target, CellFootprint* footprint) {
  PumpChoice choice;
  const Vh3 vh = s.vertices[v].handle;
  std::vector<Ch3> cells;  // v's star, then the zone as it grows
  std::unordered_map<Ch3, double, CellHash> crit_cache;  // critical weights of the cells across the link
  // Every return goes through here: the footprint is the zone's cells and those whose critical weights were read.
  auto done = [&]() -> PumpChoice {
    if (footprint) {
      footprint->clear();
      for (const Ch3& c : cells) footprint->emplace_back(c, c->time_stamp());
      for (const auto& entry : crit_cache) footprint->emplace_back(entry.first, entry.first->time_stamp());
    }
    return choice;
  };
  const double w0 = vh->point().weight();
  const double f = local_feature_size_at(s, v);
  bool by_omega = false;
  const double cap = s.params.weight_cap(f, s.sq_nearest[v], &by_omega);
  if (by_omega) choice.end = WalkEnd::CapOmega;
  if (!(cap > w0)) {
    choice.end = WalkEnd::NoRoom;
    if (footprint) s.tr.incident_cells(vh, std::back_inserter(cells));  // N(v) and v's weight live in its star
    return done();
  }
  s.tr.incident_cells(vh, std::back_inserter(cells));
  const KPoint3 p = s.kpoint(v);
  StarEvaluator evaluator(s, v);

  bool target_in_zone = target && std::find(cells.begin(), cells.end(), *target) != cells.end();
  // The link: per facet, its sorted ids (kNoIndex sorts last), the critical weight of the cell across it (NaN until
  // computed) and the new cell the evaluator measured over it (null until then). A flat vector, scanned in place: a
  // link has a few dozen facets (44 on average over pump carter's 70k walks, 1.2M events), and every event scans it
  // twice (next_event, quality_of_walk).
  struct LinkEntry {
    Key3 key;
    LinkFacet facet;
    double crit = std::numeric_limits<double>::quiet_NaN();
    const NewCell* cell = nullptr;
  };
  std::vector<LinkEntry> link;
  link.reserve(2 * cells.size() + 16);
  auto key_of = [](Ch3 c, int i) {
    return sorted3(c->vertex((i + 1) & 3)->info(), c->vertex((i + 2) & 3)->info(), c->vertex((i + 3) & 3)->info());
  };
  // Link facets per vertex (0 = hidden).
  thread_local LinkCounts link_count;
  link_count.start();
  auto count_of = [&](Index id) -> int& { return link_count[id]; };
  for (const Ch3& c : cells) {
    const int i = c->index(vh);
    const Key3 k = key_of(c, i);
    link.push_back(LinkEntry{k, LinkFacet{c, i}});
    for (Index id : k) ++count_of(id);
  }
  const int star_region = cells.front()->info().region;
  const bool volume_vertex = s.vertices[v].kind == VertexKind::Volume;
  std::vector<CellElements> element_store;
  element_store.reserve(cells.size() + 256);

  auto link_vector = [&]() {
    std::vector<LinkFacet> out;
    out.reserve(link.size());
    for (const LinkEntry& entry : link) out.push_back(entry.facet);
    return out;
  };
  // The subsegments and subfacets of the zone's cells, read when a star is checked (StarEvaluator::check): most
  // stars of a walk are not worth checking (quality first), so the cells (v's star's too) are read lazily.
  auto element_ptrs = [&]() {
    while (element_store.size() < cells.size()) element_store.push_back(elements_of(s, cells[element_store.size()]));
    std::vector<const CellElements*> out;
    for (const auto& e : element_store) out.push_back(&e);
    return out;
  };
  const StarScore current = evaluator.score_current(cells, link_vector());
  if (!current.valid && current.final) {
    choice.end = WalkEnd::CurrentInvalid;
    choice.refusal = current.refusal;
    return done();
  }
  choice.current = current;
  choice.best = current;
  if (!std::isfinite(current.min_dihedral_deg)) return done();  // no in-domain cell
  StarScore destroyed;  // target mode: the zone's cells
  if (target)
    for (const Ch3& c : cells) add_destroyed_cell(s, c, &destroyed);
  bool found = false;

  auto next_event = [&](Ch3* cell) {
    double best = std::numeric_limits<double>::infinity();
    for (LinkEntry& entry : link) {
      const Ch3 n = entry.facet.inner->neighbor(entry.facet.index);
      if (std::isnan(entry.crit)) {
        auto it = crit_cache.find(n);
        entry.crit = it != crit_cache.end() ? it->second : (crit_cache[n] = critical_weight(s, p, n));
      }
      const double w = entry.crit;
      if (w < best) best = w, *cell = n;
    }
    return best;
  };
  constexpr int kMaxEvents = 96;  // stars change a few dozen times within the caps
  Ch3 n;
  double w = next_event(&n);
  for (int event = 0; event < kMaxEvents && w < cap; ++event) {
    if (w < w0) w = w0;  // rounding: a cell already due
    // Absorb n: toggle its four faces in the link.
    if (volume_vertex && n->info().region != star_region) {  // a volume vertex's star stays in its region
      choice.end = WalkEnd::Refused;
      choice.refusal = Refusal::Region;
      break;
    }
    if (target) {
      target_in_zone = target_in_zone || n == *target;
      add_destroyed_cell(s, n, &destroyed);
    }
    cells.push_back(n);
    for (int i = 0; i < 4; ++i) {
      const Key3 k = key_of(n, i);
      auto it = std::find_if(link.begin(), link.end(), [&](const LinkEntry& e) { return KeyEq()(e.key, k); });
      const int delta = it != link.end() ? -1 : 1;
      if (it != link.end()) {
        *it = link.back();
        link.pop_back();
      } else {
        link.push_back(LinkEntry{k, LinkFacet{n, i}});
      }
      for (Index id : k) count_of(id) += delta;
    }
    bool hidden = false;
    for (int k = 0; k < 4; ++k) {
      const Index id = n->vertex(k)->info();
      hidden = hidden || (id != kNoIndex && id != v && count_of(id) <= 0);
    }
    if (hidden) {  // the zone only grows: a hidden vertex stays hidden
      choice.end = WalkEnd::Refused;
      choice.refusal = Refusal::Hidden;
      break;
    }
    Ch3 n2;
    const double w_next = next_event(&n2);
    const double hi = std::min(w_next, cap);
    if (hi > w) {
      // Only a star that would be chosen is checked in full (the link's edges and faces against the zone's
      // subsegments and subfacets, the expensive half of the score). A star skipped here may be finally invalid
      // (a lost element), which ends the walk when found; the walk then ends at the next star that would be
      // chosen, found invalid for the same reason (the zone only grows), and picks the same weight.
      StarScore sc = evaluator.quality_of_walk(link);
      const bool wanted =
          target ? target_in_zone && better(sc, destroyed) && (!found || better(sc, choice.best))
                 : better(sc, choice.best);
      if (wanted && keeps_radius_edge(s, sc, current)) {
        evaluator.check(cells, link_vector(), element_ptrs(), true, &sc);
        if (!sc.valid && sc.final) {  // the zone only grows: a hidden vertex or a lost element stays so
          choice.end = WalkEnd::Refused;
          choice.refusal = sc.refusal;
          break;
        }
        if (sc.valid) {
          choice.best = sc;
          choice.weight = 0.5 * (w + hi);
          found = true;
        }
      }
    }
    n = n2;
    w = w_next;
  }
  if (choice.end != WalkEnd::Refused && w < cap) choice.end = WalkEnd::Events;
  choice.improves = (target ? found : better(choice.best, current)) && choice.weight > w0;
  return done();
}

bool footprint_holds(const MeshState& s, const CellFootprint& footprint) {
  const auto& container = s.tr.tds().cells();
  return std::all_of(footprint.begin(), footprint.end(), [&](const std::pair<Ch3, std::size_t>& c) {
    return container.is_used(c.first) && c.first->time_stamp() == c.second;
  });
}

const PumpChoice& WalkCache::walk(MeshState& s, Index v) {
  auto [it, fresh] = entries_.try_emplace(v);
  Entry& e = it->second;
  if (!fresh && footprint_holds(s, e.cells)) {
    ++hits_;
    return e.choice;
  }
  ++misses_;
  e.choice = best_weight(s, v, nullptr, &e.cells);
  return e.choice;
}

// Re-checks `weight` on CGAL's exact conflict zone and applies it; false (nothing changed) when a check fails or
// the star is not better.
// `target` (optional, see best_weight): the sliver must be in the zone, and the new star must beat all the cells it
// destroys (then `current` bounds only the radius-edge ratio).
bool apply_weight(MeshState& s, Index v, double weight, const StarScore& current, std::vector<Index>* touched,
                  std::size_t* num_retiled, std::size_t* num_retile_failures, const Ch3* target) {
  const Vh3 vh = s.vertices[v].handle;
  const KWeightedPoint3 wp(s.kpoint(v), weight);
  std::vector<Ch3> cells;
  std::vector<Facet3> boundary;
  s.tr.find_conflicts(wp, vh->cell(), std::back_inserter(boundary), std::back_inserter(cells),
                      CGAL::Emptyset_iterator());
  if (cells.empty() || boundary.empty()) return false;
  // Every cell of v's star must be in the zone (the new vertex replaces v).
  std::vector<Ch3> star;
  s.tr.incident_cells(vh, std::back_inserter(star));
  std::unordered_set<Ch3, CellHash> zone(cells.begin(), cells.end());
  for (const Ch3& c : star)
    if (!zone.count(c)) return false;
  std::vector<LinkFacet> link;
  link.reserve(boundary.size());
  for (const Facet3& f : boundary) link.push_back({f.first, f.second});
  std::vector<CellElements> elements;
  elements.reserve(cells.size());
  for (const Ch3& c : cells) elements.push_back(elements_of(s, c));
  std::vector<const CellElements*> ptrs;
  for (const auto& e : elements) ptrs.push_back(&e);
  StarEvaluator evaluator(s, v);
  const StarScore sc = evaluator.score(cells, link, ptrs);
  if (!sc.valid || !keeps_radius_edge(s, sc, current)) return false;
  if (target) {
    StarScore destroyed;
    for (const Ch3& c : cells) add_destroyed_cell(s, c, &destroyed);
    if (!zone.count(*target) || !better(sc, destroyed)) return false;
  } else if (!better(sc, current)) {
    return false;
  }

  // Regions of the new cells: the zone cell each was carved from, found across its outer face after insertion.
  std::vector<HoleFace> outer;
  outer.reserve(boundary.size());
  for (const Facet3& f : boundary) outer.push_back(hole_face(f, f.first->info().region));
  // Stars that change: v's and those of the zone's vertices.
  for (const Ch3& c : cells)
    for (int k = 0; k < 4; ++k)
      if (c->vertex(k)->info() != kNoIndex) touched->push_back(c->vertex(k)->info());
  const std::size_t num_before = s.tr.number_of_vertices();
  const Vh3 nv = s.tr.insert_in_hole(wp, cells.begin(), cells.end(), boundary.front().first,
                                     boundary.front().second);
  nv->info() = v;
  s.vertices[v].handle = nv;
  for (const HoleFace& o : outer) {
    const Ch3 c = o.new_cell();
    c->info().region = s.tr.is_infinite(c) ? kOutsideRegion : o.region;
    c->info().guess = kUnknownRegion;
  }
  if (!evaluator.lost_subfacets().empty()) {
    ++*num_retiled;
    if (!retile_facets(s, v, evaluator.lost_subfacets())) ++*num_retile_failures;
  }
  if (s.tr.number_of_vertices() != num_before) {
    // Unreachable: the zone check above keeps every vertex; a hidden vertex would break "no vertex removed".
    throw std::logic_error("pumping hid a vertex");
  }
  return true;
}

}  // namespace qualmesh::detail
