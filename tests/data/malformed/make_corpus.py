#!/usr/bin/env python3
"""Writes the malformed-input corpus of test_malformed.cpp into this folder (deterministic bytes).

Each entry: file name, content (str or bytes), expected ErrorCode name (to_string), a substring of the message,
and the expected 1-based line (0: binary file or not checked). EXPECTED.tsv is written from the same table.
Run: python3 make_corpus.py
"""
import os
import random
import struct

HERE = os.path.dirname(os.path.abspath(__file__))
rng = random.Random(20240611)


def garbage(n, first=0xFF):
    return bytes([first]) + bytes(rng.randrange(256) for _ in range(n - 1))


def binary_stl(triangles, header=b"solid but binary", count=None):
    data = header.ljust(80, b" ") + struct.pack("<I", len(triangles) if count is None else count)
    for tri in triangles:
        data += struct.pack("<3f", 0, 0, 1)
        for p in tri:
            data += struct.pack("<3f", *p)
        data += b"\0\0"
    return data


TRI = [(0, 0, 0), (1, 0, 0), (0, 1, 0)]
TET_OFF_HEAD = "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n"
TET_FACES = "3 0 2 1\n3 0 1 3\n3 1 2 3\n3 2 0 3\n"
MESH_HEAD = "MeshVersionFormatted 1\nDimension 3\n"
MESH_VERTS = "Vertices\n4\n0 0 0 0\n1 0 0 0\n0 1 0 0\n0 0 1 0\n"
POLY_NODES = "# tetrahedron\n4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n"
STL_FACET = "facet normal 0 0 1\n outer loop\n  vertex 0 0 0\n  vertex 1 0 0\n  vertex 0 1 0\n endloop\nendfacet\n"

CORPUS = [
    # OFF
    ("empty.off", "", "empty", "the file is empty", 0),
    ("off_no_header.off", "4 4 0\n0 0 0\n", "parse", "missing the OFF header", 1),
    ("off_truncated_vertices.off", "OFF\n4 1 0\n0 0 0\n1 0 0\n" + " " * 60, "parse",
     "unexpected end of file: expected vertex 2", 5),
    ("off_truncated_faces.off", TET_OFF_HEAD + "3 0 2 1\n3 0 1 3\n" + " " * 40, "parse",
     "unexpected end of file: expected face 2", 9),
    ("off_nan.off", "OFF\n4 4 0\n0 0 0\n1 nan 0\n0 1 0\n0 0 1\n" + TET_FACES, "non-finite",
     "y coordinate of vertex 1 is not finite", 4),
    ("off_inf.off", "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 -inf\n" + TET_FACES, "non-finite",
     "z coordinate of vertex 3 is not finite", 6),
    ("off_overflow.off", "OFF\n4 4 0\n0 0 0\n1e999 0 0\n0 1 0\n0 0 1\n" + TET_FACES, "non-finite",
     "x coordinate of vertex 1 is not finite", 4),
    ("off_index_out_of_range.off", TET_OFF_HEAD + "3 0 2 1\n3 0 1 3\n3 1 2 4\n3 2 0 3\n", "index-out-of-range",
     "face 2 refers to vertex 4, but there are 4 vertices", 9),
    ("off_negative_index.off", TET_OFF_HEAD + "3 0 2 1\n3 0 -1 3\n3 1 2 3\n3 2 0 3\n", "index-out-of-range",
     "face 1 refers to vertex -1", 8),
    ("off_absurd_count.off", "OFF\n99999999999 1 0\n0 0 0\n", "parse", "vertex count (99999999999) is absurd", 2),
    ("off_counts_too_big.off", "OFF\n3 3 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1", "parse", "do not fit", 2),
    ("off_face_short_line.off", TET_OFF_HEAD + "3 0 2\n3 0 1 3\n3 1 2 3\n3 2 0 3\n", "parse",
     "face 0 announces 3 vertices but the line has 2", 7),
    ("off_face_two_vertices.off", TET_OFF_HEAD + "2 0 2\n3 0 1 3\n3 1 2 3\n3 2 0 3\n", "parse",
     "face 0 has 2 vertices", 7),
    ("off_garbage_number.off", "OFF\n4 4 0\n0 0 0\n1.0abc 0 0\n0 1 0\n0 0 1\n" + TET_FACES, "parse",
     "expected a number for the x coordinate of vertex 1", 4),
    ("off_binary.off", "OFF BINARY\n", "unsupported", "binary OFF", 1),
    ("off_zero_faces.off", "OFF\n4 0 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n", "empty", "face count is 0", 2),
    ("off_binary_garbage.off", garbage(300), "parse", "missing the OFF header", 1),
    # STL
    ("stl_binary_wrong_size.stl", binary_stl([TRI] * 3, count=10), "parse",
     "header announces 10 triangles (584 bytes) but the file has 234 bytes", 0),
    ("stl_binary_huge_count.stl", binary_stl([TRI], count=0xFFFFFFFF), "parse", "binary STL of wrong size", 0),
    ("stl_binary_truncated.stl", binary_stl([TRI] * 4, header=b"binary")[:-30], "parse",
     "binary STL of wrong size", 0),
    ("stl_binary_nan.stl", binary_stl([TRI, [(0, 0, 0), (float("nan"), 0, 0), (0, 1, 0)]]), "non-finite",
     "triangle 2 (of 2) has a non-finite coordinate", 0),
    ("stl_garbage.stl", garbage(200, 0x00)[:80] + struct.pack("<I", 7) + garbage(116), "parse",
     "binary STL of wrong size", 0),
    ("stl_tiny_garbage.stl", garbage(10), "parse", "not an STL file", 0),
    ("stl_ascii_truncated.stl", "solid t\n" + STL_FACET + "facet normal 0 0 1\n outer loop\n  vertex 0 0 0\n  vertex 1",
     "parse", "unexpected end of file: expected the y coordinate of vertex 2 of facet 2", 12),
    ("stl_ascii_bad_keyword.stl", "solid t\nfacet normal 0 0 1\n outer lop\n", "parse", "expected 'loop' in facet 1",
     3),
    ("stl_ascii_nan_vertex.stl", "solid t\n" + STL_FACET.replace("vertex 1 0 0", "vertex 1 NaN 0") + "endsolid t\n",
     "non-finite", "y coordinate of vertex 2 of facet 1 is not finite", 5),
    ("stl_ascii_two_vertices.stl", "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nendloop\n",
     "parse", "facet 1 has 2 vertices", 6),
    ("stl_empty_solid.stl", "solid nothing\nendsolid nothing\n", "empty", "no facets", 0),
    # OBJ
    ("obj_index_zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", "index-out-of-range",
     "face 1 refers to vertex 0, but OBJ vertices are numbered from 1", 4),
    ("obj_out_of_range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 9\n", "index-out-of-range",
     "face 2 refers to vertex 9, but there are 3 vertices", 5),
    ("obj_relative_too_far.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -5\n", "index-out-of-range",
     "face 1 refers to vertex -5 (relative)", 4),
    ("obj_no_faces.obj", "# only points\nv 0 0 0\nv 1 0 0\n", "empty", "no faces", 0),
    ("obj_bad_vertex.obj", "v 0 0 0\nv 1 2\n", "parse", "missing the z coordinate of vertex 2", 2),
    ("obj_nan_vertex.obj", "v 0 0 0\nv 1 nan 2\nv 0 1 0\nf 1 2 3\n", "non-finite", "y coordinate of vertex 2", 2),
    ("obj_garbage.obj", b"v 0 0 0\n" + garbage(100, 0xC3).replace(b"\n", b" ").replace(b"#", b" "), "parse",
     "unknown OBJ statement", 2),
    ("obj_face_two_corners.obj", "v 0 0 0\nv 1 0 0\nf 1 2\n", "parse", "face 1 has 2 vertices", 3),
    # Medit
    ("mesh_missing_vertices.mesh", MESH_HEAD + "Triangles\n1\n1 2 3 0\nEnd\n", "parse", "no 'Vertices' section", 0),
    ("mesh_no_triangles.mesh", MESH_HEAD + MESH_VERTS + "Tetrahedra\n1\n1 2 3 4 0\nEnd\n", "empty",
     "no 'Triangles' or 'Quadrilaterals' section", 0),
    ("mesh_triangle_out_of_range.mesh", MESH_HEAD + MESH_VERTS + "Triangles\n2\n1 2 3 0\n1 2 5 0\nEnd\n",
     "index-out-of-range", "triangle 2 refers to vertex 5, but there are 4 vertices", 12),
    ("mesh_absurd_count.mesh", MESH_HEAD + "Vertices\n99999999999\n0 0 0 0\n", "parse",
     "vertex count (99999999999) is absurd", 4),
    ("mesh_dimension2.mesh", "MeshVersionFormatted 1\nDimension 2\nVertices\n1\n0 0 0\nEnd\n", "unsupported",
     "dimension 2", 2),
    ("mesh_truncated.mesh", MESH_HEAD + MESH_VERTS + "Triangles\n2\n1 2 3 0\n1 2", "parse",
     "unexpected end of file: expected the vertex of triangle 2", 12),
    ("mesh_no_version.mesh", "Dimension 3\n" + MESH_VERTS, "parse", "missing 'MeshVersionFormatted'", 2),
    # TetGen
    ("poly_bad_facet.poly", POLY_NODES + "4 0\n1\n3 1 3 2\n1\n3 1 2 9\n1\n3 2 3 4\n1\n3 3 1 4\n", "index-out-of-range",
     "facet 2 refers to vertex 9, but there are 4 vertices", 11),
    ("poly_truncated.poly", POLY_NODES + "4 0\n1\n3 1 3 2\n1\n3 1 2 4\n" + " " * 40, "parse",
     "unexpected end of file: expected facet 3 of 4", 12),
    ("poly_first_index_2.poly", "4 3 0 0\n2 0 0 0\n3 1 0 0\n4 0 1 0\n5 0 0 1\n", "parse",
     "first node index is 2", 2),
    ("poly_missing_node_file.poly", "0 3 0 0\n1 0\n1\n3 1 2 3\n", "io", "does not exist", 1),
    ("poly_facet_no_polygons.poly", POLY_NODES + "1 0\n0 0\n", "parse", "facet 1 has no polygons", 8),
    ("poly_absurd_facets.poly", POLY_NODES + "99999999999 0\n1\n3 1 2 3\n", "parse", "facet count (99999999999) is absurd",
     7),
    ("poly_dimension2.poly", "3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n", "unsupported", "dimension 2", 1),
    ("poly_nan_hole.poly", POLY_NODES + "1 0\n1 1\n3 1 2 3\n1 nan 0 0\n0\n", "non-finite",
     "x coordinate of hole 1 of facet 1", 10),
    ("poly_binary_garbage.poly", garbage(256, 0xFE), "parse", "expected an integer for the node count", 1),
    ("smesh_negative_index.smesh", "4 3 0 0\n0 0 0 0\n1 1 0 0\n2 0 1 0\n3 0 0 1\n2 0\n3 0 2 1\n3 0 -1 3\n",
     "index-out-of-range", "facet 1 refers to vertex -1", 8),
    ("smesh_nan_node.smesh", "4 3 0 0\n0 0 0 0\n1 1 0 0\n2 0 NaN 0\n3 0 0 1\n1 0\n3 0 1 2\n", "non-finite",
     "y coordinate of node 2 is not finite", 4),
    ("smesh_missing_coordinate.smesh", "2 3 0 0\n0 0 0 0\n1 1 0\n", "parse", "missing the z coordinate of node 1", 3),
    ("node_no_nodes.node", "0 3 0 0\n", "empty", "no nodes", 0),
]


def main():
    rows = ["# file\tcode\tmessage substring\tline (0: not checked)"]
    for name, content, code, substring, line in CORPUS:
        data = content.encode() if isinstance(content, str) else content
        with open(os.path.join(HERE, name), "wb") as out:
            out.write(data)
        rows.append(f"{name}\t{code}\t{substring}\t{line}")
    with open(os.path.join(HERE, "EXPECTED.tsv"), "w") as out:
        out.write("\n".join(rows) + "\n")
    print(len(CORPUS), "files")


if __name__ == "__main__":
    main()
