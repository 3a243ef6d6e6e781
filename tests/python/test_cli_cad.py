"""End-to-end: CAD and OpenSCAD inputs through the `qualmesh` command line (issue 5's CLI part).

`qualmesh info MODEL` must list solids, faces, edges, the validation result and the input angles; a model that
cannot be read is refused with exit code 2 and a message naming the file; `qualmesh mesh MODEL -o deck.inp` writes a
CalculiX deck with one ELSET per solid, read back by meshio.
"""
import json
import os
import re
import subprocess
from pathlib import Path

import pytest

from conftest import require_module, shared_file


def test_info_step_lists_solids_faces_edges_and_angles(run_qualmesh):
    step = shared_file("data/cad/part.step")
    proc = run_qualmesh("info", step)
    assert proc.returncode == 0, proc.stderr
    out = proc.stdout
    # MANIFEST: part.step has 1 solid, 26 faces, 70 edges, 46 vertices.
    assert "STEP model: 1 solids, 26 faces, 70 edges, 46 vertices" in out
    assert "validation:   ok" in out
    assert "closed:       yes" in out
    m = re.search(r"facet-facet\s+min\s+([0-9.]+) deg", out)
    assert m, out
    # MANIFEST: min feature dihedral of part.step is 84.5 deg (approximate, from a coarse tessellation).
    assert 80.0 < float(m.group(1)) <= 90.0


def test_info_two_solids_become_two_regions(run_qualmesh):
    beam = shared_file("data/cad/fcFEM_Stacked_Beam_Example.FCStd")
    proc = run_qualmesh("info", beam)
    assert proc.returncode == 0, proc.stderr
    assert "2 solids" in proc.stdout
    assert re.search(r"regions:\s+2 seeds", proc.stdout), proc.stdout


def test_garbage_step_is_refused_with_exit_code_2(run_qualmesh, tmp_path):
    bad = tmp_path / "broken.step"
    bad.write_text("ISO-10303-21;\nHEADER;\nthis is not STEP\n")
    proc = run_qualmesh("info", bad)
    assert proc.returncode == 2
    assert "broken.step" in proc.stderr and "error[" in proc.stderr


def test_mesh_fcstd_writes_calculix_deck_with_one_elset_per_solid(run_qualmesh, tmp_path):
    meshio = require_module("meshio")
    beam = shared_file("data/cad/fcFEM_Stacked_Beam_Example.FCStd")
    deck = tmp_path / "beam.inp"
    proc = run_qualmesh("mesh", beam, "-o", deck)
    assert proc.returncode == 0, proc.stderr
    text = deck.read_text()
    assert "ELSET=Solid1" in text and "ELSET=Solid2" in text
    mesh = meshio.read(deck, file_format="abaqus")
    tets = sum(len(block.data) for block in mesh.cells if block.type == "tetra")
    m = re.search(r"output:\s+(\d+) vertices \(\d+ Steiner\), (\d+) tetrahedra", proc.stdout)
    assert m, proc.stdout
    assert tets == int(m.group(2))
    assert len(mesh.points) == int(m.group(1))


def test_mesh_step_conforms_to_its_cad_model(run_qualmesh, tmp_path):
    """`check --ref part.step` judges the mesh against the CAD model: every boundary node within its face's
    tolerance (measured by OpenCASCADE), and at --size 5 the volume closer to the CAD volume (360939.79) than the old
    default tessellation's chordal volume (360555, 1.07e-3 low): every surface node is on the CAD surface, and the
    volume refinement's boundary nodes are moved onto it (measured 2.2e-4 at 5.3; 1.6e-3 at the default size 21.3,
    where Gmsh's default mesh is 6.4e-3 off)."""
    step = shared_file("data/cad/part.step")
    out = tmp_path / "part.vtu"
    proc = run_qualmesh("mesh", step, "-o", out, "--size", 5, timeout=600)
    assert proc.returncode == 0, proc.stderr
    check = run_qualmesh("check", out, "--ref", step, "--json")
    report = json.loads(check.stdout)
    assert report["num_tets"] > 1000
    assert report["num_nonpositive_tets"] == 0
    assert report["cad"]["num_nodes"] > 1000
    assert report["cad"]["num_beyond_tolerance"] == 0
    assert report["cad"]["volume_relative_error"] < 0.6e-3
    assert check.returncode == 0, check.stdout[:2000]


def test_cad_meshing_keeps_the_relaxed_rule_under_the_split_floor(run_qualmesh, tmp_path):
    """Under the split floor the CLI gives CAD inputs, Steiner mode has no conflict-zone budget (scheduler.cpp):
    Kurbelwelle.stp at --size 1.707 gave it up before (zones of 1529 cells on average) and was meshed again without
    the projection onto the CAD surface; now it keeps both (measured 12 s, 4832 nodes, against 10.7 s and 4742). The
    mesh still conforms to the CAD model."""
    step = shared_file("data/cad/Kurbelwelle.stp")
    out = tmp_path / "k.vtu"
    proc = run_qualmesh("mesh", step, "-o", out, "--size", 1.707, "-v", timeout=600)
    assert proc.returncode == 0, proc.stderr
    assert "gave up" not in proc.stderr and "meshing again" not in proc.stderr, proc.stderr[-3000:]
    assert "projection:" not in proc.stdout and "encroaching:" not in proc.stdout, proc.stdout
    check = run_qualmesh("check", out, "--ref", step, "--json")
    report = json.loads(check.stdout)
    assert report["num_nonpositive_tets"] == 0
    assert report["cad"]["num_beyond_tolerance"] == 0
    assert check.returncode == 0, check.stdout[:2000]


def test_bottle_coarser_than_itself_meshes_with_every_node_on_its_cad_face(run_qualmesh, tmp_path):
    """bottle.brep at --size 80 (coarser than the bottle): the sized surface keeps the thread's sliver facets (0.9 deg
    at (7.445, -0.904, 53.726)). Session 33: Rules 1-2 split there down to 1e-15, a point fell on a vertex of a
    facet's 2D triangulation, QualMesh overwrote that vertex's id and CGAL crashed (exit 139). Session 34: the point
    was refused and the run stopped at the limit of double precision (exit 4, error[precision], nothing written;
    Levels.FacetPointOnATwoDimensionalVertexIsRefusedAndStopsRefinement keeps that mechanism under test). Session 35:
    the curved faces' triangles are flipped to locally Delaunay edges (face_remesh.cpp), the cascade no longer starts,
    and the bottle meshes at every size tried (40 to 200): exit 0 with the relaxed rule, no fallback, and every
    boundary node within its face's tolerance."""
    bottle = shared_file("data/cad/bottle.brep")
    out = tmp_path / "bottle.vtu"
    proc = run_qualmesh("mesh", bottle, "-o", out, "--size", 80, "-v", timeout=600)
    assert proc.returncode == 0, (proc.returncode, proc.stderr[-3000:])
    assert "meshing again" not in proc.stderr and "precision" not in proc.stderr, proc.stderr[-3000:]
    check = run_qualmesh("check", out, "--ref", bottle, "--json")
    report = json.loads(check.stdout)
    assert report["num_tets"] > 1000
    assert report["num_nonpositive_tets"] == 0
    assert report["cad"]["num_beyond_tolerance"] == 0, report["cad"]
    assert check.returncode == 0, check.stdout[:2000]


@pytest.mark.parametrize("plugin_kind", ["missing", "not-a-library"])
def test_unloadable_cad_plugin_is_refused_with_exit_code_2_naming_its_path(qualmesh_exe, tmp_path, plugin_kind):
    """The CLI dlopens its CAD front end on the first CAD input, from $QUALMESH_CAD_PLUGIN when set (nowhere else).
    A plugin that is missing or does not load is bad usage: exit code 2, and the message names the plugin's path,
    the model file and what to do; it is never an internal error or a crash."""
    if not (Path(qualmesh_exe).parent / "libqualmesh_cad_plugin.so").exists():
        pytest.skip("this qualmesh was built without the CAD front end")
    plugin = tmp_path / "plugin" / "libqualmesh_cad_plugin.so"
    if plugin_kind == "not-a-library":
        plugin.parent.mkdir()
        plugin.write_text("not an ELF shared object\n")
    model = tmp_path / "model.step"  # a regular file (a missing one is refused first); the plugin fails before
    model.write_text("ISO-10303-21;\n")  # the model is read
    env = dict(os.environ, QUALMESH_CAD_PLUGIN=str(plugin))
    proc = subprocess.run([qualmesh_exe, "info", str(model)], capture_output=True, text=True, env=env, timeout=120)
    assert proc.returncode == 2, proc.stderr
    assert str(plugin) in proc.stderr
    assert str(model) in proc.stderr and "error[unsupported]" in proc.stderr
    assert "CAD front end (OpenCASCADE) is not available" in proc.stderr
    assert "libocct-data-exchange-dev" in proc.stderr
    assert "internal error" not in proc.stderr
