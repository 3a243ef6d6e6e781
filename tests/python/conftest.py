"""Shared fixtures for the Python end-to-end tests (run by Debian's /usr/bin/python3 through CTest).

CTest passes QUALMESH_EXE, QUALMESH_SOURCE_DIR and QUALMESH_SHARED_DIR. A test whose tool or input is missing is
skipped with the reason, never passed.
"""
import os
import shutil
import subprocess
from pathlib import Path

import pytest

SOURCE_DIR = Path(os.environ.get("QUALMESH_SOURCE_DIR", Path(__file__).resolve().parents[2]))
SHARED_DIR = Path(os.environ.get("QUALMESH_SHARED_DIR", SOURCE_DIR.parent / "shared"))


def _exe():
    exe = os.environ.get("QUALMESH_EXE")
    if exe and Path(exe).exists():
        return exe
    found = shutil.which("qualmesh")
    if found:
        return found
    pytest.skip("qualmesh executable not found (set QUALMESH_EXE)")


@pytest.fixture(scope="session")
def qualmesh_exe():
    return _exe()


@pytest.fixture
def run_qualmesh(qualmesh_exe):
    """Run `qualmesh ARGS...`; returns the CompletedProcess (text mode)."""
    def run(*args, timeout=1200):
        return subprocess.run([qualmesh_exe, *map(str, args)], capture_output=True, text=True, timeout=timeout)
    return run


def shared_file(relative):
    """Path of ../shared/RELATIVE, or skip the test when it is absent."""
    path = SHARED_DIR / relative
    if not path.exists():
        pytest.skip(f"missing shared input {path}")
    return path


def require_tool(name):
    """Path of an executable on PATH, or skip the test."""
    path = shutil.which(name)
    if path is None:
        pytest.skip(f"tool '{name}' is not installed")
    return path


def require_module(name):
    """Import a Python module, or skip the test."""
    return pytest.importorskip(name)
