"""Every script in benchmarks/ still starts: `--help` runs and exits 0, and `--tiny` (a smoke
run at a tiny size, no peers) runs through. The benchmarks are run on demand, not by the
tests, so an import that broke (benchmarks/scale.py looked the module sheetkin.compute up
in sys.modules, which the lazy `import sheetkin` of issue 15 no longer fills) or a crash
(`benchmarks/evaluator.py --phases`, issue 24) would otherwise only show when someone
reruns them. Nothing here is timed."""
from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
SCRIPTS = sorted((ROOT / "benchmarks").glob("*.py"))


def test_there_are_scripts():
    assert len(SCRIPTS) >= 8


def _run(script: Path, *argv: str, timeout: float = 120) -> subprocess.CompletedProcess:
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    return subprocess.run([sys.executable, str(script), *argv], cwd=ROOT, env=env,
                          capture_output=True, text=True, timeout=timeout)


@pytest.mark.parametrize("script", SCRIPTS, ids=lambda p: p.name)
def test_help_runs(script):
    p = _run(script, "--help")
    assert p.returncode == 0, p.stderr[-2000:]
    assert "usage:" in p.stdout and "--tiny" in p.stdout


@pytest.mark.parametrize("script", SCRIPTS, ids=lambda p: p.name)
def test_tiny_run(script, tmp_path):
    argv = ["--tiny"] + (["--out", str(tmp_path)] if script.name == "scale.py" else [])
    p = _run(script, *argv, timeout=600)
    assert p.returncode == 0, (p.stdout[-1500:], p.stderr[-2000:])
    assert "Traceback" not in p.stderr
