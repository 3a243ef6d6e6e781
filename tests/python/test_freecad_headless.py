"""The FreeCAD FEM addon (freecad_module/) headless, through `freecadcmd`: mesh object, tool, CalculiX chain.

Each case runs tests/freecad/fc_model_checks.py in its own freecadcmd (a temporary HOME holds the addon link) and
asserts the facts it writes: the mesh is made and its statistics agree with it; every node group Face<i> is
exactly what FEM's geometric search `getNodesByFace` finds on FreeCAD's Face<i> (planar faces), or at least a
superset of it (curved faces and their neighbours: see test_faces_every_node_on_the_surface); every FEM constraint
on a face finds our group's nodes; FreeCAD's CalculiX writer writes a C3D10 deck that ccx solves; save and reopen keep
mesh, groups, proxy and statistics; a failing run leaves the document exactly as it was.
"""
import math
import subprocess
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "freecad"))
import fcrunner  # noqa: E402

from conftest import shared_file  # noqa: E402

CASES = {
    # case: (max size mm, input relative to ../shared or None)
    "box": (5.0, None),
    "cylinder": (2.0, None),
    "step": (10.0, "data/cad/part.step"),
    "stacked_beam": (4.0, "data/cad/fcFEM_Stacked_Beam_Example.FCStd"),
}
_facts = {}


def facts_of(case, tmp_path_factory, qualmesh_exe):
    """Run the checks of one case once per session (several tests read them)."""
    if case not in _facts:
        fcrunner.require("freecadcmd")
        fcrunner.require("ccx")
        max_size, relative = CASES[case]
        extra = {"QUALMESH_FC_MAX_SIZE": max_size}
        if relative:
            extra["QUALMESH_FC_INPUT"] = shared_file(relative)
        tmp = tmp_path_factory.mktemp("fc_" + case)
        if case == "box":
            # The same model meshed by the CLI as .unv, for FreeCAD's own UNV import to compare with.
            freecad_script = tmp / "export_box.py"
            freecad_script.write_text(
                "import sys\ntry:\n    import Part\n    Part.makeBox(100, 10, 10).exportBrep(%r)\n"
                "except Exception:\n    sys.exit(1)\n" % str(tmp / "box.brep"))
            assert fcrunner.run_freecadcmd(freecad_script, tmp, qualmesh_exe).returncode == 0
            subprocess.run([qualmesh_exe, "mesh", str(tmp / "box.brep"), "--order", "2", "--size",
                            str(max_size), "-o", str(tmp / "box.unv")], check=True, capture_output=True)
            extra["QUALMESH_FC_UNV"] = tmp / "box.unv"
        _facts[case] = fcrunner.run_checks(case, tmp, qualmesh_exe, **extra)
    return _facts[case]


@pytest.fixture(params=sorted(CASES))
def facts(request, tmp_path_factory, qualmesh_exe):
    return facts_of(request.param, tmp_path_factory, qualmesh_exe)


def test_mesh_is_created_with_groups_and_statistics(facts):
    create, mesh, shape = facts["create"], facts["mesh"], facts["shape"]
    assert create["status"] == "succeeded", create["message"]
    assert mesh["proxy_type"] == "QualMesh::FemMeshQualMesh"
    # (box 100 x 10 x 10 at 5: 405 tets, 164 corner nodes; Gmsh -clmax 5: 190 nodes)
    assert mesh["volumes"] == mesh["tetra"] == create["statistics"]["tetrahedra"] > 100
    assert mesh["nodes"] == create["statistics"]["nodes"]
    assert mesh["orientation"]["positive"] == 0, "SMESH's tetrahedra are negatively oriented"
    stats = mesh["object_stats"]
    assert stats["Nodes"] == mesh["nodes"] and stats["Tetrahedra"] == mesh["volumes"]
    assert 0.0 < stats["MinDihedralAngle"] < 70.53
    assert stats["TetsBelow10Deg"] == create["statistics"]["tets_below_10_deg"]
    names = {(name, kind) for name, kind, _ in mesh["groups"]}
    for i in range(1, shape["faces"] + 1):
        assert (f"Face{i}", "Node") in names and (f"Face{i}", "Face") in names
    for i in range(1, shape["edges"] + 1):
        assert (f"Edge{i}", "Node") in names
    for i in range(1, shape["solids"] + 1):
        assert (f"Solid{i}", "Volume") in names
    volume_total = sum(n for name, kind, n in mesh["groups"] if kind == "Volume")
    assert volume_total == mesh["volumes"], "every tetrahedron in exactly one Solid<i>"


def test_face_groups_hold_everything_getNodesByFace_finds(facts):
    # Nothing FEM finds on FreeCAD's Face<i> is outside our Face<i>: the names are FreeCAD's.
    wrong = [f for f in facts["faces"] if f["extra"] or f["ours"] == 0]
    assert not wrong, wrong


@pytest.mark.parametrize("case", ["box", "cylinder", "stacked_beam", "step"])
def test_planar_face_groups_are_exactly_what_getNodesByFace_finds(case, tmp_path_factory, qualmesh_exe):
    planar = [f for f in facts_of(case, tmp_path_factory, qualmesh_exe)["faces"] if f["planar"]]
    assert planar
    wrong = [f for f in planar if f["missing"] or f["extra"]]
    assert not wrong, wrong


def test_straight_edge_groups_are_what_getNodesByEdge_finds(facts):
    straight = [e for e in facts["edges"] if e["curve"] == "Line"]
    assert not [e for e in straight if e["missing"] or e["extra"]], straight
    assert not [e for e in facts["edges"] if e["extra"]], "an edge group names another edge's nodes"


def test_every_face_constraint_finds_our_face_group(facts):
    constraints = facts["constraints"]
    assert constraints, "each case has at least one constraint on a face"
    for c in constraints:
        assert c["part_face"], c
        assert c["extra"] == 0, c
        assert c["missing"] == 0 and c["found"] == c["ours"] > 0, c  # curved faces too (the step case's load)


def test_freecad_calculix_writer_and_ccx(facts):
    ccx = facts["ccx"]
    assert ccx["deck_has_c3d10"] and ccx["frd"] and ccx["results"] >= 1, ccx


def test_save_and_reopen_keeps_mesh_groups_and_statistics(facts):
    reopen = facts["reopen"]
    assert reopen["same_groups"] and reopen["same_counts"] and reopen["same_tets"], reopen
    assert reopen["proxy_type"] == "QualMesh::FemMeshQualMesh" and reopen["in_analysis"], reopen
    before, after = facts["mesh"]["object_stats"], reopen["stats"]
    assert before["Nodes"] == after["Nodes"] and before["TetsBelow10Deg"] == after["TetsBelow10Deg"]
    assert math.isclose(before["MinDihedralAngle"], after["MinDihedralAngle"], rel_tol=1e-6)


def test_failed_run_leaves_the_document_unchanged(facts):
    for how, outcome in facts["failures"].items():
        assert outcome["status"] == "failed" and outcome["message"], (how, outcome)
        assert outcome["unchanged"], (how, outcome)


def test_same_mesh_as_freecads_own_unv_import(tmp_path_factory, qualmesh_exe):
    compare = facts_of("box", tmp_path_factory, qualmesh_exe)["unv_compare"]
    assert compare["same_tets"] and compare["ours"] == compare["unv"], compare
    assert compare["same_face_node_groups"], compare


def test_cylinder_edges_get_freecads_names(tmp_path_factory, qualmesh_exe):
    # Part::Cylinder: qualmesh numbers the two circles the other way round; the tool renames the groups.
    facts = facts_of("cylinder", tmp_path_factory, qualmesh_exe)
    assert not [e for e in facts["edges"] if e["missing"] or e["extra"]], facts["edges"]


def test_two_solids_get_their_groups(tmp_path_factory, qualmesh_exe):
    facts = facts_of("stacked_beam", tmp_path_factory, qualmesh_exe)
    volumes = {name: n for name, kind, n in facts["mesh"]["groups"] if kind == "Volume"}
    assert set(volumes) == {"Solid1", "Solid2"} and all(n > 0 for n in volumes.values()), volumes
    assert facts["constraints"][0]["reference"] == "Box001.Face6"


# Every node of every Face<i>, mid nodes included, is on its CAD face, and FreeCAD's search finds it wherever the
# face's bounding box, where getNodesByFace starts, holds it: the sized CAD surface puts corner nodes on the face,
# and a mid node that cannot reach the projection of its edge's midpoint without spoiling an element, or whose target
# is outside that box, goes elsewhere along its edge on the surface (qualmesh's `curving:` line). part.step's Face23
# (a surface of extrusion) bulges 0.007 mm past its box in a band along an edge, where no place is findable: one mid
# node of 12737 lies there at --size 10 (measured 2026-12-04; 0 before the sized surface stopped splitting edges),
# on the surface to 1e-20 mm. The cylinder misses none.
@pytest.mark.parametrize("case", ["cylinder", "step"])
def test_faces_every_node_on_the_surface(case, tmp_path_factory, qualmesh_exe):
    facts = facts_of(case, tmp_path_factory, qualmesh_exe)
    missing = {f["name"]: (f["missing"], f["missing_outside_box"], f["missing_max_distance"])
               for f in facts["faces"] if f["missing"]}
    print(case, "nodes getNodesByFace misses (count, outside the face's box, largest distance):", missing)
    for name, (count, outside, distance) in missing.items():
        assert outside == count and distance < 1e-6, (name, count, outside, distance)
    assert sum(count for count, _, _ in missing.values()) <= (0 if case == "cylinder" else 2), missing
