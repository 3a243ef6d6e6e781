// Pumping's star evaluation (pump_star.cpp): scoring the star a vertex would have at a weight, walking a vertex's
// critical weights to the best one, and applying it (Cheng & Dey, Section 3.7 step 3, Section 7.3). The passes
// that choose which vertices to pump are pump.cpp's.
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <unordered_map>
#include <utility>
#include <vector>

#include "refine/refine_state.h"

namespace qualmesh::detail {

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
bool better(const StarScore& a, const StarScore& b);
// A new star may not raise the largest radius-edge ratio above what Rule 3 promised (rho0) or, for cells at acute
// input angles (the only ones allowed above rho0), above the old star's.
bool keeps_radius_edge(const MeshState& s, const StarScore& candidate, const StarScore& current);

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

// The cell on vertices `ids`, if the triangulation still has it.
bool current_cell(const MeshState& s, const std::array<Index, 4>& ids, Ch3& c);

// Cells a computation read, with their time stamps (cgal_types.h's WithTimeStamp): a destroyed cell, or a new cell
// in its place, fails footprint_holds. WalkCache keeps walks by them, and sliver insertion its refused slivers.
using CellFootprint = std::vector<std::pair<Ch3, std::size_t>>;
bool footprint_holds(const MeshState& s, const CellFootprint& footprint);

// Walks the critical weights of v from its current weight up to its cap (pump_star.cpp's file comment) and returns
// the best star's weight. `target` (optional): a sliver v is not a vertex of, to be removed by growing v's star over
// it (a neighbour of the sliver, after its own vertices failed). Then a star is acceptable when the sliver is in the
// zone and the new star beats every cell it destroys (the zone, not only v's old star: the sliver is not in v's
// star), so the mesh's smallest dihedral angle still cannot drop. Changes nothing but caches (f(v), angles).
// `footprint` (optional): gets the cells the walk read (WalkCache).
PumpChoice best_weight(MeshState& s, Index v, const Ch3* target = nullptr, CellFootprint* footprint = nullptr);

// Walks kept across pump_around() calls (sliver insertion pumps again around every point it inserts, and most of
// the vertices it walks there were walked around an earlier point, with the same star). A walk is kept with its
// footprint: the cells it read (v's star, the cells its zone grew over and those across the zone's link) and their
// time stamps (cgal_types.h's WithTimeStamp). A destroyed cell, or a new cell in its place, fails the stamp check,
// and what else a walk reads changes only with a cell of its footprint: v's weight and its neighbours' (their stars
// are rebuilt), N(v) (a new neighbour), the subfacets of v's zone (a move or an insertion there). So a walk whose
// cells all hold gives what walking again would: the same mesh, without the walk.
class WalkCache {
 public:
  // v's walk (best_weight without a target), remembered or walked now.
  const PumpChoice& walk(MeshState& s, Index v);
  std::size_t hits() const { return hits_; }
  std::size_t misses() const { return misses_; }

 private:
  struct Entry {
    PumpChoice choice;
    CellFootprint cells;
  };
  std::unordered_map<Index, Entry> entries_;
  std::size_t hits_ = 0, misses_ = 0;
};
// Re-checks `weight` on CGAL's exact conflict zone and applies it; false (nothing changed) when a check fails or
// the star is not better. `touched` gets the vertices whose stars changed; a move that changed subfacets is
// counted in *num_retiled (and in *num_retile_failures when the facet's 2D triangulation could not follow).
// `target` (optional, see best_weight): the sliver must be in the zone, and the new star must beat all the cells it
// destroys (then `current` bounds only the radius-edge ratio).
bool apply_weight(MeshState& s, Index v, double weight, const StarScore& current, std::vector<Index>* touched,
                  std::size_t* num_retiled, std::size_t* num_retile_failures, const Ch3* target = nullptr);

}  // namespace qualmesh::detail
