"""Solver-ready output (issue 14), judged by the real solver: Debian's CalculiX `ccx` 2.20 runs our second-order
decks, using only our group names (Face<i>, Edge<i>, Solid<i>), and the answers match closed-form solutions.

- Cantilever 100 x 10 x 10 mm, steel (E 210000 MPa, nu 0.3), fixed on Face1 (x = 0), 1000 N shear on Face2
  (x = 100) through a distributing coupling (the load spreads over the face without stiffening it). Reference: the
  mean tip deflection of the 3D problem, 1.906 mm, what fine second-order meshes converge to (shared/docs/FREECAD.md;
  between Euler-Bernoulli's P L^3 / 3EI = 1.905 mm and Timoshenko's 1.920 mm with shear factor 5/6, the difference
  being the 3D end effects). Gmsh's C3D10 meshes of the same STEP, made in the same run, are solved with the same
  deck, so the node counts compare at equal accuracy.
- Thick-walled cylinder, inner radius 10, outer 20, length 10, internal pressure 100 MPa, axial and tangential
  displacement fixed on both ends (plane strain, axisymmetric): Lame's radial displacement at the bore,
  u(a) = (1 + nu) p a^2 / (E (b^2 - a^2)) ((1 - 2 nu) a + b^2 / a).
- Every file of ../shared/data/cad that meshes: its --order 2 deck runs (first face fixed, pressure on the last).
"""
import math
import os
import re
import subprocess
from pathlib import Path

import pytest

from conftest import SHARED_DIR, SOURCE_DIR, require_module, require_tool

REFERENCE_TIP = 1.906  # mm
TOLERANCE = 0.005      # 0.5 %


def parse_inp(path):
    """Nodes {id: (x, y, z)}, node sets {name: [ids]}, elements [(id, [nodes])] of a .inp (ours or this test's)."""
    nodes, sets, elements = {}, {}, []
    mode, name = None, None
    for line in Path(path).read_text().splitlines():
        if line.startswith("**") or not line.strip():
            continue
        if line.startswith("*"):
            key = line.split(",")[0].strip().upper()
            params = {k.strip().upper(): v.strip() for k, _, v in (p.partition("=") for p in line.split(",")[1:])}
            mode = key
            name = params.get("NSET") if key == "*NSET" else None
            if key == "*NSET":
                sets.setdefault(name, [])
            continue
        fields = [f for f in line.replace(",", " ").split()]
        if mode == "*NODE":
            nodes[int(fields[0])] = tuple(float(f) for f in fields[1:4])
        elif mode == "*NSET":
            sets[name].extend(int(f) for f in fields)
        elif mode == "*ELEMENT":
            elements.append((int(fields[0]), [int(f) for f in fields[1:]]))
    return nodes, sets, elements


def run_ccx(workdir, job, timeout=900):
    ccx = require_tool("ccx")
    result = subprocess.run([ccx, "-i", job], cwd=workdir, capture_output=True, text=True, timeout=timeout)
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-2000:]
    assert "*ERROR" not in result.stdout, result.stdout[-3000:]
    return result


def node_displacements(dat_path):
    """{node: (ux, uy, uz)} from the displacement blocks of a .dat file."""
    out = {}
    block = False
    for line in Path(dat_path).read_text().splitlines():
        if "displacements" in line:
            block = True
            continue
        fields = line.split()
        if block and len(fields) == 4:
            try:
                out[int(fields[0])] = tuple(float(f) for f in fields[1:])
            except ValueError:
                block = False
    return out


CANTILEVER_DECK = """*INCLUDE, INPUT={mesh}
*MATERIAL, NAME=STEEL
*ELASTIC
210000., 0.3
*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL
*NODE, NSET=TIPREF
900000, 100., 5., 5.
*COUPLING, REF NODE=900000, SURFACE={tip}, CONSTRAINT NAME=TIPLOAD
*DISTRIBUTING
1, 3
*BOUNDARY
{fixed}, 1, 3, 0.
*STEP
*STATIC
*CLOAD
900000, 2, -1000.
*NODE PRINT, NSET={tip_nodes}
U
*END STEP
"""


def solve_cantilever(workdir, mesh_inp, tip="Face2", fixed="Face1", tip_nodes="Face2"):
    deck = Path(workdir) / "cantilever.inp"
    deck.write_text(CANTILEVER_DECK.format(mesh=Path(mesh_inp).name, tip=tip, fixed=fixed, tip_nodes=tip_nodes))
    run_ccx(workdir, "cantilever")
    u = node_displacements(Path(workdir) / "cantilever.dat")
    return -sum(v[1] for v in u.values()) / len(u), len(u)


def qualmesh_beam(run_qualmesh, workdir, size):
    step = SOURCE_DIR / "examples" / "cantilever" / "beam.step"
    mesh = Path(workdir) / "beam.inp"
    args = ["mesh", step, "--order", "2", "-o", mesh] + (["--size", size] if size else [])
    result = run_qualmesh(*args)
    assert result.returncode == 0, result.stderr
    nodes, sets, elements = parse_inp(mesh)
    # Our groups are the CAD faces: Face1 is x = 0, Face2 is x = 100, as FreeCAD numbers the box's faces.
    assert all(abs(nodes[n][0]) < 1e-9 for n in sets["Face1"])
    assert all(abs(nodes[n][0] - 100) < 1e-9 for n in sets["Face2"])
    assert all(len(e[1]) == 10 for e in elements)
    return mesh, len(nodes)


def gmsh_beam_inp(workdir, clmax):
    """Gmsh's C3D10 mesh of the same STEP, written as a deck with Face1/Face2 node sets and a tip surface found
    geometrically, C3D10 node order (Gmsh's tet10 swaps the mid nodes of edges 2-3 and 1-3: reordered by position)."""
    gmsh = require_module("gmsh")
    np = require_module("numpy")
    gmsh.initialize()
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.occ.importShapes(str(SOURCE_DIR / "examples" / "cantilever" / "beam.step"))
        gmsh.model.occ.synchronize()
        gmsh.option.setNumber("Mesh.CharacteristicLengthMax", clmax)
        gmsh.option.setNumber("Mesh.ElementOrder", 2)
        gmsh.model.mesh.generate(3)
        tags, coords, _ = gmsh.model.mesh.getNodes()
        xyz = dict(zip((int(t) for t in tags), coords.reshape(-1, 3)))
        _, tet_tags, tet_nodes = gmsh.model.mesh.getElements(3)
        tets = np.array(tet_nodes[0], dtype=np.int64).reshape(-1, 10)
    finally:
        gmsh.finalize()
    used = sorted(set(tets.flatten().tolist()))
    lines = ["*NODE, NSET=NALL"] + [f"{n}, {xyz[n][0]:.12g}, {xyz[n][1]:.12g}, {xyz[n][2]:.12g}" for n in used]
    lines.append("*ELEMENT, TYPE=C3D10, ELSET=EALL")
    pairs = [(0, 1), (1, 2), (0, 2), (0, 3), (1, 3), (2, 3)]
    tip_faces = []
    for k, t in enumerate(tets, start=1):
        corners = list(t[:4])
        mids = {}
        for m in t[4:]:
            for i, j in pairs:
                if np.allclose(xyz[m], 0.5 * (xyz[corners[i]] + xyz[corners[j]]), atol=1e-9):
                    mids[(i, j)] = m
        assert len(mids) == 6
        lines.append(", ".join(str(v) for v in [k] + corners + [mids[p] for p in pairs]))
        for side, face in enumerate([(0, 1, 2), (0, 3, 1), (1, 3, 2), (2, 3, 0)], start=1):
            if all(abs(xyz[corners[i]][0] - 100) < 1e-9 for i in face):
                tip_faces.append((k, side))
    face1 = [n for n in used if abs(xyz[n][0]) < 1e-9]
    face2 = [n for n in used if abs(xyz[n][0] - 100) < 1e-9]
    for name, ids in (("Face1", face1), ("Face2", face2)):
        lines.append(f"*NSET, NSET={name}")
        lines += [", ".join(str(i) for i in ids[k:k + 16]) for k in range(0, len(ids), 16)]
    lines.append("*SURFACE, NAME=TipSurface, TYPE=ELEMENT")
    lines += [f"{k}, S{s}" for k, s in tip_faces]
    mesh = Path(workdir) / "gmsh_beam.inp"
    mesh.write_text("\n".join(lines) + "\n")
    return mesh, len(used)


def coarsest_within(results):
    """Smallest node count among (nodes, deflection) pairs within the tolerance of the reference."""
    ok = [n for n, d in results if abs(d - REFERENCE_TIP) <= TOLERANCE * REFERENCE_TIP]
    return min(ok) if ok else None


def test_cantilever_c3d10_tip_deflection_converges_to_the_reference(run_qualmesh, tmp_path):
    require_tool("ccx")
    ours = []
    for size in (12, 8, 5):
        work = tmp_path / f"qm{size}"
        work.mkdir()
        mesh, nodes = qualmesh_beam(run_qualmesh, work, size)
        ours.append((nodes, solve_cantilever(work, mesh)[0]))
    print("QualMesh C3D10 (nodes, mean tip deflection mm):", ours)
    # The finest of ours is within 0.5 % of the reference.
    assert abs(ours[-1][1] - REFERENCE_TIP) <= TOLERANCE * REFERENCE_TIP, ours
    # Refinement converges toward the reference from below (tets are stiff, never too soft).
    assert all(d < REFERENCE_TIP * 1.001 for _, d in ours), ours
    assert coarsest_within(ours) is not None, ours


# Issue 14's node-count target: the coarsest mesh within 0.5 % of the reference, for each mesher over the same sweep
# of size parameters (--size for QualMesh, CharacteristicLengthMax for Gmsh; node counts are not monotone in either,
# so the sweep is dense and identical for both). Measured 2026-12-03: QualMesh 551 nodes at 9.5 (1.8965 mm), Gmsh 591
# at 9 (1.8971 mm; its 551 nodes at 9.5 give 1.8964 mm, just outside). That is since the planar CAD faces are meshed
# at their edges' spacing (brep_to_plc.cpp): before, their interiors were left to the volume mesher and QualMesh
# needed 833 nodes.
CANTILEVER_SWEEP = (12, 11, 10, 9.5, 9, 8.5, 8, 7.5, 7, 6.5, 6)


def test_cantilever_needs_no_more_nodes_than_gmsh_for_the_same_accuracy(run_qualmesh, tmp_path):
    require_tool("ccx")
    ours, theirs = [], []
    for size in CANTILEVER_SWEEP:
        work = tmp_path / f"qm{size}"
        work.mkdir()
        mesh, nodes = qualmesh_beam(run_qualmesh, work, size)
        ours.append((nodes, solve_cantilever(work, mesh)[0]))
        work = tmp_path / f"gmsh{size}"
        work.mkdir()
        mesh, nodes = gmsh_beam_inp(work, size)
        theirs.append((nodes, solve_cantilever(work, mesh, tip="TipSurface")[0]))
    print("QualMesh C3D10 (nodes, mean tip deflection mm):", ours)
    print("Gmsh C3D10 (nodes, mean tip deflection mm):", theirs)
    gmsh_needed, ours_needed = coarsest_within(theirs), coarsest_within(ours)
    print(f"coarsest within 0.5 %: QualMesh {ours_needed} nodes, Gmsh {gmsh_needed}")
    assert gmsh_needed is not None and ours_needed is not None, (ours, theirs)
    assert ours_needed <= gmsh_needed, (ours, theirs)


def test_cantilever_example_runs_as_documented(tmp_path):
    """examples/cantilever/run.sh, the README's one command, prints the tip deflection within 0.5 %."""
    require_tool("ccx")
    env = dict(os.environ, WORK=str(tmp_path))
    exe = os.environ.get("QUALMESH_EXE")
    if exe:
        env["QUALMESH"] = exe
    result = subprocess.run(["bash", str(SOURCE_DIR / "examples" / "cantilever" / "run.sh")], env=env,
                            capture_output=True, text=True, timeout=600)
    assert result.returncode == 0, result.stdout + result.stderr
    match = re.search(r"tip deflection \(mean over the \d+ nodes of Face2\): ([0-9.]+) mm", result.stdout)
    assert match, result.stdout
    assert abs(float(match.group(1)) - REFERENCE_TIP) <= TOLERANCE * REFERENCE_TIP, result.stdout


def make_thick_cylinder_step(path):
    gmsh = require_module("gmsh")
    gmsh.initialize()
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        outer = gmsh.model.occ.addCylinder(0, 0, 0, 0, 0, 10, 20)
        inner = gmsh.model.occ.addCylinder(0, 0, 0, 0, 0, 10, 10)
        gmsh.model.occ.cut([(3, outer)], [(3, inner)])
        gmsh.model.occ.synchronize()
        gmsh.write(str(path))
    finally:
        gmsh.finalize()


def tet10_min_jacobians(np, xyz, elements):
    """Minimum over the ten nodes of det(dx/dL) per C3D10 element (positive: not inverted)."""
    conn = np.array([e[1] for e in elements])
    X = np.stack([np.array([xyz[n] for n in conn[:, k]]) for k in range(10)], axis=1)  # (E, 10, 3)
    mid = {(0, 1): 4, (1, 2): 5, (0, 2): 6, (0, 3): 7, (1, 3): 8, (2, 3): 9}
    points = [np.eye(4)[i] for i in range(4)] + [0.5 * (np.eye(4)[i] + np.eye(4)[j]) for i, j in mid]
    worst = np.full(len(conn), np.inf)
    for L in points:
        g = []
        for a in range(4):
            d = (4 * L[a] - 1) * X[:, a]
            for b in range(4):
                if b != a:
                    d = d + 4 * L[b] * X[:, mid[(min(a, b), max(a, b))]]
            g.append(d)
        J = np.stack([g[k] - g[0] for k in (1, 2, 3)], axis=2)
        worst = np.minimum(worst, np.linalg.det(J))
    return worst


LAME_DECK = """*INCLUDE, INPUT=cyl.inp
*MATERIAL, NAME=STEEL
*ELASTIC
210000., 0.3
*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL
*NSET, NSET=ENDS
{ends}
*TRANSFORM, NSET=ENDS, TYPE=C
0., 0., 0., 0., 0., 1.
*BOUNDARY
ENDS, 2, 3, 0.
*STEP
*STATIC
*DSLOAD
{bore}, P, 100.
*NODE PRINT, NSET={bore}
U
*END STEP
"""


def test_thick_cylinder_matches_lame_and_stays_on_the_cad_surface(run_qualmesh, tmp_path):
    np = require_module("numpy")
    require_tool("ccx")
    step = tmp_path / "cyl.step"
    make_thick_cylinder_step(step)
    mesh = tmp_path / "cyl.inp"
    result = run_qualmesh("mesh", step, "--order", "2", "--max-edge", "2.5", "-o", mesh)
    assert result.returncode == 0, result.stderr
    print(result.stdout)
    nodes, sets, elements = parse_inp(mesh)
    assert all(len(e[1]) == 10 for e in elements)
    diagonal = math.sqrt(40 ** 2 + 40 ** 2 + 10 ** 2)
    radius = {n: math.hypot(p[0], p[1]) for n, p in nodes.items()}
    faces = {name: ids for name, ids in sets.items() if name.startswith("Face")}
    bore = [name for name, ids in faces.items() if all(abs(radius[n] - 10) < 1e-3 for n in ids)]
    outer = [name for name, ids in faces.items() if all(abs(radius[n] - 20) < 1e-3 for n in ids)]
    ends = [name for name, ids in faces.items() if all(abs(nodes[n][2]) < 1e-9 or abs(nodes[n][2] - 10) < 1e-9
                                                       for n in ids)]
    assert len(bore) == 1 and len(outer) == 1 and len(ends) == 2, sorted(faces)
    # Every boundary node and mid node lies on its CAD surface within 1e-7 of the diagonal.
    for name, r in ((bore[0], 10), (outer[0], 20)):
        worst = max(abs(radius[n] - r) for n in faces[name])
        assert worst <= 1e-7 * diagonal, (name, worst)
    # No inverted (or flat) element: the Jacobian is positive at all ten nodes of every element.
    jac = tet10_min_jacobians(np, nodes, elements)
    assert (jac > 0).all(), int((jac <= 0).sum())
    end_nodes = sorted(set(faces[ends[0]]) | set(faces[ends[1]]))
    (tmp_path / "lame.inp").write_text(LAME_DECK.format(
        ends="\n".join(", ".join(map(str, end_nodes[k:k + 16])) for k in range(0, len(end_nodes), 16)),
        bore=bore[0]))
    run_ccx(tmp_path, "lame")
    u = node_displacements(tmp_path / "lame.dat")
    # Displacements of *NODE PRINT are in the global system; the radial part at each bore node.
    ur = [(ux * nodes[n][0] + uy * nodes[n][1]) / radius[n] for n, (ux, uy, _) in u.items()]
    E, nu, p, a, b = 210000.0, 0.3, 100.0, 10.0, 20.0
    lame = (1 + nu) * p * a * a / (E * (b * b - a * a)) * ((1 - 2 * nu) * a + b * b / a)
    mean = sum(ur) / len(ur)
    print(f"bore radial displacement: mean {mean:.6g}, min {min(ur):.6g}, max {max(ur):.6g}; Lame {lame:.6g}; "
          f"{len(nodes)} nodes")
    assert abs(mean - lame) <= TOLERANCE * lame
    assert max(abs(x - lame) for x in ur) <= 0.02 * lame


CAD_FILES = sorted(p.name for p in (SHARED_DIR / "data" / "cad").glob("*")) if (SHARED_DIR / "data" / "cad").exists() else []
# Files whose run is too long for every CI run. They run with QUALMESH_SLOW_TESTS=1. Measured (default size,
# --order 2, mesh + ccx): 918_pump 54 s and 1385_Laufrad 78 s, both pass (18.5k and 43k corner nodes; 2026-12-02);
# bottle.brep meshes in 22 s from its sized surface (235146 nodes; since 2026-12-05 the edge sagitta is measured
# from the chord, so its region seed fits its 0.6 wall; before, it fell back to the tessellation, whose mesh held a
# flat tetrahedron that ccx refused) and ccx solves it in 88 s (3.2 GB); U_Joint_2 meshes in 141 s (132531 nodes)
# and ccx solves it in 30 s
# (2026-12-03: with the relaxed rule kept under the split floor; before, the paper's rule took 276 s for 1517385 nodes
# and ccx refused a flat element). wrenchnut (28 s) and Zylkopf (its mesh took 20 min before the projection safety
# net, 8.5 s after) run in every CI run.
SLOW_CAD_FILES = {
    "U_Joint_2.stp": "mesh 141 s + ccx 30 s", "bottle.brep": "mesh 22 s + ccx 88 s (3.2 GB)",
    "1385_Laufrad_1000.stp": "78 s", "918_pump_carter_sup_21_03_2006.stp": "54 s",
}


@pytest.mark.parametrize("name", CAD_FILES)
def test_ccx_runs_the_second_order_deck_of_every_cad_file(run_qualmesh, tmp_path, name):
    require_tool("ccx")
    if name in SLOW_CAD_FILES and os.environ.get("QUALMESH_SLOW_TESTS") != "1":
        pytest.skip(f"{name}: {SLOW_CAD_FILES[name]} at the default size; set QUALMESH_SLOW_TESTS=1 to run it")
    mesh = tmp_path / "part.inp"
    result = run_qualmesh("mesh", SHARED_DIR / "data" / "cad" / name, "--order", "2", "-o", mesh)
    if result.returncode == 2:
        pytest.skip(f"{name} does not mesh (bad input, exit 2): {result.stderr.strip()[:300]}")
    assert result.returncode == 0, result.stderr
    names = re.findall(r"^\*NSET, NSET=(Face\d+)$", mesh.read_text(), flags=re.M)
    surfaces = re.findall(r"^\*SURFACE, NAME=(Face\d+), TYPE=ELEMENT$", mesh.read_text(), flags=re.M)
    assert names and surfaces
    numbers = sorted(int(n[4:]) for n in names)
    first, last = f"Face{numbers[0]}", f"Face{numbers[-1]}"
    assert last in surfaces
    (tmp_path / "deck.inp").write_text(f"""*INCLUDE, INPUT=part.inp
*MATERIAL, NAME=STEEL
*ELASTIC
210000., 0.3
*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL
*BOUNDARY
{first}, 1, 3, 0.
*STEP
*STATIC
*DSLOAD
{last}, P, 1.
*NODE FILE
U
*END STEP
""")
    run_ccx(tmp_path, "deck", timeout=1500)
    assert (tmp_path / "deck.frd").stat().st_size > 0
