"""examples/freecad_headless.py, the whole FEM chain in freecadcmd: STEP -> QualMesh C3D10 mesh object in an
analysis -> FreeCAD's CalculiX writer -> ccx -> mean tip deflection of the 100 x 10 x 10 mm steel cantilever under
1000 N, against the converged 1.906 mm (Euler-Bernoulli 1.905 mm)."""
import json
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "freecad"))
import fcrunner  # noqa: E402

CONVERGED_MM = 1.906


def test_cantilever_tip_deflection_through_freecad(tmp_path, qualmesh_exe):
    fcrunner.require("freecadcmd")
    fcrunner.require("ccx")
    example = fcrunner.SOURCE_DIR / "examples" / "freecad_headless.py"
    result = tmp_path / "figures.json"
    proc = fcrunner.run_freecadcmd(example, tmp_path, qualmesh_exe, QUALMESH_EXAMPLE_MAX_SIZE=5,
                                   QUALMESH_EXAMPLE_WORKDIR=tmp_path / "work", QUALMESH_EXAMPLE_RESULT=result)
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]
    figures = json.loads(result.read_text())
    assert "mean tip deflection" in proc.stdout
    assert figures["tip_nodes"] > 20, figures
    assert abs(figures["mean_tip_deflection_mm"] - CONVERGED_MM) <= 0.005 * CONVERGED_MM, figures
    assert (tmp_path / "work" / "cantilever.FCStd").exists()
