// Regions (issue 3; paper Section 2, "Input": the tetrahedra outside the domain are removed at the end). Once the
// boundary conforms (no encroached subsegment or subfacet, every subfacet a face of the triangulation), the cells
// are flooded across faces that are not subfacets: what the infinite cells reach is outside, every other component
// is a region of the domain; hole seeds turn their component outside, region seeds give their component its
// attribute and volume bound. Internal facets separate regions because their subfacets stop the flood.
//
// Later boundary insertions (Rules 1 and 2 during Rule 3's stage) create cells of unknown region, all in the stars
// of the inserted vertices; flood_pending_regions() gives them the region of a known neighbour across a non-subfacet
// face once the boundary conforms again.
#include <algorithm>

#include "refine/refine_state.h"

namespace qualmesh::detail {

namespace {

void flood(MeshState& s, std::vector<Ch3>& stack, int region, std::vector<Ch3>* assigned) {
  while (!stack.empty()) {
    const Ch3 c = stack.back();
    stack.pop_back();
    for (int i = 0; i < 4; ++i) {
      const Ch3 n = c->neighbor(i);
      if (n->info().region != kUnknownRegion) continue;
      if (face_subfacet(s, c, i) != kNoIndex) continue;
      n->info().region = s.tr.is_infinite(n) ? kOutsideRegion : region;
      if (assigned && n->info().region >= 0) assigned->push_back(n);
      stack.push_back(n);
    }
  }
}

}  // namespace

void compute_regions(MeshState& s) {
  std::vector<Ch3> stack;
  for (auto c = s.tr.all_cells_begin(); c != s.tr.all_cells_end(); ++c) c->info().region = kUnknownRegion;
  for (auto c = s.tr.all_cells_begin(); c != s.tr.all_cells_end(); ++c) {
    if (!s.tr.is_infinite(c)) continue;
    c->info().region = kOutsideRegion;
    stack.push_back(c);
  }
  flood(s, stack, kOutsideRegion, nullptr);
  int num_components = 0;
  for (auto c = s.tr.finite_cells_begin(); c != s.tr.finite_cells_end(); ++c) {
    if (c->info().region != kUnknownRegion) continue;
    c->info().region = num_components;
    stack.assign(1, c);
    flood(s, stack, num_components, nullptr);
    ++num_components;
  }
  s.regions.assign(num_components, RegionInfo{});
  const Plc& plc = *s.plc;
  std::vector<char> removed(num_components, 0);
  auto component_at = [&](const Point3& p) {
    const Ch3 c = s.tr.locate(KWeightedPoint3(to_kpoint(p), 0));
    return (c == Ch3() || s.tr.is_infinite(c)) ? kOutsideRegion : c->info().region;
  };
  for (const Point3& h : plc.holes) {
    const int comp = component_at(h);
    if (comp >= 0) removed[comp] = 1;
  }
  for (const RegionSeed& seed : plc.regions) {
    const int comp = component_at(seed.point);
    if (comp < 0) continue;
    s.regions[comp].attribute = seed.attribute;
    s.regions[comp].max_volume = seed.max_volume;
  }
  if (std::find(removed.begin(), removed.end(), 1) != removed.end()) {
    for (auto c = s.tr.finite_cells_begin(); c != s.tr.finite_cells_end(); ++c)
      if (c->info().region >= 0 && removed[c->info().region]) c->info().region = kOutsideRegion;
  }
  s.regions_known = true;
  s.region_pending.clear();
  std::size_t num_inside = 0;
  for (int comp = 0; comp < num_components; ++comp) num_inside += removed[comp] ? 0 : 1;
  s.log_line("regions: " + std::to_string(num_inside) + " component(s) inside the domain, " +
             std::to_string(plc.holes.size()) + " hole seed(s)");
}

void flood_pending_regions(MeshState& s, std::vector<Ch3>& assigned) {
  // The unknown cells: stars of the pending vertices, and unknown cells next to them.
  std::vector<Ch3> unknown, star, stack;
  for (const Index v : s.region_pending) {
    star.clear();
    s.tr.incident_cells(s.vertices[v].handle, std::back_inserter(star));
    for (const Ch3& c : star) {
      if (c->info().region != kUnknownRegion) continue;
      if (s.tr.is_infinite(c)) {
        c->info().region = kOutsideRegion;
        continue;
      }
      unknown.push_back(c);
    }
  }
  s.region_pending.clear();
  // Seeds of the flood: the unknown cells that have a known neighbour across a non-subfacet face.
  for (const Ch3& c : unknown) {
    if (c->info().region != kUnknownRegion) continue;
    for (int i = 0; i < 4; ++i) {
      const Ch3 n = c->neighbor(i);
      const int r = n->info().region;
      if (r == kUnknownRegion || face_subfacet(s, c, i) != kNoIndex) continue;
      c->info().region = r;
      if (r >= 0) assigned.push_back(c);
      stack.assign(1, c);
      flood(s, stack, r, &assigned);
      break;
    }
  }
  // Components no known neighbour reaches (the insertions replaced every cell of the region around them): the
  // region of the cells they replaced.
  for (const Ch3& c : unknown) {
    if (c->info().region != kUnknownRegion || c->info().guess == kUnknownRegion) continue;
    const int r = c->info().guess;
    c->info().region = r;
    if (r >= 0) assigned.push_back(c);
    stack.assign(1, c);
    flood(s, stack, r, &assigned);
  }
  for (const Ch3& c : unknown)
    if (c->info().region == kUnknownRegion) c->info().region = kOutsideRegion;  // enclosed by subfacets only
}

// Encroaching::Steiner: when every subsegment and subfacet is present but a region's boundary crosses a face that
// is none (the region labels that insertions hand on went wrong somewhere: steiner_holds() names a flood through a
// subfacet missing at that moment), the regions are flooded again from the outside, now bounded by subfacets that
// are all present, and Rule 3 refines the cells that changed side.
// Up to kMaxRefloods times; steiner_holds() then judges the result. U_Joint_2.stp at --size 6.85 with boundary
// points projected onto the CAD surface gave up here and was meshed again without the projection, leaving 160
// boundary nodes that the CAD fit could not move onto the surface. Since the CAD surface remesher's change of
// session 30 no bench model needs it; tests/cpp/test_levels.cpp's constructed case exercises it.
void reflood_regions(MeshState& s) {
  constexpr int kMaxRefloods = 2;
  for (int round = 0; round < kMaxRefloods; ++round) {
    if (s.params.encroachment.paper() || s.vertex_limit_reached || !s.steiner_abandoned.empty() ||
        !s.regions_known || region_boundaries_are_subfacets(s) || !boundary_present(s))
      return;
    s.log_line("regions: a region's boundary crosses no subfacet after refinement; flooding the regions again");
    ++s.stats.num_region_refloods;
    compute_regions(s);
    enqueue_all_tets(s);
    run_refinement(s, true);
  }
}

}  // namespace qualmesh::detail
