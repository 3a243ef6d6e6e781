// Merging of adjacent, exactly coplanar facets into polygonal facets (outer loops plus inner loops).
//
// Why: surface formats (STL, OFF, OBJ, Medit) carry only triangles. The mesher must respect every input facet
// edge (conformity, paper Theorem 7.2), so a diagonal of a flat square kept as an input segment would force
// needless refinement along it. Merging restores the polygonal facets the CAD model had.
#pragma once

#include "qualmesh/plc.h"

namespace qualmesh {

// Returns a copy of `plc` in which facets are merged when they
//  - are each a single planar polygon loop of >= 3 vertices without hole points (other facets are kept as they are),
//  - share an edge used by exactly these two facets (and not an explicit segment),
//  - are exactly coplanar (exact orientation predicate, no tolerance), and lie on opposite sides of that edge.
// A merged facet holds the boundary loops of the union: the loop(s) oriented like the first facet of the group come
// first, inner loops (holes, implied by the odd-count rule of plc.h) after; no hole points are added. Every vertex is
// kept, collinear ones included; a vertex that ends inside a merged facet becomes a 1-vertex loop, and an interior
// edge used by other facets too becomes a 2-vertex loop, so conformity with neighbours is kept. The marker is kept
// when all merged facets agree, else 0. Vertices, segments, holes and regions are unchanged. Output facets are
// ordered by their smallest original facet index; the result is deterministic.
//
// relative_tolerance > 0 (a fraction of the bounding-box diagonal D) also merges facets that are coplanar only up
// to it, as TetGen merges triangles within 0.1 deg of coplanar: tessellated flat faces whose triangles a file's
// rounding left a hair off one plane, whose needle triangles would otherwise stay input angles of a few degrees.
// A group grows from its seed facet (lowest index) while every vertex of a joining facet is within
// relative_tolerance * D of the seed's plane, and is kept merged only when every vertex is within that distance of
// the merged facet's plane as validate_plc measures it (so a tolerance up to validate_plc's planarity tolerance,
// 1e-6 by default, never makes an invalid facet). The mesh then conforms to the merged facets: its boundary lies
// within that distance of the input triangles, not on them. 0 (the default) is the exact rule above.
Plc merge_coplanar_facets(const Plc& plc, double relative_tolerance = 0.0);

}  // namespace qualmesh
