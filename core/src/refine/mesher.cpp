// mesh_plc(): the stages of QUALMESH steps 1-2 (Cheng & Dey, Section 3.7) in order, timed and reported:
//   Initial     the Delaunay (zero-weight regular) triangulation of the input vertices (step 1), the input complex
//               and the subfacet triangulations;
//   Boundary    Rules 1 and 2 until no subsegment or subfacet is encroached or missing (the boundary conforms);
//   Regions     flood fill of the domain's regions (regions.cpp);
//   Refinement  Rules 1-3 in priority order (scheduler.cpp and the levels rule1_subsegments.cpp,
//               rule2_subfacets.cpp, rule3_tets.cpp);
//   Pumping     Rule 4 rounds (rule4.cpp), then step 3, pumping the vertices of slivers (pump.cpp), then points
//               at the slivers pumping left away from acute input angles (sliver_insertion.cpp, unless
//               MeshOptions::sliver_insertion is false); all skipped with MeshOptions::pump = false;
//   Extraction  the TetMesh and its quality figures (extract.cpp).
// Separate closed surfaces run the stages one by one, and their meshes are joined (components.cpp).
#include "qualmesh/mesher.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>

#include "qualmesh/quality.h"
#include "improve/improve.h"
#include "refine/components.h"
#include "refine/refine_state.h"

namespace qualmesh {

const char* to_string(MeshStage stage) {
  switch (stage) {
    case MeshStage::Initial: return "initial";
    case MeshStage::Boundary: return "boundary";
    case MeshStage::Refinement: return "refinement";
    case MeshStage::Regions: return "regions";
    case MeshStage::Pumping: return "pumping";
    case MeshStage::Extraction: return "extraction";
  }
  return "?";
}

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

void begin_stage(detail::MeshState& s, MeshStage stage) {
  s.stage = stage;
  if (s.progress) s.progress(ProgressEvent{stage, 0.0, s.tr.number_of_vertices()});
}

// Encroaching::Steiner: false (and a log line) when it gave up on its work budget, left a subsegment or subfacet
// missing, or let a region flood through a subfacet that was missing at that moment (t13_data.stl as unmerged
// triangles; the cause is not found yet); always true with the paper's rule.
bool steiner_holds(detail::MeshState& s, const char* when) {
  if (s.params.encroachment.paper() || s.vertex_limit_reached) return true;
  if (s.steiner_abandoned.empty() && !detail::boundary_present(s))
    s.steiner_abandoned = std::string("a subsegment or subfacet is missing ") + when;
  if (s.steiner_abandoned.empty() && s.regions_known && !detail::region_boundaries_are_subfacets(s))
    s.steiner_abandoned = std::string("a region's boundary crosses no subfacet ") + when;
  if (s.steiner_abandoned.empty()) return true;
  s.log_line("encroaching: Steiner mode gave up (" + s.steiner_abandoned + ")");
  return false;
}

// MeshOptions::project_to_boundary's safety net in Rules 1-2 (MeshState::count_below_floor_split): true (and a log
// line) when `stage` split more elements below the floor than the budget allows; mesh_plc() meshes again without
// the projection.
bool refinement_ran_away(detail::MeshState& s, const char* stage) {
  if (!s.projection_runaway) return false;
  s.log_line(std::string(stage) + ": " + std::to_string(s.below_floor_splits) +
             " splits below the split floor with boundary points projected onto the CAD surface; meshing again "
             "without it");
  return true;
}

// The improvement pass (improve.h, beyond the paper) on the extracted mesh, with extract.cpp's acute-angle criterion
// for the tets it changes: mesh vertex ids map back to the engine's in order (extraction keeps the engine's order).
// `engine_id`: the engine's vertex of each mesh point, found before MeshOptions::before_improve moved any.
void improve_extracted(detail::MeshState& s, MeshResult& result, const std::vector<Index>& engine_id) {
  const auto t = Clock::now();
  detail::ImproveOptions options;
  options.sliver_angle_deg = s.options.sliver_angle_deg;
  options.radius_edge_bound = kImproveRadiusEdgeFactor * s.params.radius_edge_bound;
  options.cancel = s.options.cancel;
  options.boundary_insertion = !s.options.before_improve;  // a CAD-fitted surface: no new point on a chord
  options.log = [&s](const std::string& line) { s.log_line(line); };
  options.project_to_boundary = s.options.project_to_boundary;  // CAD inputs: vertices move on curved faces
  const detail::ImproveResult r = detail::improve_mesh(
      result.mesh, *s.plc, options, &result.tet_touches_acute_angle, [&](Index u, Index w) {
        // A vertex the pass added (an edge split) counts as on no input element, even inside a facet: its tets are
        // never excused as touching an acute angle.
        return u < engine_id.size() && w < engine_id.size() && engine_id[u] != kNoIndex &&
               engine_id[w] != kNoIndex && detail::shortest_edge_forced_by_acute_angle(s, engine_id[u], engine_id[w]);
      });
  s.stats.num_tets_improved = r.num_tets_touched;
  s.stats.num_improve_vertex_moves = r.num_vertex_moves;
  s.stats.num_improve_flips = r.num_flips;
  s.stats.num_improve_insertions = r.num_insertions;
  s.stats.num_improve_caps_removed = r.num_caps_removed;
  s.stats.min_dihedral_before_improve_deg = r.min_dihedral_before_deg;
  s.stats.seconds_improve = seconds_since(t);
  s.log_line("improve: " + std::to_string(r.num_tets_touched) + " tets touched, " +
             std::to_string(r.num_vertex_moves) + " vertex moves, " + std::to_string(r.num_flips) + " flips (" +
             std::to_string(r.num_flips23) + " 2-3, " + std::to_string(r.num_edge_removals) +
             " edge removals), " + std::to_string(r.num_insertions) + " edge splits (" +
             std::to_string(r.num_boundary_insertions) + " inside a facet), " + std::to_string(r.num_caps_removed) +
             " caps removed; " + std::to_string(r.num_on_surface) + " vertices movable on curved CAD faces, " +
             std::to_string(r.num_on_curve) + " on curved CAD edges; below " +
             std::to_string(options.sliver_angle_deg) + " deg: " +
             std::to_string(r.num_below_before) + " -> " + std::to_string(r.num_below_after));
}

// MeshOptions::before_improve, with the acute-angle flags kept on the tets that remain (it may remove some).
void run_before_improve(const std::function<void(TetMesh&)>& hook, MeshResult& result) {
  std::map<std::array<Index, 4>, std::uint8_t> flag;
  for (std::size_t i = 0; i < result.mesh.tets.size(); ++i) {
    std::array<Index, 4> key = result.mesh.tets[i];
    std::sort(key.begin(), key.end());
    flag[key] = result.tet_touches_acute_angle[i];
  }
  hook(result.mesh);
  result.tet_touches_acute_angle.clear();
  for (const auto& tet : result.mesh.tets) {
    std::array<Index, 4> key = tet;
    std::sort(key.begin(), key.end());
    const auto it = flag.find(key);
    if (it == flag.end()) throw std::logic_error("before_improve added a tetrahedron");
    result.tet_touches_acute_angle.push_back(it->second);
  }
}

// One run of the stages. Encroaching::Steiner (beyond the paper) guarantees neither that every subsegment and
// subfacet is recovered nor small conflict zones: returns nothing when it gave up, and mesh_plc() runs again with the
// paper's rule.
std::optional<MeshResult> mesh_attempt(const Plc& plc, const MeshOptions& options, const ProgressCallback& progress,
                                       const LogCallback& log) {
  auto state = std::make_unique<detail::MeshState>();
  detail::MeshState& s = *state;
  s.plc = &plc;
  s.set_options(options);
  s.params.set_rounding_floor(bounding_box(plc).diagonal());
  s.progress = progress;
  s.log = log;

  MeshResult result;
  auto t = Clock::now();
  begin_stage(s, MeshStage::Initial);
  s.complex = detail::build_input_complex(plc, false, s.params.corner_acute_deg);
  detail::insert_input_vertices(s);
  detail::build_facet_meshes(s);
  std::size_t num_acute = 0;
  for (auto a : s.complex.acute_vertex) num_acute += a;
  s.log_line("input: " + std::to_string(plc.vertices.size()) + " vertices, " +
             std::to_string(s.complex.segments.size()) + " segments, " + std::to_string(plc.facets.size()) +
             " facets, " + std::to_string(num_acute) + " apices of acute input angles");
  s.stats.seconds_initial = seconds_since(t);

  t = Clock::now();
  begin_stage(s, MeshStage::Boundary);
  detail::enqueue_initial_boundary(s);
  detail::run_refinement(s, false);
  if (refinement_ran_away(s, "the boundary stage") || !steiner_holds(s, "after the boundary stage"))
    return std::nullopt;
  s.stats.seconds_boundary = seconds_since(t);

  if (!s.vertex_limit_reached) {
    t = Clock::now();
    begin_stage(s, MeshStage::Regions);
    detail::compute_regions(s);
    s.stats.seconds_regions = seconds_since(t);

    t = Clock::now();
    begin_stage(s, MeshStage::Refinement);
    detail::enqueue_all_tets(s);
    detail::run_refinement(s, true);
    detail::reflood_regions(s);
    if (refinement_ran_away(s, "refinement") || !steiner_holds(s, "after refinement")) return std::nullopt;
    if (!s.region_pending.empty()) {
      std::vector<detail::Ch3> assigned;
      detail::flood_pending_regions(s, assigned);
    }
    s.stats.seconds_refinement = seconds_since(t);

    if (options.pump && !s.vertex_limit_reached) {
      t = Clock::now();
      begin_stage(s, MeshStage::Pumping);
      // Boundary points projected onto a CAD surface lie off their facets' planes. On Zylkopf.stp at its default
      // size that made Rule 4 and sliver insertion run away (4.9k -> 73k vertices in 60 s of pumping; 4226
      // vertices in all without the projection). Pumping normally adds a few percent (part.step: 89 to 2799;
      // Zylkopf.stp without the projection 74 to 4035), so more than a tenth and 200 is taken for a runaway.
      if (options.project_to_boundary)
        s.pumping_vertex_budget = s.tr.number_of_vertices() + s.tr.number_of_vertices() / 10 + 200;
      detail::apply_rule4(s);
      if (!s.vertex_limit_reached) {
        detail::pump_slivers(s);
        if (options.sliver_insertion) detail::insert_at_slivers(s);
        detail::pumping_statistics(s);
      }
      s.stats.seconds_pumping = seconds_since(t);
      if (s.projection_runaway) {
        s.log_line("pumping: more than " + std::to_string(s.pumping_vertex_budget) +
                   " vertices with boundary points projected onto the CAD surface; meshing again without it");
        return std::nullopt;
      }
    }
  } else {
    detail::compute_regions(s);
  }
  if (s.cancelled) {
    result.status = MeshStatus::Cancelled;
    s.log_line("stopped: cancelled");
  } else if (!s.precision_stop.empty()) {
    result.status = MeshStatus::PrecisionExhausted;
    result.message = s.precision_stop;
    s.log_line("stopped at the limit of double precision: " + s.precision_stop);
  } else if (s.vertex_limit_reached) {
    result.status = MeshStatus::VertexLimitReached;
    s.log_line("stopped: vertex limit " + std::to_string(options.max_vertices) + " reached");
  }

  t = Clock::now();
  begin_stage(s, MeshStage::Extraction);
  result.mesh = detail::extract_mesh(s, result.tet_touches_acute_angle);
  if (result.status == MeshStatus::Ok && (options.before_improve || (options.improve && options.pump))) {
    std::vector<Index> engine_id(result.mesh.points.size(), kNoIndex);
    for (Index v = 0, e = 0; v < engine_id.size() && e < s.vertices.size(); ++e)
      if (s.vertices[e].point == result.mesh.points[v]) engine_id[v++] = e;
    if (options.before_improve) run_before_improve(options.before_improve, result);
    if (engine_id.size() != result.mesh.points.size()) throw std::logic_error("before_improve added points");
    if (options.improve && options.pump) improve_extracted(s, result, engine_id);
  }
  MeshStats& st = s.stats;
  st.num_tets = result.mesh.tets.size();
  st.num_boundary_faces = result.mesh.faces.size();
  st.max_radius_edge = 0;
  const bool improved = st.num_tets_improved > 0 || st.num_improve_caps_removed > 0;
  if (improved) {
    // The improvement pass changed tets: the radius-edge audit of extract.cpp is redone over the output (the
    // reasons of MeshStats stay those of the tets the engine left; a changed tet may be above rho0, within
    // kImproveRadiusEdgeFactor * rho0 away from acute input angles).
    st.num_tets_above_bound = 0;
    st.max_radius_edge_away_from_acute = 0;
  }
  st.min_dihedral_deg = result.mesh.tets.empty() ? 0 : 180;
  st.min_dihedral_away_from_acute_deg = 180;
  for (std::size_t i = 0; i < result.mesh.tets.size(); ++i) {
    const auto& tet = result.mesh.tets[i];
    const auto& p = result.mesh.points;
    const TetQuality q = tet_quality(p[tet[0]], p[tet[1]], p[tet[2]], p[tet[3]]);
    st.max_radius_edge = std::max(st.max_radius_edge, q.radius_edge);
    if (improved) {
      st.num_tets_above_bound += q.radius_edge > s.params.radius_edge_bound;
      if (!result.tet_touches_acute_angle[i])
        st.max_radius_edge_away_from_acute = std::max(st.max_radius_edge_away_from_acute, q.radius_edge);
    }
    st.min_dihedral_deg = std::min(st.min_dihedral_deg, q.min_dihedral_deg);
    if (!result.tet_touches_acute_angle[i]) {
      st.min_dihedral_away_from_acute_deg = std::min(st.min_dihedral_away_from_acute_deg, q.min_dihedral_deg);
      if (q.min_dihedral_deg < options.sliver_angle_deg) ++st.num_tets_below_sliver_angle_away_from_acute;
    }
  }
  st.seconds_extraction = seconds_since(t) - st.seconds_improve;  // the improvement pass is timed apart
  if (s.progress) s.progress(ProgressEvent{MeshStage::Extraction, 1.0, s.tr.number_of_vertices()});
  result.stats = st;
  return result;
}

// One PLC in one triangulation: the relaxed rule's fallbacks (MeshStats::boundary_projection_dropped,
// encroaching_fell_back) when a run gives up.
MeshResult mesh_whole(const Plc& plc, const MeshOptions& options, const ProgressCallback& progress,
                      const LogCallback& log) {
  // An attempt that stopped at the limit of double precision (MeshState::stop_at_precision) is given up like one
  // that ran away; bottle.brep at --size 80 reached it with the relaxed rule, unprojected (a CGAL crash before the
  // check).
  auto usable = [](const std::optional<MeshResult>& r) {
    return r && r->status != MeshStatus::PrecisionExhausted;
  };
  std::optional<MeshResult> result = mesh_attempt(plc, options, progress, log);
  if (usable(result)) return std::move(*result);
  MeshOptions retry = options;
  const bool projected = options.project_to_boundary != nullptr;
  if (projected) {
    // The relaxed rule gave up, or pumping ran away (above), with boundary points projected onto the CAD surface:
    // they leave their planar subfacets. On t20_data.step at --size 5.88 the relaxed rule gave up (conflict zones
    // of 801 cells on average) and the paper's rule then ran for minutes; without the projection it meshes in a
    // second, and the CLI's CAD fit moves the boundary nodes afterwards.
    if (log) log("meshing again without projecting boundary points onto the CAD surface");
    retry.project_to_boundary = nullptr;
    result = mesh_attempt(plc, retry, progress, log);
    if (usable(result)) {
      result->stats.boundary_projection_dropped = true;
      return std::move(*result);
    }
  }
  if (options.encroaching != MeshOptions::Encroaching::All) {
    if (log) log("encroaching: meshing again with the paper's rule");
    retry.encroaching = MeshOptions::Encroaching::All;  // never gives up without the projection
    result = mesh_attempt(plc, retry, progress, log);
    if (result) result->stats.encroaching_fell_back = true;
  }
  if (!result) throw std::logic_error("mesh_attempt gave up with the paper's rule and no projection");
  result->stats.boundary_projection_dropped = projected;
  return std::move(*result);
}

}  // namespace

MeshResult mesh_plc(const Plc& plc, const MeshOptions& options, const ProgressCallback& progress,
                    const LogCallback& log) {
  // Separate closed surfaces (solids of an assembly that do not touch) one by one (components.h).
  const std::vector<detail::PlcComponent> parts = detail::separate_components(plc);
  if (parts.empty()) return mesh_whole(plc, options, progress, log);
  if (log) log("components: " + std::to_string(parts.size()) + " separate closed surfaces, meshed one by one");
  std::vector<MeshResult> results;
  std::vector<const TetMesh*> meshes;
  for (const detail::PlcComponent& part : parts) {
    results.push_back(mesh_whole(part.plc, options, progress, log));
    if (results.back().status != MeshStatus::Ok) return detail::merge_component_results(parts, results);
  }
  for (const MeshResult& r : results) meshes.push_back(&r.mesh);
  if (!detail::meshed_volumes_meet(meshes)) return detail::merge_component_results(parts, results);
  if (log) log("components: one lies inside or on another's volume; meshing them together");
  return mesh_whole(plc, options, progress, log);
}

}  // namespace qualmesh
