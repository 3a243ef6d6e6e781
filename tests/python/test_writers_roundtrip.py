"""Every mesh writer's output read back by an independent reader: meshio (VTU, Gmsh 4.1, Medit, Abaqus, TetGen),
gmsh's own Python API for .msh, and CalculiX (`ccx`) running a small static analysis on the .inp. The mesh comes from
`tetgen -pq2A` on a two-region box (an internal facet at x = 1) and is converted with `qualmesh convert`; the figures
every reader must find (points, tets, volume per region, orientation) are computed here from TetGen's files."""
import os
import re
import shutil
import subprocess

import numpy as np
import pytest

from conftest import require_module, require_tool

# A 2 x 1 x 1 box cut by the internal facet x = 1 into region 1 (x < 1) and region 2 (x > 1). Facet markers 1..7.
BOX_POLY = """\
12 3 0 0
1 0 0 0
2 1 0 0
3 2 0 0
4 2 1 0
5 1 1 0
6 0 1 0
7 0 0 1
8 1 0 1
9 2 0 1
10 2 1 1
11 1 1 1
12 0 1 1
11 1
1 0 1
4 1 2 5 6
1 0 1
4 2 3 4 5
1 0 2
4 7 8 11 12
1 0 2
4 8 9 10 11
1 0 3
4 1 6 12 7
1 0 4
4 3 4 10 9
1 0 5
4 1 2 8 7
1 0 5
4 2 3 9 8
1 0 6
4 6 5 11 12
1 0 6
4 5 4 10 11
1 0 7
4 2 5 11 8
0
2
1 0.5 0.5 0.5 1 0.1
2 1.5 0.5 0.5 2 0.1
"""

EXTENSIONS = ("vtu", "msh", "mesh", "inp", "node")


def read_table(path):
    lines = [line.split("#", 1)[0].split() for line in open(path)]
    lines = [tokens for tokens in lines if tokens]
    return lines[0], lines[1:1 + int(lines[0][0])]


@pytest.fixture(scope="module")
def meshes(tmp_path_factory, qualmesh_exe):
    tetgen = require_tool("tetgen")
    work = tmp_path_factory.mktemp("writers")
    (work / "box.poly").write_text(BOX_POLY)
    done = subprocess.run([tetgen, "-pq2Aa0.01", "box.poly"], cwd=work, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stdout + done.stderr
    _, nodes = read_table(work / "box.1.node")
    first = int(nodes[0][0])
    points = np.array([[float(x) for x in row[1:4]] for row in nodes])
    _, eles = read_table(work / "box.1.ele")
    tets = np.array([[int(v) - first for v in row[1:5]] for row in eles])
    regions = np.array([int(float(row[5])) for row in eles])
    outputs = {}
    for ext in EXTENSIONS:
        out = work / f"out.{ext}"
        done = subprocess.run([qualmesh_exe, "convert", work / "box.1.ele", out], capture_output=True, text=True,
                              timeout=300)
        assert done.returncode == 0, f"convert to .{ext}: " + done.stdout + done.stderr
        outputs[ext] = out
    return {"work": work, "points": points, "tets": tets, "regions": regions, "outputs": outputs}


def volumes(points, tets):
    p = points[tets]
    return np.einsum("ij,ij->i", np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), p[:, 3] - p[:, 0]) / 6.0


def volume_by_region(points, tets, regions):
    v = volumes(points, tets)
    return {int(r): float(v[regions == r].sum()) for r in np.unique(regions)}


def test_tetgen_mesh_as_expected(meshes):
    v = volumes(meshes["points"], meshes["tets"])
    assert (v > 0).all()  # TetGen 1.5 writes positively oriented tetrahedra
    by_region = volume_by_region(meshes["points"], meshes["tets"], meshes["regions"])
    assert by_region == pytest.approx({1: 1.0, 2: 1.0}, rel=1e-12)


def meshio_tets(mesh):
    """Tetrahedra and their per-cell data of a meshio mesh, concatenated over the tetra blocks."""
    tets, data = [], {}
    for i, block in enumerate(mesh.cells):
        if block.type != "tetra":
            continue
        tets.append(block.data)
        for name, arrays in mesh.cell_data.items():
            data.setdefault(name, []).append(np.asarray(arrays[i]))
    return np.concatenate(tets), {name: np.concatenate(parts) for name, parts in data.items()}


@pytest.mark.parametrize("ext, region_key", [("vtu", "region"), ("msh", "gmsh:physical"), ("mesh", "medit:ref"),
                                             ("inp", None), ("node", None)])
def test_meshio_reads_back(meshes, ext, region_key):
    meshio = require_module("meshio")
    path = meshes["outputs"][ext]
    if ext == "node":
        path = path.with_suffix(".ele")
    mesh = meshio.read(str(path))
    assert len(mesh.points) == len(meshes["points"])
    np.testing.assert_array_equal(mesh.points, meshes["points"])  # coordinates written exactly
    tets, data = meshio_tets(mesh)
    assert len(tets) == len(meshes["tets"])
    v = volumes(mesh.points, tets)
    assert (v > 0).all(), f".{ext}: {int((v <= 0).sum())} tets not positively oriented"
    assert v.sum() == pytest.approx(2.0, rel=1e-12)
    if region_key is not None:
        regions = data[region_key].astype(int)
        assert volume_by_region(mesh.points, tets, regions) == pytest.approx({1: 1.0, 2: 1.0}, rel=1e-12)
    if ext == "inp":
        # One element set per region, holding that region's tetrahedra.
        names = {name for name in mesh.cell_sets}
        assert {"Solid1", "Solid2"} <= names, names
    if ext == "vtu":
        assert "min_dihedral_deg" in data and "radius_edge" in data
        assert data["min_dihedral_deg"].min() > 0 and np.isfinite(data["radius_edge"]).all()


def test_gmsh_api_reads_msh(meshes):
    gmsh = require_module("gmsh")
    gmsh.initialize()
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.open(str(meshes["outputs"]["msh"]))
        tags, nodes = gmsh.model.mesh.getElementsByType(4)
        assert len(tags) == len(meshes["tets"])
        node_tags, coords, _ = gmsh.model.mesh.getNodes()
        assert len(node_tags) == len(meshes["points"])
        names = {gmsh.model.getPhysicalName(dim, tag) for dim, tag in gmsh.model.getPhysicalGroups(3)}
        assert names == {"Solid1", "Solid2"}
        face_names = {gmsh.model.getPhysicalName(dim, tag) for dim, tag in gmsh.model.getPhysicalGroups(2)}
        assert {"Face1", "Face4", "Face7"} <= face_names, face_names
        # Volume of each physical region from gmsh's own element volumes... via its node coordinates.
        index = {int(t): i for i, t in enumerate(node_tags)}
        xyz = np.asarray(coords).reshape(-1, 3)
        tets = np.array([index[int(t)] for t in nodes]).reshape(-1, 4)
        assert volumes(xyz, tets).sum() == pytest.approx(2.0, rel=1e-12)
    finally:
        gmsh.finalize()


def test_calculix_runs_inp(meshes, tmp_path):
    ccx = require_tool("ccx")
    points = meshes["points"]
    inp = meshes["outputs"]["inp"].read_text()
    fixed = [str(i + 1) for i in np.flatnonzero(np.abs(points[:, 0]) < 1e-12)]
    assert fixed
    step = ["*MATERIAL, NAME=STEEL", "*ELASTIC", "210000., 0.3", "*DENSITY", "7.85e-9",
            "*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL", "*NSET, NSET=NFIX"]
    step += [", ".join(fixed[i:i + 16]) for i in range(0, len(fixed), 16)]
    # Pressure 1 on the end facet x = 2 (marker 4, area 1) through the element-face *SURFACE Face4: if the C3D4 face
    # numbering (S1..S4) is right, the supports at x = 0 react with a total force of exactly (1, 0, 0).
    step += ["*STEP", "*STATIC", "*BOUNDARY", "NFIX, 1, 3", "*DSLOAD", "Face4, P, 1.",
             "*NODE PRINT, NSET=NFIX, TOTALS=ONLY", "RF", "*END STEP", ""]
    (tmp_path / "job.inp").write_text(inp + "\n".join(step))
    done = subprocess.run([ccx, "-i", "job"], cwd=tmp_path, capture_output=True, text=True, timeout=600,
                          env={**os.environ, "OMP_NUM_THREADS": "1"})
    output = done.stdout + done.stderr
    assert done.returncode == 0, output[-3000:]
    assert "*ERROR" not in output, output[-3000:]
    assert "Job finished" in output, output[-3000:]
    dat = (tmp_path / "job.dat").read_text()
    match = re.search(r"total force \(fx,fy,fz\)[^\n]*\n\s*\n?\s*(\S+)\s+(\S+)\s+(\S+)", dat)
    assert match, dat[-2000:]
    force = [float(x) for x in match.groups()]
    assert force == pytest.approx([1.0, 0.0, 0.0], abs=1e-9), force
