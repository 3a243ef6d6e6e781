"""Degenerate and adversarial geometry (issue 16's adversarial inputs, issue 18's degenerate-geometry suite), made
here as exact files: every case is small, and its exact volume is known, so that a mesh can be judged from scratch.

Each builder returns (file name, text, exact volume). Coordinates are written with repr(), so they round-trip.
"""
import math


def off(vertices, faces):
    lines = ["OFF", f"{len(vertices)} {len(faces)} 0"]
    lines += [f"{x!r} {y!r} {z!r}" for x, y, z in vertices]
    lines += [" ".join(str(i) for i in (len(f), *f)) for f in faces]
    return "\n".join(lines) + "\n"


def poly(vertices, facets, regions=(), markers=None):
    """TetGen .poly, 1-based, one polygon per facet; regions: (x, y, z, attribute)."""
    lines = [f"{len(vertices)} 3 0 0"]
    lines += [f"{i + 1} {x!r} {y!r} {z!r}" for i, (x, y, z) in enumerate(vertices)]
    lines.append(f"{len(facets)} 1")
    for k, f in enumerate(facets):
        lines += [f"1 0 {markers[k] if markers else k + 1}", " ".join(str(i) for i in (len(f), *(j + 1 for j in f)))]
    lines.append("0")
    lines.append(str(len(regions)))
    lines += [f"{i + 1} {x!r} {y!r} {z!r} {a} -1" for i, (x, y, z, a) in enumerate(regions)]
    return "\n".join(lines) + "\n"


# A box as 8 corners and 6 outward quads (OFF, 0-based).
BOX_QUADS = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)]


def box_corners(lo, hi):
    (x0, y0, z0), (x1, y1, z1) = lo, hi
    return [(x0, y0, z0), (x1, y0, z0), (x1, y1, z0), (x0, y1, z0),
            (x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1)]


def cube_offset(d):
    """The unit cube moved by (d, d, d): exact in binary for d = 1e9 (1e15 too: its ulp is 0.125)."""
    return f"cube_offset_{d:g}.off", off(box_corners((d, d, d), (d + 1, d + 1, d + 1)), BOX_QUADS), 1.0


def cube_scaled(s):
    return f"cube_scaled_{s:g}.off", off(box_corners((0, 0, 0), (s, s, s)), BOX_QUADS), s ** 3


def slab(t):
    return f"slab_{t:g}.off", off(box_corners((0, 0, 0), (1, 1, t)), BOX_QUADS), t


def schonhardt(twist_deg=30.0, reflex=True):
    """Schonhardt's twisted prism: two equilateral triangles (radius 1) 1 apart, the top turned by twist_deg, and each
    side quad cut along the diagonal that makes it reflex, so no tetrahedrisation without Steiner points exists."""
    bottom = [(math.cos(2 * math.pi * k / 3), math.sin(2 * math.pi * k / 3), 0.0) for k in range(3)]
    t = math.radians(twist_deg)
    top = [(math.cos(2 * math.pi * k / 3 + t), math.sin(2 * math.pi * k / 3 + t), 1.0) for k in range(3)]
    v = bottom + top
    faces = [(0, 2, 1), (3, 4, 5)]
    for k in range(3):
        a, b = k, (k + 1) % 3
        # quad bottom a, bottom b, top b, top a; the reflex diagonal joins bottom a to top b for a positive twist
        faces += [(a, b, 3 + b), (a, 3 + b, 3 + a)] if reflex else [(a, b, 3 + a), (b, 3 + b, 3 + a)]
    # volume: the prism's sides bend inward; computed exactly by the divergence theorem on the triangles
    return "schonhardt.off", off(v, faces), signed_volume(v, faces)


def fan(n=20, radius=1.0, height=1.0):
    """A cone: n side triangles around one apex over an n-gon base (a fan of n triangles at one vertex)."""
    base = [(radius * math.cos(2 * math.pi * k / n), radius * math.sin(2 * math.pi * k / n), 0.0) for k in range(n)]
    v = base + [(0.0, 0.0, height)]
    faces = [tuple(range(n - 1, -1, -1))] + [(k, (k + 1) % n, n) for k in range(n)]
    return f"fan_{n}_{radius:g}.off", off(v, faces), signed_volume(v, faces)


def wedge(angle_deg=1.0):
    """A wedge whose two long faces meet at angle_deg along the edge z = 0, y = 0 (an acute input dihedral)."""
    a = math.radians(angle_deg)
    ys, zs = math.cos(a), math.sin(a)
    v = [(0.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, ys, zs), (1.0, 0.0, 0.0), (1.0, 1.0, 0.0), (1.0, ys, zs)]
    faces = [(0, 2, 1), (3, 4, 5), (0, 1, 4, 3), (1, 2, 5, 4), (0, 3, 5, 2)]
    return f"wedge_{angle_deg:g}.off", off(v, faces), signed_volume(v, faces)


def nearly_coplanar(eps=1e-10):
    """The unit cube whose top is two triangles, the far corner raised by eps: two facets 1e-10 from coplanar."""
    v = box_corners((0, 0, 0), (1, 1, 1))
    v[6] = (1.0, 1.0, 1.0 + eps)
    faces = [f for f in BOX_QUADS if f != (4, 5, 6, 7) and f not in ((1, 2, 6, 5), (2, 3, 7, 6))]
    faces += [(4, 5, 7), (5, 6, 7), (1, 2, 6), (1, 6, 5), (2, 3, 7), (2, 7, 6)]
    return f"nearly_coplanar_{eps:g}.off", off(v, faces), signed_volume(v, faces)


def cubes_touching(kind):
    """Two unit cubes as two closed shells meeting only along an edge ("edge") or at a vertex ("vertex")."""
    shift = (1.0, 1.0, 0.0) if kind == "edge" else (1.0, 1.0, 1.0)
    a = box_corners((0, 0, 0), (1, 1, 1))
    b = box_corners(shift, tuple(s + 1 for s in shift))
    v, faces = list(a), list(BOX_QUADS)
    index = {p: i for i, p in enumerate(v)}
    remap = []
    for p in b:
        if p not in index:
            index[p] = len(v)
            v.append(p)
        remap.append(index[p])
    faces += [tuple(remap[i] for i in f) for f in BOX_QUADS]
    return f"cubes_sharing_{kind}.off", off(v, faces), 2.0


def row_of_regions(n=100):
    """n unit cubes in a row along x, each its own region (attribute k + 1): n - 1 internal facets."""
    v = [(float(x), float(y), float(z)) for x in range(n + 1) for y in (0, 1) for z in (0, 1)]
    vid = {p: i for i, p in enumerate(v)}

    def q(*pts):
        return [vid[tuple(map(float, p))] for p in pts]

    facets = [q((x, 0, 0), (x, 1, 0), (x, 1, 1), (x, 0, 1)) for x in range(n + 1)]  # the n + 1 cross sections
    for x in range(n):
        facets += [q((x, 0, 0), (x + 1, 0, 0), (x + 1, 0, 1), (x, 0, 1)), q((x, 1, 0), (x + 1, 1, 0), (x + 1, 1, 1), (x, 1, 1)),
                   q((x, 0, 0), (x + 1, 0, 0), (x + 1, 1, 0), (x, 1, 0)), q((x, 0, 1), (x + 1, 0, 1), (x + 1, 1, 1), (x, 1, 1))]
    regions = [(x + 0.5, 0.5, 0.5, x + 1) for x in range(n)]
    return f"row_of_{n}_regions.poly", poly(v, facets, regions), float(n)


def signed_volume(v, faces):
    total = 0.0
    for f in faces:
        p0 = v[f[0]]
        for i in range(1, len(f) - 1):
            p1, p2 = v[f[i]], v[f[i + 1]]
            total += (p0[0] * (p1[1] * p2[2] - p1[2] * p2[1]) - p0[1] * (p1[0] * p2[2] - p1[2] * p2[0]) +
                      p0[2] * (p1[0] * p2[1] - p1[1] * p2[0])) / 6.0
    return total
