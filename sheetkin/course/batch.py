"""Validating many workbooks: which files (folders, Moodle's zip, each file once), then a
process pool over every core, reports in the order given.

Each worker process keeps its own caches (the evaluator's parsed formulas, the validator's
generated sheet per structure and reference per variant), so a class's workbooks cost one
reference per variant and worker; the parent keeps only the reports (a Book of a 360-column
workbook is tens of MB and is dropped as soon as its report is made).
"""
from __future__ import annotations

import atexit
import os
import shutil
import tempfile
import zipfile
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from pathlib import Path, PurePosixPath

from sheetkin.kinematics.scene import SceneError


def default_jobs() -> int:
    return os.cpu_count() or 1


def validate_many(paths: list[Path], jobs: int | None = None,
                  progress: Callable[[int, Path], None] | None = None, options=None) -> Iterator:
    """Yield validate(path) for every path, in order. jobs: processes (default: one per
    core); 1, or a single file, validates in this process. progress(done, path) is called
    before each report is yielded. options: issued.Options (roster, key, ...)."""
    from functools import partial

    from .validator import validate as _validate_one
    validate = partial(_validate_one, options=options)
    jobs = min(jobs or default_jobs(), len(paths)) or 1
    if jobs == 1:
        for i, p in enumerate(paths, 1):
            rep = validate(p)
            if progress:
                progress(i, p)
            yield rep
        return
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor
    # fork: the workers start with sheetkin imported (spawn would re-import it in each);
    # where fork is missing (Windows, macOS default) the platform's method is used
    method = "fork" if "fork" in multiprocessing.get_all_start_methods() else None
    with ProcessPoolExecutor(jobs, mp_context=multiprocessing.get_context(method)) as pool:
        # small chunks keep the workers evenly busy; files of one variant next to each
        # other (sorted names) mostly land in one worker and share its reference
        for i, (p, rep) in enumerate(zip(paths, pool.map(validate, paths, chunksize=2), strict=False), 1):
            if progress:
                progress(i, p)
            yield rep


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
