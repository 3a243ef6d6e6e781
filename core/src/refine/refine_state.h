// State of the refinement engine (paper Section 3.7, steps 1-2): the one Regular_triangulation_3, the vertex
// records with their symbolic host (input vertex, point of a segment with parameter t, point of a facet with local
// coordinates (u, v), or a volume point), the subsegment chains (Section 3.2), the subfacet triangulations
// (Section 3.2), the regions, and the levels of Rules 1, 2 and 3 with their queues (levels.h).
//
// Stage files: complex.cpp (input), refine_params.cpp (derived parameters, encroachment policy), subsegments.cpp
// (chains, Rule 1 split points), subfacets.cpp (per-facet 2D triangulations, Lemma 3.5 projection, retiling after
// pumping), insertion.cpp (the one insertion), rule1_subsegments.cpp, rule2_subfacets.cpp, rule3_tets.cpp (the
// levels), scheduler.cpp (their order), small_angles.cpp (acute input angles), regions.cpp (flood fill), rule4.cpp,
// pump_star.cpp and pump.cpp (Rule 4, step 3), sliver_insertion.cpp, extract.cpp (TetMesh), mesher.cpp
// (orchestration, public API).
#pragma once

#include <array>
#include <deque>
#include <memory>
#include <optional>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "cgal_types.h"
#include "qualmesh/mesher.h"
#include "qualmesh/quality.h"
#include "local_feature_size.h"
#include "refine/complex.h"
#include "refine/flat_map.h"
#include "refine/levels.h"
#include "refine/refine_params.h"

namespace qualmesh::detail {

// MeshState::count_below_floor_split's budget, beyond the number of input vertices. Healthy CAD runs make a few
// dozen such splits (wrenchnut.stp at its default size 107, part.step 51, Zylkopf.stp 7); the runaways make
// thousands: part.step's surface without the cross-face edge splits (brep_to_plc.cpp) had a subsegment split down
// to 2e-4 against a floor of 0.35, 9500 Rule 1 points and counting.
inline constexpr std::size_t kBelowFloorSplitBudget = 2000;

enum class VertexKind : std::uint8_t { Input, Segment, Facet, Volume };

struct VertexRecord {
  Point3 point{};
  VertexKind kind = VertexKind::Input;
  Index host = kNoIndex;  // segment id (Segment), facet id (Facet); input vertex id for Input
  double t = 0;           // Segment: parameter along the host segment, 0 at its `a`, 1 at its `b`
  Index prev = kNoIndex;  // Segment: neighbours along the host segment (an endpoint id or a Segment vertex id)
  Index next = kNoIndex;
  Vh3 handle;
  Vh2 facet_handle;  // Facet: the vertex in its host facet's 2D triangulation (FacetMesh's map holds the others)
};

// One input facet's subfacets: the Delaunay triangulation of the vertices on the facet (Section 3.2) in the facet's
// plane frame, constrained by its subsegments so that its in-domain triangles stay defined while subsegments are
// encroached. `handle_map` maps the id of a vertex on a segment or an input vertex to its 2D vertex; a facet vertex
// keeps its own in VertexRecord::facet_handle (facet_vertex_handle() looks in the right place).
struct FacetMesh {
  Cdt2 cdt;
  FlatMap<Vh2> handle_map;
  Vh2 find(Index vertex) const {
    const Vh2* vh = handle_map.find(vertex);
    return vh ? *vh : Vh2();
  }
};

struct SegmentChain {
  Index first = kNoIndex;  // first Steiner vertex after `a` (or `b` when none)
  Index last = kNoIndex;   // last Steiner vertex before `b` (or `a` when none)
};

struct RegionInfo {
  int attribute = 0;
  double max_volume = 0;  // <= 0: none
};

struct MeshState {
  const Plc* plc = nullptr;
  MeshOptions options;  // as the user gave them; the engine reads `params`
  RefineParams params;  // derived once from `options` (RefineParams::from)

  InputComplex complex;
  RegularTriangulation3 tr;
  std::vector<VertexRecord> vertices;
  std::vector<SegmentChain> chains;
  std::vector<FacetMesh> facets;
  std::vector<RegionInfo> regions;  // per component id
  bool regions_known = false;
  std::vector<Index> region_pending;  // boundary vertices inserted since the last flood

  // The levels, each with its queue (levels.h); Rules 1-2 hold params.encroachment (init_levels).
  Rule1Subsegments rule1;
  Rule2Subfacets rule2;
  Rule3Tets rule3;

  // Rule 4 and pumping (rule4.cpp, pump.cpp): the local feature size of the input (built on first use) and its
  // value per vertex (negative: not computed yet).
  std::unique_ptr<LocalFeatureSize> lfs;
  std::vector<double> lfs_at;
  // Pumping's cap delta^2 N(v)^2: N(v)^2 per vertex, measured when step 3 starts (pump_slivers) and lowered when
  // sliver insertion adds a vertex next to v.
  std::vector<double> sq_nearest;

  // Encroaching::Steiner's work budget (run_refinement): cells of the conflict zones computed since the last check.
  std::size_t zone_cells = 0, zone_count = 0;
  // Non-empty: why Encroaching::Steiner gave up (run_refinement stopped); mesh_plc() starts again with the paper's
  // rule.
  std::string steiner_abandoned;

  MeshStats stats;
  ProgressCallback progress;
  LogCallback log;
  MeshStage stage = MeshStage::Initial;
  bool vertex_limit_reached = false;  // also set on cancellation: every stage stops as at the vertex limit
  bool cancelled = false;             // MeshOptions::cancel returned true
  // MeshOptions::project_to_boundary's safety net: the vertex count the pumping stage may reach (set when it
  // begins); past it, projection_runaway and vertex_limit_reached stop every stage, and mesh_plc()
  // meshes again without the projection.
  std::size_t pumping_vertex_budget = static_cast<std::size_t>(-1);
  bool projection_runaway = false;
  // Rules 1-2 splits of elements below MeshOptions::min_split_length (forced by a missing subsegment or subfacet,
  // or by a missing subfacet's centre). With MeshOptions::project_to_boundary, more than
  // kBelowFloorSplitBudget of them is taken for a runaway as well (count_below_floor_split).
  std::size_t below_floor_splits = 0;
  void count_below_floor_split() {
    if (++below_floor_splits > kBelowFloorSplitBudget + plc->vertices.size() && options.project_to_boundary)
      projection_runaway = vertex_limit_reached = true;
  }
  // Non-empty: why refinement stopped at the limit of double precision. A Rule 1-2 point whose place in a facet's
  // 2D triangulation is already a vertex (facet_accepts_point) cannot be inserted, and the element it was to split
  // stays encroached or missing, so every stage stops as at the vertex limit; mesh_plc() meshes again with its next
  // fallback, and the last one returns MeshStatus::PrecisionExhausted.
  std::string precision_stop;
  // Records the first such stop: `element` names the input element ("segment 291"), `size` the length (radius) of
  // its subsegment (subfacet), `where` the split point (subfacets.cpp).
  void stop_at_precision(const std::string& element, double size, const Point3& where);
  std::size_t cancel_polls = 0;

  // Polls MeshOptions::cancel every 64 calls; true (and vertex_limit_reached) once it has said stop.
  bool poll_cancel() {
    if (cancelled || !options.cancel || (++cancel_polls & 63) != 0) return cancelled;
    if (options.cancel()) cancelled = vertex_limit_reached = true;
    return cancelled;
  }

  // Sets the user's options and derives the parameters once; Rules 1-2 get the encroachment policy.
  void set_options(const MeshOptions& o) {
    options = o;
    params = RefineParams::from(o);
    rule1.policy = params.encroachment;
    rule2.policy = params.encroachment;
  }

  void log_line(const std::string& line) const {
    if (log) log(line);
  }
  const Point3& point(Index v) const { return vertices[v].point; }
  KPoint3 kpoint(Index v) const { return to_kpoint(vertices[v].point); }
};

// A facet of a conflict zone's boundary, seen from the cell outside the zone: after insert_in_hole the new cell on
// that facet is new_cell() (the new vertex's star, without a walk around it). `region`: what the caller wants to
// carry from the destroyed cell inside to the new one.
struct HoleFace {
  Ch3 outside;
  int mirror;
  int region;
  Ch3 new_cell() const { return outside->neighbor(mirror); }
};
inline HoleFace hole_face(const Facet3& f, int region) {
  const Ch3 n = f.first->neighbor(f.second);
  return {n, n->index(f.first), region};
}

// Whether p lies strictly inside the diametral ball of segment ab / of triangle abc (Section 3.2: p encroaches it).
inline bool strictly_encroaches(const KPoint3& a, const KPoint3& b, const KPoint3& p) {
  return Kernel().side_of_bounded_sphere_3_object()(a, b, p) == CGAL::ON_BOUNDED_SIDE;
}
inline bool strictly_encroaches(const KPoint3& a, const KPoint3& b, const KPoint3& c, const KPoint3& p) {
  return Kernel().side_of_bounded_sphere_3_object()(a, b, c, p) == CGAL::ON_BOUNDED_SIDE;
}

// Smallest dihedral angle of finite cell c in degrees, measured once per cell (CellInfo::min_dihedral_deg): the
// pumping passes and sliver insertion rescan every cell many times.
inline double cell_min_dihedral_deg(const MeshState& s, Ch3 c) {
  double& angle = c->info().min_dihedral_deg;
  if (angle < 0)
    angle = tet_min_dihedral_deg(s.point(c->vertex(0)->info()), s.point(c->vertex(1)->info()),
                                 s.point(c->vertex(2)->info()), s.point(c->vertex(3)->info()));
  return angle;
}

// Radius-edge ratio of finite cell c, measured once per cell (CellInfo::radius_edge): sliver insertion reads the cells
// of overlapping conflict zones, candidate after candidate and sliver after sliver.
inline double cell_radius_edge(const MeshState& s, Ch3 c) {
  double& rho = c->info().radius_edge;
  if (rho < 0)
    rho = tet_radius_edge(s.point(c->vertex(0)->info()), s.point(c->vertex(1)->info()), s.point(c->vertex(2)->info()),
                          s.point(c->vertex(3)->info()));
  return rho;
}

// Vertex v in the 2D triangulation of `facet` (null when v is not on it). A facet vertex keeps its handle in its
// record; the others (on segments, input vertices: on several facets) are in the facet's map.
inline Vh2 facet_vertex_handle(const MeshState& s, Index facet, Index v) {
  const VertexRecord& r = s.vertices[v];
  if (r.kind == VertexKind::Facet) return r.host == facet ? r.facet_handle : Vh2();
  return s.facets[facet].find(v);
}

// --- complex / vertices (subsegments.cpp) ---
// Is vertex v on segment s (symbolically)?
bool vertex_on_segment(const MeshState& s, Index v, Index segment);
// Is vertex v on facet f (symbolically)?
bool vertex_on_facet(const MeshState& s, Index v, Index facet);
// Whether vertex w of `facet` lies strictly inside the circumcircle of subfacet abc in the facet's 2D triangulation
// (true when one of them is not in it yet).
bool encroaches_in_facet_plane(const MeshState& s, Index facet, const std::array<Index, 3>& abc, Index w);
// Is vertex v on a facet of plane group `group` (InputComplex::plane_group), symbolically?
bool vertex_on_plane(const MeshState& s, Index v, Index group);
// The vertex after / before v along segment `segment` (v must be on it), kNoIndex at the end.
Index next_on_segment(const MeshState& s, Index segment, Index v);
// The segment of which (u, v) is a subsegment (consecutive vertices), or kNoIndex.
Index subsegment_of(const MeshState& s, Index u, Index v);
// Can a vertex of this kind end a subsegment (an input vertex or one on a segment)? subsegment_of is kNoIndex
// unless both ends can; a caller that has the kinds at hand skips the call for other pairs.
inline bool can_end_subsegment(VertexKind kind) { return kind == VertexKind::Input || kind == VertexKind::Segment; }
// The parameter of vertex w along `segment`: 0 at its `a`, 1 at its `b`, VertexRecord::t for a vertex inside it.
double segment_parameter(const MeshState& s, Index segment, Index w);
// Rule 1 split point of subsegment (u, v) of `segment`: its midpoint, or Shewchuk's concentric-shell point when an
// end is an acute input vertex. Returns the parameter t along the segment.
double subsegment_split_parameter(const MeshState& s, Index segment, Index u, Index v);
// Links a new Segment vertex w between u and v on `segment`.
void link_segment_vertex(MeshState& s, Index segment, Index u, Index v, Index w);
// Sorted input vertex ids of the input element hosting a vertex, for adjacency tests (empty for volume vertices).
const std::vector<Index>* host_element_vertices(const MeshState& s, Index v, std::vector<Index>& scratch);

// --- subfacets (subfacets.cpp) ---
void build_facet_meshes(MeshState& s);
// Facets that contain all three vertices, checked against their 2D triangulations: the facet of which (a, b, c) is
// an in-domain subfacet, or kNoIndex.
Index subfacet_of(const MeshState& s, Index a, Index b, Index c);
// Whether a boundary point `r` (kind Segment, with its chain neighbours prev and next, or kind Facet) has a place in
// the 2D triangulation of every facet it lies on: false when its location there is already a vertex (refinement at
// the limit of double precision), or when a segment point's neighbours are not joined by an edge. Rules 1-2 ask
// before inserting (MeshState::stop_at_precision); insert_into_facet() then finds the same place.
bool facet_accepts_point(const MeshState& s, const VertexRecord& r);
// Inserts vertex w (on facet f, or on a segment of f) into f's 2D triangulation; returns the new subfacets. Throws
// std::logic_error where facet_accepts_point() is false.
void insert_into_facet(MeshState& s, Index facet, Index w, std::vector<std::array<Index, 3>>* new_faces);
// Is (a, b, c) an in-domain subfacet of f?
bool is_subfacet(const MeshState& s, Index facet, Index a, Index b, Index c);
// The in-domain subfacet of f containing the projection of `p` (Lemma 3.5), if any.
// `hint`: a vertex of f near p (kNoIndex: none), where the 2D walk starts.
std::optional<std::array<Index, 3>> subfacet_containing_projection(const MeshState& s, Index facet, const Point3& p,
                                                                   Index hint = kNoIndex);
// The first subsegment (its two vertex ids) that the straight line in f's plane from the centroid of subfacet abc
// to p's location crosses; none when p's location is reached first (or the walk leaves the triangulation or
// takes more than 256 steps).
std::optional<std::array<Index, 2>> subsegment_towards(const MeshState& s, Index facet,
                                                      const std::array<Index, 3>& abc, const Point3& p);
// Is the 2D location of point p (on f's plane) inside f's domain?
bool facet_point_in_domain(const MeshState& s, Index facet, const Point3& p, Index hint = kNoIndex);
// Tries to flip 2D edges of subfacet (a, b, c) so that f's subfacets match the 3D triangulation's choice among
// cocircular configurations; appends the new subfacets and returns true when it flipped.
// `only_across_from`: flip only the edge of abc opposite that vertex (kNoIndex: any edge).
bool flip_subfacet_to_match(MeshState& s, Index facet, const std::array<Index, 3>& abc,
                            std::vector<std::array<Index, 3>>* new_faces, Index only_across_from = kNoIndex);
// All in-domain subfacets of f.
void collect_subfacets(const MeshState& s, Index facet, std::vector<std::array<Index, 3>>& out);
// Which facet (if any) the triangulation face (c, i) is a subfacet of.
Index face_subfacet(const MeshState& s, Ch3 c, int i);
// After a pumping move of vertex v that replaced subfacets (`lost`: facet, sorted ids), flips those facets' 2D
// triangulations to the new 3D star (Section 7.2's weighted-subfacets). False if some lost subfacet is left, or a
// subfacet at v is no 3D face (a bug: the move was checked to retile its facets).
bool retile_facets(MeshState& s, Index v, const std::vector<std::pair<Index, std::array<Index, 3>>>& lost);

// --- insertion (insertion.cpp) ---
// Step 1: the Delaunay triangulation of the input vertices (throws InputError on duplicates or no volume).
void insert_input_vertices(MeshState& s);
// The conflict zone of p (weight zero), located from `hint`; false when p coincides with a vertex (or the zone is
// empty). Counts the zone for Encroaching::Steiner's work budget.
bool find_conflict_zone(MeshState& s, const KPoint3& p, Ch3 hint, ConflictZone& cz);
void collect_candidates(const MeshState& s, const ConflictZone& cz, Candidates& out);
// Appends a vertex record (not yet in the triangulation); returns its id.
Index add_vertex(MeshState& s, const Point3& p, VertexKind kind, Index host, double t = 0);

// boundary_projection.cpp: a Rule 1 point on `segment`, a Rule 2 point on `facet`, moved onto the curved CAD edge or
// face they stand for (MeshOptions::project_to_boundary) when that moves it by at most max_move; false otherwise.
bool project_segment_point(const MeshState& s, Index segment, double max_move, Point3& p);
bool project_facet_point(const MeshState& s, Index facet, double max_move, Point3& p);
// Inserts vertex `id` into the hole of `cz` (consumed) and into its facets' 2D triangulations, gives the new cells
// `region` (kUnknownRegion for boundary points: flooded later), counts it, and returns what changed; the caller
// hands that to notify_insertion().
InsertionResult insert_vertex(MeshState& s, Index id, ConflictZone& cz, const Candidates& cand, int region);
// A cell incident to vertex v, where point location near v starts.
Ch3 hint_of(const MeshState& s, Index v);
// Inserts a volume vertex at p (weight zero) into the hole `cells` (p's conflict zone, CGAL find_conflicts, with
// its boundary facets `boundary`; both are consumed) with the engine's bookkeeping: vertex record, statistics,
// regions (`region`: the zone's), and the Rule 1-3 queues for whatever p encroaches or makes bad (a caller that
// checked p encroaches nothing and makes no bad cell leaves them empty). Returns the new vertex id.
Index insert_volume_vertex(MeshState& s, const Point3& p, std::vector<Ch3>& cells, std::vector<Facet3>& boundary,
                           int region);

// --- scheduler (scheduler.cpp) ---
// Every level's after-insertion hook (Rule 3, Rule 1, Rule 2; each queue keeps its own order).
void notify_insertion(MeshState& s, const InsertionResult& r);
void enqueue_initial_boundary(MeshState& s);
// Drains Rules 1-2 (stage Boundary) or Rules 1-3 (stage Refinement).
void run_refinement(MeshState& s, bool with_rule3);
void enqueue_all_tets(MeshState& s);
// Whether every face between cells of different regions (or an in-domain cell and the outside) is a subfacet.
bool region_boundaries_are_subfacets(const MeshState& s);
// Whether every subsegment and subfacet is an edge / face of the triangulation (a global scan).
bool boundary_present(const MeshState& s);

// --- Rule 3, after refinement (rule3_tets.cpp) ---
// Why an in-domain cell of radius-edge ratio above rho0 was left by Rule 3: skipped for an acute input angle,
// given up after rejected circumcentres (Rule3Tets::given_up; call sort_given_up() first), or other.
enum class LeftReason { AcuteAngle, Rejected, Other };
void sort_given_up(MeshState& s);
// Degenerate cells (four nearly cocircular points whose rounded volume may be non-positive) lying on a facet's
// plane, in the domain, with an outside cell across their subfacets: the facet's 2D triangulation takes the other
// diagonal (both are Delaunay) and the cell leaves the domain, so no output tetrahedron is flat. Before extraction.
void remove_flat_boundary_cells(MeshState& s);
LeftReason why_left(MeshState& s, Ch3 c);

// --- small input angles (small_angles.cpp) ---
// The input element hosting vertex v; *has is false for volume vertices.
InputComplex::ElementRef host_element(const MeshState& s, Index v, bool* has);
// The one definition of "touches an acute input angle" (MeshResult::tet_touches_acute_angle): the shortest edge
// of the tetrahedron joins vertices on input elements that meet at an acute angle (InputComplex::elements_meet_acute).
bool tet_touches_acute_angle(const MeshState& s, const std::array<Index, 4>& ids);
bool shortest_edge_forced_by_acute_angle(const MeshState& s, Index u, Index w);
// Rule 2's small-angle exemption: present subfacet abc of `facet`, encroached by vertex `enc`, is left alone.
bool subfacet_encroacher_exempt(const MeshState& s, Index facet, const std::array<Index, 3>& abc, Index enc);

// --- Rule 4 and pumping (rule4.cpp, pump.cpp; paper Sections 3.3, 3.7, 7.2, 7.3) ---
// f(v), the local feature size at vertex v (paper Section 2), cached per vertex.
double local_feature_size_at(MeshState& s, Index v);
// Is finite cell c an in-domain sliver (RefineParams::is_sliver)? `min_dihedral_deg` (may be null) gets the cell's
// smallest dihedral angle.
bool is_sliver(const MeshState& s, Ch3 c, double* min_dihedral_deg);
// The orthosphere of finite cell c in the regular triangulation: its centre and squared radius (pump.cpp).
std::pair<KPoint3, double> orthosphere(Ch3 c);
// Rule 4 rounds: weighted encroachment by the vertices of slivers (weight omega0^2 f(v)^2), each round drained by
// run_refinement(); ends when a round finds nothing or the vertex budget of Rule 4 is spent.
void apply_rule4(MeshState& s);
// Step 3: pumps the vertices of slivers, worst sliver first, keeping the triangulation regular and conforming.
// Measures MeshState::sq_nearest first.
void pump_slivers(MeshState& s);
// Pumps again, worst first, the vertices of the cells below the sliver angle among the stars of `vertices` (after
// an insertion: the new vertex's star), with step 3's caps and checks; a few passes. Returns the moves accepted.
// `cache` (optional): walks remembered across calls (pump_star.h).
class WalkCache;
std::size_t pump_around(MeshState& s, const std::vector<Index>& vertices, WalkCache* cache = nullptr);
// After pumping and sliver insertion: slivers left, vertices pumped, weight statistics (MeshStats).
void pumping_statistics(MeshState& s);
// After step 3 (sliver_insertion.cpp, beyond the paper): inserts points at the slivers that pumping left away from
// acute input angles, worst first, within a vertex budget, then pumps the new stars again.
void insert_at_slivers(MeshState& s);

// --- regions (regions.cpp) ---
void compute_regions(MeshState& s);
// Floods the cells created by boundary insertions since the last flood; calls `on_cell` for each assigned cell.
void flood_pending_regions(MeshState& s, std::vector<Ch3>& assigned);
// Encroaching::Steiner, after Rule 3's stage: where every subsegment and subfacet is present but a region boundary
// crosses a face that is none, floods the regions again and refines again (up to twice;
// MeshStats::num_region_refloods).
void reflood_regions(MeshState& s);

// --- extraction (extract.cpp) ---
// touches_acute: per output tet, MeshResult::tet_touches_acute_angle; the MeshStats counts above the bound.
TetMesh extract_mesh(MeshState& s, std::vector<std::uint8_t>& touches_acute);

}  // namespace qualmesh::detail
