"""`qualmesh check MESH --ref MODEL.step`: quality outside a radius around the CAD model's sharp features (issue
15's goal: no tet below 10 degrees anywhere the CAD dihedral angles are 30 degrees or more).

The models are built here with Gmsh's OpenCASCADE kernel, so the features are known exactly:
 - a prism on a triangle with a 20-degree apex: its apex edge is the one sharp edge (20 deg; the others are 80 and
   90 deg) and its two apex corners the sharp vertices (20 deg between the cap's edges);
 - an L-shaped prism: every dihedral angle is 90 deg, but one, the notch's edge, is 270 deg (reflex).
The zone of the report is recomputed here from the mesh file alone (numpy): the tetrahedra with a vertex within the
radius of the sharp edge (whose ends are the sharp vertices), and the quality outside it.
"""
import json
import re

import pytest

from conftest import require_module

APEX_DEG = 20.0
LENGTH = 10.0
HEIGHT = 5.0


def build_prism(path, polygon, height):
    """A prism over the planar polygon `polygon` (xy corners), written by Gmsh's OpenCASCADE kernel to `path`."""
    gmsh = require_module("gmsh")
    gmsh.initialize(["-noenv"])
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add("prism")
        occ = gmsh.model.occ
        points = [occ.addPoint(x, y, 0) for x, y in polygon]
        lines = [occ.addLine(points[i], points[(i + 1) % len(points)]) for i in range(len(points))]
        surface = occ.addPlaneSurface([occ.addCurveLoop(lines)])
        occ.extrude([(2, surface)], 0, 0, height)
        occ.synchronize()
        gmsh.write(str(path))
    finally:
        gmsh.finalize()


def wedge_polygon():
    np = require_module("numpy")
    half = np.radians(APEX_DEG / 2)
    return [(0.0, 0.0), (LENGTH, -LENGTH * np.tan(half)), (LENGTH, LENGTH * np.tan(half))]


def check_json(run_qualmesh, mesh, ref, *extra):
    proc = run_qualmesh("check", mesh, "--ref", ref, "--json", *extra)
    assert proc.returncode in (0, 3), proc.stderr
    return json.loads(proc.stdout)


def min_dihedral_deg(points, tets):
    """Smallest dihedral angle of each tetrahedron (degrees), from the angle between the outward face normals."""
    np = require_module("numpy")
    p = points[tets]
    faces = [(1, 2, 3, 0), (0, 3, 2, 1), (0, 1, 3, 2), (0, 2, 1, 3)]
    normals = []
    for a, b, c, d in faces:
        n = np.cross(p[:, b] - p[:, a], p[:, c] - p[:, a])
        n /= np.linalg.norm(n, axis=1)[:, None]
        side = np.einsum("ij,ij->i", n, p[:, d] - p[:, a])
        normals.append(n * -np.sign(side)[:, None])  # outward: away from the opposite vertex
    angles = []
    for i in range(4):
        for j in range(i + 1, 4):
            cos = -np.einsum("ij,ij->i", normals[i], normals[j])
            angles.append(np.degrees(np.arccos(np.clip(cos, -1, 1))))
    return np.min(angles, axis=0)


def expected_zone(points, tets, near):
    """(tets inside, min dihedral outside, outside < 10, outside < 15): inside, a tet with a vertex flagged `near`."""
    np = require_module("numpy")
    inside = near[tets].any(axis=1)
    q = min_dihedral_deg(points, tets)[~inside]
    return int(inside.sum()), float(q.min()), int((q < 10).sum()), int((q < 15).sum())


def read_tets(path):
    meshio = require_module("meshio")
    m = meshio.read(path)
    return m.points.astype(float), m.cells_dict["tetra"]


@pytest.mark.parametrize("mesher", ["qualmesh", "gmsh"])
def test_wedge_zone_is_a_radius_around_its_sharp_edge(run_qualmesh, tmp_path, mesher):
    np = require_module("numpy")
    model = tmp_path / "wedge.step"
    build_prism(model, wedge_polygon(), HEIGHT)
    if mesher == "qualmesh":
        mesh = tmp_path / "wedge.vtu"
        proc = run_qualmesh("mesh", model, "--size", "1.5", "-o", mesh)
        assert proc.returncode == 0, proc.stderr
        # The summary's line: the same zone with --size as the radius.
        summary = re.search(r"cad zones:   farther than 1\.5 from the sharp CAD features \(angles < 30 deg: "
                            r"2 vertices, 1 edges; (\d+) of (\d+) tetrahedra inside\): min dihedral ([0-9.e+-]+) "
                            r"deg, (\d+)/(\d+) tetrahedra below 10/15 deg", proc.stdout)
        assert summary, proc.stdout
        distance = []
        report = check_json(run_qualmesh, mesh, model, "--protection-radius", "1")
        assert report["cad"]["distances_measured"] is True
        assert report["cad"]["num_beyond_tolerance"] == 0
    else:
        gmsh = require_module("gmsh")
        mesh = tmp_path / "wedge.msh"
        gmsh.initialize(["-noenv"])
        try:
            gmsh.option.setNumber("General.Terminal", 0)
            gmsh.open(str(model))
            gmsh.option.setNumber("Mesh.MeshSizeMax", 1.5)
            gmsh.model.mesh.generate(3)
            gmsh.write(str(mesh))
        finally:
            gmsh.finalize()
        # Gmsh numbers faces its own way: only the volume and the features are judged.
        distance = ["--no-cad-distance"]
        report = check_json(run_qualmesh, mesh, model, "--protection-radius", "1", *distance)
        assert report["cad"]["distances_measured"] is False
    assert report["protection_checked"] is True
    assert report["protection_zone"] == "cad_feature_balls"
    assert report["protection_angle_deg"] == 30
    assert report["protection_radius"] == 1
    assert report["num_sharp_segments"] == 1  # the apex edge; the others are 80 and 90 deg
    assert report["num_sharp_vertices"] == 2  # the apex corners of the two caps

    points, tets = read_tets(mesh)
    # Distance to the apex edge, the segment from (0, 0, 0) to (0, 0, HEIGHT).
    below_top = np.clip(points[:, 2], 0, HEIGHT)
    to_apex = np.sqrt(points[:, 0] ** 2 + points[:, 1] ** 2 + (points[:, 2] - below_top) ** 2)
    assert (to_apex <= 1e-9).sum() >= 3  # the edge is meshed, with its ends
    inside, min_out, below10, below15 = expected_zone(points, tets, to_apex <= 1)
    assert 0 < inside < len(tets)
    assert report["num_tets_in_protection_zone"] == inside
    assert report["min_dihedral_outside_protection_deg"] == pytest.approx(min_out, abs=1e-6)
    assert report["num_tets_outside_protection_below_10"] == below10
    assert report["num_tets_outside_protection_below_15"] == below15
    if mesher == "qualmesh":
        inside, min_out, below10, below15 = expected_zone(points, tets, to_apex <= 1.5)
        assert 0 < inside < len(tets)
        assert [int(summary.group(k)) for k in (1, 2, 4, 5)] == [inside, len(tets), below10, below15]
        assert float(summary.group(3)) == pytest.approx(min_out, rel=1e-3)  # printed with 4 digits

    # The default radius is the mesh's median edge length.
    default = check_json(run_qualmesh, mesh, model, *distance)
    edges = np.linalg.norm(points[tets[:, [0, 0, 0, 1, 1, 2]]] - points[tets[:, [1, 2, 3, 2, 3, 3]]], axis=2).ravel()
    median = np.sort(edges)[len(edges) // 2]
    assert default["protection_radius"] == pytest.approx(median, rel=1e-12)
    assert default["num_tets_in_protection_zone"] == expected_zone(points, tets, to_apex <= median)[0]

    # Below the apex angle nothing is sharp: the figures outside are those over all tetrahedra.
    blunt = check_json(run_qualmesh, mesh, model, "--protection-angle", "15", *distance)
    assert blunt["num_sharp_segments"] == 0 and blunt["num_sharp_vertices"] == 0
    assert blunt["num_tets_in_protection_zone"] == 0
    assert blunt["min_dihedral_outside_protection_deg"] == pytest.approx(blunt["min_dihedral_deg"], abs=1e-9)
    assert blunt["num_tets_outside_protection_below_15"] == blunt["num_tets_min_dihedral_below_15"]


def test_info_names_the_sharp_features(run_qualmesh, tmp_path):
    """`qualmesh info` lists the sharp features below 30 deg with the smallest of each kind: on the wedge, the two
    20-degree apex corners of its caps (the first at the origin) and its 20-degree apex edge; none on the L prism."""
    wedge, ell = tmp_path / "wedge.step", tmp_path / "ell.step"
    build_prism(wedge, wedge_polygon(), HEIGHT)
    build_prism(ell, [(0, 0), (4, 0), (4, 1), (1, 1), (1, 3), (0, 3)], 2.0)
    proc = run_qualmesh("info", wedge)
    assert proc.returncode == 0, proc.stderr
    assert re.search(r"sharp features below 30 deg: 2 face corners \(smallest 20\.00 deg at Vertex\d+ "
                     r"\((0|-?[0-9.e-]+), (0|-?[0-9.e-]+), (0|5)\)\), 1 edges \(smallest dihedral angle 20\.00 deg, "
                     r"along Edge\d+\)", proc.stdout), proc.stdout
    proc = run_qualmesh("info", ell)
    assert "sharp features below 30 deg: 0 face corners, 0 edges" in proc.stdout, proc.stdout


def test_reflex_edge_is_never_sharp(run_qualmesh, tmp_path):
    """An L-shaped prism: at a threshold of 100 deg its 5 convex vertical edges and 12 cap edges (90 deg) are sharp,
    the notch's vertical edge (270 deg, reflex) is not; every corner has two edges leaving it at 90 deg. At 30 deg
    nothing is sharp."""
    model = tmp_path / "ell.step"
    build_prism(model, [(0, 0), (4, 0), (4, 1), (1, 1), (1, 3), (0, 3)], 2.0)
    mesh = tmp_path / "ell.vtu"
    proc = run_qualmesh("mesh", model, "--size", "1", "-o", mesh)
    assert proc.returncode == 0, proc.stderr
    sharp = check_json(run_qualmesh, mesh, model, "--protection-angle", "100")
    assert sharp["num_sharp_segments"] == 17
    assert sharp["num_sharp_vertices"] == 12
    assert sharp["num_tets_in_protection_zone"] > 0
    blunt = check_json(run_qualmesh, mesh, model)
    assert blunt["num_sharp_segments"] == 0 and blunt["num_sharp_vertices"] == 0
    assert blunt["num_tets_in_protection_zone"] == 0


def test_plc_reference_keeps_its_balls_and_60_degrees(run_qualmesh, tmp_path):
    """A PLC reference is judged as before: protecting balls, 60 degrees by default."""
    poly = tmp_path / "cube.off"
    poly.write_text("OFF\n8 6 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n"
                    "4 0 3 2 1\n4 4 5 6 7\n4 0 1 5 4\n4 1 2 6 5\n4 2 3 7 6\n4 3 0 4 7\n")
    mesh = tmp_path / "cube.vtu"
    proc = run_qualmesh("mesh", poly, "-o", mesh)
    assert proc.returncode == 0, proc.stderr
    report = check_json(run_qualmesh, mesh, poly)
    assert report["protection_zone"] == "protecting_balls"
    assert report["protection_angle_deg"] == 60
