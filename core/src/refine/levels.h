// The refinement levels of QUALMESH step 2 (Cheng & Dey, Section 3.7) without Rule 4, modelled on CGAL Mesh_3's
// Mesher_level: each Rule is a level with its own queue, a refinement point for an element, a conflict test of that
// point (the Conflict below) and an after-insertion hook that queues what an insertion made bad:
//   Rule 1, Rule1Subsegments (rule1_subsegments.cpp): encroached or missing subsegments, split at a midpoint or a
//           concentric-shell point;
//   Rule 2, Rule2Subfacets (rule2_subfacets.cpp): encroached or missing subfacets, split at a circumcentre unless
//           it encroaches a subsegment (Lemma 3.5 picks the subfacet);
//   Rule 3, Rule3Tets (rule3_tets.cpp): tetrahedra of radius-edge ratio above rho0 or too large for the size field,
//           split at a circumcentre unless it encroaches a subsegment or subfacet.
// The scheduler (scheduler.cpp, run_refinement) drains them in the paper's priority order: a level runs only when
// the queues of the levels before it are empty. Every insertion goes through one module (insertion.cpp,
// insert_vertex), which returns what it changed (InsertionResult); notify_insertion hands that to every level's hook.
// Rules 1-2 decide who encroaches with the EncroachmentPolicy they are given (refine_params.h).
//
// A parallel version would lock or partition by conflict zone: a level's refinement point and conflict test read
// only the element's neighbourhood and its conflict zone, and InsertionResult names everything an insertion touched.
#pragma once

#include <array>
#include <cstdint>
#include <deque>
#include <vector>

#include "cgal_types.h"
#include "refine/refine_params.h"

namespace qualmesh::detail {

struct MeshState;

// The outcome of a level's conflict test of its refinement point.
enum class Conflict : std::uint8_t {
  None,             // the point encroaches nothing it must not: insert it
  SplitSubsegment,  // it encroaches subsegments, now queued for Rule 1: the element waits (queued again)
  SplitSubfacet,    // it encroaches (or its insertion would remove) subfacets, now queued for Rule 2: it waits
  Drop,             // the point is unusable (on a vertex, or its zone inconsistent) and nothing was queued
};

// The cells whose circumsphere holds a point (the cells its insertion destroys), the facets of their union's
// boundary and the facets between two of them (CGAL find_conflicts).
struct ConflictZone {
  std::vector<Ch3> cells;
  std::vector<Facet3> boundary;
  std::vector<Facet3> internal;
};

// Subsegments (segment, u, v with u < v) and subfacets (facet, a, b, c with a < b < c) that are edges / faces of
// a conflict zone's cells, sorted, each once.
struct Candidates {
  std::vector<std::array<Index, 3>> subsegments;
  std::vector<std::array<Index, 4>> subfacets;
};

// What one insertion changed (insertion.cpp insert_vertex). Handles to the destroyed cells are gone; their
// subsegments and subfacets are listed by vertex ids.
struct InsertionResult {
  Index vertex = kNoIndex;  // the new vertex
  int region = kUnknownRegion;  // region given to the new in-domain cells (kUnknownRegion: flooded later)
  std::size_t num_destroyed_cells = 0;
  std::vector<Ch3> new_cells;  // the new vertex's star: one cell per facet of the hole's boundary
  // The zone's subsegments and subfacets (Candidates), each with whether it is still an edge / face (it lies on
  // the hole's boundary; the others were destroyed with the zone).
  std::vector<std::array<Index, 3>> zone_subsegments;
  std::vector<std::uint8_t> zone_subsegment_kept;
  std::vector<std::array<Index, 4>> zone_subfacets;
  std::vector<std::uint8_t> zone_subfacet_kept;
  // New subsegments (segment, u, v), the two halves of a split subsegment (prev, w) and (w, next), and new
  // subfacets (facet, a, b, c), the new vertex's stars in its facets' 2D triangulations.
  std::vector<std::array<Index, 3>> new_subsegments;
  std::vector<std::array<Index, 4>> new_subfacets;
};

// --- Rule 1 (rule1_subsegments.cpp) ------------------------------------------------------------------------------

struct SubsegmentEntry {
  Index segment;
  Index u, v;  // consecutive vertices on the segment
  bool forced = false;  // a rejected circumcentre encroaches it: split even if no vertex does
  // Forced by a subfacet's centre (Rule 2): split whatever MeshOptions::min_split_length says, since the subfacet
  // waits for it (a missing one would otherwise stay missing).
  bool below_floor_too = false;
};

class Rule1Subsegments {
 public:
  std::deque<SubsegmentEntry> queue;
  EncroachmentPolicy policy;

  bool empty() const { return queue.empty(); }
  void push(const SubsegmentEntry& e) { queue.push_back(e); }
  // True when subsegment (u, v) of `segment` is missing from the triangulation or a vertex the policy counts lies
  // strictly inside its diametral ball; *encroacher gets that vertex (kNoIndex when missing).
  bool encroached(const MeshState& s, Index segment, Index u, Index v, Index* encroacher) const;
  void enqueue_if_encroached(MeshState& s, Index segment, Index u, Index v);
  // Rule 1's point on (u, v): the midpoint, or a concentric-shell point next to an acute apex; *t: its parameter
  // along the segment.
  Point3 refinement_point(const MeshState& s, Index segment, Index u, Index v, double* t) const;
  // A subsegment's split point is never rejected: None, or Drop when rounding put it on a vertex. Fills `cz`.
  Conflict conflict(MeshState& s, const Point3& p, Ch3 hint, ConflictZone& cz) const;
  // Pops the front entry and splits it if it is still a subsegment and still encroached (or forced).
  void refine_one(MeshState& s);
  // Queues the zone's subsegments that the insertion removed or that the new vertex encroaches, and the new
  // subsegments when encroached.
  void after_insertion(MeshState& s, const InsertionResult& r);
};

// --- Rule 2 (rule2_subfacets.cpp) --------------------------------------------------------------------------------

struct SubfacetEntry {
  Index facet;
  std::array<Index, 3> vertices;
  bool has_point = false;  // a rejected circumcentre encroaches it (Rule 3)
  Point3 point{};
  bool forced = false;  // split even when no vertex encroaches it (Rule 3 rejection)
  int attempts = 0;     // times its split point was rejected (it is queued again behind Rule 1's splits)
  bool eager = false;   // split when any vertex encroaches it, whichever the policy says
};

class Rule2Subfacets {
 public:
  std::deque<SubfacetEntry> queue;
  EncroachmentPolicy policy;

  bool empty() const { return queue.empty(); }
  void push(const SubfacetEntry& e) { queue.push_back(e); }
  // True when subfacet abc is missing or a vertex (any vertex with `all`, else one the policy counts) lies strictly
  // inside its diametral ball; *encroacher gets it (kNoIndex when missing).
  bool encroached(const MeshState& s, const std::array<Index, 3>& abc, Index* encroacher, bool all) const;
  void enqueue_if_encroached(MeshState& s, Index facet, const std::array<Index, 3>& abc);
  void enqueue_if_encroached(MeshState& s, Index facet, const std::vector<std::array<Index, 3>>& faces);
  // Rule 2's point: the circumcentre of subfacet abc.
  KPoint3 refinement_point(const MeshState& s, const std::array<Index, 3>& abc) const;
  // Rule 2's second clause: SplitSubsegment when the centre encroaches subsegments or leaves the facet across one
  // (those are queued, forced); Drop when it coincides with a vertex or leaves the facet with nothing to split;
  // None: insert it (`cz`, `cand`: its conflict zone and the zone's elements).
  Conflict conflict(MeshState& s, Index facet, const std::array<Index, 3>& abc, const KPoint3& center,
                    ConflictZone& cz, Candidates& cand) const;
  // Pops the front entry and splits the subfacet Lemma 3.5 picks, if it is still a subfacet and still encroached
  // (or forced); a rejected split queues it again behind Rule 1 (up to 16 times).
  void refine_one(MeshState& s);
  // Queues the zone's subfacets that the insertion removed or that the new vertex encroaches, and the new
  // subfacets when encroached.
  void after_insertion(MeshState& s, const InsertionResult& r);
};

// --- Rule 3 (rule3_tets.cpp) -------------------------------------------------------------------------------------

struct TetEntry {
  std::array<Index, 4> vertices;
  int attempts = 0;  // times its circumcentre was rejected
};

// Rule 3's verdict on an in-domain cell: good, radius-edge ratio above rho0 (or degenerate), too large for the
// size field, or above the bound only because an acute input angle forces its shortest edge (left alone).
enum class TetVerdict { Good, Skinny, TooLarge, ForcedBySmallAngle };

class Rule3Tets {
 public:
  std::deque<TetEntry> queue;
  // Tetrahedra (sorted vertex ids) given up after 8 rejected circumcentres (MeshStats' "rejected").
  std::vector<std::array<Index, 4>> given_up;

  bool empty() const { return queue.empty(); }
  TetVerdict judge(MeshState& s, Ch3 c) const;
  // Queues in-domain cell c when it is skinny or too large.
  void enqueue_if_bad(MeshState& s, Ch3 c);
  void enqueue_all(MeshState& s);
  // Rule 3's point for cell v: its circumcentre, or the centre of its largest face's circle when it is degenerate
  // (four nearly cocircular points).
  KPoint3 refinement_point(const MeshState& s, const std::array<Index, 4>& v) const;
  // Rule 3's two bullets for point z of cell c (entry e): SplitSubsegment when z encroaches subsegments,
  // SplitSubfacet when it encroaches subfacets or its zone leaves the region (those are queued for Rules 1-2);
  // Drop when z is unusable and c has no subfacet to split; None: insert z (`cz`, `cand`: its zone).
  Conflict conflict(MeshState& s, const TetEntry& e, Ch3 c, const KPoint3& z, ConflictZone& cz,
                    Candidates& cand);
  // Pops the front entry and refines it if it is still a bad cell of the domain.
  void refine_one(MeshState& s);
  // Queues the new in-domain cells of the star that are bad.
  void after_insertion(MeshState& s, const InsertionResult& r);
  void give_up(std::array<Index, 4> v);
};

}  // namespace qualmesh::detail
