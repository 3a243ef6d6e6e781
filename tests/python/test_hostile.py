"""Issue 18: the hostile-input catalogue (tests/hostile/cases.py). Each case runs `qualmesh` once and asserts the exact
exit code, a pattern on stderr and, for refused cases, that nothing at all was written (no mesh, no temporary file).

Each case runs under a time limit and an address-space limit (QUALMESH_HOSTILE_MEMORY_MB, default 4096; 0 turns the
limit off; an AddressSanitizer build runs without it), so that a runaway case fails instead of hanging or swapping
the machine. Whatever qualmesh prints on stderr must be printable: no control byte but the line feed, no byte that is
not UTF-8 (random input must not reach the terminal raw).

Tags a case may carry (cases.py): mkdir:NAME, mkfifo:NAME, symlink:NAME=TARGET, file:NAME=TEXT (made in the output
folder first; a refused case must leave every file:'s content as it was, a "replaces" case must change it),
fsize:BYTES (RLIMIT_FSIZE, `ulimit -f`), signal:NAME (the signal is sent once a "*.tmp-*" output appears: during the
write), scad-signal:NAME (sent to qualmesh once its `openscad` child runs; the child must be gone after, and the
temporary folder of the render too), needs:openscad, needs:shared.
"""
import os
import re
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from conftest import SHARED_DIR, SOURCE_DIR

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
               .replace("{shared}", str(SHARED_DIR))
               .replace("{small}", str(SOURCE_DIR / "tests" / "data" / "small"))
               .replace("{malformed}", str(catalogue.MALFORMED_DIR))
               .replace("{outdir}", str(outdir))
               .replace("{out}", str(outdir / "mesh.vtu")))


def test_catalogue_is_large_enough():
    assert len(catalogue.CASES) >= 100
    assert len({c.name for c in catalogue.CASES}) == len(catalogue.CASES)


def _children(pid):
    """Pids of the live processes whose parent is `pid` (from /proc)."""
    found = []
    for entry in os.listdir("/proc"):
        if not entry.isdigit():
            continue
        try:
            stat = Path(f"/proc/{entry}/stat").read_text()
        except OSError:
            continue
        fields = stat[stat.rindex(")") + 2:].split()
        if int(fields[1]) == pid and fields[0] != "Z":
            found.append(int(entry))
    return found


def _alive(pid):
    try:
        stat = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return False
    return stat[stat.rindex(")") + 2:].split()[0] != "Z"


def _run_signalled(argv, case, tag, outdir, env, preexec, cwd):
    """Runs argv, sends the tag's signal at the moment the tag names; returns (proc, stdout, stderr, note)."""
    kind, name = tag.split(":", 1)
    sig = getattr(signal, "SIG" + name)
    proc = subprocess.Popen(argv, stdout=subprocess.PIPE, stderr=subprocess.PIPE, cwd=cwd, preexec_fn=preexec,
                            env=env)
    deadline = time.monotonic() + case.timeout
    note = {}
    while time.monotonic() < deadline and proc.poll() is None:
        if kind == "signal":
            temps = [n for n in os.listdir(outdir) if ".tmp-" in n]
            if temps:
                note["during"] = temps
                proc.send_signal(sig)
                break
            time.sleep(0.0002)
        else:  # scad-signal: once openscad runs
            kids = _children(proc.pid)
            if kids:
                time.sleep(0.3)  # well inside the render
                note["children"] = kids
                proc.send_signal(sig)
                break
            time.sleep(0.01)
    try:
        out, err = proc.communicate(timeout=max(1.0, deadline - time.monotonic()))
    except subprocess.TimeoutExpired:
        proc.kill()
        proc.communicate()
        pytest.fail(f"{case.name}: still running after {case.timeout} s: {' '.join(argv)}")
    return proc, out.decode("utf-8", "replace"), err.decode("utf-8", "replace"), note


@pytest.mark.parametrize("case", catalogue.CASES, ids=[c.name for c in catalogue.CASES])
def test_hostile(case, qualmesh_exe, input_dir, limit_memory, tmp_path):
    for tag in case.tags:
        if tag == "needs:openscad" and shutil.which("openscad") is None:
            pytest.skip("openscad is not installed")
        if tag == "needs:shared" and not SHARED_DIR.is_dir():
            pytest.skip(f"{SHARED_DIR} is absent")
    outdir = tmp_path / "out"
    outdir.mkdir()
    scratch = tmp_path / "tmp"  # TMPDIR of the run: the OpenSCAD front end renders in a folder there
    scratch.mkdir()
    files = {}
    file_size_limit = None
    for tag in case.tags:
        if tag.startswith("mkdir:"):
            (outdir / tag[len("mkdir:"):]).mkdir()
        elif tag.startswith("mkfifo:"):  # a FIFO nobody writes to: reading it must not block
            os.mkfifo(outdir / tag[len("mkfifo:"):])
        elif tag.startswith("symlink:"):  # symlink:NAME=TARGET
            name, target = tag[len("symlink:"):].split("=", 1)
            (outdir / name).symlink_to(target)
        elif tag.startswith("file:"):  # file:NAME=TEXT, an old output that must survive a failed write
            name, text = tag[len("file:"):].split("=", 1)
            (outdir / name).parent.mkdir(parents=True, exist_ok=True)
            (outdir / name).write_text(text)
            files[name] = text
        elif tag.startswith("fsize:"):
            file_size_limit = int(tag[len("fsize:"):])
    before = sorted(p.name for p in outdir.iterdir())
    argv = [qualmesh_exe] + [_expand(a, input_dir, outdir) for a in case.argv]

    signalled = [t for t in case.tags if t.startswith(("signal:", "scad-signal:"))]

    def preexec():
        if signalled:  # a background job or nohup may hand qualmesh these ignored; it keeps what it is given
            for sig in (signal.SIGINT, signal.SIGTERM, signal.SIGHUP):
                signal.signal(sig, signal.SIG_DFL)
        if limit_memory:
            limit_memory()
        if file_size_limit is not None:
            import resource
            resource.setrlimit(resource.RLIMIT_FSIZE, (file_size_limit, file_size_limit))
    env = dict(os.environ, TMPDIR=str(scratch))
    note = {}
    if signalled:
        proc, stdout, stderr, note = _run_signalled(argv, case, signalled[0], outdir, env, preexec, tmp_path)
    else:
        try:
            done = subprocess.run(argv, capture_output=True, timeout=case.timeout, cwd=tmp_path, preexec_fn=preexec,
                                  env=env)
        except subprocess.TimeoutExpired:
            pytest.fail(f"{case.name}: still running after {case.timeout} s: {' '.join(argv)}")
        proc, stdout, stderr = done, done.stdout.decode("utf-8", "replace"), done.stderr.decode("utf-8", "replace")
    described = (f"{' '.join(argv)}\nexit {proc.returncode}\nstderr:\n{stderr}\n"
                 f"stdout (tail):\n{stdout[-2000:]}\n{note}")
    assert proc.returncode == case.code, described
    assert re.search(case.stderr, stderr, re.MULTILINE), f"stderr does not match /{case.stderr}/\n{described}"
    assert re.search(case.stdout, stdout, re.MULTILINE), f"stdout does not match /{case.stdout}/\n{described}"
    unprintable = sorted({c for c in stderr if (ord(c) < 32 and c != "\n") or c in "\x7f\ufffd"})
    assert not unprintable, f"stderr holds raw bytes {unprintable!r}\n{described}"
    if signalled and signalled[0].startswith("signal:"):
        assert note.get("during"), f"the run ended before any temporary appeared\n{described}"
    if signalled and signalled[0].startswith("scad-signal:"):
        assert note.get("children"), f"openscad never started\n{described}"
        for _ in range(300):  # killed at once; give the kernel a moment to reap it
            if not any(_alive(pid) for pid in note["children"]):
                break
            time.sleep(0.01)
        assert not any(_alive(pid) for pid in note["children"]), f"openscad still runs\n{described}"
        assert not list(scratch.iterdir()), f"the render's folder was left: {list(scratch.iterdir())}\n{described}"
    after = sorted(p.name for p in outdir.iterdir())
    temporaries = [str(p.relative_to(outdir)) for p in outdir.rglob("*") if ".tmp-" in p.name]
    assert not temporaries, f"temporary files left: {temporaries}\n{described}"
    if case.code != 0 and "writes" in case.tags:  # --allow-partial: a limit stopped it, the partial mesh is kept
        assert len(after) > len(before), f"no partial output written\n{described}"
    elif case.code != 0:
        assert after == before, f"a refused case wrote {sorted(set(after) - set(before))}\n{described}"
        for name, text in files.items():
            assert (outdir / name).read_text() == text, f"{name} was changed by a failed write\n{described}"
    else:
        # `convert` says what it wrote on stderr ("qualmesh: wrote PATH"); nothing else may be there
        assert re.sub(r"^qualmesh: wrote .*\n", "", stderr, flags=re.MULTILINE) == "" if case.argv[:1] == ["convert"] \
            else stderr == "", described
        if "replaces" in case.tags:
            for name, text in files.items():
                assert (outdir / name).read_text() != text, f"{name} was not replaced\n{described}"
        elif "-o" in case.argv or case.argv[:1] == ["convert"]:
            assert len(after) > len(before), f"no output written\n{described}"
