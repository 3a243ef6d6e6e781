"""Hostile inputs of the catalogue (cases.py), written on the fly: write_inputs(folder) writes every file of INPUTS
there (deterministic bytes). Each is tiny, so that a refused case costs milliseconds and an accepted one well under a
second.
"""
from pathlib import Path

CUBE = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)]
CUBE_QUADS = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)]


def off(vertices, faces):
    lines = ["OFF", f"{len(vertices)} {len(faces)} 0"]
    lines += [" ".join(repr(float(c)) for c in v) for v in vertices]
    lines += [" ".join(str(i) for i in (len(f), *f)) for f in faces]
    return "\n".join(lines) + "\n"


def moved(vertices, d):
    return [(x + d[0], y + d[1], z + d[2]) for x, y, z in vertices]


def triangles_of(vertices, quads):
    out = []
    for q in quads:
        out.append((vertices[q[0]], vertices[q[1]], vertices[q[2]]))
        out.append((vertices[q[0]], vertices[q[2]], vertices[q[3]]))
    return out


def ascii_stl(facets):
    """facets: lists of corner points (3 for a triangle; more for a malformed facet)."""
    lines = ["solid hostile"]
    for corners in facets:
        lines += ["  facet normal 0 0 0", "    outer loop"]
        lines += [f"      vertex {x!r} {y!r} {z!r}" for x, y, z in corners]
        lines += ["    endloop", "  endfacet"]
    lines.append("endsolid hostile")
    return "\n".join(lines) + "\n"


def poly(vertices, facets, holes=(), regions=()):
    """TetGen .poly, 1-based; facets: lists of polygons (one polygon each here)."""
    lines = [f"{len(vertices)} 3 0 0"]
    lines += [f"{i + 1} {x!r} {y!r} {z!r}" for i, (x, y, z) in enumerate(vertices)]
    lines.append(f"{len(facets)} 0")
    for f in facets:
        lines += ["1 0", " ".join(str(i) for i in (len(f), *(j + 1 for j in f)))]
    lines.append(str(len(holes)))
    lines += [f"{i + 1} {x!r} {y!r} {z!r}" for i, (x, y, z) in enumerate(holes)]
    lines.append(str(len(regions)))
    lines += [f"{i + 1} {x!r} {y!r} {z!r} {a} {v!r}" for i, (x, y, z, a, v) in enumerate(regions)]
    return "\n".join(lines) + "\n"


# Two unit cubes side by side (x in [0, 2]) sharing the face x = 1: 12 vertices, 11 facets, one internal.
TWO_CUBES = [(x, y, z) for z in (0, 1) for y in (0, 1) for x in (0, 1, 2)]


def _v(x, y, z):
    return TWO_CUBES.index((x, y, z))


def _quad(*pts):
    return [_v(*p) for p in pts]


TWO_CUBE_FACETS = [
    _quad((0, 0, 0), (0, 1, 0), (1, 1, 0), (1, 0, 0)), _quad((1, 0, 0), (1, 1, 0), (2, 1, 0), (2, 0, 0)),
    _quad((0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)), _quad((1, 0, 1), (2, 0, 1), (2, 1, 1), (1, 1, 1)),
    _quad((0, 0, 0), (1, 0, 0), (1, 0, 1), (0, 0, 1)), _quad((1, 0, 0), (2, 0, 0), (2, 0, 1), (1, 0, 1)),
    _quad((0, 1, 0), (0, 1, 1), (1, 1, 1), (1, 1, 0)), _quad((1, 1, 0), (1, 1, 1), (2, 1, 1), (2, 1, 0)),
    _quad((0, 0, 0), (0, 0, 1), (0, 1, 1), (0, 1, 0)), _quad((2, 0, 0), (2, 1, 0), (2, 1, 1), (2, 0, 1)),
    _quad((1, 0, 0), (1, 1, 0), (1, 1, 1), (1, 0, 1)),  # internal facet
]

# A cube with one top vertex raised by 1e-3: the top quad and the two side quads through that vertex are 1e-3 off
# their planes (`info` names the top, facet 1, first).
_bent = list(CUBE)
_bent[6] = (1, 1, 1.001)


def _tet_off(d=(0, 0, 0), scale=1.0):
    v = [(0, 0, 0), (scale, 0, 0), (0, scale, 0), (0, 0, scale)]
    return moved(v, d), [(0, 2, 1), (0, 1, 3), (1, 2, 3), (2, 0, 3)]


def _two_overlapping_tets_stl():
    a, fa = _tet_off()
    b, fb = _tet_off((0.2, 0.2, 0.2))
    return ascii_stl([[a[i] for i in f] for f in fa] + [[b[i] for i in f] for f in fb])


INPUTS = {
    # category 1: inputs `info` marks INVALID
    "open_box.off": off(CUBE, CUBE_QUADS[:5]),
    "open_box.stl": ascii_stl(triangles_of(CUBE, CUBE_QUADS[1:])),
    "duplicated_face.off": off(CUBE, CUBE_QUADS + [CUBE_QUADS[2]]),
    "duplicated_face_reversed.off": off(CUBE, CUBE_QUADS + [tuple(reversed(CUBE_QUADS[2]))]),
    "duplicated_internal_facet.poly": poly(TWO_CUBES, TWO_CUBE_FACETS + [TWO_CUBE_FACETS[-1]]),
    "four_vertex_facet.stl": ascii_stl([[_bent[i] for i in CUBE_QUADS[1]]] + triangles_of(CUBE, CUBE_QUADS[:1])
                                       + triangles_of(_bent, CUBE_QUADS[2:])),
    "bowtie_facet.stl": ascii_stl([[CUBE[i] for i in (4, 6, 5, 7)]]
                                  + triangles_of(CUBE, CUBE_QUADS[:1] + CUBE_QUADS[2:])),
    "quad_off_plane.off": off(_bent, CUBE_QUADS),
    "quad_off_plane.poly": poly(_bent, CUBE_QUADS),
    "overlapping_cubes.off": off(CUBE + moved(CUBE, (0.5, 0.5, 0.5)),
                                 CUBE_QUADS + [tuple(i + 8 for i in q) for q in CUBE_QUADS]),
    "self_intersecting.stl": _two_overlapping_tets_stl(),
    "duplicate_vertex.off": off(CUBE + [CUBE[0]], CUBE_QUADS),
    "degenerate_facet.off": off(CUBE, CUBE_QUADS + [(0, 1, 2, 3, 0)]),
    # its long edge 1 -> 0 is on no face the other way round (the front quad, which holds 0 -> 1, is missing): no
    # repair, refused
    "collinear_triangle.off": off(CUBE + [(0.5, 0, 0)], CUBE_QUADS[:2] + CUBE_QUADS[3:] + [(1, 0, 8)]),
    # a closed cube with an extra triangle (5, 5, 6): dropped
    "repeated_vertex_triangle.off": off(CUBE, CUBE_QUADS + [(5, 5, 6)]),
    # a T-junction in disguise: the bottom has the middle 8 of edge 0-1, the front quad (face 2) does not, and the
    # triangle (1, 0, 8) of zero area closes the gap; the front quad gets 8 in its edge 0-1
    "t_junction_triangle.off": off(CUBE + [(0.5, 0, 0)], [(0, 3, 2, 1, 8)] + CUBE_QUADS[1:] + [(1, 0, 8)]),
    # the same as triangles: the bottom's are (0, 3, 2), (0, 2, 8), (8, 2, 1); the front's first, triangle 3, is split
    "t_junction_triangle.stl": ascii_stl(triangles_of(CUBE, CUBE_QUADS[1:])
                                         + [[(CUBE + [(0.5, 0, 0)])[i] for i in t]
                                            for t in ((0, 3, 2), (0, 2, 8), (8, 2, 1), (1, 0, 8))]),
    "single_triangle.off": off([(0, 0, 0), (1, 0, 0), (0, 1, 0)], [(0, 1, 2)]),
    "flat_square.off": off(CUBE[:4], [(0, 1, 2, 3)]),
    "whole_domain_hole.poly": poly(CUBE, CUBE_QUADS, holes=[(0.5, 0.5, 0.5)]),
    "both_regions_holes.poly": poly(TWO_CUBES, TWO_CUBE_FACETS, holes=[(0.5, 0.5, 0.5), (1.5, 0.5, 0.5)]),
    # accepted inputs (exit 0), so that the catalogue also pins what works
    "cube.off": off(CUBE, CUBE_QUADS),
    "cube.stl": ascii_stl(triangles_of(CUBE, CUBE_QUADS)),
    "cube_quads.stl": ascii_stl([[CUBE[i] for i in q] for q in CUBE_QUADS]),
    "two_cubes.poly": poly(TWO_CUBES, TWO_CUBE_FACETS),
    "one_of_two_holes.poly": poly(TWO_CUBES, TWO_CUBE_FACETS, holes=[(0.5, 0.5, 0.5)]),
    "hole_outside.poly": poly(CUBE, CUBE_QUADS, holes=[(5, 5, 5)]),
    "tet.off": off(*_tet_off()),
    "cube_offset_1e3.off": off(moved(CUBE, (1e3, -1e3, 1e3)), CUBE_QUADS),
    "cube_scaled_1e-3.off": off([(x * 1e-3, y * 1e-3, z * 1e-3) for x, y, z in CUBE], CUBE_QUADS),
}


def _kuhn_tets():
    """Kuhn's six tetrahedra of CUBE along the diagonal 0-6 (CUBE's ids), each positively oriented."""
    tets = []
    for a, b in [(1, 2), (1, 5), (3, 2), (3, 7), (4, 5), (4, 7)]:
        t = [0, a, b, 6]
        p = [CUBE[i] for i in t]
        u, v, w = ([p[k][j] - p[0][j] for j in range(3)] for k in (1, 2, 3))
        det = (u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0])
               + u[2] * (v[0] * w[1] - v[1] * w[0]))
        tets.append(t if det > 0 else [t[1], t[0], t[2], t[3]])
    return tets


def tetgen_mesh(vertices, tets):
    """A TetGen .node and .ele pair (1-based), as (node text, ele text)."""
    node = [f"{len(vertices)} 3 0 0"] + [f"{i + 1} {x!r} {y!r} {z!r}" for i, (x, y, z) in enumerate(vertices)]
    ele = [f"{len(tets)} 4 0"] + [" ".join(str(i) for i in (k + 1, *(j + 1 for j in t))) for k, t in enumerate(tets)]
    return "\n".join(node) + "\n", "\n".join(ele) + "\n"


# check far from the origin (issue 18 item 5): the cube moved by D, as an input and as a 6-tet mesh of it; and the
# same mesh with one vertex 1e-5 (80 ulps) off the input at 1e9, which check must still find.
for _name, _d in [("1e9", 1e9), ("1e15", 1e15), ("minus_1e15", -1e15)]:
    INPUTS[f"cube_offset_{_name}.off"] = off(moved(CUBE, (_d, _d, _d)), CUBE_QUADS)
    INPUTS[f"cube_mesh_{_name}.node"], INPUTS[f"cube_mesh_{_name}.ele"] = tetgen_mesh(moved(CUBE, (_d, _d, _d)),
                                                                                   _kuhn_tets())
_off_by = moved(CUBE, (1e9, 1e9, 1e9))
_off_by[6] = (_off_by[6][0], _off_by[6][1], _off_by[6][2] + 1e-5)
INPUTS["cube_mesh_1e9_bent.node"], INPUTS["cube_mesh_1e9_bent.ele"] = tetgen_mesh(_off_by, _kuhn_tets())


def _prism(n):
    """A prism over a regular n-gon: all its vertices on one sphere, so the initial Delaunay triangulation is slow."""
    import math
    ring = [(math.cos(2 * math.pi * i / n), math.sin(2 * math.pi * i / n)) for i in range(n)]
    vertices = [(x, y, z) for z in (0.0, 1.0) for x, y in ring]
    faces = [tuple(reversed(range(n))), tuple(range(n, 2 * n))]
    faces += [(i, (i + 1) % n, n + (i + 1) % n, n + i) for i in range(n)]
    return off(vertices, faces)


INPUTS["prism_2000.off"] = _prism(2000)


# ---------------------------------------------------------------------------------------------------------------
# Issue 18 item 7, unclear messages made clear: a UTF-8 byte order mark and CR-only or CR LF line ends read as plain
# text; random bytes in a text file; coordinates whose powers overflow or underflow; empty OpenSCAD files.
BOM = b"\xef\xbb\xbf"
_cube_obj = "".join(f"v {x} {y} {z}\n" for x, y, z in CUBE) + "".join(
    "f " + " ".join(str(i + 1) for i in q) + "\n" for q in CUBE_QUADS)
INPUTS["bom.obj"] = BOM + _cube_obj.encode()
INPUTS["bom.off"] = BOM + off(CUBE, CUBE_QUADS).encode()
INPUTS["bom.stl"] = BOM + ascii_stl(triangles_of(CUBE, CUBE_QUADS)).encode()
INPUTS["bom.poly"] = BOM + poly(CUBE, CUBE_QUADS).encode()
for _ext, _text in [("off", off(CUBE, CUBE_QUADS)), ("obj", _cube_obj), ("poly", poly(CUBE, CUBE_QUADS)),
                    ("stl", ascii_stl(triangles_of(CUBE, CUBE_QUADS)))]:
    INPUTS[f"cr_only.{_ext}"] = _text.replace("\n", "\r")
    INPUTS[f"crlf.{_ext}"] = _text.replace("\n", "\r\n")
# a CR-only file with an error: its line number counts CRs as line ends (the bad vertex is on line 5)
INPUTS["cr_only_bad_vertex.off"] = off(CUBE, CUBE_QUADS).replace("1.0 1.0 0.0", "1.0 1.0 zz", 1).replace("\n", "\r")
_rng_state = [20261201]


def _random_bytes(n):
    """Deterministic bytes (a linear congruential generator), escape (0x1b) and bell (0x07) included."""
    out = bytearray()
    for _ in range(n):
        _rng_state[0] = (_rng_state[0] * 1103515245 + 12345) & 0x7FFFFFFF
        out.append((_rng_state[0] >> 16) & 0xFF)
    return bytes(out)


INPUTS["random_bytes.obj"] = b"v \x1b[31m\x07" + _random_bytes(200)
INPUTS["random_bytes.off"] = b"OFF\n\x9b\x1b]0;pwned\x07" + _random_bytes(200)
# under 84 bytes and without NUL, so that it is read as ASCII STL
INPUTS["random_bytes.stl"] = b"solid x\n facet \xff\xfe\x1b[2J" + _random_bytes(60).replace(b"\0", b"\x01")
INPUTS["random_bytes.inp"] = b"*NODE\n1, \x1b[31m\x07" + _random_bytes(100)
INPUTS["random_bytes.msh"] = b"$MeshFormat\n\x1b[2J\xc3" + _random_bytes(100)
INPUTS["random_bytes.mesh"] = b"\x1b[2J\xc3\x28" + _random_bytes(100)
for _name, _k in [("1e308", 1e308), ("1e100", 1e100), ("minus_1e80", -1e80), ("1e-300", 1e-300),
                  ("1e-100", 1e-100), ("1e60", 1e60), ("1e-60", 1e-60)]:
    INPUTS[f"cube_scaled_{_name}.off"] = off([(x * _k, y * _k, z * _k) for x, y, z in CUBE], CUBE_QUADS)
# far out but small: 1e75 away, 1 wide
# A slab 1e-4 thick (issue 18 item 3): its local feature size asks for about 1e8 tets; refused before any work.
INPUTS["slab_1e-4.off"] = off([(x, y, z) for z in (0.0, 1e-4) for y in (0.0, 1.0) for x in (0.0, 1.0)],
                              [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (1, 3, 7, 5), (3, 2, 6, 7), (2, 0, 4, 6)])
# 100 nested cube shells 0.0025 apart (issue 18 item 3): within the memory budget, but tens of millions of tets.
INPUTS["nested_100_cubes.off"] = off([(sx * (0.5 - 0.0025 * k), sy * (0.5 - 0.0025 * k), sz * (0.5 - 0.0025 * k))
                                      for k in range(100) for sz in (-1, 1) for sy in (-1, 1) for sx in (-1, 1)],
                                     [tuple(8 * k + i for i in q) for k in range(100)
                                      for q in ((0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (1, 3, 7, 5), (3, 2, 6, 7),
                                                (2, 0, 4, 6))])
INPUTS["cube_offset_1e75.off"] = off(moved(CUBE, (1e75, 0, 0)), CUBE_QUADS)
INPUTS["empty.scad"] = ""
INPUTS["blank.scad"] = "  \n\t\n"
INPUTS["comment_only.scad"] = "// nothing is drawn here\nmodule unused() { cube(1); }\n"
# Renders for well over a minute (CGAL unions of spheres): the run is stopped while openscad works on it.
INPUTS["slow.scad"] = "union() { for (i = [0:40]) translate([i * 0.7, 0, 0]) sphere(r = 1, $fn = 48); }\n"


def _grid_mesh(n):
    """A structured mesh of the unit cube: n^3 cells of Kuhn's six tetrahedra each (6 n^3 tets), as .node/.ele."""
    step = 1.0 / n
    vertices = [(i * step, j * step, k * step) for k in range(n + 1) for j in range(n + 1) for i in range(n + 1)]
    tets = []
    kuhn = _kuhn_tets()

    def vid(i, j, k):
        return i + (n + 1) * (j + (n + 1) * k)
    for k in range(n):
        for j in range(n):
            for i in range(n):
                corner = [vid(i + x, j + y, k + z) for x, y, z in CUBE]
                tets.extend([corner[a] for a in t] for t in kuhn)
    return tetgen_mesh(vertices, tets)


# 162000 tets: a .vtu of some 10 MB, written for long enough that a signal can be sent in the middle of the write
INPUTS["grid.node"], INPUTS["grid.ele"] = _grid_mesh(30)
INPUTS["small_mesh.node"], INPUTS["small_mesh.ele"] = tetgen_mesh(CUBE, _kuhn_tets())


# Fuzzing findings (tests/fuzz/regressions/READER/), split as fuzz_reader.cpp splits them ("\n@@\n"), by their
# exact bytes: a TetGen .ele region attribute of 3.3e16 was converted to int (undefined behaviour).
_FUZZ = Path(__file__).resolve().parents[1] / "fuzz" / "regressions"
_parts = (_FUZZ / "mesh_tetgen" / "region-attribute-beyond-int").read_bytes().split(b"\n@@\n", 2)
for _ext, _part in zip([".node", ".ele", ".face"], _parts):
    INPUTS["fuzz_region_attribute" + _ext] = _part + (b"\n" if _ext != [".node", ".ele", ".face"][len(_parts) - 1] else b"")

# a TetGen .ele vertex index of -1.1e19: raw - first index overflowed long long (undefined behaviour)
_parts = (_FUZZ / "mesh_tetgen" / "vertex-index-overflow").read_bytes().split(b"\n@@\n", 2)
for _ext, _part in zip([".node", ".ele", ".face"], _parts):
    INPUTS["fuzz_vertex_index" + _ext] = _part + (b"\n" if _ext != [".node", ".ele", ".face"][len(_parts) - 1] else b"")
# a VTU offset of 3.1e78 was converted to size_t (undefined behaviour)
INPUTS["fuzz_offset_beyond_size_t.vtu"] = (_FUZZ / "vtu" / "offset-beyond-size_t").read_bytes()
# a Medit mesh announcing 999999999 vertices in a few bytes: 24 GB were allocated for them
INPUTS["fuzz_vertex_count.mesh"] = (_FUZZ / "mesh_medit" / "vertex-count-beyond-file").read_bytes()
# an .inp whose sets were copied into themselves, each copy doubling them: 4 GB and 223 s for 6 kB
INPUTS["fuzz_set_copied_into_itself.inp"] = (_FUZZ / "inp" / "set-copied-into-itself").read_bytes()


def write_inputs(folder):
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    for name, data in INPUTS.items():
        if isinstance(data, bytes):
            (folder / name).write_bytes(data)
        else:
            (folder / name).write_text(data, newline="")  # CR and CR LF line ends as given
    return folder
