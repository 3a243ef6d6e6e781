"""Issue 18: the hostile-input catalogue (tests/hostile/cases.py). Each case runs `qualmesh` once and asserts the exact
exit code, a pattern on stderr and, for refused cases, that nothing at all was written (no mesh, no temporary file).

Each case runs under a time limit and an address-space limit (QUALMESH_HOSTILE_MEMORY_MB, default 4096; 0 turns the
limit off; an AddressSanitizer build runs without it), so that a runaway case fails instead of hanging or swapping
the machine.
"""
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

from conftest import SOURCE_DIR

sys.path.insert(0, str(SOURCE_DIR / "tests" / "hostile"))
import cases as catalogue  # noqa: E402
import inputs  # noqa: E402

MEMORY_MB = int(os.environ.get("QUALMESH_HOSTILE_MEMORY_MB", "4096"))


def _memory_limit_mb(exe):
    """MEMORY_MB, or 0 for an AddressSanitizer build (its shadow memory reserves terabytes of address space)."""
    try:
        return 0 if b"__asan_init" in Path(exe).read_bytes() else MEMORY_MB
    except OSError:
        return MEMORY_MB


@pytest.fixture(scope="module")
def input_dir(tmp_path_factory):
    return inputs.write_inputs(tmp_path_factory.mktemp("hostile_inputs"))


@pytest.fixture(scope="module")
def limit_memory(qualmesh_exe):
    limit_mb = _memory_limit_mb(qualmesh_exe)
    if limit_mb <= 0:
        return None

    def limit():
        import resource
        resource.setrlimit(resource.RLIMIT_AS, (limit_mb << 20, limit_mb << 20))
    return limit


def _expand(arg, input_dir, outdir):
    return (arg.replace("{in}", str(input_dir))
               .replace("{small}", str(SOURCE_DIR / "tests" / "data" / "small"))
               .replace("{malformed}", str(catalogue.MALFORMED_DIR))
               .replace("{outdir}", str(outdir))
               .replace("{out}", str(outdir / "mesh.vtu")))


def test_catalogue_is_large_enough():
    assert len(catalogue.CASES) >= 100
    assert len({c.name for c in catalogue.CASES}) == len(catalogue.CASES)


@pytest.mark.parametrize("case", catalogue.CASES, ids=[c.name for c in catalogue.CASES])
def test_hostile(case, qualmesh_exe, input_dir, limit_memory, tmp_path):
    outdir = tmp_path / "out"
    outdir.mkdir()
    for tag in case.tags:
        if tag.startswith("mkdir:"):
            (outdir / tag[len("mkdir:"):]).mkdir()
        elif tag.startswith("mkfifo:"):  # a FIFO nobody writes to: reading it must not block
            os.mkfifo(outdir / tag[len("mkfifo:"):])
        elif tag.startswith("symlink:"):  # symlink:NAME=TARGET
            name, target = tag[len("symlink:"):].split("=", 1)
            (outdir / name).symlink_to(target)
    before = sorted(p.name for p in outdir.iterdir())
    argv = [qualmesh_exe] + [_expand(a, input_dir, outdir) for a in case.argv]
    try:
        proc = subprocess.run(argv, capture_output=True, text=True, timeout=case.timeout, cwd=tmp_path,
                              preexec_fn=limit_memory, errors="replace")
    except subprocess.TimeoutExpired:
        pytest.fail(f"{case.name}: still running after {case.timeout} s: {' '.join(argv)}")
    described = (f"{' '.join(argv)}\nexit {proc.returncode}\nstderr:\n{proc.stderr}\n"
                 f"stdout (tail):\n{proc.stdout[-2000:]}")
    assert proc.returncode == case.code, described
    assert re.search(case.stderr, proc.stderr, re.MULTILINE), f"stderr does not match /{case.stderr}/\n{described}"
    after = sorted(p.name for p in outdir.iterdir())
    if case.code != 0 and "writes" in case.tags:  # --allow-partial: a limit stopped it, the partial mesh is kept
        assert not [n for n in after if ".tmp" in n], f"temporary files left: {after}\n{described}"
        assert len(after) > len(before), f"no partial output written\n{described}"
    elif case.code != 0:
        assert after == before, f"a refused case wrote {sorted(set(after) - set(before))}\n{described}"
    else:
        assert proc.stderr == "", described
        assert not [n for n in after if ".tmp" in n], f"temporary files left: {after}\n{described}"
        if "-o" in case.argv:
            assert len(after) > len(before), f"no output written\n{described}"
