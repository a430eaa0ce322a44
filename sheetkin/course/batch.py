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
import time
import zipfile
from collections import deque
from collections.abc import Callable, Generator, Iterator
from dataclasses import dataclass, field
from pathlib import Path, PurePosixPath

from sheetkin.files import child_ended, child_started, shown
from sheetkin.kinematics.scene import SceneError
from sheetkin.messages import message

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
                  progress: Callable[[int, Path], None] | None = None, options=None,
                  time_limit: float | None = None) -> Generator[Report, None, None]:
    """Yield validate(path) for every path, in order. jobs: processes (default: one per
    core; at most max_jobs()); 1, or a single file, validates in this process.
    progress(done, path) is called before each report is yielded. options: issued.Options
    (roster, key, ...). time_limit: seconds a file may take (default file_time_limit());
    past it the file gets its one line and the class goes on. An entry of a zip that
    could not be unpacked (submission_files) gets its one line without being validated.
    Close the generator (or let it finish) to stop the workers."""
    from functools import partial

    validate = partial(_validate_one, options=options)
    limit = file_time_limit() if time_limit is None else time_limit
    real = [p for p in paths if str(p) not in _REFUSED]
    jobs = min(jobs or default_jobs(), max_jobs(), len(real)) or 1
    if jobs == 1:
        each: Iterator[Report] = (_in_process(validate, p, limit) for p in real)
    else:
        each = _pooled(real, jobs, validate, None, limit)
    try:
        for i, p in enumerate(paths, 1):
            rep = Report(str(p), error=_REFUSED[str(p)]) if str(p) in _REFUSED else next(each)
            rep.notes += _NOTES.get(str(p), [])
            if progress:       # a file's name on the terminal: a student's, escaped (issue 30)
                progress(i, Path(shown(str(p))))
            yield rep
    finally:
        close = getattr(each, "close", None)
        if close:
            close()


FILE_TIME_LIMIT = 600.0     # seconds one file may take (a book at the cells cap takes ~50 s on a busy VM)


def file_time_limit() -> float:
    """The seconds one file may take: FILE_TIME_LIMIT, or the environment's
    SHEETKIN_FILE_TIME_LIMIT (docs/reliability.md)."""
    try:
        return max(1.0, float(os.environ.get("SHEETKIN_FILE_TIME_LIMIT", FILE_TIME_LIMIT)))
    except ValueError:
        return FILE_TIME_LIMIT


def too_long(path, limit: float) -> str:
    """The one line of a file that took longer than the limit."""
    return (f"{path}: took longer than {limit:g} s (SHEETKIN_FILE_TIME_LIMIT); stopped, this file is not graded "
            "(try it alone: sheetkin validate FILE); the other files were validated")


class _TooLong(BaseException):
    """Raised by the alarm in the middle of a file (a BaseException: no `except Exception` of
    the validator turns it into that book's internal error)."""


def _in_process(validate, path, limit: float) -> Report:
    """validate(path) in this process, stopped by SIGALRM after `limit` seconds (where
    there is one, in the main thread)."""
    import threading
    if not hasattr(signal, "setitimer") or threading.current_thread() is not threading.main_thread():
        return validate(path)

    def alarm(signum, frame):
        raise _TooLong()
    old = signal.signal(signal.SIGALRM, alarm)
    signal.setitimer(signal.ITIMER_REAL, limit)
    try:
        return validate(path)
    except _TooLong:
        return Report(str(path), error=too_long(path, limit))
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, old)


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
        self.started = 0.0                 # when it was given that file (time.monotonic)

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


def _pooled(paths: list[Path], jobs: int, validate, progress, limit: float = FILE_TIME_LIMIT) -> Iterator[Report]:
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
                    w.started = time.monotonic()
                    w.conn.send(paths[w.index])
            busy = [w for w in workers if w.index is not None]
            first = min(w.started for w in busy)
            ready = set(wait([w.conn for w in busy] + [w.process.sentinel for w in busy],
                             timeout=max(0.0, first + limit - time.monotonic()) + 0.05))
            now = time.monotonic()
            for k, w in enumerate(workers):
                late = w.index is not None and now - w.started > limit
                if w.index is None or not (w.conn in ready or w.process.sentinel in ready or late):
                    continue
                rep = None if late and w.conn not in ready else _receive(w)
                if rep is None:               # it died or took too long: this file's error, a fresh worker
                    w.stop(hurry=True)        # reaped: its exit code says how it died
                    _leftovers(w.process.pid)
                    why = too_long(paths[w.index], limit) if late else died(paths[w.index], w.process.exitcode)
                    rep = Report(str(paths[w.index]), error=why)
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
ZIP_MAX_BYTES = 2_000_000_000     # unpacked by a whole run, all its zips (each file has its own gate after)
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


def _escaped(name: str) -> str:
    """A file's name as reports and notes show it (sheetkin.files.shown: a student's name
    with ESC, CR or a bidi override in it is shown escaped)."""
    return shown(name)


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
    if unpack:
        _BUDGET[0] = 0        # the cap holds for the run: every zip of this call together

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
                    add(f, _escaped(str(f)))
        elif unpack and _is_zip(p) and p.is_file():
            for g, shown in _unpack(p, strict):
                add(g, shown)
        else:
            add(p, _escaped(str(p)))
    return out


def _unpack(zpath: Path, strict: bool, shown_as: str | None = None, depth: int = 0) -> list[tuple[Path, str]]:
    """The spreadsheets of a zip, written to a temporary folder (never outside it: absolute
    names and ".." are refused), with their dates, each under a short name of its own (a
    200-letter Cyrillic name is 400 bytes, past a file system's 255; two entries of one
    name are two files). What one student's entry does wrong (too big, a zip bomb, a lying
    header, a zip inside that cannot be read) is that entry's own line (`refused`), and the
    rest of the class is unpacked; a zip inside (a student's work.zip) is unpacked in turn,
    up to ZIP_MAX_DEPTH. The unpacked bytes of the whole run are capped (ZIP_MAX_BYTES),
    judged from the headers and the compression ratio before a byte is written."""
    shown_zip = shown_as or str(zpath)
    try:
        zf = _open_zip(zpath)
    except Exception as e:   # noqa: BLE001 - a crafted central directory: struct.error, ValueError, ...
        raise SceneError(f"{shown(shown_zip)}: not a zip archive this reads ({shown(str(e))})") from None
    with zf:
        infos = zf.infolist()
        if len(infos) > ZIP_MAX_MEMBERS:
            raise SceneError(f"{shown(shown_zip)}: {len(infos):,} entries; a class's zip holds at most "
                             f"{ZIP_MAX_MEMBERS:,}")
        members = []
        for info in infos:
            name = PurePosixPath(_entry_name(info).replace("\\", "/"))
            if info.is_dir() or not (_spreadsheet(Path(name.name)) or _is_zip(Path(name.name))):
                continue
            if name.is_absolute() or ".." in name.parts or not name.parts:
                raise SceneError(f"{shown(shown_zip)}: entry {shown(info.filename)!r} points outside the archive; "
                                 "refused")
            members.append((info, name))
        if not members and strict and depth == 0:
            raise SceneError(f"{shown(shown_zip)}: no spreadsheet files (.xlsx, .xls, .ods) in this zip")
        tmp = tempfile.mkdtemp(prefix="sheetkin-zip-")
        _UNPACKED.append(tmp)
        out: list[tuple[Path, str]] = []
        seen: dict[str, int] = {}
        for k, (info, name) in enumerate(members):
            entry = shown(f"{shown_zip}/{name.as_posix()}")     # ESC, CR, bidi as escapes
            seen[entry] = seen.get(entry, 0) + 1
            if seen[entry] > 1:        # two different files under one name: each its own line, none dropped
                entry += f" (entry {seen[entry]} of this name in the zip)"
            target = Path(tmp, f"{k:05d}", _short_name(name.name))
            problem = _entry_problem(info)
            if problem is None and _is_zip(target) and depth >= ZIP_MAX_DEPTH:
                problem = "a zip inside a zip inside the class's zip; not unpacked (unpack it and validate its files)"
            if problem is None:
                target.parent.mkdir(parents=True, exist_ok=True)
                problem = _unpack_entry(zf, info, target)
            if problem is not None:
                _refuse(target, out, entry, problem)
                continue
            if _name_note(info):
                _NOTES.setdefault(str(target), []).append(_name_note(info))
            _UNPACKED_AS[str(target)] = entry
            stamp = time.mktime((*info.date_time, 0, 0, -1))   # Moodle's date of the submission's file
            os.utime(target, (stamp, stamp))
            if _is_zip(target):
                out += _nested(target, entry, depth)
            else:
                out.append((target, entry))
        return out


ZIP_MAX_RATIO = 200               # unpacked / packed of one entry past 1 MB (the workbook gate's ratio)
ZIP_MAX_DEPTH = 1                 # a zip inside the class's zip is unpacked; one inside that is named
_BUDGET = [0]                     # bytes unpacked in this run (submission_files resets it)
_REFUSED: dict[str, str] = {}     # an entry's placeholder path -> its one line
_NOTES: dict[str, list[str]] = {} # an unpacked file -> notes for its report (a name read as cp866)
_UNPACKED_AS: dict[str, str] = {}  # an unpacked file -> its entry as the teacher knows it (zip/folder/name)


def unpacked_as(path: str) -> str:
    """The name a file unpacked from a zip had there (its Moodle folder in it), else `path`:
    a file is unpacked under a short name of its own, and who handed it in is read from the
    entry's folder (the from-scratch grading asks it inside the worker)."""
    return _UNPACKED_AS.get(str(path), str(path))


def _open_zip(zpath: Path) -> zipfile.ZipFile:
    """The zip, opened; one whose entry is marked UTF-8 but is not (a zipper's slip, or a
    student's crafted name) makes zipfile refuse the whole archive: it is opened again from
    a copy whose bad entries lose that mark, so their names are read as DOS names
    (_entry_name: cp866, said in a note) and the rest of the class is graded."""
    try:
        return zipfile.ZipFile(zpath)
    except UnicodeDecodeError:
        pass
    tmp = tempfile.mkdtemp(prefix="sheetkin-zip-")
    _UNPACKED.append(tmp)
    copy = Path(tmp, "names-unmarked.zip")
    shutil.copyfile(zpath, copy)
    with open(copy, "r+b") as f:
        _unmark_bad_utf8_names(f)
    return zipfile.ZipFile(copy)


def _unmark_bad_utf8_names(f) -> None:
    """Clear the UTF-8 flag (bit 11) of every entry whose name does not decode as UTF-8, in
    its central directory record and in its local header (zipfile compares the two)."""
    data = f.read()
    at = data.rfind(b"PK\x05\x06")                      # the end of central directory
    if at < 0 or at + 22 > len(data):
        return
    count = int.from_bytes(data[at + 10:at + 12], "little")
    pos = int.from_bytes(data[at + 16:at + 20], "little")
    for _ in range(count):
        if data[pos:pos + 4] != b"PK\x01\x02" or pos + 46 > len(data):
            return
        flags = int.from_bytes(data[pos + 8:pos + 10], "little")
        n, extra, comment = (int.from_bytes(data[pos + k:pos + k + 2], "little") for k in (28, 30, 32))
        local = int.from_bytes(data[pos + 42:pos + 46], "little")
        try:
            data[pos + 46:pos + 46 + n].decode("utf-8")
        except UnicodeDecodeError:
            if flags & 0x800:
                f.seek(pos + 8)
                f.write((flags & ~0x800).to_bytes(2, "little"))
                if data[local:local + 4] == b"PK\x03\x04":
                    f.seek(local + 6)
                    f.write((int.from_bytes(data[local + 6:local + 8], "little") & ~0x800).to_bytes(2, "little"))
        pos += 46 + n + extra + comment


def _entry_problem(info: zipfile.ZipInfo) -> str | None:
    """What is wrong with an entry, judged from its headers before a byte is unpacked."""
    if info.flag_bits & 0x1:
        return message("password_protected", what="an encrypted zip entry") + "; unpack it with its password first"
    if info.file_size > ZIP_MAX_FILE_BYTES:
        return f"unpacks to {info.file_size:,} bytes; a workbook is at most {ZIP_MAX_FILE_BYTES:,}; not graded"
    if info.file_size > 2 ** 20 and info.file_size > ZIP_MAX_RATIO * max(info.compress_size, 1):
        return (f"{info.compress_size:,} bytes that unpack to {info.file_size:,} (more than {ZIP_MAX_RATIO} times: "
                "a zip bomb, or a corrupt header); not unpacked, not graded")
    if _BUDGET[0] + info.file_size > ZIP_MAX_BYTES:
        return (f"not unpacked: this run has unpacked {_BUDGET[0]:,} bytes, and at most {ZIP_MAX_BYTES:,} are "
                "unpacked in one run (validate the rest in another run)")
    return None


def _unpack_entry(zf: zipfile.ZipFile, info: zipfile.ZipInfo, target: Path) -> str | None:
    """Unpack one entry to target; its one line if that fails (nothing of it is left)."""
    import zlib
    try:
        with zf.open(info) as src, open(target, "wb") as dst:
            copied = _copy_bounded(src, dst, info.file_size)
    except (zipfile.BadZipFile, OSError, RuntimeError, EOFError, zlib.error, ValueError, NotImplementedError) as e:
        _remove(target)
        return f"cannot be unpacked ({shown(str(e) or type(e).__name__)}; its header may be corrupt); not graded"
    if copied is None:
        _remove(target)
        return "holds more than its header says (a corrupt or forged header); refused, not graded"
    _BUDGET[0] += copied
    return None


def _nested(inner: Path, entry: str, depth: int) -> list[tuple[Path, str]]:
    """A student's work.zip inside the class's zip: its spreadsheets, or its one line."""
    try:
        found = _unpack(inner, False, entry, depth + 1)
    except SceneError as e:
        return _refuse(inner, [], entry, f"a zip inside the class's zip that cannot be used ({e}); not graded")
    finally:
        _remove(inner)
    if not found:
        return _refuse(inner, [], entry, "a zip inside the class's zip with no spreadsheet in it; nothing graded")
    return found


def _refuse(target: Path, out: list, entry: str, why: str) -> list:
    """Add the entry as a file whose report is its one line (validate_many)."""
    placeholder = target.with_name(target.name + ".refused")
    _REFUSED[str(placeholder)] = f"{entry}: {why}"
    out.append((placeholder, entry))
    return out


def _remove(path: Path) -> None:
    import contextlib
    with contextlib.suppress(OSError):
        path.unlink()


def _entry_name(info: zipfile.ZipInfo) -> str:
    """The entry's name: UTF-8 when flagged so (Moodle); unflagged, zipfile read it as
    cp437: UTF-8 without the flag (Info-ZIP, macOS) or else DOS Cyrillic (cp866, a Russian
    Windows' zipper) is tried (_name_note says so)."""
    if info.flag_bits & 0x800 or info.filename.isascii():
        return info.filename
    try:
        raw = info.filename.encode("cp437")
    except UnicodeEncodeError:
        return info.filename
    try:
        return raw.decode("utf-8")
    except UnicodeDecodeError:
        return raw.decode("cp866")


def _name_note(info: zipfile.ZipInfo) -> str:
    if info.flag_bits & 0x800 or info.filename.isascii():
        return ""
    try:
        info.filename.encode("cp437").decode("utf-8")
        return ""
    except (UnicodeEncodeError, UnicodeDecodeError):
        return ("its name in the zip is not marked as UTF-8 and was read as DOS Cyrillic (cp866); "
                f"as stored: {shown(info.filename)!r}")


def _short_name(name: str) -> str:
    """A short, safe file name keeping the suffix (the reader is chosen by it)."""
    import re
    p = PurePosixPath(name)
    stem = re.sub(r"[^\w.-]+", "_", p.stem)[:60].strip("._") or "file"
    return stem + p.suffix.lower()


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
