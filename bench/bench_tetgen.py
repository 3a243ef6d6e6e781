#!/usr/bin/python3
"""Side-by-side benchmark: QualMesh `mesh` against `tetgen -pq2` on the same PLC, in the same run.

TetGen runs as `tetgen -pq2aA`: `-a` (no number) and `-A` make it honour the regions' maximum volumes of a .poly
(example.poly: 0.001 and 0.01), which QualMesh always honours; without them TetGen ignores those constraints and
meshes example.poly with 209 vertices instead of 6424. On inputs without region constraints the two are identical.

Both tools get the very same input: each model is first converted by `qualmesh convert` to a TetGen .poly (so
TetGen also reads binary STL and sees the same merged polygonal facets). Reported per model: wall time (best of
--repeat runs) and output vertex and tetrahedron counts, and the ratios QualMesh / TetGen. Not a test: timings on a
shared machine are noisy, which is why only ratios from one run are compared.

Usage: bench/bench_tetgen.py [--qualmesh build/converters/qualmesh] [--repeat 3] [--qualmesh-arg=--no-pump] [MODEL ...]
Default models: the closed, valid files of ../shared/data/plc/ plus examples/l_bracket.poly.
"""
import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SHARED = ROOT.parent / "shared" / "data" / "plc"
DEFAULT_MODELS = [ROOT / "examples" / "l_bracket.poly"] + [SHARED / n for n in (
    "example.poly", "joint.off", "anchor.off", "couplingdown.off", "elephant.off", "fandisk.off", "pinion.off",
    "lever.stl", "t13_data.stl", "turbine.off", "cheese.off", "bunny00.off", "wedge-1.smesh", "spike-1-10.smesh",
    "slit-1.smesh", "cubes.off")]


TIMEOUT_S = 600


def timed(cmd, cwd):
    """Runs cmd; returns (seconds, CompletedProcess). A run past TIMEOUT_S counts as a failure (returncode 124)."""
    start = time.perf_counter()
    try:
        proc = subprocess.run(cmd, cwd=cwd, capture_output=True, text=True, timeout=TIMEOUT_S)
    except subprocess.TimeoutExpired:
        proc = subprocess.CompletedProcess(cmd, 124, "", f"timed out after {TIMEOUT_S} s")
    return time.perf_counter() - start, proc


def count_node_file(path):
    with open(path) as f:
        for line in f:
            line = line.split("#")[0].split()
            if line:
                return int(line[0])
    return 0


def to_tetgen_poly(qualmesh, model, tmp):
    """Converts `model` to TMP/STEM.poly with `qualmesh convert`, the one input every tool of a benchmark gets.

    TetGen 1.5.0 aborts on some merged polygonal facets (collinear vertices on a polygon): then the unmerged
    triangles are written instead, so that all tools still see the same PLC. Returns (poly path, display name,
    error or None); the name gets " (triangles)" in that case.
    """
    poly = Path(tmp) / (model.stem + ".poly")
    conv = subprocess.run([qualmesh, "convert", str(model), str(poly)], capture_output=True, text=True)
    if conv.returncode != 0:
        return poly, model.name, f"convert failed: {conv.stderr.strip()[:80]}"
    probe = subprocess.run(["tetgen", "-pQ", poly.name], cwd=tmp, capture_output=True, text=True)
    name = model.name
    if probe.returncode != 0:
        subprocess.run([qualmesh, "convert", "--keep-triangles", str(model), str(poly)],
                       capture_output=True, text=True, check=True)
        name += " (triangles)"
    for stale in Path(tmp).glob(model.stem + ".1.*"):  # the probe's output
        stale.unlink()
    return poly, name, None


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--qualmesh", default=str(ROOT / "build" / "converters" / "qualmesh"))
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--radius-edge", default="2.0")
    parser.add_argument("--timeout", type=int, default=600, help="seconds per run before it counts as failed")
    parser.add_argument("--qualmesh-arg", action="append", default=[],
                        help="extra argument for `qualmesh mesh` (repeatable), e.g. --qualmesh-arg=--no-pump to "
                             "compare Rules 1-3 alone with TetGen's refinement")
    parser.add_argument("models", nargs="*")
    args = parser.parse_args()
    args.qualmesh = str(Path(args.qualmesh).resolve())
    global TIMEOUT_S
    TIMEOUT_S = args.timeout
    if shutil.which("tetgen") is None:
        sys.exit("tetgen is not installed (apt-get install tetgen)")
    models = [Path(m) for m in args.models] or [m for m in DEFAULT_MODELS if m.exists()]

    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for model in models:
            poly, name, error = to_tetgen_poly(args.qualmesh, model, tmp)
            if error:
                rows.append((model.name, None, None, error))
                continue
            best_q = best_t = float("inf")
            q_out = t_out = None
            for _ in range(args.repeat):
                out = Path(tmp) / (model.stem + "_qm.vtu")
                dt, q = timed([args.qualmesh, "mesh", str(poly), "-o", str(out), "--radius-edge", args.radius_edge]
                              + args.qualmesh_arg, tmp)
                if q.returncode != 0:
                    q_out = f"qualmesh failed ({q.returncode}): {q.stderr.strip()[-120:]}"
                    break
                best_q = min(best_q, dt)
                q_out = q.stdout
                dt, t = timed(["tetgen", "-pq" + args.radius_edge + "aA", "-Q", poly.name], tmp)
                if t.returncode != 0:
                    t_out = f"tetgen failed ({t.returncode})"
                    break
                best_t = min(best_t, dt)
                t_out = count_node_file(Path(tmp) / (model.stem + ".1.node"))
            rows.append((name, (best_q, q_out), (best_t, t_out), None))

    print(f"| model | QualMesh s | TetGen s | time ratio | QualMesh vertices | TetGen vertices | vertex ratio |")
    print("|---|---|---|---|---|---|---|")
    for name, q, t, err in rows:
        if err:
            print(f"| {name} | {err} | | | | | |")
            continue
        if not isinstance(q[1], str) or "failed" in q[1] or not isinstance(t[1], int):
            print(f"| {name} | {q[1] if isinstance(q[1], str) and 'failed' in q[1] else ''} | {t[1]} | | | | |")
            continue
        m = re.search(r"output:\s+(\d+) vertices", q[1])
        qv = int(m.group(1)) if m else 0
        print(f"| {name} | {q[0]:.3f} | {t[0]:.3f} | {q[0] / t[0]:.2f} | {qv} | {t[1]} | "
              f"{qv / t[1] if t[1] else float('nan'):.2f} |")


if __name__ == "__main__":
    main()
