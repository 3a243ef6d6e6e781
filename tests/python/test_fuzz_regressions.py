"""Issue 18, fuzzing: every input the reader fuzzers (tests/fuzz/fuzz_reader.cpp, scripts/fuzz.sh) ever found to
crash, hang or throw something else than InputError is kept in tests/fuzz/regressions/<reader>/, and here goes
through the command line that reads it: `qualmesh info` for the PLC readers, `qualmesh check` for the mesh readers.
Each must end within 10 s with a verdict (exit 0, 2 bad input, or 3 defects), never an internal error (1), a
resource exit (4) or a signal, with a printable message. The seed corpus (tests/fuzz/corpus/<reader>/, merged from
every fuzzing session by `scripts/fuzz.sh --merge READER`: hundreds of inputs per reader) runs the same way, up to
CORPUS_PER_READER inputs per reader, evenly spread over the sorted names, so that CI's time stays bounded; CI's
fuzzing smoke run (scripts/test.sh) loads every corpus input under ASan and UBSan anyway. QUALMESH_FUZZ_CORPUS_ALL=1
replays them all (about 7000 inputs, a minute or two).
"""
import os
import subprocess
from pathlib import Path

import pytest

from conftest import SOURCE_DIR

FUZZ_DIR = SOURCE_DIR / "tests" / "fuzz"
SEPARATOR = b"\n@@\n"  # fuzz_reader.cpp: multi-file inputs are split at this line
# reader -> (command, extensions of the parts, in split order)
READERS = {
    "poly": ("info", [".poly", ".node"]), "smesh": ("info", [".smesh", ".node"]), "node": ("info", [".node"]),
    "off": ("info", [".off"]), "stl": ("info", [".stl"]), "obj": ("info", [".obj"]), "medit": ("info", [".mesh"]),
    "vtu": ("check", [".vtu"]), "msh": ("check", [".msh"]), "inp": ("check", [".inp"]), "unv": ("check", [".unv"]),
    "mesh_medit": ("check", [".mesh"]), "mesh_tetgen": ("check", [".node", ".ele", ".face"]),
}


CORPUS_PER_READER = None if os.environ.get("QUALMESH_FUZZ_CORPUS_ALL") == "1" else 40


def _inputs(kind, per_reader=None):
    found = []
    for reader in READERS:
        folder = FUZZ_DIR / kind / reader
        if folder.is_dir():
            files = [p for p in sorted(folder.iterdir()) if p.is_file()]
            if per_reader and len(files) > per_reader:
                files = [files[i * len(files) // per_reader] for i in range(per_reader)]
            found += [(reader, p) for p in files]
    return found


def _run(reader, data, qualmesh_exe, tmp_path):
    command, extensions = READERS[reader]
    parts = data.split(SEPARATOR, len(extensions) - 1)
    for i, ext in enumerate(extensions):
        if i < len(parts):
            (tmp_path / ("input" + ext)).write_bytes(parts[i] + (b"\n" if i + 1 < len(parts) else b""))
    proc = subprocess.run([qualmesh_exe, command, str(tmp_path / ("input" + extensions[0]))], capture_output=True,
                          timeout=10)
    stderr = proc.stderr.decode("utf-8", "replace")
    assert proc.returncode in (0, 2, 3), f"exit {proc.returncode}\n{stderr}"
    assert not [c for c in stderr if (ord(c) < 32 and c != "\n") or c == "\ufffd"], stderr


REGRESSIONS = _inputs("regressions")


@pytest.mark.skipif(not REGRESSIONS, reason="no fuzzing finding recorded in tests/fuzz/regressions")
@pytest.mark.parametrize("reader,path", REGRESSIONS, ids=[f"{r}/{p.name}" for r, p in REGRESSIONS])
def test_fuzz_finding_is_a_clean_verdict(reader, path, qualmesh_exe, tmp_path):
    _run(reader, path.read_bytes(), qualmesh_exe, tmp_path)


CORPUS = _inputs("corpus", CORPUS_PER_READER)


@pytest.mark.parametrize("reader,path", CORPUS, ids=[f"{r}/{p.name}" for r, p in CORPUS])
def test_fuzz_corpus_is_a_clean_verdict(reader, path, qualmesh_exe, tmp_path):
    _run(reader, path.read_bytes(), qualmesh_exe, tmp_path)
