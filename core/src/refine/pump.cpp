// Step 3 of QUALMESH, pumping (Cheng & Dey, Section 3.7 step 3 and Section 7.3, after the sliver exudation of
// Cheng, Dey, Edelsbrunner, Facello and Teng): each vertex v of a sliver gets a weight in
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
// Order: slivers worst first, each time the best of its four vertices; passes repeat while some move is accepted.
// Then, for the slivers left, the vertices across their faces (a neighbour's star grown over the sliver), accepted
// only when the new star beats every cell the move destroys. Last, one log line says why the rest survive.
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <string>
#include <stdexcept>
#include <unordered_map>
#include <unordered_set>

#include "qualmesh/quality.h"
#include "refine/refine_state.h"

namespace qualmesh::detail {

namespace {

// The cell on vertices `ids`, if the triangulation still has it.
bool current_cell(const MeshState& s, const std::array<Index, 4>& ids, Ch3& c) {
  return s.tr.is_cell(s.vertices[ids[0]].handle, s.vertices[ids[1]].handle, s.vertices[ids[2]].handle,
                      s.vertices[ids[3]].handle, c);
}

const Kernel& kernel() {
  static const Kernel k;
  return k;
}

struct CellHash {
  std::size_t operator()(const Ch3& c) const { return std::hash<const void*>()(&*c); }
};

using Key3 = std::array<Index, 3>;
using Key2 = std::array<Index, 2>;

struct KeyHash {
  template <std::size_t N>
  std::size_t operator()(const std::array<Index, N>& k) const {
    std::size_t h = 0;
    for (Index i : k) h = h * 1000003u ^ std::hash<Index>()(i);
    return h;
  }
};

Key3 sorted3(Index a, Index b, Index c) {
  Key3 k{a, b, c};
  std::sort(k.begin(), k.end());
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

// Why a star (or a whole walk) was refused; counted for the survivors' diagnosis (pump_slivers' last log line).
enum class Refusal : std::uint8_t {
  None,             // valid
  Hidden,           // a vertex of the zone would be hidden
  LostSubsegment,   // a subsegment would stop being an edge
  LostSubfacet,     // a subfacet of a facet v is not on would vanish
  FacetNotRetiled,  // the new faces on v's facet would not cover what its subfacets covered
  Region,           // a volume vertex's zone would cross a region boundary or the domain boundary
  BadCell,          // a new cell flat, inverted, or above rho0 away from acute input angles
};

struct StarScore {
  bool valid = false;
  Refusal refusal = Refusal::None;
  // When invalid: true if every larger weight is invalid too (a vertex hidden, a subsegment or subfacet lost, a
  // volume vertex's zone across regions: the zone only grows); false for a flat or inverted new cell (a degenerate
  // event) or a cell above rho0, which a larger weight may undo.
  bool final = true;
  double min_dihedral_deg = std::numeric_limits<double>::infinity();  // over in-domain cells of the new star
  double max_radius_edge = 0;  // over in-domain cells of the new star above rho0 (all touch acute input angles)
  // Sum over in-domain cells of the new star of (sliver angle - min dihedral) where positive, in degrees: how far
  // the star is from having no sliver. Breaks ties of min_dihedral_deg (a star whose worst cell is not v's to fix
  // can still lose its other slivers).
  double sliver_deficit_deg = 0;
};

// Is star `a` better than star `b`: a larger smallest dihedral angle, or the same one (never smaller: the mesh's
// minimum dihedral angle must not drop) and less sliver deficit.
bool better(const StarScore& a, const StarScore& b) {
  if (a.min_dihedral_deg > b.min_dihedral_deg + 1e-9) return true;
  return a.min_dihedral_deg >= b.min_dihedral_deg && a.sliver_deficit_deg < b.sliver_deficit_deg - 1e-9;
}

// A new star may not raise the largest radius-edge ratio above what Rule 3 promised (rho0) or, for cells at acute
// input angles (the only ones allowed above rho0, StarEvaluator), above the old star's.
bool keeps_radius_edge(const MeshState& s, const StarScore& candidate, const StarScore& current) {
  return candidate.max_radius_edge <= std::max(s.options.radius_edge_bound, current.max_radius_edge);
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

  // The same over a walk's link, a map from sorted ids (kNoIndex last) to entries with a LinkFacet `facet` and a
  // `cell` pointer (null until measured), in which each facet keeps its measured new cell across events.
  template <typename LinkMap>
  StarScore quality_of_walk(LinkMap& link) {
    StarScore result;
    invalid_for_now_ = false;
    for (auto& kv : link) {
      if (kv.first[2] == kNoIndex) continue;  // infinite
      if (!kv.second.cell) kv.second.cell = &new_cell(kv.second.facet, kv.first);
      add_new_cell(*kv.second.cell, &result);
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
      std::unordered_set<Key3, KeyHash> inside;
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
    result->sliver_deficit_deg += std::max(0.0, s_.options.sliver_angle_deg - cell.min_dihedral_deg);
    if (cell.radius_edge > s_.options.radius_edge_bound) {
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
    if (tq.radius_edge > s_.options.radius_edge_bound) {
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
  std::unordered_map<Key3, NewCell, KeyHash> memo_;
  std::unordered_set<Key3, KeyHash> link_faces_;
  std::unordered_set<Key2, KeyHash> link_edges_;
  std::vector<Index> link_vertices_;
  std::vector<std::pair<Index, Key3>> lost_subfacets_;
};

// Critical weight of cell c for v: the weight above which v^ is closer than orthogonal to c's orthosphere.
double critical_weight(const MeshState& s, const KPoint3& p, Ch3 c) {
  if (s.tr.is_infinite(c)) return std::numeric_limits<double>::infinity();
  const auto [z, sq_r] = orthosphere(c);
  return CGAL::squared_distance(p, z) - sq_r;
}

// What ended a vertex's walk over critical weights (diagnosis of the slivers that survive).
// CapDelta / CapOmega: reached the cap, delta^2 N(v)^2 or omega0^2 f(v)^2 whichever is smaller.
enum class WalkEnd : std::uint8_t { CapDelta, CapOmega, NoRoom, Events, CurrentInvalid, Refused };

struct PumpChoice {
  WalkEnd end = WalkEnd::CapDelta;
  Refusal refusal = Refusal::None;  // when end == Refused
  double weight = 0;
  StarScore current;
  StarScore best;
  bool improves = false;
};

// The score of cells a move destroys (in-domain ones): their smallest dihedral angle and sliver deficit.
void add_destroyed_cell(const MeshState& s, Ch3 c, StarScore* score) {
  if (s.tr.is_infinite(c) || c->info().region < 0) return;
  const double angle = cell_min_dihedral_deg(s, c);
  score->min_dihedral_deg = std::min(score->min_dihedral_deg, angle);
  score->sliver_deficit_deg += std::max(0.0, s.options.sliver_angle_deg - angle);
}

// Walks the critical weights of v from its current weight up to its cap (see the file comment).
// `target` (optional): a sliver v is not a vertex of, to be removed by growing v's star over it (a neighbour of the
// sliver, after its own vertices failed). Then a star is acceptable when the sliver is in the zone and the new star
// beats every cell it destroys (the zone, not only v's old star: the sliver is not in v's star), so the mesh's
// smallest dihedral angle still cannot drop.
PumpChoice best_weight(MeshState& s, Index v, const Ch3* target = nullptr) {
  PumpChoice choice;
  const Vh3 vh = s.vertices[v].handle;
  const double w0 = vh->point().weight();
  const double f = local_feature_size_at(s, v);
  double cap = s.options.delta * s.options.delta * s.sq_nearest[v];
  if (std::isfinite(f) && s.options.omega * s.options.omega * f * f < cap) {
    cap = s.options.omega * s.options.omega * f * f;
    choice.end = WalkEnd::CapOmega;
  }
  if (!(cap > w0)) {
    choice.end = WalkEnd::NoRoom;
    return choice;
  }
  const KPoint3 p = s.kpoint(v);
  StarEvaluator evaluator(s, v);

  std::vector<Ch3> cells;
  s.tr.incident_cells(vh, std::back_inserter(cells));
  std::unordered_set<Ch3, CellHash> in_zone(cells.begin(), cells.end());
  // The link, keyed by sorted ids (kNoIndex sorts last); per facet, the critical weight of the cell across it (NaN
  // until computed) and the new cell the evaluator measured over it (null until then).
  struct LinkEntry {
    LinkFacet facet;
    double crit = std::numeric_limits<double>::quiet_NaN();
    const NewCell* cell = nullptr;
  };
  std::unordered_map<Key3, LinkEntry, KeyHash> link;
  auto key_of = [](Ch3 c, int i) {
    return sorted3(c->vertex((i + 1) & 3)->info(), c->vertex((i + 2) & 3)->info(), c->vertex((i + 3) & 3)->info());
  };
  std::unordered_map<Index, int> link_count;  // link facets per vertex: 0 = hidden
  for (const Ch3& c : cells) {
    const int i = c->index(vh);
    const Key3 k = key_of(c, i);
    link.emplace(k, LinkEntry{LinkFacet{c, i}});
    for (Index id : k) ++link_count[id];
  }
  const int star_region = cells.front()->info().region;
  const bool volume_vertex = s.vertices[v].kind == VertexKind::Volume;
  std::vector<CellElements> element_store;
  element_store.reserve(cells.size() + 256);

  auto link_vector = [&]() {
    std::vector<LinkFacet> out;
    out.reserve(link.size());
    for (const auto& kv : link) out.push_back(kv.second.facet);
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
    return choice;
  }
  choice.current = current;
  choice.best = current;
  if (!std::isfinite(current.min_dihedral_deg)) return choice;  // no in-domain cell
  StarScore destroyed;  // target mode: the zone's cells
  if (target)
    for (const Ch3& c : cells) add_destroyed_cell(s, c, &destroyed);
  bool found = false;

  std::unordered_map<Ch3, double, CellHash> crit_cache;
  auto next_event = [&](Ch3* cell) {
    double best = std::numeric_limits<double>::infinity();
    for (auto& kv : link) {
      const Ch3 n = kv.second.facet.inner->neighbor(kv.second.facet.index);
      if (std::isnan(kv.second.crit)) {
        auto it = crit_cache.find(n);
        kv.second.crit = it != crit_cache.end() ? it->second : (crit_cache[n] = critical_weight(s, p, n));
      }
      const double w = kv.second.crit;
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
    in_zone.insert(n);
    if (target) add_destroyed_cell(s, n, &destroyed);
    cells.push_back(n);
    for (int i = 0; i < 4; ++i) {
      const Key3 k = key_of(n, i);
      auto it = link.find(k);
      const int delta = it != link.end() ? -1 : 1;
      if (it != link.end()) link.erase(it);
      else link.emplace(k, LinkEntry{LinkFacet{n, i}});
      for (Index id : k) link_count[id] += delta;
    }
    bool hidden = false;
    for (int k = 0; k < 4; ++k) {
      const Index id = n->vertex(k)->info();
      hidden = hidden || (id != kNoIndex && id != v && link_count[id] <= 0);
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
          target ? in_zone.count(*target) && better(sc, destroyed) && (!found || better(sc, choice.best))
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
  return choice;
}

// Whether two sides of triangle (a, b, c) are subsegments of one segment: its vertices are consecutive on that
// segment, hence collinear, whatever their rounded coordinates say.
bool consecutive_on_a_segment(const MeshState& s, Index a, Index b, Index c) {
  const auto middle = [&s](Index u, Index m, Index w) {
    const Index seg = subsegment_of(s, u, m);
    return seg != kNoIndex && subsegment_of(s, m, w) == seg;
  };
  return middle(a, b, c) || middle(b, c, a) || middle(c, a, b);
}

// After a move that changed subfacets (StarEvaluator::lost_subfacets): flips the 2D triangulation of each such
// facet F to the new star. Raising v's weight lowers v's lifted point, so, as for an insertion, the 2D weighted
// Delaunay triangulation of F's vertices is reached by flipping edges opposite v that are not locally regular; each
// flip makes an edge vd that the 3D star has (the target). Returns false if some lost subfacet is left, or a
// subfacet at v is no 3D face (a bug: the move was checked to retile F).
bool retile_facets(MeshState& s, Index v, const std::vector<std::pair<Index, Key3>>& lost) {
  std::vector<Index> facets;
  for (const auto& l : lost) facets.push_back(l.first);
  std::sort(facets.begin(), facets.end());
  facets.erase(std::unique(facets.begin(), facets.end()), facets.end());
  const Vh3 v3 = s.vertices[v].handle;
  for (const Index facet : facets) {
    FacetMesh& fm = s.facets[facet];
    const Vh2 v2 = facet_vertex_handle(s, facet, v);
    if (v2 == Vh2()) return false;
    bool flipped = true;
    for (int round = 0; flipped && round < 1000; ++round) {
      flipped = false;
      auto fc = fm.cdt.incident_faces(v2), done = fc;
      do {
        Fh2 fh = fc;
        if (fm.cdt.is_infinite(fh) || !fh->info().in_domain()) continue;
        const int i = fh->index(v2);
        if (fh->is_constrained(i)) continue;
        const Fh2 g = fh->neighbor(i);
        if (fm.cdt.is_infinite(g) || !g->info().in_domain()) continue;
        const Vh2 d = g->vertex(fm.cdt.mirror_index(fh, i));
        const Vh2 x = fh->vertex(Cdt2::ccw(i)), y = fh->vertex(Cdt2::cw(i));
        Ch3 cell;
        int i0 = 0, i1 = 0;
        if (!s.tr.is_edge(v3, s.vertices[d->info()].handle, cell, i0, i1)) continue;
        // xy crosses vd: the quadrilateral v x d y is strictly convex.
        const auto o1 = CGAL::orientation(x->point(), y->point(), v2->point());
        const auto o2 = CGAL::orientation(x->point(), y->point(), d->point());
        const auto o3 = CGAL::orientation(v2->point(), d->point(), x->point());
        const auto o4 = CGAL::orientation(v2->point(), d->point(), y->point());
        if (o1 == CGAL::COLLINEAR || o2 == CGAL::COLLINEAR || o1 == o2 || o3 == CGAL::COLLINEAR ||
            o4 == CGAL::COLLINEAR || o3 == o4)
          continue;
        // The 2D points are rounded projections, so three consecutive vertices of one segment may pass the test
        // above, and the 3D triangulation can have the edge vd over a flat triangle of them (outside the domain).
        // Symbolically such a quadrilateral is not convex: the flip would make a triangle of collinear vertices.
        if (consecutive_on_a_segment(s, v, x->info(), d->info()) ||
            consecutive_on_a_segment(s, v, d->info(), y->info()))
          continue;
        const FaceInfo2 info = fh->info();
        fm.cdt.flip(fh, i);
        auto nc = fm.cdt.incident_faces(v2), ndone = nc;
        do {
          const Fh2 f = nc;
          if (!fm.cdt.is_infinite(f) && f->has_vertex(d)) f->info() = info;
        } while (++nc != ndone);
        flipped = true;
        break;  // the circulator is stale
      } while (++fc != done);
    }
  }
  for (const auto& l : lost)
    if (is_subfacet(s, l.first, l.second[0], l.second[1], l.second[2])) return false;
  // And every subfacet at v on those facets is a face of the 3D triangulation.
  for (const Index facet : facets) {
    const FacetMesh& fm = s.facets[facet];
    const Vh2 v2 = facet_vertex_handle(s, facet, v);
    auto fc = fm.cdt.incident_faces(v2), done = fc;
    do {
      if (fm.cdt.is_infinite(fc) || !fc->info().in_domain()) continue;
      Ch3 cell;
      int i, j, k;
      if (!s.tr.is_facet(s.vertices[fc->vertex(0)->info()].handle, s.vertices[fc->vertex(1)->info()].handle,
                         s.vertices[fc->vertex(2)->info()].handle, cell, i, j, k))
        return false;
    } while (++fc != done);
  }
  return true;
}

// Re-checks `weight` on CGAL's exact conflict zone and applies it; false (nothing changed) when a check fails or
// the star is not better.
// `target` (optional, see best_weight): the sliver must be in the zone, and the new star must beat all the cells it
// destroys (then `current` bounds only the radius-edge ratio).
bool apply_weight(MeshState& s, Index v, double weight, const StarScore& current, std::vector<Index>* touched,
                  std::size_t* num_retiled, std::size_t* num_retile_failures, const Ch3* target = nullptr) {
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
      if (angle < s.options.sliver_angle_deg)
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
  std::size_t num_retiled = 0, num_retile_failures = 0;  // moves that changed subfacets; of those, not followed
  std::size_t num_neighbour_moves = 0;
  // Per vertex, how its last walk ended (WalkEnd, or kImproved; kNotTried: never walked) and why (Refusal).
  constexpr std::uint8_t kImproved = 200, kNotTried = 255;
  std::vector<std::uint8_t> last_end(s.vertices.size(), kNotTried), last_refusal(s.vertices.size(), 0);
  for (int pass = 0; pass < kMaxPasses && !bad.empty(); ++pass) {
    std::size_t moves = 0;
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
        if (!dirty[v]) continue;
        const PumpChoice choice = best_weight(s, v);
        last_end[v] = std::uint8_t(choice.end);
        last_refusal[v] = std::uint8_t(choice.refusal);
        if (choice.improves) last_end[v] = kImproved;
        if (!choice.improves) dirty[v] = 0;
        if (choice.improves && (best_v == kNoIndex || better(choice.best, best.best))) best = choice, best_v = v;
      }
      if (best_v == kNoIndex) continue;
      if (apply_weight(s, best_v, best.weight, best.current, &touched, &num_retiled, &num_retile_failures)) {
        ++moves;
        ++s.stats.num_pump_moves;
        for (const Index t : touched) dirty[t] = 1;
      } else {
        ++s.stats.num_pump_rejected;
        dirty[best_v] = 0;
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

std::size_t pump_around(MeshState& s, const std::vector<Index>& vertices) {
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
      if (angle < s.options.sliver_angle_deg) bad.push_back({angle, ids});
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
    if (it == walks.end()) it = walks.emplace(v, best_weight(s, v)).first;
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
    double cap = s.options.delta * s.options.delta * s.sq_nearest[v];
    if (std::isfinite(f)) cap = std::min(cap, s.options.omega * s.options.omega * f * f);
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
