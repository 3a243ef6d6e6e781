"""Helpers for the pytest drivers of the FreeCAD addon tests (tests/python/test_freecad_*.py).

FreeCAD finds the addon under $HOME/.local/share/FreeCAD/Mod/<Name>/, so each test gets a temporary HOME with
the source tree's freecad_module/ linked there as QualMesh (no install, no user configuration touched).
freecadcmd exits 0 even when its script raises: the scripts here catch everything and exit 1 themselves, and
write their facts as JSON for the driver to assert.
"""
import json
import os
import shutil
import subprocess
from pathlib import Path

import pytest

HERE = Path(__file__).resolve().parent
SOURCE_DIR = Path(os.environ.get("QUALMESH_SOURCE_DIR", HERE.parents[1]))


def require(tool):
    path = shutil.which(tool)
    if path is None:
        pytest.skip(f"tool '{tool}' is not installed")
    return path


def freecad_home(tmp_path):
    """A HOME in which FreeCAD finds the addon (a link to the source tree's freecad_module/)."""
    home = tmp_path / "home"
    mod = home / ".local" / "share" / "FreeCAD" / "Mod"
    mod.mkdir(parents=True, exist_ok=True)
    link = mod / "QualMesh"
    if not link.exists():
        link.symlink_to(SOURCE_DIR / "freecad_module", target_is_directory=True)
    return home


def freecad_env(tmp_path, qualmesh_exe, **extra):
    env = dict(os.environ)
    env.update({"HOME": str(freecad_home(tmp_path)), "QUALMESH_EXE": str(qualmesh_exe),
                "PYTHONDONTWRITEBYTECODE": "1", "MESA_SHADER_CACHE_DISABLE": "true",
                "QTWEBENGINE_DISABLE_SANDBOX": "1"})
    env.update({k: str(v) for k, v in extra.items()})
    return env


def run_freecadcmd(script, tmp_path, qualmesh_exe, timeout=600, **extra):
    """Run `freecadcmd SCRIPT` in tmp_path; returns the CompletedProcess (text)."""
    exe = require("freecadcmd")
    return subprocess.run([exe, str(script)], cwd=tmp_path, env=freecad_env(tmp_path, qualmesh_exe, **extra),
                          capture_output=True, text=True, timeout=timeout)


def run_checks(case, tmp_path, qualmesh_exe, **extra):
    """Run tests/freecad/fc_model_checks.py for one case; returns its JSON facts (fails the test on a crash)."""
    result_path = tmp_path / f"{case}.json"
    workdir = tmp_path / "work"
    workdir.mkdir(exist_ok=True)
    proc = run_freecadcmd(HERE / "fc_model_checks.py", tmp_path, qualmesh_exe, QUALMESH_FC_CASE=case,
                          QUALMESH_FC_RESULT=result_path, QUALMESH_FC_WORKDIR=workdir, **extra)
    facts = json.loads(result_path.read_text()) if result_path.exists() else {"errors": ["no result file"]}
    assert proc.returncode == 0 and not facts["errors"], (
        f"freecadcmd failed (exit {proc.returncode}):\n{''.join(facts['errors'])}\n{proc.stdout[-3000:]}\n"
        f"{proc.stderr[-3000:]}")
    return facts
