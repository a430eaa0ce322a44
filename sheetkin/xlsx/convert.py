"""Files that are not .xlsx, before the reader sees them: password sniffing (an encrypted
Office file, an .xls with FILEPASS, an OpenDocument file with encrypted entries), telling
OpenDocument spreadsheets (.ods, .fods) and Excel 97-2003 books (.xls) apart, the
OpenDocument gate (size, zip, and what repeated rows and cells expand to, before LibreOffice
sees the file), and the conversion to .xlsx through LibreOffice (one file, or a class's
files in one run).

Separate from cells.py (which reads an .xlsx's cells) because this is about the file as a
whole and another program: it reads only a file's first bytes, its OLE directory or its
OpenDocument content, never cells. cells.read_book asks it what a file is and, for
OpenDocument or .xls, for the converted .xlsx (`converted`), which it then reads like any.
"""
from __future__ import annotations

import io
import os
import shutil
import stat
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

from sheetkin.messages import message

from .package import Limits, UnusableWorkbook

# ----------------------------------------------------------------- passwords, old Excel (.xls)
_OLE = b"\xd0\xcf\x11\xe0\xa1\xb1\x1a\xe1"
_SNIFF_BYTES = 1 << 16      # what is read to tell a file's kind (never the whole file)


def _head(path, n: int = _SNIFF_BYTES) -> bytes:
    """The file's first n bytes; b"" for anything but a regular file (a FIFO would block)."""
    import stat
    try:
        if not stat.S_ISREG(os.stat(path).st_mode):
            return b""
        with open(path, "rb") as fh:
            return fh.read(n)
    except (OSError, ValueError):
        return b""              # the gate says what is wrong with the path


def _ole_streams(path) -> dict[str, tuple[int, int]]:
    """{stream name: (first sector's offset, size)} of an OLE compound file (.xls, or an
    encrypted Office file), from its first directory sector; {} when it is not one."""
    import struct
    head = _head(path, 512)          # a regular file's, or b"" (then nothing else is opened)
    if len(head) < 512 or not head.startswith(_OLE):
        return {}
    shift = struct.unpack_from("<H", head, 0x1E)[0]
    if shift not in (9, 12):
        return {}
    size = 1 << shift
    first_dir = struct.unpack_from("<I", head, 0x30)[0]
    try:
        with open(path, "rb") as fh:
            fh.seek((first_dir + 1) * size)
            block = fh.read(size)
    except (OSError, ValueError, OverflowError):
        return {}
    out = {}
    for k in range(0, len(block) - 127, 128):
        entry = block[k:k + 128]
        n = struct.unpack_from("<H", entry, 64)[0]
        if entry[66] not in (1, 2, 5) or not 2 <= n <= 64:
            continue
        name = entry[:n - 2].decode("utf-16-le", "replace")
        start, length = struct.unpack_from("<II", entry, 116)
        out[name] = ((start + 1) * size, length)
    return out


def _biff_filepass(path, offset: int) -> bool:
    """Whether a BIFF workbook stream starting at `offset` is encrypted: its first record
    is BOF (0x0809) and the next FILEPASS (0x002F), as Excel writes a password-protected
    .xls (only the stream's first sector is read)."""
    import struct
    try:
        with open(path, "rb") as fh:
            fh.seek(offset)
            data = fh.read(512)
    except (OSError, ValueError, OverflowError):
        return False
    if len(data) < 8:
        return False
    kind, length = struct.unpack_from("<HH", data, 0)
    if kind != 0x0809 or 4 + length + 4 > len(data):
        return False
    return struct.unpack_from("<H", data, 4 + length)[0] == 0x002F


def is_old_excel(path) -> bool:
    """An Excel 97-2003 workbook (.xls, BIFF in an OLE file): LibreOffice converts it."""
    streams = _ole_streams(path)
    return any(n in streams for n in ("Workbook", "Book")) and "EncryptedPackage" not in streams


def password_protected(path) -> str:
    """What kind of password-protected file `path` is ("" when it is not one): an
    encrypted Office file (.xlsx saved with a password: OLE with EncryptedPackage), an
    .xls with FILEPASS, an OpenDocument file with encrypted entries (its manifest)."""
    head = _head(path, 8)
    if head.startswith(_OLE):
        streams = _ole_streams(path)
        if "EncryptedPackage" in streams or "EncryptionInfo" in streams:
            return message("encrypted_excel_workbook")
        for name in ("Workbook", "Book"):
            if name in streams and streams[name][1] >= 4096 and _biff_filepass(path, streams[name][0]):
                return message("encrypted_xls_workbook")
        return ""
    if head.startswith(b"PK\x03\x04") and is_opendocument(path):
        import zipfile
        try:
            with zipfile.ZipFile(path) as zf:
                info = zf.getinfo("META-INF/manifest.xml")
                if info.file_size > 1 << 20:
                    return ""
                if b"encryption-data" in zf.read(info):
                    return message("encrypted_opendocument_spreadsheet")
        except (zipfile.BadZipFile, KeyError, OSError, RuntimeError, ValueError, EOFError):
            return ""
    return ""


# ----------------------------------------------------------------- OpenDocument (.ods, .fods)
_ODS_MIME = b"application/vnd.oasis.opendocument.spreadsheet"


def is_opendocument(path) -> bool:
    """Whether the file is an OpenDocument spreadsheet: a zip whose first member is its
    mimetype (.ods, whatever the file is called), or flat XML (.fods)."""
    p = Path(path)
    try:
        # non-blocking, and only a regular file: a FIFO given as a book would otherwise wait
        # here forever for a writer (the gate, open_package, refuses it in one line)
        fd = os.open(p, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_BINARY", 0))
        with open(fd, "rb") as fh:
            if not stat.S_ISREG(os.fstat(fh.fileno()).st_mode):
                return False
            head = fh.read(4096)
    except OSError:
        return False                 # the gate says what is wrong with the path
    if head.startswith(b"PK\x03\x04"):
        return head[30:38] == b"mimetype" and _ODS_MIME in head[38:200]
    return p.suffix.lower() == ".fods" or (b"<office:document" in head and _ODS_MIME in head)


@contextmanager
def converted(path, limits: Limits = Limits(), timeout: float = 120) -> Iterator[Path]:
    """The .xlsx LibreOffice makes of an OpenDocument spreadsheet or an .xls: LibreOffice
    (its own temporary profile, a time limit) converts a copy of the file in a temporary
    folder, removed when the `with` block ends; the original is only read. Without
    LibreOffice: refused, with the command that converts it. A file that
    `convert_opendocument` converted already gives its converted copy."""
    from . import libreoffice
    shown = str(path)
    how = f"convert it to .xlsx: soffice --headless --convert-to xlsx {shown!r}"
    what = "an Excel 97-2003 workbook (.xls)" if is_old_excel(path) else "an OpenDocument spreadsheet"
    size = Path(path).stat().st_size
    if size > limits.max_file_bytes:
        raise UnusableWorkbook(shown, f"{what} of {size} bytes",
                               f"at most {limits.max_file_bytes} bytes")
    done = _CONVERTED.get(_signature(path))
    if done is not None and done.is_file():
        yield done
        return
    if not is_old_excel(path):        # the gate parses OpenDocument only (an .xls is BIFF), as _convert_batch
        check_opendocument(path, limits)
    if libreoffice.soffice_path() is None:
        raise UnusableWorkbook(shown, f"{what}, and LibreOffice (soffice) is not installed to read it", how)
    with libreoffice.scratch_folder("sheetkin-ods-") as tmp:
        src = tmp / "in"
        src.mkdir()
        copy = src / ("book" + _odf_suffix(path))
        shutil.copyfile(path, copy)
        try:
            out = libreoffice.convert_to_xlsx(copy, tmp / "out", timeout)
        except (RuntimeError, OSError) as e:
            reason = message("timed_out") if "timed out" in str(e) else message("failed")
            raise UnusableWorkbook(shown, message("conversion_failed", how=reason), how) from None
        yield out


def _odf_suffix(path) -> str:
    """The suffix LibreOffice is given the copy under (it picks its reader by content)."""
    if is_old_excel(path):
        return ".xls"
    return ".fods" if Path(path).suffix.lower() == ".fods" else ".ods"


def _signature(path) -> tuple:
    """A file as it is now: its resolved name, size and modification time."""
    st = Path(path).stat()
    return str(Path(path).resolve()), st.st_size, st.st_mtime_ns


_CONVERTED: dict = {}      # _signature(original) -> its .xlsx made by convert_opendocument
_BATCH_DIRS: list = []     # their temporary folders, removed when the process ends


def convert_opendocument(paths, limits: Limits = Limits(), *, timeout_per_file: float = 60,
                         note=None) -> int:
    """Convert every OpenDocument spreadsheet among `paths` to .xlsx in ONE LibreOffice run
    (its start-up is most of the time a file costs: a class's .ods files, 2-4 s each one
    by one); read_book then reads the converted copies, as long as the originals do not
    change. Copies are converted, in a temporary folder removed when the process ends.
    If the run fails, nothing is kept: read_book converts each file alone (and says what
    is wrong with it). `note(text)` is told before the run. Returns how many were converted."""
    try:
        return _convert_batch(paths, limits, timeout_per_file, note)
    except Exception:       # noqa: BLE001 - an optimisation only: each file is then converted alone
        return 0


def _convert_batch(paths, limits: Limits, timeout_per_file: float, note) -> int:
    from . import libreoffice
    todo = []
    for p in paths:
        try:
            if ((is_opendocument(p) or is_old_excel(p)) and not password_protected(p)
                    and Path(p).stat().st_size <= limits.max_file_bytes):
                if is_opendocument(p):
                    check_opendocument(p, limits)    # refused ones are converted (refused) alone
                todo.append(p)
        except (OSError, UnusableWorkbook):
            continue
    if len(todo) < 2 or libreoffice.soffice_path() is None:
        return 0
    if note is not None:
        note(f"{len(todo)} OpenDocument spreadsheets: converting them to .xlsx with LibreOffice (one run)")
    tmp = tempfile.TemporaryDirectory(prefix="sheetkin-ods-batch-")
    _BATCH_DIRS.append(tmp)
    libreoffice.keep_folder(tmp.name)
    src = Path(tmp.name) / "in"
    src.mkdir()
    copies = {}
    for i, p in enumerate(todo):
        copy = src / f"book{i}{_odf_suffix(p)}"
        try:
            shutil.copyfile(p, copy)
        except OSError:
            continue
        copies[copy.resolve()] = (p, _signature(p))
    try:
        outputs = libreoffice.recalculate(list(copies), Path(tmp.name) / "out", 60 + timeout_per_file * len(copies))
    except (RuntimeError, OSError, ValueError):
        return 0
    for copy, out in outputs.items():
        _CONVERTED[copies[copy][1]] = out
    return len(outputs)


# ----------------------------------------------------------------- the OpenDocument gate
_ODF_TABLE = "urn:oasis:names:tc:opendocument:xmlns:table:1.0"
_ODF_OFFICE = "urn:oasis:names:tc:opendocument:xmlns:office:1.0"
_ROW, CELL_REF, _COVERED = (f"{{{_ODF_TABLE}}}{t}" for t in ("table-row", "table-cell", "covered-table-cell"))
_ROWS_REP, _COLS_REP = f"{{{_ODF_TABLE}}}number-rows-repeated", f"{{{_ODF_TABLE}}}number-columns-repeated"
_VALUE_TYPE, _FORMULA = f"{{{_ODF_OFFICE}}}value-type", f"{{{_ODF_TABLE}}}formula"
_TABLE = f"{{{_ODF_TABLE}}}table"


def check_opendocument(path, limits: Limits = Limits()) -> None:
    """The gate an OpenDocument spreadsheet passes before LibreOffice sees it (a 1,337-byte
    .fods repeating one row a million times took LibreOffice to 3.7 GB): the file's size; for
    .ods the zip's parts (count, sizes, ratio) as open_package checks an .xlsx; then one
    streaming pass over the content (defusedxml: no DTD, no entities) counting what the
    repeat attributes expand to: rows and columns up to the last cell holding something,
    and those cells, all sheets together, within the .xlsx limits (max_rows, max_cols,
    max_cells). Styled emptiness repeated to the sheet's end costs nothing and passes."""
    import zipfile

    shown = str(path)

    def fail(problem: str, expected: str):
        raise UnusableWorkbook(shown, problem, expected)
    try:
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_BINARY", 0))
        with open(fd, "rb") as fh:
            st = os.fstat(fh.fileno())
            if not stat.S_ISREG(st.st_mode):
                fail("is not a regular file", "expected an OpenDocument spreadsheet file")
            if st.st_size > limits.max_file_bytes:
                fail(f"an OpenDocument spreadsheet of {st.st_size:,} bytes",
                     f"at most {limits.max_file_bytes:,} bytes (sheetkin's limit for a workbook)")
            data = fh.read(limits.max_file_bytes + 1)
    except OSError as e:
        fail(f"cannot be read ({e.strerror or e})", "expected a readable spreadsheet file")
    if len(data) > limits.max_file_bytes:
        fail("more than the size limit", f"at most {limits.max_file_bytes:,} bytes")
    if data.startswith(b"PK"):
        try:
            archive = zipfile.ZipFile(io.BytesIO(data))
            infos = archive.infolist()
        except (zipfile.BadZipFile, zipfile.LargeZipFile, EOFError, OSError, ValueError, NotImplementedError) as e:
            fail(f"a damaged .ods file ({str(e)[:100]})", "expected an OpenDocument spreadsheet saved whole")
        if len(infos) > limits.max_parts:
            fail(f"{len(infos):,} parts in the .ods zip", f"at most {limits.max_parts:,}")
        total = 0
        for info in infos:
            total += info.file_size
            ratio = info.file_size / max(1, info.compress_size)
            if info.file_size > limits.max_part_bytes or total > limits.max_total_bytes:
                fail(f"{info.filename[:100]} inflates to {info.file_size:,} bytes",
                     f"at most {limits.max_part_bytes:,} a part, {limits.max_total_bytes:,} in all")
            if info.file_size > limits.ratio_min_bytes and ratio > limits.max_ratio:
                fail(f"{info.filename[:100]} inflates {ratio:.0f} times (a zip bomb's mark)",
                     f"at most {limits.max_ratio:g}:1")
        if "content.xml" not in archive.namelist():
            fail("an .ods file without content.xml", "expected an OpenDocument spreadsheet")
        stream = archive.open("content.xml")
    else:
        stream = io.BytesIO(data)
    _check_odf_expansion(stream, shown, limits)


def _check_odf_expansion(stream, shown: str, limits: Limits) -> None:
    import defusedxml.ElementTree as DET
    from defusedxml import DefusedXmlException

    cells = 0
    row = last_row = 0
    try:
        for event, el in DET.iterparse(stream, events=("start", "end")):
            if event == "start":
                if el.tag == _TABLE:
                    row = 0
                continue
            if el.tag != _ROW:
                continue
            reps = _repeat(el.get(_ROWS_REP))
            col = last_col = held = 0
            for c in el:
                if c.tag not in (CELL_REF, _COVERED):
                    continue
                n = _repeat(c.get(_COLS_REP))
                col += n
                if c.get(_VALUE_TYPE) is not None or c.get(_FORMULA) is not None or len(c):
                    held += n
                    last_col = col
            if held:
                cells += held * reps
                last_row = row + reps
                if last_col > limits.max_cols or last_row > limits.max_rows or cells > limits.max_cells:
                    raise UnusableWorkbook(
                        shown, f"its repeated rows and cells expand to {last_row:,} rows, {last_col:,} "
                        f"columns, {cells:,} cells holding something",
                        f"at most {limits.max_rows:,} rows, {limits.max_cols:,} columns and "
                        f"{limits.max_cells:,} cells (sheetkin's limits for a workbook)")
            row += reps
            el.clear()
    except UnusableWorkbook:
        raise
    except (DET.ParseError, DefusedXmlException, ValueError, EOFError, OSError) as e:
        raise UnusableWorkbook(shown, f"its content is not well-formed XML or is refused ({type(e).__name__}: "
                               f"{str(e)[:120]})", "an OpenDocument spreadsheet as a spreadsheet program "
                               "saves it") from None


def _repeat(text: str | None) -> int:
    if text is None:
        return 1
    try:
        return max(1, int(text))
    except ValueError:
        return 1
