"""Validating many workbooks: which files (folders, Moodle's zip, each file once), then a
pool of worker processes, reports in the order given.

Each worker process keeps its own caches (the evaluator's parsed formulas, the validator's
generated sheet per structure and reference per variant), so a class's workbooks cost one
reference per variant and worker; the parent keeps only the reports (a Book of a 360-column
workbook is tens of MB and is dropped as soon as its report is made).

The pool is our own, not concurrent.futures': the parent hands each worker one file at a
time, so it always knows which file a worker holds. A worker that dies (the kernel's
out-of-memory killer, a crash in a library) costs that file only: it gets a one-line error,
a new worker takes the next file, and the class is graded. Workers ignore SIGINT (a Ctrl-C
in a terminal reaches the whole process group; the parent decides) and die on SIGTERM;
when the parent stops for any reason (done, an interrupt, an error) it terminates and
reaps every worker, and a worker whose parent vanished exits at its next read.
"""
from __future__ import annotations

import atexit
import os
import shutil
import signal
import tempfile
import zipfile
from collections import deque
from collections.abc import Callable, Generator, Iterator
from dataclasses import dataclass, field
from pathlib import Path, PurePosixPath

from sheetkin.files import child_ended, child_started
from sheetkin.kinematics.scene import SceneError

from .report_model import Report
from .validator import validate as _validate_one

MAX_JOBS_PER_CORE = 2        # --jobs above this many per core only costs memory (docs/reliability.md)


def default_jobs() -> int:
    return os.cpu_count() or 1


def max_jobs() -> int:
    """The most worker processes --jobs may ask for: a few per core (each holds a workbook
    and its caches, ~100-300 MB; more than the cores only adds memory)."""
    return max(4, MAX_JOBS_PER_CORE * default_jobs())


def validate_many(paths: list[Path], jobs: int | None = None,
                  progress: Callable[[int, Path], None] | None = None, options=None) -> Generator[Report, None, None]:
    """Yield validate(path) for every path, in order. jobs: processes (default: one per
    core; at most max_jobs()); 1, or a single file, validates in this process.
    progress(done, path) is called before each report is yielded. options: issued.Options
    (roster, key, ...). Close the generator (or let it finish) to stop the workers."""
    from functools import partial

    validate = partial(_validate_one, options=options)
    jobs = min(jobs or default_jobs(), max_jobs(), len(paths)) or 1
    if jobs == 1:
        for i, p in enumerate(paths, 1):
            rep = validate(p)
            if progress:
                progress(i, p)
            yield rep
        return
    yield from _pooled(paths, jobs, validate, progress)


def _stopped(signum, frame):
    # SIGTERM from the parent (or a second Ctrl-C there): unwind, so that a LibreOffice run of
    # this worker is killed and its temporary folders removed (sheetkin.xlsx.libreoffice)
    raise SystemExit(128 + signum)


def _worker(conn, validate) -> None:
    """A worker's loop: a path in, its report out, until the parent closes the pipe."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, _stopped)
    while True:
        try:
            path = conn.recv()
        except (EOFError, OSError):
            return                     # the parent is done (or gone)
        conn.send(validate(path))


class _Worker:
    def __init__(self, ctx, validate):
        parent, child = ctx.Pipe()
        self.conn = parent
        self.process = ctx.Process(target=_worker, args=(child, validate), daemon=True)
        self.process.start()
        child_started(self.process.pid)
        child.close()
        self.index: int | None = None      # the file it holds

    def stop(self, hurry: bool) -> None:
        """Close its pipe (it exits at its next read) and reap it; terminate it if it is
        still busy (hurry: at once), kill it if SIGTERM did not end it."""
        self.conn.close()
        self.process.join(0 if hurry else 2)
        if self.process.is_alive():
            self.process.terminate()
            self.process.join(2)
        if self.process.is_alive():
            self.process.kill()
            self.process.join()
        child_ended(self.process.pid)


def died(path: Path, exitcode: int | None) -> str:
    """The one line of a file whose worker died while validating it."""
    if exitcode is not None and exitcode < 0:
        try:
            how = f"killed by {signal.Signals(-exitcode).name}"
        except ValueError:
            how = f"killed by signal {-exitcode}"
        if -exitcode == signal.SIGKILL:
            how += " (the system's out-of-memory killer, or a kill -9)"
    else:
        how = f"ended with exit code {exitcode}"
    return (f"{path}: the process validating it was {how}; this file is not graded (try it alone: "
            "sheetkin validate FILE); the other files were validated")


def _pooled(paths: list[Path], jobs: int, validate, progress) -> Iterator[Report]:
    import multiprocessing
    from multiprocessing.connection import wait
    # fork: the workers start with sheetkin imported (spawn would re-import it in each);
    # where fork is missing (Windows, macOS default) the platform's method is used
    method = "fork" if "fork" in multiprocessing.get_all_start_methods() else None
    ctx = multiprocessing.get_context(method)
    # files of one variant next to each other (sorted names) mostly go to one worker in
    # turn and share its reference
    todo = deque(range(len(paths)))
    done: dict[int, Report] = {}
    workers: list[_Worker] = []
    shown = 0
    finished = False
    try:
        workers = [_Worker(ctx, validate) for _ in range(jobs)]
        while shown < len(paths):
            for w in workers:
                if w.index is None and todo:
                    w.index = todo.popleft()
                    w.conn.send(paths[w.index])
            busy = [w for w in workers if w.index is not None]
            ready = set(wait([w.conn for w in busy] + [w.process.sentinel for w in busy]))
            for k, w in enumerate(workers):
                if w.index is None or not (w.conn in ready or w.process.sentinel in ready):
                    continue
                rep = _receive(w)
                if rep is None:               # it died: this file's error, a fresh worker
                    w.stop(hurry=True)        # reaped: its exit code says how it died
                    _leftovers(w.process.pid)
                    rep = Report(str(paths[w.index]), error=died(paths[w.index], w.process.exitcode))
                    workers[k] = _Worker(ctx, validate) if todo else w
                done[w.index] = rep
                w.index = None
            while shown in done:
                rep = done.pop(shown)
                shown += 1
                if progress:
                    progress(shown, paths[shown - 1])
                yield rep
        finished = True
    finally:
        for w in workers:
            w.stop(hurry=not finished)


def _leftovers(pid: int | None) -> None:
    """A worker killed outright (SIGKILL) cleaned nothing up: a LibreOffice it was running
    converts on in its own session, and its profile stays."""
    from sheetkin.xlsx.libreoffice import stop_orphans
    if pid is not None:
        stop_orphans(pid)


def _receive(w: _Worker) -> Report | None:
    """The worker's report, or None if it died (its pipe closed without one). wait() said
    its pipe or its sentinel is ready: alive, its pipe holds the report (or the EOF of a
    death just now); dead, a report it sent before dying may still be in the pipe."""
    try:
        if w.process.is_alive() or w.conn.poll(0.1):
            return w.conn.recv()
    except (EOFError, OSError):
        return None
    return None


# --------------------------------------------------------------------------- which files
SPREADSHEET_SUFFIXES = (".xlsx", ".xlsm", ".xltx", ".xltm", ".xls", ".ods", ".fods")
ZIP_MAX_MEMBERS = 10_000          # a class of 300 with a few files each
ZIP_MAX_BYTES = 2_000_000_000     # unpacked spreadsheets of one zip (each file has its own gate after)
ZIP_MAX_FILE_BYTES = 50 * 2 ** 20 # one unpacked file: the gate's max_file_bytes
_UNPACKED: list = []              # temporary folders of unpacked zips, removed at exit


@dataclass
class Submissions:
    """The files to validate, each once, in order; `shown`: the name the teacher knows a
    file by when it was unpacked from a zip ("class.zip/Иван Иванов_12_assignsubmission_file_/a.xlsx")."""
    files: list[Path] = field(default_factory=list)
    shown: dict[str, str] = field(default_factory=dict)
    twice: list[str] = field(default_factory=list)       # given more than once: validated once

    def name(self, path) -> str:
        return self.shown.get(str(path), str(path))


def _spreadsheet(p: Path) -> bool:
    return p.suffix.lower() in SPREADSHEET_SUFFIXES and not p.name.startswith(("~$", ".~lock"))


def _is_zip(p: Path) -> bool:
    return p.suffix.lower() == ".zip"


def submission_files(paths, strict: bool = True, unpack: bool = True) -> Submissions:
    """The spreadsheets among `paths` (files; folders searched recursively; a .zip, such as
    Moodle's "download all submissions", unpacked to a temporary folder as it is, its folder
    names kept). A file named twice (also through a link, or a folder and a file in it) is
    validated once. strict: a folder or zip without spreadsheets is an error."""
    out = Submissions()
    seen: dict[tuple, str] = {}

    def add(f: Path, shown: str) -> None:
        key: tuple
        try:
            st = f.stat()
            key = (st.st_dev, st.st_ino)
        except OSError:
            key = ("missing", str(f.resolve()) if f.is_absolute() else os.path.abspath(f))
        if key in seen:
            out.twice.append(shown)
            return
        seen[key] = shown
        out.files.append(f)
        if shown != str(f):
            out.shown[str(f)] = shown
    for p in map(Path, paths):
        if p.is_dir():
            found = sorted(f for f in p.rglob("*") if f.is_file() and (_spreadsheet(f) or (unpack and _is_zip(f))))
            if not found and strict:
                raise SceneError(f"{p}: no spreadsheet files (.xlsx, .xls, .ods) in this folder")
            for f in found:
                if _is_zip(f):
                    for g, shown in _unpack(f, strict):
                        add(g, shown)
                else:
                    add(f, str(f))
        elif unpack and _is_zip(p) and p.is_file():
            for g, shown in _unpack(p, strict):
                add(g, shown)
        else:
            add(p, str(p))
    return out


def _unpack(zpath: Path, strict: bool) -> list[tuple[Path, str]]:
    """The spreadsheets of a zip, written to a temporary folder under their own relative
    names (never outside it: absolute names and ".." are refused), with their dates."""
    import time
    try:
        zf = zipfile.ZipFile(zpath)
    except (zipfile.BadZipFile, OSError) as e:
        raise SceneError(f"{zpath}: not a zip archive this reads ({e})") from None
    with zf:
        infos = zf.infolist()
        if len(infos) > ZIP_MAX_MEMBERS:
            raise SceneError(f"{zpath}: {len(infos):,} entries; a class's zip holds at most {ZIP_MAX_MEMBERS:,}")
        members = []
        for info in infos:
            name = PurePosixPath(info.filename.replace("\\", "/"))
            if info.is_dir() or not _spreadsheet(Path(name.name)):
                continue
            if name.is_absolute() or ".." in name.parts or not name.parts:
                raise SceneError(f"{zpath}: entry {info.filename!r} points outside the archive; refused")
            if info.flag_bits & 0x1:
                raise SceneError(f"{zpath}: entry {info.filename!r} is password-protected (an encrypted zip); "
                                 "unpack it with its password first")
            if info.file_size > ZIP_MAX_FILE_BYTES:
                raise SceneError(f"{zpath}: entry {info.filename!r} unpacks to {info.file_size:,} bytes; "
                                 f"a workbook is at most {ZIP_MAX_FILE_BYTES:,}")
            members.append((info, name))
        if sum(i.file_size for i, _ in members) > ZIP_MAX_BYTES:
            raise SceneError(f"{zpath}: its spreadsheets unpack to more than {ZIP_MAX_BYTES:,} bytes")
        if not members and strict:
            raise SceneError(f"{zpath}: no spreadsheet files (.xlsx, .xls, .ods) in this zip")
        tmp = tempfile.mkdtemp(prefix="sheetkin-zip-")
        _UNPACKED.append(tmp)
        out = []
        for info, name in members:
            target = Path(tmp, *name.parts)
            target.parent.mkdir(parents=True, exist_ok=True)
            try:
                with zf.open(info) as src, open(target, "wb") as dst:
                    copied = _copy_bounded(src, dst, info.file_size)
            except (zipfile.BadZipFile, OSError, RuntimeError, EOFError) as e:
                raise SceneError(f"{zpath}: entry {info.filename!r} cannot be unpacked ({e})") from None
            if copied is None:
                raise SceneError(f"{zpath}: entry {info.filename!r} is longer than its header says; refused")
            stamp = time.mktime((*info.date_time, 0, 0, -1))   # Moodle's date of the submission's file
            os.utime(target, (stamp, stamp))
            out.append((target, f"{zpath}/{name.as_posix()}"))
        return out


def _copy_bounded(src, dst, size: int) -> int | None:
    """Copy at most `size` bytes; None when the entry holds more (a lying header)."""
    done = 0
    while True:
        block = src.read(1 << 20)
        if not block:
            return done
        done += len(block)
        if done > size:
            return None
        dst.write(block)


@atexit.register
def _remove_unpacked() -> None:
    for tmp in _UNPACKED:
        shutil.rmtree(tmp, ignore_errors=True)
