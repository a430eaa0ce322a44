"""Untrusted .xlsx input: a read-only, checked view of a workbook's zip package.

Workbooks that students filled in (with Excel, LibreOffice, ...) are untrusted input.
`open_package(path)` reads the file once (read-only, never written), checks it and returns a
`Package`; anything unusable raises `UnusableWorkbook`, whose str() is one line in the
project's style, ``<path>: <what is wrong>; <what was expected>``, never a traceback.

Refused: a missing path or a directory; an empty or oversized file; not a zip archive (with a
hint for an old binary .xls, a password-protected workbook, XML/HTML or plain text); an
OpenDocument (.ods) file; a corrupt or truncated zip (bad CRC-32, truncated data, a header
that lies about a part's size); encrypted entries; not a spreadsheet package (no
[Content_Types].xml or no workbook part; .xlsb, .docx and .pptx are named); macros (.xlsm,
.xltm, .xlam, xl/vbaProject.bin, Excel 4 macro sheets, a macro-enabled content type);
external links (xl/externalLinks/ parts, externalLink relationships, any TargetMode="External"
relationship other than a hyperlink); too many parts; too much uncompressed data or a zip-bomb
compression ratio; any XML part with a DTD or entity declarations (entity bombs) or declared in
an encoding other than UTF-8/UTF-16. (A worksheet's <dimension ref> is only the writer's
claim, A1:XFD1048576 for styled emptiness: the row/column limits apply to cells that hold
something, which the reader counts with `check_dimension`'s limits.)

Checks run cheapest first, so a zip bomb is refused before anything is inflated:

1. the path: missing, a directory, not a regular file, empty, larger than max_file_bytes;
2. the container: OLE header (.xls / encrypted workbook), not a zip, corrupt or truncated
   zip, an OpenDocument file;
3. the zip's central directory only (nothing inflated): duplicate names, encrypted entries,
   unsupported compression, not a spreadsheet package, macros (by part name and file
   extension), external link parts, too many parts, declared sizes and ratios;
4. one streaming pass over every part (inflated in 1 MiB chunks, never trusting the
   headers: the real byte count is enforced while inflating, and it, the end of the deflate
   stream and the CRC-32 must match the central directory), scanning each XML part for
   ``<!DOCTYPE`` / ``<!ENTITY`` (UTF-8 and UTF-16) and refusing an XML declaration of any
   encoding but UTF-8 or UTF-16 (the standard's two; Python's expat would otherwise also
   read single-byte code pages, or fail on UTF-32 with a ValueError, not a ParseError);
5. the content, parsed with defusedxml: macro-enabled content types, macro and external
   relationships, the workbook's sheets.

Once checks 1-4 passed, every part's real size and CRC equal what the zip's directory says,
so any zip reader (zipfile, openpyxl) sees exactly the bytes that were checked. To make sure
of it, hand openpyxl the checked bytes, not the path (the file could change in between):
``openpyxl.load_workbook(io.BytesIO(pkg.data))``.

Limits (`Limits`, all per workbook file; MB = 1,000,000 bytes):

=================  ===========  ============================================================
field              default      meaning
=================  ===========  ============================================================
max_file_bytes     50 MB        size of the .xlsx file on disk (compressed)
max_part_bytes     100 MB       one part (zip member) uncompressed
max_total_bytes    300 MB       all parts together uncompressed
max_ratio          200          uncompressed / compressed size of one part (zip-bomb
                                signal); Excel's and LibreOffice's XML compresses 5-20x,
                                deflate's ceiling is about 1030x
ratio_min_bytes    1 MB         max_ratio applies only to parts larger than this
max_parts          2000         members in the zip (a generated workbook has about 20)
max_rows           100,000      rows of one worksheet: the last row of a cell that holds
                                something (counted by the reader; styled empty rows and
                                the <dimension ref> do not count)
max_cols           4,000        columns of one worksheet (likewise; LibreOffice's whole
                                width is 1024, Excel's 16384)
max_cells          2,000,000    cells that hold a value or a formula, all sheets together
                                (the cells as read cost ~150-300 bytes each)
max_used_cells     10,000,000   the evaluator's cells: rows x columns from A1 to the last
                                cell that holds something, all sheets together
max_reads          400,000,000  cells the evaluator reads for all formulas together (a
                                range clipped to the used range; its time is about this)
max_formula_chars  2,000,000    characters of formula text the evaluator parses: one
                                formula per run of cells filled from a neighbour, every
                                other formula on its own (parsed trees are ~30 bytes a
                                character)
=================  ===========  ============================================================
"""
from __future__ import annotations

import io
import os
import posixpath
import re
import stat
import struct
import zipfile
import zlib
from collections.abc import Callable, Iterable, Iterator
from dataclasses import dataclass
from pathlib import PurePath
from typing import NamedTuple, NoReturn
from urllib.parse import unquote
from xml.etree.ElementTree import Element, ParseError

import defusedxml
import defusedxml.ElementTree as _DET

from sheetkin.messages import message

from .errors import SpreadsheetError

__all__ = ["Limits", "Package", "SheetPart", "UnusableWorkbook", "check_dimension",
           "check_openpyxl_safe", "open_package", "sheet_dimension", "sheet_parts"]

MB = 1_000_000
_CHUNK = 1 << 20            # inflate output per step
_IN_CHUNK = 1 << 16         # compressed input per step
_DIMENSION_PREFIX = 1 << 16  # <dimension> is near the top of a worksheet part

_OLE_MAGIC = b"\xd0\xcf\x11\xe0\xa1\xb1\x1a\xe1"
_LOCAL_HEADER = struct.Struct("<4s5H3L2H")  # sig, version, flags, method, time, date, crc, csize, usize, nlen, xlen
_MACRO_EXTENSIONS = (".xlsm", ".xltm", ".xlam")
_DTD_MARKERS = tuple(m.encode(enc) for m in ("<!DOCTYPE", "<!ENTITY")
                     for enc in ("utf-8", "utf-16-le", "utf-16-be"))
_DTD_OVERLAP = max(len(m) for m in _DTD_MARKERS) - 1


def _has_dtd(tail: bytes, chunk: bytes) -> bool:
    """Whether a marker of _DTD_MARKERS lies in tail + chunk (tail: the last _DTD_OVERLAP
    bytes before the chunk), without making that copy of each 1 MB chunk (issue 32): a
    marker lies in the chunk, or starts in the tail and ends within the chunk's first
    _DTD_OVERLAP bytes. Every marker holds a "!" (in UTF-8 and in UTF-16), looked for
    first: a rare byte in most parts, one fast search (17 ms less for the 360-column
    shaper, issue 32)."""
    seam = tail + chunk[:_DTD_OVERLAP]
    return (b"!" in chunk or b"!" in seam) and any(m in chunk or m in seam for m in _DTD_MARKERS)


_XML_EXTENSIONS = ("xml", "rels", "vml")
_DIMENSION_RE = re.compile(
    rb"<(?:[A-Za-z_][\w.-]*:)?dimension\b[^>]*?\bref\s*=\s*[\"']([^\"']*)[\"']")
_DECLARATION_RE = re.compile(rb"\s*<\?xml\s[^>]*?\bencoding\s*=\s*[\"']([^\"']{0,40})[\"']")
# ECMA-376 Part 2, 8.1.4: XML parts are UTF-8 or UTF-16 (ASCII is a subset of UTF-8).
_XML_ENCODINGS = frozenset({"utf-8", "utf8", "utf-16", "utf16", "utf-16le", "utf-16be",
                            "us-ascii", "ascii"})
_CELL_RE = re.compile(r"\$?([A-Za-z]{1,3})\$?([0-9]{1,7})")


@dataclass(frozen=True)
class Limits:
    """Resource limits for one untrusted workbook (see the module docstring)."""

    max_file_bytes: int = 50 * MB
    max_part_bytes: int = 100 * MB
    max_total_bytes: int = 300 * MB
    max_ratio: float = 200.0
    ratio_min_bytes: int = 1 * MB
    max_parts: int = 2000
    max_rows: int = 100_000
    max_cols: int = 4_000
    max_cells: int = 2_000_000
    max_used_cells: int = 10_000_000
    max_reads: int = 400_000_000
    max_formula_chars: int = 2_000_000

    def __post_init__(self):
        for field, value in vars(self).items():
            if not value > 0:
                raise ValueError(f"Limits.{field} must be positive, got {value!r}")


def shorten(text: object, limit: int = 300) -> str:
    """`text` made safe for a one-line message: control characters escaped, long text cut."""
    s = "".join(c if c.isprintable() else repr(c)[1:-1] for c in str(text))
    return s if len(s) <= limit else s[:limit - 1] + "…"


def _size(n: float) -> str:
    if n >= MB:
        return f"{n / MB:.4g} MB"
    if n >= 10_000:
        return f"{n / 1000:.4g} kB"
    return f"{int(n)} bytes"


def _count(n: int, noun: str) -> str:
    return f"{n} {noun}" + ("" if n == 1 else "s")


class UnusableWorkbook(SpreadsheetError):
    """An input workbook sheetkin refuses; str() is one line starting with the path.

    Attributes: path (as given), part (the zip member concerned, or None), problem,
    expected (what would have been accepted, or None).
    """

    def __init__(self, path, problem: str, expected: str | None = None, part: str | None = None):
        self.path = os.fspath(path)
        self.part = part
        self.problem = problem
        self.expected = expected
        msg = f"{shorten(self.path, 1000)}: "
        if part is not None:
            msg += f"{shorten(part)}: "
        msg += problem
        if expected:
            msg += f"; {expected}"
        super().__init__(" ".join(msg.splitlines()))  # one line, whatever slipped through

    def __str__(self) -> str:
        return self.args[0]


class SheetPart(NamedTuple):
    """A sheet of the workbook, in workbook order."""

    name: str    # the tab's name
    part: str    # zip member, e.g. "xl/worksheets/sheet1.xml"
    state: str   # "visible", "hidden" or "veryHidden"
    kind: str    # "worksheet", "chartsheet" or "dialogsheet"


def _local(tag: str) -> str:
    return tag.rsplit("}", 1)[-1]


def _rel_tail(rel_type: str) -> str:
    return rel_type.rstrip("/").rsplit("/", 1)[-1]


class Package:
    """Read-only view of a checked .xlsx zip package; made by `open_package`.

    The file was read once into `data`; nothing here touches the file again.
    """

    def __init__(self, path, data: bytes, archive: zipfile.ZipFile, limits: Limits):
        self.path = os.fspath(path)
        self.data = data          # the checked bytes of the file
        self.limits = limits
        self._zip = archive
        self._infos = {i.filename: i for i in archive.infolist()}
        self.names: tuple[str, ...] = tuple(i.filename for i in archive.infolist())
        self._lower = {n.lower(): n for n in self.names}
        self._defaults: dict[str, str] = {}
        self._overrides: dict[str, str] = {}
        self.workbook_part = "xl/workbook.xml"
        self._sheets: list[SheetPart] | None = None
        # parts the gate's scan inflated (and checked: sizes, CRC), kept up to _KEEP_BYTES in
        # all so that reading them is not inflating them again (`sheetkin evaluate`, issue 32)
        self._inflated: dict[str, bytes] = {}

    # -- errors ---------------------------------------------------------------------------
    def _fail(self, problem: str, expected: str | None = None, part: str | None = None) -> NoReturn:
        raise UnusableWorkbook(self.path, problem, expected, part)

    def _corrupt(self, part: str, what: str) -> NoReturn:
        self._fail(f"corrupt zip archive ({what})",
                   "expected an intact .xlsx file: save the workbook again", part)

    # -- parts ----------------------------------------------------------------------------
    def __contains__(self, name: str) -> bool:
        return name in self._infos

    def find(self, name: str) -> str | None:
        """The member called `name`, matched case-insensitively as OPC part names are."""
        return name if name in self._infos else self._lower.get(name.lower())

    def info(self, name: str) -> zipfile.ZipInfo:
        if name not in self._infos:
            self._fail(f"no part {shorten(name)!s} in the package", "expected a complete workbook")
        return self._infos[name]

    def content_type(self, name: str) -> str | None:
        """The part's content type from [Content_Types].xml (Override, else Default)."""
        ct = self._overrides.get("/" + name.lower())
        if ct is None:
            ct = self._defaults.get(posixpath.splitext(name)[1][1:].lower())
        return ct

    def chunks(self, name: str, limit: int | None = None) -> Iterator[bytes]:
        """The part's uncompressed bytes in chunks, inflated here and never trusting headers.

        Raises UnusableWorkbook as soon as more bytes come out than the zip's directory
        declares or than `limit` (default Limits.max_part_bytes), and at the end unless the
        deflate stream ended, the byte count equals the declared size and the CRC-32 matches.
        """
        info = self.info(name)
        limit = self.limits.max_part_bytes if limit is None else limit
        data = self.data
        off = info.header_offset
        if off < 0 or off + _LOCAL_HEADER.size > len(data):
            self._corrupt(name, "its local header lies outside the file")
        sig, _ver, flags, _method, _t, _d, _crc, _cs, _us, nlen, xlen = _LOCAL_HEADER.unpack_from(data, off)
        if sig != b"PK\x03\x04":
            self._corrupt(name, "no local header where the directory points")
        if flags & 0x41:
            self._fail(message("encrypted_password_protected_zip"),
                       message("expected_unencrypted_xlsx_file"), name)
        start = off + _LOCAL_HEADER.size + nlen + xlen
        end = start + info.compress_size
        if end > len(data):
            self._corrupt(name, "its data runs past the end of the file: truncated")
        declared = info.file_size
        raw = memoryview(data)[start:end]
        count = crc = 0

        def account(out: bytes) -> None:
            nonlocal count, crc
            count += len(out)
            if count > declared:
                self._corrupt(name, f"inflates to more than the {_size(declared)} its header says")
            if count > limit:
                self._fail(message("uncompressed", size=_size(limit)),
                           f"expected at most {_size(limit)} per part", name)
            crc = zlib.crc32(out, crc)

        if info.compress_type == zipfile.ZIP_STORED:
            for pos in range(0, len(raw), _CHUNK):
                out = bytes(raw[pos:pos + _CHUNK])
                account(out)
                yield out
        elif info.compress_type == zipfile.ZIP_DEFLATED:
            inflater = zlib.decompressobj(-zlib.MAX_WBITS)
            pos = 0
            while not inflater.eof:
                buf: bytes | memoryview
                if inflater.unconsumed_tail:
                    buf = inflater.unconsumed_tail
                else:
                    buf = raw[pos:pos + _IN_CHUNK]
                    pos += len(buf)
                try:
                    out = inflater.decompress(buf, _CHUNK)
                except zlib.error as e:
                    self._corrupt(name, f"bad deflate data: {e}")
                if not out and not buf and not inflater.eof:
                    self._corrupt(name, "its compressed data ends early: truncated")
                if out:
                    account(out)
                    yield out
        else:
            self._fail(f"compressed with zip method {info.compress_type}",
                       "expected deflate or stored, as Excel and LibreOffice write", name)
        if count != declared:
            self._corrupt(name, f"holds {count} bytes, its header says {declared}")
        if crc != info.CRC:
            self._corrupt(name, "bad CRC-32")

    def read(self, name: str, limit: int | None = None) -> bytes:
        """The part's uncompressed bytes, limits enforced while inflating (see `chunks`), or
        as the gate's scan kept them (inflated and checked there within the default limit;
        a smaller limit they exceed is left to `chunks` to refuse)."""
        kept = self._inflated.get(name)
        if kept is not None and (limit is None or len(kept) <= limit):
            return kept
        return b"".join(self.chunks(name, limit))

    def xml(self, name: str) -> Element:
        """The part parsed with defusedxml (no DTD, no entities, no external references)."""
        data = self.read(name)
        try:
            return _DET.fromstring(data, forbid_dtd=True)
        except Exception as e:  # noqa: BLE001 - every parser failure is one message
            self._xml_error(name, e)

    def iterparse(self, name: str, events: Iterable[str] = ("end",)) -> Iterator[tuple[str, Element]]:
        """defusedxml's iterparse over the part, streamed: for big worksheets."""
        stream = _ChunkStream(self.chunks(name))
        try:
            yield from _DET.iterparse(stream, events=tuple(events), forbid_dtd=True)
        except UnusableWorkbook:
            raise
        except Exception as e:  # noqa: BLE001
            self._xml_error(name, e)

    def _xml_error(self, name: str, e: Exception) -> NoReturn:
        if isinstance(e, defusedxml.DefusedXmlException):
            self._fail("XML with a DTD or entity declarations (possible entity bomb)",
                       "refused: Excel and LibreOffice never write one", name)
        if isinstance(e, ParseError):
            self._fail(f"not well-formed XML ({shorten(e, 120)})",
                       "expected XML as Excel or LibreOffice write it", name)
        if isinstance(e, (ValueError, LookupError, UnicodeError, TypeError)):
            self._fail(f"unreadable XML ({type(e).__name__}: {shorten(e, 120)})",
                       "expected XML as Excel or LibreOffice write it", name)
        raise e

    def relationships(self, source: str) -> list[tuple[str, str, str, str]]:
        """(Id, Type, resolved Target, TargetMode) of `source`'s relationships ("" = package).

        Internal targets are resolved to member names (relative to the source part's folder,
        or absolute from the package root); external targets are left as written.
        """
        folder, base = posixpath.split(source)
        rels_name = self.find(posixpath.join(folder, "_rels", base + ".rels"))
        return [] if rels_name is None else self._parse_rels(rels_name, folder)

    def _parse_rels(self, rels_name: str, folder: str) -> list[tuple[str, str, str, str]]:
        out = []
        for rel in self.xml(rels_name):
            if _local(rel.tag) != "Relationship":
                continue
            target = rel.get("Target", "")
            mode = rel.get("TargetMode", "Internal")
            if mode != "External":
                target = self._resolve(folder, target)
            out.append((rel.get("Id", ""), rel.get("Type", ""), target, mode))
        return out

    def _resolve(self, folder: str, target: str) -> str:
        target = target.split("#", 1)[0].replace("\\", "/")
        joined = target.lstrip("/") if target.startswith("/") else posixpath.join(folder, target)
        joined = posixpath.normpath(joined) if joined else joined
        for candidate in (joined, unquote(joined)):
            found = self.find(candidate)
            if found is not None:
                return found
        return joined


class _ChunkStream(io.RawIOBase):
    """A readable file over an iterator of byte chunks."""

    def __init__(self, chunks: Iterator[bytes]):
        self._chunks = chunks
        self._buf = memoryview(b"")

    def readable(self) -> bool:
        return True

    def readinto(self, b) -> int:
        while not self._buf:
            chunk = next(self._chunks, b"")
            if not chunk:
                return 0
            self._buf = memoryview(chunk)
        n = min(len(b), len(self._buf))
        b[:n] = self._buf[:n]
        self._buf = self._buf[n:]
        return n


def _sniff(head: bytes) -> str:
    """What a non-zip file looks like, for the message."""
    if head.startswith(_OLE_MAGIC):
        if "EncryptedPackage".encode("utf-16-le") in head:
            return message("password_protected_encrypted_workbook")
        return message("old_binary_excel_xls")
    sample = head[:4096]
    if sample.lstrip(b"\xef\xbb\xbf \t\r\n")[:1] == b"<":
        return "XML or HTML, not a zip archive"
    try:
        sample.decode("utf-8")
    except UnicodeDecodeError as e:
        if e.start < len(sample) - 3:
            return message("not_zip_archive")
    if b"\x00" in sample:
        return message("not_zip_archive")
    return "plain text, not a zip archive"


def open_package(path, limits: Limits = Limits()) -> Package:
    """Read and check the workbook at `path` (see the module docstring); never writes to it."""
    shown = os.fspath(path)

    def fail(problem: str, expected: str | None = None, part: str | None = None) -> NoReturn:
        raise UnusableWorkbook(shown, problem, expected, part)

    data = _read_file(path, limits, fail)                    # 1. the path
    pkg, infos = _open_zip(path, data, limits, fail)        # 2. the container

    # 3. the central directory, nothing inflated
    seen: set[str] = set()
    for info in infos:
        low = info.filename.lower()
        if low in seen:
            pkg._corrupt(info.filename, "two parts with this name")
        seen.add(low)
        if info.flag_bits & 0x41:
            fail(message("encrypted_password_protected_zip"), message("expected_unencrypted_xlsx_file"),
                 info.filename)
        if info.compress_type not in (zipfile.ZIP_STORED, zipfile.ZIP_DEFLATED):
            fail(f"compressed with zip method {info.compress_type}",
                 "expected deflate or stored, as Excel and LibreOffice write", info.filename)
    expected_xlsx = message("expected_xlsx_workbook")
    if pkg.find("xl/workbook.bin") is not None:
        fail(message("not_xlsx_file", what=message("excel_binary_workbook_xlsb")),
             "expected .xlsx: save it as Excel Workbook (.xlsx)")
    if pkg.find("word/document.xml") is not None:
        fail("not a spreadsheet (a Word document)", expected_xlsx)
    if pkg.find("ppt/presentation.xml") is not None:
        fail("not a spreadsheet (a PowerPoint presentation)", expected_xlsx)
    ct_name = pkg.find("[Content_Types].xml")
    if ct_name is None:
        fail("not a spreadsheet package (a zip archive without [Content_Types].xml)", expected_xlsx)
    if pkg.find("xl/workbook.xml") is None and pkg.find("_rels/.rels") is None:
        fail("not a spreadsheet package (no xl/workbook.xml)", expected_xlsx)
    macro_hint = "sheetkin never runs macros: save it as .xlsx (Excel Workbook)"
    for name in pkg.names:
        low = name.lower()
        if "vbaproject" in posixpath.basename(low) or low.startswith("xl/macrosheets/"):
            fail(message("contains_macros", what=shorten(name)), macro_hint)
    suffix = PurePath(shown).suffix.lower()
    if suffix in _MACRO_EXTENSIONS:
        fail(message("contains_macros_or_enabled", what=suffix), macro_hint)
    external_hint = ("sheetkin reads one workbook on its own: copy the values in and remove the "
                     "links (Excel: Data > Edit Links > Break Link)")
    for name in pkg.names:
        if name.lower().startswith("xl/externallinks/"):
            fail(message("links_other_files", what=f"external links: {shorten(name)}"), external_hint)
    if len(infos) > limits.max_parts:
        fail(f"has {len(infos)} parts in its zip archive",
             message("at_most_limit", size=limits.max_parts))
    total = 0
    for info in infos:
        if info.file_size > limits.max_part_bytes:
            fail(f"{_size(info.file_size)} uncompressed",
                 f"expected at most {_size(limits.max_part_bytes)} per part", info.filename)
        _check_ratio(pkg, info, info.file_size)
        total += info.file_size
    if total > limits.max_total_bytes:
        fail(f"{_size(total)} uncompressed in all",        # no "more than": said as it is
             message("at_most_limit", size=_size(limits.max_total_bytes)))

    _scan_parts(pkg, ct_name, infos, limits, fail)  # 4. one streaming pass: real sizes, CRCs, DTDs

    # 5. the content
    _check_content(pkg, macro_hint, external_hint, fail)
    office = [t for _i, rtype, t, mode in pkg.relationships("")
              if _rel_tail(rtype) == "officeDocument" and mode != "External" and t in pkg]
    if office:
        pkg.workbook_part = office[0]
    elif (workbook_xml := pkg.find("xl/workbook.xml")) is not None:
        pkg.workbook_part = workbook_xml
    else:
        fail("not a spreadsheet package (no workbook part)", expected_xlsx)
    # The sheets must resolve. Their <dimension ref> is not a limit: LibreOffice writes
    # A1:XFD1048576 for a sheet whose empty rows and columns are styled to the end; the
    # row/column limits apply to the cells that hold something (the reader counts them).
    sheet_parts(pkg)
    return pkg


def _read_file(path, limits: Limits, fail: Callable[..., NoReturn]) -> bytes:
    """open_package's step 1, the path: the file's bytes, refused if it is no regular file or too big."""
    try:
        st = os.stat(path)
    except FileNotFoundError:
        fail("no such file", message("expected_xlsx_workbook"))
    except (OSError, ValueError) as e:
        fail(f"cannot be read ({shorten(getattr(e, 'strerror', None) or e)})",
             "expected a readable .xlsx file")
    if stat.S_ISDIR(st.st_mode):
        fail("is a directory", message("expected_xlsx_file"))
    try:
        # Read-only; non-blocking in case a FIFO replaced the file since the stat.
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_BINARY", 0))
        with open(fd, "rb") as f:
            st = os.fstat(f.fileno())
            if not stat.S_ISREG(st.st_mode):
                fail("is not a regular file", message("expected_xlsx_file"))
            if st.st_size > limits.max_file_bytes:
                fail(message("file_size", size=_size(st.st_size)), message("at_most_limit",
                                                                           size=_size(limits.max_file_bytes)))
            data = f.read(limits.max_file_bytes + 1)
    except OSError as e:
        fail(f"cannot be read ({shorten(e.strerror or e)})", "expected a readable .xlsx file")
    if len(data) > limits.max_file_bytes:
        fail(message("file_more_than", size=_size(limits.max_file_bytes)),
             message("at_most_limit", size=_size(limits.max_file_bytes)))
    if not data:
        fail(message("empty_file_0_bytes"), message("expected_xlsx_workbook"))
    return data


def _open_zip(path, data: bytes, limits: Limits,
              fail: Callable[..., NoReturn]) -> tuple[Package, list[zipfile.ZipInfo]]:
    """open_package's step 2, the container: a zip archive, not an OpenDocument file."""
    if not data.startswith((b"PK\x03\x04", b"PK\x05\x06")):
        what = _sniff(data[:65536])
        if data.startswith(_OLE_MAGIC):
            fail(message("not_xlsx_file", what=what), message("expected_xlsx_save_it"))
        fail(message("not_xlsx_file", what=what), message("expected_excel_workbook_saved"))
    try:
        archive = zipfile.ZipFile(io.BytesIO(data))
        infos = archive.infolist()
    except (zipfile.BadZipFile, zipfile.LargeZipFile, EOFError, OSError, ValueError,
            NotImplementedError, struct.error, UnicodeError) as e:
        detail = message("end_missing") if str(e) == "File is not a zip file" else shorten(e, 120)
        fail(message("corrupt_zip", what=detail),
             message("expected_complete_xlsx_file"))
    pkg = Package(path, data, archive, limits)
    mimetype = pkg.find("mimetype")
    if mimetype is not None and pkg.info(mimetype).file_size <= 200:
        kind = pkg.read(mimetype, limit=200).decode("ascii", "replace").strip()
        if kind.startswith("application/vnd.oasis.opendocument.spreadsheet"):
            fail(message("not_xlsx_file", what=message("opendocument_spreadsheet_ods")),
                 message("expected_xlsx_libreoffice_file"))
        if kind.startswith("application/vnd.oasis.opendocument"):
            fail(message("not_xlsx_file", what=f"an OpenDocument file, {shorten(kind, 80)}"),
                 message("expected_excel_workbook_saved"))
    return pkg, infos


def _scan_parts(pkg: Package, ct_name: str, infos: list[zipfile.ZipInfo], limits: Limits,
                fail: Callable[..., NoReturn]) -> None:
    """open_package's step 4, one streaming pass over every part: the content types, real
    sizes, CRCs, no DTD, a declared encoding of UTF-8 or UTF-16."""
    for node in pkg.xml(ct_name):
        tag = _local(node.tag)
        if tag == "Default":
            pkg._defaults[node.get("Extension", "").lower()] = node.get("ContentType", "")
        elif tag == "Override":
            pkg._overrides[node.get("PartName", "").lower()] = node.get("ContentType", "")
    real_total = kept = 0
    for info in infos:
        if info.is_dir():
            continue
        name = info.filename
        scan = _is_xmlish(name, pkg.content_type(name))
        tail = b""
        first = True
        keep: list[bytes] | None = [] if kept + info.file_size <= _KEEP_BYTES else None
        for chunk in pkg.chunks(name):
            if keep is not None:
                keep.append(chunk)
            real_total += len(chunk)
            if scan and first:
                first = False
                encoding = _declared_encoding(chunk)
                if encoding is not None and encoding not in _XML_ENCODINGS:
                    pkg._fail(f"XML declared in encoding '{shorten(encoding, 40)}'",
                              "expected UTF-8 or UTF-16, as the .xlsx standard requires", name)
            if scan:
                if _has_dtd(tail, chunk):
                    pkg._fail("XML with a DTD or entity declarations (possible entity bomb)",
                              "refused: Excel and LibreOffice never write one", name)
                tail = (tail + chunk)[-_DTD_OVERLAP:] if len(chunk) < _DTD_OVERLAP else chunk[-_DTD_OVERLAP:]
        if real_total > limits.max_total_bytes:
            fail(message("uncompressed_all", size=_size(limits.max_total_bytes)),
                 f"expected at most {_size(limits.max_total_bytes)}")
        if keep is not None:                    # the whole part, checked (chunks raised otherwise)
            pkg._inflated[name] = b"".join(keep)
            kept += len(pkg._inflated[name])


_KEEP_BYTES = 64 * 1024 * 1024      # inflated parts the scan keeps for reading (see Package._inflated)


def _check_content(pkg: Package, macro_hint: str, external_hint: str, fail: Callable[..., NoReturn]) -> None:
    """open_package's step 5 (its first part): no macros by content type or relationship, no
    links to other files."""
    for name in pkg.names:
        ct = (pkg.content_type(name) or "").lower()
        if "macroenabled" in ct or "vbaproject" in ct or "macrosheet" in ct:
            fail(message("contains_macros_or_enabled", what=f"content type of {shorten(name)}"), macro_hint)
    for rels in [n for n in pkg.names if n.lower().endswith(".rels")]:
        for _id, rtype, target, mode in pkg._parse_rels(rels, posixpath.dirname(posixpath.dirname(rels))):
            rel_kind = _rel_tail(rtype).lower()
            if "vbaproject" in rel_kind or "macrosheet" in rel_kind:
                fail(message("contains_macros", what=f"{shorten(_rel_tail(rtype))} relationship in {shorten(rels)}"),
                     macro_hint)
            if "externallink" in rel_kind or (mode == "External" and rel_kind != "hyperlink"):
                fail(message("links_other_files", what=f"{shorten(_rel_tail(rtype))} relationship to "
                                                       f"{shorten(target, 120)} in {shorten(rels)}"), external_hint)


def _declared_encoding(head: bytes) -> str | None:
    """The encoding named in an XML declaration at the start of `head`, lower-cased."""
    if head.startswith(b"\xef\xbb\xbf"):
        head = head[3:]
    elif head[:2] in (b"\xff\xfe", b"\xfe\xff", b"<\x00", b"\x00<"):
        codec = "utf-16" if head[:2] in (b"\xff\xfe", b"\xfe\xff") else (
            "utf-16-le" if head[:1] == b"<" else "utf-16-be")
        head = head[:512].decode(codec, "replace").encode("ascii", "replace")
    m = _DECLARATION_RE.match(head[:512])
    return m.group(1).decode("ascii", "replace").lower() if m else None


def _is_xmlish(name: str, content_type: str | None) -> bool:
    """Whether a part is XML a reader (this module, openpyxl) may parse."""
    if posixpath.splitext(name)[1][1:].lower() in _XML_EXTENSIONS:
        return True
    ct = (content_type or "").lower()
    return "xml" in ct and not ct.startswith("image/")


def _check_ratio(pkg: Package, info: zipfile.ZipInfo, size: int) -> None:
    if size <= pkg.limits.ratio_min_bytes:
        return
    ratio = size / max(info.compress_size, 1)
    if ratio > pkg.limits.max_ratio:
        pkg._fail(f"compressed {ratio:.0f}:1 ({_size(size)} from {_size(info.compress_size)}), "
                  "the mark of a zip bomb",
                  f"expected at most {pkg.limits.max_ratio:g}:1", info.filename)


def sheet_parts(pkg: Package) -> list[SheetPart]:
    """The workbook's sheets in workbook (tab) order, resolved through its relationships."""
    if pkg._sheets is not None:
        return list(pkg._sheets)
    wb = pkg.workbook_part
    rels = {rid: (rtype, target) for rid, rtype, target, mode in pkg.relationships(wb)
            if mode != "External"}
    root = pkg.xml(wb)
    sheets_node = next((n for n in root if _local(n.tag) == "sheets"), None)
    out: list[SheetPart] = []
    seen: set[str] = set()
    for node in [] if sheets_node is None else sheets_node:
        if _local(node.tag) != "sheet":
            continue
        name = node.get("name", "")
        # Excel refuses two sheets whose names differ only in case; read on, the later
        # would replace the earlier (a book graded against a hidden sheet of the same name)
        if name.casefold() in seen:
            pkg._fail(f"two sheets named '{shorten(name, 100)}' (sheet names are compared ignoring case)",
                      "expected distinct sheet names, as Excel requires", wb)
        seen.add(name.casefold())
        rid = next((v for k, v in node.attrib.items()
                    if _local(k) == "id" and k.startswith("{") and "relationships" in k), None)
        if rid is None or rid not in rels:
            pkg._fail(f"sheet '{shorten(name, 100)}' has no relationship to its part",
                      "expected a complete workbook package", wb)
        rtype, target = rels[rid]
        if target not in pkg:
            pkg._fail(f"sheet '{shorten(name, 100)}' refers to a missing part ({shorten(target, 120)})",
                      "expected a complete workbook package", wb)
        out.append(SheetPart(name, target, node.get("state", "visible"), _rel_tail(rtype)))
    if not out:
        pkg._fail("the workbook has no sheets", "expected at least one worksheet", wb)
    pkg._sheets = out
    return list(out)


def _column_number(letters: str) -> int:
    n = 0
    for c in letters.upper():
        n = n * 26 + ord(c) - 64
    return n


def sheet_dimension(pkg: Package, part: str) -> tuple[int, int] | None:
    """(last row, last column) from the worksheet's <dimension ref>, or None if it has none.

    Only the start of the part is inflated; the values are what the writer claims, so a
    reader still counts rows and columns (`check_dimension`).
    """
    head = b""
    for chunk in pkg.chunks(part):
        head += chunk
        if len(head) >= _DIMENSION_PREFIX:
            break
    m = _DIMENSION_RE.search(head)
    if m is None:
        return None
    cells = _CELL_RE.findall(m.group(1).decode("ascii", "replace"))
    if not cells:
        return None
    return max(int(r) for _c, r in cells), max(_column_number(c) for c, _r in cells)


def check_dimension(path, sheet: str, rows: int, cols: int, limits: Limits = Limits()) -> None:
    """Raise UnusableWorkbook if a sheet reaches past `limits` (last row, last column)."""
    if rows > limits.max_rows or cols > limits.max_cols:
        raise UnusableWorkbook(
            path, f"sheet '{shorten(sheet, 100)}' spans {_count(rows, 'row')} and {_count(cols, 'column')}",
            f"expected at most {limits.max_rows} rows and {limits.max_cols} columns per sheet "
            "(clear the cells outside the table, or delete those rows and columns)")


def check_openpyxl_safe() -> bool:
    """True if openpyxl parses XML with defusedxml (openpyxl.xml.DEFUSEDXML).

    False when defusedxml is missing or OPENPYXL_DEFUSEDXML is set to something other than
    "True" before openpyxl was imported. (open_package refuses any DTD anyway.)
    """
    try:
        import openpyxl.xml
    except ImportError:
        return False
    return openpyxl.xml.DEFUSEDXML is True
