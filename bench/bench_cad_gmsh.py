#!/usr/bin/python3
"""Side-by-side benchmark on CAD models: QualMesh against Gmsh on the same STEP/IGES/BREP file, in the same run.

Per model, three sizes: Gmsh's default (a tenth of the bounding-box diagonal, what Gmsh gives a CAD vertex without a
prescribed size), then 2x and 4x finer. At each size both meshers get matched parameters: `qualmesh mesh --size H
--curvature N` and `gmsh -3 -clmax H -clcurv N` (N elements per full circle, 12 by default, as QualMesh's default).
Reported for both, measured by one checker (`qualmesh check --json`, over ALL tetrahedra): nodes, tets, minimum
dihedral angle, tets below 10 and 15 degrees, whole-process wall time (file to mesh), and the volume error against
OpenCASCADE's volume of the solids (read from `qualmesh info`). A mesh file without tetrahedra counts as a failure
("N (no tets)", no ratios). For QualMesh's mesh also the largest distance of a boundary node from its CAD face and how
many nodes lie beyond the face's tolerance (`qualmesh check --ref MODEL`, through OpenCASCADE; Gmsh's face numbers
are its own, so its mesh is not measured). The second line, never the headline: the same checker's quality outside
the zones of the model's sharp features (CAD dihedral angles and face corners below 30 deg, found on the CAD geometry,
the same for both meshers; a tet is inside when a vertex lies within the size parameter H of one): min dihedral /
tets < 10 deg (share of tets in the zones). Not a test: timings are noisy, compare within one run only.

Usage: bench/bench_cad_gmsh.py [--qualmesh build/converters/qualmesh] [--timeout 600] [--curvature 12] [MODEL ...]
A MODEL is a path, or the name of a file in ../shared/data/cad; with none, every STEP, IGES and BREP file there.
"""
import argparse
import json
import re
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
CAD = ROOT.parent / "shared" / "data" / "cad"


def timed(cmd, cwd, timeout):
    start = time.perf_counter()
    try:
        proc = subprocess.run(cmd, cwd=cwd, capture_output=True, text=True, errors="replace", timeout=timeout)
    except subprocess.TimeoutExpired:
        proc = subprocess.CompletedProcess(cmd, 124, "", f"timed out after {timeout} s")
    return time.perf_counter() - start, proc


def judge(qualmesh, mesh, cwd, ref, size, distances=True):
    """`qualmesh check --json --ref MODEL` of a mesh: the volume, the quality outside the size parameter's distance
    from the CAD model's sharp features, and (`distances`) its boundary nodes measured against their CAD faces
    through OpenCASCADE (the report's "cad" entry; off for Gmsh, whose face numbers are its own)."""
    command = [qualmesh, "check", str(mesh), "--json", "--ref", str(ref), "--protection-radius", f"{size:.6g}"] + \
        ([] if distances else ["--no-cad-distance"])
    proc = subprocess.run(command, cwd=cwd, capture_output=True, text=True)
    try:
        return json.loads(proc.stdout)
    except json.JSONDecodeError:
        return None


def model_facts(qualmesh, model, cwd):
    """(bounding-box diagonal, OpenCASCADE volume of all solids, surface note) from `qualmesh info`."""
    proc = subprocess.run([qualmesh, "info", str(model)], cwd=cwd, capture_output=True, text=True)
    diag = re.search(r"diagonal ([0-9.eE+-]+)", proc.stdout)
    volumes = [float(v) for v in re.findall(r"Solid\d+: volume ([0-9.eE+-]+)", proc.stdout)]
    fallback = "tessellated" if "no sized surface mesh" in proc.stdout else "sized"
    return (float(diag.group(1)) if diag else None), (sum(volumes) if volumes else None), fallback


def fmt(x, spec):
    return format(x, spec) if isinstance(x, (int, float)) else "-"


def row(report, seconds, ok, cad_volume):
    if not ok or report is None:
        return ["failed", "-", "-", "-", "-", fmt(seconds, ".2f"), "-"]
    if not report.get("num_tets"):  # a mesh file without a tetrahedron (Gmsh on cube1000.igs) is no volume mesh
        return [fmt(report.get("num_points"), "d") + " (no tets)", "0", "-", "-", "-", fmt(seconds, ".2f"), "-"]
    error = abs(report["mesh_volume"] - cad_volume) / cad_volume if cad_volume else None
    return [fmt(report["num_points"], "d"), fmt(report["num_tets"], "d"), fmt(report["min_dihedral_deg"], ".2f"),
            fmt(report["num_tets_min_dihedral_below_10"], "d"), fmt(report["num_tets_min_dihedral_below_15"], "d"),
            fmt(seconds, ".2f"), fmt(error, ".2e")]


def off_cad(report):
    """The largest distance of a boundary node from its CAD face, and how many nodes are beyond the face's tolerance."""
    cad = (report or {}).get("cad")
    if not cad or not cad.get("distances_measured"):
        return "-"
    return f"{cad['max_distance']:.2g} ({cad['num_beyond_tolerance']} beyond)"


def outside_zones(report):
    """Quality farther than the size parameter from the sharp CAD features (dihedral or face-corner angles below 30
    deg): "min dihedral / tets < 10 deg (share of tets in the zones)"."""
    if not report or not report.get("num_tets") or not report.get("protection_checked"):
        return "-"
    share = report["num_tets_in_protection_zone"] / report["num_tets"]
    if report["num_tets_in_protection_zone"] == report["num_tets"]:
        return f"none outside ({share:.0%})"
    return (f"{report['min_dihedral_outside_protection_deg']:.2f} / "
            f"{report['num_tets_outside_protection_below_10']} ({share:.0%})")


def resolve_model(name):
    """A model given on the command line: a path, or a file name in ../shared/data/cad."""
    path = Path(name)
    if not path.exists() and (CAD / name).exists():
        path = CAD / name
    if not path.exists():
        sys.exit(f"{name}: no such file (neither a path nor a file of {CAD})")
    return path.resolve()


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--qualmesh", default=str(ROOT / "build" / "converters" / "qualmesh"))
    parser.add_argument("--timeout", type=int, default=600)
    parser.add_argument("--curvature", type=float, default=12)
    parser.add_argument("models", nargs="*")
    args = parser.parse_args()
    qualmesh = str(Path(args.qualmesh).resolve())
    if shutil.which("gmsh") is None:
        sys.exit("gmsh is not installed (apt-get install gmsh)")
    models = [resolve_model(m) for m in args.models] or sorted(
        p for p in CAD.iterdir() if p.suffix.lower() in (".step", ".stp", ".igs", ".iges", ".brep"))

    head = ["nodes", "tets", "min dih", "<10", "<15", "wall s", "vol err"]
    print("| model | size | surface | " + " | ".join("QM " + h for h in head) + " | "
          + " | ".join("Gmsh " + h for h in head) + " | nodes QM/Gmsh | time QM/Gmsh | QM node off CAD | "
          "QM outside zones | Gmsh outside zones |")
    print("|" + "---|" * (8 + 2 * len(head)))
    with tempfile.TemporaryDirectory() as tmp:
        for model in models:
            diag, cad_volume, surface = model_facts(qualmesh, model, tmp)
            if diag is None:
                print(f"| {model.name} | - | qualmesh info failed | " + " | ".join(["-"] * (2 * len(head) + 5)) + " |")
                continue
            for factor in (1, 2, 4):
                size = diag / 10 / factor
                qm_out, g_out = Path(tmp) / "qm.vtu", Path(tmp) / "gmsh.msh"
                t_q, q = timed([qualmesh, "mesh", str(model), "-o", str(qm_out), "--size", f"{size:.6g}",
                                "--curvature", f"{args.curvature:g}"], tmp, args.timeout)
                q_rep = judge(qualmesh, qm_out, tmp, model, size) if q.returncode == 0 else None
                t_g, g = timed(["gmsh", "-3", str(model), "-clmax", f"{size:.6g}", "-clcurv", f"{args.curvature:g}",
                                "-format", "msh41", "-o", str(g_out)], tmp, args.timeout)
                g_ok = g.returncode == 0 and g_out.exists()
                g_rep = judge(qualmesh, g_out, tmp, model, size, distances=False) if g_ok else None
                both = q_rep and g_rep and q_rep.get("num_tets") and g_rep.get("num_tets")
                ratio_n = fmt(q_rep["num_points"] / g_rep["num_points"], ".2f") if both else "-"
                ratio_t = fmt(t_q / t_g, ".2f") if both else "-"
                cells = [model.name, f"{size:.4g}", surface] + row(q_rep, t_q, q.returncode == 0, cad_volume) + \
                    row(g_rep, t_g, g_ok, cad_volume) + [ratio_n, ratio_t, off_cad(q_rep), outside_zones(q_rep),
                                                         outside_zones(g_rep)]
                print("| " + " | ".join(cells) + " |", flush=True)
                for f in (qm_out, g_out):
                    f.unlink(missing_ok=True)


if __name__ == "__main__":
    main()
