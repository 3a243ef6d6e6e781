#!/usr/bin/env python3
"""Writes the seed corpus of the reader fuzzers (fuzz_reader.cpp) into tests/fuzz/corpus/<reader>/.

Seeds: the small and malformed files of tests/data, the small files (<= 12 KB) of ../shared/data/plc, and, for the
mesh readers of `check`, meshes of tests/data/small/box.poly that `qualmesh` writes in every format (linear and
second order). Multi-file inputs are joined at the line "@@" as fuzz_reader.cpp splits them. Deterministic file
names (the source's name); run it again after adding data, then let scripts/fuzz.sh minimise (-merge=1).
Usage: seed_corpus.py QUALMESH_EXE [SHARED_DIR]
"""
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
SOURCE = HERE.parents[1]
MAX_SEED_BYTES = 12_000
SEP = b"\n@@\n"

PLC_EXT = {"poly": ".poly", "smesh": ".smesh", "node": ".node", "off": ".off", "stl": ".stl", "obj": ".obj",
           "medit": ".mesh"}
MESH_EXT = {"vtu": ".vtu", "msh": ".msh", "inp": ".inp", "unv": ".unv", "mesh_medit": ".mesh"}


def put(reader, name, data):
    folder = HERE / "corpus" / reader
    folder.mkdir(parents=True, exist_ok=True)
    (folder / name).write_bytes(data)


def main():
    exe = sys.argv[1]
    shared = Path(sys.argv[2]) if len(sys.argv) > 2 else SOURCE.parent / "shared"
    sources = list((SOURCE / "tests/data/small").glob("*")) + list((SOURCE / "tests/data/malformed").glob("*"))
    sources += list((shared / "data/plc").glob("*"))
    for path in sorted(sources):
        if not path.is_file() or path.stat().st_size > MAX_SEED_BYTES:
            continue
        ext = path.suffix.lower()
        for reader, reader_ext in PLC_EXT.items():
            if ext == reader_ext:
                put(reader, path.parent.name + "_" + path.name, path.read_bytes())
        if ext == ".mesh":
            put("mesh_medit", path.parent.name + "_" + path.name, path.read_bytes())
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        for order in ("1", "2"):
            for reader, ext in list(MESH_EXT.items()) + [("mesh_tetgen", ".node")]:
                out = tmp / f"box{order}{ext}"
                subprocess.run([exe, "mesh", str(SOURCE / "tests/data/small/box.poly"), "-o", str(out), "--order",
                                order], check=True, capture_output=True)
                if reader == "mesh_tetgen":
                    data = SEP.join((tmp / f"box{order}{e}").read_bytes() for e in (".node", ".ele", ".face"))
                else:
                    data = out.read_bytes()
                put(reader, f"box_order{order}{ext if reader != 'mesh_tetgen' else ''}", data)
        # a .poly whose nodes are in the sibling .node file (node count 0)
        poly = (SOURCE / "tests/data/small/box.poly").read_bytes()
        put("poly", "box_with_node_file", b"0 3 0 0\n" + poly.split(b"\n", 1)[1] + SEP + poly)


if __name__ == "__main__":
    main()
