"""The FreeCAD addon in the GUI, under Xvfb (tests/freecad/fc_gui_checks.py in `freecad`): the FEM workbench shows
the QualMesh toolbar, the command opens the task panel, Apply meshes, Cancel stops a long run and keeps the
previous mesh, a document saved headless gets its view provider back. Screenshots are kept in the test's
temporary folder and copied to /tmp/qualmesh-screens/."""
import json
import shutil
import subprocess
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "freecad"))
import fcrunner  # noqa: E402

SCREEN_COPY = Path("/tmp/qualmesh-screens")
MAKE_DOCUMENT = """
import sys, traceback
try:
    import FreeCAD, qualmesh_fem
    doc = FreeCAD.newDocument("Headless")
    box = doc.addObject("Part::Box", "Box")
    doc.recompute()
    obj = qualmesh_fem.make_mesh_qualmesh(doc)
    obj.Part = box
    obj.CharacteristicLengthMax = 2.0
    result = qualmesh_fem.QualMeshTools(obj).create_mesh()
    assert result.succeeded, result.message
    doc.saveAs(%r)
except Exception:
    traceback.print_exc()
    sys.exit(1)
"""


def test_gui_toolbar_panel_apply_cancel(tmp_path, qualmesh_exe):
    freecad = fcrunner.require("freecad")
    xvfb = fcrunner.require("xvfb-run")
    fcrunner.require("import")
    headless_doc = tmp_path / "headless.FCStd"
    maker = tmp_path / "make_document.py"
    maker.write_text(MAKE_DOCUMENT % str(headless_doc))
    made = fcrunner.run_freecadcmd(maker, tmp_path, qualmesh_exe)
    assert made.returncode == 0, made.stdout[-2000:] + made.stderr[-2000:]

    screens = tmp_path / "screens"
    screens.mkdir()
    result = tmp_path / "gui.json"
    env = fcrunner.freecad_env(tmp_path, qualmesh_exe, QUALMESH_FC_SCREENS=screens, QUALMESH_FC_RESULT=result,
                               QUALMESH_FC_HEADLESS_DOC=headless_doc)
    proc = subprocess.run([xvfb, "-a", "-s", "-screen 0 1600x1000x24", freecad,
                           str(fcrunner.HERE / "fc_gui_checks.py")], cwd=tmp_path, env=env, capture_output=True,
                          text=True, timeout=240)
    SCREEN_COPY.mkdir(exist_ok=True)
    for png in screens.glob("*.png"):
        shutil.copy(png, SCREEN_COPY / png.name)
    facts = json.loads(result.read_text()) if result.exists() else {"errors": ["no result file"]}
    assert proc.returncode == 0 and not facts["errors"], (
        "".join(facts["errors"]) + proc.stdout[-2000:] + proc.stderr[-2000:])

    toolbar = facts["fem_toolbar"]
    assert toolbar["found"] and toolbar["visible"] and toolbar["enabled_with_selection"], toolbar
    assert toolbar["actions"] == ["FEM mesh from shape by QualMesh"], toolbar
    assert facts["panel"]["mesh_objects"] == 1 and facts["panel"]["open"] and facts["panel"]["in_analysis"]
    assert facts["apply"]["nodes"] > 300 and facts["apply"]["Nodes"] == facts["apply"]["nodes"]  # box at 5: 882 (C3D10)
    assert facts["apply"]["log_has_summary"] and facts["apply"]["progress"] == 100, facts["apply"]
    assert facts["long_run"]["children_before_cancel"] == 1, facts["long_run"]
    cancel = facts["cancel"]
    assert cancel["unchanged"] and cancel["log_says_cancelled"] and cancel["stopped_s"] < 10, cancel
    assert cancel["panel_still_open"], "the first Cancel stops the run, the panel stays"
    assert facts["panel_closed"], "the second Cancel closes the panel"
    assert facts["headless_doc"]["meshes"] == 1 and facts["headless_doc"]["view_provider"], facts["headless_doc"]
    own = facts["own_workbench"]
    assert own["active"] == "QualMeshWorkbench" and "FEM mesh from shape by QualMesh" in own["actions"], own
    assert len(facts["screens"]) >= 5, facts["steps"]
