// Writers and readers of tetrahedral meshes: QualMesh's output formats (VTU, TetGen, Gmsh 4.1, Medit, Abaqus /
// CalculiX, UNV, Elmer) and the readers the checker uses to judge foreign meshes (TetGen, Gmsh 4.1 and 2.2, Medit,
// VTU, Abaqus / CalculiX, UNV). Every writer carries the groups Solid<r>, Face<m> and Edge<e> (tet_mesh.h) where the
// format can, and writes second-order meshes (TetMesh::tet_mid) in the format's own node order.
//
// Orientation: QualMesh writes tetrahedra positively oriented, (p1-p0) x (p2-p0) . (p3-p0) > 0, which is what
// VTK, Gmsh, Medit and CalculiX C3D4 expect (C3D4's node order is SMESH's [1,0,2,3], SMESH's being negative).
// Conventions measured on the real tools (Debian bookworm): TetGen 1.5.0 (`tetgen -pq2`, fandisk.off and a cube
// .poly) writes every tetrahedron positively oriented, and its .face triangles with the normal (b-a) x (c-a)
// pointing INTO the mesh; Gmsh 4.8.4 (`gmsh -3`, OCC box) writes positively oriented tetrahedra and boundary
// triangles with outward normals. Readers never reorder the nodes of a tetrahedron or triangle: a foreign mesh
// keeps the orientation of its file, so the checker sees it as it is; writers keep TetMesh's face orientation.
// Indices are 0-based in TetMesh; every format's 1-based numbering (or TetGen's 0- or 1-based) is converted here.
// Every writer goes through write_file_atomically: a failure never leaves a half-written file nor clobbers one.
#pragma once

#include <string>

#include "qualmesh/tet_mesh.h"

namespace qualmesh {

enum class MeshFormat {
  Vtu,     // VTK XML unstructured grid, ASCII; cell data "region", "min_dihedral_deg", "radius_edge"
  TetGen,  // BASE.node, BASE.ele (region as the tetrahedron attribute), BASE.face (facet marker)
  Gmsh41,  // Gmsh .msh 4.1 ASCII; physical groups Solid<r> (volumes), Face<m> (surfaces), Edge<e> (curves)
  Medit,   // Medit .mesh; region = tetrahedron reference, face marker = triangle reference
  Abaqus,  // Abaqus / CalculiX .inp; C3D4 / C3D10, ELSET Solid<r>, NSET + element *SURFACE Face<m>, NSET Edge<e>
  Unv,     // I-DEAS universal .unv (FreeCAD's native import); 2411 / 2412 / 2467 groups Solid<r>, Face<m>, Edge<e>
  Elmer,   // Elmer mesh directory NAME.elmer/ (mesh.header, .nodes, .elements, .boundary, .names); write only
};

// The format of a mesh file by its extension: .vtu, .node / .ele (TetGen), .msh, .mesh, .inp, .unv, .elmer (a
// directory; a trailing '/' is allowed).
// Throws InputError(ErrorCode::Unsupported) for any other extension.
MeshFormat mesh_format_from_path(const std::string& path);

// True when the extension names a mesh format (one that mesh_format_from_path accepts).
bool is_mesh_path(const std::string& path);

// Writes `mesh` to `path` in the format given by its extension. For TetGen, `path` may end in .node or .ele and
// BASE.node, BASE.ele and BASE.face are written; for Elmer, `path` is the directory to create (or replace). The
// mesh is not modified. Throws InputError(Io) on failure.
void write_tet_mesh(const TetMesh& mesh, const std::string& path);
void write_tet_mesh(const TetMesh& mesh, const std::string& path, MeshFormat format);

// Reads a tetrahedral mesh: TetGen (.ele or .node path: reads BASE.node + BASE.ele, and BASE.face when present),
// Gmsh .msh 4.1 and 2.2 ASCII, Medit .mesh, .vtu as QualMesh writes it (ASCII), Abaqus / CalculiX .inp (C3D4 /
// C3D10, *SURFACE element sides as faces; mesh_read_abaqus.cpp), UNV (111 / 118 tets, 2467 groups). Regions:
// TetGen's first tetrahedron attribute, the n of a group named Solid<n> (or the older Region<n>) in Gmsh, .inp and
// UNV (else Gmsh's physical or entity tag, the order of the .inp ELSETs or UNV volume groups), Medit's reference,
// VTU's "region" array. Face markers likewise (TetGen boundary marker, Face<n>, Medit reference, VTU "face_id"),
// edge markers from Edge<n> line elements (Gmsh, UNV, .inp) and Medit Edges. face_facet is -1 for every face read.
// Second-order meshes (Gmsh, VTU, Medit P2, .inp, .unv) fill tet_mid / face_mid / edge_mid, their points renumbered
// corners first; TetGen gives corners. Elmer directories are not read (Unsupported).
// Throws InputError (Io, Parse, Unsupported, IndexOutOfRange, NonFinite) with the file and line.
TetMesh read_tet_mesh(const std::string& path);

}  // namespace qualmesh
