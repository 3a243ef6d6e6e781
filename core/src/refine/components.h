// Separate closed surfaces of one PLC (several solids of an assembly that do not touch), meshed one by one
// (components.cpp; beyond the paper). The paper meshes one PLC in one Delaunay triangulation. Two solids a small
// gap apart (wrenchnut.stp: a nut 0.44 mm from its wrench) then refine each other's facets down to the gap, which
// no mesh of either solid needs: there 6529 nodes against 2263 for the two solids meshed apart. Each component is
// meshed alone; the meshes are kept only when no component lies inside another's meshed volume (a solid inside a
// cavity of another is fine, an inclusion meshed with its host is not), otherwise the PLC is meshed whole.
#pragma once

#include <vector>

#include "qualmesh/mesher.h"
#include "qualmesh/plc.h"

namespace qualmesh::detail {

struct PlcComponent {
  Plc plc;                    // its vertices, segments and facets; every hole and region seed of the input
  std::vector<Index> facets;  // the input facet of each of its facets
};

// The connected components of `plc` (vertices joined by segments and facet loops), each with every hole and region
// seed of the input (a seed outside a component's domain does nothing there: regions.cpp). Empty when there is one
// component, when a component is no closed surface (a facet edge used once) or a vertex is on no facet or segment
// (such a piece belongs inside another one's volume), or when a component's vertex is inside another's closed
// surface by ray parity (a cavity's wall, an inclusion): then the input is meshed whole.
std::vector<PlcComponent> separate_components(const Plc& plc);

// Whether a vertex of one mesh lies inside, or on the boundary of, another mesh's volume (ray parity against its
// hull faces, three rays; within 1e-9 of the diagonal of its hull counts as on it).
bool meshed_volumes_meet(const std::vector<const TetMesh*>& meshes);

// One mesh of the components' meshes, in order: points, tets and faces appended with their indices shifted, face
// facets mapped back to the input's (PlcComponent::facets); statistics summed (counts), least or largest (extreme
// figures), or joined (flags).
MeshResult merge_component_results(const std::vector<PlcComponent>& parts, std::vector<MeshResult>& results);

}  // namespace qualmesh::detail
