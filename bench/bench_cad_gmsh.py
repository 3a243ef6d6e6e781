#!/usr/bin/python3
"""Side-by-side benchmark on CAD models: QualMesh against Gmsh on the same STEP/IGES/BREP file, in the same run.

Per model: QualMesh's time to PLC (`qualmesh convert MODEL x.poly`: read, heal, tessellate) and to mesh
(`qualmesh mesh`), Gmsh's time to mesh (`gmsh -3`, default sizes), and for both meshes the tetrahedron count and the
minimum dihedral angle as `qualmesh check` measures them (one checker judges both). Not a test: timings are noisy,
compare within one run only.

Usage: bench/bench_cad_gmsh.py [--qualmesh build/converters/qualmesh] [--timeout 600] [MODEL ...]
"""
import argparse
import json
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
        proc = subprocess.run(cmd, cwd=cwd, capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        proc = subprocess.CompletedProcess(cmd, 124, "", f"timed out after {timeout} s")
    return time.perf_counter() - start, proc


def judge(qualmesh, mesh, cwd):
    proc = subprocess.run([qualmesh, "check", str(mesh), "--json"], cwd=cwd, capture_output=True, text=True)
    try:
        report = json.loads(proc.stdout)
    except json.JSONDecodeError:
        return None, None
    return report.get("num_tets"), report.get("min_dihedral_deg")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--qualmesh", default=str(ROOT / "build" / "converters" / "qualmesh"))
    parser.add_argument("--timeout", type=int, default=600)
    parser.add_argument("models", nargs="*")
    args = parser.parse_args()
    qualmesh = str(Path(args.qualmesh).resolve())
    if shutil.which("gmsh") is None:
        sys.exit("gmsh is not installed (apt-get install gmsh)")
    models = [Path(m).resolve() for m in args.models] or sorted(
        p for p in CAD.iterdir() if p.suffix.lower() in (".step", ".stp", ".igs", ".iges", ".brep"))

    print("| model | QM to PLC s | QM mesh s | QM tets | QM min dihedral | Gmsh s | Gmsh tets | Gmsh min dihedral "
          "| time ratio QM/Gmsh |")
    print("|---|---|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        for model in models:
            t_plc, conv = timed([qualmesh, "convert", str(model), "plc.poly"], tmp, args.timeout)
            qm_out = Path(tmp) / "qm.vtu"
            t_q, q = timed([qualmesh, "mesh", str(model), "-o", str(qm_out)], tmp, args.timeout)
            q_tets, q_dih = judge(qualmesh, qm_out, tmp) if q.returncode == 0 else (None, None)
            g_out = Path(tmp) / "gmsh.msh"
            t_g, g = timed(["gmsh", "-3", str(model), "-format", "msh41", "-o", str(g_out)], tmp, args.timeout)
            g_tets, g_dih = judge(qualmesh, g_out, tmp) if g.returncode == 0 and g_out.exists() else (None, None)

            def fmt(x, spec):
                return format(x, spec) if isinstance(x, (int, float)) else "-"
            q_time = fmt(t_q, ".2f") if q.returncode == 0 else f"failed ({q.returncode})"
            g_time = fmt(t_g, ".2f") if g.returncode == 0 else f"failed ({g.returncode})"
            ratio = fmt(t_q / t_g, ".2f") if q.returncode == 0 and g.returncode == 0 else "-"
            plc_time = fmt(t_plc, ".2f") if conv.returncode == 0 else f"failed ({conv.returncode})"
            print(f"| {model.name} | {plc_time} | {q_time} | {fmt(q_tets, 'd')} | {fmt(q_dih, '.2f')} | {g_time} | "
                  f"{fmt(g_tets, 'd')} | {fmt(g_dih, '.2f')} | {ratio} |", flush=True)
            for f in (qm_out, g_out):
                f.unlink(missing_ok=True)


if __name__ == "__main__":
    main()
