"""`qualmesh check` on a mesh made by TetGen (`tetgen -pq2` on fandisk.off), compared with figures computed here
independently with numpy from the .node/.ele files: tet count, total volume, minimum dihedral angle (1e-9
relative). Then conformity to the input:
- TetGen 1.5.0 by default merges nearly coplanar adjacent facets (its -M switch turns that off) and remeshes them, so
  the boundary of the `-pq2` mesh leaves fandisk's surface by up to about 1.6e-5 of the bounding-box diagonal
  (about 1250 of its 19224 boundary faces are off the input at the default 1e-9 tolerance) and the volume differs by
  about 4e-7 relative. The checker must see that, and find the faces on the input at a 1e-4 tolerance.
- With `tetgen -pq2M` the mesh conforms exactly: volume and every facet's area agree to 1e-9, the check is ok."""
import json
import shutil
import subprocess

import numpy as np
import pytest

from conftest import require_tool, shared_file


def read_tetgen_table(path, columns):
    """Rows of a TetGen file (after the header line), comments dropped, as a list of token lists."""
    rows = []
    with open(path) as stream:
        lines = [line.split("#", 1)[0].split() for line in stream]
    lines = [tokens for tokens in lines if tokens]
    header, body = lines[0], lines[1:]
    count = int(header[0])
    assert len(body) >= count
    return header, [tokens[:columns] for tokens in body[:count]]


def load_tetgen_mesh(base):
    _, nodes = read_tetgen_table(f"{base}.node", 4)
    first = int(nodes[0][0])
    points = np.array([[float(x) for x in row[1:4]] for row in nodes])
    _, eles = read_tetgen_table(f"{base}.ele", 5)
    tets = np.array([[int(v) - first for v in row[1:5]] for row in eles], dtype=np.int64)
    return points, tets


def dihedral_angles_deg(points, tets):
    """All six interior dihedral angles of every tetrahedron, shape (n, 6)."""
    p = points[tets]
    angles = []
    for i, j, k, l in ((0, 1, 2, 3), (0, 2, 1, 3), (0, 3, 1, 2), (1, 2, 0, 3), (1, 3, 0, 2), (2, 3, 0, 1)):
        e = p[:, j] - p[:, i]
        u = p[:, k] - p[:, i]
        v = p[:, l] - p[:, i]
        n1 = np.cross(e, u)
        n2 = np.cross(e, v)
        # Angle between the two faces along e: between the components of u and v orthogonal to e.
        cos = np.einsum("ij,ij->i", n1, n2) / (np.linalg.norm(n1, axis=1) * np.linalg.norm(n2, axis=1))
        angles.append(np.degrees(np.arccos(np.clip(cos, -1.0, 1.0))))
    return np.stack(angles, axis=1)


def run_tetgen(tmp_path_factory, switches):
    tetgen = require_tool("tetgen")
    work = tmp_path_factory.mktemp("fandisk")
    shutil.copy(shared_file("data/plc/fandisk.off"), work / "fandisk.off")
    done = subprocess.run([tetgen, switches, "fandisk.off"], cwd=work, capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stdout + done.stderr
    return work


@pytest.fixture(scope="module")
def fandisk_mesh(tmp_path_factory):
    return run_tetgen(tmp_path_factory, "-pq2")


@pytest.fixture(scope="module")
def fandisk_mesh_unmerged(tmp_path_factory):
    return run_tetgen(tmp_path_factory, "-pq2M")


def test_check_agrees_with_numpy(fandisk_mesh, run_qualmesh):
    work = fandisk_mesh
    done = run_qualmesh("check", work / "fandisk.1.ele", "--ref", work / "fandisk.off", "--json")
    assert done.returncode in (0, 3), done.stdout + done.stderr
    report = json.loads(done.stdout)

    points, tets = load_tetgen_mesh(work / "fandisk.1")
    p = points[tets]
    volumes = np.einsum("ij,ij->i", np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), p[:, 3] - p[:, 0]) / 6.0
    min_dihedral = dihedral_angles_deg(points, tets).min()
    print(f"fandisk tetgen -pq2: qualmesh check: {report['num_tets']} tets, volume {report['mesh_volume']:.17g}, "
          f"min dihedral {report['min_dihedral_deg']:.17g} deg")
    print(f"                     numpy:          {len(tets)} tets, volume {volumes.sum():.17g}, "
          f"min dihedral {min_dihedral:.17g} deg")
    print(f"                     reference volume {report['reference_volume']:.17g}, "
          f"volume error {report['volume_relative_error']:.3g}, max facet area error "
          f"{report['max_facet_area_relative_error']:.3g}")

    assert report["num_tets"] == len(tets)
    assert report["num_points"] == len(points)
    assert report["mesh_volume"] == pytest.approx(volumes.sum(), rel=1e-9)
    assert report["min_dihedral_deg"] == pytest.approx(min_dihedral, rel=1e-9)
    # TetGen 1.5 writes positively oriented, properly matched tetrahedra.
    assert report["num_nonpositive_tets"] == int((volumes <= 0).sum()) == 0
    assert report["num_overshared_faces"] == 0
    assert report["num_folded_faces"] == 0


def check_json(run_qualmesh, work, *extra):
    done = run_qualmesh("check", work / "fandisk.1.ele", "--ref", work / "fandisk.off", "--json", *extra)
    assert done.returncode in (0, 3), done.stdout + done.stderr
    return done.returncode, json.loads(done.stdout)


def test_tetgen_default_mesh_nearly_conforms(fandisk_mesh, run_qualmesh):
    _, report = check_json(run_qualmesh, fandisk_mesh)
    assert report["has_reference"]
    assert report["reference_volume_method"].startswith("closed-shells")
    assert report["volume_relative_error"] < 1e-6
    # TetGen merged nearly coplanar facets: some faces are off the input at 1e-9, none at 1e-4.
    assert report["num_faces_off_input"] > 0
    assert not report["ok"]
    _, loose = check_json(run_qualmesh, fandisk_mesh, "--tolerance", "1e-4")
    assert loose["num_faces_off_input"] == 0
    assert loose["covered_area"] == pytest.approx(loose["facet_area"], rel=1e-6)


def test_tetgen_unmerged_mesh_conforms_exactly(fandisk_mesh_unmerged, run_qualmesh):
    code, report = check_json(run_qualmesh, fandisk_mesh_unmerged)
    print(f"fandisk tetgen -pq2M: volume error {report['volume_relative_error']:.3g}, max facet area error "
          f"{report['max_facet_area_relative_error']:.3g}")
    assert report["volume_relative_error"] < 1e-9
    assert report["num_faces_off_input"] == 0
    assert report["num_miscovered_facets"] == 0
    assert report["max_facet_area_relative_error"] < 1e-9
    assert report["covered_area"] == pytest.approx(report["facet_area"], rel=1e-9)
    assert report["ok"], report["problems"]
    assert code == 0
