"""Issue 3, determinism: the same input and options give byte-identical output across separate processes
(VTU and TetGen files), with pumping (the default) and without."""
import pytest

from conftest import shared_file


@pytest.mark.parametrize("pump", [True, False], ids=["pumped", "no-pump"])
def test_two_runs_write_identical_bytes(run_qualmesh, tmp_path, pump):
    model = shared_file("data/plc/joint.off")
    outputs = []
    for run in ("a", "b"):
        out = tmp_path / f"{run}.vtu"
        args = ["mesh", model, "-o", out] + ([] if pump else ["--no-pump"])
        proc = run_qualmesh(*args, timeout=600)
        assert proc.returncode == 0, proc.stderr
        outputs.append(out.read_bytes())
    assert len(outputs[0]) > 100_000
    assert outputs[0] == outputs[1]
