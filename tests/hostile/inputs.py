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
    "collinear_triangle.off": off(CUBE + [(0.5, 0, 0)], CUBE_QUADS[:2] + CUBE_QUADS[3:] + [(0, 1, 8)]),
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


def write_inputs(folder):
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    for name, text in INPUTS.items():
        (folder / name).write_text(text)
    return folder
