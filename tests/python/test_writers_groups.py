"""Every group-carrying writer read back by an independent reader (issue 14).

examples/l_bracket.poly is meshed once per format, linear and second order (`--order 2`; skipped when the CLI lacks
it), and each file is read by a tool that is not QualMesh: meshio (vtu, msh, mesh, inp), the gmsh API (msh), CalculiX
(inp, run for real with a support on an Face<m> node set and a pressure on a Face<m> element surface) and FreeCAD's
Fem.read (unv, then FreeCAD's own .inp export read by meshio to check orientation). Checked: the group names Solid<r>
/ Face<m> / Edge<e> and their sizes, positive orientation, total volume, and that every mid-node lies at the midpoint
of the edge it claims (the bracket is polyhedral, so second-order mid-nodes are exact midpoints). The Elmer directory
has no independent reader on Debian bookworm (no ElmerGrid package): it is parsed here against the format spec.
"""
import os
import re
import subprocess

import numpy as np
import pytest

from conftest import SOURCE_DIR, require_module, require_tool

FORMATS = ["inp", "unv", "msh", "vtu", "mesh", "elmer"]
TET10_EDGES = [(0, 1), (1, 2), (0, 2), (0, 3), (1, 3), (2, 3)]  # VTK / C3D10 order of the mid-nodes 4..9


@pytest.fixture(scope="module", params=[1, 2], ids=["linear", "quadratic"])
def meshes(request, tmp_path_factory, qualmesh_exe):
    order = request.param
    work = tmp_path_factory.mktemp(f"groups{order}")
    poly = SOURCE_DIR / "examples" / "l_bracket.poly"
    if not poly.exists():
        pytest.skip(f"missing {poly}")
    outputs = {}
    for ext in FORMATS:
        out = work / f"bracket.{ext}"
        args = [qualmesh_exe, "mesh", str(poly), "-o", str(out), "--max-edge", "0.5"]
        if order == 2:
            args += ["--order", "2"]
        done = subprocess.run(args, capture_output=True, text=True, timeout=600)
        if order == 2 and done.returncode == 2 and "order" in done.stderr:
            pytest.skip("qualmesh mesh has no --order option yet")
        assert done.returncode == 0, done.stderr
        outputs[ext] = out
    return {"order": order, "work": work, "outputs": outputs}


def signed_volumes(points, tets):
    p = np.asarray(points)
    t = np.asarray(tets)
    a, b, c, d = (p[t[:, i]] for i in range(4))
    return np.einsum("ij,ij->i", np.cross(b - a, c - a), d - a) / 6.0


def max_mid_error(points, cells, edges):
    """Largest distance between a mid-node and the midpoint of the corners it claims."""
    p = np.asarray(points)
    c = np.asarray(cells)
    n = c.shape[1] - len(edges)
    return max(np.abs(p[c[:, n + k]] - (p[c[:, a]] + p[c[:, b]]) / 2).max() for k, (a, b) in enumerate(edges))


def meshio_blocks(mesh, kind):
    return [b for b in mesh.cells if b.type == kind]


@pytest.mark.parametrize("ext", ["vtu", "msh", "mesh", "inp"])
def test_meshio_reads_groups_and_mid_nodes(meshes, ext):
    meshio = require_module("meshio")
    order = meshes["order"]
    if ext == "mesh" and order == 2:
        pytest.skip("meshio 5 reads only linear Medit keywords (TetrahedraP2 is not among them)")
    mesh = meshio.read(str(meshes["outputs"][ext]))
    tet_type = "tetra10" if order == 2 else "tetra"
    tets = np.concatenate([b.data for b in meshio_blocks(mesh, tet_type)])
    v = signed_volumes(mesh.points, tets[:, :4])
    assert (v > 0).all(), f".{ext}: {int((v <= 0).sum())} tets not positive"
    assert v.sum() == pytest.approx(meshes.setdefault("volume", v.sum()), rel=1e-9)
    if order == 2:
        assert max_mid_error(mesh.points, tets, TET10_EDGES) < 1e-12
    if order == 2 and ext != "inp":  # an .inp deck's faces are element sides (*SURFACE), not elements
        tri = meshio_blocks(mesh, "triangle6")
        assert tri, f".{ext}: no triangle6 cells"
        assert max_mid_error(mesh.points, np.concatenate([b.data for b in tri]), [(0, 1), (1, 2), (2, 0)]) < 1e-12
    if ext == "vtu":
        i = [k for k, b in enumerate(mesh.cells) if b.type.startswith("triangle")]
        face_ids = np.concatenate([mesh.cell_data["face_id"][k] for k in i])
        assert face_ids.min() > 0
        assert len(np.unique(face_ids)) >= 8  # the L bracket has at least 8 facets
    if ext == "inp":
        assert "Solid1" in mesh.cell_sets or "SOLID1" in {k.upper() for k in mesh.cell_sets}, mesh.cell_sets.keys()
        face_sets = [k for k in mesh.point_sets if k.upper().startswith("FACE")]
        assert len(face_sets) >= 8, mesh.point_sets.keys()
    if ext == "msh":
        names = set(mesh.field_data)
        assert "Solid1" in names and sum(n.startswith("Face") for n in names) >= 8, names


def test_gmsh_api_reads_physical_groups(meshes):
    gmsh = require_module("gmsh")
    order = meshes["order"]
    gmsh.initialize()
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.open(str(meshes["outputs"]["msh"]))
        names = {dim: {gmsh.model.getPhysicalName(dim, tag) for d, tag in gmsh.model.getPhysicalGroups(dim)}
                 for dim in (1, 2, 3)}
        assert "Solid1" in names[3]
        assert len(names[2]) >= 8 and all(n.startswith("Face") for n in names[2])
        tet_type = 11 if order == 2 else 4
        node_tags, coords, _ = gmsh.model.mesh.getNodes()
        xyz = dict(zip(node_tags, np.asarray(coords).reshape(-1, 3)))
        _, nodes = gmsh.model.mesh.getElementsByType(tet_type)
        _, _, _, nn, local, _ = gmsh.model.mesh.getElementProperties(tet_type)
        local = np.asarray(local).reshape(nn, 3)
        cells = np.asarray(nodes).reshape(-1, nn)
        # Every node sits where Gmsh's own reference element puts it (local coordinates mapped by the corners).
        worst = 0.0
        for cell in cells[:200]:
            p = np.array([xyz[n] for n in cell])
            for k in range(nn):
                bary = np.concatenate([[1 - local[k].sum()], local[k]])
                worst = max(worst, np.abs(bary @ p[:4] - p[k]).max())
        assert worst < 1e-12
    finally:
        gmsh.finalize()


def test_calculix_runs_with_face_groups(meshes, tmp_path):
    ccx = require_tool("ccx")
    deck = meshes["outputs"]["inp"].read_text()
    faces = sorted({int(m) for m in re.findall(r"\*NSET, NSET=Face(\d+)\n", deck)})
    assert len(faces) >= 2
    fixed, loaded = faces[0], faces[-1]
    assert f"*SURFACE, NAME=Face{loaded}, TYPE=ELEMENT" in deck
    # Unit pressure on one facet; the supports on another react with the facet's force (a check of the S<k> sides).
    step = ["*MATERIAL, NAME=STEEL", "*ELASTIC", "210000., 0.3", "*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL",
            "*STEP", "*STATIC", "*BOUNDARY", f"Face{fixed}, 1, 3", "*DSLOAD", f"Face{loaded}, P, 1.",
            f"*NODE PRINT, NSET=Face{fixed}, TOTALS=ONLY", "RF", "*END STEP", ""]
    (tmp_path / "job.inp").write_text(deck + "\n".join(step))
    done = subprocess.run([ccx, "-i", "job"], cwd=tmp_path, capture_output=True, text=True, timeout=600,
                          env={**os.environ, "OMP_NUM_THREADS": "1"})
    output = done.stdout + done.stderr
    assert done.returncode == 0, output[-3000:]
    assert "*ERROR" not in output, output[-3000:]
    dat = (tmp_path / "job.dat").read_text()
    match = re.search(r"total force \(fx,fy,fz\)[^\n]*\n\s*\n?\s*(\S+)\s+(\S+)\s+(\S+)", dat)
    assert match, dat[-2000:]
    force = np.array([float(x) for x in match.groups()])
    assert np.linalg.norm(force) > 0  # the load reached the supports


FREECAD_SCRIPT = r"""
import sys
for p in ('/usr/lib/freecad-python3/lib', '/usr/lib/freecad/lib', '/usr/share/freecad/Mod/Fem'):
    sys.path.append(p)
import FreeCAD, Fem
m = Fem.read(sys.argv[1])
print('COUNTS', m.NodeCount, m.VolumeCount, m.FaceCount)
for g in m.Groups:
    print('GROUP', m.getGroupName(g), m.getGroupElementType(g), len(m.getGroupElements(g)))
m.write(sys.argv[2])
"""


def test_freecad_reads_unv_groups(meshes, tmp_path):
    python = "/usr/bin/python3"
    probe = subprocess.run([python, "-c", "import sys; sys.path += ['/usr/lib/freecad-python3/lib', "
                            "'/usr/lib/freecad/lib']; import FreeCAD, Fem"], capture_output=True, text=True)
    if probe.returncode != 0:
        pytest.skip("FreeCAD (package freecad) is not importable from /usr/bin/python3")
    meshio = require_module("meshio")
    script = tmp_path / "read_unv.py"
    script.write_text(FREECAD_SCRIPT)
    export = tmp_path / "freecad.inp"
    done = subprocess.run([python, str(script), str(meshes["outputs"]["unv"]), str(export)], capture_output=True,
                          text=True, timeout=600)
    assert done.returncode == 0, done.stderr[-3000:]
    groups = {}
    for line in done.stdout.splitlines():
        if line.startswith("GROUP"):
            _, name, kind, size = line.split()
            groups[name] = (kind, int(size))
    # Our own .unv says how many elements and nodes each group must have.
    ours = meshio.read(str(meshes["outputs"]["vtu"]))
    tri = [k for k, b in enumerate(ours.cells) if b.type.startswith("triangle")]
    face_ids = np.concatenate([ours.cell_data["face_id"][k] for k in tri])
    tet = [k for k, b in enumerate(ours.cells) if b.type.startswith("tetra")]
    regions = np.concatenate([ours.cell_data["region"][k] for k in tet])
    tri_cells = np.concatenate([ours.cells[k].data for k in tri])
    for label in np.unique(face_ids):
        assert groups.get(f"Face{label}") == ("Face", int((face_ids == label).sum())), groups
        nodes = np.unique(tri_cells[face_ids == label])  # mid-nodes included
        assert groups.get(f"Face{label}_Nodes") == ("Node", len(nodes)), groups
    for r in np.unique(regions):
        assert groups.get(f"Solid{max(r, 1)}") == ("Volume", int((regions == r).sum())), groups
    # FreeCAD's own C3D4 / C3D10 export of what it read: positive elements, mid-nodes at their edges' midpoints.
    back = meshio.read(str(export))
    kind = "tetra10" if meshes["order"] == 2 else "tetra"
    tets = np.concatenate([b.data for b in meshio_blocks(back, kind)])
    assert (signed_volumes(back.points, tets[:, :4]) > 0).all()
    if meshes["order"] == 2:
        assert max_mid_error(back.points, tets, TET10_EDGES) < 1e-9


def test_elmer_directory_matches_spec(meshes):
    d = meshes["outputs"]["elmer"]
    header = [line.split() for line in (d / "mesh.header").read_text().splitlines() if line.strip()]
    num_nodes, num_elements, num_boundary = map(int, header[0])
    types = {int(t): int(n) for t, n in header[2:2 + int(header[1][0])]}
    quadratic = meshes["order"] == 2
    assert types == {510 if quadratic else 504: num_elements, 306 if quadratic else 303: num_boundary}
    nodes = np.loadtxt(d / "mesh.nodes")
    assert nodes.shape == (num_nodes, 5) and (nodes[:, 0] == np.arange(1, num_nodes + 1)).all()
    xyz = nodes[:, 2:]
    elements = np.loadtxt(d / "mesh.elements", dtype=np.int64)
    assert elements.shape == (num_elements, 3 + (10 if quadratic else 4))
    cells = elements[:, 3:] - 1
    assert (signed_volumes(xyz, cells[:, :4]) > 0).all()
    if quadratic:
        assert max_mid_error(xyz, cells, TET10_EDGES) < 1e-12
    boundary = np.loadtxt(d / "mesh.boundary", dtype=np.int64)
    assert boundary.shape[0] == num_boundary and (boundary[:, 1] > 0).all() and (boundary[:, 2] >= 1).all()
    # Each boundary element's corners belong to its first parent.
    for row in boundary[:200]:
        parent = set(elements[row[2] - 1, 3:7])
        assert set(row[5:8]) <= parent
    names = (d / "mesh.names").read_text()
    assert names.startswith("! ----- names for bodies -----\n$ Solid1 = 1\n")
    assert "! ----- names for boundaries -----" in names
