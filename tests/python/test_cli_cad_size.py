"""The CAD size options of `qualmesh mesh` (issue 15): range checks at parse time, a local size on an entity the model
does not have, node counts against Gmsh at matched size parameters (`--size H --curvature 12` against
`gmsh -3 -clmax H -clcurv 12`), and byte-identical output on two runs. Small inputs: well under 30 s in all."""
import re
import subprocess
from pathlib import Path

import pytest

from conftest import SOURCE_DIR, require_tool, shared_file

CYLINDER = SOURCE_DIR / "tests" / "data" / "cad" / "cylinder.brep"


@pytest.mark.parametrize("option", [
    ["--size", "0"], ["--size", "-1"], ["--size", "nan"], ["--size", "inf"], ["--min-size", "0"],
    ["--curvature", "-1"], ["--curvature", "1e9"], ["--gradation", "1"], ["--local-size", "Face0=1"],
    ["--local-size", "Face3"], ["--local-size", "Face3=0"], ["--local-size", "Vertex1=2"],
    ["--local-size", "Face3=abc"], ["--cad-surface", "coarse"]])
def test_bad_size_options_are_refused_at_parse_time(run_qualmesh, tmp_path, option):
    proc = run_qualmesh("mesh", CYLINDER, "-o", tmp_path / "m.vtu", *option)
    assert proc.returncode == 2, (option, proc.stdout, proc.stderr)
    assert not (tmp_path / "m.vtu").exists()


def test_a_local_size_on_a_face_the_model_lacks_is_refused_by_name(run_qualmesh, tmp_path):
    proc = run_qualmesh("mesh", CYLINDER, "-o", tmp_path / "m.vtu", "--local-size", "Face4=1")
    assert proc.returncode == 2, proc.stderr
    assert "Face4" in proc.stderr and "3 Faces" in proc.stderr, proc.stderr


def test_the_same_input_gives_byte_identical_output(run_qualmesh, tmp_path):
    outputs = []
    for run in range(2):
        out = tmp_path / f"m{run}.inp"
        proc = run_qualmesh("mesh", CYLINDER, "-o", out, "--size", "5")
        assert proc.returncode == 0, proc.stderr
        outputs.append(out.read_bytes())
    assert outputs[0] == outputs[1]


def qualmesh_nodes(run_qualmesh, model, size, tmp_path):
    proc = run_qualmesh("mesh", model, "-o", tmp_path / "q.vtu", "--size", size, "--curvature", 12)
    assert proc.returncode == 0, proc.stderr
    return int(re.search(r"output:\s+(\d+) vertices", proc.stdout).group(1))


def gmsh_nodes(model, size, tmp_path):
    gmsh = require_tool("gmsh")
    proc = subprocess.run([gmsh, "-3", str(model), "-clmax", str(size), "-clcurv", "12", "-o", str(tmp_path / "g.msh")],
                          capture_output=True, text=True, timeout=120)
    counts = re.findall(r"(\d+) nodes \d+ elements", proc.stdout)
    assert counts, proc.stdout[-2000:]
    return int(counts[-1])


# Measured (2026-12-03, planar faces meshed at the size with their nodes in the facet): the cylinder at 5 gives 202
# nodes against Gmsh's 273 (0.74x; 176, 0.64x, before, when its planar caps were left to the volume mesher), and
# part.step at 10 gives 2189 against 1298 (1.69x; was 1.98x): 426 Steiner points, mostly Rule 1 splits where its
# fillets meet planes at about 3 deg, input angles the engine protects. Issue 15. Since 2026-12-06 (curved faces
# remeshed without holding the nodes next to their border) the cylinder gives 192 (0.70x: Gmsh's lateral face has
# edges of 0.75 of -clmax on average, ours 0.86) and part.step 2178 (1.68x).
@pytest.mark.parametrize("model,size", [("cylinder", 5), pytest.param(
    "part.step", 10, marks=pytest.mark.xfail(strict=True, reason="part.step at 10: 1.69x Gmsh's nodes (issue 15)"))])
def test_node_count_within_30_percent_of_gmsh_at_matched_sizes(run_qualmesh, tmp_path, model, size):
    path = CYLINDER if model == "cylinder" else shared_file("data/cad/part.step")
    ours, theirs = qualmesh_nodes(run_qualmesh, path, size, tmp_path), gmsh_nodes(path, size, tmp_path)
    print(f"{model} at {size}: qualmesh {ours} nodes, gmsh {theirs}")
    assert 0.7 <= ours / theirs <= 1.3, (ours, theirs)
