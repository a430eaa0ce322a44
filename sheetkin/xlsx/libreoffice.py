"""Recalculate .xlsx workbooks in LibreOffice Calc (headless) and read the values back.

Used by the tests (the formulas sheetkin writes must compute, in a real spreadsheet, what
sheetkin computes in Python) and by `sheetkin bench`. Install LibreOffice with tests/setup.sh.

What LibreOffice 7.4 does, found while writing this (see tests/xlsx/test_libreoffice.py):

* Converting xlsx -> xlsx computes formula cells that have no cached value (openpyxl writes
  none), but by default it KEEPS a cached value that is present, even if it is wrong and even
  if the file says fullCalcOnLoad="1" (default OOXMLRecalcMode = 1, "never recalculate").
  Each run therefore gets a private profile whose registrymodifications.xcu sets
  OOXMLRecalcMode (and ODFRecalcMode) to 0, "always recalculate".
* Cached numbers are written with 15 significant digits (pi/2 -> 1.5707963267949): compare
  to a relative tolerance of about 1e-14, not exactly.
* Subtractions that nearly cancel are snapped to 0 (=1+1E-15-1 gives 0, Python 1.1e-15).
* Errors come back as Excel codes, but not always the ones Excel would give (SQRT(-1),
  LN(0), FACT(200), a circular reference -> #VALUE!; Excel: #NUM! / 0). Treat them all
  as "an error" (is_error).
"""
from __future__ import annotations

import contextlib
import os
import re
import shutil
import signal
import subprocess
import tempfile
import time
from collections.abc import Iterator
from pathlib import Path

import openpyxl

__all__ = [
    "soffice_path",
    "recalculate",
    "convert_to_xlsx",
    "read_values",
    "is_error",
    "render_pdf",
    "pdf_to_png",
    "SETUP_HINT",
    "scratch_folder",
    "stop_orphans",
    "keep_folder",
    "stop_all",
]

SETUP_HINT = "LibreOffice (soffice) not found: run `bash tests/setup.sh` (as root, Debian/Ubuntu)"

# 0 = always recalculate on load, 1 = never (the default), 2 = ask.
_REGISTRY = (
    '<?xml version="1.0" encoding="UTF-8"?>\n'
    '<oor:items xmlns:oor="http://openoffice.org/2001/registry" xmlns:xs="http://www.w3.org/2001/XMLSchema" '
    'xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance">\n'
    '<item oor:path="/org.openoffice.Office.Calc/Formula/Load">'
    '<prop oor:name="OOXMLRecalcMode" oor:op="fuse"><value>0</value></prop></item>\n'
    '<item oor:path="/org.openoffice.Office.Calc/Formula/Load">'
    '<prop oor:name="ODFRecalcMode" oor:op="fuse"><value>0</value></prop></item>\n'
    "</oor:items>\n"
)

_ERROR_CODES = frozenset(
    {"#NULL!", "#DIV/0!", "#VALUE!", "#REF!", "#NAME?", "#NUM!", "#N/A", "#SPILL!", "#CALC!",
     "#GETTING_DATA"}
)
_LO_ERROR = re.compile(r"Err:\d{3}")


# What a process that must exit at once (a second Ctrl-C: sheetkin.cli) stops first: the
# process groups of the soffice runs in progress, and the temporary folders of conversions
# (profiles, copies, outputs). An exception or a first signal cleans up on its way out
# (_convert, scratch_folder); os._exit would skip that.
_RUNNING: set[int] = set()
_FOLDERS: set[str] = set()


@contextlib.contextmanager
def scratch_folder(prefix: str) -> Iterator[Path]:
    """A temporary folder, removed when the block ends (whatever ends it) or by stop_all; its
    name holds this process's pid, for stop_orphans."""
    folder = tempfile.mkdtemp(prefix=f"{prefix}{os.getpid()}-")
    _FOLDERS.add(folder)
    try:
        yield Path(folder)
    finally:
        _FOLDERS.discard(folder)
        shutil.rmtree(folder, ignore_errors=True)


def keep_folder(folder: str) -> None:
    """A temporary folder that lives until the process ends: stop_all removes it too."""
    _FOLDERS.add(folder)


def stop_all() -> None:
    """SIGKILL every soffice run of this process (its whole process group) and remove the
    temporary folders of conversions: for a process about to exit at once."""
    for pgid in list(_RUNNING):
        with contextlib.suppress(OSError):
            os.killpg(pgid, signal.SIGKILL)
    for pgid in list(_RUNNING):
        _wait_group(pgid, 2.0)
    for folder in list(_FOLDERS):
        shutil.rmtree(folder, ignore_errors=True)


PROFILE_PREFIX = "sheetkin-lo-profile-"


def stop_orphans(pid: int) -> int:
    """What a process `pid` that died without cleaning up (SIGKILL) left of its soffice runs:
    every process whose command line names one of its profiles (soffice runs in a session
    of its own, so nothing else ends it) is SIGKILLed with its group, and its scratch
    folders (profiles, conversions) are removed. Returns the processes killed. Linux
    (/proc); elsewhere only the folders go."""
    mark = f"{PROFILE_PREFIX}{pid}-"
    groups: set[int] = set()
    for proc in Path("/proc").glob("[0-9]*"):
        try:
            if mark in (proc / "cmdline").read_bytes().decode("utf-8", "replace"):
                groups.add(os.getpgid(int(proc.name)))
        except (OSError, ValueError):
            continue
    for pgid in groups:
        with contextlib.suppress(OSError):
            os.killpg(pgid, signal.SIGKILL)
    for pgid in groups:
        _wait_group(pgid, 5.0)
    for folder in Path(tempfile.gettempdir()).glob("sheetkin-*"):
        if re.match(rf"sheetkin-[a-z-]+-{pid}-", folder.name):
            shutil.rmtree(folder, ignore_errors=True)
    return len(groups)


def _wait_group(pgid: int, timeout: float) -> None:
    """Until no process of group pgid is left (SIGKILLed ones take a moment: soffice.bin
    still writes into its profile until it is gone), at most `timeout` seconds."""
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        try:
            os.killpg(pgid, 0)
        except OSError:
            return
        with contextlib.suppress(ChildProcessError, OSError):
            os.waitpid(-pgid, os.WNOHANG)          # our own child in it: reaped
        time.sleep(0.02)


def recalculating_profile(folder: Path) -> None:
    """Make `folder` (new or empty) a LibreOffice user profile that recalculates every
    formula when it loads a file (_REGISTRY). Without it LibreOffice keeps the values the
    file saved (its default for Excel's files), so a conversion would time loading and
    saving, not recalculation (benchmarks/evaluator_ab.py uses it too)."""
    (folder / "user").mkdir(parents=True, exist_ok=True)
    (folder / "user" / "registrymodifications.xcu").write_text(_REGISTRY, "utf-8")


def soffice_path() -> str | None:
    """The LibreOffice executable ($SOFFICE, else `soffice`/`libreoffice` on PATH), or None."""
    env = os.environ.get("SOFFICE")
    if env:
        return shutil.which(env)
    return shutil.which("soffice") or shutil.which("libreoffice")


def _convert(paths, outdir: Path, target: str, ext: str, timeout: float) -> dict[Path, Path]:
    """One soffice run converting every file in `paths` into `outdir`; input -> output."""
    inputs = [Path(p).resolve() for p in paths]
    if not inputs:
        return {}
    for p in inputs:
        if not p.is_file():
            raise FileNotFoundError(p)
    outdir = Path(outdir).resolve()
    outdir.mkdir(parents=True, exist_ok=True)
    expected = {p: outdir / f"{p.stem}.{ext}" for p in inputs}
    if len(set(expected.values())) != len(inputs):
        raise ValueError(f"two inputs would have the same output name in {outdir}: {inputs}")
    for p, dest in expected.items():
        if dest == p:
            raise ValueError(f"output would overwrite its input: {p}")
    for dest in expected.values():
        dest.unlink(missing_ok=True)  # a stale output must not pass for a fresh one
    soffice = soffice_path()
    if soffice is None:
        raise RuntimeError(SETUP_HINT)

    # the owner's pid in the name: if this process is killed outright (SIGKILL, the
    # out-of-memory killer), its parent finds what it left by it (stop_orphans)
    with scratch_folder(PROFILE_PREFIX) as profile:
        recalculating_profile(profile)
        (profile / "tmp").mkdir()       # LibreOffice's own temporary files (lu*.tmp) go with the profile
        cmd = [
            soffice,
            f"-env:UserInstallation={profile.as_uri()}",
            "--headless", "--norestore", "--nolockcheck", "--nologo",
            "--convert-to", target, "--outdir", str(outdir),
            *map(str, inputs),
        ]
        # Own process group: on timeout kill the wrapper and soffice.bin together.
        env = dict(os.environ, TMPDIR=str(profile / "tmp"))
        proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                                stdin=subprocess.DEVNULL, start_new_session=True, env=env)
        _RUNNING.add(proc.pid)
        try:
            out, err = proc.communicate(timeout=timeout)
        except subprocess.TimeoutExpired:
            _kill_group(proc)
            out, err = proc.communicate()
            raise RuntimeError(
                f"soffice timed out after {timeout} s\ncommand: {cmd}\nstdout:\n{out}\nstderr:\n{err}"
            ) from None
        except BaseException:
            # Ctrl-C, SIGTERM (as an exception), an error: its own session keeps soffice
            # from the terminal's signals, so it would convert on alone (issue 23: 3.35 GB)
            _kill_group(proc)
            raise
        finally:
            _RUNNING.discard(proc.pid)

    missing = [p for p, o in expected.items() if not o.is_file()]
    if missing:
        raise RuntimeError(
            f"soffice produced no {ext} for {[str(m) for m in missing]} (exit code {proc.returncode})\n"
            f"command: {cmd}\nstdout:\n{out}\nstderr:\n{err}"
        )
    return expected


def _kill_group(proc: subprocess.Popen) -> None:
    """SIGKILL soffice's process group (the wrapper and soffice.bin), reap the wrapper, and
    wait until the group is gone (its profile folder is removed next)."""
    with contextlib.suppress(OSError):          # already gone
        os.killpg(proc.pid, signal.SIGKILL)
    with contextlib.suppress(subprocess.TimeoutExpired, OSError):
        proc.wait(5)
    _wait_group(proc.pid, 5.0)


def recalculate(paths: list[Path], outdir: Path, timeout: float = 300) -> dict[Path, Path]:
    """Open every workbook in LibreOffice, recalculate all formulas, save as xlsx in `outdir`.

    One soffice process for all files (its start-up is most of the cost). Returns
    {resolved input path: output path}; output names are the input names, so inputs must have
    distinct names and must not already live in `outdir`. Raises RuntimeError (with soffice's
    output) if any file was not converted.
    """
    return _convert(paths, outdir, "xlsx:Calc MS Excel 2007 XML", "xlsx", timeout)


def convert_to_xlsx(path: Path, outdir: Path, timeout: float = 120) -> Path:
    """One spreadsheet (.ods, .fods, .xlsx ...) converted to .xlsx in `outdir`, every formula
    recalculated, by a soffice run with its own temporary profile; killed after `timeout`
    seconds (RuntimeError). Returns the .xlsx written."""
    [(_, out)] = _convert([path], outdir, "xlsx:Calc MS Excel 2007 XML", "xlsx", timeout).items()
    return out


def read_values(path: Path, sheet: str | None = None) -> dict[str, object]:
    """{coordinate: cached value} of one sheet (default: the active one), empty cells left out.

    Numbers are int/float, booleans bool, dates datetime (when the cell has a date format),
    errors their code as a string ('#VALUE!', see is_error). A formula that returns "" reads
    as None, i.e. is left out like an empty cell.
    """
    wb = openpyxl.load_workbook(path, data_only=True)
    try:
        ws = wb[sheet] if sheet is not None else wb.active
        return {c.coordinate: c.value for row in ws.iter_rows() for c in row if c.value is not None}
    finally:
        wb.close()


def is_error(v: object) -> bool:
    """True for a spreadsheet error value: '#VALUE!', '#NUM!', '#DIV/0!', ..., or 'Err:502'."""
    return isinstance(v, str) and (v in _ERROR_CODES or _LO_ERROR.fullmatch(v) is not None)


def render_pdf(path: Path, outdir: Path, timeout: float = 300) -> Path:
    """Print a workbook (recalculated) to `outdir`/<name>.pdf with LibreOffice."""
    [(_, pdf)] = _convert([path], outdir, "pdf:calc_pdf_Export", "pdf", timeout).items()
    return pdf


def pdf_to_png(pdf: Path, out_prefix: Path, dpi: int = 110, first_page: int = 1,
               last_page: int = 1) -> list[Path]:
    """Render pages first_page..last_page of `pdf` to PNGs named <out_prefix>-<page>.png.

    Uses pdftoppm (poppler-utils). Returns the files written, in page order.
    """
    exe = shutil.which("pdftoppm")
    if exe is None:
        raise RuntimeError("pdftoppm not found: run `bash tests/setup.sh` (installs poppler-utils)")
    out_prefix = Path(out_prefix).resolve()
    out_prefix.parent.mkdir(parents=True, exist_ok=True)
    written = []
    # Render into a scratch dir so pdftoppm's page-number padding and stale files don't matter.
    with tempfile.TemporaryDirectory(prefix="sheetkin-pdftoppm-") as tmp:
        cmd = [exe, "-png", "-r", str(dpi), "-f", str(first_page), "-l", str(last_page),
               str(Path(pdf).resolve()), str(Path(tmp) / "p")]
        res = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
        pages = sorted(Path(tmp).glob("p-*.png"), key=lambda q: int(q.stem.rsplit("-", 1)[1]))
        if res.returncode != 0 or not pages:
            raise RuntimeError(f"pdftoppm failed ({res.returncode}): {cmd}\n{res.stdout}{res.stderr}")
        for q in pages:
            dest = out_prefix.with_name(f"{out_prefix.name}-{int(q.stem.rsplit('-', 1)[1])}.png")
            shutil.move(q, dest)
            written.append(dest)
    return written
