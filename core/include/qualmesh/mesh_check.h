// An independent validator of tetrahedral meshes (DESIGN.md "How we know it works", STYLE.md principle 6): it re-checks
// a mesh from scratch, ours or a peer's (TetGen, Gmsh, Medit), and never trusts what the mesher knows. It checks
// orientation, face-to-face matching, and, given the input PLC, conformity: the volume the input encloses equals the
// mesh volume, every boundary face lies on an input facet, and the faces on each facet cover exactly that facet (the
// paper's Theorem 7.2). It tests the weighted Delaunay (regular) property locally, across every face shared by two
// tetrahedra (TetMesh::weights; all zero: the plain Delaunay empty-sphere property). It also gathers the quality
// figures of the paper (rho = R / L, sigma = V / L^3, Section 2) and the dihedral angles FEM users read. Pure: nothing
// is printed, the mesh is not modified.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "qualmesh/plc.h"
#include "qualmesh/tet_mesh.h"

namespace qualmesh {

// What check_mesh does with the weighted Delaunay (regular) property.
enum class RegularityCheck {
  Skip,     // not tested (weighted_delaunay_checked stays false)
  Report,   // tested and counted; violations do not make the mesh fail
  Require,  // tested; each violation is a problem
};

struct CheckOptions {
  // Distance tolerance for "a vertex lies on a facet's plane", relative to the bounding-box diagonal of the
  // reference PLC (of the mesh when there is none), plus 2 epsilon times the largest absolute coordinate (a model far
  // from the origin cannot be placed more precisely). Facet planes, areas and volumes are computed relative to the
  // bounding-box centre, so results do not depend on where the model lies.
  double tolerance = 1e-9;
  // Largest accepted relative error of the mesh volume against the reference volume, and of each facet's
  // covered area against its area. Floating-point sums over millions of tetrahedra stay far below these. Facets
  // whose vertices lie up to d off their plane (flat only to validate_plc's tolerance) add 2 d to `tolerance` for
  // their own faces, 2 d times their area to the volume tolerance, and 2 d times their perimeter to their area's.
  double relative_volume_tolerance = 1e-8;
  double relative_area_tolerance = 1e-8;
  // At most this many problem lines are kept (the counts are always complete).
  std::size_t max_problems = 100;
  // The weighted Delaunay (regularity) test: Skip, Report (count only: foreign meshes such as TetGen's constrained
  // Delaunay ones need not be regular), or Require (every violation is also a problem, so `ok` becomes false).
  RegularityCheck regularity = RegularityCheck::Report;
  // With a reference: input angles below this (degrees) are sharp, and the tetrahedra in their protection zones are
  // counted apart (CheckReport's protection figures). 0 skips it.
  double protection_angle_deg = 60;
};

// How much of one input facet the mesh's boundary faces cover.
struct FacetCoverage {
  Index facet = 0;            // 0-based index into Plc::facets
  int marker = 0;             // Facet::marker
  bool bounds_domain = true;  // a region of the domain lies on at least one side; else nothing is to cover it (a
                              // hole's face seen through a facet hole, a facet between two holes, an open input)
  double area = 0;            // area of the facet (polygons by the even-odd rule, less its holes)
  double covered_area = 0;    // total area of the mesh boundary faces found on it
  double relative_error = 0;  // |covered_area - area to cover| / max(area, 1e-6 diagonal^2), see mesh_check.cpp
};

struct CheckReport {
  // Counts.
  std::size_t num_points = 0;
  std::size_t num_tets = 0;
  std::size_t num_unused_points = 0;       // points no tetrahedron uses (not a defect by itself)
  std::size_t num_faces = 0;               // distinct triangular faces of the tetrahedra
  std::size_t num_boundary_faces = 0;      // faces of one tetrahedron plus faces between different regions
  std::size_t num_hull_faces = 0;          // faces of exactly one tetrahedron
  std::size_t num_region_interface_faces = 0;  // faces of two tetrahedra of different regions
  std::size_t num_regions = 0;             // distinct region attributes

  // Structure and orientation.
  std::size_t num_nonpositive_tets = 0;    // signed volume <= 0 (inverted or flat)
  std::size_t num_duplicate_tets = 0;      // tetrahedra with the same vertex set as an earlier one
  std::size_t num_overshared_faces = 0;    // faces shared by more than two tetrahedra
  std::size_t num_folded_faces = 0;        // faces of two tetrahedra lying on the same side of it (overlap)
  std::size_t num_bad_indices = 0;         // tetrahedra with a missing or repeated vertex
  double mesh_volume = 0;                  // sum of signed volumes, model units cubed

  // Conformity to the reference PLC (has_reference false: all below are unset).
  bool has_reference = false;
  // The volume the input encloses (NaN, and the volume check skipped, when it cannot be found).
  double reference_volume = 0;
  // How it was found: "closed-shells (...)" for closed 2-manifold surfaces without hole seeds (each shell oriented
  // consistently, signed by nesting depth: an inner shell is a cavity), or "cells (...)" for PLCs with internal
  // facets or volume hole seeds (TetGen's reading: every bounded cell of the facet arrangement less the cells
  // holding a hole seed). Limit: facets must meet along whole polygon edges (no T-junctions).
  std::string reference_volume_method;
  double volume_relative_error = 0;        // |mesh_volume - reference_volume| / reference_volume; NaN when unknown
  std::size_t num_faces_off_input = 0;     // boundary faces on no input facet
  std::size_t num_interior_faces_on_input = 0;  // faces between two tets of one region that lie on an input facet
                                                // (internal facets inside a region); they count as covering it
  std::size_t num_faces_given = 0;         // TetMesh::faces listed by the mesh (not used for the checks)
  double facet_area = 0;                   // total area of the input facets
  double covered_area = 0;                 // total area of boundary faces found on a facet
  double max_facet_area_relative_error = 0;
  std::size_t num_miscovered_facets = 0;   // facets whose relative area error exceeds the tolerance
  std::vector<FacetCoverage> facets;       // one per input facet

  // Weighted Delaunay (regular) property, tested locally: for every face shared by two tetrahedra, the vertex of
  // one tetrahedron opposite the face must be no closer than orthogonal to the other's orthosphere (the sphere
  // orthogonal to the four weighted vertices; with all weights zero, the circumsphere: the vertex must not lie
  // strictly inside it). Exact power test (CGAL Epick). Cospherical (orthogonal) configurations are not violations.
  // For a triangulation of a convex region local regularity implies global regularity (Edelsbrunner and Shah); for
  // a domain mesh (non-convex, holes, regions) the test across its interior and region-interface faces is the
  // standard local check: a vertex seen only across the boundary is not tested. Unused points are not tested.
  bool weighted_delaunay_checked = false;  // the test ran (options.regularity != Skip, weights well-formed)
  std::size_t num_weighted_points = 0;     // points with a nonzero weight
  double max_weight = 0;                   // largest weight (squared radius, model units squared)
  std::size_t num_regularity_tested_faces = 0;  // faces shared by two valid tetrahedra (a flat one never fails)
  std::size_t num_non_regular_faces = 0;   // of those, the locally non-regular ones

  // Quality figures over all tetrahedra.
  double min_dihedral_deg = 0;
  double max_dihedral_deg = 0;
  double dihedral_histogram_bin_deg = 5;   // width of a histogram bin
  std::vector<std::size_t> dihedral_histogram;  // all 6 dihedral angles of every tetrahedron, bins over [0, 180]
  std::vector<std::size_t> min_dihedral_histogram;  // the smallest dihedral angle of each tetrahedron
  double max_radius_edge = 0;              // largest circumradius / shortest edge (the paper's rho)
  double min_sigma = 0;                    // smallest volume / shortest edge^3 (the paper's sigma)
  double min_volume = 0;                   // smallest signed tetrahedron volume
  std::size_t num_tets_min_dihedral_below_5 = 0;
  std::size_t num_tets_min_dihedral_below_10 = 0;
  std::size_t num_tets_min_dihedral_below_15 = 0;

  // Quality outside the protection zones of the reference's sharp input angles (issue 16): the second line, never
  // the headline. Sharp: the input angles of the paper's Section 2 below options.protection_angle_deg. The zone:
  // protecting balls of radius f (the local feature size at the centre) at every apex of a sharp segment-segment or
  // segment-facet angle, and along every segment with a sharp facet-facet angle (a capsule of radius
  // min(f(a), f(b), f(midpoint))). A tetrahedron is in the zone when one of its vertices lies in a ball.
  // Set only with a reference and protection_angle_deg > 0 (protection_checked). For a CAD reference the zone is
  // drawn around the CAD model's sharp features instead (fill_cad_feature_protection, protection_zone).
  bool protection_checked = false;
  enum class ProtectionZone { Balls, CadFeatureBalls };
  ProtectionZone protection_zone = ProtectionZone::Balls;
  double protection_radius = 0;                // CadFeatureBalls: the zone's radius around every sharp feature
  double protection_angle_deg = 0;
  std::size_t num_sharp_vertices = 0;  // apices of sharp segment-segment or segment-facet angles (CAD: vertices)
  std::size_t num_sharp_segments = 0;  // segments with a sharp facet-facet angle (CAD: edges)
  std::size_t num_tets_in_protection_zone = 0;
  double min_dihedral_outside_protection_deg = 0;  // 0 when every tetrahedron is in the zone
  std::size_t num_tets_outside_protection_below_10 = 0;
  std::size_t num_tets_outside_protection_below_15 = 0;

  // Verdict.
  std::size_t num_problems = 0;            // all problems found (problems keeps the first max_problems)
  std::vector<std::string> problems;       // "tet 12: non-positive volume -1e-3", "face (3, 8, 9): ..."
  bool ok = false;                         // no problem found
};

// Checks `mesh`; with `reference` (may be null) also its conformity to that input.
CheckReport check_mesh(const TetMesh& mesh, const Plc* reference, const CheckOptions& options = {});

// The protection-zone figures alone (CheckReport's protection fields, num_points and num_tets; nothing else is
// checked or set), as check_mesh computes them against `reference` with protection_angle_deg = angle_deg: for a
// mesher's summary, at a fraction of check_mesh's cost.
CheckReport check_protection_zones(const TetMesh& mesh, const Plc& reference, double angle_deg = 60);

// The protection-zone figures of a mesh of a CAD model (issue 15's goal: no tet below 10 degrees anywhere the CAD
// dihedral angles are 30 degrees or more), into report's protection fields (protection_zone CadFeatureBalls).
// `near_feature_nodes` are the mesh vertices within `radius` of the model's sharp features below `angle_deg`, which
// the CAD front end finds on the CAD geometry (measure_against_cad); `num_sharp_vertices` and `num_sharp_edges` say
// how many it found. A tetrahedron with such a vertex is inside the zone. The CAD model has no local feature size
// the checker could use for the radius, as it does for a PLC; the caller picks it (median_edge_length by default).
void fill_cad_feature_protection(CheckReport& report, const TetMesh& mesh,
                                 const std::vector<Index>& near_feature_nodes, double angle_deg, double radius,
                                 std::size_t num_sharp_vertices, std::size_t num_sharp_edges);

// The median length of the mesh's tetrahedron edges (each counted once per tetrahedron): one element of the whole
// mesh, the default zone radius. A statistic of the whole mesh, it does not shrink near the features where a mesher
// refines as a count of element layers would, though heavy refinement anywhere lowers it: to compare two meshers,
// give both the same radius.
double median_edge_length(const TetMesh& mesh);

// Human-readable summary, several lines.
std::string to_text(const CheckReport& report);

// The report as one JSON object with stable keys (the field names above); numbers printed with %.17g
// (NaN and infinity as null).
std::string to_json(const CheckReport& report);

}  // namespace qualmesh
