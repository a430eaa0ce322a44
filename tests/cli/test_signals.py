"""Issue 23, nothing lost: a worker killed during `validate` costs its file only (the others
are graded, the reports written); SIGTERM and SIGINT (once or twice) leave no temporary
file and no worker, and exit 143 / 130 promptly. Real processes and real signals: the
command runs in a child Python whose validation (or computation) is slowed down, so the
signal lands while the work is in progress."""
from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
WORKBOOKS = ROOT / "workbooks"

# The command, with each file's validation (or each computed block) made slow.
_DRIVER = r"""
import os, sys, time
import sheetkin.course.batch as batch
import sheetkin.views.output as output
delay = float(os.environ["SHEETKIN_TEST_DELAY"])
real_validate, real_blocks = batch._validate_one, output.compute_blocks
def slow_validate(path, **kw):
    time.sleep(delay)
    return real_validate(path, **kw)
def slow_blocks(*a, **kw):
    for blk in real_blocks(*a, **kw):
        time.sleep(delay)
        yield blk
batch._validate_one, output.compute_blocks = slow_validate, slow_blocks
from sheetkin.cli.commands import main
sys.exit(main(sys.argv[1:]))
"""


def _start(tmp_path: Path, delay: float, *argv) -> subprocess.Popen:
    env = dict(os.environ, PYTHONPATH=str(ROOT), SHEETKIN_TEST_DELAY=str(delay))
    return subprocess.Popen([sys.executable, "-c", _DRIVER, *map(str, argv)], cwd=tmp_path, env=env,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def _children(pid: int) -> list[int]:
    out = []
    for d in Path("/proc").iterdir():
        if d.name.isdigit():
            try:
                stat = (d / "stat").read_text()
            except OSError:
                continue
            if int(stat.rsplit(")", 1)[1].split()[1]) == pid:
                out.append(int(d.name))
    return out


def _alive(pid: int) -> bool:
    try:
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except OSError:
        return False
    return state != "Z"


def _wait_for(test, timeout: float = 60.0):
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        got = test()
        if got:
            return got
        time.sleep(0.05)
    pytest.fail("timed out waiting")


pytestmark = pytest.mark.skipif(not Path("/proc/self/stat").exists(), reason="reads /proc")


@pytest.fixture
def klass(tmp_path):
    """Eight copies of the four-bar's workbook."""
    (tmp_path / "cls").mkdir()
    data = (WORKBOOKS / "fourbar.xlsx").read_bytes()
    for i in range(8):
        (tmp_path / "cls" / f"s{i}.xlsx").write_bytes(data)
    return tmp_path


def test_a_killed_worker_costs_its_file_only(klass):
    proc = _start(klass, 1.0, "validate", "cls", "--jobs", "2", "--html", "r.html", "--grades", "g.csv")
    workers = _wait_for(lambda: len(_children(proc.pid)) >= 2 and _children(proc.pid))
    time.sleep(0.3)
    os.kill(workers[0], signal.SIGKILL)           # as the out-of-memory killer would
    out, err = proc.communicate(timeout=300)
    assert proc.returncode == 2, err              # one file unusable, not exit 70
    assert "internal error" not in err and "Traceback" not in err
    # the report is in the books' language (Russian by default): UNUSABLE is "НЕ ПРОВЕРЯЕТСЯ"
    dead = [line for line in out.splitlines() if "НЕ ПРОВЕРЯЕТСЯ" in line and "killed by SIGKILL" in line]
    assert len(dead) == 1, out
    assert "the other files were validated" in dead[0]
    grades = (klass / "g.csv").read_text(encoding="utf-8-sig").splitlines()
    assert len(grades) == 9                        # the header and every file, the dead one too
    assert "killed by SIGKILL" in (klass / "r.html").read_text(encoding="utf-8")
    assert not [p for p in _children(proc.pid) if _alive(p)]


@pytest.mark.parametrize("sig, code", [(signal.SIGTERM, 143), (signal.SIGINT, 130)])
def test_a_signal_stops_the_pool(klass, sig, code):
    proc = _start(klass, 2.0, "validate", "cls", "--jobs", "2", "--html", "r.html")
    workers = _wait_for(lambda: len(_children(proc.pid)) >= 2 and _children(proc.pid))
    time.sleep(0.3)
    t0 = time.monotonic()
    os.kill(proc.pid, sig)
    out, err = proc.communicate(timeout=60)
    assert proc.returncode == code, err
    assert time.monotonic() - t0 < 10
    assert err.strip().splitlines()[-1] in ("sheetkin: terminated", "sheetkin: interrupted")
    assert not any(_alive(w) for w in workers), "a worker outlived the command"
    assert not (klass / "r.html").exists()


@pytest.mark.parametrize("signals, code", [((signal.SIGTERM,), 143), ((signal.SIGINT,), 130),
                                           ((signal.SIGINT, signal.SIGINT), 130),
                                           ((signal.SIGTERM, signal.SIGTERM), 143)])
def test_an_interrupted_write_leaves_the_old_file_and_no_temporary(tmp_path, signals, code):
    (tmp_path / "out.csv").write_text("the old content\n")
    scene = WORKBOOKS / "fourbar.toml"
    # 64 blocks of 16384 positions, each one slowed down: the .part file exists for seconds
    proc = _start(tmp_path, 0.5, "compute", scene, "--range", "0:1048576:1", "--format", "csv",
                  "-o", "out.csv")
    _wait_for(lambda: list(tmp_path.glob(".sheetkin-*.part")), timeout=120)
    t0 = time.monotonic()
    for s in signals:
        os.kill(proc.pid, s)
        time.sleep(0.02)
    out, err = proc.communicate(timeout=60)
    assert proc.returncode == code, err
    assert time.monotonic() - t0 < 10
    assert "Traceback" not in err
    assert not list(tmp_path.glob(".sheetkin-*")), "a temporary file was left behind"
    assert (tmp_path / "out.csv").read_text() == "the old content\n"


# ---------------------------------------------------------------- LibreOffice interrupted
def _fods(path: Path) -> Path:
    from helpers import realfiles as rf
    rows = [[rf.text("x"), rf.num(2.0)], [rf.text("y"), rf.formula("[.B1]*2")]]
    return rf.fods(path, [rf.table("Calc", rows)])


def _ours(marker: str) -> list[int]:
    """Live processes whose command line holds `marker` (our temporary folder: soffice,
    oosplash and soffice.bin are started with -env:UserInstallation inside it)."""
    out = []
    for d in Path("/proc").iterdir():
        if not d.name.isdigit() or int(d.name) == os.getpid():
            continue
        try:
            cmd = (d / "cmdline").read_bytes()
        except OSError:
            continue
        if marker.encode() in cmd and (b"soffice" in cmd or b"oosplash" in cmd) and _alive(int(d.name)):
            out.append(int(d.name))
    return out


@pytest.mark.parametrize("layout", ["one", "batch", "worker"])
@pytest.mark.parametrize("signals, code", [((signal.SIGINT,), 130), ((signal.SIGTERM,), 143),
                                           ((signal.SIGINT, signal.SIGINT), 130)])
def test_libreoffice_interrupted_leaves_nothing(tmp_path, soffice, layout, signals, code):
    """`validate` of OpenDocument books, interrupted while LibreOffice converts: one book
    (converted in the command's process), two (one LibreOffice run for both, before the
    pool), or one .fods beside an .xlsx with two workers (converted inside a worker). The
    command exits 130/143 promptly; no soffice, oosplash or soffice.bin started with our
    temporary profile is left, and nothing is left in the temporary folder (TMPDIR)."""
    tmp = tmp_path / "tmp"
    tmp.mkdir()
    cls = tmp_path / "cls"
    cls.mkdir()
    _fods(cls / "a.fods")
    if layout == "batch":
        _fods(cls / "b.fods")
    if layout == "worker":
        (cls / "b.xlsx").write_bytes((WORKBOOKS / "fourbar.xlsx").read_bytes())
    env = dict(os.environ, PYTHONPATH=str(ROOT), TMPDIR=str(tmp))
    target = cls / "a.fods" if layout == "one" else cls
    proc = subprocess.Popen([sys.executable, "-m", "sheetkin", "validate", str(target), "--jobs", "2"],
                            cwd=tmp_path, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    _wait_for(lambda: _ours(str(tmp)), timeout=60)
    time.sleep(0.3)
    t0 = time.monotonic()
    for s in signals:
        os.kill(proc.pid, s)
        time.sleep(0.05)
    out, err = proc.communicate(timeout=60)
    assert proc.returncode == code, (out, err)
    assert time.monotonic() - t0 < 15
    assert "Traceback" not in err
    deadline = time.monotonic() + 5              # SIGKILLed processes vanish at once; allow the reaping
    while _ours(str(tmp)) and time.monotonic() < deadline:
        time.sleep(0.1)
    assert not _ours(str(tmp)), "a LibreOffice process of ours outlived the command"
    left = sorted(str(p.relative_to(tmp)) for p in tmp.rglob("*"))
    assert not left, f"temporary files left: {left[:10]}"


def _ppid(pid: int) -> int:
    try:
        return int(Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[1])
    except (OSError, ValueError, IndexError):
        return 0


def test_a_worker_killed_while_libreoffice_converts_leaves_nothing(tmp_path, soffice):
    """A worker SIGKILLed (as the out-of-memory killer would) while its LibreOffice converts a
    .fods cannot clean up: LibreOffice runs in a session of its own and would convert on. The
    parent ends what the dead worker left (by its profile's name) and grades the rest."""
    tmp = tmp_path / "tmp"
    tmp.mkdir()
    cls = tmp_path / "cls"
    cls.mkdir()
    _fods(cls / "a.fods")
    (cls / "b.xlsx").write_bytes((WORKBOOKS / "fourbar.xlsx").read_bytes())
    env = dict(os.environ, PYTHONPATH=str(ROOT), TMPDIR=str(tmp))
    proc = subprocess.Popen([sys.executable, "-m", "sheetkin", "validate", str(cls), "--jobs", "2"],
                            cwd=tmp_path, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    lo = _wait_for(lambda: _ours(str(tmp)), timeout=60)
    workers = set(_children(proc.pid))
    owner = next((p for p in lo if _ppid(p) in workers), None)
    assert owner is not None, (lo, workers)
    os.kill(_ppid(owner), signal.SIGKILL)
    out, err = proc.communicate(timeout=120)
    assert proc.returncode == 2 and "Traceback" not in err, (out, err)
    assert "killed by SIGKILL" in out
    deadline = time.monotonic() + 5
    while _ours(str(tmp)) and time.monotonic() < deadline:
        time.sleep(0.1)
    assert not _ours(str(tmp)), "the dead worker's LibreOffice outlived the command"
    left = sorted(str(p.relative_to(tmp)) for p in tmp.rglob("*"))
    assert not left, f"temporary files left: {left[:10]}"
