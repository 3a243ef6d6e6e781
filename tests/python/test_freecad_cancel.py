"""The FreeCAD addon's failure paths headless (tests/freecad/fc_cancel_checks.py in freecadcmd): cancelling a long
run kills the process within seconds and leaves the mesh object as it was; the API raises typed errors."""
import json
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "freecad"))
import fcrunner  # noqa: E402


def test_cancel_and_refusals(tmp_path, qualmesh_exe):
    fcrunner.require("freecadcmd")
    result = tmp_path / "cancel.json"
    proc = fcrunner.run_freecadcmd(fcrunner.HERE / "fc_cancel_checks.py", tmp_path, qualmesh_exe,
                                   QUALMESH_FC_RESULT=result)
    facts = json.loads(result.read_text())
    assert proc.returncode == 0 and not facts["errors"], "".join(facts["errors"]) + proc.stderr[-2000:]
    assert facts["first"]["status"] == "succeeded"
    cancel = facts["cancel"]
    assert cancel["status"] == "cancelled" and cancel["unchanged"], cancel
    assert cancel["process_exit"] is not None, "the qualmesh process is gone"
    assert cancel["wall_s"] < 10, cancel
    assert facts["api_cancel"].startswith("cancelled"), facts["api_cancel"]
    assert facts["api_no_solid"].startswith("refused") and "no solid" in facts["api_no_solid"]
    region = facts["region"]
    assert region["status"] == "succeeded", region
    assert region["local_size_passed"] or any("MeshRegionList ignored (Face1=1.0)" in w
                                              for w in region["warnings"]), region
    readers = facts["readers"]
    assert readers["same_tets"] and readers["same_groups"] and readers["unv_edge_groups"] == 3, readers
    linear = facts["api_linear"]
    assert linear["nodes_per_tet"] == 4 and linear["volumes"] > 10 and linear["log_lines"] > 5, linear
